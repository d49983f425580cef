"""Robustness of ``curve``, ``spline``, ``surprisal`` and ``figures``: tiny
parameters reach their analytic limits, inputs are never overwritten,
degenerate contours are refused in one line, negative numbers in scientific
notation are option values."""

import numpy as np
import pandas as pd
import pytest
from scipy.special import exp1

from attneave.cli import main
from attneave.stimuli.curves.lac.aesthetic import log_aesthetic
from attneave.stimuli.curves.pseudospiral import pseudospiral
from attneave.stimuli.curves.superspiral import superspiral


def _nielsen(s, lam):
    """alpha = 0 limit of eq. 9 (Nielsen's spiral, kappa = exp(-lam s)), through E1."""
    m = np.exp(-lam * s) / lam
    return -np.exp(1j / lam) / lam * (exp1(1j / lam) - exp1(1j * m))


def _one_error_line(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    return lines[0]


# ----------------------------------------------------------------- item 1: tiny parameters


@pytest.mark.parametrize("alpha", [1e-300, -1e-300, 1e-200, 1e-100, 1e-50, 1e-30, 1e-20, 1e-12, 1e-8])
@pytest.mark.parametrize("num", [5, 201])  # the closed form alone, and with the dense-grid quadrature
def test_lac_tiny_alpha_reaches_nielsen_limit(alpha, num):
    lam, s_end = 1.0, 3.0
    cv = log_aesthetic(alpha, lam, 0.0, s_end, num=num)
    z = _nielsen(cv.s, lam)
    # the curve differs from its alpha = 0 limit by O(alpha (lam s)^2) of its length
    tol = 1e-12 + 10 * abs(alpha) * (lam * s_end) ** 2 * s_end
    assert np.max(np.abs(cv.x + 1j * cv.y - z)) < tol
    assert abs(cv.x[-1] - 2.2458837) < 1e-6 and abs(cv.y[-1] - 1.8388652) < 1e-6
    assert np.allclose(cv.theta, 1 - np.exp(-lam * cv.s), atol=tol)
    assert np.allclose(cv.curvature, np.exp(-lam * cv.s), rtol=tol)


@pytest.mark.parametrize("alpha", [0.0, 0.5, -1.0, 1e-300])
@pytest.mark.parametrize("lam", [1e-300, -1e-300, 1e-12, 1e-8])
def test_lac_tiny_lambda_reaches_circle(alpha, lam):
    cv = log_aesthetic(alpha, lam, 0.0, 3.0, num=5)
    circle = 1j * (1 - np.exp(1j * cv.s))  # lam = 0: the unit circle
    assert np.max(np.abs(cv.x + 1j * cv.y - circle)) < 1e-12 + 10 * abs(lam) * 27


@pytest.mark.parametrize("m", [1 - 1e-6, 1 - 1e-10, 1 - 1e-14, 1 + 1e-10])
def test_pseudospiral_near_m1_reaches_log_spiral(m):
    a, s0, s1 = 1.0, 1.0, 3.0
    cv = pseudospiral(a, m, s0, s1, num=5)
    ref = pseudospiral(a, 1.0, s0, s1, num=5)  # theta = ln(s/s0)/a
    assert np.allclose(ref.theta, np.log(ref.s / s0) / a, atol=1e-14)
    tol = 1e-9 + 10 * abs(1 - m) * np.log(s1) ** 2 * s1
    assert np.max(np.abs(cv.points - ref.points)) < tol
    assert np.max(np.abs(cv.theta - ref.theta)) < tol


@pytest.mark.parametrize("b, c", [(1e-300, 2e-300), (1e-20, 2e-20)])
def test_superspiral_tiny_b_c(b, c):
    # 2F1(1, b; 2b; -psi) -> as b -> 0 its series is 1 + sum_k (1)_k/(2 k!) ... = (1 + 1/(1+psi))/2
    cv = superspiral(1.0, b, c, np.pi, num=21)
    psi = cv.theta
    assert np.allclose(1 / cv.curvature, 0.5 * (1 + 1 / (1 + psi)), rtol=1e-12)
    # x(pi) from the closed form: int_0^pi rho cos = pi/2 ... evaluated by quad here
    from scipy.integrate import quad

    X = quad(lambda p: 0.5 * (1 + 1 / (1 + p)) * np.cos(p), 0, np.pi, epsabs=1e-14)[0]
    Y = quad(lambda p: 0.5 * (1 + 1 / (1 + p)) * np.sin(p), 0, np.pi, epsabs=1e-14)[0]
    assert abs(cv.x[-1] - X) < 1e-10 and abs(cv.y[-1] - Y) < 1e-10


def test_curve_cli_lac_tiny_alpha(tmp_path):
    out = tmp_path / "l.csv"
    assert main(["curve", "lac", "--alpha", "1e-300", "--lam", "1", "--s-end", "3", "-o", str(out)]) == 0
    df = pd.read_csv(out)
    assert abs(df["x"].iloc[-1] - 2.2458837) < 1e-6 and abs(df["y"].iloc[-1] - 1.8388652) < 1e-6


# ----------------------------------------------------------------- item 7: negative exponents


def test_negative_scientific_option_values(tmp_path):
    out = tmp_path / "l.csv"
    assert main(["curve", "lac", "--alpha", "-1e-300", "--lam", "1", "--s-end", "3", "-o", str(out)]) == 0
    assert abs(pd.read_csv(out)["x"].iloc[-1] - 2.2458837) < 1e-6
    assert main(["curve", "clothoid", "--k0", "-5.", "--c", "-1.5E-3", "--s-end", "1", "-o", str(out)]) == 0
    assert pd.read_csv(out)["curvature"].iloc[0] == -5.0


def test_negative_scientific_spline_alpha(tmp_path, capsys):
    pts = tmp_path / "p.csv"
    pts.write_text("x,y\n0,0\n10,0\n10,10\n0,10\n")
    # parsed as a value (not "expected one argument"); with qic it is refused for the method
    assert main(["spline", str(pts), "-o", str(tmp_path / "o.csv"), "--alpha", "-1e9"]) == 2
    assert "lac-g1 and lac" in _one_error_line(capsys)


# ----------------------------------------------------------------- item 8: constant-info messages


@pytest.mark.parametrize(
    "argv, want, unwanted",
    [
        (["--C", "1", "--n", "10", "--s-end", "5"], "sqrt(|C|)*n = 10", "got s_start"),
        (["--C", "1", "--n", "1e300", "--s-end", "5"], "1e+300", "np.float64"),
        (["--C", "0", "--s-start", "0", "--s-end", "5"], "s > 0", "s >= 0"),
    ],
)
def test_constant_info_messages(tmp_path, capsys, argv, want, unwanted):
    assert main(["curve", "constant-info", *argv, "-o", str(tmp_path / "c.csv")]) == 2
    line = _one_error_line(capsys)
    assert want in line and unwanted not in line


# ----------------------------------------------------------------- item 2: inputs are never overwritten


def _square(tmp_path, name="sq.csv"):
    p = tmp_path / name
    p.write_text("x,y\n0,0\n10,0\n10,10\n0,10\n")
    return p


@pytest.mark.parametrize(
    "argv",
    [
        ["surprisal", "{p}", "-o", "{p}", "-n", "10"],
        ["spline", "{p}", "-o", "{p}"],
        ["spline", "{p}", "-o", "{d}/o.csv", "--summary", "{d}/o.csv"],
        ["spline", "{p}", "-o", "{d}/o.csv", "--summary", "{p}"],
    ],
)
def test_outputs_spare_inputs(tmp_path, capsys, argv):
    p = _square(tmp_path)
    before = p.read_bytes()
    argv = [a.format(p=p, d=tmp_path) for a in argv]
    assert main(argv) == 2
    _one_error_line(capsys)
    assert p.read_bytes() == before
    assert not (tmp_path / "o.csv").exists()


# ----------------------------------------------------------------- item 3: degenerate contours


@pytest.mark.parametrize(
    "text, words",
    [
        ("x,y\n0,0\n1,1\n2,2\n3,3\n", "no area"),
        ("x,y\n0,0\n10,10\n10,0\n0,10\n", "crosses itself"),
    ],
)
def test_surprisal_refuses_degenerate_closed(tmp_path, capsys, text, words):
    p = tmp_path / "c.csv"
    p.write_text(text)
    assert main(["surprisal", str(p), "-o", str(tmp_path / "o.csv"), "-n", "10"]) == 2
    assert words in _one_error_line(capsys)
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("command", ["surprisal", "spline"])
def test_closing_repeat_dropped_with_note(tmp_path, capsys, command):
    p = tmp_path / "r.csv"
    p.write_text("x,y\n0,0\n10,0\n10,10\n0,10\n0,0\n")
    out = tmp_path / "o.csv"
    extra = ["-n", "10"] if command == "surprisal" else []
    assert main([command, str(p), "-o", str(out), *extra]) == 0
    err = capsys.readouterr().err
    assert "repeats the first" in err and "line 6" in err and len(err.strip().splitlines()) == 1
    ref = tmp_path / "ref.csv"
    _square(tmp_path, "sq.csv")
    assert main([command, str(tmp_path / "sq.csv"), "-o", str(ref), *extra]) == 0
    assert pd.read_csv(out).equals(pd.read_csv(ref))


# ----------------------------------------------------------------- items 4, 5: spline


@pytest.mark.parametrize("method", ["cubic", "qic", "poly3"])
@pytest.mark.parametrize("text", ["x,y\n0,0\n10,0\n0,0\n10,0\n", "x,y\n0,0\n1,1\n2,2\n3,3\n"])
def test_spline_refuses_doubling_back(tmp_path, capsys, method, text):
    p = tmp_path / "b.csv"
    p.write_text(text)
    out, js = tmp_path / "o.csv", tmp_path / "j.json"
    assert main(["spline", str(p), "-o", str(out), "--method", method, "--summary", str(js)]) == 2
    assert "double back" in _one_error_line(capsys)
    assert not out.exists() and not js.exists()


def test_spline_writes_no_blank_curvature(tmp_path):
    p = _square(tmp_path)
    out = tmp_path / "o.csv"
    for method in ("qic", "cubic", "poly3", "lac-g1"):
        assert main(["spline", str(p), "-o", str(out), "--method", method]) == 0
        assert pd.read_csv(out)["curvature"].notna().all()


@pytest.mark.parametrize("method", ["qic", "cubic", "poly4"])
def test_spline_alpha_refused_for_other_methods(tmp_path, capsys, method):
    p = _square(tmp_path)
    assert main(["spline", str(p), "-o", str(tmp_path / "o.csv"), "--method", method, "--alpha", "0.5"]) == 2
    line = _one_error_line(capsys)
    assert "lac-g1 and lac" in line and method in line


# ----------------------------------------------------------------- item 6: figures


@pytest.mark.parametrize("out", ["", "/proc/attneave-figs", "/sys/kernel/attneave-figs"])
def test_figures_unwritable_output(capsys, out):
    assert main(["figures", "-o", out]) == 2
    assert "-o" in _one_error_line(capsys)


def test_figures_names_replaced_files(tmp_path, capsys, monkeypatch):
    from attneave.papers import ziatdinov as figures
    from attneave.papers.base import FigureData, Line, Panel

    def fig1():
        return FigureData("fig1", "fig1_u_vs_curvature.png", "test", (Panel((Line(np.zeros(2), np.ones(2)),)),))

    monkeypatch.setattr(figures, "FIGURES", {"fig1": fig1})
    (tmp_path / "figures.md").write_text("mine")
    (tmp_path / "fig1.png").write_text("mine")
    assert main(["figures", "-o", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert "replaced 1 existing file(s): figures.md" in err
    assert (tmp_path / "fig1.png").read_text() == "mine"  # not one of ours: left alone
