"""Click files as labs hand them over: files joined together, ids written in another letter case."""

import json

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.clicks.exclusions import match_stimulus_ids
from attneave.analysis.clicks.mapping import map_clicks, predict
from attneave.analysis.clicks.read import read_clicks
from attneave.cli import main
from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set

W = H = 100
# the columns the browser page and the PsychoPy script write (task.js COLUMNS, attneave_task.py.in)
COLUMNS = ["participant", "stimulus_id", "x", "y", "click", "trial", "rt_ms", "condition", "list", "parent_id",
           "shown_w", "shown_h", "px_per_deg", "px_per_mm", "viewing_distance_cm", "screen_w", "screen_h",
           "device_pixel_ratio", "pointer_type", "user_agent", "timestamp"]


def _ellipse(cx, cy, a, b, n=64):
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[cx + a * np.cos(th), cy + b * np.sin(th)]


@pytest.fixture(scope="module")
def stimset(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    write_stimulus_set(d, {"rf_003": _ellipse(50, 50, 30, 15), "rf_004": _ellipse(50, 50, 15, 35)}, size=(W, H))
    return d


def _file(participant, agent, clicks_per_stimulus=3):
    """A participant's file as the page (agent with a comma, so quoted) or PsychoPy (no quotes) writes it."""
    lines = [",".join(COLUMNS)]
    for trial, (sid, a, b) in enumerate([("rf_003", 30, 15), ("rf_004", 15, 35)], start=1):
        for k in range(clicks_per_stimulus):
            th = 2 * np.pi * k / clicks_per_stimulus
            row = dict.fromkeys(COLUMNS, "")
            row.update(participant=participant, stimulus_id=sid, x=f"{50 + a * np.cos(th):.3f}",
                       y=f"{50 + b * np.sin(th):.3f}", click=k + 1, trial=trial, rt_ms=900, list=1,
                       shown_w=300, shown_h=300, px_per_deg=30, viewing_distance_cm=57, pointer_type="mouse",
                       user_agent=agent, timestamp="2026-01-01T10:00:00.000Z")
            lines.append(",".join(str(row[c]) for c in COLUMNS))
    return "\n".join(lines) + "\n"


BROWSER = '"Mozilla/5.0 (X11; Linux x86_64) AppleWebKit/537.36 (KHTML, like Gecko) Chrome/126.0 Safari/537.36"'


@pytest.mark.parametrize("agent", [BROWSER, "PsychoPy 2024.2.4"], ids=["browser", "psychopy"])
@pytest.mark.parametrize("bom", [False, True], ids=["utf8", "excel-bom"])
def test_files_joined_together_repeat_their_header_and_it_is_no_click(tmp_path, stimset, agent, bom):
    # `cat attneave_P01.csv attneave_P02.csv > all.csv`: the second header is a line of the file; it was
    # excluded as a click with non-numeric coordinates (with a hint about the decimal mark) and its
    # 'participant' value became a participant of per_participant.csv
    f = tmp_path / "all.csv"
    one, two = _file("P01", agent), _file("P02", agent)
    mark = "\ufeff" if bom else ""  # files re-saved by Excel each begin with a byte-order mark
    f.write_text(mark + one + mark + two, encoding="utf-8")
    clicks = read_clicks(f)
    assert len(clicks) == 13 and clicks["line"].tolist()[6] == 8
    mapped = map_clicks(clicks, predict(read_stimulus_set(stimset), n=20))
    assert mapped["reason"].tolist() == [""] * 6 + ["repeated_header"] + [""] * 6


def test_joined_files_analyse_with_the_header_excluded_and_no_fake_participant(tmp_path, stimset):
    f = tmp_path / "all.csv"
    f.write_text(_file("P01", BROWSER) + _file("P02", "PsychoPy 2024.2.4") + _file("P03", BROWSER), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["analyze", str(f), "--stimuli", str(stimset), "-o", str(out), "-n", "20", "--permutations", "9",
                 "--group-simulations", "19", "--no-figures"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["n_clicks"] == 20 and s["n_used"] == 18 and s["exclusions"]["repeated_header"] == 2
    assert s["exclusions"]["non_numeric_coordinate"] == 0
    assert pd.read_csv(out / "per_participant.csv")["participant"].tolist() == ["P01", "P02", "P03"]
    kept = pd.read_csv(out / "clicks.csv", keep_default_na=False)
    assert (kept.loc[kept["reason"] == "repeated_header", "line"] == [8, 15]).all()


def test_stimulus_values_in_another_letter_case_name_their_stimulus(stimset):
    # a path typed on Windows names the same file in any case (C:\EXP\RF_003.PNG is rf_003.png there)
    ids, how = match_stimulus_ids(["RF_003", "C:\\EXP\\IMAGES\\RF_004.PNG", "Images/Rf_003.png", "rf_003", "rf_9"],
                                  read_stimulus_set(stimset))
    assert ids.tolist() == ["rf_003", "rf_004", "rf_003", "rf_003", "rf_9"]
    assert how.tolist() == ["case", "case", "case", "id", ""]


def test_ids_that_differ_only_by_case_are_not_guessed(tmp_path):
    d = tmp_path / "set"
    write_stimulus_set(d, {"ab": _ellipse(50, 50, 30, 15), "AB": _ellipse(50, 50, 15, 35),
                           "c": _ellipse(50, 50, 20, 20)}, size=(W, H))
    ids, how = match_stimulus_ids(["ab", "AB", "C", "Ab", "x/Ab.png"], read_stimulus_set(d))
    assert ids.tolist() == ["ab", "AB", "c", "Ab", "x/Ab.png"] and how.tolist() == ["id", "id", "case", "", ""]


def _analyze(files, stimset, out, capsys):
    rc = main(["analyze", *map(str, files), "--stimuli", str(stimset), "-o", str(out), "-n", "20",
               "--permutations", "9", "--group-simulations", "99", "--no-figures"])
    return rc, capsys.readouterr()


def test_one_file_per_participant_is_analysed_as_one_table(tmp_path, stimset, capsys):
    # the experiment writes attneave_P01.csv, attneave_P02.csv, ...: analyze takes them all, each read
    # on its own (here one with ';' and decimal commas, as German Excel saves it), and gives the same
    # analysis as the files joined by hand
    (tmp_path / "attneave_P01.csv").write_text(_file("P01", BROWSER))
    euro = _file("P02", "PsychoPy 2024.2.4").replace(",", ";")
    euro = "\n".join(ln if i == 0 else _decimal_commas(ln) for i, ln in enumerate(euro.splitlines())) + "\n"
    (tmp_path / "attneave_P02.csv").write_text(euro)
    (tmp_path / "attneave_P03.csv").write_text(_file("P03", BROWSER))
    files = sorted(tmp_path.glob("attneave_*.csv"))
    rc, cap = _analyze(files, stimset, tmp_path / "out", capsys)
    assert rc == 0, cap.err
    clicks = pd.read_csv(tmp_path / "out" / "clicks.csv", keep_default_na=False)
    assert len(clicks) == 18 and not clicks["excluded"].any()
    assert [p.split("/")[-1] for p in clicks["source_file"].unique()] == [f.name for f in files]
    assert clicks.groupby("source_file")["line"].min().tolist() == [2, 2, 2]  # each file's own lines
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["group"]["n"] == 3 and s["inputs"]["clicks"] == [str(f) for f in files]
    joined = tmp_path / "joined.csv"
    joined.write_text(_file("P01", BROWSER) + _file("P02", BROWSER).split("\n", 1)[1]
                      + _file("P03", BROWSER).split("\n", 1)[1])
    rc, cap = _analyze([joined], stimset, tmp_path / "out_joined", capsys)
    t = json.loads((tmp_path / "out_joined" / "summary.json").read_text())
    assert rc == 0 and t["beta_hat"] == pytest.approx(s["beta_hat"], abs=1e-9)
    assert t["group"]["statistic"] == pytest.approx(s["group"]["statistic"], abs=1e-9)


def _decimal_commas(line):
    """A ';'-separated row with its numbers written with decimal commas (x, y: fields 3 and 4)."""
    f = line.split(";")
    f[2], f[3] = f[2].replace(".", ","), f[3].replace(".", ",")
    return ";".join(f)


def test_the_same_clicks_given_twice_are_refused(tmp_path, stimset, capsys):
    one = tmp_path / "attneave_P01.csv"
    one.write_text(_file("P01", BROWSER))
    copy = tmp_path / "download" / "attneave_P01.csv"  # the download and the copy that was POSTed
    copy.parent.mkdir()
    copy.write_text(one.read_text())
    for files, needle in (([one, one], "given twice"), ([one, copy], "the same contents as")):
        rc, cap = _analyze(files, stimset, tmp_path / "out", capsys)
        err = cap.err.strip().splitlines()
        assert rc == 2 and len(err) == 1 and needle in err[0], cap.err
        assert not (tmp_path / "out").exists()


def test_a_participant_in_several_files_is_named(tmp_path, stimset, capsys):
    (tmp_path / "a.csv").write_text(_file("P01", BROWSER))
    (tmp_path / "b.csv").write_text(_file("P01", BROWSER, clicks_per_stimulus=2))  # a second session
    rc, cap = _analyze([tmp_path / "a.csv", tmp_path / "b.csv"], stimset, tmp_path / "out", capsys)
    assert rc == 0
    assert "participant id(s) found in several click files" in cap.err and "P01 (2 files)" in cap.err
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["group"]["n"] == 1 and any("P01 (2 files)" in w for w in s["warnings"])


def test_a_bad_file_among_several_is_named(tmp_path, stimset, capsys):
    (tmp_path / "a.csv").write_text(_file("P01", BROWSER))
    (tmp_path / "b.csv").write_text("participant,stimulus,x\nP02,rf_003,1\n")
    rc, cap = _analyze([tmp_path / "a.csv", tmp_path / "b.csv"], stimset, tmp_path / "out", capsys)
    err = cap.err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "b.csv" in err[0] and "missing column" in err[0]


def test_rows_of_separators_only_are_no_clicks(tmp_path, stimset, capsys):
    # Excel keeps rows whose cells were cleared as ';;;;' lines: they are kept, excluded as empty_row,
    # and do not raise the "most clicks excluded" warning (40 such rows gave "27% of the clicks ...
    # were excluded: missing_coordinate 40"); a row with only x and y empty is still a missing click
    text = _file("P01", "PsychoPy 2024.2.4", clicks_per_stimulus=5).replace(",", ";")
    blank = ";" * (len(COLUMNS) - 1)
    half = ";".join(["P01", "rf_003", "", ""] + [""] * (len(COLUMNS) - 4))
    f = tmp_path / "excel.csv"
    f.write_text(text + "\n".join([half] + [blank] * 40) + "\n")
    rc, cap = _analyze([f], stimset, tmp_path / "out", capsys)
    assert rc == 0 and "were excluded" not in cap.err, cap.err
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["exclusions"]["empty_row"] == 40 and s["exclusions"]["missing_coordinate"] == 1
    assert s["n_used"] == 10 and len(pd.read_csv(tmp_path / "out" / "clicks.csv")) == 51
    only = tmp_path / "only.csv"
    only.write_text(";".join(COLUMNS) + "\n" + "\n".join([blank] * 3) + "\n")
    rc, cap = _analyze([only], stimset, tmp_path / "out2", capsys)
    assert rc == 1 and "no row is a click: empty_row 3" in cap.err


def test_rows_repeated_in_every_column_are_named(tmp_path, stimset, capsys):
    # the same file joined to itself (or a copy pasted twice): each click's timestamp makes real clicks
    # differ, so rows equal in every column are copies; they are analysed, and the warning says so
    one = _file("P01", BROWSER)
    f = tmp_path / "twice.csv"
    f.write_text(one + one)
    rc, cap = _analyze([f], stimset, tmp_path / "out", capsys)
    assert rc == 0 and "6 row(s) repeat an earlier row in every column (first at line 9)" in cap.err
    g = tmp_path / "once.csv"
    g.write_text(one)
    rc, cap = _analyze([g], stimset, tmp_path / "out2", capsys)
    assert rc == 0 and "repeat an earlier row" not in cap.err
