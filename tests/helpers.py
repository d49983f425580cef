"""Helpers shared by the test modules: a small stimulus set with images, and
driving the experiment page in headless Chromium (image pixels to client
coordinates, doing every trial, reading the page's click file).

Fixtures built on them (``browser``, ``setup``, ``stimset``) are in
``conftest.py``.
"""

import json
import os
import shutil
import urllib.parse

import numpy as np
import pandas as pd

from attneave.analysis.experiment import order
from attneave.cli import main
from attneave.stimuli.stimulus_set import write_stimulus_set

W, H = 160, 120


GROUND = 128

# three items in two conditions (peaks / troughs fragments of one base shape), and a filler


ITEMS = ("a", "b", "c")


def polygon(k, cx=80.0, cy=60.0):
    """A star-like polygon with 2k vertices, well inside the W x H canvas (x, y image px, y down)."""
    a = np.linspace(0, 2 * np.pi, 2 * k, endpoint=False)
    r = np.where(np.arange(2 * k) % 2 == 0, 44.0, 28.0)
    return np.c_[cx + r * np.cos(a), cy + 0.9 * r * np.sin(a)]


def make_set(directory):
    """A small stimulus set with images, conditions and parents; returns {id: vertices}."""
    import cv2

    shapes, conditions, parents = {}, {}, {}
    for i, item in enumerate(ITEMS):
        for j, cond in enumerate(("peaks", "troughs")):
            sid = f"{item}_{cond}"
            shapes[sid] = polygon(4 + i + j)
            conditions[sid], parents[sid] = cond, item
    shapes["filler"] = polygon(3)
    conditions["filler"], parents["filler"] = "filler", ""
    write_stimulus_set(directory, shapes, size=(W, H), condition=conditions)
    m = pd.read_csv(directory / "manifest.csv", dtype=str, keep_default_na=False)
    m["parent_id"] = [parents[s] for s in m["stimulus_id"]]
    m.to_csv(directory / "manifest.csv", index=False)
    (directory / "images").mkdir(exist_ok=True)
    for sid, pts in shapes.items():
        img = np.full((H, W), GROUND, np.uint8)
        cv2.fillPoly(img, [np.round(pts * 16).astype(np.int32)], 0, lineType=cv2.LINE_AA, shift=4)
        cv2.imwrite(str(directory / "images" / f"{sid}.png"), img)
    return shapes


CHROMIUM = "/usr/bin/chromium"


ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


PX_PER_DEG = 40.0


SIZE_DEG = 6.0  # the 160-px side is 240 CSS px: 1.5 CSS px per image px


def missing():
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "the playwright package is not installed (pip install playwright)"
    if not (os.path.exists(CHROMIUM) or shutil.which("chromium")):
        return f"{CHROMIUM} is not installed (apt-get install chromium)"
    return None


def with_timeout(make):
    def wrapped(*args, **kwargs):
        obj = make(*args, **kwargs)
        obj.set_default_timeout(20000)
        return obj
    return wrapped


def page_url(exp, **query):
    return (exp / "index.html").as_uri() + ("?" + urllib.parse.urlencode(query) if query else "")


def target_points(shapes, sid):
    """Three vertices of the stimulus's polygon: the points the participant means to select."""
    v = shapes[sid]
    return [tuple(v[k]) for k in (0, len(v) // 3, 2 * len(v) // 3)]


def client_xy(page, p):
    """Client (CSS px) coordinates of image pixel p on the current #stimulus."""
    r = page.evaluate("""() => { const e = document.getElementById('stimulus'); const b = e.getBoundingClientRect();
                      return [b.left, b.top, b.width, b.height, e.naturalWidth, e.naturalHeight]; }""")
    left, top, w, h, nw, nh = r
    return left + (p[0] + 0.5) * w / nw, top + (p[1] + 0.5) * h / nh, w, h


def do_all_trials(page, shapes, tap=False, wrong_first=False):
    """Do every trial: click (or tap) the three targets; returns [(stimulus_id, targets)] in shown order."""
    shown = []
    while True:
        state = page.wait_for_function("""() => document.getElementById('download') ? 'end'
            : document.querySelector('#screen:not([hidden])[data-screen=break]') ? 'break'
            : document.querySelector('#frame:not([hidden]) #stimulus[data-stimulus-id]') ? 'trial' : null""").json_value()
        if state == "end":
            return shown
        if state == "break":
            page.click("#next")
            continue
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        targets = target_points(shapes, sid)
        assert page.is_disabled("#next")
        if wrong_first and not shown:
            x, y, _, _ = client_xy(page, (5.0, 5.0))  # a slip: undone with Backspace
            page.mouse.click(x, y)
            page.keyboard.press("Backspace")
        for p in targets:
            x, y, w, h = client_xy(page, p)
            if tap:
                page.touchscreen.tap(x, y)
            else:
                page.mouse.click(x, y)
        assert not page.is_disabled("#next")
        shown.append((sid, targets, w, h))
        if len(shown) % 2:
            page.keyboard.press("Space")  # the keyboard contract: space = next
        else:
            page.click("#next")
        page.wait_for_function(f"() => document.getElementById('stimulus').getAttribute('data-stimulus-id') !== "
                               f"{json.dumps(sid)} || document.getElementById('download')")


def download_csv(page, path):
    href = page.get_attribute("#download", "href")
    assert href.startswith("data:text/csv")
    text = urllib.parse.unquote(href.split(",", 1)[1])
    path.write_text(text, encoding="utf-8")
    return text


def analyze_clicks(clicks, stimset, out):
    assert main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), "--no-figures",
                 "--permutations", "20", "--group-simulations", "0", "-n", "64"]) == 0
    return pd.read_csv(out / "clicks.csv", keep_default_na=False), json.loads((out / "summary.json").read_text())


