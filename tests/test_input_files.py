"""Fault cases of issue 11, input side: special files, sizes, overflow, the files real tools write.

One test per item (4, 9, 10, 11, 12, 13, 14); each failed on the code as it was
before the fix. Every command is run in-process through ``attneave.cli.main``
except the one smoke test whose point is ``python -W error::RuntimeWarning``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main
from attneave.stimuli.stimulus_set import write_stimulus_set

DATA = Path(__file__).parent / "data"
WINDOW = (1920, 1080)  # the window of the PsychoPy fixture


def _rf(k):
    """A radial-frequency contour with k lobes, 200 points, centred in a 512 x 512 image."""
    th = 2 * np.pi * np.arange(200) / 200
    r = 100 + 30 * np.cos(k * th)
    return np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]


@pytest.fixture(scope="module")
def stimset(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    write_stimulus_set(d, {"rf_003": _rf(3), "rf_005": _rf(5)}, size=(512, 512))
    return d


def _cli(argv, capsys):
    """Run the command line in-process -> (exit status, stderr)."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse's usage errors
        code = exc.code
    err = capsys.readouterr().err
    return code, err


def _one_line_error(code, err, status=2):
    assert code == status, err
    assert err.count("\n") == 1 and "Traceback" not in err, err


def _square_csv(path, side=100.0, offset=0.0):
    pd.DataFrame({"x": np.array([0, side, side, 0]) + offset, "y": np.array([0, 0, side, side]) + offset}).to_csv(
        path, index=False, float_format="%.17g")
    return path


# --------------------------------------------------------------------------- item 4
def _unblock(fifo, every=5):
    """Open `fifo` for writing every `every` s until the returned event is set.

    A reader blocked on the FIFO (the old code) then sees an empty file and
    fails differently instead of hanging the suite.
    """
    done = threading.Event()

    def unblock():
        while not done.wait(every):
            try:
                os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
            except OSError:
                pass

    threading.Thread(target=unblock, daemon=True).start()
    return done


def test_item4_special_files_are_refused_not_read(tmp_path, stimset, capsys):
    # a FIFO blocked the reader forever; a writer opened after 5 s keeps the old code from
    # hanging the suite (it then failed on the empty file instead of naming the FIFO)
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    done = _unblock(fifo)
    try:
        code, err = _cli(["surprisal", fifo, "-o", tmp_path / "o.csv"], capsys)
        _one_line_error(code, err)
        assert "FIFO" in err and "not a regular file" in err
        code, err = _cli(["analyze", fifo, "--stimuli", stimset, "-o", tmp_path / "out"], capsys)
        _one_line_error(code, err)
        assert "FIFO" in err
    finally:
        done.set()
    # a character device: /dev/null reads as empty and /dev/zero without end
    code, err = _cli(["surprisal", "/dev/null", "-o", tmp_path / "o.csv"], capsys)
    _one_line_error(code, err)
    assert "character device" in err
    assert not (tmp_path / "o.csv").exists() and not (tmp_path / "out").exists()


# --------------------------------------------------------------------------- item 9
@pytest.mark.parametrize("args,expected", [
    (["-n", "100000000"], "n <= 1,000,000"),
    (["-n", "1000000000000"], "n <= 1,000,000"),
    (["-n", "-5"], "3 <= n"),
    (["-n", "1e12"], "invalid int value"),
    (["-n", "inf"], "invalid int value"),
    (["--spacing", "1e-9"], "n <= 1,000,000"),
    (["--spacing", "nan"], "finite"),
    (["--spacing", "-1"], "> 0"),
    (["--spacing", "text"], "invalid float value"),
])
def test_item9_surprisal_sizes_are_bounded_and_named(tmp_path, capsys, args, expected):
    src = _square_csv(tmp_path / "sq.csv")
    code, err = _cli(["surprisal", src, "-o", tmp_path / "o.csv", *args], capsys)
    _one_line_error(code, err)
    assert expected in err
    assert not (tmp_path / "o.csv").exists()


# --------------------------------------------------------------------------- item 10
def test_item10_input_size_is_bounded_before_reading(tmp_path, stimset, capsys):
    from attneave.stimuli.io import MAX_TEXT_BYTES

    big = tmp_path / "big.csv"
    with open(big, "wb") as fh:  # sparse: no disk used, but st_size says 201 MB
        fh.write(b"x,y\n")
        fh.truncate(MAX_TEXT_BYTES + 1)
    for argv in (["surprisal", big, "-o", tmp_path / "o.csv"],
                 ["analyze", big, "--stimuli", stimset, "-o", tmp_path / "out"]):
        code, err = _cli(argv, capsys)
        _one_line_error(code, err)
        assert "larger than the limit of 200 MB" in err


