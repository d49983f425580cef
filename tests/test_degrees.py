"""A batch canvas in degrees of visual angle: images of the pixel size it means, shown at those degrees.

The expected pixel sizes and degrees are computed here from the definition
of the central degree (px per mm x 2 d tan 0.5 deg), not by the package.
"""

import math

import pytest
from PIL import Image

from attneave.analysis.experiment import calibration
from attneave.cli import main

CONFIG = """seed: 3
canvas: {{{canvas}}}
conditions:
  - name: big
    recipe: attneave_polygon
    params: {{grid: 100, min_angle: 10, max_angle: 170, version: polygon, n_points: 6}}
  - name: small
    recipe: attneave_polygon
    params: {{grid: 100, min_angle: 10, max_angle: 170, version: polygon, n_points: 6}}
    canvas: {{{small}}}
"""


def generate(tmp_path, canvas, small="width_deg: 2, height_deg: 2", name="set"):
    cfg = tmp_path / f"{name}.yaml"
    cfg.write_text(CONFIG.format(canvas=canvas, small=small))
    out = tmp_path / name
    return main(["generate", str(cfg), "-o", str(out)]), out


def sizes(out):
    return {p.stem.split("_")[0]: Image.open(p).size for p in sorted((out / "images").glob("*.png"))}


@pytest.fixture(scope="module")
def degree_set(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("deg")
    code, out = generate(tmp, "width_deg: 4, height_deg: 3, margin_deg: 0.25, px_per_deg: 40")
    assert code == 0
    return out


def test_canvas_in_degrees_gives_images_of_that_many_pixels(degree_set):
    assert sizes(degree_set) == {"big": (160, 120), "small": (80, 80)}   # 4 x 3 and 2 x 2 deg at 40 px/deg
    text = (degree_set / "config.yaml").read_text()
    assert "width_deg: 4.0" in text and "px_per_deg: 40.0" in text and "margin: 10.0" in text


def test_the_resolved_config_gives_the_same_images(degree_set, tmp_path):
    out = tmp_path / "again"
    assert main(["generate", str(degree_set / "config.yaml"), "-o", str(out)]) == 0
    for p in (degree_set / "images").glob("*.png"):
        assert (out / "images" / p.name).read_bytes() == p.read_bytes()


def test_viewing_distance_and_screen_give_the_scale(tmp_path):
    code, out = generate(tmp_path, "width_deg: 5, height_deg: 5, margin_deg: 0.5, viewing_distance_cm: 60, "
                                   "screen_width_cm: 52, screen_width_px: 1920", small="width: 64, height: 64")
    assert code == 0
    ppd = (1920 / 520) * 2 * 600 * math.tan(math.radians(0.5))   # px per mm x 2 d tan(0.5 deg)
    assert sizes(out) == {"big": (round(5 * ppd), round(5 * ppd)), "small": (64, 64)}   # pixels override


@pytest.mark.parametrize("canvas, words", [
    ("width_deg: 4, height_deg: 4", "needs the display's scale"),
    ("width: 100, width_deg: 4, height_deg: 4, px_per_deg: 40", "disagree"),
    ("width_deg: 4, height_deg: 4, viewing_distance_cm: 57", "without"),
    ("width_deg: 4, height_deg: 4, px_per_deg: 30, viewing_distance_cm: 57, screen_width_cm: 50, "
     "screen_width_px: 1000", "give one scale"),
])
def test_bad_degrees_are_refused_in_one_line(tmp_path, capsys, canvas, words):
    code, _ = generate(tmp_path, canvas)
    err = capsys.readouterr().err
    assert code == 2 and words in err and "canvas" in err and "Traceback" not in err


def test_experiment_shows_the_set_at_its_degrees(browser, degree_set, tmp_path):
    exp = tmp_path / "exp"
    # this lab's screen has another scale than the canvas was made at: 50 CSS px per degree
    assert main(["experiment", str(degree_set), "-o", str(exp), "--px-per-deg", "50", "--fixation-ms", "0",
                 "--iti-ms", "0", "--order", "fixed", "--clicks", "1"]) == 0
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto((exp / "index.html").as_uri() + "?participant=deg")
    page.click("#next")
    widths = {}
    for _ in range(2):
        page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        box = page.evaluate("(() => { const b = document.getElementById('stimulus').getBoundingClientRect();"
                            " return [b.left, b.top, b.width, b.height]; })()")
        widths[sid.split("_")[0]] = box[2:]
        page.mouse.click(box[0] + box[2] / 2, box[1] + box[3] / 2)
        page.click("#next")
        page.wait_for_function(f"() => document.getElementById('stimulus').getAttribute('data-stimulus-id') !== "
                               f"'{sid}'")
    page.close()
    assert widths["big"][0] / 50 == pytest.approx(4, rel=0.01) and widths["big"][1] / 50 == pytest.approx(3, rel=0.01)
    assert widths["small"][0] / 50 == pytest.approx(2, rel=0.01)


def test_experiment_at_the_set_degrees_after_card_calibration(browser, degree_set, tmp_path):
    exp = tmp_path / "exp"
    assert main(["experiment", str(degree_set), "-o", str(exp), "--fixation-ms", "0", "--order", "fixed"]) == 0
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto((exp / "index.html").as_uri() + "?participant=cal&px_per_mm=3.5&distance_cm=50")
    page.click("#next")
    page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
    width = page.evaluate("document.getElementById('stimulus').getBoundingClientRect().width")
    page.close()
    ppd = calibration.px_per_degree(3.5, 500.0)
    assert width / ppd == pytest.approx(4, rel=0.01)


def test_a_size_given_wins_over_the_set_degrees(degree_set, tmp_path):
    exp = tmp_path / "exp"
    assert main(["experiment", str(degree_set), "-o", str(exp), "--size-deg", "7"]) == 0
    assert '"size_deg": 7.0' in (exp / "index.html").read_text()
