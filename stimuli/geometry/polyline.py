"""Functions of point arrays: turning angles, Gaussian-derivative curvature,
the shoelace area, segment vectors, the nearest point on a polyline and its
self-crossings.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down).
:class:`~attneave.stimuli.geometry.contour.Contour` is built on these.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number, check_flag, check_points

__all__ = ["turning_angles", "gaussian_curvature", "shoelace", "edges", "bounds", "unchecked_nearest",
           "unchecked_crossings"]


def turning_angles(points, closed=True):
    """Signed turning angle at every vertex of a polyline.

    Parameters
    ----------
    points : (N, 2) array_like
        ``(x, y)`` in image pixels (y down).
    closed : bool
        Whether the last point joins the first.

    Returns
    -------
    (N,) ndarray
        Angle in radians in (-pi, pi] by which the direction of travel turns at
        each vertex; left turns *as seen on the screen* are positive, so a
        closed contour stored counter-clockwise on the screen turns by +2*pi in
        all and its convex vertices have positive angles. The two ends of an
        open polyline have no turning angle and get NaN.

    Notes
    -----
    Computed as ``atan2(cross, dot)`` of consecutive segment vectors, with the
    cross product's sign flipped because y points down. It is exact for a
    polygon and finite at corners, where curvature is not (the paper's eq. 6).

    Raises
    ------
    InputError
        `points` not an (N, 2) array of finite numbers, fewer than 3 points
        (closed) or 2 (open), or `closed` not a bool.

    Examples
    --------
    >>> turning_angles(np.array([(0.0, 0.0), (1.0, 0.0), (0.0, -1.0)])).round(4).tolist()  # ccw on screen
    [1.5708, 2.3562, 2.3562]
    """
    closed = check_flag(closed, "closed")
    p = check_points(points, "points", min_points=3 if closed else 2)
    return unchecked_turning_angles(p, closed)


def unchecked_turning_angles(p, closed):
    """:func:`turning_angles` of checked (N, 2) float points."""
    d = edges(p, closed)  # d[i] = p[i+1] - p[i]
    if closed:
        dp = np.concatenate((d[-1:], d[:-1]))  # segment arriving at vertex i
        dn = d
    else:
        dp, dn = d[:-1], d[1:]
    cross = dp[:, 0] * dn[:, 1] - dp[:, 1] * dn[:, 0]
    dot = dp[:, 0] * dn[:, 0] + dp[:, 1] * dn[:, 1]
    # minus: y points down, so a left turn on the screen has a negative cross product
    a = np.arctan2(np.negative(cross, out=cross), dot)
    if not closed:
        a = np.concatenate(([np.nan], a, [np.nan]))
    return a


def gaussian_curvature(points, sigma):
    """Curvature of a closed, uniformly sampled curve by periodic Gaussian derivatives.

    The coordinates are differentiated in the Fourier domain with the
    derivatives of a periodic Gaussian of standard deviation `sigma` (in
    pixels of arc length). Unlike ``scipy.ndimage.gaussian_filter1d(order=2)``,
    whose truncated kernel does not sum to zero, the spectral derivative
    annihilates constants and linear trends exactly, so a circle's curvature
    comes out at 1/R up to the smoothing bias of order (sigma/R)^2.

    Parameters
    ----------
    points : (N, 2) array_like
        ``(x, y)`` in image pixels (y down), equally spaced along the arc,
        closed (first point not repeated), counter-clockwise on the screen.
    sigma : float
        Scale of the Gaussian in pixels of arc length (> 0).

    Returns
    -------
    (N,) ndarray
        Signed curvature in 1/px, positive where convex.

    References
    ----------
    .. [1] Mokhtarian, F., & Mackworth, A. K. (1992). A theory of multiscale,
           curvature-based shape representation for planar curves. IEEE PAMI
           14(8), 789-805.

    Raises
    ------
    InputError
        `points` not an (N, 2) array of finite numbers or fewer than 3 of
        them, all points equal, or `sigma` not a finite number > 0.
    """
    p = check_points(points, "points", min_points=3)
    sigma = as_number(sigma, "sigma", gt=0)
    if not (p != p[0]).any():
        raise InputError("points: all points are equal; a curve needs at least 2 distinct points")
    return unchecked_gaussian_curvature(p, sigma)


def unchecked_gaussian_curvature(p, sigma):
    """:func:`gaussian_curvature` of checked points and sigma."""
    n = len(p)
    seg = np.hypot(*np.diff(np.vstack([p, p[:1]]), axis=0).T)
    length = seg.sum()
    # angular frequency per pixel of arc length for each FFT bin
    w = 2 * np.pi * np.fft.fftfreq(n, d=length / n)
    g = np.exp(-0.5 * (w * sigma) ** 2)
    z = np.fft.fft(p[:, 0] + 1j * p[:, 1])
    d1 = np.fft.ifft(z * g * (1j * w))
    d2 = np.fft.ifft(z * g * (-(w**2)))
    # y points down, so the screen-geometric cross product has the opposite sign
    cross = d1.real * d2.imag - d1.imag * d2.real
    speed = np.abs(d1)
    return -cross / speed**3


def shoelace(points):
    """Signed shoelace area of a closed polygon in the coordinates given.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices ``(x, y)``, first point not repeated (N >= 1).

    Returns
    -------
    float
        ``0.5 * sum(x_i y_{i+1} - x_{i+1} y_i)``: positive for a polygon
        running counter-clockwise in a y-up frame, which is *clockwise on the
        screen* for image coordinates (y down); :attr:`Contour.signed_area`
        flips the sign so that counter-clockwise on the screen is positive.

    Examples
    --------
    >>> shoelace(np.array([(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)]))
    2.0

    Raises
    ------
    InputError
        Not an (N, 2) array of numbers, no points, or non-finite
        coordinates (or an area beyond the float range).
    """
    # cheap checks only (the renderer calls this per ring): shape here, finiteness on the result
    if isinstance(points, np.ndarray) and points.dtype == np.float64 and points.ndim == 2 and points.shape[1] == 2:
        p = points
    else:
        p = check_points(points)
    if not len(p):
        raise InputError("points: need at least 1 point(s), got 0")
    a = unchecked_shoelace(p)
    if not np.isfinite(a):
        check_points(p)  # names the non-finite row
        raise InputError(f"points: the area overflows ({a}); rescale the coordinates")
    return a


def unchecked_shoelace(points):
    """:func:`shoelace` of checked (N, 2) float points."""
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1])


def edges(p, closed):
    """Segment vectors ``p[i+1] - p[i]`` (closed: including the closing one).

    Parameters
    ----------
    p : (N, 2) ndarray of float
        Checked points ``(x, y)`` in image pixels (no validation here: an
        inner-loop helper).
    closed : bool
        Include the segment from the last point back to the first.

    Returns
    -------
    (N, 2) or (N - 1, 2) ndarray
    """
    if not closed:
        return p[1:] - p[:-1]
    d = np.empty_like(p)
    np.subtract(p[1:], p[:-1], out=d[:-1])
    np.subtract(p[0], p[-1], out=d[-1])
    return d


def bounds(points):
    """``(xmin, ymin, xmax, ymax)`` of (N, 2) points.

    Parameters
    ----------
    points : (N, 2) ndarray of float
        ``(x, y)`` in image pixels, N >= 1 (no validation here: an
        inner-loop helper).

    Returns
    -------
    tuple of 4 float

    Reduces each coordinate as a strided 1-D view: numpy's ``min(axis=0)``
    on an (N, 2) array runs an inner loop of length 2 and is about 40x
    slower on a million points.

    Examples
    --------
    >>> bounds(np.array([(1.0, 5.0), (3.0, -2.0)]))
    (1.0, -2.0, 3.0, 5.0)
    """
    x, y = points[:, 0], points[:, 1]
    return float(x.min()), float(y.min()), float(x.max()), float(y.max())


def unchecked_nearest(q, p, d, cum, closed, chunk=2_000_000):
    """Nearest point of the polyline `p` (segment vectors `d`, cumulative lengths `cum`)
    to each of the checked points `q`: ``(nearest, t, distance)``, as
    :meth:`~attneave.stimuli.geometry.contour.Contour.project` documents.

    The nearest segment of each point is the first of those at the least
    distance, found among a few candidates from a k-d tree of the segments'
    midpoints where that provably suffices (many points on a long polyline),
    else by trying every segment; the values are the same either way."""
    a = p[: len(d)]
    # x and y apart: (M, N) arrays of each, rather than (M, N, 2) arrays
    # reduced over a last axis of 2, which numpy does several times slower
    seg = tuple(np.ascontiguousarray(v) for v in (a[:, 0], a[:, 1], d[:, 0], d[:, 1]))
    L2 = seg[2] * seg[2] + seg[3] * seg[3]
    j = np.zeros(len(q), np.intp)
    rest = np.arange(len(q))
    if len(d) > _CANDIDATES and len(q) * len(d) >= _TREE_PAIRS:
        rest = _nearest_by_tree(q, a, d, seg, L2, j)
    step = max(1, chunk // max(len(d), 1))
    for lo in range(0, len(rest), step):
        rows = rest[lo : lo + step]
        j[rows] = np.argmin(_distances2(q[rows], seg, L2)[1], axis=1)
    u, d2 = _distances2(q, tuple(v[j] for v in seg), L2[j], paired=True)
    nearest = a[j] + u[:, None] * d[j]
    tt = (cum[j] + u * np.sqrt(L2[j])) / cum[-1] if len(q) else np.empty(0)
    if closed:
        tt = np.mod(tt, 1.0)
    return nearest, tt, np.sqrt(d2)


#: Segments tried per point on the k-d tree's path, and the points x segments from which it is taken.
_CANDIDATES = 8
_TREE_PAIRS = 20_000


def _distances2(q, seg, L2, paired=False):
    """Position u in [0, 1] along each segment of its nearest point to each of `q`, and the squared
    distance: (M, N) arrays, or (M,) with `paired` (point i against segment i). One formula for
    every path, so that the paths agree to the last bit."""
    ax, ay, dx, dy = seg
    if not paired:
        ax, ay, dx, dy, L2 = (v[None, :] for v in (ax, ay, dx, dy, L2))
        rx, ry = q[:, :1] - ax, q[:, 1:] - ay
    else:
        rx, ry = q[:, 0] - ax, q[:, 1] - ay
    u = rx * dx
    u += ry * dy
    u /= L2
    np.clip(u, 0.0, 1.0, out=u)
    rx -= u * dx
    ry -= u * dy
    d2 = rx * rx
    d2 += ry * ry
    return u, d2


def _nearest_by_tree(q, a, d, seg, L2, j):
    """Set `j` (the nearest segment) of the points whose nearest segment is among the
    :data:`_CANDIDATES` with the nearest midpoints; return the indices of the others.

    A segment whose midpoint is r from a point is at least ``r - h`` from it (h the largest
    half-length), so when the farthest candidate's midpoint is more than ``h`` beyond the best
    candidate's distance (with a margin for rounding), no other segment can be as near."""
    from scipy.spatial import cKDTree

    r, cand = cKDTree(a + 0.5 * d).query(q, k=_CANDIDATES)
    cand = np.sort(cand, axis=1)  # ties go to the first segment, as with every segment tried
    m, k = cand.shape
    _, d2 = _distances2(np.repeat(q, k, axis=0), tuple(v[cand.ravel()] for v in seg), L2[cand.ravel()], paired=True)
    d2 = d2.reshape(m, k)
    best = np.argmin(d2, axis=1)
    dist = np.sqrt(d2[np.arange(m), best])
    h = 0.5 * float(np.sqrt(L2.max()))
    sure = r[:, -1] - h > dist + 1e-9 * (1.0 + dist + h)
    j[sure] = cand[sure, best[sure]]
    return np.flatnonzero(~sure)


def unchecked_crossings(p, closed):
    """``(x, y)`` where the polyline `p` (closed: joined back to its first point) crosses or
    touches itself, as :meth:`~attneave.stimuli.geometry.contour.Contour.self_intersections` documents."""
    import shapely

    ring = np.vstack([p, p[:1]]) if closed else p
    line = shapely.LineString(ring)
    if shapely.is_simple(line):
        return np.empty((0, 2))
    # self-noding the line yields the crossing points as shared nodes
    noded = shapely.node(line)
    coords = [np.asarray(g.coords) for g in shapely.get_parts(noded)]
    ends = np.vstack([np.vstack([c[0], c[-1]]) for c in coords])
    uniq, counts = np.unique(ends.round(9), axis=0, return_counts=True)
    start = ring[0].round(9)
    mask = counts > 2
    if not closed:
        mask |= (counts >= 2) & ~np.all(uniq == start, axis=1) & ~np.all(uniq == ring[-1].round(9), axis=1)
    out = uniq[mask]
    if len(out) == 0:  # touching without a node (e.g. overlap); report a vertex of it
        out = ends[:1]
    return out
