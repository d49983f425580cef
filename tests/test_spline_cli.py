"""``attneave spline``: output format, summary, methods and bad input."""

import json

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main


def _write_points(path, P):
    pd.DataFrame({"x": P[:, 0], "y": P[:, 1]}).to_csv(path, index=False)


@pytest.fixture()
def blob(tmp_path):
    t = np.linspace(0, 2 * np.pi, 14, endpoint=False)
    rad = 60 * (1 + 0.25 * np.cos(3 * t))
    P = np.c_[200 + rad * np.cos(t), 200 - rad * np.sin(t)]  # counter-clockwise on screen
    path = tmp_path / "pts.csv"
    _write_points(path, P)
    return path, P


def test_qic_output_and_summary(blob, tmp_path):
    path, P = blob
    out, summ = tmp_path / "out.csv", tmp_path / "sum.json"
    assert main(["spline", str(path), "-o", str(out), "--summary", str(summ), "--samples", "9"]) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == ["s", "x", "y", "curvature", "segment"]
    assert len(df) == 14 * 9
    # each segment starts on its input point and ends on the next one
    for i, g in df.groupby("segment"):
        assert len(g) == 9
        np.testing.assert_allclose(g[["x", "y"]].iloc[0], P[i], atol=1e-9)
        np.testing.assert_allclose(g[["x", "y"]].iloc[-1], P[(i + 1) % 14], atol=1e-9)
    assert np.all(np.diff(df["s"]) >= 0)
    # convex blob stored counter-clockwise on screen: positive curvature at
    # the outermost points (t = 0: the rightmost point)
    assert df["curvature"].iloc[0] > 0
    s = json.loads(summ.read_text())
    for key in ("method", "n_points", "closed", "g2_error", "interior_extrema", "loops", "iterations", "seconds"):
        assert key in s
    assert s["method"] == "qic" and s["n_points"] == 14 and s["closed"] is True
    assert s["g2_error"] < 1e-10 and s["interior_extrema"] == 0 and s["loops"] == 0
    assert s["iterations"] >= 1
    assert s["alpha"] == -1.0  # a smooth blob: clothoid segments


def test_log_aesthetic_form_in_output_and_summary(tmp_path):
    # a lobed outline reduced to 16 points, where the robust rule takes the
    # log-aesthetic form: the summary says alpha, the samples show its law
    # (sign(k)|k|**0.3 linear in arc length on every segment) and monotone curvature
    from attneave.stimuli.curves.qic.lac import ALPHA
    from attneave.stimuli.geometry.contour import Contour

    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    r = 1 + 0.5 * np.cos(3 * t) + 0.2 * np.cos(7 * t + 1)
    P = Contour(np.c_[200 + 100 * r * np.cos(t), 200 - 100 * r * np.sin(t)]).resample(16).points
    path, out, summ = tmp_path / "pts.csv", tmp_path / "out.csv", tmp_path / "sum.json"
    _write_points(path, P)
    assert main(["spline", str(path), "-o", str(out), "--summary", str(summ), "--samples", "17"]) == 0
    s = json.loads(summ.read_text())
    assert s["alpha"] == ALPHA and s["interior_extrema"] == 0 and s["self_intersections"] == 0
    df = pd.read_csv(out)
    for _, g in df.groupby("segment"):
        k, sarc = g["curvature"].to_numpy(), g["s"].to_numpy()
        u = np.sign(k) * np.abs(k) ** (-ALPHA)
        fit = np.polyval(np.polyfit(sarc, u, 1), sarc)
        assert np.abs(u - fit).max() <= 1e-6 * np.abs(u).max()


def test_polynomial_methods_report_extrema(blob, tmp_path):
    path, _ = blob
    counts = {}
    for method in ("cubic", "poly2", "poly4", "poly5"):
        summ = tmp_path / f"{method}.json"
        assert main(["spline", str(path), "-o", str(tmp_path / f"{method}.csv"), "--method", method,
                     "--summary", str(summ)]) == 0
        s = json.loads(summ.read_text())
        assert s["method"] == method and s["iterations"] == 0
        counts[method] = s["interior_extrema"]
    # the three-lobed blob: polynomial splines put extrema between points
    assert counts["cubic"] > 0 and counts["poly5"] > 0


def test_open_curve(tmp_path):
    x = np.linspace(0, 100, 7)
    path = tmp_path / "open.csv"
    _write_points(path, np.c_[x, 50 + 10 * np.sin(x / 20)])
    out = tmp_path / "o.csv"
    assert main(["spline", str(path), "-o", str(out), "--open", "--samples", "4"]) == 0
    df = pd.read_csv(out)
    assert len(df) == 6 * 4 and sorted(df["segment"].unique()) == list(range(6))
    assert abs(df["curvature"].iloc[0]) < 1e-12 and abs(df["curvature"].iloc[-1]) < 1e-12
    assert main(["spline", str(path), "-o", str(out), "--open", "--method", "cubic-natural"]) == 0


