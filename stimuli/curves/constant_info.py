"""Constant-information curves (the seed paper's eq. 7): curvature
``k(s) = (1/s) (n arccos(C n**2 / s**2) + 2 pi)``, for which the surprisal of
eq. 5 with ``ds = s/n`` is constant along the curve. y-UP coordinates, as in
:mod:`attneave.stimuli.curves.natural`.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.natural import EPS, MAX_ARC, RTOL, arc_grid, integrate_natural, relabel
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["constant_info", "constant_info_curvature", "constant_info_domain"]


def _check_C_n(C, n):
    C = as_number(C, "C")
    n = as_number(n, "n")
    if not n > 0:
        raise InputError(f"constant-info: n must be > 0, got {n:g}")
    return C, n


def _domain_text(C, n):
    """What eq. 7 needs, in one clause, without contradictions at C = 0."""
    if C == 0:
        return (f"for C=0 it needs s > 0 (the curvature (n*pi/2 + 2*pi)/s is infinite at s = 0), "
                f"n={n:g}")
    s_min = float(np.sqrt(abs(C)) * n)
    return (f"it needs |C|*n^2 <= s^2, i.e. s >= {s_min:g} (= sqrt(|C|)*n) for C={C:g}, n={n:g}")


def constant_info_domain(C, n):
    """Smallest arc length where eq. 7 is defined: ``sqrt(|C|) * n``.

    Eq. 7 needs ``|C n^2 / s^2| <= 1`` (the argument of arccos), i.e.
    ``|C| n^2 <= s^2``, and ``s > 0``. For ``C = 0`` the bound is 0 itself
    excluded (the curvature is ``(pi/s)(n/2 + 2)``).

    Parameters
    ----------
    C : float
        The constant of eq. 7 (finite).
    n : float
        Number of points (finite, > 0).

    Returns
    -------
    float
        ``s_min``; eq. 7 is defined for ``s >= s_min`` (``s > 0`` when C = 0).

    Raises
    ------
    InputError
        Naming `C` or `n` when not finite, or n <= 0.

    Examples
    --------
    >>> constant_info_domain(0.01, 10)
    1.0
    """
    C, n = _check_C_n(C, n)
    return float(np.sqrt(abs(C)) * n)


def constant_info_curvature(s, C, n):
    """Curvature of the paper's eq. 7, for which surprisal (eq. 5) is constant.

    ``kappa(s) = (1/s) * (n * arccos(C n^2 / s^2) + 2 pi)``.

    With ``ds = s/n`` (the spacing of n points on the arc up to s),
    ``kappa ds - 2 pi/n = arccos(C n^2/s^2)``, so eq. 5 gives
    ``u = -ln A' - b (s/n)^2 (C n^2/s^2) = -ln A' - b C`` for every s.

    Parameters
    ----------
    s : array_like
        Arc lengths, all in the domain ``s > 0``, ``|C| n^2 <= s^2``.
    C : float
        The constant (the paper plots 0, +-0.01, +-0.02, +-0.03).
    n : float
        Number of points (> 0; the paper uses 10).

    Returns
    -------
    ndarray
        Curvature at `s` (positive: the curve turns left).

    Raises
    ------
    InputError
        If any `s` is outside the domain, naming the first such value and
        the bound ``sqrt(|C|) n``.

    Examples
    --------
    >>> float(constant_info_curvature(1.0, 0.0, 10)) == 7 * np.pi
    True
    """
    C, n = _check_C_n(C, n)
    s = np.asarray(s, dtype=float)
    s_min = np.sqrt(abs(C)) * n
    # a relative slack of a few ulps so that s = sqrt(|C|) n itself is accepted
    bad = ~np.isfinite(s) | (s <= 0) | (s < s_min * (1 - 4 * EPS))
    if np.any(bad):
        first = float(s[bad].flat[0])
        raise InputError(f"constant-info: s={first:g} is outside the domain of eq. 7; {_domain_text(C, n)}")
    # C n^2 / s^2 as sign(C) (s_min / s)^2, which lies in [-1, 1] on the domain: n^2 and s^2
    # themselves under- or overflow at extreme n or s (0/0 = NaN, with a RuntimeWarning on stderr)
    w = np.clip(np.sign(C) * (s_min / s) ** 2, -1.0, 1.0)
    return (n * np.arccos(w) + 2 * np.pi) / s


def constant_info(C=0.0, n=10, s_start=None, s_end=5.0, num=201, *, s=None, rtol=RTOL):
    """Constant-information curve of the paper's eq. 7, integrated.

    Parameters
    ----------
    C : float
        Constant of eq. 7.
    n : float
        Number of points (> 0).
    s_start : float, optional
        First arc length; default the start of the domain,
        ``max(sqrt(|C|) n, 1e-3 * s_end)`` (``s = 0`` itself is excluded:
        the curvature is infinite there).
    s_end : float
        Last arc length.
    num, s, rtol
        See :func:`integrate_natural`.

    Returns
    -------
    Curve
        y-UP coordinates from the origin with ``theta = 0`` at ``s_start``;
        ``params`` include ``C, n``. Along it eq. 5 with ``ds = s/n`` is the
        constant ``-ln A' - b*C`` for any A', b.

    Raises
    ------
    InputError
        If any arc length is outside ``s > 0, |C| n^2 <= s^2``.

    Notes
    -----
    For ``C = 0``, ``kappa = (pi/s)(n/2 + 2)``: ``rho`` is proportional to s,
    a logarithmic spiral (pseudospiral with m = 1), not a clothoid as the
    paper's text says. For ``C < 0`` the curvature decreases monotonically;
    for ``C > 0`` it rises from ``2 pi / s_min`` before falling.
    """
    C, n = _check_C_n(C, n)
    if s is None and s_start is None:
        # the default start is derived from C and n: say so when it does not fit
        s_end_f = as_number(s_end, "s_end")
        s_min = float(np.sqrt(abs(C)) * n)
        if s_min > MAX_ARC:
            raise InputError(
                f"constant-info: eq. 7 starts at s = sqrt(|C|)*n = {s_min:g} for C={C:g}, n={n:g}, "
                f"beyond the largest arc length {MAX_ARC:g}; use a smaller |C| or n"
            )
        if not s_end_f > s_min:
            raise InputError(
                f"constant-info: s_end={s_end_f:g} is not beyond the start of eq. 7's domain: s_start "
                f"defaults to sqrt(|C|)*n = {s_min:g} (C={C:g}, n={n:g}), so s_end must be > {s_min:g}"
                + ("" if C == 0 else "; or choose a smaller |C| or n")
            )
        s_start = max(s_min, 1e-3 * s_end_f)
    grid = arc_grid(s_start, s_end, num, s)
    constant_info_curvature(grid, C, n)  # domain check with a clear message
    curve = integrate_natural(lambda u: constant_info_curvature(u, C, n), s=grid, rtol=rtol)
    return relabel(curve, "constant-info", C=C, n=n)
