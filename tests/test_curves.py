"""The paper's curves against closed forms and defining properties.

Every expected value here is computed from an independent formula (Fresnel,
sine/cosine integrals, the logarithmic spiral's complex power, the involute
of a circle, the dilogarithm) or from finite differences of the returned
points, never from the stored curvature alone.
"""

import numpy as np
import pytest
from scipy.special import fresnel, hyp2f1, sici, spence

from attneave.stimuli.curves import (
    clothoid,
    constant_info,
    constant_info_curvature,
    constant_info_domain,
    integrate_natural,
    log_aesthetic,
    pseudospiral,
    superspiral,
)
from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.information import surprisal_paper

TOL = 1e-9


# --------------------------------------------------------------------------- independent closed forms


def canonical_clothoid(k0, c, s):
    """Curve with curvature k0 + c*s from s[0] (origin, theta 0), built from the
    standard clothoid Q(v) = int_0^v exp(i c u^2/2) du = sqrt(pi/c) (C(t) + i S(t)),
    t = v sqrt(c/pi) (curvature c v, tangent angle c v^2/2): our curve is its piece
    v = s + k0/c moved rigidly. For c < 0 it is the mirror image (y -> -y) of the
    curve with curvature -k0 - c s."""
    if c < 0:
        return np.conj(canonical_clothoid(-k0, -c, s))
    v = s + k0 / c
    S, C = fresnel(v * np.sqrt(c / np.pi))
    q = np.sqrt(np.pi / c) * (C + 1j * S)
    return (q - q[0]) * np.exp(-1j * c * v[0] ** 2 / 2)


def log_spiral(lam, sigma):
    """Log spiral rho = lam*sigma (sigma > 0 = arc length from the pole), from sigma[0]."""
    e = 1 + 1j / lam
    theta0 = -np.log(sigma[0]) / lam
    z = np.exp(1j * theta0) * (sigma**e - sigma[0] ** e) / e
    pole = -np.exp(1j * theta0) * sigma[0] ** e / e
    return z, pole


def involute(R, t):
    """Involute of a circle of radius R (centre 0) by unwinding angle t, moved to start at
    the origin with tangent angle 0; returns points and the moved centre."""
    q = R * ((np.cos(t) + t * np.sin(t)) + 1j * (np.sin(t) - t * np.cos(t)))
    rot = np.exp(-1j * t[0])
    return (q - q[0]) * rot, (0 - q[0]) * rot


def nielsen(lam, s):
    """LAC alpha = 0 (kappa = exp(-lam s)) from Nielsen's spiral a (ci t, si t)."""
    a = 1 / abs(lam)
    if lam < 0:  # kappa = exp(s/a) = t/a with t = a exp(s/a), tangent angle t
        t = a * np.exp(s / a)
        si_, ci_ = sici(t)
        q = a * (ci_ + 1j * si_)
        return (q - q[0]) * np.exp(-1j * t[0])
    # lam > 0: t = a exp(-s/a) decreases; the mirrored spiral a (ci t, -si t) has tangent angle pi - t
    t = a * np.exp(-s / a)
    si_, ci_ = sici(t)
    q = a * (ci_ - 1j * si_)
    return (q - q[0]) * np.exp(-1j * (np.pi - t[0]))


def fd_curvature(x, y, h):
    """Signed curvature from points on a uniform parameter grid (5-point stencils), interior only."""

    def d1(f):
        return (f[:-4] - 8 * f[1:-3] + 8 * f[3:-1] - f[4:]) / (12 * h)

    def d2(f):
        return (-f[:-4] + 16 * f[1:-3] - 30 * f[2:-2] + 16 * f[3:-1] - f[4:]) / (12 * h * h)

    x1, y1, x2, y2 = d1(x), d1(y), d2(x), d2(y)
    return (x1 * y2 - y1 * x2) / (x1 * x1 + y1 * y1) ** 1.5


def z_of(curve):
    return curve.x + 1j * curve.y


def circle_fit(z):
    """Algebraic least-squares circle through complex points: centre, radius."""
    x, y = z.real, z.imag
    A = np.column_stack([x, y, np.ones_like(x)])
    sol, *_ = np.linalg.lstsq(A, x * x + y * y, rcond=None)
    cx, cy = sol[0] / 2, sol[1] / 2
    return cx + 1j * cy, np.sqrt(sol[2] + cx * cx + cy * cy)