# --------------------------------------------------------------------------- item 11
@pytest.mark.parametrize("side,offset,expected", [
    (1e308, -1e308, "within +-1e+12 px"),  # coordinates whose differences overflow
    (1e-300, 0.0, "spans only 1e-300 px"),  # a square whose squared sides underflow
    (1.0, 1e11, "spans only 1 px"),  # a shape resolved only by rounding, far from the origin
])
def test_item11_overflowing_or_degenerate_contours_are_errors(tmp_path, capsys, side, offset, expected):
    src = _square_csv(tmp_path / "sq.csv", side, offset)
    code, err = _cli(["surprisal", src, "-o", tmp_path / "o.csv"], capsys)
    _one_line_error(code, err)
    assert expected in err and "rescale" in err
    assert not (tmp_path / "o.csv").exists()


def test_item11_an_overflowing_surprisal_is_an_error_not_inf(tmp_path, capsys):
    # b * ds^2 beyond the largest double (ds in pixels, as the paper writes it): the old code wrote
    # -inf for every point, exit 0
    src = _square_csv(tmp_path / "sq.csv", side=1e12)
    code, err = _cli(["surprisal", src, "-o", tmp_path / "o.csv", "--b", "1e300", "--length-unit", "px"], capsys)
    _one_line_error(code, err)
    assert "overflows" in err and not (tmp_path / "o.csv").exists()


def test_item11_no_runtime_warning_reaches_the_user(tmp_path, stimset):
    # a real process: -W error::RuntimeWarning turns any numpy warning into a traceback
    src = _square_csv(tmp_path / "huge.csv", side=1e308, offset=-1e308)
    clicks = tmp_path / "clicks.csv"
    pts = _rf(3)[::25]
    pd.DataFrame({"participant": "P1", "stimulus_id": "rf_003", "x": [*pts[:, 0], 1e308, -1e200],
                  "y": [*pts[:, 1], 1e308, 5.0]}).to_csv(clicks, index=False)
    env = dict(os.environ, MPLBACKEND="Agg")
    script = ("import sys; from attneave.cli import main; "
              "codes = [main(a) for a in sys.argv[1:] and [sys.argv[1:5], sys.argv[5:]]]; print(codes)")
    argv = ["surprisal", str(src), "-o", str(tmp_path / "o.csv"),
            "analyze", str(clicks), "--stimuli", str(stimset), "-o", str(tmp_path / "out"),
            "--group-simulations", "19", "--permutations", "19", "--no-figures"]
    r = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-c", script, *argv],
                       capture_output=True, text=True, env=env, timeout=120)
    assert "Warning" not in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert r.stdout.strip().splitlines()[-1] == "[2, 0]", r.stdout + r.stderr
    out = pd.read_csv(tmp_path / "out" / "clicks.csv", keep_default_na=False)
    assert out["reason"].tolist()[-2:] == ["coordinate_out_of_range"] * 2


# --------------------------------------------------------------------------- item 12
def _mapped(out):
    m = pd.read_csv(Path(out) / "clicks.csv", dtype={"reason": str, "row_error": str})
    return m.assign(reason=m["reason"].fillna(""))


