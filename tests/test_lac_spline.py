"""G2 log-aesthetic spline (attneave.stimuli.curves.lac.spline): interpolation checked
by integrating the curve's natural equation independently (solve_ivp),
curvature continuity, monotone curvature, the log curvature graph of every
segment, the reduction to the G2 clothoid spline at alpha = -1, and the
error where no solution exists."""

import json

import numpy as np
import pandas as pd
import pytest
from scipy.integrate import solve_ivp

from attneave.cli import main
from attneave.stimuli.curves.lac.spline import lac_spline
from attneave.stimuli.curves.metrics import g2_error, interior_extrema, segment_slices
from attneave.stimuli.curves.qic.spline import qic_spline
from attneave.stimuli.errors import InputError


def radial(n, amps, size=80.0, centre=(200.0, 150.0)):
    """n points on a radial Fourier curve, counter-clockwise on screen."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1 + sum(a * np.cos((k + 2) * t + k) for k, a in enumerate(amps))
    return np.c_[centre[0] + size * r * np.cos(t), centre[1] - size * r * np.sin(t)]


CONVEX = radial(9, [0.08, 0.03])        # turns one way: every alpha
WAVY = radial(11, [0.2, 0.12])          # inflections: alpha < 0 only


def natural_curvature(alpha, k0, k1):
    """kappa(t) on [0, 1] from the definition: rho**alpha (log rho when
    alpha = 0) linear in arc length, continued through kappa = 0 as
    sign(v)|v|**(-1/alpha) for alpha < 0 (written here independently of
    attneave.stimuli.curves.lac.arc), and the inflection's t (or None)."""
    if alpha == 0:
        return (lambda t: k0 * (k1 / k0) ** t), None
    g = lambda k: np.sign(k) * abs(k) ** (-alpha)  # noqa: E731
    v0, v1 = g(k0), g(k1)
    t_infl = v0 / (v0 - v1) if v0 * v1 < 0 else None
    return (lambda t: np.sign(v0 + t * (v1 - v0)) * abs(v0 + t * (v1 - v0)) ** (-1 / alpha)), t_infl


def integrate_segment(alpha, x0, y0, th0, k0, k1, L):
    """End point and tangent of the arc, by solving x' = cos th, y' = sin th,
    th' = kappa(s / L) at tight tolerance (in two pieces at an inflection,
    where kappa is not smooth)."""
    kap, t_infl = natural_curvature(alpha, k0, k1)
    u = [x0, y0, th0]
    for a, b in ((0.0, t_infl), (t_infl, 1.0)) if t_infl is not None else ((0.0, 1.0),):
        sol = solve_ivp(lambda s, v: [np.cos(v[2]), np.sin(v[2]), kap(s / L)], (a * L, b * L), u,
                        method="DOP853", rtol=1e-13, atol=1e-13 * max(L, 1.0))
        u = sol.y[:, -1]
    return u


@pytest.mark.parametrize("alpha, P", [(-2.0, WAVY), (-1.0, WAVY), (-0.5, WAVY), (0.0, CONVEX), (1.0, CONVEX),
                                      (2.0, CONVEX)])
def test_interpolates_is_g2_and_monotone(alpha, P):
    sp = lac_spline(P, alpha)
    size = np.ptp(P, axis=0).max()
    n = len(P)
    total = 0.0
    for j in range(n):
        b = (j + 1) % n
        x, y, th = integrate_segment(alpha, *P[j], sp.theta[j], sp.kappa[j], sp.kappa[b], sp.length[j])
        # the arc drawn from its natural equation ends on the next point, with the next node's tangent
        assert np.hypot(x - P[b, 0], y - P[b, 1]) <= 1e-9 * size
        assert abs(np.angle(np.exp(1j * (th - sp.theta[b])))) <= 1e-9
        total += th - sp.theta[j]
    # counter-clockwise on the screen is clockwise in (x, y down): the tangent turns by -2 pi
    assert total == pytest.approx(-2 * np.pi, abs=1e-9)
    c = sp.sample(64)
    # G2: both segments' formulas give the same curvature at every node
    assert g2_error(c.curvature, c.segment, closed=True) <= 1e-10
    # monotone curvature: no extremum strictly inside any segment
    assert interior_extrema(c.curvature, c.segment).sum() == 0
    # the sampled curve passes through every point in order
    first = [q.start for q in segment_slices(c.segment)]
    assert np.allclose(np.c_[c.x[first], c.y[first]], P, rtol=0, atol=1e-12 * size)
    if alpha < 0:
        assert np.any(np.diff(np.sign(sp.kappa)) != 0)  # the wavy shape has inflections


