"""G2 log-aesthetic splines through points: log-aesthetic arcs of one slope
alpha, joined with curvature continuity, each with monotone curvature.

Every segment between consecutive points is an arc of a log-aesthetic curve
(LAC, the seed paper's eq. 9) of the given alpha, fixed by its end
curvatures and length (:mod:`attneave.stimuli.curves.lac.arc`). The unknowns are, at
every node, the tangent angle theta_i and the curvature kappa_i, shared by
the two segments that meet there (so the spline is G2 by construction), and
every segment's length L_j. Each segment gives three equations: its tangent
turns by ``L_j Theta_j(1)`` from theta_i to theta_{i+1}, and its chord
``L_j int_0^1 exp(i theta(t)) dt`` equals the vector between its points.
A closed curve has as many equations as unknowns (3N); an open one has two
end conditions: zero end curvature (natural ends) for alpha < 0, and for
alpha >= 0, whose arcs cannot reach zero curvature, a circular first and
last segment (``kappa_0 = kappa_1``, ``kappa_{N-1} = kappa_{N-2}``). The
system is solved by damped Newton (:mod:`attneave.stimuli.curves.lac.newton`) in
the curvatures' graph variables, with a sparse Jacobian (block-banded:
each segment involves only its two nodes), starting from the G2 clothoid
spline (:func:`attneave.stimuli.curves.qic.spline.qic_spline` with ``robust=False``), which
is the solution for alpha = -1; when Newton does not converge directly, the
solution is continued in alpha from -1 (from 0 for alpha >= 0) with
adaptive steps.

This construction -- node angles and curvatures as unknowns, a LAC arc of
fixed alpha per segment, Newton on curvature continuity -- is the G2
"two-parameter spline" scheme of Levien & Sequin (the Euler-spiral spline
is its alpha = -1 case) carried over to LAC arcs in the form of
:mod:`attneave.stimuli.curves.lac.arc`; it is derived here rather than taken from
one paper (Miura and co-workers' G2 LAC constructions fit one or a few
segments to G2 Hermite data; no formula for a whole interpolating spline
through N points was found).

Existence. For alpha >= 0 a LAC arc has no inflection (curvature cannot
reach 0), so a closed G2 LAC spline has curvature of one sign: its points
must form a convex polygon (turning one way at every point); otherwise
:func:`lac_spline` says so (an :class:`~attneave.stimuli.errors.InputError` naming
the rows). Even through a convex polygon a solution may not exist: an arc
with alpha >= 1 turns little between very different curvatures (alpha = 1:
by ``L log(rho0/rho1) / (rho0 - rho1)``), so long flat sides next to sharp
turns drive a node's curvature towards 0 or infinity as alpha grows (seen
as the continuation's curvature spread in the error). For alpha < 0 arcs
pass through inflections, and the points the clothoid spline takes are
usually taken too (every simple 12-, 20-, 40- and 80-gon of the 350 MPEG-7
outlines at alpha = -1 and -0.5; at alpha = -2 all but 4 of the 336
20-gons, where the branch of solutions continued from alpha = -1 turns back
before -2 while other alphas have solutions on other branches). A system Newton cannot solve is a
:class:`~attneave.stimuli.curves.qic.spline.ConvergenceError`, never a silent curve.

Coordinates: points ``(x, y)`` in image pixels (y down) unless
``y_down=False``; node tangent angles are in the input coordinates;
reported curvature has the project's geometric sign.

References
----------
.. [1] R. Levien and C. H. Sequin, "Interpolating splines: which is the
       fairest of them all?", Computer-Aided Design and Applications 6(1),
       91-102, 2009; R. Levien, "From spiral to spline", PhD thesis, UC
       Berkeley, 2009 (two-parameter G2 splines, the Euler-spiral spline).
.. [2] K. T. Miura, S. Usuki and R. U. Gobithaasan, "Variational
       formulation of the log-aesthetic curve", and R. U. Gobithaasan,
       S. W. Yip and K. T. Miura, "Log-aesthetic curves for shape
       completion problem", J. Applied Mathematics 2014, 960302.
.. [3] N. Yoshida and T. Saito, "Interactive aesthetic curve segments",
       The Visual Computer 22(9-11), 896-905, 2006.
"""

from __future__ import annotations

import time

import numpy as np

from attneave.stimuli.curves.euler import wrap_angle
from attneave.stimuli.curves.lac.newton import LACSystem, continue_in_alpha
from attneave.stimuli.curves.lac.result import LACG2Spline, solved_spline
from attneave.stimuli.curves.points import circle_tangents, geometric_sign, spline_points
from attneave.stimuli.curves.qic.spline import ConvergenceError, qic_spline
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = ["LACG2Spline", "lac_spline"]


def _guess(P, closed, y_down):
    """(theta, kappa, length, winding) at the nodes: the G2 clothoid spline,
    or circle tangents and curvatures where that fails."""
    try:
        q = qic_spline(P, closed, robust=False, y_down=y_down)
        turns = q.k0 * q.length + 0.5 * q.dk * q.length ** 2
        theta = q.theta0[0] + np.r_[0.0, np.cumsum(turns)]
        kappa = np.r_[q.k0, q.k0[-1] + q.dk[-1] * q.length[-1]]
        length = q.length
    except InputError:
        th = circle_tangents(P, closed)
        theta = th[0] + np.r_[0.0, np.cumsum(wrap_angle(np.diff(np.r_[th, th[:1]] if closed else th)))]
        nxt, prv = np.roll(P, -1, axis=0), np.roll(P, 1, axis=0)
        u, v = P - prv, nxt - P
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        kappa = 2 * cross / (np.hypot(*u.T) * np.hypot(*v.T) * np.hypot(*(nxt - prv).T))
        if not closed:
            kappa[0] = kappa[-1] = 0.0
        kappa = np.r_[kappa, kappa[:1]]
        length = np.hypot(*(np.diff(np.vstack([P, P[:1]]), axis=0) if closed else np.diff(P, axis=0)).T)
    wind = int(np.round((theta[-1] - theta[0]) / (2 * np.pi))) if closed else 0
    n = len(P)
    return theta[:n], kappa[:n], length, wind