def test_item12_psychopy_and_jspsych_files_are_analysed_as_they_are(tmp_path, stimset, capsys):
    # PsychoPy Builder: image paths (POSIX, Windows, bare file name) as the stimulus, list-valued
    # mouse columns (one to three clicks per trial), height units, a trailing comma on every line
    out = tmp_path / "psychopy"
    code, err = _cli(["analyze", DATA / "psychopy_height.csv", "--stimuli", stimset, "-o", out,
                      "--columns", "stimulus_id=image_file,x=mouse.x,y=mouse.y", "--coords", "height",
                      "--window-size", "1920,1080", "--group-simulations", "19", "--permutations", "19",
                      "--no-figures"], capsys)
    assert code == 0, err
    m = _mapped(out)
    assert len(m) == 7 and not m["excluded"].any()
    assert m["stimulus_id"].tolist() == ["rf_003", "rf_005", "rf_005", "rf_003", "rf_005", "rf_005", "rf_005"]
    assert m["stimulus_as_written"].tolist()[2] == "C:\\exp\\stimuli\\rf_003.png" or \
        m["stimulus_as_written"].tolist()[3] == "C:\\exp\\stimuli\\rf_003.png"
    # the fixture's clicks are contour vertices written to 6 decimals of the window height
    assert m["distance"].max() < 1e-3
    assert m["list_index"].tolist() == [-1, 0, 1, -1, 0, 1, 2]
    assert m["mouse.time"].tolist() == ["[1.2000]", "1.2000", "2.1000", "[1.2000]", "1.2000", "2.1000", "3.0000"]
    # jsPsych: every value quoted, the stimulus an image path, an instruction trial first
    out = tmp_path / "jspsych"
    code, err = _cli(["analyze", DATA / "jspsych.csv", "--stimuli", stimset, "-o", out,
                      "--columns", "participant=subject,stimulus_id=stimulus,x=click_x,y=click_y",
                      "--group-simulations", "19", "--permutations", "19", "--no-figures"], capsys)
    assert code == 0, err
    m = _mapped(out)
    # the instruction trial (no click) is set aside as a row of another kind, not an excluded click
    assert m["reason"].tolist() == [""] * 8
    assert m["distance"].max() < 1e-3
    # 1 of 9 excluded: under the 20% threshold (one participant: the warnings of a design too small remain)
    assert "set aside" in err and "html-keyboard-response: 1" in err and "only 1 participant" in err
    assert "click(s) excluded" not in err and "clicks excluded" not in err


def test_item12_many_exclusions_warn_and_none_usable_is_exit_1(tmp_path, stimset, capsys):
    clicks = tmp_path / "c.csv"
    pts = _rf(3)[::10]
    # clicks recorded on an image shown 1.15 times its size, analysed without --scale
    shown = (pts + 0.5) * 1.15 - 0.5
    pd.DataFrame({"participant": "P1", "stimulus_id": "rf_003", "x": shown[:, 0], "y": shown[:, 1]}).to_csv(
        clicks, index=False)
    code, err = _cli(["analyze", clicks, "--stimuli", stimset, "-o", tmp_path / "out",
                      "--group-simulations", "19", "--permutations", "19", "--no-figures"], capsys)
    assert code == 0, err
    m = _mapped(tmp_path / "out")
    k = int(m["excluded"].sum())
    assert 0.2 * len(m) < k < len(m)  # the case of the issue: most excluded, a p-value from the rest
    warning = [ln for ln in err.splitlines() if "were excluded" in ln]
    assert len(warning) == 1 and f"({k} of {len(m)})" in warning[0] and "--scale" in warning[0]
    assert any("were excluded" in w for w in json.loads((tmp_path / "out" / "summary.json").read_text())["warnings"])
    # with the scale the same clicks all land on the contour
    code, err = _cli(["analyze", clicks, "--stimuli", stimset, "-o", tmp_path / "out2", "--scale", "1.15",
                      "--group-simulations", "19", "--permutations", "19", "--no-figures"], capsys)
    assert code == 0 and "were excluded" not in err
    assert not _mapped(tmp_path / "out2")["excluded"].any()
    # no usable click: exit 1, one line, no output directory
    bad = tmp_path / "bad.csv"
    bad.write_text("participant,stimulus_id,x,y\nP1,nope.png,1,2\nP1,nope.png,3,4\n")
    code, err = _cli(["analyze", bad, "--stimuli", stimset, "-o", tmp_path / "out3"], capsys)
    _one_line_error(code, err, status=1)
    assert "no usable click" in err and "unknown_stimulus 2" in err and "'nope.png'" in err
    assert not (tmp_path / "out3").exists()


