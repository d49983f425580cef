"""report.html in a real headless browser: it reads as a methods-and-results section and fits 1280 px.

Skipped when Debian's chromium or Python's playwright is missing, unless
ATTNEAVE_REQUIRE_BROWSER=1 (as in CI), where a missing browser is a failure.
"""

import json
import os
import shutil

import numpy as np
import pytest

from attneave.cli import main

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _browser_or_skip():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
    if sync_playwright is None or not os.path.exists(CHROMIUM):
        if os.environ.get("ATTNEAVE_REQUIRE_BROWSER") == "1":
            pytest.fail("ATTNEAVE_REQUIRE_BROWSER=1 but chromium or playwright is missing")
        pytest.skip("chromium or playwright missing")
    return sync_playwright


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    from attneave.stimuli.stimulus_set import write_stimulus_set

    tmp = tmp_path_factory.mktemp("browser")
    rng = np.random.default_rng(0)
    shapes = {}
    for i in range(7):
        k = 8 + i
        th = np.sort(rng.uniform(0, 2 * np.pi, k))
        r = 140 * rng.uniform(0.45, 1.0, k)
        shapes[f"polygon_with_a_long_name_{i:03d}"] = np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]
    write_stimulus_set(tmp / "set", shapes)
    assert main(["simulate", "--stimuli", str(tmp / "set"), "-o", str(tmp / "c.csv"), "--participants", "6",
                 "--clicks", "4", "--top-share", "0.4", "--seed", "1", "--noise", "1"]) == 0
    assert main(["analyze", str(tmp / "c.csv"), "--stimuli", str(tmp / "set"), "-o", str(tmp / "out"),
                 "--group-simulations", "199", "--permutations", "100",
                 "--predictors", "surprisal,concavity"]) == 0
    return tmp / "out"


def test_report_reads_as_methods_and_results_and_fits_1280px(report):
    sync_playwright = _browser_or_skip()
    summary = json.loads((report / "summary.json").read_text())
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.goto((report / "report.html").as_uri())
        page.screenshot(path=str(report / "report_1280.png"), full_page=True)
        width = page.evaluate("document.documentElement.scrollWidth")
        text = page.inner_text("body")
        images = page.evaluate("Array.from(document.images).map(i => [i.naturalWidth, i.getBoundingClientRect().right])")
        browser.close()
    assert width <= 1280
    assert (report / "report_1280.png").stat().st_size > 10_000
    # every figure loaded and lies within the page
    assert len(images) == 3 and all(w > 0 and right <= 1280 for w, right in images)
    for heading in ("Method", "Results", "Exclusions", "Parameters", "Predictors fitted jointly", "Per stimulus"):
        assert heading in text
    # the result in APA style, with the numbers of summary.json at two decimals
    m = summary["mixed"]
    assert f"95% CI [{m['ci_low']:.2f}, {m['ci_high']:.2f}]" in text
    assert f"lift = {summary['effect']['lift']:.2f}" in text
    assert "Figure 1." in text and "Figure 3." in text and "SVG" in text
    # no raw floating-point dumps, no infinities
    words = text.replace("information", "").replace("infinite", "").replace("inference", "")
    assert "e-1" not in text and "inf" not in words
    # a reference list for every work the method cites, and parameters in words, not identifiers
    for work in ("Ziatdinov, R. (2016)", "Feldman, J., & Singh, M. (2005)", "Attneave, F. (1954)",
                 "McFadden, D. (1974)", "Baayen, R. H.", "Breslow, N. E."):
        assert work in text
    for raw in ("click_sd", "window_size", "None", "group_simulations", "sum_i"):
        assert raw not in text


def test_every_figure_is_also_written_as_svg(report):
    pngs = sorted(p.stem for p in (report / "figures").glob("*.png"))
    svgs = sorted(p.stem for p in (report / "figures").glob("*.svg"))
    assert pngs == svgs and len(pngs) == 3
    assert (report / "figures" / "group.svg").read_text().lstrip().startswith("<?xml")


# ---- printing and narrow windows (the `browser` fixture of conftest.py) ----

