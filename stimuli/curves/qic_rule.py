"""The robust QIC spline's rule: which nodes give up curvature continuity.

On jagged points the pure G2 spline can loop or swing far from the polygon
(a segment turning by more than pi, a self-crossing the polygon does not
have). The robust form (the default) then relaxes continuity at a few nodes.
The *bisector tangent* of a node is the direction of the sum of the unit
vectors along the two polygon sides that meet there
(:func:`stimuli.curves.points.bisector_tangents`). The rule, repeated until
nothing changes (at most N + 1 rounds):

1. Fit the spline (G2 at every node not yet relaxed).
2. *Straying nodes*: a G2 node whose tangent differs from its bisector
   tangent by more than :data:`MAX_TANGENT_DEVIATION` (pi/4), and by at least
   as much as at both neighbours, becomes a **G1 node**: its tangent is held
   at the bisector tangent and its curvature may jump.
3. *Bad segments*: a segment whose tangent turns by more than pi, whose
   tangent leaves its chord's direction by more than
   ``max(pi/2, a + pi/10)`` (``a`` the larger angle between the chord and the
   bisector tangents at its ends: what a smooth curve cannot avoid), or that
   crosses another segment although the polygon of the points is simple. In
   every run of consecutive bad segments, the G2 node with the sharpest
   polygon turn among the run's nodes becomes a G1 node; where all of them
   already are G1 nodes, the sharpest becomes a **G0 corner** (the curve is
   cut there into open pieces with natural ends; corners carry
   information, the seed's eq. 6).
4. Where Newton does not converge, the G2 node with the sharpest polygon
   turn becomes a G1 node (two nodes at the next failure, then four, ...).

On MPEG-7 outlines reduced to 12 / 20 / 40 / 80 points equally spaced by arc
length this relaxes 8.0 / 7.4 / 4.9 / 0.7 % of the nodes, leaves 0.6 / 0 / 0 / 0
% of the curves crossing themselves and no segment turning by more than pi,
and the 90th percentile of the largest distance to the outline is 1.18 /
1.13 / 1.15 / 1.09 times that of scipy's periodic cubic spline (the pure G2
spline: 1.49 / 1.43 / 1.31 / 1.20; ``benchmarks/validate_spline.py``).

References
----------
.. [1] R. Ziatdinov, "Visual perception, quantity of information function and
       the concept of the quantity of information continuous splines" (eq. 6:
       corners carry information).
"""

from __future__ import annotations

import numpy as np

from stimuli.curves.euler import wrap_angle
from stimuli.curves.metrics import self_crossing_segments

__all__ = [
    "MAX_CHORD_ANGLE",
    "CHORD_MARGIN",
    "MAX_TANGENT_DEVIATION",
    "polygon_turns",
    "polygon_is_simple",
    "bad_segments",
    "hold_straying_nodes",
    "relax_bad_runs",
]

#: A segment whose tangent leaves its chord's direction by more than this
#: (radians), and by more than the bisector tangents at its ends do plus
#: CHORD_MARGIN, swings out of the polygon: the robust rule relaxes a node.
MAX_CHORD_ANGLE = 0.5 * np.pi
CHORD_MARGIN = 0.1 * np.pi
#: A G2 node whose tangent differs from the bisector tangent by more than
#: this (radians) strays: the robust rule holds it at the bisector (G1).
MAX_TANGENT_DEVIATION = 0.25 * np.pi


def polygon_turns(P, closed):
    """Absolute turning angle of the polygon at every node (radians; 0 at the
    ends of an open curve).

    Examples
    --------
    >>> polygon_turns(np.array([[0, 0], [1, 0], [1, 1], [0, 1.]]), True).round(4).tolist()
    [1.5708, 1.5708, 1.5708, 1.5708]
    """
    D = (np.roll(P, -1, axis=0) - P) if closed else np.diff(P, axis=0)
    phi = np.arctan2(D[:, 1], D[:, 0])
    if closed:
        return np.abs(wrap_angle(phi - np.roll(phi, 1)))
    return np.r_[0.0, np.abs(wrap_angle(np.diff(phi))), 0.0]


