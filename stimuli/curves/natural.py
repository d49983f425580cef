"""Plane curves from their natural equations (curvature as a function of arc length).

The result of every family of the seed paper (Ziatdinov, sections 2.2 and 3),
:class:`Curve`, and a generic integrator for any natural equation
``kappa(s)``. The families, each in its own module and all available from
:mod:`attneave.stimuli.curves`: clothoids (:mod:`~attneave.stimuli.curves.clothoid`),
pseudospirals (eq. 8, :mod:`~attneave.stimuli.curves.pseudospiral`), log-aesthetic
curves (eq. 9, :mod:`~attneave.stimuli.curves.lac.aesthetic`), superspirals (eq. 10,
:mod:`~attneave.stimuli.curves.superspiral`) and the constant-information curves of
eq. 7 (:mod:`~attneave.stimuli.curves.constant_info`).

Coordinates
-----------
Every curve here is in **y-UP mathematical coordinates**: x to the right, y
up, angles counter-clockwise from +x, and positive curvature turns left
(counter-clockwise). This is *not* the image convention of the rest of
:mod:`stimuli` (y down). To draw a curve in an image so that it looks the
same as in a y-up plot, use ``(x, -y)`` (then add an offset): the picture is
unchanged, and a left turn in the plot is a left turn on the screen.

Every curve starts at the origin with tangent angle ``theta = 0`` (along +x)
at its first arc length ``s_start``; ``theta(s) = integral of kappa from
s_start to s``. ``s`` itself is the natural parameter of the equation, so a
curve that starts at ``s_start = 2`` has curvature ``kappa(2)`` at the origin.

Accuracy
--------
Clothoids use Fresnel integrals in closed form. Superspirals use adaptive
Gauss-Kronrod quadrature (:func:`scipy.integrate.quad_vec`, 21-point rule).
Log-aesthetic curves (:mod:`attneave.stimuli.curves.lac.aesthetic`) are in closed form
through the incomplete gamma function. Superspirals and the
constant-information curves live in :mod:`attneave.stimuli.curves.superspiral` and
:mod:`attneave.stimuli.curves.constant_info`. The other families use :func:`integrate_natural`, an explicit Runge-Kutta
method of order 8 (DOP853, :func:`scipy.integrate.solve_ivp`) on
``(theta, x, y)`` with ``rtol = 1e-13`` and ``atol = 1e-13 * length``. With
these defaults the positions agree with closed forms (Fresnel integrals,
sine/cosine integrals, the involute and the logarithmic spiral) to about
``1e-12 * length``; the tests assert 1e-9.

References
----------
.. [1] Ziatdinov, R. Visual perception, quantity of information function and
       the concept of the quantity of information continuous splines.
       Eq. 7-10.
.. [2] Savelov, A. A. (1960). Plane curves: systematics, properties,
       applications. (Pseudospirals.)
.. [3] Yoshida, N., & Saito, T. (2006). Interactive aesthetic curve segments.
       The Visual Computer 22, 896-905. (Log-aesthetic curves.)
.. [4] Ziatdinov, R. (2012). Family of superspirals with completely monotonic
       curvature given in terms of Gauss hypergeometric function. Computer
       Aided Geometric Design 29(7), 510-518.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.curves.checks import (  # noqa: F401  (re-exported: the limits of the families, documented here)
    MAX_ARC,
    MAX_POINTS,
    MAX_RATE,
    arc_grid,
    check_count,
    check_flag,
    check_samples,
    check_tolerance,
)
from attneave.stimuli.errors import InputError

__all__ = [
    "Curve",
    "FAMILIES",
    "RTOL",
    "arc_grid",
    "relabel",
    "integrate_natural",
    "EPS",
    "MAX_POINTS",
]

FAMILIES = ("clothoid", "pseudospiral", "lac", "superspiral", "constant-info")

RTOL = 1e-13
EPS = np.finfo(float).eps


@dataclass(frozen=True)
class Curve:
    """A sampled plane curve with its natural parametrisation.

    All arrays have the same length. Coordinates are y-UP (mathematical),
    see the module docstring.

    Attributes
    ----------
    family : str
        Which construction made it (``'clothoid'``, ``'natural'``, ...).
    s : ndarray
        Arc length (the natural parameter of the family's equation).
    x, y : ndarray
        Position, y up; ``(x[0], y[0]) = (0, 0)``.
    theta : ndarray
        Tangent angle in radians, counter-clockwise from +x; ``theta[0] = 0``.
    curvature : ndarray
        Signed curvature ``d theta / d s`` (positive turns left).
    params : dict
        Every resolved parameter (family parameters, ``s_start``, ``s_end``,
        ``num``, the method and its tolerances).
    """

    family: str
    s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    curvature: np.ndarray
    params: dict = field(default_factory=dict)

    def __post_init__(self):
        for name in ("s", "x", "y", "theta", "curvature"):
            arr = np.array(getattr(self, name), dtype=float)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    def __len__(self):
        return len(self.s)

    @property
    def points(self):
        """``(N, 2)`` array of ``(x, y)`` in y-UP coordinates."""
        return np.column_stack([self.x, self.y])

    def table(self):
        """Columns ``s, x, y, theta, curvature`` as a dict (for :func:`attneave.stimuli.tables.write_table`)."""
        return {k: np.asarray(getattr(self, k)) for k in ("s", "x", "y", "theta", "curvature")}


# --------------------------------------------------------------------------- helpers




_MAX_NFEV = 1_000_000  # about 50,000 rad of turning, ~10 s


class _TooManyEvaluations(Exception):
    pass


def _check_turning(curvature_fn, s0, s1):
    """Refuse at once a curve whose tangent turns by more than ``_MAX_NFEV / 10`` rad.

    The turning is ``int |kappa| ds``, estimated by the trapezoid rule on
    4097 arc lengths spaced evenly and, when the interval starts above 0,
    4097 more spaced geometrically (a curvature like ``1/s`` near a small
    ``s_start`` lives there). The integrator takes 15 to 25 evaluations per
    radian (measured), so such a curve would only run into its budget after
    seconds of work (13 s for eq. 7 with n = 1e300).
    """
    u = np.linspace(s0, s1, 4097)
    if s0 > 0:
        u = np.union1d(u, np.geomspace(s0, s1, 4097))
    with np.errstate(all="ignore"):
        try:
            k = np.abs(np.broadcast_to(np.asarray(curvature_fn(u), dtype=float), u.shape))
        except (TypeError, ValueError):
            return  # the integrator names the problem
        turn = float(np.sum(0.5 * (k[1:] + k[:-1]) * np.diff(u)))
    if turn > _MAX_NFEV / 10:  # inf included
        raise InputError(
            f"the curve turns by about {turn:.3g} rad on [{s0:g}, {s1:g}]; integrating it needs more than "
            f"{_MAX_NFEV:.0e} steps (about 20 per radian); shorten the interval"
        )


def integrate_natural(
    curvature_fn,
    s_start=None,
    s_end=None,
    num=201,
    *,
    s=None,
    theta_fn=None,
    rtol=RTOL,
    atol=None,
    max_step=None,
):
    """Integrate a natural equation ``kappa(s)`` into a plane curve.

    Solves ``theta' = kappa(s)``, ``x' = cos(theta)``, ``y' = sin(theta)``
    from ``(theta, x, y) = (0, 0, 0)`` at ``s_start`` with the explicit
    Runge-Kutta method of order 8 (DOP853) and reads the solution at the
    requested arc lengths.

    Parameters
    ----------
    curvature_fn : callable
        ``kappa(s)``; must accept a float and a 1-D array of arc lengths and
        return finite values over ``[s_start, s_end]``.
    s_start, s_end : float
        Arc-length interval (``s_end > s_start``). Ignored when `s` is given.
    num : int
        Number of equally spaced output points (>= 2).
    s : array_like, optional
        Strictly increasing output arc lengths instead of `s_start`, `s_end`,
        `num`; the curve starts at ``s[0]``.
    theta_fn : callable, optional
        Closed-form tangent angle ``theta(s)`` with ``theta(s[0]) = 0``. When
        given only ``(x, y)`` are integrated and ``theta`` is exact.
    rtol : float
        Relative tolerance of the integrator (default 1e-13; the smallest
        SciPy accepts is about 2.2e-14).
    atol : float, optional
        Absolute tolerance (default ``rtol * (s_end - s_start)``, so that
        the tolerance scales with the size of the curve).
    max_step : float, optional
        Largest step (default ``(s_end - s_start) / 64``, so that a narrow
        curvature feature cannot be stepped over).

    Returns
    -------
    Curve
        ``family='natural'``, y-UP coordinates, with ``params`` holding
        ``s_start, s_end, num, method, rtol, atol, max_step, nfev``.

    Raises
    ------
    InputError
        If the interval is empty, the curvature is not finite, or the
        integration fails or would need more than 1e6 evaluations (about
        50,000 rad of turning).

    Notes
    -----
    Accuracy, verified in ``tests/test_curves.py`` (1e-9 asserted) and
    measured when writing this module: with the default tolerances the
    positions of ``kappa = pi*s`` agree with the Fresnel integrals to
    2.4e-13 over s in [0, 5] (39 rad of turning), 4.8e-13 over [0, 10] and
    9.2e-13 over [0, 20] (628 rad); the tangent angle of eq. 7 curves
    (C = +-0.03, s from the domain edge to 5) agrees with adaptive
    quadrature of ``kappa`` to 2.6e-12, despite the square-root
    singularity of ``d kappa / d s`` at the edge of the domain.

    Examples
    --------
    >>> c = integrate_natural(lambda s: 0.5 + 0 * s, 0.0, 2 * np.pi / 0.5, num=5)
    >>> bool(np.allclose(c.points[-1], (0, 0), atol=1e-10))  # a full circle closes
    True
    """
    from scipy.integrate import solve_ivp

    if not callable(curvature_fn):
        raise InputError(f"curvature_fn: must be a callable kappa(s), got {type(curvature_fn).__name__}")
    if theta_fn is not None and not callable(theta_fn):
        raise InputError(f"theta_fn: must be a callable theta(s) or None, got {type(theta_fn).__name__}")
    grid = arc_grid(s_start, s_end, num, s)
    s0, s1 = float(grid[0]), float(grid[-1])
    length = s1 - s0
    # SciPy raises its own ValueError (or spins to the step budget) on these
    rtol = check_tolerance(rtol, "rtol")
    atol = rtol * length if atol is None else check_tolerance(atol, "atol")
    max_step = length / 64 if max_step is None else check_tolerance(max_step, "max_step")

    with np.errstate(all="ignore"):  # non-finite values are reported below
        try:
            kappa = np.asarray(curvature_fn(grid), dtype=float)
            if kappa.shape != grid.shape:
                kappa = np.broadcast_to(kappa, grid.shape).astype(float)
        except (TypeError, ValueError):
            raise InputError(
                f"curvature_fn: must return one finite number per arc length (an array of shape "
                f"{grid.shape} or a scalar)"
            ) from None
    if not np.all(np.isfinite(kappa)):
        bad = grid[~np.isfinite(kappa)][0]
        raise InputError(f"curvature is not finite at s={bad:g}")
    if theta_fn is not None:
        with np.errstate(all="ignore"):
            theta = np.asarray(theta_fn(grid), dtype=float)
        if theta.shape != grid.shape or not np.all(np.isfinite(theta)):
            raise InputError(f"the tangent angle is not finite on [{s0:g}, {s1:g}] (it overflows)")
        # the tangent's total change is at least its change between the output points; at 15 to
        # 25 evaluations per radian (measured), more than _MAX_NFEV / 10 radians would only run
        # into the budget below after seconds of work: say so at once
        turn = float(np.sum(np.abs(np.diff(theta))))
        if turn > _MAX_NFEV / 10:
            raise InputError(
                f"the curve turns by {turn:.3g} rad on [{s0:g}, {s1:g}]; integrating it needs more than "
                f"{_MAX_NFEV:.0e} steps (about 20 per radian); shorten the interval"
            )

    else:
        _check_turning(curvature_fn, s0, s1)

    calls = [0]

    def budget():
        # solve_ivp has no evaluation limit; a curve that winds ~1e5 times would run for hours
        calls[0] += 1
        if calls[0] > _MAX_NFEV:
            raise _TooManyEvaluations

    if theta_fn is None:

        def rhs(t, y):
            budget()
            return np.array([float(curvature_fn(t)), np.cos(y[0]), np.sin(y[0])])

        y0 = [0.0, 0.0, 0.0]
    else:

        def rhs(t, y):
            budget()
            th = float(theta_fn(t))
            return np.array([np.cos(th), np.sin(th)])

        y0 = [0.0, 0.0]

    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(
                rhs, (s0, s1), y0, method="DOP853", t_eval=grid, rtol=rtol, atol=atol, max_step=max_step
            )
    except _TooManyEvaluations:
        raise InputError(
            f"integration of the natural equation on [{s0:g}, {s1:g}] needs more than {_MAX_NFEV:.0e} "
            "steps: the curve turns too often (about 20 steps per radian); shorten the interval"
        ) from None
    if not sol.success or sol.y.shape[1] != len(grid) or not np.all(np.isfinite(sol.y)):
        raise InputError(f"integration of the natural equation failed on [{s0:g}, {s1:g}]: {sol.message}")
    if theta_fn is None:
        theta, x, y = sol.y
    else:
        x, y = sol.y
    params = dict(
        s_start=s0,
        s_end=s1,
        num=len(grid),
        method="DOP853",
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        nfev=int(sol.nfev),
        theta="closed form" if theta_fn is not None else "integrated",
    )
    return Curve("natural", grid, x, y, theta, kappa, params)


def relabel(curve, family, **params):
    """Re-label an integrated curve and prepend the family's parameters."""
    return Curve(family, curve.s, curve.x, curve.y, curve.theta, curve.curvature, {**params, **curve.params})
