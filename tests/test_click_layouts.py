"""analyze reads jsPsych data (CSV and JSON) and the attneave PsychoPy Builder data file.

The files are written here by hand in the layouts the tools document:
jsPsych's ``data.get().csv()`` (every field quoted, objects as JSON text) and
``.json()``; PsychoPy's ExperimentHandler wide CSV (the conditions' columns
copied into each row, mouse lists as ``[x1, x2]``). Each must give the same
clicks as the equivalent file in image pixels.
"""

import csv
import json

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.clicks.files import read_click_files
from attneave.analysis.clicks.read import read_clicks
from attneave.cli import main
from attneave.stimuli.errors import InputError

from helpers import H, W, make_set

# (participant, stimulus, [(x, y, rt)]) in image pixels
TRIALS = [("P01", "a_peaks", [(40.25, 30.5, 812), (100.0, 70.125, 1310), (79.5, 20.75, 1800)]),
          ("P01", "b_troughs", [(50.5, 60.0, 640)]),
          ("P01", "filler", [(80.0, 30.0, 500), (60.0, 80.0, 900)])]


def _plain(path, trials=TRIALS):
    rows = [dict(participant=p, stimulus_id=s, x=x, y=y) for p, s, cl in trials for x, y, _ in cl]
    pd.DataFrame(rows).to_csv(path, index=False)
    return path


def _jspsych_trials():
    out = [dict(trial_type="html-keyboard-response", trial_index=0, time_elapsed=1200, rt=1180,
                stimulus="<p>Welcome</p>", response=" ", internal_node_id="0.0-0.0"),
           dict(trial_type="survey-text", trial_index=1, time_elapsed=5000, rt=3800,
                response={"Q0": "P01", "Q1": "a, b"}, internal_node_id="0.0-1.0")]
    for k, (p, s, cl) in enumerate(TRIALS):
        out.append(dict(trial_type="attneave-points", trial_index=k + 2, time_elapsed=9000 + k, rt=2000,
                        stimulus_id=s, participant=p, internal_node_id=f"0.0-{k + 2}.0",
                        clicks=[dict(x=x, y=y, rt=rt) for x, y, rt in cl]))
    return out


def _jspsych_csv(path, trials):
    """jsPsych's JSON2CSV: a header of every key, every field quoted, objects as JSON."""
    keys = list(dict.fromkeys(k for t in trials for k in t))
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, quoting=csv.QUOTE_ALL, lineterminator="\r\n")
        w.writerow(keys)
        for t in trials:
            w.writerow([json.dumps(t[k]) if isinstance(t.get(k), (dict, list)) else t.get(k, "") for k in keys])
    return path


def _xy(table):
    return np.c_[table["x"].astype(float), table["y"].astype(float)]


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_jspsych_data_gives_the_clicks_of_the_pixel_file(tmp_path, fmt):
    trials = _jspsych_trials()
    path = tmp_path / f"data.{fmt}"
    if fmt == "csv":
        _jspsych_csv(path, trials)
    else:
        path.write_text(json.dumps(trials), encoding="utf-8")
    got, ref = read_clicks(path), read_clicks(_plain(tmp_path / "plain.csv"))
    assert np.array_equal(_xy(got), _xy(ref))
    assert got["stimulus_id"].tolist() == ref["stimulus_id"].tolist()
    assert got["participant"].tolist() == ["P01"] * 6
    assert got["clicks.rt"].tolist() == ["812", "1310", "1800", "640", "500", "900"]
    assert got["list_index"].tolist() == [0, 1, 2, 0, 0, 1]
    # the instructions and the survey (whose response is an object) are no clicks: set aside, counted
    assert got.attrs["set_aside"] == {"trial_type html-keyboard-response": 1, "trial_type survey-text": 1}
    assert "clicks" not in got.columns and set(got["trial_type"]) == {"attneave-points"}


def test_analyze_reports_the_rows_set_aside(tmp_path, capsys):
    stimset = tmp_path / "set"
    stimset.mkdir()
    shapes = make_set(stimset)
    trials = _jspsych_trials()
    for t in trials[2:]:  # clicks on the contours' vertices, as a participant aims
        pts = shapes[t["stimulus_id"]]
        t["clicks"] = [dict(x=float(pts[i][0]), y=float(pts[i][1]), rt=500 + i) for i in range(len(t["clicks"]))]
    path = _jspsych_csv(tmp_path / "data.csv", trials)
    out = tmp_path / "out"
    assert main(["analyze", str(path), "--stimuli", str(stimset), "-o", str(out), "--permutations", "20",
                 "--group-simulations", "0", "--no-figures"]) == 0
    err = capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["rows_set_aside"] == {"trial_type html-keyboard-response": 1, "trial_type survey-text": 1}
    assert summary["n_clicks"] == 6 and summary["n_excluded"] == 0
    assert "set aside" in err and "survey-text: 1" in err


