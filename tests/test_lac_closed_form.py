"""Log-aesthetic curves in closed form (incomplete gamma, Ziatdinov, Yoshida
& Kim 2012) against quadrature at tight tolerance, and the generalised LAC
(GLAC) against its defining properties."""

import mpmath
import numpy as np
import pytest

from attneave.stimuli.curves import glac, log_aesthetic
from attneave.stimuli.curves.lac.aesthetic import glac_curvature
from attneave.stimuli.curves.lac.g1 import lac_length, lac_standard_end
from attneave.stimuli.curves.lac.gamma import _gamma_form, lac_position
from attneave.stimuli.errors import InputError

ALPHAS = [-2, -1, -0.5, 0, 0.5, 1, 1.5, 2, 3]


def quad_position(s, alpha, lam):
    """int_0^s exp(i theta(u)) du with theta from its own closed form, by
    mpmath's tanh-sinh quadrature at 25 digits (independent of the gamma form)."""
    with mpmath.workdps(25):
        a, l = mpmath.mpf(alpha), mpmath.mpf(lam)

        def theta(u):
            if alpha == 0:
                return (1 - mpmath.exp(-l * u)) / l
            base = l * a * u + 1
            if alpha == 1:
                return mpmath.log(base) / l
            p = (a - 1) / a
            return (base**p - 1) / (l * a * p)

        return complex(mpmath.quad(lambda u: mpmath.expj(theta(u)), [0, s]))


@pytest.mark.parametrize("alpha", ALPHAS)
@pytest.mark.parametrize("lam", [0.8, -0.35])
def test_closed_form_agrees_with_quadrature(alpha, lam):
    s = np.array([0.05, 0.6, 1.4])
    if alpha * lam < 0:
        s = s[lam * alpha * s + 1 > 0.05]
    z = lac_position(s, alpha, lam)  # panel quadrature of the closed-form angle
    closed = _gamma_form(s.copy(), alpha, lam) if alpha not in (0, 1) else z  # the incomplete gammas
    for u, zu, zc in zip(s, z, closed):
        q = quad_position(float(u), alpha, lam)
        assert abs(zu - q) <= 1e-12 and abs(zc - q) <= 1e-12


@pytest.mark.parametrize("alpha", [-1.0, 0.5, 2.0])
def test_dense_grid_agrees_with_quadrature(alpha):
    # more points than closed-form anchors: the in-between points too
    s = np.linspace(0.0, 1.0, 301)
    z = lac_position(s, alpha, 0.6)
    for i in (1, 77, 150, 299):
        assert abs(z[i] - quad_position(float(s[i]), alpha, 0.6)) <= 1e-12


def test_segment_end_uses_the_closed_form():
    # the Yoshida-Saito standard form's end point: int rho(psi) exp(i psi) dpsi
    for alpha in (0.0, 0.5, 1.0, 2.5):
        te, lam = 1.1, 0.4
        E = lac_standard_end(te, alpha, lam)
        with mpmath.workdps(25):
            if alpha == 1:
                rho = lambda p: mpmath.exp(lam * p)  # noqa: E731
            else:
                rho = lambda p: ((alpha - 1) * lam * p + 1) ** (1 / mpmath.mpf(alpha - 1))  # noqa: E731
            ref = complex(mpmath.quad(lambda p: rho(p) * mpmath.expj(p), [0, te]))
        assert abs(E - ref) <= 1e-12 * lac_length(te, alpha, lam)


def test_log_aesthetic_curve_is_the_closed_form():
    cv = log_aesthetic(1.5, 0.7, 0.5, 2.0, 7)
    assert cv.params["method"] == "incomplete gamma"
    ref = np.array([quad_position(float(u), 1.5, 0.7) for u in cv.s])
    th0 = float(np.asarray(cv.s[0]))
    # from s_start, turned so that the tangent there is +x
    p = (1.5 - 1) / 1.5
    theta0 = ((0.7 * 1.5 * th0 + 1) ** p - 1) / (0.7 * 1.5 * p)
    expected = (ref - ref[0]) * np.exp(-1j * theta0)
    assert np.max(np.abs(cv.x + 1j * cv.y - expected)) <= 1e-12


