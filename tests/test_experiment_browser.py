"""The experiment page in real headless Chromium: clicks in, a click file out, analysed as it is.

Needs Debian's ``chromium`` and the Python ``playwright`` package (no
``playwright install``). Skipped when they are missing, unless
``ATTNEAVE_REQUIRE_BROWSER=1`` (CI), which turns the skip into a failure.
"""

import json
import urllib.parse

import pandas as pd
import pytest

from attneave.analysis.experiment import calibration, order
from attneave.cli import main

from helpers import (
    PX_PER_DEG,
    SIZE_DEG,
    H,
    W,
    analyze_clicks,
    check_click_mapping,
    client_xy,
    do_all_trials,
    do_one_trial,
    download_csv,
    expected_stimulus_order,
    page_url,
    target_points,
)


def test_desktop_clicks_become_image_pixels_and_analyze_reads_them(browser, setup, tmp_path):
    participant = "P.01-x@lab"  # the page takes ids of letters, digits and _ . @ - only; the user agent's
    # commas and spaces still need the CSV's quoting
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto(page_url(setup["exp"], participant=participant))
    assert page.get_attribute("#screen", "data-screen") == "instructions"  # px_per_deg fixed: no calibration
    page.click("#next")
    shown = do_all_trials(page, setup["shapes"], wrong_first=True)
    rows = page.evaluate("window.attneaveData")
    text = download_csv(page, tmp_path / "clicks.csv")
    page.close()

    lst = order.participant_list(participant, 2, "test")
    assert [s for s, *_ in shown] == expected_stimulus_order(setup, participant, lst)  # Python predicts the JS order
    # CSS size != image size: 160 x 120 px shown at 240 x 180 CSS px
    assert all(abs(w - W * SIZE_DEG * PX_PER_DEG / W) < 0.1 and abs(h - H * 1.5) < 0.1 for _, _, w, h in shown)
    assert len(rows) == 3 * len(shown) == 12
    assert text.splitlines()[0].startswith("participant,stimulus_id,x,y,click,trial,rt_ms,condition,list,")
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    assert set(df.participant) == {participant} and set(df.list) == {str(lst)}
    assert df.user_agent.str.contains("Chrome").all()
    assert df.trial.astype(int).tolist() == [t for t in range(1, 5) for _ in range(3)]
    assert df.click.astype(int).tolist() == [1, 2, 3] * 4
    assert (df.rt_ms.astype(float) > 0).all() and df.px_per_deg.astype(float).eq(PX_PER_DEG).all()

    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", setup["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0 and summary["n_clicks"] == 12
    check_click_mapping(mapped, shown, participant)


def test_phone_touch_with_card_calibration(browser, setup, tmp_path):
    ctx = browser.new_context(viewport={"width": 390, "height": 844}, has_touch=True, is_mobile=True,
                              device_scale_factor=3)
    page = ctx.new_page()
    page.goto(page_url(setup["cal"], list=2, distance_cm=40))
    # no ?participant=: a screen asks for it
    assert page.get_attribute("#screen", "data-screen") == "participant"
    assert page.is_disabled("#next")
    page.fill("#participant-input", "phone-1")
    page.tap("#next")
    assert page.get_attribute("#screen", "data-screen") == "calibration"
    page.fill("#card-size", "400")              # the on-screen card now matches a real one: 400 CSS px
    assert page.evaluate("document.getElementById('card').getBoundingClientRect().width") == 400
    page.tap("#next")
    page.tap("#next")                           # instructions
    shown = do_all_trials(page, setup["shapes"], tap=True)
    download_csv(page, tmp_path / "clicks.csv")
    ctx.close()

    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    assert set(df.pointer_type) == {"touch"} and set(df.device_pixel_ratio) == {"3"} and set(df.list) == {"2"}
    ppm = 400 / calibration.CARD_WIDTH_MM
    ppd = calibration.px_per_degree(ppm, 400.0)
    assert df.px_per_mm.astype(float).to_numpy() == pytest.approx(ppm, abs=1e-4)
    assert df.px_per_deg.astype(float).to_numpy() == pytest.approx(ppd, abs=1e-4)
    # the 160-px side is SIZE_DEG degrees wide on the phone too
    assert df.shown_w.astype(float).to_numpy() == pytest.approx(SIZE_DEG * ppd, rel=1e-3)
    assert [s for s, *_ in shown] == expected_stimulus_order(setup, "phone-1", 2)
    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", setup["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0
    check_click_mapping(mapped, shown, "phone-1")


@pytest.mark.parametrize("ppm, distance_cm", [(4.0, 60.0), (2.5, 80.0)])
def test_stimulus_measures_its_size_in_degrees(browser, setup, ppm, distance_cm):
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto(page_url(setup["cal"], participant="size", px_per_mm=ppm, distance_cm=distance_cm))
    page.click("#next")                         # ?px_per_mm= skips the calibration
    page.wait_for_selector("#stimulus[data-stimulus-id]:visible")
    width = page.evaluate("document.getElementById('stimulus').getBoundingClientRect().width")
    page.close()
    # the largest image's larger side (all are 160 x 120 here) is SIZE_DEG degrees
    ppd = calibration.px_per_degree(ppm, distance_cm * 10)   # computed here, not by the page
    assert width / ppd == pytest.approx(SIZE_DEG, rel=0.01)


