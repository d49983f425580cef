"""Regenerate docs/experiment.png: the experiment page in headless Chromium at 1280 x 800.

    attneave generate configs/attneave_polygons.yaml -o out/attneave_polygons
    attneave experiment out/attneave_polygons -o out/exp --config configs/experiment.yaml
    python docs/screenshot_experiment.py out/exp out/attneave_polygons docs/experiment.png
"""

import sys
from pathlib import Path

import pandas as pd
from playwright.sync_api import sync_playwright

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def main(exp, stimset, png):
    exp, stimset = Path(exp).resolve(), Path(stimset).resolve()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.goto((exp / "index.html").as_uri() + "?participant=P01&px_per_mm=3.78")
        page.click("#next")
        page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        pts = pd.read_csv(stimset / "contours" / f"{sid}.csv").to_numpy()
        box = page.locator("#stimulus").bounding_box()
        w, h = page.evaluate("[document.getElementById('stimulus').naturalWidth, document.getElementById('stimulus').naturalHeight]")
        for k in (0, len(pts) // 4, len(pts) // 2):  # three points on the outline
            x, y = pts[k]
            page.mouse.click(box["x"] + (x + 0.5) * box["width"] / w, box["y"] + (y + 0.5) * box["height"] / h)
        page.mouse.move(box["x"] + box["width"] * 0.9, box["y"] + box["height"] * 0.1)
        page.screenshot(path=str(png))
        browser.close()


if __name__ == "__main__":
    main(*sys.argv[1:4])
