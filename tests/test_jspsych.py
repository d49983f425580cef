"""The jsPsych page and plugin with the real jsPsych 8 from npm, in headless Chromium.

Nothing of jsPsych is shipped: ``ATTNEAVE_JSPSYCH_DIR`` names an npm prefix
where ``npm install jspsych@8 @jspsych/plugin-instructions
@jspsych/plugin-survey-text`` ran (``.ci/run`` makes one). Without it (or
without Chromium and playwright) the tests are skipped, unless
``ATTNEAVE_REQUIRE_BROWSER=1``, which makes the skip a failure.
"""

import json
import urllib.parse

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.experiment import order
from attneave.cli import main

from helpers import (
    PX_PER_DEG,
    SIZE_DEG,
    H,
    W,
    analyze_clicks,
    client_xy,
    install_jspsych,
    target_points,
    write_jatos_stand_in,
)

LAB_TIMELINE = """var timeline = [{type: jsPsychInstructions, pages: ['<p id="lab-welcome">Welcome to our lab.</p>'],
      show_clickable_nav: true}].concat(attneaveJsPsych.timeline(jsPsych),
      [{type: jsPsychSurveyText, questions: [{prompt: 'Your age?', name: 'age'}]}]);"""
GENERATED_TIMELINE = "var timeline = attneaveJsPsych.timeline(jsPsych);"


def lab_page(exp, timeline=LAB_TIMELINE):
    """jspsych.html with the lab's plugins loaded and its own trials around the task's."""
    html = (exp / "jspsych.html").read_text()
    assert html.count(GENERATED_TIMELINE) == 1
    html = html.replace('<script src="attneave-jspsych.js"></script>',
                        '<script src="attneave-jspsych.js"></script>\n<script src="jspsych/plugin-instructions.js">'
                        '</script>\n<script src="jspsych/plugin-survey-text.js"></script>')
    (exp / "lab.html").write_text(html.replace(GENERATED_TIMELINE, timeline))
    return exp / "lab.html"


def serve(page, exp, posts=None):
    """Serve `exp` at http://attneave.test/ (as a static host or JATOS would); POSTs to /submit recorded."""
    def handle(route):
        req = route.request
        path = urllib.parse.urlparse(req.url).path
        if path == "/submit" and posts is not None:
            posts.append(req.post_data)
            route.fulfill(status=200, body="ok")
        elif path == "/done":
            route.fulfill(status=200, body="<p id='completed'>completed</p>", content_type="text/html")
        else:
            f = exp / path.lstrip("/")
            route.fulfill(path=str(f)) if f.is_file() else route.fulfill(status=404)
    page.route("http://attneave.test/**", handle)


def run_task(page, shapes):
    """Do every screen and trial of the task; returns [(stimulus_id, targets, w, h, practice)] as shown."""
    shown = []
    while True:
        state = page.wait_for_function("""() => document.querySelector('#jspsych-survey-text-next') ? 'survey'
            : document.querySelector('#screen[data-screen=end], #completed') ? 'end'
            : document.querySelector('#frame:not([hidden]) #stimulus[data-stimulus-id]') ? 'trial'
            : document.querySelector('#screen[data-screen]') ?
              document.querySelector('#screen[data-screen]').getAttribute('data-screen') : null""").json_value()
        if state in ("survey", "end"):
            return shown, state
        if state != "trial":
            assert state in ("instructions", "practice-end", "break"), state
            page.click("#next")
            page.wait_for_function(f"() => !document.querySelector('#screen[data-screen={state}]')")
            continue
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        progress = page.inner_text("#progress")
        targets = target_points(shapes, sid)
        assert page.is_disabled("#next")
        for p in targets:
            x, y, w, h = client_xy(page, p)
            page.mouse.click(x, y)
        shown.append((sid, targets, w, h, progress.startswith("Practice")))
        page.click("#next")
        # the next trial may show its stimulus before a poll sees none: wait for another id or none
        page.wait_for_function(f"() => {{ const e = document.querySelector('#stimulus[data-stimulus-id]');"
                               f" return !e || e.getAttribute('data-stimulus-id') !== {json.dumps(sid)}; }}")