def expected_stimulus_order(setup, participant, lst):
    mine = [s for s in json.loads(read_page_config(setup["exp"]))["stimuli"] if lst in s["lists"]]
    return order.trial_order(participant, [s["id"] for s in mine], [s["condition"] for s in mine], "random", "test")


def read_page_config(exp):
    html = (exp / "index.html").read_text()
    start = html.index('id="attneave-config">') + len('id="attneave-config">')
    return html[start:html.index("</script>", start)]


def check_click_mapping(mapped, shown, participant):
    mine = mapped[mapped.participant == participant]
    assert len(mine) == 3 * len(shown)
    assert (mine.excluded.astype(str) == "False").all() and (mine.reason == "").all()
    for sid, targets, _, _ in shown:
        rows = mine[mine.stimulus_id == sid].sort_values("click")
        got = rows[["x_image", "y_image"]].to_numpy(float)
        err = np.hypot(*(got - np.array(targets)).T)
        assert err.max() < 0.5, (sid, got, targets)      # the intended contour point, in image pixels
        assert rows.distance.astype(float).max() < 0.5   # and on the contour


def do_one_trial(page, shapes):
    """Click the three targets of the trial shown and press Next; returns its stimulus id."""
    page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
    sid = page.get_attribute("#stimulus", "data-stimulus-id")
    for p in target_points(shapes, sid):
        x, y, _, _ = client_xy(page, p)
        page.mouse.click(x, y)
    page.click("#next")
    return sid


def install_jspsych(exp, npm):
    """The lab's copy of jsPsych beside the page, as docs/experiment.md says to make it from npm."""
    lib = exp / "jspsych"
    lib.mkdir(exist_ok=True)
    shutil.copyfile(npm / "jspsych/dist/index.browser.js", lib / "jspsych.js")
    shutil.copyfile(npm / "jspsych/css/jspsych.css", lib / "jspsych.css")
    for plugin in ("instructions", "survey-text"):
        shutil.copyfile(npm / f"@jspsych/plugin-{plugin}/dist/index.browser.js", lib / f"plugin-{plugin}.js")


#: the study link's parameters reach the component page only through jatos.urlQueryParameters
STAND_IN = """
window.jatosCalls = [];
window.jatos = {
  urlQueryParameters: %(query)s,
  studyJsonInput: {},
  componentJsonInput: %(component_input)s,
  onLoad: function (cb) { jatosCalls.push(['onLoad']); setTimeout(cb, 5); },
  submitResultData: function (data) {
    jatosCalls.push(['submitResultData', data]);
    // the server refuses the first attempt: the page must try again
    var n = jatosCalls.filter(function (c) { return c[0] === 'submitResultData'; }).length;
    return n === 1 ? Promise.reject(new Error('503')) : Promise.resolve('ok');
  },
  endStudy: function () { jatosCalls.push(['endStudy'].concat([].slice.call(arguments))); },
  endStudyAndRedirect: function () { jatosCalls.push(['endStudyAndRedirect'].concat([].slice.call(arguments))); }
};
"""


def write_jatos_stand_in(exp, query, component_input):
    """A stand-in jatos.js beside the page that records the calls (window.jatosCalls)."""
    (exp / "jatos.js").write_text(STAND_IN % dict(query=json.dumps(query),
                                                  component_input=json.dumps(component_input)))
