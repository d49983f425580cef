"""Audit of the experiment page as participants use it (headless Chromium, as test_experiment_browser).

Each test reproduces one defect found by the audit: ?fresh=1 forgotten again by a reload, a
right-click taken as a point, a stimulus cut off when a phone is turned mid-trial, the same
participant in two tabs, and a participant whose data were sent starting over on reopening.
"""

import json
import urllib.parse

import numpy as np
import pandas as pd

from attneave.analysis.experiment import order
from attneave.cli import main

from helpers import (
    analyze_clicks,
    client_xy,
    do_all_trials,
    do_one_trial,
    download_csv,
    expected_stimulus_order,
    page_url,
    target_points,
)


def _wait_trial(page):
    page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
    return page.get_attribute("#stimulus", "data-stimulus-id")


def test_fresh_forgets_once_so_a_reload_resumes(browser, setup, tmp_path):
    # a link with ?fresh=1 (an experimenter's "start again" link): a reload mid-experiment used to
    # forget the trials done again, because ?fresh=1 was still in the address
    ctx = browser.new_context(viewport={"width": 1280, "height": 800})
    page = ctx.new_page()
    page.on("dialog", lambda d: d.accept())
    page.goto(page_url(setup["exp"], participant="FR1", fresh=1))
    page.click("#next")
    first = [do_one_trial(page, setup["shapes"]) for _ in range(2)]
    page.wait_for_selector("#screen:not([hidden])[data-screen=break]")
    assert "fresh" not in urllib.parse.urlparse(page.url).query and "participant=FR1" in page.url
    page.reload()
    page.wait_for_selector("#screen:not([hidden])[data-screen=resume]")
    assert len(page.evaluate("window.attneaveData")) == 6
    page.click("#next")
    rest = do_all_trials(page, setup["shapes"])
    download_csv(page, tmp_path / "clicks.csv")
    ctx.close()
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    assert df.trial.astype(int).tolist() == [t for t in range(1, 5) for _ in range(3)]
    lst = order.participant_list("FR1", 2, "test")
    assert first + [s for s, *_ in rest] == expected_stimulus_order(setup, "FR1", lst)


def test_right_and_middle_clicks_select_no_point(browser, setup):
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto(page_url(setup["exp"], participant="RC1"))
    page.click("#next")
    sid = _wait_trial(page)
    x, y, _, _ = client_xy(page, target_points(setup["shapes"], sid)[0])
    page.mouse.click(x, y, button="right")
    page.mouse.click(x, y, button="middle")
    assert page.evaluate("document.querySelectorAll('#marks .mark').length") == 0
    assert page.is_disabled("#next")
    # the context menu is not opened over the stimulus
    assert page.evaluate("""() => { const e = new MouseEvent('contextmenu', {bubbles: true, cancelable: true});
        return !document.getElementById('stimulus').dispatchEvent(e); }""")
    for p in target_points(setup["shapes"], sid):
        page.mouse.click(*client_xy(page, p)[:2])
    page.click("#next")
    page.wait_for_function("window.attneaveData.length === 3")
    rows = page.evaluate("window.attneaveData")
    page.close()
    assert [r["click"] for r in rows] == [1, 2, 3]


def test_a_phone_turned_mid_trial_refits_the_stimulus_and_keeps_clicks_on_their_points(browser, setup, tmp_path):
    # the 160 x 120 image at 500 x 375 CSS px: in landscape it is shrunk to the stage's height, and
    # turned to portrait (390 CSS px wide) it used to keep its landscape size, cut off at both sides
    exp = tmp_path / "exp"
    assert main(["experiment", str(setup["set"]), "-o", str(exp), "--clicks", "3", "--size-px", "500",
                 "--fixation-ms", "0", "--iti-ms", "0", "--order", "fixed", "--conditions", "filler"]) == 0
    ctx = browser.new_context(viewport={"width": 844, "height": 390}, has_touch=True, is_mobile=True,
                              device_scale_factor=3)
    page = ctx.new_page()
    page.goto(page_url(exp, participant="turn"))
    page.tap("#next")
    sid = _wait_trial(page)
    targets = target_points(setup["shapes"], sid)
    page.touchscreen.tap(*client_xy(page, targets[0])[:2])
    page.set_viewport_size({"width": 390, "height": 844})   # turned to portrait, mid-trial
    page.wait_for_function("document.getElementById('stimulus').getBoundingClientRect().width <= 390")
    box = page.evaluate("""() => { const b = document.getElementById('stimulus').getBoundingClientRect();
        const s = document.getElementById('stage').getBoundingClientRect();
        return [b.left - s.left, b.top - s.top, s.right - b.right, s.bottom - b.bottom]; }""")
    assert min(box) >= 0, box                                 # the whole stimulus is within reach
    for p in targets[1:]:
        page.touchscreen.tap(*client_xy(page, p)[:2])
    # every mark sits on its point, the one placed before the turn too
    marks = page.evaluate("""() => [...document.querySelectorAll('#marks .mark')].map(m => {
        const b = m.getBoundingClientRect(); return [b.left + b.width / 2, b.top + b.height / 2]; })""")
    for (mx, my), p in zip(marks, targets):
        cx, cy, _, _ = client_xy(page, p)
        assert abs(mx - cx) < 1 and abs(my - cy) < 1, (mx, my, cx, cy)
    page.tap("#next")
    page.wait_for_selector("#download")
    download_csv(page, tmp_path / "clicks.csv")
    ctx.close()
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    w = df.shown_w.astype(float).to_numpy()
    assert w[0] > 390 and (w[1:] <= 390).all()                # shown_w: the size at each click
    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", setup["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0
    got = mapped.sort_values("click")[["x_image", "y_image"]].to_numpy(float)
    assert np.hypot(*(got - np.array(targets)).T).max() < 0.5