def polygon_is_simple(P, closed):
    """Whether the polygon (closed) or polyline of the points is simple (GEOS)."""
    import shapely

    return bool(shapely.is_simple(shapely.LinearRing(P) if closed else shapely.LineString(P)))


def bad_segments(seg, curve, ref_dev):
    """Indices (into the segment arrays) of the segments the rule repairs
    (step 3 of the module notes).

    Parameters
    ----------
    seg : dict
        Per segment (in order from the first point): ``start`` (node index),
        ``turn`` (range of the tangent angle) and ``chord_dev`` (largest angle
        between tangent and chord).
    curve : SampledCurve or None
        The curve's samples, for the crossing test (None: no test, e.g. when
        the polygon itself is not simple).
    ref_dev : ndarray
        Per node: the larger angle between its segment's chord and the
        bisector tangents at its ends.
    """
    limit = np.maximum(MAX_CHORD_ANGLE, ref_dev[seg["start"]] + CHORD_MARGIN)
    bad = (seg["turn"] > np.pi) | (seg["chord_dev"] > limit)
    if curve is not None:
        for s in self_crossing_segments(curve.x, curve.y, curve.segment, curve.closed):
            bad[np.flatnonzero(seg["start"] == s)] = True
    return np.flatnonzero(bad)


def hold_straying_nodes(seg, N, closed, g0, held, tangents, turns, corner_turn, max_dev):
    """Step 2 of the module notes: relax the nodes whose G2 tangent strays
    from the bisector tangent by more than `max_dev` (and by at least as much
    as at both neighbours). `g0` (set) and `held` (dict node -> tangent) are
    updated in place; returns whether any node changed."""
    theta = np.full(N, np.nan)
    theta[seg["start"]] = seg["theta0"]
    dev = np.abs(wrap_angle(theta - tangents))
    dev[list(g0) + list(held)] = 0.0
    if not closed:
        dev[0] = dev[-1] = 0.0
    dev = np.nan_to_num(dev)
    peak = (dev > max_dev) & (dev >= np.roll(dev, 1)) & (dev >= np.roll(dev, -1))
    for e in np.flatnonzero(peak):
        _relax_node(int(e), g0, held, tangents, turns, corner_turn)
    return bool(peak.any())


def _relax_node(e, g0, held, tangents, turns, corner_turn):
    """A G2 node becomes a G1 node, its tangent held at the bisector, or a
    G0 corner where the polygon turns by more than `corner_turn`."""
    if turns[e] > corner_turn:
        g0.add(e)
    else:
        held[e] = tangents[e]


def _runs(bad, m, closed):
    """Runs of consecutive segment indices (cyclic when closed)."""
    runs, cur = [], [int(bad[0])]
    for j in bad[1:]:
        if j == cur[-1] + 1:
            cur.append(int(j))
        else:
            runs.append(cur)
            cur = [int(j)]
    runs.append(cur)
    if closed and len(runs) > 1 and runs[0][0] == 0 and runs[-1][-1] == m - 1:
        runs[0] = runs.pop() + runs[0]
    return runs


def relax_bad_runs(bad, seg, N, closed, turns, g0, held, tangents, corner_turn):
    """Step 3 of the module notes: one node per run of bad segments becomes
    G1 (or G0 where all its candidates already are G1). Updates `g0` and
    `held` in place; returns False when nothing is left to relax."""
    changed = False
    for run in _runs(bad, len(seg["start"]), closed):
        nodes = {int(seg["start"][j]) for j in run} | {(int(seg["start"][j]) + 1) % N for j in run}
        nodes = [e for e in nodes if (closed or 0 < e < N - 1) and e not in g0]
        if not nodes:
            continue
        g2 = [e for e in nodes if e not in held]
        if g2:
            _relax_node(max(g2, key=lambda i: turns[i]), g0, held, tangents, turns, corner_turn)
        else:
            e = max(nodes, key=lambda i: turns[i])
            del held[e]
            g0.add(e)
        changed = True
    return changed