# --------------------------------------------------------------------------- generic integrator and clothoid


CLOTHOIDS = [(0.0, np.pi, 0.0, 1.0), (0.0, 1.0, 0.0, 10.0), (1.0, -0.5, 0.0, 8.0), (0.3, 2.0, -3.0, 4.0),
             (-2.0, -1.5, -1.0, 3.0)]


@pytest.mark.parametrize("k0, c, s0, s1", CLOTHOIDS)
def test_integrator_matches_fresnel(k0, c, s0, s1):
    cv = integrate_natural(lambda s: k0 + c * s, s0, s1, num=301)
    ref = canonical_clothoid(k0, c, cv.s)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL
    assert np.allclose(cv.theta, k0 * (cv.s - s0) + c * (cv.s**2 - s0**2) / 2, atol=TOL, rtol=0)
    assert cv.params["method"] == "DOP853" and cv.params["theta"] == "integrated"


def test_canonical_case_is_fresnel_directly():
    # kappa = pi*s from 0: (x, y) = (C(s), S(s)) exactly
    cv = integrate_natural(lambda s: np.pi * s, 0.0, 2.0, num=41)
    S, C = fresnel(cv.s)
    assert np.max(np.abs(cv.x - C)) < TOL and np.max(np.abs(cv.y - S)) < TOL


@pytest.mark.parametrize("k0, c, s0, s1", CLOTHOIDS)
def test_clothoid_closed_form(k0, c, s0, s1):
    cv = clothoid(k0, c, s0, s1, 301)
    assert cv.params["method"] == "fresnel"
    assert np.max(np.abs(z_of(cv) - canonical_clothoid(k0, c, cv.s))) < TOL
    assert np.allclose(cv.curvature, k0 + c * cv.s)
    fine = clothoid(k0, c, s0, s1, 5001)
    h = fine.s[1] - fine.s[0]
    assert np.allclose(fd_curvature(fine.x, fine.y, h), k0 + c * fine.s[2:-2], rtol=1e-6, atol=1e-8)


def test_clothoid_c0_is_circle_or_line():
    cv = clothoid(0.25, 0.0, 0.0, 30.0, 101)
    assert cv.params["method"] == "circle"
    # centre of curvature of a left-turning circle from the origin heading +x is (0, 1/k0)
    assert np.allclose(np.abs(z_of(cv) - 4j), 4.0, atol=1e-12)
    line = clothoid(0.0, 0.0, 2.0, 5.0, 7)
    assert np.allclose(line.x, line.s - 2.0) and np.allclose(line.y, 0.0)


def test_clothoid_tiny_c_uses_integrator_and_stays_accurate():
    cv = clothoid(1.0, 1e-9, 0.0, 10.0, 101)
    assert cv.params["method"] == "DOP853"
    ref = integrate_natural(lambda s: 1.0 + 1e-9 * s, 0.0, 10.0, 101)
    assert np.max(np.abs(z_of(cv) - z_of(ref))) < TOL
    # and it is within 1e-7 of the unit circle (the c-term moves points by ~ c s^3)
    assert np.max(np.abs(np.abs(z_of(cv) - 1j) - 1.0)) < 1e-6


def test_full_circle_closes():
    cv = integrate_natural(lambda s: 0.5 + 0 * s, 0.0, 4 * np.pi, num=9)
    assert np.allclose(cv.points[-1], (0.0, 0.0), atol=1e-11)
    assert np.isclose(cv.theta[-1], 2 * np.pi, rtol=0, atol=1e-11)


# --------------------------------------------------------------------------- LAC (eq. 9)


@pytest.mark.parametrize("lam", [0.5, -0.3])
def test_lac_alpha_minus1_is_clothoid(lam):
    # rho = (1 - lam s)^-1  =>  kappa = 1 - lam s
    cv = log_aesthetic(-1.0, lam, 0.0, 1.8, 201)
    assert np.max(np.abs(z_of(cv) - canonical_clothoid(1.0, -lam, cv.s))) < TOL


