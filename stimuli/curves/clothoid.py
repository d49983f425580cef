"""The clothoid (Euler or Cornu spiral), ``kappa = k0 + c*s``, a family of
:mod:`attneave.stimuli.curves.natural` in closed form (Fresnel integrals).

y-UP coordinates, as every curve of :mod:`attneave.stimuli.curves.natural`.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.checks import MAX_RATE, arc_grid
from attneave.stimuli.curves.natural import EPS, Curve, integrate_natural, relabel
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["clothoid"]


def clothoid(k0=0.0, c=1.0, s_start=0.0, s_end=1.0, num=201, *, s=None):
    """Clothoid (Euler/Cornu spiral) with curvature ``kappa = k0 + c*s``.

    Parameters
    ----------
    k0 : float
        Curvature at ``s = 0``.
    c : float
        Rate of change of curvature (any sign; 0 gives a circle of radius
        ``1/|k0|``, or a line when ``k0 = 0``).
    s_start, s_end, num, s
        Output arc lengths, see :func:`integrate_natural`.

    Returns
    -------
    Curve
        y-UP coordinates, starting at the origin with ``theta = 0`` at
        ``s_start``. ``params['method']`` is ``'fresnel'``, ``'circle'`` or,
        when ``|c|`` is so small beside ``k0`` that the Fresnel arguments
        lose precision, ``'DOP853'`` (the integrator with the exact tangent
        angle).

    Notes
    -----
    Evaluated by :func:`attneave.stimuli.curves.euler.clothoid_points` (the one
    clothoid evaluator of the package): the generalised Fresnel integral
    ``int_0^d exp(i (k(s0) u + c u**2 / 2)) du`` through the Fresnel
    integrals :func:`scipy.special.fresnel` after completing the square, or
    power series where those lose precision.

    Examples
    --------
    >>> cl = clothoid(k0=0, c=np.pi, s_start=0, s_end=1, num=3)  # t = s
    >>> from scipy.special import fresnel
    >>> S, C = fresnel(1.0)
    >>> bool(np.allclose(cl.points[-1], (C, S)))
    True
    """
    from attneave.stimuli.curves.euler import clothoid_points

    k0 = as_number(k0, "k0", ge=-MAX_RATE, le=MAX_RATE)
    c = as_number(c, "c", ge=-MAX_RATE, le=MAX_RATE)
    grid = arc_grid(s_start, s_end, num, s)
    s0 = grid[0]
    theta = k0 * (grid - s0) + 0.5 * c * (grid - s0) * (grid + s0)
    kappa = k0 + c * grid
    base = dict(k0=k0, c=c, s_start=float(s0), s_end=float(grid[-1]), num=len(grid))

    if c == 0.0:
        d = grid - s0
        # (exp(i k0 d) - 1)/(i k0) written with sinc so that k0 -> 0 is a line
        z = d * np.sinc(k0 * d / (2 * np.pi)) * np.exp(0.5j * k0 * d)
        return Curve("clothoid", grid, z.real, z.imag, theta, kappa, {**base, "method": "circle"})

    v = grid + k0 / c
    scale = np.sqrt(abs(c) / np.pi)
    t = v * scale
    # Rounding of t (relative eps) is amplified by sqrt(pi/|c|) and by the
    # phase pi*t0**2/2; this estimate is ~100x pessimistic (measured).
    with np.errstate(over="ignore"):  # an overflowing estimate is inf: the integrator takes over
        err = EPS * np.max(t * t) * np.sqrt(np.pi / abs(c))
    if err > 1e-10 * max(1.0, grid[-1] - s0):
        curve = integrate_natural(
            lambda u: k0 + c * u, s=grid, theta_fn=lambda u: k0 * (u - s0) + 0.5 * c * (u - s0) * (u + s0)
        )
        return relabel(curve, "clothoid", k0=k0, c=c)

    # one clothoid evaluator for the whole package: the segments' own
    # (Fresnel integrals, or their series where those lose precision)
    x, y, _, _ = clothoid_points(0.0, 0.0, 0.0, k0 + c * s0, c, grid - s0)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        # the compiled evaluator gives up (NaN) on a clothoid turning by more than about 8000 rad
        # (never a spline's segment); the numpy evaluator's Fresnel closed form has no such bound
        x, y, _, _ = clothoid_points(0.0, 0.0, 0.0, k0 + c * s0, c, grid - s0, compiled=False)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(np.isfinite(theta))):
        raise InputError(
            f"clothoid: the points overflow for k0={k0:g}, c={c:g} on [{s0:g}, {grid[-1]:g}]; "
            "use smaller |k0|, |c| or a shorter interval"
        )
    return Curve("clothoid", grid, x, y, theta, kappa, {**base, "method": "fresnel"})
