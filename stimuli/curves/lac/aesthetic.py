"""Log-aesthetic curves (the seed paper's eq. 9) in closed form, and the
generalised log-aesthetic curves (GLAC) with their extra parameter nu.

y-UP coordinates, as in :mod:`attneave.stimuli.curves.natural`: every curve starts at
the origin with ``theta = 0`` at its first arc length.

References
----------
.. [1] N. Yoshida and T. Saito, "Interactive aesthetic curve segments",
       The Visual Computer 22, 896-905, 2006.
.. [2] R. Ziatdinov, N. Yoshida and T. Kim, "Analytic parametric equations
       of log-aesthetic curves in terms of incomplete gamma functions",
       CAGD 29(2), 129-140, 2012.
.. [3] R. U. Gobithaasan and K. T. Miura, "Aesthetic spiral for design",
       Sains Malaysiana 40(11), 1301-1305, 2011; R. U. Gobithaasan,
       R. Karpagavalli and K. T. Miura, "Drawable region of the generalized
       log aesthetic curves", J. Applied Mathematics 2013, 732457.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.lac.gamma import lac_position, lac_theta, log_rho
from attneave.stimuli.curves.natural import RTOL, Curve, arc_grid, integrate_natural, relabel
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["log_aesthetic", "lac_curvature", "glac", "glac_curvature"]


def _check_domain(alpha, lam, s0, s1):
    if alpha == 0 or lam == 0:
        return
    ends = 1 + lam * alpha * np.array([s0, s1])
    if np.all(ends > 0) or (alpha < 0 and np.all(ends >= 0)):
        return
    bound = -1 / (lam * alpha)
    side = "s > " if lam * alpha > 0 else "s < "
    raise InputError(
        f"lac: [s_start, s_end] = [{s0:g}, {s1:g}] leaves the domain of eq. 9; "
        f"need lam*alpha*s + 1 > 0, i.e. {side}{bound:g} for alpha={alpha:g}, lam={lam:g}"
    )


#: ln of the largest float64: a radius of curvature below exp(-LOG_MAX) has a
#: curvature that float64 cannot hold.
LOG_MAX = float(np.log(np.finfo(float).max))


def _check_overflow(alpha, lam, grid):
    """The curvature ``1/rho`` must be a float64 on the grid: ``ln rho >= -LOG_MAX``.

    With ``rho = exp(lam s)`` (alpha = 0) the curve winds into its pole ever
    faster; past ``lam s = -709.78`` its curvature (and tangent angle) are
    beyond float64, so the curve cannot be tabulated there."""
    with np.errstate(all="ignore"):
        lr = log_rho(grid, alpha, lam)
    bad = ~(lr >= -LOG_MAX)
    if not bad.any():
        return
    j = int(np.flatnonzero(bad)[0])
    s_bad = float(grid[j])
    if alpha == 0:
        s_far = float(grid[-1] if lam < 0 else grid[0])
        bound = -LOG_MAX / s_far
        side = ">=" if s_far > 0 else "<="
        raise InputError(
            f"lam: the curvature exp(-lam*s) of the LAC (alpha=0) overflows float64 at s={s_bad:g} "
            f"(lam*s = {lam * s_bad:.6g}); need lam*s >= -{LOG_MAX:.6g} on [s_start, s_end], "
            f"i.e. lam {side} {bound:.6g} for this interval, got lam={lam:g}"
        )
    raise InputError(
        f"lam: the curvature (lam*alpha*s + 1)**(-1/alpha) of the LAC overflows float64 at s={s_bad:g} "
        f"for alpha={alpha:g}, lam={lam:g} (ln rho = {float(lr[j]):.6g}; need >= -{LOG_MAX:.6g}); "
        f"use a smaller |lam| or keep the interval further from the domain end "
        f"s = {-1 / (lam * alpha):g}"
    )


def lac_curvature(s, alpha, lam):
    """Curvature ``1/rho`` of the eq. 9 LAC: ``exp(-lam s)`` (alpha = 0),
    ``(lam alpha s + 1)**(-1/alpha)`` otherwise (0 where the base is 0).

    Parameters
    ----------
    s : array_like
        Arc lengths.
    alpha, lam : float
        Shape parameter and rate of eq. 9.

    Returns
    -------
    ndarray
        Curvature at `s` (inf where it overflows; :func:`log_aesthetic`
        refuses such intervals).

    Examples
    --------
    >>> float(lac_curvature(1.0, -1.0, 0.5))   # clothoid: 1 - lam s
    0.5
    """
    s = np.asarray(s, dtype=float)
    if alpha == 0 or lam == 0:
        return np.exp(-lam * s)
    with np.errstate(divide="ignore"):
        return np.exp(-np.log1p(lam * alpha * s) / alpha)


def log_aesthetic(alpha=0.0, lam=1.0, s_start=0.0, s_end=1.0, num=201, *, s=None):
    """Log-aesthetic curve (LAC) of the paper's eq. 9, in closed form.

    ``rho(s) = exp(lam*s)`` for ``alpha = 0`` and
    ``rho(s) = (lam*alpha*s + 1)**(1/alpha)`` otherwise, so ``rho(0) = 1``.

    Special cases (checked in the tests against their own closed forms):
    ``alpha = -1`` a clothoid (``kappa = 1 - lam*s``), ``alpha = 0``
    Nielsen's spiral (``kappa = exp(-lam*s)``), ``alpha = 1`` a logarithmic
    spiral (``rho = lam*s + 1``), ``alpha = 2`` an involute of a circle
    (``rho**2 = 2*lam*s + 1``, circle of radius ``lam``); ``lam = 0`` is
    the unit circle.

    Parameters
    ----------
    alpha : float
        Shape parameter, any real.
    lam : float
        Rate (the paper's lambda).
    s_start, s_end, num, s
        Output arc lengths (may be negative), see
        :func:`attneave.stimuli.curves.natural.integrate_natural`. Need
        ``lam*alpha*s + 1 > 0`` on the whole interval (``>= 0`` at an end
        when ``alpha < 0``, where the curvature tends to 0).

    Returns
    -------
    Curve
        y-UP coordinates from the origin with ``theta = 0`` at ``s_start``;
        ``params`` include ``alpha, lam`` and ``method='incomplete gamma'``.

    Raises
    ------
    InputError
        If the interval leaves the domain, or where the curve's curvature
        or tangent angle overflows float64: for alpha = 0 the curvature is
        ``exp(-lam*s)``, so ``lam*s`` must stay >= -709.78 on the interval
        (e.g. ``lam >= -709.78`` for s in [0, 1]); large positive ``lam*s``
        is fine (the curve straightens out).

    Notes
    -----
    Positions from :func:`attneave.stimuli.curves.lac.gamma.lac_position`:
    Gauss-Legendre quadrature of the closed-form tangent angle, exact to
    rounding and checked against the incomplete-gamma closed form of
    Ziatdinov, Yoshida & Kim 2012 (which it falls back to for curves that
    wind thousands of times); tangent angle and curvature in closed form.

    Examples
    --------
    >>> cv = log_aesthetic(2.0, 0.5, 0.0, 1.0, num=3)   # an involute of a circle
    >>> bool(np.allclose(cv.curvature, 1 / np.sqrt(2 * 0.5 * cv.s + 1)))
    True
    """
    alpha = as_number(alpha, "alpha")
    lam = as_number(lam, "lam")
    grid = arc_grid(s_start, s_end, num, s)
    s0, s1 = float(grid[0]), float(grid[-1])
    _check_domain(alpha, lam, s0, s1)
    _check_overflow(alpha, lam, grid)
    with np.errstate(all="ignore"):  # an overflow is refused below, in one line
        th = lac_theta(grid, alpha, lam)
        z = lac_position(grid, alpha, lam)
        # from the first arc length, turned so that the tangent there is +x
        z = (z - z[0]) * np.exp(-1j * th[0])
        theta = th - th[0]
        kappa = lac_curvature(grid, alpha, lam)
    if not all(np.all(np.isfinite(v)) for v in (z, theta, kappa)):
        raise InputError(
            f"lam: the LAC's tangent angle or position overflows float64 for alpha={alpha:g}, lam={lam:g} "
            f"on [{s0:g}, {s1:g}]; use a smaller |lam| or a shorter interval"
        )
    params = dict(alpha=alpha, lam=lam, s_start=s0, s_end=s1, num=len(grid), method="incomplete gamma")
    return Curve("lac", grid, z.real, z.imag, theta, kappa, params)


def glac_curvature(s, alpha, lam, nu):
    """Curvature of the generalised LAC (see :func:`glac`):
    ``1 / (R(s) - nu)`` with ``R(s) = (lam alpha s + (1 + nu)**alpha)**(1/alpha)``
    (``(1 + nu) exp(lam s)`` when alpha = 0).

    Parameters
    ----------
    s : array_like
        Arc lengths.
    alpha, lam, nu : float
        Parameters of :func:`glac`.

    Returns
    -------
    ndarray
        Curvature at `s` (non-finite or <= 0 outside the domain).

    Examples
    --------
    >>> bool(np.isclose(glac_curvature(0.7, 0.5, 1.0, 0.0), 1 / (0.5 * 0.7 + 1) ** 2))  # nu = 0: the LAC
    True
    """
    s = np.asarray(s, dtype=float)
    R0 = 1.0 + nu
    if alpha == 0:
        R = R0 * np.exp(lam * s)
    else:
        base = lam * alpha * s + R0**alpha
        with np.errstate(invalid="ignore", divide="ignore"):
            R = np.where(base > 0, base ** (1.0 / alpha), np.where(alpha < 0, np.inf, 0.0))
    with np.errstate(divide="ignore"):
        return 1.0 / (R - nu)


def glac(alpha=0.0, lam=1.0, nu=0.0, s_start=0.0, s_end=1.0, num=201, *, s=None, rtol=RTOL):
    """Generalised log-aesthetic curve (GLAC) with extra parameter `nu`.

    The LAC's logarithmic curvature graph is a straight line of slope alpha:
    ``rho ds/drho = rho**alpha / lam``. The GLAC shifts the radius of
    curvature by ``nu``: ``R = rho + nu`` obeys the LAC law,
    ``R ds/dR = R**alpha / lam``, so that

        R(s) = (lam alpha s + (1 + nu)**alpha)**(1/alpha)  (alpha != 0),
        R(s) = (1 + nu) exp(lam s)                          (alpha = 0),

    ``rho = R - nu`` (``rho(0) = 1``) and ``kappa = 1/rho``. At ``nu = 0``
    it is the LAC of :func:`log_aesthetic`; for every nu the curvature is
    monotone in s (R is). **Derived here**: Gobithaasan & Miura's paper
    formula was not available to us; this is the one-parameter extension
    that keeps their stated properties (reduces to the LAC at nu = 0,
    monotone curvature), and it may differ from theirs in form.

    Parameters
    ----------
    alpha, lam : float
        As for the LAC.
    nu : float
        Radius shift (px in curve units), ``nu > -1``; 0 gives the LAC.
    s_start, s_end, num, s
        Output arc lengths; the curve needs ``R(s) > nu`` (positive rho)
        and, for alpha != 0, ``lam alpha s + (1 + nu)**alpha > 0``.
    rtol : float
        Tolerance of :func:`attneave.stimuli.curves.natural.integrate_natural`.

    Returns
    -------
    Curve
        y-UP coordinates; ``params`` include ``alpha, lam, nu``.

    Raises
    ------
    InputError
        A parameter out of range or an interval leaving the domain.

    Examples
    --------
    >>> a = glac(0.5, 1.0, 0.0, 0.0, 1.0, num=5)
    >>> b = log_aesthetic(0.5, 1.0, 0.0, 1.0, num=5)
    >>> bool(np.allclose(a.points, b.points, atol=1e-10))
    True
    """
    alpha = as_number(alpha, "alpha")
    lam = as_number(lam, "lam")
    nu = as_number(nu, "nu", gt=-1.0)
    grid = arc_grid(s_start, s_end, num, s)
    k = glac_curvature(grid, alpha, lam, nu)
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise InputError(
            f"glac: [s_start, s_end] = [{grid[0]:g}, {grid[-1]:g}] leaves the domain "
            f"(rho = R(s) - nu must stay positive) for alpha={alpha:g}, lam={lam:g}, nu={nu:g}"
        )
    curve = integrate_natural(lambda u: glac_curvature(u, alpha, lam, nu), s=grid, rtol=rtol)
    return relabel(curve, "glac", alpha=alpha, lam=lam, nu=nu)
