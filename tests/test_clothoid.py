"""Clothoid segments: generalized Fresnel integrals, G1 Hermite solver,
derivatives and evaluation, checked against independent closed forms and
quadrature."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import fresnel

from attneave.stimuli.curves.euler import (
    ClothoidConvergenceError,
    clothoid_points,
    fresnel_moments,
    g1_hermite,
    guess_A,
    wrap_angle,
)


def _quad_moment(k, a, b, c, fn):
    val, _ = quad(lambda t: t**k * fn(0.5 * a * t * t + b * t + c), 0.0, 1.0,
                  epsabs=1e-15, epsrel=1e-14, limit=400)
    return val


# (a, b) across the three evaluation regions: double series (|a| < 2, |b| <= 3),
# a-series over recurrent moments (|a| < 0.5, |b| > 3), Fresnel closed form
GRID = [(a, b) for a in (0.0, 1e-9, 3e-3, 0.3, 0.7, 1.99, 2.01, -1.5, 5.0, -12.0, 40.0)
        for b in (0.0, 1e-7, 0.4, -2.9, 3.1, -6.0, 12.0)]


@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize("c", [0.0, 0.8])
def test_fresnel_moments_match_quadrature(c):
    a = np.array([g[0] for g in GRID])
    b = np.array([g[1] for g in GRID])
    X, Y = fresnel_moments(a, b, c)
    for i, (ai, bi) in enumerate(GRID):
        for k, tol in ((0, 2e-14), (1, 2e-12), (2, 1e-10)):
            assert abs(X[k, i] - _quad_moment(k, ai, bi, c, np.cos)) < tol, (k, ai, bi)
            assert abs(Y[k, i] - _quad_moment(k, ai, bi, c, np.sin)) < tol, (k, ai, bi)


def test_fresnel_moments_at_a_zero_closed_form():
    b = np.array([1e-6, 0.5, 2.0, 7.0])
    X, Y = fresnel_moments(0.0, b)
    np.testing.assert_allclose(X[0], np.sin(b) / b, rtol=1e-14)
    np.testing.assert_allclose(Y[0], 2 * np.sin(b / 2) ** 2 / b, rtol=1e-13)
    # first moment: int t cos(bt) = (cos b + b sin b - 1) / b^2
    bb = b[1:]  # the reference formula itself cancels at tiny b
    np.testing.assert_allclose(X[1, 1:], (np.cos(bb) + bb * np.sin(bb) - 1) / bb**2, rtol=1e-12)


def _clothoid_end_fresnel(theta0, k, dk, L):
    """End point of a clothoid from the textbook Fresnel closed form,
    written independently of attneave.stimuli.curves.euler (dk > 0)."""
    # theta(s) = theta0 + k s + dk s^2 / 2 = (pi/2) u^2 + theta0 - k^2/(2 dk)
    # with u = (dk s + k) / sqrt(pi dk)
    sq = np.sqrt(np.pi * dk)
    u0, u1 = k / sq, (k + dk * L) / sq
    S0, C0 = fresnel(u0)
    S1, C1 = fresnel(u1)
    ph = theta0 - k * k / (2 * dk)
    cx, cy = C1 - C0, S1 - S0
    x = (np.cos(ph) * cx - np.sin(ph) * cy) / sq * np.pi
    y = (np.sin(ph) * cx + np.cos(ph) * cy) / sq * np.pi
    return x, y


def test_g1_reproduces_known_clothoids():
    rng = np.random.default_rng(7)
    n = 400
    k = rng.uniform(-2.0, 2.0, n)
    dk = rng.uniform(0.2, 3.0, n) * rng.choice([-1, 1], n)
    L = rng.uniform(0.3, 1.5, n)
    theta0 = rng.uniform(-np.pi, np.pi, n)
    x0, y0 = rng.uniform(-5, 5, (2, n))
    # closed form for dk > 0; a mirror image (y -> -y) for dk < 0
    sgn = np.sign(dk)
    ex, ey = _clothoid_end_fresnel(sgn * theta0, sgn * k, np.abs(dk), L)
    x1, y1 = x0 + ex, y0 + sgn * ey
    theta1 = theta0 + k * L + 0.5 * dk * L * L
    # keep the segments whose tangent stays within pi of the chord, the ones
    # the Bertolazzi-Frego normalisation selects
    phi = np.arctan2(y1 - y0, x1 - x0)
    s = np.linspace(0, 1, 50)[:, None] * L
    dev = theta0 + k * s + 0.5 * dk * s * s - phi
    ok = (np.abs(dev[0] - wrap_angle(dev[0])) < 1e-12) & (np.ptp(dev, axis=0) < np.pi) \
        & (np.abs(wrap_angle(dev[-1]) - dev[-1]) < 1e-12)
    assert ok.sum() > 200
    r = g1_hermite(x0[ok], y0[ok], theta0[ok], x1[ok], y1[ok], theta1[ok])
    np.testing.assert_allclose(r["k"], k[ok], rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(r["dk"], dk[ok], rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(r["L"], L[ok], rtol=1e-10)
    assert r["iterations"] <= 6
    # and its points at arc lengths match quadrature of the known clothoid
    j = np.flatnonzero(ok)[:5]
    for i, jj in enumerate(j):
        for si in (0.3 * L[jj], L[jj]):
            th = lambda t: theta0[jj] + k[jj] * t + 0.5 * dk[jj] * t * t  # noqa: E731
            xr = x0[jj] + quad(lambda t: np.cos(th(t)), 0, si, epsabs=1e-14)[0]
            yr = y0[jj] + quad(lambda t: np.sin(th(t)), 0, si, epsabs=1e-14)[0]
            x, y, _, _ = clothoid_points(x0[jj], y0[jj], theta0[jj], r["k"][i], r["dk"][i], si)
            assert abs(x - xr) < 1e-10 and abs(y - yr) < 1e-10


def test_g1_circle_and_line():
    # quarter circle of radius 2 centred at the origin, counter-clockwise
    r = g1_hermite(2, 0, np.pi / 2, 0, 2, np.pi)
    assert abs(r["k"] - 0.5) < 1e-13 and abs(r["dk"]) < 1e-13
    assert abs(r["L"] - np.pi) < 1e-12
    # straight line
    r = g1_hermite(1, 1, np.pi / 4, 4, 4, np.pi / 4)
    assert abs(r["k"]) < 1e-14 and abs(r["dk"]) < 1e-14 and abs(r["L"] - 3 * np.sqrt(2)) < 1e-13


def test_g1_reversal_symmetry():
    # the same curve traversed backwards: curvatures swap and change sign
    f = g1_hermite(0, 0, 0.3, 2, 1, 1.2)
    b = g1_hermite(2, 1, 1.2 + np.pi, 0, 0, 0.3 + np.pi)
    assert abs(b["k"] + f["k1"]) < 1e-12 and abs(b["k1"] + f["k"]) < 1e-12
    assert abs(b["L"] - f["L"]) < 1e-12


def test_g1_derivatives_match_finite_differences():
    rng = np.random.default_rng(3)
    x1, y1 = rng.uniform(0.5, 2, 2)
    t0, t1 = rng.uniform(-1, 1, 2)
    r = g1_hermite(0, 0, t0, x1, y1, t1, derivatives=True)
    h = 1e-6
    for which, d in (("theta0", (h, 0)), ("theta1", (0, h))):
        p = g1_hermite(0, 0, t0 + d[0], x1, y1, t1 + d[1])
        m = g1_hermite(0, 0, t0 - d[0], x1, y1, t1 - d[1])
        for q, key in (("k", "dk0"), ("k1", "dk1"), ("L", "dL"), ("dk", "ddk")):
            fd = (p[q] - m[q]) / (2 * h)
            assert abs(r[f"{key}_d{which}"] - fd) < 1e-6 * max(1, abs(fd)), (q, which)


def test_guess_near_small_angle_root():
    # for small angles the root of g(A) is 3 (phi0 + phi1); the fitted guess
    # is within a few percent of it
    assert abs(guess_A(1e-4, 2e-4) - 9e-4) < 0.02 * 9e-4


def test_g1_bad_input():
    with pytest.raises(ValueError):
        g1_hermite(1, 1, 0, 1, 1, 1)
    with pytest.raises(ValueError):
        g1_hermite(np.nan, 1, 0, 1, 2, 1)
    with pytest.raises(ClothoidConvergenceError):
        g1_hermite(0, 0, 0.3, 1, 0, 0.2, max_iter=0)
