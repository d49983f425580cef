"""The robust QIC spline's log-aesthetic form: the same nodes and joints,
log-aesthetic arcs of slope :data:`ALPHA` instead of clothoids, where that
keeps the curve closer to what the points say.

A clothoid's curvature is linear in arc length, so next to a node of large
curvature a G2 clothoid segment carries much of that curvature far from the
node and swings out; the periodic cubic through the same points puts it
near the node (at the price of curvature extrema inside segments). A
log-aesthetic arc with alpha between -1 and 0 (the seed's eq. 9; curvature
``|c0 s + c1|**(-1/alpha)``, convex in s) also concentrates curvature at
the end where it is large while keeping it monotone on the segment, the
QIC property. The log-aesthetic form (:func:`log_aesthetic_form`) solves
the G2 log-aesthetic system (:class:`~attneave.stimuli.curves.lac.newton.LACSystem`)
with the robust fit's G1 nodes (tangent held, curvature free on each side)
and G0 corners (natural ends on both sides), continued in alpha from the
clothoid fit itself (its solution at alpha = -1).

The rule (:func:`prefer_log_aesthetic`): where a segment of the clothoid
fit turns by more than :data:`SCREEN_TURN` and the fit strays from the
periodic cubic spline through the same points by more than :data:`TRIGGER`
mean chords (on smooth input neither happens, and nothing more is
computed), the log-aesthetic form is solved, and it replaces
the clothoid fit when it strays less from that cubic, turns by at most pi
on every segment and does not cross itself (where the points' polygon is
simple). The cubic serves only as a reference computed from the points: the
curve stays a QIC spline, with monotone curvature on every segment.

Tuning (all 350 MPEG-7 outlines reduced to 12 / 20 / 40 / 80 points, with
both fixed halves checked; ``benchmarks/validate_spline.py --halves``): the
90th percentile of the largest distance to the outline (divided by the
perimeter) goes from 1.10 / 1.05 / 1.08 / 1.07 times the cubic's to 1.06 /
1.01 / 1.01 / 1.03 (each half within 1.06 / 1.02 / 1.02 / 1.04); of alpha in
-0.2 ... -0.7, -0.3 was best on both halves at N = 20 and 40; a trigger of
0.08 mean chords loses nothing against trying every fit (0.12 did, at
N = 12); every fit the form was taken for (174 / 163 / 167 / 167 of the
outlines at N = 12 / 20 / 40 / 80) turns by more than 55 degrees on some
segment (the screen :data:`SCREEN_TURN` is 45 degrees), and 50 random
smooth curves of 30 and of 1000 points (``benchmarks/bench_spline.py``'s)
turn by at most 36 and 1 degrees: they never reach the cubic. Cost where it is solved:
about 3-9 ms per curve at N = 12-80 (median 3.2 / 4.2 / 5.7 / 9.1 ms at N =
12 / 20 / 40 / 80, ``benchmarks/bench_lac_step.py``; Newton in numpy, from
the clothoid straight to alpha, by continuation only where that fails).
"""

from __future__ import annotations

import time

import numpy as np

from attneave.stimuli.curves.lac.newton import LACSystem, continue_in_alpha
from attneave.stimuli.curves.lac.result import solved_spline

__all__ = ["ALPHA", "SCREEN_TURN", "TRIGGER", "log_aesthetic_form", "prefer_log_aesthetic"]

#: Slope of the log curvature graph of the log-aesthetic form's arcs (-1 would be the clothoid).
ALPHA = -0.3
#: Distance (in mean chords) by which the clothoid fit must stray from the periodic cubic
#: before the log-aesthetic form is tried.
TRIGGER = 0.08
#: The cubic is asked only where a segment of the clothoid fit turns by more than this (radians;
#: 45 degrees): where every segment turns less the points sample the curve densely and the two
#: agree (screen measured below).
SCREEN_TURN = 0.25 * np.pi
# a distance to the cubic smaller by less than this (in mean chords) is a tie: the clothoid stays
_TIE = 1e-9
# samples per segment for the comparison with the cubic (the cubic's: 4x denser)
_SAMPLES = 16


