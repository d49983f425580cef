"""Pseudospirals (eq. 8 of the seed paper; Savelov 1960), ``rho = a*s^m``, a
family of :mod:`attneave.stimuli.curves.natural` integrated by
:func:`~attneave.stimuli.curves.natural.integrate_natural`.

y-UP coordinates, as every curve of :mod:`attneave.stimuli.curves.natural`.

References
----------
.. [1] Savelov, A. A. (1960). Plane curves: systematics, properties,
       applications.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.checks import arc_grid
from attneave.stimuli.curves.natural import RTOL, integrate_natural, relabel
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["pseudospiral"]


def pseudospiral(a=1.0, m=1.0, s_start=1.0, s_end=2.0, num=201, *, s=None, rtol=RTOL):
    """Pseudospiral with radius of curvature ``rho = a * s**m`` (paper eq. 8).

    ``m = 1`` is a logarithmic spiral (``rho`` proportional to the arc
    length from its pole), ``m = -1`` the Cornu spiral (clothoid through
    its inflection), ``m = 1/2`` an involute of a circle (see Notes),
    ``m = 0`` a circle of radius ``|a|``.

    Parameters
    ----------
    a : float
        Scale, nonzero; ``a < 0`` turns right (negative curvature).
    m : float
        Exponent.
    s_start, s_end, num, s
        Output arc lengths. Need ``s >= 0`` (``s**m`` is not real for
        ``s < 0``), and ``s > 0`` when ``m > 0`` (``rho = 0``, infinite
        curvature, at ``s = 0``).
    rtol : float
        Tolerance of :func:`integrate_natural`.

    Returns
    -------
    Curve
        y-UP coordinates, from the origin with ``theta = 0`` at ``s_start``;
        curvature ``s**(-m) / a``; the tangent angle is in closed form
        (``(s**(1-m) - s0**(1-m)) / (a (1-m))``, or ``ln(s/s0)/a`` for m = 1).

    Raises
    ------
    InputError
        ``a == 0`` or arc lengths outside the domain.

    Notes
    -----
    The paper writes ``d theta / d s = rho``; the curvature is
    ``d theta / d s = 1/rho``, which is what is integrated here. For
    ``m = 1/2``, ``rho = a sqrt(s)`` is the involute of a circle of radius
    ``R = a**2 / 2`` (``rho**2 = 2 R s``), unwound from the circle at s = 0.
    """
    a = as_number(a, "a")
    m = as_number(m, "m")
    if a == 0:
        raise InputError("pseudospiral: a must be nonzero (rho = a*s^m)")
    grid = arc_grid(s_start, s_end, num, s)
    s0 = float(grid[0])
    if s0 < 0 or (m > 0 and s0 <= 0):
        need = "s > 0" if m > 0 else "s >= 0"
        raise InputError(f"pseudospiral: s_start={s0:g} is outside the domain; rho = a*s^m with m={m:g} needs {need}")

    def kappa(u):
        return np.power(u, -m) / a

    if m == 1:

        def theta(u):
            return np.log(np.asarray(u) / s0) / a

    elif s0 > 0:
        p = 1.0 - m
        # (u**p - s0**p) / (a p) cancels when p = 1 - m is small (m near 1: every
        # digit is lost below p ~ 1e-16 and the integrator stalls on the noise);
        # s0**p expm1(p ln(u/s0)) / (a p) is the same, exact to rounding, and
        # tends to the m = 1 form ln(u/s0)/a as p -> 0
        with np.errstate(over="ignore"):  # an overflow (inf) is refused by integrate_natural
            front = np.float64(s0) ** p / (a * p)

        def theta(u):
            return front * np.expm1(p * np.log(np.asarray(u) / s0))

    else:  # s0 = 0 (m < 0 here, p > 1): no cancellation
        p = 1.0 - m

        def theta(u):
            return np.power(u, p) / (a * p)

    curve = integrate_natural(kappa, s=grid, theta_fn=theta, rtol=rtol)
    return relabel(curve, "pseudospiral", a=a, m=m)
