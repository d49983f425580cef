"""Audit of the spline and curve code on adversarial-but-plausible input:
each test fails on the code before its fix (see the comment above it)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from attneave.cli import main


def _write(path, text):
    path.write_text(text)
    return path


# --- error lines name the right CSV line -----------------------------------------------------
# `spline` named "line i + 2" for row i, wrong once the file has blank lines (skipped by the
# reader) or a quoted field spanning two lines.


def test_repeated_point_named_by_its_real_lines_with_blank_lines(tmp_path, capsys):
    src = _write(tmp_path / "p.csv", "x,y\n\n0,0\n\n10,0\n10,0\n0,10\n")
    assert main(["spline", str(src), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "lines 5 and 6 are the same point" in err, err
    assert not (tmp_path / "o.csv").exists()


def test_doubling_back_named_by_its_real_line(tmp_path, capsys):
    # (20, 0) -> (10, 0) reverses the side (0, 0) -> (20, 0): the cusp is at the point on line 6
    src = _write(tmp_path / "p.csv", "x,y\n0,0\n\n10,0\n20,0\n10,0\n0,10\n")
    assert main(["spline", str(src), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "line 5: the points double back" in err, err


def test_closing_repeat_note_names_its_real_lines(tmp_path, capsys):
    src = _write(tmp_path / "p.csv", "x,y\n\n0,0\n10,0\n0,10\n\n0,0\n")
    assert main(["spline", str(src), "-o", str(tmp_path / "o.csv")]) == 0
    err = capsys.readouterr().err
    assert "line 7 repeats the first point (line 3)" in err, err


# --- every segment begins and ends exactly on its input points ------------------------------
# Only each segment's first sample was put on its input point; the last sample kept the fit's
# round-off (polynomial splines) or its ~1e-10 miss (G1 log-aesthetic segments). The written curve
# then had tiny zig-zags at the nodes: it crossed itself there, and the summary could count a
# self-intersection that no warning named.

CROWN = np.array([
    [71.9460372022865, 102.30091297996637], [105.80126910317324, 98.24076060411656],
    [126.60482865559348, 76.1504738653288], [146.8692864638243, 48.46053185085634],
    [134.80852104052434, 43.75792282300871], [108.83223892199996, 41.81400743987773],
    [92.50014302275113, 48.28655099496484], [94.86202982864161, 39.860012991973136],
    [71.5846871412299, 20.997965625484618], [59.18406029093712, 51.382590620525654],
    [50.591809135747475, 37.3110641608575], [20.145827231580636, 46.92060283754756],
    [7.607258121706481, 53.032170558626184], [21.236759005313075, 74.56095309285024],
    [44.81806966824425, 98.18505396377077],
])  # a jittered MPEG-7 crown, 15 points


@pytest.mark.parametrize("method, closed", [("poly5", True), ("poly2", False), ("lac-g1", False)])
def test_segments_end_exactly_on_the_next_point(tmp_path, capsys, method, closed):
    src = tmp_path / "p.csv"
    src.write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in CROWN.tolist()))
    out, summ = tmp_path / "o.csv", tmp_path / "s.json"
    argv = ["spline", str(src), "-o", str(out), "--method", method, "--summary", str(summ)]
    assert main(argv + ([] if closed else ["--open"])) == 0
    err = capsys.readouterr().err
    o = np.loadtxt(out, delimiter=",", skiprows=1)
    seg = o[:, 4].astype(int)
    first = np.r_[True, seg[1:] != seg[:-1]]
    last = np.r_[seg[1:] != seg[:-1], True]
    n = len(CROWN)
    np.testing.assert_array_equal(o[first, 1:3], CROWN[seg[first]])
    np.testing.assert_array_equal(o[last, 1:3], CROWN[(seg[last] + 1) % n])
    # a crossing counted in the summary is named on stderr, and none is counted at a mere join
    s = json.loads(summ.read_text())
    assert (s["self_intersections"] > 0) == ("crosses itself" in err), (s["self_intersections"], err)


# --- the LAC at a subnormal lambda is the unit circle -----------------------------------------
# lam * (alpha - 1) underflowed to 0: the tangent angle was 0/0 = NaN and the closed form's digit
# count int(-log10(0)) raised OverflowError (a traceback from `attneave curve lac --lam 5e-324`).


@pytest.mark.parametrize("alpha", [0.5, 0.9999999999, -1.0, 3.0])
@pytest.mark.parametrize("lam", [5e-324, -1e-310, 1e-300])
def test_lac_with_vanishing_lambda_is_the_unit_circle(alpha, lam):
    from attneave.stimuli.curves import log_aesthetic

    cv = log_aesthetic(alpha, lam, -2.0, 3.0, num=41)
    u = cv.s + 2.0  # arc length from the start, where theta = 0
    np.testing.assert_allclose(cv.theta, u, atol=1e-14)
    np.testing.assert_allclose(cv.curvature, 1.0, atol=1e-14)
    np.testing.assert_allclose(cv.x, np.sin(u), atol=1e-14)
    np.testing.assert_allclose(cv.y, 1.0 - np.cos(u), atol=1e-14)


def test_curve_lac_subnormal_lambda_on_the_command_line(tmp_path, capsys):
    out = tmp_path / "c.csv"
    argv = ["curve", "lac", "--alpha", "0.5", "--lam", "5e-324", "--s-start", "-2", "--s-end", "0",
            "--points", "3", "-o", str(out)]
    assert main(argv) == 0, capsys.readouterr().err
    o = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(o[:, 1], np.sin(o[:, 0] + 2.0), atol=1e-14)


# --- eq. 7's curvature at extreme n or s ------------------------------------------------------
# C n^2 / s^2 was formed as (C n n) / (s s): at s = 1e-170 (or n = 5e-324) both products
# underflow to 0, and 0/0 gave NaN with a RuntimeWarning printed above the one-line error.


@pytest.mark.parametrize("s, C, n", [(1e-170, 0.0, 10.0), (1e-300, -1.0, 5e-324), (1e200, 0.02, 10.0)])
def test_constant_info_curvature_without_underflow(s, C, n):
    import warnings

    from attneave.stimuli.curves.constant_info import constant_info_curvature

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        k = float(constant_info_curvature(s, C, n))
    # |C| n^2 / s^2 is far below 1e-16 in all three: arccos of it is pi/2 to rounding
    assert k == pytest.approx((n * np.pi / 2 + 2 * np.pi) / s, rel=1e-15)


# --- bad Python arguments raise InputError naming the parameter -------------------------------
# end_tangents of strings or of the wrong length, and lac_g1_spline's alpha / tangents of strings,
# raised a bare ValueError or TypeError from float() or tuple unpacking, naming nothing.


@pytest.mark.parametrize("end_tangents, name", [
    (("ab", None), "end_tangents[0]"), ("ab", "end_tangents"), ((None,), "end_tangents"),
    (5, "end_tangents"), (((1, 0), [1, "x"]), "end_tangents[1]"), (({}, None), "end_tangents[0]"),
])
def test_qic_bad_end_tangents_named(end_tangents, name):
    from attneave.stimuli.curves.qic.spline import qic_spline
    from attneave.stimuli.errors import InputError

    P = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 5.0], [30.0, 0.0]])
    with pytest.raises(InputError, match=rf"^{re.escape(name)}: "):
        qic_spline(P, closed=False, end_tangents=end_tangents)


@pytest.mark.parametrize("kwargs, name", [
    ({"alpha": "x"}, "alpha"), ({"alpha": [1]}, "alpha"), ({"tangents": ["a", "b", "c", "d"]}, "tangents"),
    ({"tangents": {}}, "tangents"),
])
def test_lac_g1_bad_arguments_named(kwargs, name):
    from attneave.stimuli.curves.lac.g1 import lac_g1_spline
    from attneave.stimuli.errors import InputError

    P = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 5.0], [30.0, 0.0]])
    with pytest.raises(InputError, match=rf"^{name}: "):
        lac_g1_spline(P, False, **kwargs)


# --- tiny shapes, and small shapes far from the origin, are fitted ----------------------------
# Within the bounds of every contour (at least 1e-6 px, and 1e-10 of the distance from the
# origin: those of attneave surprisal), a tiny triangle, or a small one far from the origin, is
# fitted in a rescaled frame. The curve must be the scaled copy of the one through the unit-size
# points: curvature times 1/scale, arc length times scale.


@pytest.mark.parametrize("scale, offset", [(2e-6, 0.0), (2.0**-13, 2.0**20)])
def test_tiny_triangle_is_the_scaled_unit_curve(tmp_path, capsys, scale, offset):
    T = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])

    def fit(points, name):
        src = tmp_path / f"{name}.csv"
        src.write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in points.tolist()))
        out = tmp_path / f"{name}_o.csv"
        assert main(["spline", str(src), "-o", str(out)]) == 0, capsys.readouterr().err
        return np.loadtxt(out, delimiter=",", skiprows=1)

    unit = fit(T, "unit")
    small = fit(offset + scale * T, "small")  # powers of two and 1e-7: the points as written
    np.testing.assert_allclose(small[:, 0], unit[:, 0] * scale, rtol=1e-9)
    kmax = np.abs(unit[:, 3]).max()
    np.testing.assert_allclose(small[:, 3] * scale, unit[:, 3], rtol=1e-9, atol=1e-9 * kmax)
    # written at `offset`, a position carries the rounding of offset (2**-52 of it), not of scale
    atol = max(1e-9, 8 * 2.0**-52 * offset / scale)
    np.testing.assert_allclose((small[:, 1:3] - offset) / scale, unit[:, 1:3], atol=atol)


def test_surprisal_notes_name_the_true_lines(tmp_path, capsys):
    # blank lines are no points: the repeated point below is on line 6 and the closing repeat on
    # line 9 (the note counted rows as if every line held one: lines 4 and 7)
    from attneave.cli import main

    f = tmp_path / "c.csv"
    f.write_text("x,y\n\n0,0\n\n10,0\n10,0\n10,10\n0,10\n0,0\n")
    assert main(["surprisal", str(f), "-o", str(tmp_path / "s.csv"), "-n", "40"]) == 0
    err = capsys.readouterr().err
    assert "(line(s) 6)" in err and "the last point (line 9)" in err, err