# --------------------------------------------------------------------------- item 13
def test_item13_european_csv_and_a_malformed_row(tmp_path, stimset, capsys):
    out = tmp_path / "out"
    code, err = _cli(["analyze", DATA / "european.csv", "--stimuli", stimset, "-o", out,
                      "--group-simulations", "19", "--permutations", "19", "--no-figures"], capsys)
    assert code == 0, err
    m = _mapped(out)
    assert m["line"].tolist() == [2, 3, 4, 5, 6]
    assert m["reason"].tolist() == ["", "", "malformed_row", "", ""]
    assert m["row_error"].tolist()[2] == "6 fields, the header has 5"
    # decimal commas read as decimals: the vertices lie on the contour, not 0.x px beside it
    assert m.loc[~m["excluded"], "distance"].max() < 1e-3
    assert m["x"].tolist()[0] == 386.0
    # a comma-separated file with a malformed row: kept, not refusing the file
    f = tmp_path / "c.csv"
    f.write_text("participant,stimulus_id,x,y\nP1,rf_003,386,256\nP1,rf_003,256,356,oops\n")
    code, err = _cli(["analyze", f, "--stimuli", stimset, "-o", tmp_path / "out2",
                      "--group-simulations", "19", "--permutations", "19", "--no-figures"], capsys)
    assert code == 0, err
    assert _mapped(tmp_path / "out2")["reason"].tolist() == ["", "malformed_row"]


# --------------------------------------------------------------------------- item 14
def test_item14_messages_do_not_echo_arbitrary_files(tmp_path, stimset, capsys):
    secret = "root:$y$j9T$SECRETSALT$SECRETHASHVALUE:19700:0:99999:7:::\ndaemon:*:19700:0:99999:7:::\n"
    f = tmp_path / "shadow"
    f.write_text(secret)
    d = tmp_path / "set"
    d.mkdir()
    (d / "manifest.csv").write_text(secret)
    for argv in (["surprisal", f, "-o", tmp_path / "o.csv"],
                 ["analyze", f, "--stimuli", stimset, "-o", tmp_path / "out"],
                 ["analyze", DATA / "european.csv", "--stimuli", d, "-o", tmp_path / "out"]):
        code, err = _cli(argv, capsys)
        _one_line_error(code, err)
        assert "missing column" in err and "SECRET" not in err and "19700" not in err, err
    # a real CSV header is still named, cut short
    g = tmp_path / "c.csv"
    g.write_text(",".join(["a" * 50] + [f"c{i}" for i in range(8)]) + "\n1,2,3,4,5,6,7,8,9\n")
    code, err = _cli(["surprisal", g, "-o", tmp_path / "o.csv"], capsys)
    _one_line_error(code, err)
    assert "'" + "a" * 29 + "...'" in err and "'c3', ..." in err and "(9 columns)" in err and "c4" not in err


@pytest.mark.parametrize("flag, value, needle", [
    ("-n", "100000000", "at most 100,000"),                      # a 100-million-point prediction per contour
    ("--group-simulations", "1000000000", "at most 100,000"),    # ran for ever
    ("--grid", "1000000000", "at most 65,536"),                  # asked 179 GiB
    ("--click-sd", "1e300", "from 0.001 to 1e+06 px"),           # ValueError traceback
    ("--click-sd", "1e-300", "from 0.001 to 1e+06 px"),          # overflow RuntimeWarning
    ("--bandwidth", "1e308", "from 0 to 1e+06 px"),              # overflow RuntimeWarning
    ("--seed", "-5", "--seed must be a whole number >= 0"),      # numpy ValueError traceback
])
def test_item9_analyze_size_and_scale_arguments_are_bounded(tmp_path, capsys, stimset, flag, value, needle):
    clicks = tmp_path / "clicks.csv"
    pts = _rf(3)[::50]
    pd.DataFrame({"participant": "P1", "stimulus_id": "rf_003", "x": pts[:, 0], "y": pts[:, 1]}).to_csv(clicks, index=False)
    out = tmp_path / "out"
    code, err = _cli(["analyze", clicks, "--stimuli", stimset, "-o", out, "--no-figures", flag, value], capsys)
    _one_line_error(code, err)
    assert needle in err and not out.exists()


# --- found by the independent hostile-user check (after the items above were fixed) ---


def test_review_an_output_that_is_a_fifo_or_device_is_refused_not_replaced(tmp_path, capsys):
    # atomic_write's rename used to put a regular file in place of the FIFO
    # (and, run as root, in place of /dev/full: the device was destroyed)
    contour = _square_csv(tmp_path / "square.csv")
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    code, err = _cli(["surprisal", contour, "-o", fifo], capsys)
    _one_line_error(code, err)
    assert "out.fifo: is a FIFO" in err and "file name to write" in err
    assert fifo.is_fifo()
    link = tmp_path / "null.csv"
    link.symlink_to(os.devnull)
    code, err = _cli(["surprisal", contour, "-o", link], capsys)
    _one_line_error(code, err)
    assert Path(os.devnull).is_char_device() and link.is_symlink()


