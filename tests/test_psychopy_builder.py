"""The PsychoPy Builder export (attneave_task.psyexp): PsychoPy's own compiler, the order, the clicks.

PsychoPy is not a dependency: the compiler runs in the interpreter named by
ATTNEAVE_PSYCHOPY_PYTHON (a separate virtual environment; .ci/run makes one),
and those tests skip without it unless ATTNEAVE_REQUIRE_PSYCHOPY=1.
"""

import csv
import json
import os
import py_compile
import shutil
import subprocess
import textwrap
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from attneave.analysis.experiment import order, psyexp
from attneave.cli import main

PSYCHOPY = os.environ.get("ATTNEAVE_PSYCHOPY_PYTHON")


def _need_psychopy():
    if PSYCHOPY:
        return PSYCHOPY
    why = "ATTNEAVE_PSYCHOPY_PYTHON is not set (an interpreter with psychopy installed)"
    if os.environ.get("ATTNEAVE_REQUIRE_PSYCHOPY") == "1":
        pytest.fail(f"ATTNEAVE_REQUIRE_PSYCHOPY=1 but {why}")
    pytest.skip(why)


@pytest.fixture(scope="module")
def exported(stimset, tmp_path_factory):
    out = tmp_path_factory.mktemp("exp") / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--psychopy", "--practice", "1", "--lists", "2",
                 "--break-every", "2", "--seed", "s1"]) == 0
    return out / "psychopy"


def _code(root, component, key):
    el = root.find(f".//CodeComponent[@name='{component}']")
    return el.find(f"Param[@name='{key}']").get("val")


