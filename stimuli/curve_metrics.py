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
    "SampledCurve",
    "segment_slices",
    "interior_extrema",
    "join_jumps",
    "g2_error",
    "bending_energy",
    "segment_turning",
    "curve_metrics",
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


def segment_slices(segment):
    """Slices of consecutive samples sharing a segment label, in order."""
    segment = np.asarray(segment)
    if segment.size == 0:
        return []
    cut = np.flatnonzero(np.diff(segment) != 0) + 1
    starts = np.r_[0, cut]
    stops = np.r_[cut, segment.size]
    return [slice(a, b) for a, b in zip(starts, stops)]


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
    tol = rtol * (np.max(np.abs(k)) if k.size else 0.0)
    counts = []
    for sl in segment_slices(segment):
        d = np.diff(k[sl])
        d = d[np.abs(d) > tol]
        counts.append(int(np.count_nonzero(np.sign(d[1:]) != np.sign(d[:-1]))))
    return np.asarray(counts, dtype=int)


def join_jumps(curvature, segment, closed=True, breaks=()):
    """Absolute curvature jumps at the joins between consecutive segments.

    The joins into segments listed in `breaks` (G0 corners) are skipped.
    """
    k = np.asarray(curvature, dtype=float)
    sls = segment_slices(segment)
    labels = [int(np.asarray(segment)[sl.start]) for sl in sls]
    pairs = list(zip(sls[:-1], sls[1:], labels[1:]))
    if closed and len(sls) > 1:
        pairs.append((sls[-1], sls[0], labels[0]))
    breaks = set(int(b) for b in breaks)
    return np.asarray([abs(k[a.stop - 1] - k[b.start]) for a, b, lab in pairs if lab not in breaks])


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
    total = 0.0
    for sl in segment_slices(segment):
        total += float(np.sum(0.5 * (k2[sl][1:] + k2[sl][:-1]) * np.diff(s[sl])))
    return total


def segment_turning(s, curvature, segment, theta=None):
    """Range (max - min) of the tangent angle within each segment, radians.

    From `theta` when given, otherwise by integrating the curvature.
    """
    s = np.asarray(s, dtype=float)
    k = np.asarray(curvature, dtype=float)
    out = []
    for sl in segment_slices(segment):
        if theta is not None:
            th = np.unwrap(np.asarray(theta, dtype=float)[sl])
        else:
            th = np.r_[0.0, np.cumsum(0.5 * (k[sl][1:] + k[sl][:-1]) * np.diff(s[sl]))]
        out.append(float(np.ptp(th)) if th.size else 0.0)
    return np.asarray(out)


def curve_metrics(curve, rtol=1e-9):
    """All metrics of a :class:`SampledCurve`.

    Returns
    -------
    dict
        ``g2_error`` (max curvature jump at a join / max |k|),
        ``interior_extrema`` (total count), ``extrema_per_segment`` (list),
        ``max_abs_curvature`` (1/px), ``bending_energy`` (1/px),
        ``loops`` (number of segments whose tangent turns by more than pi),
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
        "n_segments": int(per.size),
        "length": float(curve.s[-1] - curve.s[0]) if k.size else 0.0,
    }
