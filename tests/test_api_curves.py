"""Python-API robustness of the curve families and splines: no NaN for any
accepted parameters, one-line InputErrors naming the argument, size caps."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from attneave.stimuli import curves
from attneave.stimuli.curves.natural import MAX_POINTS
from attneave.stimuli.curves.splines import fit_spline, qic_spline
from attneave.stimuli.errors import InputError

_T = np.linspace(0, 2 * np.pi, 8, endpoint=False)
P = np.c_[100 + 50 * np.cos(_T), 100 + 40 * np.sin(_T)]


def _finite(c):
    return all(np.all(np.isfinite(getattr(c, n))) for n in ("s", "x", "y", "theta", "curvature"))


def test_lac_large_positive_lam_is_finite_and_straightens():
    c = curves.log_aesthetic(alpha=0, lam=1000, s_end=1, num=51)
    assert _finite(c)
    # the tangent tends to 1/lam: the curve is (nearly) a straight line of length s
    assert np.allclose(np.hypot(c.x, c.y)[1:] / c.s[1:], 1.0, atol=1e-3)


@pytest.mark.parametrize("lam", [-710, -1000])
def test_lac_curvature_overflow_refused_naming_lam(lam):
    with pytest.raises(InputError, match=r"^lam: .*709"):
        curves.log_aesthetic(lam=lam, s_end=1)


def test_lac_alpha_near_one_is_right():
    # eq. 9 with alpha = 1.01, lam = 100 is nearly straight over s in [0, 1]; the closed form
    # lost every digit there (x was 0.27 at s = 1)
    c = curves.log_aesthetic(alpha=1.01, lam=100, s_end=1, num=3)
    u = np.linspace(0, 1, 200_001)
    from attneave.stimuli.curves.lac.gamma import lac_theta

    f = np.exp(1j * lac_theta(u, 1.01, 100.0))
    z = np.sum(0.5 * (f[1:] + f[:-1])) * (u[1] - u[0])
    assert abs(complex(c.x[-1], c.y[-1]) - z) < 1e-8


@settings(max_examples=40, deadline=None)
@given(alpha=st.sampled_from([0.0, -1.0, 0.5, 2.0, 3.0, -0.3]),
       lam=st.floats(-2000, 2000), s_end=st.floats(1e-3, 3.0))
def test_lac_never_nan(alpha, lam, s_end):
    try:
        c = curves.log_aesthetic(alpha=alpha, lam=lam, s_end=s_end, num=20)
    except InputError:
        return
    assert _finite(c)
    assert np.all(np.hypot(c.x, c.y) <= c.s - c.s[0] + 1e-9)


@settings(max_examples=30, deadline=None)
@given(k0=st.floats(-1e10, 1e10), c=st.floats(-1e10, 1e10), s0=st.floats(-5, 0), L=st.floats(1e-3, 5))
def test_clothoid_never_nan(k0, c, s0, L):
    try:
        cv = curves.clothoid(k0=k0, c=c, s_start=s0, s_end=s0 + L, num=20)
    except InputError:
        return
    assert _finite(cv)


def test_clothoid_many_turns_finite():
    # the compiled evaluator gives NaN beyond ~8000 rad of turning; the family falls back
    cv = curves.clothoid(k0=0.011372232021982833, c=4247746651.334588, s_start=-3.405731603377733,
                         s_end=0.016511373289027357, num=30)
    assert _finite(cv)


def test_pseudospiral_overflow_is_inputerror():
    with pytest.raises(InputError):
        curves.pseudospiral(a=2.2e-5, m=836.0, s_start=9.8e-5, s_end=428.0, num=30)


@pytest.mark.parametrize("call, name", [
    (lambda: curves.clothoid(num="10"), "num"),
    (lambda: curves.clothoid(num=10**9), "num"),
    (lambda: curves.superspiral(epsabs=-1), "epsabs"),
    (lambda: curves.superspiral(epsrel=np.nan), "epsrel"),
    (lambda: curves.superspiral(num=10**9), "num"),
    (lambda: curves.integrate_natural(5, 0, 1), "curvature_fn"),
    (lambda: curves.integrate_natural(lambda s: 0 * s + 1, 0, 1, rtol=np.nan), "rtol"),
    (lambda: curves.integrate_natural(lambda s: 0 * s + 1, 0, 1, max_step=0), "max_step"),
    (lambda: curves.integrate_natural(lambda s: np.array([1.0, 2.0]), 0, 1), "curvature_fn"),
    (lambda: qic_spline(P, tol=np.nan), "tol"),
    (lambda: qic_spline(P, tol=-1), "tol"),
    (lambda: qic_spline(P, corner_turn=np.nan), "corner_turn"),
    (lambda: qic_spline(P, max_tangent_deviation=-1), "max_tangent_deviation"),
    (lambda: qic_spline(P, corners=[1.5]), "corners"),
    (lambda: qic_spline(P, max_iter=-1), "max_iter"),
    (lambda: qic_spline(P, max_iter="x"), "max_iter"),
    (lambda: qic_spline(P, closed="no"), "closed"),
    (lambda: fit_spline(P, "cubic", closed="no"), "closed"),
    (lambda: qic_spline(P).sample(10**9), "samples"),
    (lambda: fit_spline(P, "cubic").sample(10**9), "samples"),
])
def test_bad_options_name_the_argument(call, name):
    with pytest.raises(InputError) as e:
        call()
    msg = str(e.value)
    assert name in msg and "\n" not in msg
    assert type(e.value).__name__ == "InputError"  # not a ConvergenceError


def test_api_messages_name_parameters_not_flags():
    with pytest.raises(InputError) as e:
        fit_spline(P, "cubic-natural", closed=True)
    assert "--" not in str(e.value) and "closed=False" in str(e.value)


def test_caps_documented():
    assert MAX_POINTS == 10**7
    assert "MAX_POINTS" in curves.superspiral.__doc__