@pytest.mark.parametrize("lam, s0, s1", [(-0.5, 0.0, 4.0), (0.7, -1.0, 5.0)])
def test_lac_alpha0_is_nielsen_spiral(lam, s0, s1):
    cv = log_aesthetic(0.0, lam, s0, s1, 201)
    assert np.max(np.abs(z_of(cv) - nielsen(lam, cv.s))) < TOL


@pytest.mark.parametrize("lam", [0.5, 2.0])
def test_lac_alpha1_is_log_spiral(lam):
    # rho = lam s + 1 = lam (s + 1/lam): arc length from the pole sigma = s + 1/lam
    cv = log_aesthetic(1.0, lam, 0.0, 12.0, 301)
    ref, pole = log_spiral(lam, cv.s + 1 / lam)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL
    # defining property: constant angle between radius vector and tangent, cot = lam
    ang = np.angle((z_of(cv) - pole) * np.exp(-1j * cv.theta))
    assert np.allclose(ang, -np.arctan2(1 / lam, 1), atol=1e-9)


@pytest.mark.parametrize("lam", [0.4, 3.0])
def test_lac_alpha2_is_involute_of_circle(lam):
    # rho^2 = 2 lam s + 1: involute of a circle of radius R = lam, unwinding angle t = rho/R
    cv = log_aesthetic(2.0, lam, 0.0, 6.0, 301)
    rho = np.sqrt(2 * lam * cv.s + 1)
    ref, centre = involute(lam, rho / lam)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL
    # defining property: the centres of curvature (evolute) lie on one circle of radius R
    ev = z_of(cv) + np.exp(1j * cv.theta) * 1j / cv.curvature
    c_fit, r_fit = circle_fit(ev)
    assert abs(r_fit - lam) < 1e-9 and abs(c_fit - centre) < 1e-9
    assert np.max(np.abs(np.abs(ev - c_fit) - lam)) < 1e-9


@pytest.mark.parametrize("alpha, lam", [(0.5, 1.0), (-2.0, 0.2), (3.0, -0.1)])
def test_lac_general_alpha(alpha, lam):
    cv = log_aesthetic(alpha, lam, 0.0, 2.0, 2001)
    rho = (lam * alpha * cv.s + 1) ** (1 / alpha)
    assert np.allclose(cv.curvature, 1 / rho, rtol=1e-13)
    h = cv.s[1] - cv.s[0]
    assert np.allclose(fd_curvature(cv.x, cv.y, h), 1 / rho[2:-2], rtol=1e-7)
    # the closed-form tangent angle equals the integrated one
    ref = integrate_natural(lambda s: (lam * alpha * s + 1) ** (-1 / alpha), 0.0, 2.0, 2001)
    assert np.max(np.abs(cv.theta - ref.theta)) < TOL
    assert np.max(np.abs(z_of(cv) - z_of(ref))) < TOL


def test_lac_small_lambda_is_unit_circle():
    cv = log_aesthetic(1.5, 1e-12, 0.0, 2 * np.pi, 101)
    assert np.allclose(cv.theta, cv.s, atol=1e-10)
    assert np.allclose(np.abs(z_of(cv) - 1j), 1.0, atol=1e-10)


def test_lac_domain():
    with pytest.raises(InputError, match="lam\\*alpha\\*s \\+ 1 > 0"):
        log_aesthetic(1.0, -1.0, 0.0, 2.0)
    with pytest.raises(InputError, match="s > -0.5"):
        log_aesthetic(2.0, 1.0, -1.0, 1.0)
    # alpha < 0 may reach base 0 at an end, where kappa -> 0
    cv = log_aesthetic(-1.0, 1.0, 0.0, 1.0, 11)
    assert cv.curvature[-1] == 0.0


# --------------------------------------------------------------------------- pseudospirals (eq. 8)


def test_pseudospiral_m1_is_log_spiral():
    a = 0.3
    cv = pseudospiral(a, 1.0, 0.5, 6.0, 301)  # rho = a s: pole at s = 0
    ref, pole = log_spiral(a, cv.s)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL
    ang = np.angle((z_of(cv) - pole) * np.exp(-1j * cv.theta))
    assert np.allclose(ang, -np.arctan2(1 / a, 1), atol=1e-9)


