"""Regression tests for defects found in review of the analysis package (issue 6)."""

from __future__ import annotations

import numpy as np
import pytest

from attneave.analysis.clicks.read import read_clicks
from attneave.stimuli.errors import InputError


# ---------------------------------------------------------------- reading click files
def test_trailing_delimiters_do_not_shift_columns(tmp_path):
    # exporters that end every data row with a comma: pandas would take the
    # first field as the index and shift every value one column to the left
    f = tmp_path / "c.csv"
    f.write_text("participant,stimulus_id,x,y\nP1,sq,100,20,\nP2,sq,150,200,\n")
    df = read_clicks(f)
    assert df["participant"].tolist() == ["P1", "P2"]
    assert df["stimulus_id"].tolist() == ["sq", "sq"]
    assert df["x"].tolist() == ["100", "150"] and df["y"].tolist() == ["20", "200"]


def test_extra_values_beyond_the_header_flag_the_row_naming_the_line(tmp_path):
    # issue 11 item 13: one malformed row no longer refuses the file; it is kept, flagged
    # (analysis excludes it with reason malformed_row) and its line is named
    f = tmp_path / "c.csv"
    f.write_text("participant,stimulus_id,x,y\nP1,sq,100,20\nP2,sq,150,200,7\n")
    df = read_clicks(f)
    assert df["line"].tolist() == [2, 3]
    assert df["row_error"].tolist() == ["", "5 fields, the header has 4"]


def test_line_numbers_count_blank_lines_and_multiline_fields(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text('participant,stimulus_id,x,y,note\n'
                 'P1,sq,1,2,a\n'
                 '\n'
                 'P2,sq,3,4,"two\nlines"\n'
                 ',,,,\n'
                 'P3,sq,5,6,b\n'
                 '\n\n')
    df = read_clicks(f)
    # blank lines are not rows; a row of empty fields is (it is excluded later, not dropped)
    assert df["participant"].tolist() == ["P1", "P2", "", "P3"]
    assert df["line"].tolist() == [2, 4, 6, 7]
    assert df["note"].tolist() == ["a", "two\nlines", "", "b"]


def test_manifest_with_trailing_delimiters_and_blank_lines(tmp_path):
    from attneave.stimuli.stimulus_set import read_stimulus_set

    (tmp_path / "contours").mkdir()
    (tmp_path / "contours" / "sq.csv").write_text("x,y\n10,10\n10,50\n50,50\n50,10\n")
    (tmp_path / "manifest.csv").write_text("stimulus_id,contour,width,height\n"
                                           "sq,contours/sq.csv,64,64,\n\n"
                                           "bad id,contours/sq.csv,64,64,\n")
    with pytest.raises(InputError, match=r"manifest.csv: line 4: stimulus_id must match"):
        read_stimulus_set(tmp_path)
    (tmp_path / "manifest.csv").write_text("stimulus_id,contour,width,height\nsq,contours/sq.csv,64,64,\n")
    s = read_stimulus_set(tmp_path)
    assert s.ids == ["sq"] and s.sizes["sq"] == (64, 64)


# ------------------------------------------------------------------ writing outputs
def _tiny_set(d):
    from attneave.stimuli.stimulus_set import write_stimulus_set

    th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    write_stimulus_set(d, {"ell": np.c_[100 + 60 * np.cos(th), 100 + 30 * np.sin(th)],
                           "sq": np.array([[50.0, 50], [50, 150], [150, 150], [150, 50]])}, size=(200, 200))
    return d


def test_unwritable_output_location_is_one_line_exit_2(tmp_path, capsys):
    from attneave.cli import main

    s = _tiny_set(tmp_path / "set")
    f = tmp_path / "c.csv"
    f.write_text("participant,stimulus_id,x,y\nP1,ell,160,100\nP2,sq,50,50\n")
    blocker = tmp_path / "afile"
    blocker.write_text("")
    rc = main(["analyze", str(f), "--stimuli", str(s), "-o", str(blocker / "out"), "--no-figures",
               "--permutations", "10"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "error:" in err and "afile" in err and len(err.strip().splitlines()) == 1


# -------------------------------------------------------------------------- statistics
def test_participant_without_informative_clicks_has_no_effect(tmp_path):
    # clicks on a circle (constant surprisal, z = 0 everywhere) say nothing about
    # the prediction: a participant who clicked only there has no measured effect,
    # not an effect of exactly 0 that would enter the group t-test as data
    from attneave.analysis.analyze import analyze
    from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set

    th = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    d = tmp_path / "set"
    write_stimulus_set(d, {"ell": np.c_[100 + 80 * np.cos(th), 100 + 30 * np.sin(th)],
                           "disc": np.c_[100 + 50 * np.cos(th), 100 + 50 * np.sin(th)]}, size=(200, 200))
    s = read_stimulus_set(d)
    import pandas as pd

    rows = [("A", "disc", 150.0, 100.0), ("A", "disc", 100.0, 150.0)]
    for p, xs in (("B", (180.0, 20.0, 100.0)), ("C", (180.0, 20.0, 180.0)), ("D", (20.0, 100.0, 180.0))):
        rows += [(p, "ell", x, 100.0 if x != 100.0 else 70.0) for x in xs]
    res = analyze(pd.DataFrame(rows, columns=["participant", "stimulus_id", "x", "y"]), s, n=100, permutations=0)
    assert res.per_stimulus.set_index("stimulus_id").loc["disc", "constant_prediction"]
    pp = res.per_participant.set_index("participant")
    assert pp.loc["A", "n_used"] == 2
    assert np.isnan(pp.loc["A", "mean_z"]) and np.isnan(pp.loc["A", "auc"])
    assert res.summary["group"]["n"] == 3
    assert res.summary["auc"]["test_vs_half"]["n"] == 3
    assert all(np.isfinite(pp.loc[["B", "C", "D"], "mean_z"]))


def test_power_checks_its_output_before_simulating(tmp_path, monkeypatch, capsys):
    import attneave.analysis.simulate.observers
    from attneave.cli import main

    s = _tiny_set(tmp_path / "set")

    def boom(*a, **k):  # the simulation must not start
        raise AssertionError("power() ran before the output was checked")

    monkeypatch.setattr(attneave.analysis.simulate.observers, "power", boom)
    rc = main(["power", "--stimuli", str(s), "--beta", "0.5", "--participants", "2,4", "--simulations", "2",
               "-o", str(tmp_path / "no_such_dir" / "p.csv")])
    assert rc == 2 and "no_such_dir" in capsys.readouterr().err