def _check_one_way(P, closed, alpha):
    """alpha >= 0: LAC arcs have no inflection, so the points must turn one
    way (a curve of one-signed curvature through points in order)."""
    nxt, prv = np.roll(P, -1, axis=0), np.roll(P, 1, axis=0)
    u, v = P - prv, nxt - P
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    if not closed:
        cross = cross[1:-1]
        rows = np.arange(1, len(P) - 1)
    else:
        rows = np.arange(len(P))
    if cross.size == 0:
        return
    major = 1.0 if np.count_nonzero(cross > 0) >= np.count_nonzero(cross < 0) else -1.0
    bad = rows[~(cross * major > 0)]
    if bad.size:
        shown = ", ".join(map(str, bad[:10])) + (" ..." if bad.size > 10 else "")
        raise InputError(
            f"no G2 log-aesthetic spline with alpha={alpha:g} exists through these points: arcs with alpha >= 0 "
            f"have no inflection, so the points must turn one way, but {'rows' if bad.size > 1 else 'row'} "
            f"{shown} (0-based) {'turn' if bad.size > 1 else 'turns'} the other way or not at all (use alpha < 0)"
        )


def lac_spline(points, alpha=-1.0, closed=True, y_down=True, tol=1e-12, max_iter=40):
    """G2 spline of log-aesthetic arcs through points, with monotone
    curvature on every segment.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (y down); a closed curve does not
        repeat its first point.
    alpha : float
        Slope of every segment's log curvature graph: -1 the clothoid (the
        pure G2 QIC spline), 0 Nielsen's spiral, 1 the logarithmic spiral,
        2 the circle involute. Default -1.
    closed : bool
    y_down : bool
        Only the sign of reported curvature for open curves depends on it.
    tol : float
        Newton stops when every equation's residual is below `tol` (angles
        in radians, positions in mean chord lengths).
    max_iter : int
        Newton iterations per solve.

    Returns
    -------
    LACG2Spline

    Raises
    ------
    InputError
        Invalid points or alpha; alpha >= 0 with points that do not turn
        one way (no G2 LAC spline exists).
    ConvergenceError
        Newton (with continuation in alpha) finds no solution.

    Notes
    -----
    The curvature is shared by the two segments at every node (G2 by
    construction), and monotone on every segment: the graph variable
    ``g(kappa)`` is linear in arc length and g is monotone. See the module
    notes for the equations and :mod:`attneave.stimuli.curves.lac.arc` for the arcs.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    >>> sp = lac_spline(np.c_[50 + 20 * np.cos(t), 50 - 20 * np.sin(t)], alpha=1.0)
    >>> bool(np.allclose(sp.node_curvature, 0.05))      # a circle of radius 20
    True
    """
    t_start = time.perf_counter()
    P = spline_points(points, closed)
    alpha = as_number(alpha, "alpha")
    if alpha >= 0:
        if not closed and len(P) < 3:
            raise InputError(
                f"an open G2 log-aesthetic spline with alpha={alpha:g} >= 0 needs at least 3 points: its end "
                "segments are circular arcs, and through 2 points every circular arc is one"
            )
        _check_one_way(P, closed, alpha)
    theta, kappa, length, wind = _guess(P, closed, y_down)
    system = LACSystem(P, closed, wind)
    h = system.h
    if alpha >= 0:
        # the clothoid spline may inflect near flat stretches: start from one-signed curvature
        sg = 1.0 if np.sum(kappa) >= 0 else -1.0
        kappa = sg * np.maximum(sg * kappa, 0.1 * np.mean(np.abs(kappa)))
    if not closed:
        # the end conditions, exactly (Newton keeps them)
        kappa[[0, -1]] = (0.0, 0.0) if alpha < 0 else (kappa[1], kappa[-2])
    x0 = np.concatenate((theta, kappa * h, length / h))
    x, iters, ok, res = system.newton(x0, alpha, tol, max_iter)
    alphas = [alpha]
    if not ok:
        x, iters, ok, res, alphas = continue_in_alpha(system, x0, alpha, tol, max_iter)
    if not ok:
        kabs = np.abs(system.free_graph(system.split(x)[1]))
        spread = float(kabs.max() / kabs.min()) if kabs.min() > 0 else np.inf
        raise ConvergenceError(
            f"lac spline: no G2 log-aesthetic spline with alpha={alpha:g} found (Newton, continued in alpha "
            f"from {alphas[0]:g}, reached alpha={alphas[-1]:g}, where the node curvatures span a factor "
            f"{spread:.2g}; residual {res:.2g}); the points may be jagged or too sparse for this alpha (a "
            "spread growing without bound on the way means a node's curvature diverges: try a smaller alpha)"
        )
    return solved_spline(system, x, P, closed, alpha, geometric_sign(P, closed, y_down), iters, alphas, t_start)