NO_SCROLL_BOX = """() => Array.from(document.querySelectorAll('body *')).filter(e => {
    const s = getComputedStyle(e);
    return [s.overflow, s.overflowX, s.overflowY].some(v => v === 'scroll' || v === 'auto' || v === 'hidden');
}).map(e => e.tagName + '.' + e.className)"""


@pytest.fixture(scope="module")
def long_report(tmp_path_factory):
    """36 stimuli, no figures: the per-stimulus table is longer than a printed page, and the ids occur
    nowhere else in the page, so finding each in the PDF's text means its row was printed."""
    from attneave.stimuli.stimulus_set import write_stimulus_set

    tmp = tmp_path_factory.mktemp("long")
    rng = np.random.default_rng(3)
    shapes = {}
    for i in range(36):
        k = 6 + i % 5
        th = 2 * np.pi * (np.arange(k) + rng.uniform(-0.3, 0.3, k)) / k  # star-shaped: never crosses itself
        r = 140 * rng.uniform(0.45, 1.0, k)
        shapes[f"zq{i:03d}"] = np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]
    write_stimulus_set(tmp / "set", shapes)
    assert main(["simulate", "--stimuli", str(tmp / "set"), "-o", str(tmp / "c.csv"), "--participants", "3",
                 "--clicks", "2", "--top-share", "0.4", "--seed", "2"]) == 0
    assert main(["analyze", str(tmp / "c.csv"), "--stimuli", str(tmp / "set"), "-o", str(tmp / "out"),
                 "--group-simulations", "49", "--permutations", "10", "--no-figures"]) == 0
    return tmp / "out", sorted(shapes)


def test_printed_report_keeps_every_per_stimulus_row(long_report, browser, tmp_path):
    out, ids = long_report
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto((out / "report.html").as_uri())
    page.emulate_media(media="print")
    # in print layout every row of the table is laid out, and no box around it clips or scrolls
    rows = page.evaluate("""() => Array.from(document.querySelectorAll('table.per-stimulus tbody tr')).map(r => {
        let clipped = false;
        for (let e = r.parentElement; e; e = e.parentElement) {
            const s = getComputedStyle(e);
            if ([s.overflow, s.overflowX, s.overflowY].some(v => v !== 'visible')) clipped = true;
        }
        return [r.cells[0].innerText, r.getBoundingClientRect().height, clipped];
    })""")
    assert [r[0] for r in rows] == ids
    assert all(h > 0 and not clipped for _, h, clipped in rows)
    assert page.evaluate(NO_SCROLL_BOX) == []
    pdf = tmp_path / "report.pdf"
    pdf.write_bytes(page.pdf(format="A4"))
    page.close()
    assert pdf.read_bytes().startswith(b"%PDF") and pdf.stat().st_size > 10_000
    # the printed text: every row's stimulus, when poppler's pdftotext is there to read it (CI installs it
    # and sets ATTNEAVE_REQUIRE_BROWSER=1, which turns its absence into a failure)
    if not shutil.which("pdftotext") and os.environ.get("ATTNEAVE_REQUIRE_BROWSER") == "1":
        pytest.fail("ATTNEAVE_REQUIRE_BROWSER=1 but pdftotext (poppler-utils) is not installed")
    if shutil.which("pdftotext"):
        import subprocess

        text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True,
                              check=True).stdout
        missing = [s for s in ids if s not in text]
        assert missing == [], f"rows missing from the printed report: {missing}"
        assert "References" in text and "Ziatdinov" in text


@pytest.mark.parametrize("width", [1280, 700])
def test_report_fits_the_window_without_scroll_boxes(report, browser, width):
    page = browser.new_page(viewport={"width": width, "height": 900})
    page.goto((report / "report.html").as_uri())
    shot = report / f"report_{width}.png"
    page.screenshot(path=str(shot), full_page=True)
    wide = page.evaluate("document.documentElement.scrollWidth")
    boxes = page.evaluate(NO_SCROLL_BOX)
    # nothing sticks out to the right of the window
    right = page.evaluate("Math.max(...Array.from(document.querySelectorAll('body *'))"
                          ".map(e => e.getBoundingClientRect().right))")
    page.close()
    assert wide <= width and right <= width + 0.5
    assert boxes == []
    assert shot.stat().st_size > 10_000
