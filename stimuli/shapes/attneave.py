"""Attneave & Arnoult (1956) Method 1 random polygons and their smoothed,
curved versions.

Coordinates are ``(x, y)`` with y pointing DOWN, in grid cells around the
polygon's own centre (``params["centre"]``); every generator takes its
randomness from `rng`, a `numpy.random.Generator` or an integer seed, and
returns ``(contour, params)`` (see :mod:`attneave.stimuli.shapes.generators`).

References
----------
.. [1] Attneave, F., & Arnoult, M. D. (1956). The quantitative study of
       shape and pattern perception. Psychological Bulletin 53, 452-471.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.shapes._limits import MAX_GRID, MAX_POINTS
from attneave.stimuli.validate import as_int, as_number, as_points, as_rng

__all__ = ["attneave_polygon", "attneave_curved", "smooth_closed", "SMOOTH_METHODS"]

SMOOTH_METHODS = ("cubic", "bspline", "qic")


def _vertex_angles(p):
    """Unsigned angle (degrees, in [0, 180]) between the two sides at each vertex.

    180 means the sides are collinear (no visible corner); small values are
    spikes. A reflex vertex of interior angle 270 degrees gets 90, so limits
    on it bound spikes and flat corners whatever their sign.
    """
    u = np.roll(p, 1, axis=0) - p
    v = np.roll(p, -1, axis=0) - p
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    dot = (u * v).sum(axis=1)
    return np.degrees(np.abs(np.arctan2(cross, dot)))


def _ring_is_simple(p):
    import shapely

    return bool(shapely.is_simple(shapely.LineString(np.vstack([p, p[:1]]))))


def _method1_attempt(rng, n_points, grid, min_angle, max_angle):
    """One draw of Attneave & Arnoult's Method 1; the vertex array or None.

    None when the draw is degenerate (all points collinear), when a point
    cannot be joined into any side without a crossing or an angle outside
    the limits, or when the finished polygon breaks an angle limit.
    """
    from scipy.spatial import ConvexHull, QhullError

    cells = rng.choice(grid * grid, size=n_points, replace=False)
    pts = np.column_stack([cells % grid, cells // grid]).astype(float)
    try:
        hull = ConvexHull(pts)
    except QhullError:
        return None
    ring = [int(i) for i in hull.vertices]
    # joining a point (inside the hull) into a side only narrows the angle at
    # a hull vertex, so a hull spike below the limit can never be mended
    if _vertex_angles(pts[ring]).min() < min_angle:
        return None
    rest = np.setdiff1d(np.arange(n_points), ring)
    # A&A join the remaining points one at a time, in the (random) order of
    # the random-number table, each into a side chosen at random; a side whose
    # new lines would cross another line is passed over for another one. So
    # is a side whose joining would put the new vertex's angle, or the angle
    # at either end of the side, outside the limits (an end already outside
    # them may stay so: a later join may still mend it; the final check
    # decides).
    for q in rng.permutation(rest):
        q = int(q)
        for side in rng.permutation(len(ring)):
            m = len(ring)
            a, b = ring[side], ring[(side + 1) % m]
            before = _vertex_angles(pts[[ring[side - 1], a, b, ring[(side + 2) % m]]])[1:3]
            after = _vertex_angles(pts[[ring[side - 1], a, q, b, ring[(side + 2) % m]]])[1:4]
            ok_after = (after >= min_angle) & (after <= max_angle)
            ok_before = (before >= min_angle) & (before <= max_angle)
            if not ok_after[1] or (ok_before[0] and not ok_after[0]) or (ok_before[1] and not ok_after[2]):
                continue
            cand = ring[: side + 1] + [q] + ring[side + 1 :]
            if _ring_is_simple(pts[cand]):
                ring = cand
                break
        else:
            return None
    p = pts[ring]
    ang = _vertex_angles(p)
    if ang.min() < min_angle or ang.max() > max_angle:
        return None
    return p


def _check_attneave(n_points, grid, min_angle, max_angle, max_tries):
    n_points = as_int(n_points, "n_points", lo=3)
    grid = as_int(grid, "grid", lo=2, hi=MAX_GRID)
    if n_points > grid * grid:
        raise InputError(f"n_points: a {grid}x{grid} grid has only {grid * grid} points, got {n_points}")
    min_angle = as_number(min_angle, "min_angle", ge=0, lt=180)
    max_angle = as_number(max_angle, "max_angle", gt=0, le=180)
    if not min_angle < max_angle:
        raise InputError(f"min_angle: must be < max_angle ({max_angle}), got {min_angle}")
    max_tries = as_int(max_tries, "max_tries", lo=1)
    return n_points, grid, min_angle, max_angle, max_tries


def attneave_polygon(rng, n_points=12, grid=100, min_angle=10.0, max_angle=170.0, max_tries=1000):
    """A random polygon by Attneave & Arnoult's (1956) Method 1.

    1. `n_points` distinct points are drawn at random from a `grid` x `grid`
       lattice (A&A: a 100 x 100 sheet of graph paper and a table of random
       numbers).
    2. The outermost points are joined into their convex hull.
    3. The remaining points, in random order, are each joined into a side
       of the current polygon chosen at random: the side is removed and the
       point joined to its two ends. A side whose new lines would cross (or
       touch) the polygon is passed over and another drawn.
    4. Angle limits (after Collin & McMullen, 2002, and PEBL's
       ``MakeAttneave``): the angle between the two sides at every vertex
       must lie in [`min_angle`, `max_angle`] degrees, which excludes spikes
       and corners too flat to be seen. ``min_angle=0, max_angle=180`` is A&A
       as published.

    A draw that dead-ends (a point that fits no side) or breaks an angle
    limit is thrown away and the next is drawn from the same `rng`.

    Parameters
    ----------
    rng : numpy.random.Generator or int
        The only source of randomness (an integer is a seed).
    n_points : int
        Number of points, which is the number of vertices (>= 3, at most
        ``grid**2``).
    grid : int
        Side of the lattice, in [2, 1e6]; coordinates are integers in
        [0, grid - 1].
    min_angle, max_angle : float
        Limits in degrees on the angle between the sides at each vertex.
    max_tries : int
        Draws before giving up.

    Returns
    -------
    contour : Contour
        The polygon: its vertices are the drawn grid points, as ``(x, y)``
        grid coordinates with y down, counter-clockwise on the screen.
    params : dict
        ``n_points, grid, min_angle, max_angle, max_tries, tries, hull_size,
        centre`` (the grid centre).

    Raises
    ------
    InputError
        Bad parameters, or no valid polygon in `max_tries` draws.

    References
    ----------
    .. [1] Attneave, F., & Arnoult, M. D. (1956). The quantitative study of
           shape and pattern perception. Psychological Bulletin 53(6), 452-471.
    .. [2] Collin, C. A., & McMullen, P. A. (2002). Using Matlab to generate
           families of similar Attneave shapes. Behavior Research Methods,
           Instruments, & Computers 34(1), 55-68.

    Examples
    --------
    >>> import numpy as np
    >>> c, p = attneave_polygon(np.random.default_rng(1), n_points=8)
    >>> len(c), c.is_simple(), p["grid"]
    (8, True, 100)
    """
    rng = as_rng(rng)
    n_points, grid, min_angle, max_angle, max_tries = _check_attneave(n_points, grid, min_angle, max_angle, max_tries)
    for tries in range(1, max_tries + 1):
        p = _method1_attempt(rng, n_points, grid, min_angle, max_angle)
        if p is not None:
            return _attneave_result(p, n_points, grid, min_angle, max_angle, max_tries, tries)
    raise InputError(
        f"attneave_polygon: no simple polygon with {n_points} points on a {grid}x{grid} grid and angles in "
        f"[{min_angle:g}, {max_angle:g}] degrees in {max_tries} tries; widen the angle limits or raise max_tries"
    )


def _attneave_result(p, n_points, grid, min_angle, max_angle, max_tries, tries):
    from scipy.spatial import ConvexHull

    c = Contour(p, simple=True)
    params = dict(
        n_points=n_points,
        grid=grid,
        min_angle=min_angle,
        max_angle=max_angle,
        max_tries=max_tries,
        tries=tries,
        hull_size=int(len(ConvexHull(p).vertices)),
        centre=[(grid - 1) / 2.0, (grid - 1) / 2.0],
    )
    return c, params


def attneave_curved(
    rng,
    n_points=12,
    grid=100,
    min_angle=10.0,
    max_angle=170.0,
    max_tries=1000,
    method="cubic",
    samples_per_edge=32,
):
    """An Attneave & Arnoult polygon and its smoothed ("curved") version.

    Polygons are drawn as in :func:`attneave_polygon` until one whose smoothed
    version (see :func:`smooth_closed`) is simple and stays near the polygon
    (within its bounding box grown by 10% of its size on every side: an
    interpolating spline through sharp corners can swing far out, the
    clothoid QIC spline most of all) and, for ``'qic'``, converges. Both are
    returned.

    Parameters
    ----------
    rng : numpy.random.Generator or int
        The only source of randomness (an integer is a seed).
    n_points : int
        Number of vertices (>= 3, at most ``grid**2``).
    grid : int
        Side of the lattice, in [2, 1e6]; vertices are at integer coordinates
        in [0, grid - 1].
    min_angle, max_angle : float
        Limits in degrees on the angle between the two sides at each vertex
        of the polygon (see :func:`attneave_polygon`).
    max_tries : int
        Draws before giving up (>= 1); a draw counts whether the polygon or
        its smoothing failed.
    method : {'cubic', 'bspline', 'qic'}
        How the polygon is smoothed (see :func:`smooth_closed`).
    samples_per_edge : int
        Points of the curve per polygon side (>= 2; ``n_points *
        samples_per_edge`` at most 1e6).

    Returns
    -------
    polygon : Contour
        The polygon (grid coordinates, y down).
    curved : Contour
        The smooth closed curve made from the same vertices.
    params : dict
        Those of :func:`attneave_polygon` and of :func:`smooth_closed`
        (``method, samples_per_edge``), with ``tries`` counting every draw.

    Raises
    ------
    InputError
        A bad parameter, naming it, or no polygon whose smoothing is simple
        and stays near it in `max_tries` draws.

    Examples
    --------
    >>> polygon, curved, p = attneave_curved(1, n_points=8, samples_per_edge=16)
    >>> len(curved) == 8 * 16, curved.is_simple(), p["method"]
    (True, True, 'cubic')
    """
    rng = as_rng(rng)
    n_points, grid, min_angle, max_angle, max_tries = _check_attneave(n_points, grid, min_angle, max_angle, max_tries)
    if method not in SMOOTH_METHODS:
        raise InputError(f"method: expected one of {', '.join(SMOOTH_METHODS)}, got {method!r}")
    _check_samples(samples_per_edge, n_points)
    for tries in range(1, max_tries + 1):
        p = _method1_attempt(rng, n_points, grid, min_angle, max_angle)
        if p is None:
            continue
        polygon, params = _attneave_result(p, n_points, grid, min_angle, max_angle, max_tries, tries)
        try:
            curved, sparams = smooth_closed(polygon.points, method=method, samples_per_edge=samples_per_edge)
        except _NoCurve:
            continue
        if curved.is_simple() and _stays_near(curved, polygon):
            params.update(sparams)
            return polygon, curved, params
    raise InputError(
        f"attneave_curved: no polygon with {n_points} points whose {method} smoothing is simple in "
        f"{max_tries} tries; raise max_tries or use method 'bspline'"
    )


_SLACK = 0.1  # a curved version may leave its polygon's bounding box by this fraction of its size


def _stays_near(curve, polygon):
    """Whether `curve` stays within the polygon's bounding box grown by 10% of its size
    (Contours or (N, 2) point arrays)."""
    c = np.asarray(getattr(curve, "points", curve))
    p = np.asarray(getattr(polygon, "points", polygon))
    x0, y0, x1, y1 = (*p.min(axis=0), *p.max(axis=0))
    gx, gy = _SLACK * (x1 - x0), _SLACK * (y1 - y0)
    cx0, cy0, cx1, cy1 = (*c.min(axis=0), *c.max(axis=0))
    return cx0 >= x0 - gx and cy0 >= y0 - gy and cx1 <= x1 + gx and cy1 <= y1 + gy


def smooth_closed(points, method="cubic", samples_per_edge=32):
    """A smooth closed curve made from the vertices of a polygon.

    Parameters
    ----------
    points : (N, 2) array_like
        Polygon vertices ``(x, y)`` (y down), in order, first not repeated.
    method : {'cubic', 'bspline', 'qic'}
        ``'cubic'``: the periodic C2 cubic spline *through* the vertices, with
        centripetal parameterisation (knot spacing the square root of the
        chord), which keeps the curve from looping between close vertices
        (Lee 1989). ``'bspline'``: the uniform periodic cubic B-spline with
        the vertices as control points; C2, it stays inside the convex hull
        of each four consecutive vertices and so rounds the corners without
        passing through them (what Chaikin's corner cutting converges to, one
        degree higher). ``'qic'``: the project's robust QIC spline
        (:func:`attneave.stimuli.curves.qic.spline.qic_spline`): clothoid segments, G2
        except at the few vertices where that would loop or swing out.
    samples_per_edge : int
        Points per polygon side in the output (>= 2; ``N * samples_per_edge``
        at most 1e6).

    Returns
    -------
    contour : Contour
        ``N * samples_per_edge`` points; with ``'cubic'`` and ``'qic'`` the
        vertex ``i`` is point ``i * samples_per_edge`` exactly (before
        re-orientation, which keeps the first point). Not checked for
        simplicity.
    params : dict
        ``method, samples_per_edge``.

    Raises
    ------
    InputError
        Points that are not an (N, 2) array of finite numbers with N >= 3,
        consecutive vertices that coincide (``'cubic'``), or a bad `method`
        or `samples_per_edge`.

    References
    ----------
    .. [1] Lee, E. T. Y. (1989). Choosing nodes in parametric curve
           interpolation. Computer-Aided Design 21(6), 363-370.
    """
    p = as_points(points, "points", min_points=3)
    m = _check_samples(samples_per_edge, len(p))
    n = len(p)
    if method == "cubic":
        from scipy.interpolate import CubicSpline

        chord = np.hypot(*np.diff(np.vstack([p, p[:1]]), axis=0).T)
        if np.any(chord == 0):
            raise InputError("points: consecutive vertices coincide")
        knots = np.concatenate([[0.0], np.cumsum(np.sqrt(chord))])
        spline = CubicSpline(knots, np.vstack([p, p[:1]]), bc_type="periodic")
        frac = np.arange(m) / m
        u = (knots[:-1, None] + frac[None, :] * np.diff(knots)[:, None]).ravel()
        out = spline(u)
        out[::m] = p  # the knots exactly, not to round-off
    elif method == "bspline":
        t = np.arange(m) / m
        basis = np.column_stack([(1 - t) ** 3, 3 * t**3 - 6 * t**2 + 4, -3 * t**3 + 3 * t**2 + 3 * t + 1, t**3]) / 6.0
        idx = (np.arange(n)[:, None] + np.arange(-1, 3)[None, :]) % n  # P[i-1], P[i], P[i+1], P[i+2]
        out = np.einsum("tk,ikd->itd", basis, p[idx]).reshape(-1, 2)
    elif method == "qic":
        out = _qic(p, m)
    else:
        raise InputError(f"method: expected one of {', '.join(SMOOTH_METHODS)}, got {method!r}")
    return Contour(out, orient=True), dict(method=method, samples_per_edge=m)


def _check_samples(samples_per_edge, n):
    return as_int(samples_per_edge, "samples_per_edge", lo=2, hi=max(2, MAX_POINTS // n))


class _NoCurve(InputError):
    """The smoothing did not converge for these vertices (draw another polygon)."""


# Robust QIC settings tried in turn, (corner_turn, max_tangent_deviation): the
# default rule first; where its curve still leaves the polygon's box or crosses itself, G0
# corners at turns over 90 degrees and tangents held closer to the bisector.
_QIC_STEPS = ((None, None), (0.5 * np.pi, 0.125 * np.pi), (0.5 * np.pi, 0.0))


def _qic(p, m):
    from attneave.stimuli.curves.qic.spline import ConvergenceError, qic_spline

    for corner_turn, deviation in _QIC_STEPS:
        try:
            spline = qic_spline(p, closed=True, corner_turn=corner_turn, max_tangent_deviation=deviation)
        except ConvergenceError as exc:
            raise _NoCurve(str(exc)) from None
        sc = spline.sample(m + 1)
        # segment i runs from vertex i to vertex i+1, sampled at m+1 points
        # equally spaced in arc length, both ends included: keep all but the last
        xy = np.column_stack([sc.x, sc.y]).reshape(len(p), m + 1, 2)[:, :m].reshape(-1, 2)
        if _stays_near(xy, p) and Contour(xy, orient=False).is_simple():
            break
    xy[::m] = p
    return xy