def test_trial_type_chooses_among_several_that_hold_clicks(tmp_path):
    trials = _jspsych_trials()
    trials.append(dict(trial_type="my-clicker", trial_index=9, participant="P01", stimulus_id="a_peaks",
                       clicks=[dict(x=1.0, y=2.0)]))
    path = _jspsych_csv(tmp_path / "data.csv", trials)
    # the attneave plugin's type is the default among several
    assert len(read_clicks(path)) == 6
    mine = read_clicks(path, trial_type="my-clicker")
    assert _xy(mine).tolist() == [[1.0, 2.0]] and mine.attrs["set_aside"]["trial_type attneave-points"] == 3
    for t in trials:
        if t["trial_type"] == "attneave-points":
            t["trial_type"] = "other-clicker"
    with pytest.raises(InputError, match="several trial types: 'other-clicker' .3 rows., 'my-clicker' .1 rows.; "
                                         "choose one with --trial-type"):
        read_clicks(_jspsych_csv(tmp_path / "two.csv", trials))
    with pytest.raises(InputError, match="--trial-type: .* no rows of trial_type 'nope'"):
        read_clicks(path, trial_type="nope")
    with pytest.raises(InputError, match="--trial-type: .* has no column trial_type"):
        read_clicks(_plain(tmp_path / "plain.csv"), trial_type="attneave-points")


def test_a_clicks_column_of_another_name_and_the_message_without_one(tmp_path):
    trials = _jspsych_trials()
    for t in trials[2:]:
        t["points"] = t.pop("clicks")
    path = _jspsych_csv(tmp_path / "data.csv", trials)
    # found by its cells (lists of {x, y}); mapped by name it is the same
    assert np.array_equal(_xy(read_clicks(path)), _xy(read_clicks(path, columns="x=points")))
    assert "points.rt" in read_clicks(path, columns="x=points").columns
    for t in trials[2:]:
        t.pop("points")
    with pytest.raises(InputError) as exc:
        read_clicks(_jspsych_csv(tmp_path / "none.csv", trials))
    msg = str(exc.value)
    assert "no clicks found" in msg and '{"x": .., "y": .., "rt": ..}' in msg and "missing column" not in msg
    for t in trials[2:]:
        t["clicks"] = [dict(px=1, py=2)]
    with pytest.raises(InputError, match="keys px, py, not x and y"):
        read_clicks(_jspsych_csv(tmp_path / "keys.csv", trials))


# ------------------------------------------------------------------ PsychoPy Builder

def _window(x, y, size_w, size_h):
    """Image pixels -> the window units of an image drawn size_w x size_h at the centre, y up."""
    return ((x + 0.5) / W - 0.5) * size_w, (0.5 - (y + 0.5) / H) * size_h