def test_review_a_semicolon_contour_file_is_named_as_such(tmp_path, capsys):
    path = tmp_path / "euro.csv"
    path.write_text("x;y\n0,5;0\n100;0,5\n100;100\n0;100\n")  # decimal commas, as a European locale saves
    code, err = _cli(["surprisal", path, "-o", tmp_path / "o.csv"], capsys)
    _one_line_error(code, err)
    assert "euro.csv" in err and "';' as separator" in err


def _never(*args, **kwargs):
    raise AssertionError("the simulation was reached with an option that should have been refused")


@pytest.mark.parametrize("command, args, named", [
    ("simulate", ["--participants", "100000000", "--clicks", "1", "--beta", "1"], "2,000,000"),
    ("simulate", ["--participants", "1", "--clicks", "100000000", "--beta", "1"], "--clicks 100000000"),
    ("simulate", ["--participants", "2", "--clicks", "2", "--beta", "1e308"], "--beta"),
    ("simulate", ["--participants", "2", "--clicks", "2", "--beta", "1", "--seed", "-1"], "--seed"),
    ("simulate", ["--participants", "2", "--clicks", "2", "--beta", "1", "--noise", "1e308"], "--noise"),
    ("simulate", ["--participants", "2", "--clicks", "2", "--beta", "1", "--beta-sd", "1e308"], "--beta-sd"),
    ("simulate", ["--participants", "2", "--clicks", "2", "--beta", "1", "-n", "100000000"], "-n"),
    ("power", ["--beta", "1", "--participants", "100000000"], "2,000,000"),
    ("power", ["--beta", "1", "--participants", "4", "--simulations", "1000000000"], "--simulations"),
    ("power", ["--beta", "1", "--participants", "4", "--group-simulations", "1000000000"], "--group-simulations"),
    ("power", ["--beta", "1", "--participants", "4", "--target", "1e308"], "--target"),
    ("power", ["--beta", "1", "--participants", "4", "--seed", "-1"], "--seed"),
])
def test_review_simulate_and_power_sizes_and_effects_are_bounded(tmp_path, stimset, capsys, monkeypatch,
                                                                    command, args, named):
    # each of these was a MemoryError, an overflow warning or a numpy ValueError traceback
    for name in ("attneave.analysis.clicks.mapping.predict", "attneave.analysis.simulate.observers.simulate", "attneave.analysis.simulate.observers.power"):
        monkeypatch.setattr(name, _never)  # refused before any work (the old code allocated there)
    out = ["-o", tmp_path / "sim.csv"] if command == "simulate" else []
    out += ["--seed", "1"] if command == "simulate" and "--seed" not in args else []
    code, err = _cli([command, "--stimuli", stimset, *out, *args], capsys)
    _one_line_error(code, err)
    assert named in err, err


def test_review_a_stray_quote_does_not_swallow_the_rows_after_it(tmp_path):
    # a quote left open made every later line one field of its row: 60 clicks read as 5, exit 0
    from attneave.analysis.clicks.read import read_clicks

    f = tmp_path / "clicks.csv"
    f.write_text('participant,stimulus_id,x,y,comment\n'
                 'P1,a,1,2,"fine,\nthanks"\n'          # a typed answer with a line break: one row
                 'P1,"a,3,4,\n' 'P1,a,5,6,\n'          # a stray quote ...
                 'P1,"a,7,8,\n'                        # ... closed by the next stray quote
                 + "".join(f"P2,a,{i},{i},\n" for i in range(10, 15))
                 + 'P2,a,20,21,"oops\n' 'P2,a,22,23,\n' 'P2,a,24,25,\n')  # open to the end of the file
    df = read_clicks(f)
    assert df["line"].tolist() == [2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14]
    assert df["x"].tolist()[2] == "5" and df["x"].tolist()[-2:] == ["22", "24"]
    bad = df.loc[df["row_error"] != "", "line"].tolist()
    assert bad == [4, 6, 12] and df["row_error"].iloc[1] == "a quote opened on line 4 is never closed"
    assert df["comment"].iloc[0] == "fine,\nthanks"


