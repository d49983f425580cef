"""`attneave surprisal`: the output contract and bad input."""

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main

COLUMNS = ["i", "s", "t", "x", "y", "turning_angle", "curvature", "surprisal", "peak", "length_unit"]


def write_ellipse(path, n=600, reverse=False):
    th = 2 * np.pi * np.arange(n) / n
    p = np.c_[256 + 150 * np.cos(th), 256 + 60 * np.sin(th)]
    if reverse:
        p = p[::-1]
    pd.DataFrame({"x": p[:, 0], "y": p[:, 1]}).to_csv(path, index=False)
    return p


@pytest.mark.parametrize("reverse", [False, True])
def test_paper_model_row_by_row(tmp_path, reverse):
    src = tmp_path / "ellipse.csv"
    p = write_ellipse(src, reverse=reverse)
    out = tmp_path / "out.csv"
    argv = ["surprisal", str(src), "-o", str(out), "-n", "50", "--A", "0.3", "--b", "0.02", "--length-unit", "px"]
    assert main(argv) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == COLUMNS
    assert set(df["length_unit"]) == {"px"}
    assert len(df) == 50
    assert np.allclose(df[["x", "y"]].iloc[0], p[0])  # starts at the first input point
    n = 50
    ds = df["s"].iloc[1]
    expected = -np.log(0.3) - 0.02 * ds**2 * np.cos(df["turning_angle"] - 2 * np.pi / n)
    assert np.allclose(df["surprisal"], expected, rtol=0, atol=1e-10)
    assert np.all(df["curvature"] > 0)  # an ellipse is convex everywhere
    assert df["peak"].sum() == 2
    assert set(np.round(df.loc[df.peak == 1, "x"])) == {106, 406}


def test_vonmises_bits_and_spacing(tmp_path):
    src = tmp_path / "e.csv"
    write_ellipse(src)
    out = tmp_path / "o.csv"
    assert main(["surprisal", str(src), "-o", str(out), "--spacing", "10", "--model", "vonmises", "--bits"]) == 0
    df = pd.read_csv(out)
    L = df["s"].iloc[-1] + df["s"].iloc[1]
    assert abs(L / len(df) - 10) < 0.2
    # bits: a normalised density's surprisal in bits is >= -log2(max density)
    assert np.all(np.isfinite(df["surprisal"]))


@pytest.mark.parametrize(
    "content, needle",
    [
        ("x,z\n0,0\n1,0\n0,1\n", "missing column(s) y"),
        ("x,y\n0,0\n1,nan\n0,1\n", "line 3: column 'y'"),
        ("x,y\n0,0\n1,zz\n0,1\n", "line 3: column 'y'"),
        ("x,y\n0,0\n1,0\n", "at least 3 distinct points"),
        ("x,y\n0,0\n0,0\n0,0\n1,1\n", "at least 3 distinct points"),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, capsys, content, needle):
    src = tmp_path / "bad.csv"
    src.write_text(content)
    out = tmp_path / "out.csv"
    assert main(["surprisal", str(src), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "bad.csv" in lines[0] and needle in lines[0]
    assert not out.exists()


def test_usage_error_is_one_line(tmp_path):
    # the one real process of this command's tests: exit status and stderr as a shell sees them
    proc = subprocess.run(
        [sys.executable, "-m", "attneave.cli", "surprisal", "x.csv", "-o", "y.csv", "-n", "3", "--spacing", "2"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1
