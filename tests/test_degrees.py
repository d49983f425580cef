"""A batch canvas and shape sizes in degrees of visual angle: images of the pixel sizes they mean.

The expected pixel sizes and degrees are computed here from the definition
of the central degree (px per mm x 2 d tan 0.5 deg), not by the package.
"""

import csv
import json
import math
from pathlib import Path

import numpy as np
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


# --------------------------------------------------------------------------- shape sizes in degrees

SHAPES = """seed: 5
canvas: {{{canvas}}}
conditions:
  - name: rf
    recipe: radial_frequency
    params: {{{rf}, frequency: 5, amplitude: 0.1, n: 1024}}
  - name: circle
    recipe: superformula
    params: {{{circle}, m: 4, n1: 2, n2: 2, n3: 2, n: 1024}}
  - name: dfm
    recipe: deformation
    params: {{base: {{generator: blob, params: {{{blob}}}}}, {dfm}, mode: bump}}
  - name: guided
    recipe: guided
    params: {{base: {{generator: radial_frequency, params: {{{gbase}, frequency: 3, amplitude: 0.2}}}},
              kinds: [base, peaks, troughs], {gap}}}
"""
DEG = dict(rf="r0_deg: 2", circle="scale_deg: 1.5", blob="r0_deg: 1.5", dfm="displacement_deg: 0.25",
           gbase="r0_deg: 2.5", gap="min_gap_deg: 0.25")
PX = dict(rf="r0: 80, placement: native", circle="scale: 60, placement: native", blob="r0: 60, placement: native",
          dfm="displacement: 10", gbase="r0: 100, placement: native", gap="min_gap: 10")


def generate_shapes(tmp_path, name, canvas="width_deg: 8, height_deg: 8, margin_deg: 0.5, px_per_deg: 40", **given):
    cfg = tmp_path / f"{name}.yaml"
    cfg.write_text(SHAPES.format(canvas=canvas, **{**DEG, **given}))
    out = tmp_path / name
    return main(["generate", str(cfg), "-o", str(out)]), out


def radii(path, size):
    """Distances of a contour file's points from the image centre ((w - 1) / 2, (h - 1) / 2)."""
    xy = np.loadtxt(path, delimiter=",", skiprows=1)
    return np.hypot(xy[:, 0] - (size - 1) / 2, xy[:, 1] - (size - 1) / 2)


def dark_area(png):
    """The figure's area in px: black on white, antialiased edge pixels counted by their darkness."""
    return float((1 - np.asarray(Image.open(png), float) / 255).sum())