@pytest.mark.parametrize("alpha", [-2.0, -0.5, 0.0, 1.0, 2.0])
def test_every_segment_is_a_log_aesthetic_arc(alpha):
    P = WAVY if alpha < 0 else CONVEX
    sp = lac_spline(P, alpha)
    c = sp.sample(401)
    checked = 0
    for q in segment_slices(c.segment):
        s, k = c.s[q], c.curvature[q]
        if np.any(k == 0) or np.any(np.sign(k) != np.sign(k[0])) or abs(np.log(abs(k[-1] / k[0]))) < 0.2:
            continue  # an inflection, or too little change of curvature for a slope
        log_rho = -np.log(np.abs(k))
        # the log curvature graph: log(ds / d log rho) against log rho, a line of slope alpha
        y = np.log(np.abs(np.gradient(s, log_rho)))
        inner = slice(2, -2)
        slope, icept = np.polyfit(log_rho[inner], y[inner], 1)
        assert slope == pytest.approx(alpha, abs=1e-3)
        assert np.max(np.abs(y[inner] - (slope * log_rho[inner] + icept))) < 1e-3
        # the same from the positions alone: tangent of the chords between samples
        z = c.x[q] + 1j * c.y[q]
        phi = np.unwrap(np.angle(np.diff(z)))
        kf = np.diff(phi) / np.diff(0.5 * (s[1:] + s[:-1]))
        assert np.max(np.abs(kf - sp.sign * k[1:-1])) <= 2e-3 * np.max(np.abs(k))
        checked += 1
    assert checked >= 2


@pytest.mark.parametrize("closed", [True, False])
def test_alpha_minus_one_is_the_g2_clothoid_spline(closed):
    P = WAVY if closed else WAVY[:7]
    sp = lac_spline(P, -1.0, closed=closed)
    q = qic_spline(P, closed, robust=False)
    scale = np.max(np.abs(q.k0))
    assert np.allclose(sp.kappa[: q.k0.size], q.k0, rtol=0, atol=1e-9 * scale)
    assert np.allclose(sp.length, q.length, rtol=1e-9)
    assert np.allclose(np.cos(sp.theta[: q.theta0.size] - q.theta0), 1, atol=1e-15)
    a, b = sp.sample(17), q.sample(17)
    assert np.allclose(a.x, b.x, atol=1e-9 * 100) and np.allclose(a.y, b.y, atol=1e-9 * 100)
    if not closed:
        assert sp.kappa[0] == 0 and sp.kappa[-1] == 0  # natural ends, as the clothoid spline's


def test_open_ends():
    P = WAVY[:6]
    sp = lac_spline(P, -0.5, closed=False)
    assert sp.kappa[0] == 0 and sp.kappa[-1] == 0
    # alpha >= 0 cannot reach zero curvature: the end segments are circular arcs
    C = CONVEX[:6]
    sp = lac_spline(C, 1.0, closed=False)
    c = sp.sample(9)
    for q in (segment_slices(c.segment)[0], segment_slices(c.segment)[-1]):
        assert np.ptp(c.curvature[q]) <= 1e-12 * np.max(np.abs(c.curvature))
    for j in range(len(C) - 1):
        x, y, _ = integrate_segment(1.0, *C[j], sp.theta[j], sp.kappa[j], sp.kappa[j + 1], sp.length[j])
        assert np.hypot(x - C[j + 1, 0], y - C[j + 1, 1]) <= 1e-9 * 200