def _builder_file(path, size_w, size_h, units, mangle_id=False, trials=TRIALS):
    """A data file as PsychoPy's ExperimentHandler writes Builder's (wide CSV, one row per routine outside
    the loop and per loop iteration, the conditions' columns in each trial row)."""
    head = ["thisRow.t", "notes", "instructions.started", "instructions.stopped", "image", "stimulus_id",
            "condition", "parent_id", "lists", "practice", "width_px", "height_px", "size_w", "size_h", "units",
            "trials.thisRepN", "trials.thisTrialN", "trials.thisN", "trials.thisIndex", "trials.ran",
            "trial.started", "stimulus.started", "mouse.started", "mouse.x", "mouse.y", "mouse.time", "clicks_n",
            "trial.stopped", "participant", "list", "date", "expName", "psychopyVersion", "frameRate", "expStart"]
    info = dict(participant="P01", list="1", date="2026-12-02_10h00.00.000", expName="attneave_task",
                psychopyVersion="2026.2.5", frameRate="60.0", expStart="2026-12-02 10h00.00.000000 +0000")
    rows = [dict(info, **{"thisRow.t": "3.2", "instructions.started": "0.1", "instructions.stopped": "3.2"})]
    practice = ("c_peaks", [(10.0, 10.0, 0)])
    for n, (sid, cl) in enumerate([practice] + [(s, c) for _, s, c in trials]):
        xs, ys = zip(*(_window(x, y, size_w, size_h) for x, y, _ in cl))
        row = dict(info, image=f"images/{sid}.png", stimulus_id="7.0" if mangle_id and n == 1 else sid,
                   condition=sid.split("_")[-1], parent_id=sid[0], lists="1;", practice="1" if n == 0 else "0",
                   width_px=str(W), height_px=str(H), size_w=repr(size_w), size_h=repr(size_h), units=units,
                   **{"trials.thisN": str(n), "mouse.x": repr(list(xs)), "mouse.y": repr(list(ys)),
                      "mouse.time": repr([rt / 1000 for *_, rt in cl]), "clicks_n": str(len(cl))})
        rows.append(row)
    rows.append(dict(info, **{"thisRow.t": "99.0"}))  # the end routine
    with open(path, "w", newline="", encoding="utf-8-sig") as fh:
        w = csv.DictWriter(fh, fieldnames=head, restval="", lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    return path


@pytest.mark.parametrize("size_w, size_h, units", [(0.8, 0.6, "height"), (8.0, 6.0, "deg"), (240.0, 180.0, "pix")])
def test_builder_data_gives_the_clicks_of_the_pixel_file(tmp_path, size_w, size_h, units):
    got = read_clicks(_builder_file(tmp_path / "P01_attneave_task.csv", size_w, size_h, units, mangle_id=True))
    ref = read_clicks(_plain(tmp_path / "plain.csv"))
    assert np.abs(_xy(got) - _xy(ref)).max() < 1e-6
    # importConditions made an id a number; the image's file name still names the stimulus
    assert got["stimulus_id"].tolist() == ref["stimulus_id"].tolist()
    assert got["input_stimulus_id"].iloc[0] == "7.0"
    assert got.attrs["set_aside"] == {"rows of routines outside the trials loop": 2, "practice trials": 1}
    # the values as written stay beside, one per click
    assert float(got["mouse.x"].iloc[1]) == pytest.approx(_window(100.0, 70.125, size_w, size_h)[0])
    assert got["mouse.time"].tolist()[:3] == ["0.812", "1.31", "1.8"]


def test_builder_data_through_analyze_as_the_pixel_file(tmp_path):
    stimset = tmp_path / "set"
    stimset.mkdir()
    shapes = make_set(stimset)
    # clicks on the contours' vertices, as a participant aims: none is excluded
    trials = [(p, s, [(float(shapes[s][i][0]), float(shapes[s][i][1]), 400 + i) for i in range(len(cl))])
              for p, s, cl in TRIALS]
    files = dict(builder=_builder_file(tmp_path / "b.csv", 0.8, 0.6, "height", trials=trials),
                 plain=_plain(tmp_path / "p.csv", trials))
    out = {}
    for name, path in files.items():
        assert main(["analyze", str(path), "--stimuli", str(stimset), "-o", str(tmp_path / name), "--permutations",
                     "20", "--group-simulations", "0", "--no-figures"]) == 0
        out[name] = pd.read_csv(tmp_path / name / "clicks.csv")
    assert np.abs(out["builder"][["x", "y"]].to_numpy() - out["plain"][["x", "y"]].to_numpy()).max() < 1e-6
    assert out["builder"]["stimulus_id"].tolist() == out["plain"]["stimulus_id"].tolist()
    assert not out["builder"]["excluded"].any()


def test_several_files_sum_what_was_set_aside(tmp_path):
    a = _builder_file(tmp_path / "a.csv", 0.8, 0.6, "height")
    b = _jspsych_csv(tmp_path / "b.csv", _jspsych_trials())
    t = read_click_files([a, b])
    assert len(t) == 12 and t.attrs["set_aside"] == {
        "rows of routines outside the trials loop": 2, "practice trials": 1,
        "trial_type html-keyboard-response": 1, "trial_type survey-text": 1}


def test_builder_data_refuses_a_second_conversion(tmp_path, stimset, capsys):
    path = _builder_file(tmp_path / "b.csv", 0.8, 0.6, "height")
    assert read_clicks(path).attrs["layout"] == "psychopy-builder"
    assert main(["analyze", str(path), "--stimuli", str(stimset), "-o", str(tmp_path / "o"), "--coords", "height",
                 "--window-size", "1920,1080"]) == 2
    assert "leave --coords and --scale out" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_a_clicks_cell_that_is_not_a_list_of_objects_is_a_malformed_row(tmp_path):
    from attneave.analysis.clicks.read import malformed_rows

    trials = _jspsych_trials()
    trials[3]["clicks"] = '[{"x": 1, "y": 2}, "cut'
    t = read_clicks(_jspsych_csv(tmp_path / "d.csv", trials))
    assert len(t) == 6 - 1 + 1 and malformed_rows(t).tolist() == [False] * 3 + [True] + [False] * 2
    assert "not a JSON list" in t["row_error"].iloc[3]
