"""Metrics for sampled piecewise curves: G2 error at the joins, curvature
extrema inside segments, maximum curvature, bending energy and loops.

A curve is given as samples along its arc length, grouped into segments
(the pieces between consecutive interpolated points). Every segment's
samples include both of its end points, so a join appears twice: as the last
sample of one segment and the first sample of the next. That is the format
written by ``attneave spline`` (columns ``s, x, y, curvature, segment``).

Points are ``(x, y)`` in image pixels (x = column, y = row, y down);
curvature follows the project's geometric sign (positive where a closed
curve is convex).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "SplineMeasures",
    "SampledCurve",
    "segment_slices",
    "interior_extrema",
    "extrema_indices",
    "join_jumps",
    "g2_error",
    "bending_energy",
    "segment_turning",
    "curve_metrics",
    "self_intersections",
    "self_crossing_segments",
]


@dataclass(frozen=True)
class SampledCurve:
    """Samples of a piecewise curve.

    Attributes
    ----------
    s : ndarray
        Arc length from the first point (px), non-decreasing.
    x, y : ndarray
        Positions in image pixels (y down).
    curvature : ndarray
        Curvature (1/px), positive convex for closed curves (positive for a
        left turn on the screen for open ones).
    segment : ndarray of int
        Index of the input point at which each sample's segment starts.
    theta : ndarray or None
        Tangent direction in the input coordinates (radians from +x towards
        +y), continuous within each segment; used to find loops.
    closed : bool
        Whether the last segment ends at the first point.
    breaks : tuple of int
        Segment start indices where a G0 corner was asked for; the join
        *into* such a segment is left out of the G2 error.
    """

    s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    curvature: np.ndarray
    segment: np.ndarray
    theta: np.ndarray | None = None
    closed: bool = True
    breaks: tuple = field(default_factory=tuple)

    def table(self):
        """Columns ``s, x, y, curvature, segment`` as a dict of arrays."""
        return {
            "s": self.s, "x": self.x, "y": self.y,
            "curvature": self.curvature, "segment": self.segment.astype(int),
        }


def _blocks(segment):
    """Start and stop indices of runs of equal segment labels."""
    segment = np.asarray(segment)
    if segment.size == 0:
        e = np.zeros(0, dtype=int)
        return e, e
    cut = np.flatnonzero(segment[1:] != segment[:-1]) + 1
    return np.r_[0, cut], np.r_[cut, segment.size]


def segment_slices(segment):
    """Slices of consecutive samples sharing a segment label, in order."""
    starts, stops = _blocks(segment)
    return [slice(a, b) for a, b in zip(starts, stops)]


def _within(segment):
    """For each consecutive pair of samples: its block index and whether
    both samples lie in the same block."""
    segment = np.asarray(segment)
    inside = segment[1:] == segment[:-1]
    block = np.cumsum(np.r_[0, ~inside])  # block index of each sample
    return block, inside


def interior_extrema(curvature, segment, rtol=1e-9):
    """Number of curvature extrema strictly inside each segment.

    An extremum is a change of sign of the sampled curvature differences;
    differences smaller than ``rtol * max|curvature|`` count as flat, so a
    constant-curvature arc has none.

    Returns
    -------
    ndarray of int
        One count per segment, in order of appearance.
    """
    k = np.asarray(curvature, dtype=float)
    if k.size == 0:
        return np.zeros(0, dtype=int)
    block, inside = _within(segment)
    tol = rtol * np.max(np.abs(k))
    d = np.diff(k)
    keep = inside & (np.abs(d) > tol)
    sg = np.sign(d[keep])
    bl = block[:-1][keep]
    change = (sg[1:] != sg[:-1]) & (bl[1:] == bl[:-1])
    return np.bincount(bl[1:][change], minlength=int(block[-1]) + 1).astype(int)


def extrema_indices(curvature, segment, rtol=1e-9):
    """Sample indices of the curvature extrema strictly inside segments
    (the samples counted by :func:`interior_extrema`)."""
    k = np.asarray(curvature, dtype=float)
    if k.size < 3:
        return np.zeros(0, dtype=int)
    block, inside = _within(segment)
    tol = rtol * np.max(np.abs(k))
    d = np.diff(k)
    keep = np.flatnonzero(inside & (np.abs(d) > tol))
    sg = np.sign(d[keep])
    bl = block[:-1][keep]
    change = (sg[1:] != sg[:-1]) & (bl[1:] == bl[:-1])
    # the extremum sits after the first difference of the pair (a flat run
    # between them is reported at its start)
    return keep[:-1][change] + 1


def join_jumps(curvature, segment, closed=True, breaks=()):
    """Absolute curvature jumps at the joins between consecutive segments.

    The joins into segments listed in `breaks` (G0 corners) are skipped.
    """
    k = np.asarray(curvature, dtype=float)
    seg = np.asarray(segment)
    starts, stops = _blocks(seg)
    if starts.size < 2:
        return np.zeros(0)
    last = k[stops - 1]
    first = k[starts]
    jumps = np.abs(last[:-1] - first[1:])
    into = seg[starts[1:]]
    if closed:
        jumps = np.r_[jumps, abs(last[-1] - first[0])]
        into = np.r_[into, seg[starts[0]]]
    if len(breaks):
        jumps = jumps[~np.isin(into, np.asarray(breaks, dtype=int))]
    return jumps


def g2_error(curvature, segment, closed=True, breaks=()):
    """Largest curvature jump at a join divided by the largest |curvature|
    (0 for a straight curve)."""
    jumps = join_jumps(curvature, segment, closed, breaks)
    kmax = float(np.max(np.abs(curvature))) if np.size(curvature) else 0.0
    if jumps.size == 0 or kmax == 0.0:
        return 0.0
    return float(np.max(jumps) / kmax)


def bending_energy(s, curvature, segment):
    """Integral of curvature squared over arc length (1/px), trapezoid rule
    within each segment."""
    s = np.asarray(s, dtype=float)
    k2 = np.asarray(curvature, dtype=float) ** 2
    if k2.size < 2:
        return 0.0
    _, inside = _within(segment)
    return float(np.sum((0.5 * (k2[1:] + k2[:-1]) * np.diff(s))[inside]))


def segment_turning(s, curvature, segment, theta=None):
    """Range (max - min) of the tangent angle within each segment, radians.

    From `theta` when given (unwrapped), otherwise by integrating the
    curvature (trapezoid rule).
    """
    k = np.asarray(curvature, dtype=float)
    if k.size == 0:
        return np.zeros(0)
    starts, _ = _blocks(segment)
    _, inside = _within(segment)
    if theta is not None:
        th = np.asarray(theta, dtype=float)
        # unwrapping across a join only shifts the next block by a constant
        th = np.unwrap(th)
    else:
        inc = 0.5 * (k[1:] + k[:-1]) * np.diff(np.asarray(s, dtype=float))
        th = np.r_[0.0, np.cumsum(np.where(inside, inc, 0.0))]
    return np.maximum.reduceat(th, starts) - np.minimum.reduceat(th, starts)


def curve_metrics(curve, rtol=1e-9):
    """All metrics of a :class:`SampledCurve`.

    Returns
    -------
    dict
        ``g2_error`` (max curvature jump at a join / max |k|),
        ``interior_extrema`` (total count), ``extrema_per_segment`` (list),
        ``max_abs_curvature`` (1/px), ``bending_energy`` (1/px),
        ``loops`` (number of segments whose tangent turns by more than pi),
        ``max_segment_turn`` (radians),
        ``n_segments``, ``length`` (px).
    """
    per = interior_extrema(curve.curvature, curve.segment, rtol)
    turning = segment_turning(curve.s, curve.curvature, curve.segment, curve.theta)
    k = np.asarray(curve.curvature)
    return {
        "g2_error": g2_error(curve.curvature, curve.segment, curve.closed, curve.breaks),
        "interior_extrema": int(per.sum()),
        "extrema_per_segment": per.tolist(),
        "max_abs_curvature": float(np.max(np.abs(k))) if k.size else 0.0,
        "bending_energy": bending_energy(curve.s, curve.curvature, curve.segment),
        "loops": int(np.count_nonzero(turning > np.pi)),
        "max_segment_turn": float(np.max(turning)) if turning.size else 0.0,
        "n_segments": int(per.size),
        "length": float(curve.s[-1] - curve.s[0]) if k.size else 0.0,
    }


def self_intersections(x, y, closed=True):
    """Number of points where a sampled curve crosses or touches itself.

    Counted on the polyline through the samples (consecutive repeats, e.g. a
    segment's end and the next one's start, are one point) with
    :meth:`attneave.stimuli.geometry.contour.Contour.self_intersections` (GEOS).

    Examples
    --------
    >>> import numpy as np
    >>> self_intersections(np.array([0, 1, 1, 0.]), np.array([0, 1, 0, 1.]))  # a bow tie
    1
    >>> self_intersections(np.array([0, 1, 1, 0.]), np.array([0, 0, 1, 1.]))  # a square
    0
    >>> self_intersections(np.array([0, 1, 2, 3.]), np.zeros(4)) > 0  # closed, it runs back over itself
    True
    """
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.geometry.contour import Contour

    pts = np.column_stack([x, y])
    try:
        c = Contour(pts, closed=closed, orient=False)
    except InputError:
        if not closed or len(np.unique(pts, axis=0)) < 3:  # fewer than 3 distinct points: nothing to cross
            return 0
        # a closed curve enclosing no area (it retraces itself): count on the open path that closes it
        c = Contour(np.vstack([pts, pts[:1]]), closed=False, orient=False)
    return int(len(c.self_intersections()))


def self_crossing_segments(x, y, segment, closed=True):
    """Labels of the segments of a sampled curve that cross another segment
    (or themselves), touching at a shared end point not counted.

    Parameters
    ----------
    x, y : ndarray
        Samples, each segment's samples including both its end points.
    segment : ndarray of int
        Segment label of every sample (as in :class:`SampledCurve`).
    closed : bool

    Returns
    -------
    list of int
        Sorted labels; empty when the curve is simple.

    Examples
    --------
    >>> import numpy as np
    >>> x, y = np.array([0, 1, 1, 1, 1, 0, 0, 0.]), np.array([0, 1, 1, 0, 0, 1, 1, 0.])
    >>> self_crossing_segments(x, y, np.array([0, 0, 1, 1, 2, 2, 3, 3]))
    [0, 2]
    """
    import shapely

    xy = np.column_stack([x, y])
    keep = np.r_[True, np.any(xy[1:] != xy[:-1], axis=1)]
    ring = xy[keep]
    if closed and len(ring) > 1 and np.all(ring[0] == ring[-1]):
        ring = ring[:-1]
    if len(ring) < 3 or shapely.is_simple(shapely.LinearRing(ring) if closed else shapely.LineString(ring)):
        return []
    sl = segment_slices(segment)
    labels = [int(segment[q.start]) for q in sl]
    lines = [shapely.LineString(xy[q]) if q.stop - q.start > 1 else shapely.Point(xy[q.start]) for q in sl]
    m = len(lines)
    out = set()
    for i, line in enumerate(lines):
        if not shapely.is_simple(line):
            out.add(labels[i])
    tree = shapely.STRtree(lines)
    pairs = tree.query(lines, predicate="intersects")
    for i, j in zip(*pairs):
        if j <= i:
            continue
        adjacent = j == i + 1 or (closed and i == 0 and j == m - 1)
        if adjacent:
            shared = shapely.intersection(lines[i], lines[j])
            # adjacent segments always share their end point: only more is a crossing
            if shapely.get_type_id(shared) == 0 and (
                np.allclose(shapely.get_coordinates(shared)[0], xy[sl[i].stop - 1])
                or np.allclose(shapely.get_coordinates(shared)[0], xy[sl[i].start])
            ):
                continue
        out.update((labels[i], labels[j]))
    return sorted(out)


class SplineMeasures:
    """The measures a spline result derives from its ``segment_turn`` (range
    of the tangent angle per segment), ``sample(k)`` and solver figures
    (``iterations``, ``g2_error``, ``closure_error``): shared by the QIC
    and the G2 log-aesthetic results, whose segments differ."""

    @property
    def loops(self):
        """Segments whose tangent turns by more than pi."""
        return int(np.count_nonzero(self.segment_turn > np.pi))

    @property
    def max_segment_turn(self):
        """Largest range of the tangent angle on one segment (radians)."""
        return float(np.max(self.segment_turn)) if self.segment_turn.size else 0.0

    @property
    def interior_extrema(self):
        """Curvature extrema strictly inside segments, counted on 32 samples
        per segment (zero by construction: curvature is monotone on every
        segment)."""
        return self.metrics(32)["interior_extrema"]

    def metrics(self, samples=32):
        """:func:`curve_metrics` of ``sample(samples)``, with the solver's own
        figures (``iterations``, ``solver_g2_error``, ``closure_error``)."""
        out = curve_metrics(self.sample(samples))
        out.update(iterations=self.iterations, solver_g2_error=self.g2_error, closure_error=self.closure_error)
        return out