def test_pseudospiral_m_minus1_is_cornu_spiral():
    a = 0.5
    cv = pseudospiral(a, -1.0, 0.0, 3.0, 301)  # kappa = s / a
    assert np.max(np.abs(z_of(cv) - canonical_clothoid(0.0, 1 / a, cv.s))) < TOL


def test_pseudospiral_m_half_is_involute_of_circle():
    a = 1.5
    cv = pseudospiral(a, 0.5, 0.01, 5.0, 301)  # rho = a sqrt(s): R = a^2/2
    R = a * a / 2
    ref, centre = involute(R, a * np.sqrt(cv.s) / R)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL
    ev = z_of(cv) + np.exp(1j * cv.theta) * 1j / cv.curvature
    assert np.max(np.abs(np.abs(ev - centre) - R)) < 1e-9


def test_pseudospiral_m0_is_circle_and_negative_a_turns_right():
    cv = pseudospiral(-2.0, 0.0, 0.0, 3.0, 31)
    assert np.allclose(cv.curvature, -0.5)
    assert np.allclose(np.abs(z_of(cv) + 2j), 2.0, atol=1e-11)


def test_pseudospiral_domain():
    with pytest.raises(InputError, match="s > 0"):
        pseudospiral(1.0, 0.5, 0.0, 1.0)
    with pytest.raises(InputError, match="s >= 0"):
        pseudospiral(1.0, -1.0, -1.0, 1.0)
    with pytest.raises(InputError, match="nonzero"):
        pseudospiral(0.0, 1.0, 1.0, 2.0)


# --------------------------------------------------------------------------- eq. 7


EQ7_N = 10


def test_eq7_values_and_domain_edges():
    n = EQ7_N
    # C = 0: the paper's reduction kappa = (pi/s)(n/2 + 2)
    s = np.array([0.1, 1.0, 5.0])
    assert np.allclose(constant_info_curvature(s, 0.0, n), np.pi / s * (n / 2 + 2), rtol=1e-14)
    for C in (0.03, -0.03):
        s_min = constant_info_domain(C, n)
        assert np.isclose(s_min, np.sqrt(0.03) * n)
        k = constant_info_curvature(s_min, C, n)  # arccos(+1) = 0, arccos(-1) = pi
        expected = 2 * np.pi / s_min if C > 0 else (n * np.pi + 2 * np.pi) / s_min
        assert np.isclose(k, expected, rtol=1e-12)


@pytest.mark.parametrize("C", [-0.03, 0.0, 0.03])
def test_eq7_points_have_eq7_curvature(C):
    s0 = max(constant_info_domain(C, EQ7_N), 1.0)
    cv = constant_info(C, EQ7_N, s0, 5.0, 4001)
    assert (cv.x[0], cv.y[0], cv.theta[0]) == (0.0, 0.0, 0.0)
    h = cv.s[1] - cv.s[0]
    k_fd = fd_curvature(cv.x, cv.y, h)
    s_in = cv.s[2:-2]
    k_eq7 = (np.arccos(C * EQ7_N**2 / s_in**2) * EQ7_N + 2 * np.pi) / s_in  # eq. 7 written out
    # the square-root slope of kappa at the domain edge spoils the stencil on its first points
    far = s_in > s0 + 0.05
    assert np.allclose(k_fd[far], k_eq7[far], rtol=1e-7)
    assert np.allclose(k_fd, k_eq7, rtol=2e-3)
    assert np.allclose(cv.curvature, constant_info_curvature(cv.s, C, EQ7_N), rtol=1e-14)


@pytest.mark.parametrize("C", [-0.03, 0.0, 0.03])
@pytest.mark.parametrize("b", [0.5, 1.0, 2.0])
def test_eq7_surprisal_is_constant(C, b):
    """Eq. 5 with ds = s/n along eq. 7: k ds - 2 pi/n = arccos(C n^2/s^2), so
    u = -ln A' - b (s/n)^2 (C n^2/s^2) = -ln A' - b C, whatever s."""
    A, n = 0.25, EQ7_N
    s0 = max(constant_info_domain(C, n), 0.05)
    cv = constant_info(C, n, s0, 5.0, 2001)
    ds = cv.s / n
    u = surprisal_paper(turning_angle=cv.curvature * ds, ds=ds, n=n, A=A, b=b, closed=True)
    u0 = -np.log(A) - b * C
    assert np.max(np.abs(u - u0)) / abs(u0) < 1e-9
    # the same from the curvature measured on the points
    far = cv.s[2:-2] > s0 + 0.05
    k_fd = fd_curvature(cv.x, cv.y, cv.s[1] - cv.s[0])[far]
    ds_in = cv.s[2:-2][far] / n
    u_fd = surprisal_paper(turning_angle=k_fd * ds_in, ds=ds_in, n=n, A=A, b=b, closed=True)
    assert np.max(np.abs(u_fd - u0)) / abs(u0) < 1e-5