@pytest.fixture(scope="module")
def shape_sets(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("shapes")
    code_deg, deg = generate_shapes(tmp, "deg")
    code_px, px = generate_shapes(tmp, "px", canvas="width: 320, height: 320, margin: 20", **PX)
    assert code_deg == 0 and code_px == 0
    return deg, px


def test_sizes_in_degrees_come_out_at_that_many_pixels(shape_sets):
    deg, _ = shape_sets
    # RF: r(theta) = r0 (1 + A sin(5 theta + phi)): the mean over equally spaced angles is r0 = 2 deg x 40 px/deg
    assert radii(deg / "contours" / "rf_000_000.csv", 320).mean() == pytest.approx(80, rel=0.01)
    # its area is the integral of r^2 / 2: pi r0^2 (1 + A^2 / 2)
    assert dark_area(deg / "images" / "rf_000_000.png") == pytest.approx(math.pi * 80**2 * (1 + 0.1**2 / 2), rel=0.01)
    # the superformula with m = 4 and every exponent 2 is the circle of radius `scale` = 1.5 x 40
    r = radii(deg / "contours" / "circle_000_000.csv", 320)
    assert r.min() == pytest.approx(60, rel=0.01) and r.max() == pytest.approx(60, rel=0.01)
    assert dark_area(deg / "images" / "circle_000_000.png") == pytest.approx(math.pi * 60**2, rel=0.01)
    # the blob's log-radius has mean log r0: its geometric-mean radius is 1.5 deg
    r = radii(deg / "contours" / "dfm_000_000_base.csv", 320)
    assert math.exp(np.log(r).mean()) == pytest.approx(60, rel=0.01)


def test_degrees_and_pixels_give_the_same_files(shape_sets):
    deg, px = shape_sets
    names = sorted(p.relative_to(deg).as_posix() for p in deg.glob("[ic]*/*.*"))
    assert len(names) == 2 * (1 + 1 + 3 + 3)   # an image and a contour per stimulus
    assert names == sorted(p.relative_to(px).as_posix() for p in px.glob("[ic]*/*.*"))
    for name in names:
        assert (deg / name).read_bytes() == (px / name).read_bytes(), name


def test_the_manifest_records_the_degrees_and_their_pixels(shape_sets):
    deg, px = shape_sets
    rows = {r["stimulus_id"]: json.loads(r["params"]) for r in csv.DictReader(open(deg / "manifest.csv"))}
    assert rows["rf_000_000"]["degrees"] == {"px_per_deg": 40.0, "r0_deg": 2, "r0": 80.0}
    assert rows["rf_000_000"]["shape"]["r0"] == 80.0 and rows["rf_000_000"]["placement"]["placement"] == "native"
    assert rows["dfm_000_000_convex"]["degrees"] == {"px_per_deg": 40.0, "base.params.r0_deg": 1.5,
                                                     "base.params.r0": 60.0, "displacement_deg": 0.25,
                                                     "displacement": 10.0}
    assert rows["dfm_000_000_convex"]["deformation"]["displacement"] == 10.0
    assert rows["guided_000_000_peaks"]["guided"]["min_gap"] == 10.0
    px_rows = [json.loads(r["params"]) for r in csv.DictReader(open(px / "manifest.csv"))]
    assert not any("degrees" in r for r in px_rows)


def test_a_grid_in_degrees_and_the_resolved_config_rerun(tmp_path):
    cfg = tmp_path / "g.yaml"
    cfg.write_text("seed: 2\ncanvas: {width_deg: 8, height_deg: 8, margin_deg: 0.5, viewing_distance_cm: 60,\n"
                   "         screen_width_cm: 52, screen_width_px: 1920}\nconditions:\n  - name: rf\n"
                   "    recipe: radial_frequency\n    params: {frequency: 4, amplitude: 0.05}\n"
                   "    grid: {r0_deg: [1, 2.5]}\n")
    out = tmp_path / "g"
    assert main(["generate", str(cfg), "-o", str(out)]) == 0
    ppd = (1920 / 520) * 2 * 600 * math.tan(math.radians(0.5))
    size = round(8 * ppd)
    for cell, r0 in (("rf_000_000", 1), ("rf_001_000", 2.5)):
        assert radii(out / "contours" / f"{cell}.csv", size).mean() == pytest.approx(r0 * ppd, rel=0.01)
    text = (out / "config.yaml").read_text()
    assert "r0_deg: [1, 2.5]" in text and "r0:" not in text
    again = tmp_path / "again"
    assert main(["generate", str(out / "config.yaml"), "-o", str(again)]) == 0
    for p in (out / "images").glob("*.png"):
        assert (again / "images" / p.name).read_bytes() == p.read_bytes()


@pytest.mark.parametrize("canvas, given, key, words", [
    ("px_per_deg: 40", dict(rf="r0: 80, r0_deg: 2"), "params.r0_deg", "not both"),
    ("width: 320, height: 320", {}, "params.r0_deg", "add px_per_deg"),
    ("width: 320, height: 320", dict(rf="r0: 80", circle="scale: 60", dfm="displacement: 10",
                                     gbase="r0: 90", gap="min_gap: 10"), "base.params.r0_deg", "add px_per_deg"),
    ("px_per_deg: 40", dict(rf="r0_deg: 2, frequency_deg: 3"), "params.frequency_deg", "not a length"),
    ("px_per_deg: 40", dict(circle="scale_deg: 1, m_deg: 4"), "params.m_deg", "not a length"),
    ("px_per_deg: 40", dict(rf="radius_deg: 2"), "params.radius_deg", "unknown parameter"),
    ("px_per_deg: 40", dict(rf="r0_deg: 2, placement: fit"), "params.r0_deg", "placement: native"),
    ("px_per_deg: 40", dict(dfm="displacement_deg: -1"), "params.displacement_deg", "must be > 0"),
    ("px_per_deg: 40", dict(gap="min_gap_deg: true"), "params.min_gap_deg", "number of degrees"),
])
def test_bad_lengths_in_degrees_are_refused_in_one_line(tmp_path, capsys, canvas, given, key, words):
    code, out = generate_shapes(tmp_path, "bad", canvas=canvas, **given)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "bad.yaml:" in err and key in err and words in err
    assert not out.exists()


def docs_section():
    text = (Path(__file__).resolve().parents[1] / "docs" / "experiment.md").read_text()
    return text.split("### Shape sizes in degrees", 1)[1].split("\n## ", 1)[0]


def test_the_docs_name_every_length_and_their_example_runs(tmp_path):
    from attneave.stimuli.batch.params import length_fields
    from attneave.stimuli.batch.recipes import RECIPES

    section = docs_section()
    for name, (model, _) in RECIPES.items():
        for length in length_fields(model):
            assert f"`{length}_deg`" in section, (name, length)
    cfg = tmp_path / "docs.yaml"
    cfg.write_text("seed: 1\n" + section.split("```yaml\n", 1)[1].split("```", 1)[0])
    out = tmp_path / "docs"
    assert main(["generate", str(cfg), "-o", str(out)]) == 0
    assert radii(out / "contours" / "rf_000_000.csv", 320).mean() == pytest.approx(80, rel=0.01)
