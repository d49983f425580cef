"""The QIC spline: a spline of clothoid segments through points, G2 wherever
that adds no information the points do not carry.

The **QIC spline** (quantity-of-information continuous; Ziatdinov; docs/design.md, "QIC splines")
passes through the given points; every segment between two consecutive
points is a clothoid (Euler spiral), whose curvature is linear in arc length
and so monotone: no curvature extremum, hence no spurious information,
appears between the points. The pure form (``robust=False``, the command
line's ``--method qic-g2``) joins every segment with curvature continuity
(G2) and is solved by :func:`attneave.stimuli.curves.qic.newton.solve_nodes`, or,
where it was built, by the same solve compiled (:mod:`attneave.stimuli.curves.qic.kernel`;
``ATTNEAVE_NUMPY_SPLINE=1`` forces numpy, the reference).

On jagged points the pure G2 spline can loop or swing far from the polygon.
The robust form (the default) then relaxes continuity at a few nodes by the
rule of :mod:`attneave.stimuli.curves.qic.rule`.

Every relaxed node is reported in ``corners`` (0-based input rows) with its
kind ('G1' or 'G0') in ``corner_kinds``; everywhere else the curve is G2 to
the solver's tolerance.

Coordinates: points are ``(x, y)`` in image pixels (x = column, y = row,
y down) unless ``y_down=False``. Reported curvature follows the project's
geometric sign (:func:`attneave.stimuli.curves.points.geometric_sign`). Tangent
angles stored on the spline (``theta0``) are in the input coordinates.

References
----------
.. [1] E. Bertolazzi and M. Frego, "Interpolating clothoid splines with
       curvature continuity", Math. Meth. Appl. Sci. 41(4), 1723-1737, 2018.
.. [2] R. Ziatdinov, "Visual perception, quantity of information function and
       the concept of the quantity of information continuous splines".
"""

from __future__ import annotations

import time
from dataclasses import replace
from functools import partial

import numpy as np

from attneave.stimuli.curves.checks import check_count, check_tolerance
from attneave.stimuli.curves.points import bisector_tangents, geometric_sign, spline_points
from attneave.stimuli.curves.qic import kernel as qic_kernel
from attneave.stimuli.curves.qic.pieces import PieceFit
from attneave.stimuli.curves.qic.result import QICSpline
from attneave.stimuli.curves.qic.rule import (
    CORNER_TURN,
    MAX_TANGENT_DEVIATION,
    bad_segments,
    crossing_segments,
    folded_corners,
    hold_straying_nodes,
    polygon_is_simple,
    polygon_measures,
    relax_bad_runs,
    segment_bulge,
    straying_nodes,
)
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number, check_flag

__all__ = ["ConvergenceError", "QICSpline", "qic_spline"]

# the crossing test of the robust rule: samples per segment (at most) and
# the largest change of tangent between samples (radians)
_CROSS_SAMPLES = 12
_CROSS_STEP = 0.15
# line-search halvings per Newton iteration in the robust rule's fits
_ROBUST_HALVINGS = 10


class ConvergenceError(InputError):
    """The QIC spline could not be computed for these points.

    Raised when damped Newton does not reach the tolerance within its
    iteration bound (typical of jagged or randomly ordered points). A
    subclass of :class:`~attneave.stimuli.errors.InputError`, so the command line
    reports it in one line with exit status 2.
    """


def _unit_angle(vec, what):
    if isinstance(vec, (str, bytes)):
        raise InputError(f"{what}: expected a direction vector (dx, dy), got {vec!r}")
    try:
        v = np.asarray(vec, dtype=float).reshape(-1)
    except (TypeError, ValueError):  # ('1', 'x'), a dict, ...: name the parameter, not float()
        raise InputError(f"{what}: expected a direction vector (dx, dy) of numbers, got {vec!r}") from None
    if v.size == 1:
        raise InputError(f"{what}: expected a direction vector (dx, dy), got a single number")
    if v.size != 2 or not np.all(np.isfinite(v)) or np.hypot(*v) == 0:
        raise InputError(f"{what}: expected a non-zero finite direction vector (dx, dy)")
    return float(np.arctan2(v[1], v[0]))


def _pack(P, closed, fit, g0, held, sign, t_start, method):
    seg = fit.seg
    corners = sorted(set(g0) | set(held))
    kinds = tuple("G0" if c in g0 else "G1" for c in corners)
    return QICSpline(
        points=P, closed=closed, x0=seg["x"][:, 0], y0=seg["x"][:, 1], theta0=seg["theta0"],
        k0=seg["k0"], dk=seg["dk"], length=seg["L"], start=seg["start"], sign=sign,
        iterations=fit.iterations, g2_error=fit.g2, closure_error=fit.closure,
        corners=tuple(corners), corner_kinds=kinds, seconds=time.perf_counter() - t_start, method=method,
    )