@pytest.fixture(scope="module")
def built(tmp_path_factory, jspsych_npm):
    from helpers import make_set

    root = tmp_path_factory.mktemp("jspsych")
    shapes = make_set(root / "set")
    return dict(root=root, set=root / "set", shapes=shapes, npm=jspsych_npm)


def test_lab_timeline_with_real_jspsych_gives_data_analyze_reads(browser, built, tmp_path):
    exp = tmp_path / "exp"
    assert main(["experiment", str(built["set"]), "-o", str(exp), "--jspsych", "--lists", "2", "--clicks", "3",
                 "--px-per-deg", str(PX_PER_DEG), "--size-deg", str(SIZE_DEG), "--fixation-ms", "30",
                 "--iti-ms", "0", "--practice", "a_peaks", "--seed", "test"]) == 0
    install_jspsych(exp, built["npm"])
    participant = "J01"
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.goto(lab_page(exp).as_uri() + f"?participant={participant}")
    page.wait_for_selector("#lab-welcome")
    page.click("#jspsych-instructions-next")                  # the lab's instructions trial
    shown, state = run_task(page, built["shapes"])
    assert state == "survey"
    page.fill("#input-0", "33")
    page.click("#jspsych-survey-text-next")                   # the lab's survey trial
    page.wait_for_selector("#screen[data-screen=end] #download")
    csv_text = page.evaluate("window.jsPsych.data.get().csv()")
    json_text = page.evaluate("window.jsPsych.data.get().json()")
    page.close()

    practice = [s for s in shown if s[4]]
    main_trials = [s for s in shown if not s[4]]
    assert [s[0] for s in practice] == ["a_peaks"]
    lst = order.participant_list(participant, 2, "test")
    config = json.loads(page_config_text(exp))
    mine = [s for s in config["stimuli"] if lst in s["lists"]]
    assert [s[0] for s in main_trials] == order.trial_order(participant, [s["id"] for s in mine],
                                                            [s["condition"] for s in mine], "random", "test")
    # CSS size != image size: the 160-px side at SIZE_DEG degrees of PX_PER_DEG px
    assert all(abs(w - SIZE_DEG * PX_PER_DEG) < 0.1 and abs(h - H * SIZE_DEG * PX_PER_DEG / W) < 0.1
               for _, _, w, h, _ in shown)
    rows = json.loads(json_text)
    points = [r for r in rows if r["trial_type"] == "attneave-points"]
    assert len(points) == len(main_trials) and all(len(r["clicks"]) == 3 for r in points)
    assert {r["participant"] for r in rows} == {participant} and {r["list"] for r in rows} == {lst}
    assert [r["trial_type"] for r in rows][:2] == ["instructions", "attneave-screen"]
    assert rows[-1]["trial_type"] == "survey-text" and rows[-1]["response"] == {"age": "33"}

    checked = [(s, t, w, h) for s, t, w, h, _ in main_trials]
    for name, text in (("data.csv", csv_text), ("data.json", json_text)):
        (tmp_path / name).write_text(text)
        mapped, summary = analyze_clicks(tmp_path / name, built["set"], tmp_path / f"results_{name}")
        assert summary["n_excluded"] == 0 and summary["n_clicks"] == 3 * len(main_trials)
        check_points(mapped, checked, participant)
        aside = json.dumps(summary.get("rows_set_aside"))
        for kind in ("instructions", "survey-text", "attneave-screen", "attneave-points-practice"):
            assert kind in aside, (kind, aside)


def check_points(mapped, shown, participant):
    """Every click analysed, none excluded, each within 0.5 image px of its intended contour point."""
    mine = mapped[mapped.participant == participant]
    assert len(mine) == 3 * len(shown)
    assert (mine.excluded.astype(str) == "False").all() and (mine.reason == "").all()
    for sid, targets, *_ in shown:
        rows = mine[mine.stimulus_id == sid]
        got = rows[["x_image", "y_image"]].to_numpy(float)   # in the order clicked (the list's)
        err = np.hypot(*(got - np.array(targets)).T)
        assert err.max() < 0.5, (sid, got, targets)
        assert rows.distance.astype(float).max() < 0.5


def page_config_text(exp):
    html = (exp / "jspsych.html").read_text()
    start = html.index('id="attneave-config">') + len('id="attneave-config">')
    return html[start:html.index("</script>", start)]