def test_eq7_surprisal_is_not_constant_with_fixed_ds():
    # the constancy needs ds = s/n; with the contour's fixed ds = L/n it fails (guards the test above)
    n, L = EQ7_N, 5.0
    s = np.linspace(2.0, 5.0, 50)
    k = constant_info_curvature(s, 0.03, n)
    u = surprisal_paper(turning_angle=k * L / n, ds=L / n, n=n, A=0.25, b=1.0, closed=True)
    assert np.ptp(u) > 1e-2


def test_eq7_C0_is_log_spiral():
    # kappa = (pi/s)(n/2 + 2): rho = lam s with lam = 1/(pi (n/2 + 2)), pole at s = 0
    cv = constant_info(0.0, EQ7_N, 1.0, 5.0, 401)
    lam = 1 / (np.pi * (EQ7_N / 2 + 2))
    ref, _ = log_spiral(lam, cv.s)
    assert np.max(np.abs(z_of(cv) - ref)) < TOL


def test_eq7_domain_errors():
    with pytest.raises(InputError, match=r"s >= 1\.73205"):
        constant_info_curvature(1.0, 0.03, EQ7_N)
    with pytest.raises(InputError, match=r"s >= 1\.73205"):
        constant_info_curvature(1.0, -0.03, EQ7_N)
    with pytest.raises(InputError, match="outside the domain"):
        constant_info_curvature(0.0, 0.0, EQ7_N)
    with pytest.raises(InputError, match="outside the domain of eq. 7"):
        constant_info(0.03, EQ7_N, 1.0, 5.0)
    with pytest.raises(InputError, match="n must be > 0"):
        constant_info_curvature(1.0, 0.0, 0)
    # the default start is the edge of the domain
    cv = constant_info(0.02, EQ7_N, s_end=3.0, num=11)
    assert np.isclose(cv.s[0], np.sqrt(0.02) * EQ7_N)


# --------------------------------------------------------------------------- superspirals (eq. 10)

# 2F1(1, 1; 2; -x) = ln(1 + x)/x            =>  s(theta) = -Li2(-theta)
# 2F1(1/2, 1; 3/2; -x) = arctan(sqrt x)/sqrt x  =>  s(theta) = 2 sqrt(t) arctan(sqrt t) - ln(1 + t)
SUPERSPIRALS = [
    ((1.0, 1.0, 2.0), lambda p: np.log1p(p) / p, lambda t: -spence(1 + t)),
    ((0.5, 1.0, 1.5), lambda p: np.arctan(np.sqrt(p)) / np.sqrt(p),
     lambda t: 2 * np.sqrt(t) * np.arctan(np.sqrt(t)) - np.log1p(t)),
]


@pytest.mark.parametrize("abc, rho_fn, s_fn", SUPERSPIRALS)
def test_superspiral_closed_forms(abc, rho_fn, s_fn):
    theta_end = 3 * np.pi
    cv = superspiral(*abc, theta_end=theta_end, num=3001)
    psi = cv.theta
    assert psi[0] == 0 and np.isclose(psi[-1], theta_end)
    assert np.max(np.abs(cv.s - s_fn(psi))) < TOL
    inner = psi[1:]
    assert np.allclose(1 / cv.curvature[1:], rho_fn(inner), rtol=1e-12)
    # from the points (uniform in tangent angle): dP/dpsi = rho e^{i psi}, curvature 1/rho
    h = psi[1] - psi[0]
    z = z_of(cv)
    dz = (z[:-4] - 8 * z[1:-3] + 8 * z[3:-1] - z[4:]) / (12 * h)
    p_in = psi[2:-2]
    assert np.allclose(np.abs(dz), rho_fn(p_in), rtol=1e-9)
    assert np.allclose(np.angle(dz * np.exp(-1j * p_in)), 0.0, atol=1e-9)
    assert np.allclose(fd_curvature(cv.x, cv.y, h), 1 / rho_fn(p_in), rtol=1e-7)