def _conditions(folder):
    with open(folder / "conditions.csv", newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


# ------------------------------------------------------------------ PsychoPy's compiler

def _compile(folder, target):
    py = _need_psychopy()
    out = folder / f"compiled{target}"
    # run from the experiment's folder, as Builder does (the compiler reads conditions.csv there)
    res = subprocess.run([py, "-m", "psychopy.scripts.psyexpCompile", str(folder / "attneave_task.psyexp"),
                          "-o", str(out)], cwd=folder, capture_output=True, text=True, timeout=600)
    log = res.stdout + res.stderr
    assert res.returncode == 0, log
    # the compiler logs its errors (a JS parse failure, a param it cannot translate) and still exits 0
    assert "ERROR" not in log and "Traceback" not in log, log
    return out, log


def test_psychopy_compiles_it_to_python(exported):
    out, _ = _compile(exported, ".py")
    py_compile.compile(str(out), doraise=True)
    text = out.read_text(encoding="utf-8-sig")
    assert "mouse.getPressed(getTime=True)" in text and "monitor='testMonitor'" in text
    assert "units='height'" in text
    assert "selection=practice_rows + main_rows" in text


def test_psychopy_compiles_it_to_psychojs_for_pavlovia(exported):
    out, _ = _compile(exported, ".js")
    text = out.read_text(encoding="utf-8-sig")
    # the compiler declares every name the code assigns (it parsed the JS), so no strict-mode ReferenceError
    for name in ("main_rows", "practice_rows", "attneave_settings", "attneave_x", "attneave_marks"):
        assert f"var {name};" in text
    assert "mouse.getPressed(true)" in text and "'conditions.csv'" in text
    assert "{'name': 'images/a_peaks.png', 'path': 'images/a_peaks.png'}" in text  # Pavlovia downloads it
    node = shutil.which("node")
    if node:  # a syntax check of the module as a browser would load it
        mjs = out.with_suffix(".mjs")
        shutil.copyfile(out, mjs)
        res = subprocess.run([node, "--check", str(mjs)], capture_output=True, text=True)
        assert res.returncode == 0, res.stderr


def test_psychopy_reads_the_experiment_as_written(exported):
    """PsychoPy's own loader finds the components, params and flow that were meant."""
    py = _need_psychopy()
    probe = textwrap.dedent("""
        import json, sys
        from psychopy import experiment
        exp = experiment.Experiment()
        exp.loadFromXML(sys.argv[1])
        trial = exp.routines["trial"]
        comps = {c.params["name"].val: (type(c).__name__, {k: str(p.val) for k, p in c.params.items()})
                 for c in trial}
        loop = [e for e in exp.flow if type(e).__name__ == "LoopInitiator"][0].loop
        print(json.dumps(dict(
            monitor=exp.settings.params["Monitor"].val, units=exp.settings.params["Units"].val,
            comps={k: v[0] for k, v in comps.items()}, image=comps["stimulus"][1], mouse=comps["mouse"][1],
            rows=str(loop.params["Selected rows"].val), file=str(loop.params["conditionsFile"].val),
            flow=[getattr(e, "name", None) or e.params["name"].val for e in exp.flow])))
    """)
    res = subprocess.run([py, "-c", probe, str(exported / "attneave_task.psyexp")], cwd=exported,
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert (got["monitor"], got["units"]) == ("testMonitor", "height")
    assert got["comps"]["stimulus"] == "ImageComponent" and got["comps"]["mouse"] == "MouseComponent"
    assert got["comps"]["trial_code"] == "CodeComponent"
    assert got["image"]["image"] == "$image" and got["image"]["size"] == "(size_w, size_h)"
    assert got["mouse"]["saveMouseState"] == "never"  # the code records presses (the module docstring says why)
    assert got["rows"] == "$practice_rows + main_rows" and got["file"] == "conditions.csv"
    assert got["flow"][0] == "instructions" and got["flow"][-1] == "end"


def test_the_order_code_runs_on_psychopys_own_conditions(exported):
    """The start-of-experiment code on what PsychoPy's importConditions really returns (numbers, pandas)."""
    py = _need_psychopy()
    root = ET.parse(exported / "attneave_task.psyexp").getroot()
    probe = ("import json\nfrom psychopy import data\nexpInfo = {'participant': 'P01', 'list': ''}\n"
             + _code(root, "setup_code", "Begin Experiment")
             + "\nprint(json.dumps([practice_rows, main_rows, expInfo['list']]))\n")
    res = subprocess.run([py, "-c", probe], cwd=exported, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout.strip().splitlines()[-1]) == list(_begin_python(exported, "P01"))


# ------------------------------------------------------------------ without PsychoPy

class _Data:
    """PsychoPy's data.importConditions as it reads conditions.csv: numbers where a cell reads as one."""

    def __init__(self, folder):
        self.folder = folder

    def importConditions(self, name):
        rows = []
        for r in _conditions(self.folder):
            out = {}
            for k, v in r.items():
                try:
                    out[k] = float(v)
                except ValueError:
                    out[k] = v
            rows.append(out)
        return rows


def _begin_python(folder, participant, lst=""):
    root = ET.parse(folder / "attneave_task.psyexp").getroot()
    expinfo = {"participant": participant, "list": lst}
    ns = dict(data=_Data(folder), expInfo=expinfo)
    exec(_code(root, "setup_code", "Begin Experiment"), ns)
    return ns["practice_rows"], ns["main_rows"], expinfo["list"]


@pytest.mark.parametrize("participant", ["P01", "x", "Zoë-7"])
def test_the_order_is_the_pages(exported, participant):
    rows = _conditions(exported)
    practice, main_rows, lst = _begin_python(exported, participant)
    assert [rows[i]["stimulus_id"] for i in practice] == ["a_peaks"]
    assert lst == order.participant_list(participant, 2, "s1")
    mine = [r for r in rows if r["practice"] == "0" and str(lst) in r["lists"].split(";")]
    expected = order.trial_order(participant, [r["stimulus_id"] for r in mine], None, "random", "s1")
    assert [rows[i]["stimulus_id"] for i in main_rows] == expected
    # a list given in the dialog wins
    assert _begin_python(exported, participant, "2")[2] == 2


def test_the_javascript_order_is_the_pythons(exported):
    node = shutil.which("node")
    if not node:
        pytest.skip("node is not installed")
    root = ET.parse(exported / "attneave_task.psyexp").getroot()
    rows = _Data(exported).importConditions("conditions.csv")
    stub = (f"const TrialHandler = {{importConditions: () => {json.dumps(rows)}}};\n"
            "const psychoJS = {serverManager: null};\n"
            "let attneave_settings, attneave_rows, attneave_participant, attneave_list, practice_rows, "
            "attneave_mine, main_rows;\n")
    for participant in ("P01", "x", "Zoë-7"):
        script = (stub + f"const expInfo = {{participant: {json.dumps(participant)}, list: ''}};\n"
                  + _code(root, "setup_code", "Begin JS Experiment")
                  + "\nconsole.log(JSON.stringify([practice_rows, main_rows]));\n")
        res = subprocess.run([node, "-e", script], capture_output=True, text=True)
        assert res.returncode == 0, res.stderr
        practice, main_rows, _ = _begin_python(exported, participant)
        assert json.loads(res.stdout) == [practice, main_rows]


class _Stim:
    status, units = 1, "height"

    def contains(self, mouse):
        return abs(mouse.pos[0]) < 0.4 and abs(mouse.pos[1]) < 0.3


class _Mouse:
    """event.Mouse after a tap that went down and up between two frames: button up, press time stamped."""

    def __init__(self):
        self.pos, self.times, self.buttons = (0.1, -0.2), [0.0, 0.0, 0.0], [0, 0, 0]

    def clickReset(self):
        self.times = [0.0, 0.0, 0.0]

    def getPressed(self, getTime=False):
        return (list(self.buttons), list(self.times)) if getTime else list(self.buttons)

    def getPos(self):
        return self.pos


class _Event:
    def __init__(self):
        self.keys = []

    def clearEvents(self):
        self.keys = []

    def getKeys(self, keyList=None):
        out, self.keys = [k for k in self.keys if k in keyList], []
        return out


class _Mark:
    def __init__(self, win, **kw):
        self.kw, self.drawn = kw, False

    def setAutoDraw(self, on):
        self.drawn = on


def test_a_tap_between_two_frames_is_a_click(exported):
    """Builder's Mouse component compares the button state once per frame; a tap that is over
    before the next frame leaves the state 'up' and would be lost. The export takes the press's time stamp."""
    root = ET.parse(exported / "attneave_task.psyexp").getroot()
    mouse, event = _Mouse(), _Event()
    ns = dict(stimulus=_Stim(), mouse=mouse, event=event, STARTED=1, win=None,
              visual=type("V", (), {"Circle": _Mark}), continueRoutine=True)
    exec(_code(root, "setup_code", "Begin Experiment").split("attneave_rows =")[0], ns)  # the settings
    exec(_code(root, "trial_code", "Begin Routine"), ns)
    frame = _code(root, "trial_code", "Each Frame")
    exec(frame, ns)  # the stimulus's first frame
    mouse.times[0] = 0.731  # down and up again before the next frame: buttons all 0
    exec(frame, ns)
    exec(frame, ns)  # nothing new: no second click
    assert (ns["attneave_x"], ns["attneave_y"], ns["attneave_t"]) == ([0.1], [-0.2], [0.731])
    assert [m.drawn for m in ns["attneave_marks"]] == [True]
    mouse.pos, mouse.times[0] = (0.9, 0.0), 1.2  # outside the image: no click
    exec(frame, ns)
    assert len(ns["attneave_x"]) == 1
    event.keys = ["backspace"]
    exec(frame, ns)
    assert ns["attneave_x"] == [] and ns["continueRoutine"]
    event.keys = ["space"]  # no clicks yet: space does not end the trial
    exec(frame, ns)
    assert ns["continueRoutine"]


def test_the_instructions_name_only_what_the_task_has(stimset, tmp_path):
    for extra, keys in ((["--clicks", "3"], ["Backspace", "Place 3 points"]),
                        (["--clicks", "done", "--no-undo"], ["at least 1"])):
        out = tmp_path / "_".join(extra)
        assert main(["experiment", str(stimset), "-o", str(out), "--psychopy", *extra]) == 0
        root = ET.parse(out / "psychopy" / "attneave_task.psyexp").getroot()
        text = root.find(".//TextComponent[@name='instructions_text']/Param[@name='text']").get("val")
        script = _load_script(out / "psychopy" / "attneave_task.py").SETTINGS["instructions"]
        for words in (text, script):
            assert "Next" not in words and "Undo" not in words
            assert all(k in words for k in keys)
            assert ("Backspace" in words) == ("--no-undo" not in extra)


def test_units_and_monitor(stimset, tmp_path):
    out = tmp_path / "deg"
    assert main(["experiment", str(stimset), "-o", str(out), "--psychopy", "--monitor", "lab 2"]) == 0
    root = ET.parse(out / "psychopy" / "attneave_task.psyexp").getroot()
    settings = {p.get("name"): p.get("val") for p in root.find("Settings")}
    assert (settings["Monitor"], settings["Units"]) == ("lab 2", "deg")
    assert root.get("version") == psyexp.PSYCHOPY_VERSION
    # every image the conditions name is inside the folder (Pavlovia uploads that folder only)
    for r in _conditions(out / "psychopy"):
        assert (out / "psychopy" / r["image"]).is_file() and not r["image"].startswith("..")


def _load_script(path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("attneave_task_monitor", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


class _Monitors:
    def __init__(self, known):
        self.known, self.saved, self.made = known, [], []

    def getAllMonitors(self):
        return list(self.known)

    def Monitor(self, name, **kw):
        parent = self

        class M:
            def setSizePix(self, size):
                self.size = size

            def save(self):
                parent.saved.append(name)
        self.made.append((name, kw))
        return M()


def test_the_coder_script_takes_its_monitor_from_monitor_center(exported):
    mod = _load_script(exported / "attneave_task.py")
    known = _Monitors(["testMonitor"])
    mod.monitor(known, "deg")
    assert known.made == [("testMonitor", {})] and known.saved == []  # found: used, not made again
    unknown = _Monitors([])
    mod.monitor(unknown, "height")
    assert unknown.saved == ["testMonitor"]  # saved once, so the next run finds it
    with pytest.raises(SystemExit, match="Monitor Center"):
        mod.monitor(_Monitors([]), "deg")


def test_a_column_of_numbers_and_text_is_named(stimset, tmp_path, capsys):
    import pandas as pd

    bad = tmp_path / "set"
    shutil.copytree(stimset, bad)
    m = pd.read_csv(bad / "manifest.csv", dtype=str, keep_default_na=False)
    m.loc[m["condition"] == "peaks", "condition"] = "1"
    m.to_csv(bad / "manifest.csv", index=False)
    assert main(["experiment", str(bad), "-o", str(tmp_path / "exp"), "--psychopy"]) == 0
    err = capsys.readouterr().err
    assert "column 'condition' holds numbers ('1') and text" in err and err.count("\n") == 1


def test_participant_texts_reach_the_compiled_scripts_as_written(stimset, tmp_path):
    """A leading $ (Builder's mark of code), quotes, braces and backslashes stay text in Python and PsychoJS."""
    text = "$5 for \"quoted\" it's {x} \\n back\\\\slash"
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--psychopy", "--instructions", text,
                 "--end-text", "Bye $1"]) == 0
    folder = out / "psychopy"
    for target in (".py", ".js"):
        compiled, _ = _compile(folder, target)
        body = compiled.read_text(encoding="utf-8-sig")
        if target == ".py":
            import ast

            strings = [n.value for n in ast.walk(ast.parse(body)) if isinstance(n, ast.Constant)
                       and isinstance(n.value, str)]
            assert any(s.startswith(text + "\n\n") for s in strings) and "Bye $1\n\n(press the space bar to close)" in strings
        else:
            assert json.dumps(text)[1:-1].replace('\\"', '"').replace("'", "\\'") in body


def test_a_data_file_written_by_psychopys_experimenthandler_gives_the_clicks(exported, tmp_path):
    """The Builder data file as PsychoPy itself writes it (ExperimentHandler, TrialHandler2 over the real
    importConditions) is read by analyze's reader with the clicks back in image pixels."""
    from attneave.analysis.clicks.read import read_clicks

    py = _need_psychopy()
    rows = _conditions(exported)
    clicks = [(10.25, 20.5), (150.0, 3.125), (79.5, 59.5)]  # image pixels of a 160 x 120 image
    sw, sh = float(rows[1]["size_w"]), float(rows[1]["size_h"])
    xs = [((x + 0.5) / 160 - 0.5) * sw for x, _ in clicks]
    ys = [(0.5 - (y + 0.5) / 120) * sh for _, y in clicks]
    out = tmp_path / "P01_attneave_task.csv"
    probe = textwrap.dedent(f"""
        from psychopy import data
        exp = data.ExperimentHandler(name="attneave_task", extraInfo={{"participant": "P01", "list": 1}},
                                     savePickle=False, saveWideText=False)
        exp.addData("instructions.started", 0.1)
        exp.nextEntry()
        trials = data.TrialHandler2(trialList=data.importConditions("conditions.csv", selection=[0, 1, 2]),
                                    nReps=1, method="sequential", name="trials")
        exp.addLoop(trials)
        for t in trials:
            exp.addData("mouse.x", {xs!r} if trials.thisN else [0.0])
            exp.addData("mouse.y", {ys!r} if trials.thisN else [0.0])
            exp.addData("mouse.time", [0.5, 0.75, 1.0] if trials.thisN else [0.4])
            exp.nextEntry()
        exp.addData("end.started", 9.0)
        exp.nextEntry()
        exp.saveAsWideText({str(out)!r})
    """)
    res = subprocess.run([py, "-c", probe], cwd=exported, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    t = read_clicks(out)
    assert t["stimulus_id"].tolist() == [rows[1]["stimulus_id"]] * 3 + [rows[2]["stimulus_id"]] * 3
    got = np.c_[t["x"].astype(float), t["y"].astype(float)]
    assert np.abs(got - np.array(clicks * 2)).max() < 1e-6
    assert t.attrs["set_aside"] == {"rows of routines outside the trials loop": 2, "practice trials": 1}
