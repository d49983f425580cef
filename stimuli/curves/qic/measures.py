"""The robust QIC rule's measures of the points' polygon and of a fit's
samples: turns, reference deviations and mean side of the polygon, whether
it is simple, each segment's bulge and the segments that cross.

The rule itself (which nodes give up curvature continuity, and why these
measures) is :mod:`attneave.stimuli.curves.qic.rule`, which re-exports them.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.euler import wrap_angle
from attneave.stimuli.curves.metrics import self_crossing_segments

__all__ = [
    "polygon_turns",
    "polygon_is_simple",
    "mean_side",
    "polygon_measures",
    "reference_deviation",
    "segment_bulge",
    "crossing_segments",
]


def polygon_turns(P, closed, phi=None):
    """Absolute turning angle of the polygon at every node (radians; 0 at the
    ends of an open curve); `phi`: its sides' directions, if known.

    Examples
    --------
    >>> polygon_turns(np.array([[0, 0], [1, 0], [1, 1], [0, 1.]]), True).round(4).tolist()
    [1.5708, 1.5708, 1.5708, 1.5708]
    """
    if phi is None:
        phi = _side_angles(P, closed)
    if closed:
        d = np.empty_like(phi)
        d[1:] = phi[1:] - phi[:-1]
        d[0] = phi[0] - phi[-1]
        return np.abs(wrap_angle(d))
    return np.r_[0.0, np.abs(wrap_angle(np.diff(phi))), 0.0]


def _sides(P, closed):
    """x and y steps of every side of the polygon, from each point to the
    next (N sides when closed, N - 1 when open), by 1-D slices: np.roll on
    (N, 2) arrays costs more than the arithmetic at the sizes the rule sees."""
    x, y = P[:, 0], P[:, 1]
    if not closed:
        return x[1:] - x[:-1], y[1:] - y[:-1]
    dx, dy = np.empty_like(x), np.empty_like(y)
    np.subtract(x[1:], x[:-1], out=dx[:-1])
    np.subtract(y[1:], y[:-1], out=dy[:-1])
    dx[-1], dy[-1] = x[0] - x[-1], y[0] - y[-1]
    return dx, dy


def mean_side(P, closed, r=None):
    """The mean length of the polygon's sides (`r`: their lengths, if known),
    the scale of :func:`segment_bulge`.

    Examples
    --------
    >>> mean_side(np.array([[0, 0], [3, 0], [3, 4.]]), closed=True)
    4.0
    >>> mean_side(np.array([[0, 0], [3, 0], [3, 4.]]), closed=False)
    3.5
    """
    if r is None:
        dx, dy = _sides(P, closed)
        r = np.hypot(dx, dy)
    return float(np.add.reduce(r)) / r.size


def polygon_measures(P, closed, tangents):
    """:func:`polygon_turns`, :func:`reference_deviation` and :func:`mean_side`
    of the points at once, the sides and their directions computed once
    (the same values: where the polygon is open its turns take their own
    directions, as numpy's arctan2 may round the last element of an array
    differently from the same element of a longer one).

    Returns
    -------
    turns, reference_deviation : ndarray
        Per node.
    mean_side : float

    Examples
    --------
    >>> from attneave.stimuli.curves.points import bisector_tangents
    >>> P = np.array([[0, 0], [2, 0], [2, 2], [0, 2.]])
    >>> turns, ref, h = polygon_measures(P, True, bisector_tangents(P, True))
    >>> np.allclose(turns, polygon_turns(P, True)), np.allclose(ref, np.pi / 4), h
    (True, True, 2.0)
    """
    dx, dy = _sides(P, True)
    phi = np.arctan2(dy, dx)
    turns = polygon_turns(P, closed, phi if closed else None)
    r = np.hypot(dx, dy) if closed else np.hypot(dx[:-1], dy[:-1])
    return turns, reference_deviation(P, tangents, phi), mean_side(P, closed, r)


def _side_angles(P, closed):
    """Direction (radians) of every side of the polygon (see :func:`_sides`)."""
    dx, dy = _sides(P, closed)
    return np.arctan2(dy, dx)


def polygon_is_simple(P, closed):
    """Whether the polygon (closed) or polyline of the points is simple (GEOS)."""
    import shapely

    # the vectorised constructors: the geometry classes cost more than GEOS's test at N = 30
    return bool(shapely.is_simple(shapely.linearrings(P) if closed else shapely.linestrings(P)))


def reference_deviation(P, tangents, phi=None):
    """Per node of a closed polygon (or of an open one, its last value
    unused): the larger angle between the chord from it to the next point
    and the bisector tangents at the chord's ends, the deviation from the
    chord that no smooth curve with those tangents can avoid (step 3b).
    `phi`: the directions of the closed polygon's sides, if known.

    Examples
    --------
    On a square the bisector tangents make pi/4 with every side:

    >>> from attneave.stimuli.curves.points import bisector_tangents
    >>> P = np.array([[0, 0], [1, 0], [1, 1], [0, 1.]])
    >>> reference_deviation(P, bisector_tangents(P, True)).round(4).tolist()
    [0.7854, 0.7854, 0.7854, 0.7854]
    """
    if phi is None:
        phi = _side_angles(P, True)
    n = len(tangents)
    # both ends' angles to the chord in one array: one wrap_angle (elementwise exact) instead of two
    d = np.empty(2 * n)
    np.subtract(tangents, phi, out=d[:n])
    np.subtract(tangents[1:], phi[:-1], out=d[n:-1])
    d[-1] = tangents[0] - phi[-1]
    d = np.abs(wrap_angle(d))
    return np.maximum(d[:n], d[n:])


def segment_bulge(curve, P, closed=True):
    """Largest distance of each segment's samples from the straight line
    through its end points (its chord), divided by the mean chord length.

    Parameters
    ----------
    curve : SampledCurve
        Samples of a spline through `P`, segment by segment in order, each
        labelled by the index of the point where it starts.
    P : ndarray, shape (N, 2)
        The points.
    closed : bool
        Whether the polygon of the points is closed (its mean chord then
        includes the side from the last point to the first).

    Returns
    -------
    ndarray
        One value per segment, in order of appearance.

    Examples
    --------
    A half circle over its diameter bulges by half the chord:

    >>> from types import SimpleNamespace
    >>> t = np.linspace(np.pi, 0, 101)
    >>> c = SimpleNamespace(x=np.cos(t), y=np.sin(t), segment=np.zeros(101, int))
    >>> segment_bulge(c, np.array([[-1.0, 0.0], [1.0, 0.0]]), closed=False).round(6).tolist()
    [0.5]
    """
    seg = np.asarray(curve.segment)
    starts = np.flatnonzero(np.diff(seg, prepend=-1))
    dx, dy = _sides(P, closed)
    r = np.hypot(dx, dy)
    h = mean_side(P, closed, r)
    # per sample, the chord of its segment (1-D gathers: cheaper than rows of P)
    cx, cy, ux, uy = P[:, 0][seg], P[:, 1][seg], (dx / r)[seg], (dy / r)[seg]
    # |cross product with the unit chord| is the distance from the chord's line
    cross = np.abs((curve.x - cx) * uy - (curve.y - cy) * ux)
    return np.maximum.reduceat(cross, starts) / h


def crossing_segments(start, xy, closed, sample, polygon_simple=None):
    """Indices (into the segment arrays, whose start nodes are `start`) of
    the segments that cross another segment (step 3c; `sample`: the
    samples as a SampledCurve, or a callable that makes it); none where
    ``polygon_simple()`` (asked only when the curve crosses itself) is
    False: the polygon of the points crosses itself too.

    GEOS's simplicity test runs on the samples `xy` ((n, 2), segment by
    segment in order) as they are: the segments' shared end points repeat,
    which GEOS ignores, so the copy without them that
    :func:`~attneave.stimuli.curves.metrics.self_crossing_segments` makes (and its
    segment-by-segment search on the SampledCurve that ``sample()`` gives)
    is needed only when the curve does cross itself (5x cheaper at N = 1000
    on a simple curve).

    Examples
    --------
    A figure eight of four straight segments: the first and third cross.

    >>> from attneave.stimuli.curves.metrics import SampledCurve
    >>> x, y = np.array([0, 1, 1, 1, 1, 0, 0, 0.]), np.array([0, 1, 1, 0, 0, 1, 1, 0.])
    >>> seg = np.array([0, 0, 1, 1, 2, 2, 3, 3])
    >>> curve = lambda: SampledCurve(s=np.arange(8.0), x=x, y=y, curvature=np.zeros(8), segment=seg, closed=True)
    >>> crossing_segments(np.arange(4), np.c_[x, y], True, curve).tolist()
    [0, 2]
    """
    import shapely

    if len(xy) >= 4 and shapely.is_simple(shapely.linearrings(xy) if closed else shapely.linestrings(xy)):
        return np.empty(0, np.intp)
    if polygon_simple is not None and not polygon_simple():
        return np.empty(0, np.intp)
    curve = sample() if callable(sample) else sample
    hits = self_crossing_segments(curve.x, curve.y, curve.segment, curve.closed)
    return np.flatnonzero(np.isin(start, np.fromiter(hits, dtype=np.intp, count=len(hits))))