def test_glac_reduces_to_lac_at_nu_zero():
    for alpha, lam in ((0.0, 0.5), (-1.0, 0.3), (2.0, 0.4)):
        a = glac(alpha, lam, 0.0, 0.0, 1.5, 31)
        b = log_aesthetic(alpha, lam, 0.0, 1.5, 31)
        assert np.max(np.abs(a.points - b.points)) <= 1e-10
        np.testing.assert_allclose(a.curvature, b.curvature, rtol=1e-12)


@pytest.mark.parametrize("alpha, lam, nu", [(0.5, 1.0, 0.4), (-1.0, 0.3, 2.0), (0.0, -0.4, -0.5), (2.0, 0.5, 1.0)])
def test_glac_defining_property(alpha, lam, nu):
    # R = rho + nu has a straight logarithmic curvature graph of slope alpha:
    # R ds/dR = R**alpha / lam, i.e. d ln R / ds = lam R**-alpha; checked by
    # finite differences of the curvature measured from the positions
    cv = glac(alpha, lam, nu, 0.0, 1.0, 2001)
    h = cv.s[1] - cv.s[0]
    z = cv.x + 1j * cv.y
    d1 = (z[2:] - z[:-2]) / (2 * h)
    d2 = (z[2:] - 2 * z[1:-1] + z[:-2]) / h**2
    k = (d1.real * d2.imag - d1.imag * d2.real) / np.abs(d1) ** 3
    np.testing.assert_allclose(k, glac_curvature(cv.s[1:-1], alpha, lam, nu), rtol=1e-6)
    R = 1 / cv.curvature + nu
    dlnR = np.gradient(np.log(R), h)[5:-5]
    np.testing.assert_allclose(dlnR, lam * R[5:-5] ** -alpha, rtol=1e-5)
    # monotone curvature
    dk = np.diff(cv.curvature)
    assert np.all(dk <= 0) or np.all(dk >= 0)


def test_glac_domain():
    with pytest.raises(InputError, match="nu"):
        glac(0.5, 1.0, -1.5)
    with pytest.raises(InputError, match="leaves the domain"):
        glac(1.0, -1.0, 0.5, 0.0, 5.0)


@pytest.mark.parametrize("alpha", [0.985, 0.999, 1 - 1e-9, 1 + 1e-6, 1.005])
@pytest.mark.parametrize("lam", [0.8, -0.35, 40.0])
def test_alpha_near_one_agrees_with_quadrature(alpha, lam):
    # the panel quadrature that replaces the incomplete gammas near alpha = 1 (their
    # cancellation needs thousands of digits there), against mpmath's own quadrature
    s = np.array([0.05, 0.6, 1.4])
    s = s[lam * alpha * s + 1 > 0.05]
    z = lac_position(s, alpha, lam)
    for u, zu in zip(s, z):
        assert abs(zu - quad_position(float(u), alpha, lam)) <= 1e-12


def test_alpha_near_one_tends_to_the_logarithmic_spiral_near_its_pole():
    # alpha -> 1: the elementary log spiral (rho = 1 + lam s), including arc lengths within
    # 1e-12 of the pole rho = 0, where the curve winds ever tighter
    lam = 2.0
    s = np.r_[np.linspace(-0.5 * (1 - 1e-12), 0.0, 50), np.linspace(0.01, 3.0, 50)]
    spiral = lac_position(s, 1.0, lam)
    for eps in (1e-6, -1e-6):
        near = lac_position(s / (1 + eps) if eps > 0 else s, 1 + eps, lam)
        assert np.max(np.abs(near - spiral)) < 1e-4


def test_a_curve_that_straightens_out_is_fast():
    # large lam, small alpha: rho grows by e^(1e8) and the curve is a straight line after a
    # turn of 1e-8 rad; the incomplete gammas ran for minutes
    import time

    t = time.perf_counter()
    z = lac_position(np.linspace(2.0, 100.0, 201), 1e-8, 1e8)
    assert time.perf_counter() - t < 1.0
    assert np.allclose(np.abs(z - z[0]), np.linspace(0.0, 98.0, 201), rtol=0, atol=1e-9)


def test_alpha_near_one_is_fast():
    import time

    t = time.perf_counter()
    cv = log_aesthetic(0.999, 1.0, 0.0, 1.0, 201)
    assert time.perf_counter() - t < 1.0  # the incomplete-gamma form took 19 s here
    assert np.all(np.isfinite(cv.x)) and abs(cv.s[-1] - np.sum(np.hypot(np.diff(cv.x), np.diff(cv.y)))) < 1e-4