def test_static_host_submit_with_retry_done_mode_practice_and_undo(browser, setup, tmp_path):
    """Served over http (as by JATOS or any static host): POST the data, retrying after a server error."""
    exp = tmp_path / "exp"
    assert main(["experiment", str(setup["set"]), "-o", str(exp), "--clicks", "done", "--min-clicks", "2",
                 "--max-clicks", "3", "--practice", "1", "--conditions", "peaks,filler", "--size-px", "320",
                 "--fixation-ms", "0", "--iti-ms", "0", "--submit-url", "/submit", "--order", "fixed"]) == 0
    posts = []

    def handle(route):
        req = route.request
        path = urllib.parse.urlparse(req.url).path
        if path == "/submit":
            posts.append(req.post_data)
            # the first attempt meets a server error, the second succeeds
            route.fulfill(status=503 if len(posts) == 1 else 200, body="ok")
        else:
            f = exp / path.lstrip("/")
            route.fulfill(path=str(f)) if f.is_file() else route.fulfill(status=404)

    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.route("http://attneave.test/**", handle)
    page.goto("http://attneave.test/index.html?participant=web-1")
    page.click("#next")
    shapes = setup["shapes"]
    seen = []
    for _ in range(4):  # 1 practice (a_peaks, the first selected) + 3 main trials
        page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        seen.append(sid)
        t = target_points(shapes, sid)
        page.mouse.click(*client_xy(page, t[0])[:2])
        assert page.is_disabled("#next")                     # min_clicks = 2
        page.mouse.click(*client_xy(page, (2.0, 2.0))[:2])      # a slip ...
        page.click("#undo")                                   # ... undone with the button
        page.mouse.click(*client_xy(page, (3.0, 3.0))[:2])      # another ...
        page.keyboard.press("z")                              # ... undone with Z
        page.mouse.click(*client_xy(page, t[1])[:2])
        page.mouse.click(*client_xy(page, t[2])[:2])
        page.mouse.click(*client_xy(page, (4.0, 4.0))[:2])      # a 4th click: ignored (max_clicks = 3)
        page.click("#next")
        if len(seen) == 1:
            page.wait_for_selector("#screen:not([hidden])[data-screen=practice-end]")
            page.click("#next")
    page.wait_for_selector("#submit-status[data-state=ok]", timeout=20000)
    practice = page.evaluate("window.attneavePractice")
    data = page.evaluate("window.attneaveData")
    page.close()

    assert seen == ["a_peaks", "b_peaks", "c_peaks", "filler"]  # --order fixed
    assert len(posts) == 2 and posts[0] == posts[1]
    body = json.loads(posts[1])
    assert body["participant"] == "web-1" and body["rows"] == data
    assert len(practice) == 3 and {r["stimulus_id"] for r in practice} == {"a_peaks"}
    assert [r["stimulus_id"] for r in data] == [s for s in seen[1:] for _ in range(3)]  # practice not in the data
    (tmp_path / "clicks.csv").write_text(body["csv"])
    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", setup["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0
    check_click_mapping(mapped, [(s, target_points(shapes, s), 0, 0) for s in seen[1:]], "web-1")


@pytest.mark.parametrize("query, message", [
    ({"participant": "p", "list": "3"}, "list must be a whole number from 1 to 2"),
    ({"participant": "p", "px_per_mm": "wide"}, "px_per_mm must be a positive number"),
])
def test_bad_url_parameters_stop_with_a_message(browser, setup, query, message):
    page = browser.new_page()
    page.goto(page_url(setup["cal"], **query))
    assert page.get_attribute("#screen", "data-screen") == "error"
    assert message in page.inner_text("#screen")
    assert page.is_hidden("#next")
    page.close()


def test_a_reload_resumes_where_the_participant_was_and_keeps_every_click(browser, setup, tmp_path):
    # a participant reloads (or closes and reopens) the page after two of four trials: the two trials'
    # clicks are kept, the page resumes with the third, and the file holds all four trials once, in the
    # seeded order; leaving while trials are under way asks the browser's "leave site?" question
    participant = "R01"
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    page = context.new_page()
    asked = []
    page.on("dialog", lambda d: (asked.append(d.type), d.accept()))
    page.goto(page_url(setup["exp"], participant=participant))
    page.click("#next")  # instructions
    first = [do_one_trial(page, setup["shapes"]) for _ in range(2)]
    page.wait_for_selector("#screen:not([hidden])[data-screen=break]")
    before = page.evaluate("window.attneaveData")
    page.reload()
    assert asked == ["beforeunload"]
    page.wait_for_selector("#screen:not([hidden])[data-screen=resume]")
    assert "2 of 4" in page.inner_text("#screen")
    page.click("#next")
    rest = do_all_trials(page, setup["shapes"])
    text = download_csv(page, tmp_path / "clicks.csv")
    lst = order.participant_list(participant, 2, "test")
    assert first + [s for s, *_ in rest] == expected_stimulus_order(setup, participant, lst)
    rows = page.evaluate("window.attneaveData")
    assert rows[:6] == before and len(rows) == 12
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    assert df.trial.astype(int).tolist() == [t for t in range(1, 5) for _ in range(3)]
    assert df.stimulus_id.tolist()[::3] == first + [s for s, *_ in rest]

    # finished: opening the page again shows the end with the same file, and asks nothing on leaving
    page.reload()
    page.wait_for_selector("#download")
    assert download_csv(page, tmp_path / "again.csv") == text and asked == ["beforeunload"]
    # ?fresh=1 starts again; another participant in the same browser never sees R01's progress
    page.goto(page_url(setup["exp"], participant=participant, fresh=1))
    assert page.get_attribute("#screen", "data-screen") == "instructions"
    page.goto(page_url(setup["exp"], participant="R02"))
    assert page.get_attribute("#screen", "data-screen") == "instructions"
    context.close()
    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", setup["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0 and summary["n_clicks"] == 12
