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
    assert "e-1" not in text and "inf" not in text.replace("information", "").replace("infinite", "")


def test_every_figure_is_also_written_as_svg(report):
    pngs = sorted(p.stem for p in (report / "figures").glob("*.png"))
    svgs = sorted(p.stem for p in (report / "figures").glob("*.svg"))
    assert pngs == svgs and len(pngs) == 3
    assert (report / "figures" / "group.svg").read_text().lstrip().startswith("<?xml")