def test_superspiral_rho_is_hyp2f1():
    cv = superspiral(2.0, 0.7, 1.9, theta_end=2.0, num=21)
    assert np.allclose(cv.curvature, 1 / hyp2f1(2.0, 0.7, 1.9, -cv.theta))
    assert np.all(np.diff(cv.curvature) > 0)  # completely monotone rho: monotone curvature
    assert cv.params["quad_error"] < 1e-10


@pytest.mark.parametrize("abc", [(1.0, 2.0, 2.0), (1.0, 2.0, 1.0), (0.0, 1.0, 2.0), (1.0, 0.0, 1.0)])
def test_superspiral_domain(abc):
    with pytest.raises(InputError, match="c > b > 0 and a > 0"):
        superspiral(*abc, theta_end=1.0)


def test_superspiral_theta_end_must_be_positive():
    with pytest.raises(InputError, match="theta_end"):
        superspiral(1.0, 1.0, 2.0, theta_end=0.0)


# --------------------------------------------------------------------------- common contract


@pytest.mark.parametrize(
    "make",
    [
        lambda: clothoid(0.2, -1.0, 1.0, 3.0, 11),
        lambda: pseudospiral(1.0, 0.5, 1.0, 2.0, 11),
        lambda: log_aesthetic(0.5, 1.0, -0.5, 1.0, 11),
        lambda: superspiral(1.0, 1.0, 2.0, 1.0, 11),
        lambda: constant_info(-0.01, 10, 1.0, 2.0, 11),
    ],
)
def test_every_family_starts_at_origin_heading_x(make):
    cv = make()
    assert (cv.x[0], cv.y[0], cv.theta[0]) == (0.0, 0.0, 0.0)
    assert len(cv) == 11 and set(cv.table()) == {"s", "x", "y", "theta", "curvature"}
    assert {"s_start", "s_end", "num", "method"} <= set(cv.params)
    with pytest.raises(ValueError):
        cv.x[0] = 1.0  # read-only


def test_bad_arguments():
    with pytest.raises(InputError, match="s_end must be greater"):
        clothoid(0, 1, 2.0, 1.0)
    with pytest.raises(InputError, match="num"):
        clothoid(0, 1, 0.0, 1.0, num=1)
    with pytest.raises(InputError, match="finite"):
        clothoid(np.nan, 1, 0.0, 1.0)
    with pytest.raises(InputError, match="not finite"):
        integrate_natural(lambda s: 1 / (s - 0.5), 0.0, 1.0, num=3)


def test_integrator_has_a_bounded_budget(monkeypatch):
    # a curve turning ~1e5 rad would take minutes (hours for 1e11 rad: clothoid c=1e6
    # on [0, 1000] fell back to this integrator and never returned); it must be a clear error
    import attneave.stimuli.curves.natural as curves

    monkeypatch.setattr(curves, "_MAX_NFEV", 20_000, raising=False)
    # the estimate before integrating refuses this one at once (1e5 rad)...
    with pytest.raises(InputError, match=r"turns by about 1e\+05 rad"):
        integrate_natural(lambda s: 2000.0 * s, 0.0, 10.0, num=11)
    # ...and the budget still stops a curve the estimate misses
    monkeypatch.setattr(curves, "_check_turning", lambda *a: None)
    with pytest.raises(InputError, match="turns too often"):
        integrate_natural(lambda s: 2000.0 * s, 0.0, 10.0, num=11)


def test_a_curve_turning_beyond_the_budget_is_refused_at_once():
    # eq. 7 with n = 1e300 turns by about 1e301 rad on [0.001, 1]: 13 s of integration before
    import time

    from attneave.stimuli.curves import constant_info

    t = time.perf_counter()
    with pytest.raises(InputError, match="turns by about 1.09e\\+301 rad"):
        constant_info(C=0.0, n=1e300, s_end=1.0, num=3)
    assert time.perf_counter() - t < 2.0