def _raise_failure(fit):
    idx, res = fit.failed_piece
    if res is None:
        raise ConvergenceError("QIC spline: the initial guess gives a degenerate segment")
    if not res.ok:
        raise ConvergenceError(
            f"QIC spline did not converge in {res.iterations} iterations (max curvature jump "
            f"{res.g2:.2g} of max |k|, closure {res.closure:.2g}); the points may be jagged, "
            "out of order or too sparse for a smooth curve"
        )
    # Newton can also "converge" towards a segment of unbounded length whose
    # curvature and closure residuals vanish with it (e.g. a closed curve
    # through collinear points): a bad curve, not a solution
    j = int(np.argmin(res.st["X0"]))
    raise ConvergenceError(
        f"QIC spline degenerates: the segment from point {int(idx[j])} would be "
        f"{1 / res.st['X0'][j]:.2g} times as long as its chord; the points may be "
        "collinear, out of order or too sparse for a smooth curve"
    )


def qic_spline(points, closed=True, *, robust=True, corner_turn=None, max_tangent_deviation=None,
               end_tangents=(None, None), corners=(), tol=1e-12, max_iter=50, y_down=True, log_aesthetic=True):
    """Fit the QIC spline: clothoid segments through points, G2 except at the
    few nodes the robust rule relaxes.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (x = column, y = row, y down). A
        closed curve must not repeat its first point at the end.
    closed : bool
        Closed curve (N segments) or open curve (N - 1 segments).
    robust : bool
        True (default): relax continuity where the G2 spline loops, swings
        out or crosses itself (the rule in the module notes). False: the
        pure G2 spline (``'qic-g2'``), which raises where Newton fails.
    corner_turn : float, optional
        Robust rule: a node it relaxes becomes a G0 corner, instead of a G1
        node, where the polygon turns there by more than this (radians;
        default :data:`attneave.stimuli.curves.qic.rule.CORNER_TURN`, 0.7 pi; pi:
        never).
    max_tangent_deviation : float, optional
        Robust rule: the largest difference between a G2 node's tangent and
        its bisector tangent (radians; default
        :data:`attneave.stimuli.curves.qic.rule.MAX_TANGENT_DEVIATION`, pi/4). Smaller values hug the polygon
        at the price of more G1 nodes.
    end_tangents : (vector or None, vector or None)
        Open curves only: tangent direction ``(dx, dy)`` at the first and at
        the last point, in the input coordinates. ``None`` gives a natural
        end (zero curvature).
    corners : sequence of int
        Points where the spline must break its tangent (G0 corners): whole
        0-based row indices (``1.5`` is refused, not rounded). The
        curve is split there into open pieces with natural ends.
    tol : float
        Newton stops when every curvature jump at a G2 node is below ``tol``
        times the largest |curvature| and every segment closes to 1e-14 of
        its chord (finite, > 0).
    max_iter : int
        Bound on Newton iterations (each with at most 30 step halvings);
        1 to 100000.
    y_down : bool
        Whether y points down (image pixels). Only the sign of reported
        curvature for open curves depends on it.
    log_aesthetic : bool
        Robust rule only: where the clothoid fit strays from the periodic
        cubic through the points, use its log-aesthetic form (the same
        joints, arcs of alpha = -0.3 with monotone curvature) when that
        strays less (:mod:`attneave.stimuli.curves.qic.lac`; not where
        `end_tangents` are given). False: clothoid segments only.

    Returns
    -------
    QICSpline or LACG2Spline
        The segments, with ``corners``, ``corner_kinds``, ``loops``,
        ``max_segment_turn``, ``iterations``, ``g2_error``,
        ``closure_error`` and ``seconds``. ``.sample(k)`` gives the curve.
        A :class:`~attneave.stimuli.curves.lac.result.LACG2Spline` (with ``alpha``)
        where the robust rule took the log-aesthetic form.

    Raises
    ------
    InputError
        Bad points (non-finite, too few, repeated consecutive points) or
        options (each named: flags must be bools, tolerances and angles
        finite and positive).
    ConvergenceError
        The pure G2 spline: Newton did not converge within `max_iter`
        iterations (e.g. jagged or randomly ordered points). The robust
        spline raises it only when no relaxation converges.

    Notes
    -----
    Scale invariant: each piece is scaled by its mean chord length. Newton
    starts from the small-angle G2 spline (:mod:`attneave.stimuli.curves.qic.newton`)
    and costs O(N) per iteration (a cyclic tridiagonal solve, LAPACK
    ``dgtsv``), each piece in one call of the compiled kernel where it was
    built (:data:`attneave.stimuli.curves.qic.kernel.KERNEL`); the robust rule adds
    its checks per round, on samples the kernel makes once per fit, and a
    crossing test (GEOS): on smooth curves, where one fit passes them all,
    about 2.4 x the pure spline's time at N = 30 and 1.75 x at N = 1000
    (:mod:`attneave.stimuli.curves.qic.rule`'s notes).

    References
    ----------
    .. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids", Math.
           Meth. Appl. Sci. 38(5), 881-897, 2015.
    .. [2] E. Bertolazzi and M. Frego, "Interpolating clothoid splines with
           curvature continuity", Math. Meth. Appl. Sci. 41(4), 2018.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> sp = qic_spline(np.c_[50 + 20 * np.cos(t), 50 - 20 * np.sin(t)])
    >>> round(float(sp.node_curvature[0]), 10)   # a circle of radius 20
    0.05
    >>> sp.corners
    ()
    """
    t_start = time.perf_counter()
    closed = check_flag(closed, "closed")
    robust = check_flag(robust, "robust")
    y_down = check_flag(y_down, "y_down")
    log_aesthetic = check_flag(log_aesthetic, "log_aesthetic")
    tol = check_tolerance(tol, "tol")
    max_iter = check_count(max_iter, "max_iter", lo=1, hi=100_000)
    if corner_turn is not None:
        corner_turn = as_number(corner_turn, "corner_turn", ge=0.0)
    if max_tangent_deviation is not None:
        max_tangent_deviation = as_number(max_tangent_deviation, "max_tangent_deviation", ge=0.0)
    P = spline_points(points, closed)
    N = len(P)
    g0 = set()
    if isinstance(corners, (str, bytes)) or not np.iterable(corners):
        raise InputError(f"corners: expected a sequence of point indices, got {corners!r}")
    for c in corners:
        c = check_count(c, "corners", lo=-(2**62), hi=2**62)  # whole numbers only: 1.5 is no row
        if not (0 <= c < N):
            raise InputError(f"corners: index {c} out of range 0..{N - 1}")
        if closed or 0 < c < N - 1:
            g0.add(c)
    if end_tangents is None:
        end_tangents = (None, None)
    if isinstance(end_tangents, (str, bytes)) or not np.iterable(end_tangents) or len(end_tangents) != 2:
        raise InputError(f"end_tangents: expected a pair (start, end) of direction vectors or None, got "
                         f"{end_tangents!r}")
    ts, te = end_tangents
    if closed and (ts is not None or te is not None):
        raise InputError("end_tangents: only for open curves")
    ts = None if ts is None else _unit_angle(ts, "end_tangents[0]")
    te = None if te is None else _unit_angle(te, "end_tangents[1]")
    sign = geometric_sign(P, closed, y_down)
    method = "qic" if robust else "qic-g2"
    held = {}
    if not robust:
        fit = PieceFit(P, closed, sorted(g0), held, ts, te, tol, max_iter, ranges=False)
        if fit.failed_piece is not None:
            _raise_failure(fit)
        return _pack(P, closed, fit, g0, held, sign, t_start, method)

    max_dev = MAX_TANGENT_DEVIATION if max_tangent_deviation is None else float(max_tangent_deviation)
    tangents = bisector_tangents(P, closed)
    simple_polygon = []  # polygon_is_simple(P, closed), asked only once a curve crosses itself
    turns, ref_dev, mean_chord = polygon_measures(P, closed, tangents)
    corner_turn = CORNER_TURN if corner_turn is None else float(corner_turn)
    given = set(g0)

    tried = {}
    pieces = {}  # solved pieces between G0 corners, by their nodes and held tangents

    def polygon_simple():
        # an added crossing is one the polygon of the points does not have
        if not simple_polygon:
            simple_polygon.append(polygon_is_simple(P, closed))
        return simple_polygon[0]

    def evaluate(fit, sp, g0, crossings=True):
        # the bad segments of a fit (step 3 of the rule); the crossing test (GEOS, the dearest part)
        # only where asked. The samples (sample_by_turn's) are made once for the bulge and the
        # crossing test: by the kernel, only x, y and each segment's distance from its chord
        sample = partial(sp.sample_by_turn, _CROSS_STEP, _CROSS_SAMPLES)
        if qic_kernel.LIB is not None:
            xy, dist = qic_kernel.turn_samples(_CROSS_STEP, _CROSS_SAMPLES, P, sp.start, sp.theta0, sp.k0, sp.dk,
                                               sp.length)
            bulge = dist / mean_chord
        else:
            sample = sample()  # made anyway: the crossing search takes it as it is
            xy = np.column_stack((sample.x, sample.y))
            bulge = segment_bulge(sample, P, closed)
        bad = bad_segments(fit.seg, None, ref_dev, bulge, folded_corners(fit.seg, g0, P, closed), turns,
                           corner_turn, g0)
        if crossings:
            crossing = crossing_segments(sp.start, xy, closed, sample, polygon_simple)
            if crossing.size:
                bad = np.union1d(bad, crossing)
        return bad

    def fit_state(g0, held):
        fit = PieceFit(P, closed, sorted(g0), held, ts, te, tol, min(max_iter, 30), _ROBUST_HALVINGS, pieces=pieces)
        return fit, None if fit.failed_piece is not None else _pack(P, closed, fit, g0, held, sign, t_start, method)

    def attempt(g0, held):
        # one fit under the rule: (fit, spline or None where Newton failed, bad
        # segments); held tangents are the bisector's, so the relaxed nodes
        # name a fit (step 5 often returns to one already made)
        key = (frozenset(g0), frozenset(held))
        if key not in tried:
            fit, sp = fit_state(g0, held)
            tried[key] = (fit, sp, None if sp is None else evaluate(fit, sp, g0))
        return tried[key]

    def clean(g0, held):
        # step 5's question: the spline of a fit where nothing is bad or straying, else None; the
        # cheap tests first, the crossing test last (most fits tried there fail a cheap one)
        key = (frozenset(g0), frozenset(held))
        if key in tried:
            fit, sp, bad = tried[key]
            ok = sp is not None and not bad.size
        else:
            fit, sp = fit_state(g0, held)
            ok = sp is not None
        relaxed = list(g0) + list(held)
        ok = ok and not straying_nodes(fit.seg, N, closed, relaxed, tangents, max_dev).size
        if ok and key not in tried:
            ok = not evaluate(fit, sp, g0, crossings=False).size and not evaluate(fit, sp, g0).size
        tried.setdefault(key, (fit, None, None))  # counted (iterations) but not reused
        return sp if ok else None

    failures = 0
    sp = fit = bad = None
    for _ in range(N + 1):
        # a fit that stalls is abandoned early: relaxing a node is cheaper
        fit, new, new_bad = attempt(g0, held)
        if new is None:
            free = [i for i in range(N) if i not in held and i not in g0 and (closed or 0 < i < N - 1)]
            if not free:
                break
            # Newton failed: hold the sharpest G2 node(s), twice as many each
            # time it fails again, so that hopeless input ends quickly
            failures += 1
            for e in sorted(free, key=lambda i: -turns[i])[: 2 ** (failures - 1)]:
                held[e] = tangents[e]
            continue
        sp, bad = new, new_bad
        changed = hold_straying_nodes(fit.seg, N, closed, g0, held, tangents, turns, corner_turn, max_dev)
        if bad.size:
            changed |= relax_bad_runs(bad, fit.seg, N, closed, turns, g0, held, tangents, corner_turn)
        if not changed:
            break
    if sp is None:
        _raise_failure(fit)
    if not bad.size:
        # step 5 of the rule: give G2 back where a later relaxation made a node's useless
        kinds = dict(zip(sp.corners, sp.corner_kinds))
        g0, held = {c for c in kinds if kinds[c] == "G0"}, {c: tangents[c] for c in kinds if kinds[c] == "G1"}
        for e in sorted(set(kinds) - given, key=lambda i: turns[i]):
            g, h = g0 - {e}, {k: v for k, v in held.items() if k != e}
            new = clean(g, h)
            if new is not None:
                g0, held, sp = g, h, new
    iterations = sum(f.iterations for f, _, _ in tried.values())
    if len(tried) > 1:
        sp = replace(sp, iterations=iterations)
    # the log-aesthetic form of the same joints, where it hugs the points better (imported here:
    # the log-aesthetic spline starts from this module's clothoid spline)
    from attneave.stimuli.curves.qic.lac import prefer_log_aesthetic

    final = tried.get((frozenset(g0), frozenset(held)))
    turn = float(final[0].seg["turn"].max()) if final is not None and "turn" in final[0].seg else None
    # (not with given end tangents: the log-aesthetic system's open ends are natural)
    lac = prefer_log_aesthetic(sp, polygon_simple, max_turn=turn) if log_aesthetic and ts is None and te is None else sp
    if lac is not sp:
        sp = replace(lac, iterations=iterations + lac.iterations)
    # the time, set on the spline that this call made (frozen for its users; dataclasses.replace
    # would cost as much as a tenth of the rule's checks on smooth curves, where one fit is all)
    object.__setattr__(sp, "seconds", time.perf_counter() - t_start)
    return sp