def log_aesthetic_form(sp, alpha=ALPHA, tol=1e-12, max_iter=40):
    """The spline of log-aesthetic arcs with the nodes, G1 nodes and G0
    corners of a QIC spline fit.

    Parameters
    ----------
    sp : QICSpline
        A fit of :func:`~attneave.stimuli.curves.qic.spline.qic_spline` (its segments start
        at nodes 0, 1, ... in order).
    alpha : float
        Slope of every arc's log curvature graph, below 0 (G0 corners have
        natural ends, which arcs of alpha >= 0 cannot reach).
    tol, max_iter
        Newton's tolerance and iteration bound (:func:`~attneave.stimuli.curves.lac.spline.lac_spline`).

    Returns
    -------
    LACG2Spline or None
        With `sp`'s corners, corner kinds and method; None where the
        continuation from the clothoid (alpha = -1) does not reach `alpha`.

    Examples
    --------
    >>> import numpy as np
    >>> from attneave.stimuli.curves.qic.spline import qic_spline
    >>> t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> P = np.c_[100 + 40 * np.cos(t), 100 - 25 * np.sin(t)]
    >>> lac = log_aesthetic_form(qic_spline(P), alpha=-0.3)
    >>> lac.alpha, lac.corners, bool(lac.closure_error < 1e-9)
    (-0.3, (), True)
    """
    t_start = time.perf_counter()
    P, closed, n = sp.points, sp.closed, len(sp.points)
    M = sp.length.size
    if not np.array_equal(sp.start, np.arange(M)):
        raise ValueError("the fit's segments must start at nodes 0, 1, ... in order")
    kinds = dict(zip(sp.corners, sp.corner_kinds))
    g0 = [c for c, k in kinds.items() if k == "G0"]
    g1 = {c: float(sp.theta0[c]) for c, k in kinds.items() if k == "G1"}
    L, k0, dk = sp.length, sp.k0, sp.dk
    end_theta = sp.theta0 + k0 * L + 0.5 * dk * L ** 2
    end_kappa = k0 + dk * L
    b = (np.arange(M) + 1) % n if closed else np.arange(M) + 1
    theta, kappa = np.empty(n), np.empty(n)
    theta[:M], kappa[:M] = sp.theta0, k0
    if not closed:
        theta[-1], kappa[-1] = end_theta[-1], end_kappa[-1]
    # the angle each segment reaches at its end differs from the next node's by whole turns
    # (only where the tangent is continuous; a G0 corner's incoming side has its own angle)
    shared = ~np.isin(b, g0)
    wrap = np.where(shared, 2 * np.pi * np.round((end_theta - theta[b]) / (2 * np.pi)), 0.0)
    system = LACSystem(P, closed, g1=g1, g0=g0, wrap=wrap)
    h = system.h
    th0, kap0 = np.empty(system.nt), np.empty(system.nu)
    th0[:n], kap0[:n] = theta, kappa
    th0[system.tb[~shared]] = end_theta[~shared]
    split = system.ub >= n
    kap0[system.ub[split]] = end_kappa[split]
    kap0[system.fixed_cols[system.fixed_cols >= system.nt] - system.nt] = 0.0
    x0 = np.concatenate((th0, kap0 * h, L / h))
    # straight to alpha from the clothoid (usually a few iterations), else by continuation
    x, iterations, ok, _ = system.newton(x0, alpha, tol, min(max_iter, 12))
    alphas = [-1.0, alpha]
    if not ok:
        x, more, ok, _, alphas = continue_in_alpha(system, x0, alpha, tol, max_iter)
        iterations += more
    if not ok:
        return None
    return solved_spline(system, x, P, closed, alpha, sp.sign, iterations, alphas, t_start,
                         corners=tuple(sp.corners), corner_kinds=tuple(sp.corner_kinds), method=sp.method)


def _cubic_positions(cubic, samples):
    """The points of ``cubic.sample(samples)`` (a PolynomialSpline) without its
    derivatives and arc lengths, which the comparison does not use."""
    kn = cubic.knots
    u = kn[:-1, None] + (kn[1:] - kn[:-1])[:, None] * np.linspace(0.0, 1.0, samples)[None, :]
    return cubic.spline(u.ravel())


def _xy(curve):
    return np.column_stack((curve.x, curve.y))


def prefer_log_aesthetic(sp, polygon_simple, alpha=None, trigger=None, max_turn=None):
    """`sp`, or its log-aesthetic form where that strays less from the
    periodic cubic through the points (the rule in the module notes).

    Parameters
    ----------
    sp : QICSpline
        The robust rule's fit.
    polygon_simple : callable
        Returns whether the polygon of the points is simple.
    alpha : float, optional
        Default :data:`ALPHA`.
    trigger : float, optional
        In mean chords; default :data:`TRIGGER`.
    max_turn : float, optional
        `sp`'s largest segment turn where the caller has it (default:
        ``sp.max_segment_turn``).

    Returns
    -------
    QICSpline or LACG2Spline
    """
    from scipy.spatial import cKDTree

    from attneave.stimuli.curves.metrics import segment_turning
    from attneave.stimuli.curves.polynomial import polynomial_spline
    from attneave.stimuli.curves.qic.measures import crossing_segments, mean_side

    alpha = ALPHA if alpha is None else alpha
    trigger = TRIGGER if trigger is None else trigger
    P, closed = sp.points, sp.closed
    if len(P) < 4 or (sp.max_segment_turn if max_turn is None else max_turn) <= SCREEN_TURN:
        return sp
    unit = mean_side(P, closed)
    # (an unbalanced tree builds faster and finds the same nearest distances)
    tree = cKDTree(_cubic_positions(polynomial_spline(P, 3, closed), 4 * _SAMPLES), balanced_tree=False)
    stray = float(tree.query(_xy(sp.sample(_SAMPLES)))[0].max())
    if stray <= trigger * unit or not polygon_simple():
        return sp
    lac = log_aesthetic_form(sp, alpha)
    if lac is None:
        return sp
    curve = lac.sample(_SAMPLES)
    xy = _xy(curve)
    # it must stray less by more than rounding: where both share the segment that strays most
    # (a straight one between corners) the two distances differ in the last digits only
    if float(tree.query(xy)[0].max()) >= stray - _TIE * unit:
        return sp
    turn = segment_turning(curve.s, curve.curvature, curve.segment, curve.theta)
    if turn.size and float(turn.max()) > np.pi:
        return sp
    if crossing_segments(np.arange(lac.length.size), xy, closed, curve, polygon_simple).size:
        return sp
    return lac