@pytest.mark.parametrize("content, needle", [
    ("x,z\n1,2\n3,4\n5,6\n", "missing column"),
    ("x,y\n1,2\n3,nan\n5,6\n", "line 3"),
    ("x,y\n1,2\n3,4\n3,4\n5,1\n", "lines 3 and 4"),
    ("x,y\n1,2\n3,4\n1,2\n5,1\n", "double back"),  # a cusp: curvature undefined
    ("x,y\n1,2\n3,4\n", "at least 3"),
])
def test_bad_input_exits_2(tmp_path, capsys, content, needle):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    out = tmp_path / "o.csv"
    assert main(["spline", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert needle in err and str(path) in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_non_convergence_is_a_clean_error(tmp_path, capsys):
    # points in random order: either a curve with its loops reported or one
    # clean line and exit 2, never a traceback
    rng = np.random.default_rng(4)
    for trial in range(6):
        path = tmp_path / f"r{trial}.csv"
        _write_points(path, rng.uniform(0, 100, (25, 2)))
        summ = tmp_path / f"r{trial}.json"
        rc = main(["spline", str(path), "-o", str(tmp_path / f"o{trial}.csv"), "--summary", str(summ)])
        err = capsys.readouterr().err
        if rc == 0:
            assert "loops" in json.loads(summ.read_text())
        else:
            assert rc == 2 and "did not converge" in err and len(err.strip().splitlines()) == 1


def test_lac_g1_method(blob, tmp_path):
    path, P = blob
    out, summ = tmp_path / "lac.csv", tmp_path / "lac.json"
    assert main(["spline", str(path), "-o", str(out), "--method", "lac-g1", "--alpha", "0.5",
                 "--samples", "8", "--summary", str(summ)]) == 0
    df = pd.read_csv(out)
    assert len(df) == 14 * 8
    s = json.loads(summ.read_text())
    assert s["method"] == "lac-g1" and s["interior_extrema"] == 0
    assert isinstance(s["fallback_segments"], list)


def test_unwritable_summary_leaves_no_output(tmp_path, capsys):
    # the curve CSV used to be renamed into place before the summary failed
    th = 2 * np.pi * np.arange(12) / 12
    src = tmp_path / "p.csv"
    pd.DataFrame({"x": 100 + 50 * np.cos(th), "y": 100 + 50 * np.sin(th)}).to_csv(src, index=False)
    out = tmp_path / "out.csv"
    assert main(["spline", str(src), "-o", str(out), "--summary", str(tmp_path / "no" / "s.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "s.json" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.csv"]


def test_cusp_in_a_polynomial_spline_is_refused_without_warnings(tmp_path):
    import subprocess
    import sys

    src = tmp_path / "back.csv"
    src.write_text("x,y\n0,0\n10,0\n0,0\n5,5\n")  # doubles back: the cubic would have a cusp
    out = tmp_path / "o.csv"
    proc = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-m", "attneave.cli", "spline", str(src),
                           "-o", str(out), "--method", "cubic"], capture_output=True, text=True)
    assert "RuntimeWarning" not in proc.stderr
    # curvature is undefined at the cusp: one line naming the line, never blank cells
    assert proc.returncode == 2 and "line 3" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    assert not out.exists()


LOOPING = np.array([[221.3, 200.0], [326.0, 128.1], [232.9, 83.6], [184.9, 153.4], [97.0, 130.0],
                    [121.8, 203.1], [73.8, 281.9], [136.3, 301.9], [206.3, 258.6], [280.0, 361.8],
                    [239.9, 245.9], [328.4, 266.2]])  # the pure G2 spline loops on segment 9 or so


def test_summary_reports_corners_and_problems(tmp_path, capsys):
    path = tmp_path / "j.csv"
    _write_points(path, LOOPING)
    out, summ = tmp_path / "o.csv", tmp_path / "s.json"
    assert main(["spline", str(path), "-o", str(out), "--summary", str(summ)]) == 0
    assert capsys.readouterr().err == ""
    s = json.loads(summ.read_text())
    assert s["self_intersections"] == 0 and s["max_segment_turn"] <= np.pi and s["loops"] == 0
    assert s["corners"] and len(s["corner_kinds"]) == len(s["corners"])
    # G2 everywhere but at the listed corners, measured on the written samples
    df = pd.read_csv(out)
    first = df.groupby("segment")["curvature"].first().to_numpy()
    last = df.groupby("segment")["curvature"].last().to_numpy()
    jump = np.abs(first - np.roll(last, 1))
    smooth = np.setdiff1d(np.arange(len(LOOPING)), s["corners"])
    assert jump[smooth].max() <= 1e-10 * df["curvature"].abs().max()
    assert jump[s["corners"]].max() > 1e-6 * df["curvature"].abs().max()


def test_looping_curve_warns_and_strict_writes_nothing(tmp_path, capsys):
    path = tmp_path / "j.csv"
    _write_points(path, LOOPING)
    out, summ = tmp_path / "o.csv", tmp_path / "s.json"
    assert main(["spline", str(path), "-o", str(out), "--method", "qic-g2", "--summary", str(summ)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning" in err[0] and "more than pi (segments" in err[0]
    s = json.loads(summ.read_text())
    assert s["loops"] >= 1 and s["max_segment_turn"] > np.pi and s["corners"] == []
    out2, summ2 = tmp_path / "o2.csv", tmp_path / "s2.json"
    assert main(["spline", str(path), "-o", str(out2), "--method", "qic-g2", "--summary", str(summ2),
                 "--strict"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error" in err[0] and "--strict" in err[0]
    assert not out2.exists() and not summ2.exists()


@pytest.mark.parametrize("argv, bound", [
    (["spline", "PTS", "--samples", "1e7"], "at most 1000000"),
    (["spline", "PTS", "--samples", "10000000"], "at most 1000000"),
    (["spline", "PTS", "--samples", "1e12"], "at most 1000000"),
    (["spline", "PTS", "--samples", "300000"], "at most 1000000 rows"),  # x 14 segments
    (["curve", "clothoid", "--c", "1", "--s-end", "1", "--points", "1e8"], "at most 1000000"),
    (["curve", "clothoid", "--c", "1", "--s-end", "1", "--points", "1e12"], "at most 1000000"),
])
def test_size_arguments_are_bounded(blob, tmp_path, capsys, argv, bound):
    # issue 11 item 9: one line naming the bound, exit 2, nothing allocated
    path, _ = blob
    argv = [str(path) if a == "PTS" else a for a in argv] + ["-o", str(tmp_path / "o.csv")]
    assert _exit_code(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and bound in err[0]
    assert not (tmp_path / "o.csv").exists()


def _exit_code(argv):
    """main()'s status, whether returned or raised by argparse."""
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


def test_tiny_square_gives_the_right_curve(tmp_path):
    # issue 11 item 11: a tiny square is fitted in a rescaled frame (side 1e-5 px: curvatures of 1e5 px^-1);
    # it is the circle through the corners
    path = tmp_path / "tiny.csv"
    path.write_text("x,y\n0,0\n1e-5,0\n1e-5,1e-5\n0,1e-5\n")
    out = tmp_path / "o.csv"
    assert main(["spline", str(path), "-o", str(out), "--samples", "5"]) == 0
    df = pd.read_csv(out)
    assert np.isfinite(df.to_numpy()).all()
    np.testing.assert_allclose(df["curvature"], np.sqrt(2) * 1e5, rtol=1e-9)
    np.testing.assert_allclose(df["s"].iloc[-1], 2 * np.pi * 1e-5 / np.sqrt(2), rtol=1e-9)


def test_far_from_the_origin_without_runtime_warnings(tmp_path):
    # a small square far from the origin (side 100 at 1e11, as far as the bounds of every contour
    # allow): the right curve, and no RuntimeWarning reaches the user
    import subprocess
    import sys

    src = tmp_path / "far.csv"
    src.write_text("x,y\n1e11,1e11\n100000000100,1e11\n100000000100,100000000100\n1e11,100000000100\n")
    out = tmp_path / "o.csv"
    proc = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-m", "attneave.cli", "spline", str(src),
                           "-o", str(out), "--summary", str(tmp_path / "s.json")], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    df = pd.read_csv(out)
    np.testing.assert_allclose(df["curvature"], np.sqrt(2) / 100, rtol=1e-6)
    assert np.isfinite(df.to_numpy()).all()


def test_overflowing_coordinates_are_one_line_naming_file_and_line(tmp_path, capsys):
    # coordinates near 1e308 were fitted (or refused only at a span of 1e306); the bound is now
    # that of every contour, and the message names the file and the CSV line
    src = tmp_path / "inf.csv"
    src.write_text("x,y\n-1e308,-1e308\n1e308,-1e308\n1e308,1e308\n-1e308,1e308\n")
    assert main(["spline", str(src), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(src) in err[0] and "line 2: coordinates must lie within +-1e+12 px" in err[0]


def test_corners_are_named_on_stderr_without_a_summary(tmp_path, capsys):
    # the robust fit relaxes G2 at a few nodes of this looping polygon; without --summary the user
    # learned nothing of it
    path = tmp_path / "j.csv"
    _write_points(path, LOOPING)
    out, summ = tmp_path / "o.csv", tmp_path / "s.json"
    assert main(["spline", str(path), "-o", str(out), "--summary", str(summ)]) == 0
    capsys.readouterr()
    corners = json.loads(summ.read_text())["corners"]
    assert main(["spline", str(path), "-o", str(tmp_path / "o2.csv")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("attneave spline: note:")
    assert f"except at {len(corners)} of {len(LOOPING)} points" in err[0]
    assert f"point(s) {corners[0]} (" in err[0]
    # a curve that needed no corner says nothing
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    _write_points(path, np.c_[50 + 30 * np.cos(th), 50 + 20 * np.sin(th)])
    assert main(["spline", str(path), "-o", str(tmp_path / "o3.csv")]) == 0
    assert capsys.readouterr().err == ""