def test_no_solution_with_alpha_at_least_zero_is_a_clear_error():
    P = WAVY.copy()
    nxt, prv = np.roll(P, -1, axis=0), np.roll(P, 1, axis=0)
    cross = (P - prv)[:, 0] * (nxt - P)[:, 1] - (P - prv)[:, 1] * (nxt - P)[:, 0]
    concave = np.flatnonzero(np.sign(cross) != np.sign(np.sum(np.sign(cross))))
    assert concave.size  # the polygon turns both ways
    with pytest.raises(InputError, match=r"alpha=1 .*rows? " + str(concave[0])):
        lac_spline(P, 1.0)
    with pytest.raises(InputError, match="alpha"):
        lac_spline(P, float("nan"))
    # open, alpha >= 0: circular end arcs; through 2 points any circular arc would do
    with pytest.raises(InputError, match="at least 3 points"):
        lac_spline(P[:2], 0.5, closed=False)


def test_cli_method_lac(tmp_path, capsys):
    path = tmp_path / "pts.csv"
    pd.DataFrame({"x": CONVEX[:, 0], "y": CONVEX[:, 1]}).to_csv(path, index=False)
    out, summ = tmp_path / "lac.csv", tmp_path / "lac.json"
    assert main(["spline", str(path), "-o", str(out), "--method", "lac", "--alpha", "0.5", "--samples", "8",
                 "--summary", str(summ)]) == 0
    df = pd.read_csv(out)
    assert len(df) == len(CONVEX) * 8 and (df["curvature"] > 0).all()  # convex, counter-clockwise
    s = json.loads(summ.read_text())
    assert s["method"] == "lac" and s["alpha"] == 0.5
    assert s["g2_error"] <= 1e-10 and s["interior_extrema"] == 0 and s["corners"] == []
    assert s["self_intersections"] == 0 and s["closure_error"] <= 1e-12
    wavy = tmp_path / "wavy.csv"
    pd.DataFrame({"x": WAVY[:, 0], "y": WAVY[:, 1]}).to_csv(wavy, index=False)
    capsys.readouterr()
    assert main(["spline", str(wavy), "-o", str(tmp_path / "w.csv"), "--method", "lac", "--alpha", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "wavy.csv" in err[0] and "alpha < 0" in err[0]
    assert not (tmp_path / "w.csv").exists()


@pytest.mark.parametrize("alpha, k0, k1, L", [(-2.0, -1.0, 2.0, 1.3), (-2.0, 5.0, 0.01, 3.0), (-0.5, 0.0, 1.5, 2.0),
                                              (-0.3, -1.0, 2.0, 1.3), (-0.3, 5.0, 0.05, 3.0),
                                              (0.0, 0.2, 5.0, 1.3), (1.0, 5.0, 0.01, 3.0), (2.0, 0.2, 5.0, 1.3)])
def test_arc_chord_against_the_natural_equation(alpha, k0, k1, L):
    # the chord of one arc (curvature ratios up to 500, an inflection with a
    # square-root curvature) by its graded Gauss rule, against the natural
    # equation solved at rtol 1e-13 (the curvature of the definition)
    from attneave.stimuli.curves.lac.arc import arc_integrals

    x, y, th = integrate_segment(alpha, 0.0, 0.0, 0.4, k0, k1, L)
    out = arc_integrals(np.array([0.4]), np.array([k0]), np.array([k1]), np.array([L]), alpha)
    assert abs(out["z"][0] - (x + 1j * y)) <= 5e-12 * L
    assert out["turn"][0] == pytest.approx(th - 0.4, abs=1e-11)  # closed form vs the ODE's 1e-12


@pytest.mark.parametrize("alpha", [-0.5, 1.0])
def test_similarity_and_orientation(alpha):
    # a LAC of slope alpha scaled by s is a LAC of the same slope: curvature
    # / s, lengths * s; traversed backwards, the curvature keeps its
    # geometric sign (positive on a convex curve)
    sp = lac_spline(CONVEX, alpha)
    big = lac_spline(CONVEX * 1000.0 + 1e6, alpha)
    assert np.allclose(big.kappa * 1000.0, sp.kappa, rtol=1e-9)
    assert np.allclose(big.length / 1000.0, sp.length, rtol=1e-9)
    back = lac_spline(CONVEX[::-1], alpha)
    assert np.all(sp.node_curvature > 0) and np.all(back.node_curvature > 0)
    # the same curve: node curvatures in reverse order (node i of the reversed points is node n-1-i)
    assert np.allclose(back.node_curvature, sp.node_curvature[::-1], rtol=1e-9)