@pytest.mark.parametrize("command", ["surprisal", "simulate"])
def test_review_a_full_disk_is_one_line_exit_1_for_every_writer(tmp_path, stimset, capsys, monkeypatch, command):
    # generate said it in one line; surprisal and simulate gave an OSError traceback
    import errno

    def full(table, path, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr("attneave.stimuli.tables.write_table", full)
    out = tmp_path / "out.csv"
    argv = {"surprisal": ["surprisal", _square_csv(tmp_path / "sq.csv"), "-o", out],
            "simulate": ["simulate", "--stimuli", stimset, "-o", out, "--participants", "2", "--clicks", "2",
                         "--beta", "1", "--seed", "1"]}[command]
    code, err = _cli(argv, capsys)
    _one_line_error(code, err, status=1)
    assert "No space left on device" in err and "out.csv" in err


def test_review_experiment_configs_and_sizes_are_bounded(tmp_path, stimset, capsys):
    # a FIFO as --config (of experiment, and of generate) blocked open() forever; an alias bomb
    # was expanded; --lists 1e9 was a MemoryError; --clicks 1e9 and --size-px 1e308 were accepted
    fifo = tmp_path / "exp.yaml"
    os.mkfifo(fifo)
    done = _unblock(fifo)
    try:
        for argv in (["experiment", stimset, "-o", tmp_path / "e1", "--config", fifo],
                     ["generate", fifo, "-o", tmp_path / "g"]):
            code, err = _cli(argv, capsys)
            _one_line_error(code, err)
            assert "exp.yaml: is a FIFO" in err
    finally:
        done.set()
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text("a: &a [1,1,1,1,1,1,1,1,1,1]\n" + "".join(
        f"a{i}: &a{i} [{','.join([f'*a{i - 1}' if i > 1 else '*a'] * 10)}]\n" for i in range(1, 9)))
    code, err = _cli(["experiment", stimset, "-o", tmp_path / "e2", "--config", bomb], capsys)
    _one_line_error(code, err)
    assert "aliases are expanded" in err
    for option, value in (("--lists", "1000000000"), ("--clicks", "1000000000"), ("--size-px", "1e308")):
        code, err = _cli(["experiment", stimset, "-o", tmp_path / "e3", option, value], capsys)
        _one_line_error(code, err)
        assert option in err
    assert not any((tmp_path / name).exists() for name in ("e1", "e2", "e3", "g"))


@pytest.mark.parametrize("spacing, closed", [("1e308", True), ("159", True), ("199", False)])
def test_review_a_spacing_giving_fewer_than_3_points_names_the_option(tmp_path, capsys, spacing, closed):
    # was "resampling needs n >= 3 points, got 0": no word of --spacing; a square of side 100 has
    # L = 400 closed (3 points need L/ds >= 2.5: ds < 160) and 300 open (L/ds >= 1.5: ds < 200)
    argv = ["surprisal", _square_csv(tmp_path / "sq.csv"), "-o", tmp_path / "o.csv", "--spacing", spacing]
    code, err = _cli(argv + ([] if closed else ["--open"]), capsys)
    if spacing != "1e308":  # in range: a spacing just inside the bound works
        assert code == 0, err
        return
    _one_line_error(code, err)
    assert "--spacing" in err and "fewer than 3 points" in err and "below 160 px" in err


@pytest.mark.parametrize("argv, needle", [
    (["--c", "1", "--s-end", "1e308"], "s_end: arc lengths must lie within +-1e+06"),  # overflow RuntimeWarning
    (["--c", "1e308", "--s-end", "1"], "c: must be <= 1000000000000"),
])
def test_item11_curve_arguments_that_overflow_are_one_line(tmp_path, capsys, argv, needle):
    code, err = _cli(["curve", "clothoid", *argv, "-o", tmp_path / "c.csv"], capsys)
    _one_line_error(code, err)
    assert needle in err and not (tmp_path / "c.csv").exists()


def test_item6_disk_full_in_any_command_is_one_line_exit_1(tmp_path, capsys, stimset, monkeypatch):
    import errno

    import attneave.analysis.report.outputs

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp_path / "out" / "clicks.csv"))

    monkeypatch.setattr(attneave.analysis.report.outputs, "write_analysis", full)
    clicks = tmp_path / "clicks.csv"
    pts = _rf(3)[::50]
    pd.DataFrame({"participant": "P1", "stimulus_id": "rf_003", "x": pts[:, 0], "y": pts[:, 1]}).to_csv(clicks, index=False)
    code, err = _cli(["analyze", clicks, "--stimuli", stimset, "-o", tmp_path / "out", "--no-figures",
                      "--group-simulations", "19", "--permutations", "19"], capsys)
    _one_line_error(code, err, status=1)
    assert "No space left on device" in err