@pytest.mark.parametrize("page_name", ["index.html", "jspsych.html"])
def test_prolific_parameters_recorded_and_completion_after_the_data_are_sent(browser, built, tmp_path, page_name):
    exp = tmp_path / "exp"
    assert main(["experiment", str(built["set"]), "-o", str(exp), "--jspsych", "--clicks", "3", "--size-px", "320",
                 "--fixation-ms", "0", "--iti-ms", "0", "--conditions", "peaks", "--order", "fixed",
                 "--participant-param", "prolific", "--submit-url", "/submit",
                 "--completion-url", "http://attneave.test/done?cc=C0DE&pid={participant}"]) == 0
    install_jspsych(exp, built["npm"])
    posts = []
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    serve(page, exp, posts)
    pid = "5f0c1a2b3c4d5e6f7a8b9c0d"
    page.goto(f"http://attneave.test/{page_name}?PROLIFIC_PID={pid}&STUDY_ID=S123&SESSION_ID=X9")
    shown, _ = run_task(page, built["shapes"])
    page.wait_for_selector("#completed", timeout=20000)
    final = page.url
    page.close()

    # the redirect came after the POST and carries the id
    assert len(posts) == 1 and final == f"http://attneave.test/done?cc=C0DE&pid={pid}"
    body = json.loads(posts[0])
    assert body["participant"] == pid
    rows = [r for r in body["rows"] if r.get("trial_type", "attneave-points") == "attneave-points"]
    # index.html: a row per click; jspsych.html: a row per trial
    assert list(dict.fromkeys(r["stimulus_id"] for r in rows)) == [s[0] for s in shown] == ["a_peaks", "b_peaks",
                                                                                             "c_peaks"]
    assert len(rows) == (9 if page_name == "index.html" else 3)
    assert {(r["STUDY_ID"], r["SESSION_ID"]) for r in rows} == {("S123", "X9")}
    (tmp_path / "clicks.csv").write_text(body["csv"])
    df = pd.read_csv(tmp_path / "clicks.csv", dtype=str, keep_default_na=False)
    assert "STUDY_ID" in df.columns and "SESSION_ID" in df.columns
    mapped, summary = analyze_clicks(tmp_path / "clicks.csv", built["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0
    check_points(mapped, shown, pid)


def test_jspsych_page_in_jatos_submits_the_timeline_data_then_redirects(browser, built, tmp_path):
    exp = tmp_path / "exp"
    assert main(["experiment", str(built["set"]), "-o", str(exp), "--jspsych", "--jatos", "--clicks", "2",
                 "--size-px", "320", "--fixation-ms", "0", "--iti-ms", "0", "--conditions", "troughs",
                 "--participant-param", "mturk"]) == 0
    install_jspsych(exp, built["npm"])
    done = "https://www.mturk.com/mturk/externalSubmit?assignmentId=A7"
    write_jatos_stand_in(exp, {"workerId": "W123", "assignmentId": "A7", "hitId": "H9"}, {"completion_url": done})
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    serve(page, exp)
    page.goto("http://attneave.test/jspsych.html")
    shown, _ = run_task(page, built["shapes"])
    page.wait_for_selector("#submit-status[data-state=ok]", timeout=20000)
    calls = page.evaluate("window.jatosCalls")
    data = json.loads(page.evaluate("window.jsPsych.data.get().json()"))
    page.close()

    names = [c[0] for c in calls]
    assert names[0] == "onLoad" and names.count("submitResultData") == 2     # one refused, one retry
    assert [c for c in calls if c[0].startswith("endStudy")] == [["endStudyAndRedirect", done]]
    assert names[-1] == "endStudyAndRedirect"                                 # after the data were submitted
    submitted = json.loads(calls[-2][1])
    assert submitted == data                                                  # the timeline's rows, as they are
    points = [r for r in submitted if r["trial_type"] == "attneave-points"]
    assert [r["stimulus_id"] for r in points] == [s[0] for s in shown]
    assert {(r["participant"], r["assignmentId"], r["hitId"]) for r in points} == {("W123", "A7", "H9")}
    (tmp_path / "jatos.json").write_text(calls[-2][1])
    mapped, summary = analyze_clicks(tmp_path / "jatos.json", built["set"], tmp_path / "results")
    assert summary["n_excluded"] == 0 and summary["n_clicks"] == 2 * len(shown)