def test_the_same_participant_in_two_tabs_never_shows_a_stimulus_twice(browser, setup, tmp_path):
    # a link opened twice: both tabs used to run, each keeping its own trials over the other's
    ctx = browser.new_context(viewport={"width": 1280, "height": 800})
    one = ctx.new_page()
    one.on("dialog", lambda d: d.accept())
    one.goto(page_url(setup["exp"], participant="TT1"))
    one.click("#next")
    first = do_one_trial(one, setup["shapes"])
    _wait_trial(one)                                          # trial 2 shown in the first tab
    two = ctx.new_page()
    two.on("dialog", lambda d: d.accept())
    two.goto(page_url(setup["exp"], participant="TT1"))
    two.wait_for_selector("#screen:not([hidden])[data-screen=resume]")
    two.click("#next")
    second = do_one_trial(two, setup["shapes"])                 # the second tab keeps trial 2 first ...
    one.wait_for_selector("#screen:not([hidden])[data-screen=error]")  # ... so the first one stops
    assert "another tab" in one.inner_text("#screen") and one.is_hidden("#next")
    assert one.get_attribute("#stimulus", "data-stimulus-id") is None
    one.close()
    two.wait_for_selector("#screen:not([hidden])[data-screen=break]")
    two.click("#next")
    rest = do_all_trials(two, setup["shapes"])
    download_csv(two, tmp_path / "clicks.csv")
    ctx.close()
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    shown = [first, second] + [s for s, *_ in rest]
    assert df.stimulus_id.tolist()[::3] == shown and len(set(shown)) == 4
    assert df.trial.astype(int).tolist() == [t for t in range(1, 5) for _ in range(3)]
    assert shown == expected_stimulus_order(setup, "TT1", order.participant_list("TT1", 2, "test"))


def test_a_participant_whose_data_were_sent_sees_the_end_on_reopening(browser, setup, tmp_path):
    exp = tmp_path / "exp"
    assert main(["experiment", str(setup["set"]), "-o", str(exp), "--clicks", "3", "--size-px", "320",
                 "--fixation-ms", "0", "--iti-ms", "0", "--conditions", "filler", "--submit-url", "/submit"]) == 0
    posts = []

    def handle(route):
        path = urllib.parse.urlparse(route.request.url).path
        if path == "/submit":
            posts.append(route.request.post_data)
            route.fulfill(status=200, body="ok")
        else:
            f = exp / path.lstrip("/")
            route.fulfill(path=str(f)) if f.is_file() else route.fulfill(status=404)

    ctx = browser.new_context(viewport={"width": 1280, "height": 800})
    page = ctx.new_page()
    page.route("http://attneave.test/**", handle)
    page.goto("http://attneave.test/index.html?participant=SENT1")
    page.click("#next")
    do_one_trial(page, setup["shapes"])
    page.wait_for_selector("#submit-status[data-state=ok]")
    page.reload()                                              # opened again: the end, not a new run
    assert page.get_attribute("#screen", "data-screen") == "end"
    assert page.get_attribute("#submit-status", "data-state") == "ok"
    assert page.query_selector("#download") is None and page.is_hidden("#next")
    kept = page.evaluate("Object.keys(localStorage).map(k => JSON.parse(localStorage.getItem(k)))")
    assert len(kept) == 1 and kept[0]["rows"] == [] and kept[0]["submitted"] is True  # no data kept
    page.goto("http://attneave.test/index.html?participant=SENT1&fresh=1")  # the way to start again
    assert page.get_attribute("#screen", "data-screen") == "instructions"
    ctx.close()
    assert len(posts) == 1 and len(json.loads(posts[0])["rows"]) == 3
