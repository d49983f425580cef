"""Superspirals (the seed paper's eq. 10; Ziatdinov 2012): curves whose
radius of curvature, as a function of the tangent angle, is a completely
monotonic Gauss hypergeometric function. y-UP coordinates, as in
:mod:`attneave.stimuli.curves.natural`.

References
----------
.. [1] Ziatdinov, R. (2012). Family of superspirals with completely monotonic
       curvature given in terms of Gauss hypergeometric function. Computer
       Aided Geometric Design 29(7), 510-518.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.checks import check_count, check_tolerance
from attneave.stimuli.curves.natural import Curve
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["superspiral"]


def superspiral(a=1.0, b=1.0, c=2.0, theta_end=np.pi, num=201, *, epsabs=1e-13, epsrel=1e-13):
    """Superspiral of the paper's eq. 10 (Ziatdinov 2012).

    Radius of curvature ``rho(psi) = 2F1(a, b; c; -psi)`` as a function of
    the tangent angle ``psi``, with ``c > b > 0`` and ``a > 0`` (then rho is
    completely monotone in psi, so curvature increases monotonically);
    ``x(theta) = int_0^theta rho cos(psi) dpsi``,
    ``y(theta) = int_0^theta rho sin(psi) dpsi`` and the arc length
    ``s(theta) = int_0^theta rho dpsi``.

    Parameters
    ----------
    a, b, c : float
        Parameters of the Gauss hypergeometric function
        (:func:`scipy.special.hyp2f1`); ``c > b > 0``, ``a > 0``.
    theta_end : float
        Final tangent angle in radians (> 0). The curve starts at
        ``psi = 0`` (origin, ``theta = 0``, ``rho = 1``).
    num : int
        Number of points, **equally spaced in tangent angle** (not in arc
        length) over ``[0, theta_end]``; 2 to
        :data:`attneave.stimuli.curves.natural.MAX_POINTS` (1e7).
    epsabs, epsrel : float
        Tolerances of :func:`scipy.integrate.quad_vec` (adaptive 21-point
        Gauss-Kronrod): finite, >= 0, not both 0.

    Returns
    -------
    Curve
        y-UP coordinates; ``s`` is the arc length from the start (computed),
        ``curvature = 1/rho(theta)``; ``params`` include ``a, b, c,
        theta_end, num, method, quad_error``.

    Raises
    ------
    InputError
        Parameters outside ``c > b > 0, a > 0`` or ``theta_end <= 0``, or
        bad `num`, `epsabs`, `epsrel`.

    Notes
    -----
    Each interval between consecutive output angles is integrated on its
    own (all intervals in one vectorised adaptive Gauss-Kronrod call) and
    the pieces are summed, so the cost does not grow with the winding.
    """
    from scipy.integrate import quad_vec

    a = as_number(a, "a")
    b = as_number(b, "b")
    c = as_number(c, "c")
    theta_end = as_number(theta_end, "theta_end")
    if not (c > b > 0 and a > 0):
        raise InputError(f"superspiral: need c > b > 0 and a > 0, got a={a:g}, b={b:g}, c={c:g}")
    if not theta_end > 0:
        raise InputError(f"superspiral: theta_end must be > 0, got {theta_end:g}")
    num = check_count(num, "num (points)")
    epsabs = check_tolerance(epsabs, "epsabs", allow_zero=True)
    epsrel = check_tolerance(epsrel, "epsrel", allow_zero=True)
    if epsabs == 0 and epsrel == 0:
        raise InputError("epsabs, epsrel: at least one tolerance must be > 0")
    psi = np.linspace(0.0, theta_end, num)
    left = psi[:-1]
    h = np.diff(psi)
    f21, evaluator = _choose_hyp2f1(a, b, c, theta_end, num)

    def integrand(t):
        p = left + t * h
        r = f21(p) * h
        return np.concatenate([r, r * np.cos(p), r * np.sin(p)])

    parts, err = quad_vec(integrand, 0.0, 1.0, epsabs=epsabs, epsrel=epsrel, norm="max")
    m = num - 1
    cum = np.concatenate([np.zeros((3, 1)), np.cumsum(parts.reshape(3, m), axis=1)], axis=1)
    s_arc, x, y = cum
    rho = f21(psi)
    if not (np.all(np.isfinite(cum)) and np.all(np.isfinite(rho)) and np.all(rho > 0)):
        raise InputError(
            f"superspiral: 2F1({a:g}, {b:g}; {c:g}; -psi) could not be evaluated on [0, {theta_end:g}]"
        )
    params = dict(
        a=a,
        b=b,
        c=c,
        theta_end=theta_end,
        num=num,
        s_start=0.0,
        s_end=float(s_arc[-1]),
        method="quad_vec (Gauss-Kronrod 21)",
        epsabs=epsabs,
        epsrel=epsrel,
        quad_error=float(err),
        sampling="equal tangent angle",
        hyp2f1=evaluator,
    )
    return Curve("superspiral", s_arc, x, y, psi, 1.0 / rho, params)


#: Points the double-precision 2F1 is checked at, and the largest relative
#: disagreement with the positive series accepted.
_CHECK_POINTS = 9
_CHECK_RTOL = 1e-10
#: Largest tangent angle the series serves (it needs about 40 (1 + psi) terms).
_SERIES_MAX_PSI = 100.0


def _series(a, b, c, psi):
    """``2F1(a, b; c; -psi)`` for psi >= 0 through Pfaff's transformation,
    ``(1 + psi)**-a 2F1(a, c - b; c; w)``, ``w = psi / (1 + psi)`` in [0, 1):
    with a > 0 and c > b > 0 every term is positive, so the sum has no
    cancellation, and ``(c - b)/c`` is formed once (finite however small b
    and c are)."""
    psi = np.asarray(psi, dtype=float)
    w = psi / (1.0 + psi)
    term = np.ones_like(w)
    total = np.ones_like(w)
    k = 0
    while True:
        term = term * ((a + k) * ((c - b + k) / (c + k)) / (k + 1)) * w
        total = total + term
        k += 1
        # the coefficient ratio tends to 1 (as 1 + (a - b - 1)/k), so once
        # q = max(ratio, 1) w < 1 the tail is at most about term q/(1 - q)
        q = max((a + k) * (c - b + k) / ((c + k) * (k + 1)), 1.0) * w
        if np.all(q < 1.0) and np.all(term * q / (1.0 - q) <= 1e-17 * total):
            break
        if k > 100_000:
            raise InputError(f"superspiral: the 2F1 series for a={a:g}, b={b:g}, c={c:g} does not converge")
    return total * np.exp(-a * np.log1p(psi))


def _choose_hyp2f1(a, b, c, theta_end, num):
    """The 2F1 evaluator for ``rho(psi)``: scipy's, unless it disagrees with
    the positive series :func:`_series` at a few angles in ``[0, theta_end]``.

    scipy's :func:`~scipy.special.hyp2f1` is silently wrong for tiny b and
    c (measured: 2F1(1, 1e-20; 2e-20; -0.5) = 1.0 instead of 5/6, inf at
    z = -3.14) and loses digits for z < -1 with tiny a (1e-9 relative at
    a = 1e-8); mpmath takes seconds a value there. The series is then used
    for every value, up to ``theta_end`` = :data:`_SERIES_MAX_PSI`.

    Returns
    -------
    (callable, str)
        ``f(psi)`` on arrays of psi >= 0, and the name recorded in
        ``params['hyp2f1']``.
    """
    from scipy.special import hyp2f1

    psi = np.linspace(0.0, min(theta_end, _SERIES_MAX_PSI), _CHECK_POINTS)
    with np.errstate(all="ignore"):
        fast = hyp2f1(a, b, c, -psi)
        exact = _series(a, b, c, psi)
        err = np.abs(fast - exact) / exact
    if np.all(np.isfinite(fast)) and np.all(err <= _CHECK_RTOL):
        return (lambda p: hyp2f1(a, b, c, -p)), "scipy"
    if theta_end > _SERIES_MAX_PSI:
        worst = int(np.nanargmax(np.where(np.isfinite(err), err, np.inf)))
        raise InputError(
            f"superspiral: scipy's 2F1({a:g}, {b:g}; {c:g}; -psi) is inaccurate for these parameters "
            f"({float(fast[worst]):.10g} instead of {float(exact[worst]):.10g} at psi={float(psi[worst]):g}) "
            f"and the exact series serves theta_end <= {_SERIES_MAX_PSI:g} only"
        )
    return (lambda p: _series(a, b, c, p)), "series (Pfaff)"
