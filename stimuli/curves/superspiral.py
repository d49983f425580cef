"""Superspirals (the seed paper's eq. 10; Ziatdinov 2012): curves whose
radius of curvature, as a function of the tangent angle, is a completely
monotonic Gauss hypergeometric function. y-UP coordinates, as in
:mod:`stimuli.curves.natural`.

References
----------
.. [1] Ziatdinov, R. (2012). Family of superspirals with completely monotonic
       curvature given in terms of Gauss hypergeometric function. Computer
       Aided Geometric Design 29(7), 510-518.
"""

from __future__ import annotations

import numpy as np

from stimuli.curves.natural import Curve
from stimuli.errors import InputError
from stimuli.validate import as_number

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
        length) over ``[0, theta_end]``.
    epsabs, epsrel : float
        Tolerances of :func:`scipy.integrate.quad_vec` (adaptive 21-point
        Gauss-Kronrod).

    Returns
    -------
    Curve
        y-UP coordinates; ``s`` is the arc length from the start (computed),
        ``curvature = 1/rho(theta)``; ``params`` include ``a, b, c,
        theta_end, num, method, quad_error``.

    Raises
    ------
    InputError
        Parameters outside ``c > b > 0, a > 0`` or ``theta_end <= 0``.

    Notes
    -----
    Each interval between consecutive output angles is integrated on its
    own (all intervals in one vectorised adaptive Gauss-Kronrod call) and
    the pieces are summed, so the cost does not grow with the winding.
    """
    from scipy.integrate import quad_vec
    from scipy.special import hyp2f1

    a = as_number(a, "a")
    b = as_number(b, "b")
    c = as_number(c, "c")
    theta_end = as_number(theta_end, "theta_end")
    if not (c > b > 0 and a > 0):
        raise InputError(f"superspiral: need c > b > 0 and a > 0, got a={a:g}, b={b:g}, c={c:g}")
    if not theta_end > 0:
        raise InputError(f"superspiral: theta_end must be > 0, got {theta_end:g}")
    if isinstance(num, bool) or not float(num).is_integer() or num < 2:
        raise InputError(f"num (points) must be an integer >= 2, got {num!r}")
    num = int(num)
    psi = np.linspace(0.0, theta_end, num)
    left = psi[:-1]
    h = np.diff(psi)

    def integrand(t):
        p = left + t * h
        r = hyp2f1(a, b, c, -p) * h
        return np.concatenate([r, r * np.cos(p), r * np.sin(p)])

    parts, err = quad_vec(integrand, 0.0, 1.0, epsabs=epsabs, epsrel=epsrel, norm="max")
    m = num - 1
    cum = np.concatenate([np.zeros((3, 1)), np.cumsum(parts.reshape(3, m), axis=1)], axis=1)
    s_arc, x, y = cum
    rho = hyp2f1(a, b, c, -psi)
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
    )
    return Curve("superspiral", s_arc, x, y, psi, 1.0 / rho, params)
