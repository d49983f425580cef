"""Quadrature rules for log-aesthetic arcs (:mod:`attneave.stimuli.curves.lac.arc`):
Gauss-Legendre on a whole interval where the arc's singular point ``t*``
(where its graph variable vanishes) is far, and panels graded
geometrically towards ``t*`` where it is near, so that the weak
singularity of the turn there costs no accuracy.

Intervals are on the arcs' unit parameter; a row is one interval.
"""

from __future__ import annotations

import numpy as np

__all__ = ["LEVELS", "graded_rule", "quadrature_groups"]

# Gauss-Legendre nodes per panel, and the geometric grading of the panels
# towards t* (_side_rule; finer far from t*, where a long panel meets the
# arc's whole oscillation)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
_GL_X_WIDE, _GL_W_WIDE = np.polynomial.legendre.leggauss(24)  # arcs far from t*, on [-1, 1]
LEVELS = 8  # geometric levels at most (edges down to 0.25 * 0.2**8 = 6.4e-7 of a side)


def _side_rule(levels):
    """One side of the graded rule as fractions of the distance from t*
    (nodes) and of the side's length (weights): Gauss-Legendre on each panel
    between consecutive edges 1, 0.7, 0.45, 0.25, 0.25 * 0.2**k (k = 1 ..
    levels), 0 (far end towards t*)."""
    edges = np.r_[1.0, 0.7, 0.45, 0.25, 0.25 * 0.2 ** np.arange(1, levels + 1), 0.0]
    half, mid = 0.5 * (edges[:-1] - edges[1:])[:, None], 0.5 * (edges[:-1] + edges[1:])[:, None]
    return (mid + half * _GL_X).ravel(), (half * _GL_W).ravel()


_SIDES = {k: _side_rule(k) for k in range(1, LEVELS + 1)}


def graded_rule(a, b, tstar, one_side=False, levels=LEVELS):
    """Quadrature nodes and weights on the intervals ``[a, b]`` (one per row),
    graded geometrically towards ``clip(tstar, a, b)`` from both sides.

    Parameters
    ----------
    a, b : ndarray, shape (R,), or float
    tstar : ndarray, shape (R,)
    one_side : bool
        Every row's `tstar` lies at or beyond an end of its interval: only
        the panels of the side that has a length (the other side's have
        none and weigh nothing).
    levels : int
        Geometric levels towards t* (:func:`~attneave.stimuli.curves.lac.arc.grading_levels`), 1 to 8.

    Returns
    -------
    nodes, weights : ndarray, shape (R, Q)

    Examples
    --------
    >>> x, w = graded_rule(np.array([0.0]), np.array([1.0]), np.array([0.3]))
    >>> round(float(np.sum(w * np.sqrt(np.abs(x - 0.3)))), 11)   # a sqrt kink at 0.3
    0.49998585722
    >>> round(2 / 3 * (0.3 ** 1.5 + 0.7 ** 1.5), 11)
    0.49998585722
    >>> x, w = graded_rule(np.array([0.0]), np.array([1.0]), np.array([-0.5]), one_side=True)
    >>> x.shape, round(float(np.sum(w * np.sqrt(x + 0.5))), 12) == round(2 / 3 * (1.5 ** 1.5 - 0.5 ** 1.5), 12)
    ((1, 120), True)
    """
    a, b = (np.asarray(v, dtype=float) for v in (a, b))
    a, b = (v[:, None] if v.ndim else v for v in (a, b))
    t = np.asarray(tstar, dtype=float)[:, None]
    c = np.minimum(np.maximum(np.where(np.isnan(t), 1.0, t), a), b)  # clip, a <= b
    R = t.shape[0]
    side_x, side_w = _SIDES[levels]
    if one_side:
        far = np.where(c == a, b, a) - c  # from the end away from c
        return c + far * side_x, np.abs(far) * side_w
    d = np.concatenate((a - c, b - c), axis=1)[:, :, None]
    return (c + (d * side_x).reshape(R, -1)), (np.abs(d) * side_w).reshape(R, -1)


def quadrature_groups(lo, hi, tstar, levels=LEVELS):
    """Quadrature rules for the intervals ``[lo, hi]`` (one per row) of arcs
    whose graph variable vanishes at `tstar`.

    Intervals whose `tstar` lies at least their own length beyond them see
    an integrand analytic on a wide ellipse: one 24-point Gauss rule does.
    The rest get :func:`graded_rule` (one-sided where `tstar` is not inside).

    Parameters
    ----------
    lo, hi : ndarray, shape (R,), or float
        The intervals; floats: one interval shared by every row.
    tstar : ndarray, shape (R,)
    levels : int
        Of the graded rule (:func:`~attneave.stimuli.curves.lac.arc.grading_levels`).

    Returns
    -------
    list of (rows, nodes, weights)
        Row indices and their nodes and weights, shape (len(rows), Q); the
        24-point group's shape is (1, Q) where the interval is shared (the
        same nodes for every row, broadcast).

    Examples
    --------
    >>> [(rows.tolist(), x.shape) for rows, x, w in quadrature_groups(0.0, 1.0, np.array([5.0, 0.5, -3.0, 1.5]))]
    [([0, 2], (1, 24)), ([1], (1, 240)), ([3], (1, 120))]
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    tstar = np.asarray(tstar, dtype=float)
    span = hi - lo
    easy = ~((tstar > lo - span) & (tstar < hi + span))
    out = []
    rows = np.flatnonzero(easy)
    if rows.size:
        half = 0.5 * span[..., None] if span.ndim == 0 else 0.5 * span[rows, None]
        start = lo[..., None] if lo.ndim == 0 else lo[rows, None]
        out.append((rows, np.atleast_2d(start + half * (1.0 + _GL_X_WIDE)), np.atleast_2d(half * _GL_W_WIDE)))
    # the graded rule, from both sides where tstar is inside the interval
    hard = np.flatnonzero(~easy)
    if not hard.size:
        return out
    t = tstar[hard]
    lo, hi = (v if v.ndim == 0 else v[hard] for v in (lo, hi))
    inside = (t > lo) & (t < hi)
    for one_side in (False, True):
        pick = inside != one_side
        if pick.all():
            out.append((hard, *graded_rule(lo, hi, t, one_side, levels)))
        elif pick.any():
            out.append((hard[pick], *graded_rule(*(v if v.ndim == 0 else v[pick] for v in (lo, hi, t)), one_side,
                                                 levels)))
    return out
