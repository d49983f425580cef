"""Shape generators: random polygons, radial-frequency patterns, Fourier shapes, ...

Every generator takes its randomness from a `numpy.random.Generator` passed
in, and returns ``(contour, params)``: a closed, simple `Contour` and a dict of
every resolved parameter (JSON-serialisable), as stimupy returns its
parameters with its images.

Coordinates are ``(x, y)`` floats with y pointing DOWN, as in image pixels,
but in the generator's own units and around its own centre
(``params["centre"]``): grid cells for the Attneave polygons, pixels of
radius for the polar shapes (which are centred on ``(0, 0)``). Polar angles
run counter-clockwise *as seen on the screen*: a polar point is
``(r cos(theta), -r sin(theta))``. :mod:`stimuli.batch.recipes` places a shape on an
image canvas.

Simplicity: every contour is checked with `Contour.is_simple`. Polar shapes
whose radius stays positive are star-shaped about the centre and so simple by
construction; generators whose output can cross itself (Attneave polygons
and their curved versions, elliptic Fourier shapes) draw again from the same
`Generator` until they get a simple curve, up to ``max_tries`` draws, so the
result is still a deterministic function of the seed. The number of draws
used is recorded as ``params["tries"]``.
"""

from __future__ import annotations

import math

import numpy as np

from stimuli.geometry.contour import Contour
from stimuli.errors import InputError
from stimuli.io import as_number

__all__ = [
    "attneave_polygon",
    "attneave_curved",
    "smooth_closed",
    "radial_frequency",
    "radial_frequency_radius",
    "fourier_shape",
    "superformula",
    "superformula_radius",
    "blob",
    "contour_from_csv",
    "SMOOTH_METHODS",
]

SMOOTH_METHODS = ("cubic", "bspline", "qic")


# --------------------------------------------------------------------------- checks


def _int(value, name, lo=None, hi=None):
    try:
        v = int(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be an integer, got {value!r}") from None
    if v != value:
        raise InputError(f"{name}: must be an integer, got {value!r}")
    if lo is not None and v < lo:
        raise InputError(f"{name}: must be >= {lo}, got {value!r}")
    if hi is not None and v > hi:
        raise InputError(f"{name}: must be <= {hi}, got {value!r}")
    return v


def _rng(rng):
    if not isinstance(rng, np.random.Generator):
        raise InputError(f"rng: expected a numpy.random.Generator, got {type(rng).__name__}")
    return rng


def _polar(r, theta):
    """Polar to (x, y) with y down and theta counter-clockwise on the screen."""
    return np.column_stack([r * np.cos(theta), -r * np.sin(theta)])


def _mv(m, v):
    """Matrix times vector by a plain numpy sum: the same bits whatever BLAS
    and thread count (files must be byte-identical across workers)."""
    return (m * v[None, :]).sum(axis=1)


def _angles(n):
    return 2.0 * np.pi * np.arange(n) / n


# ------------------------------------------------------------ Attneave & Arnoult


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
    n_points = _int(n_points, "n_points", lo=3)
    grid = _int(grid, "grid", lo=2)
    if n_points > grid * grid:
        raise InputError(f"n_points: a {grid}x{grid} grid has only {grid * grid} points, got {n_points}")
    min_angle = as_number(min_angle, "min_angle", ge=0, lt=180)
    max_angle = as_number(max_angle, "max_angle", gt=0, le=180)
    if not min_angle < max_angle:
        raise InputError(f"min_angle: must be < max_angle ({max_angle}), got {min_angle}")
    max_tries = _int(max_tries, "max_tries", lo=1)
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
    rng : numpy.random.Generator
        The only source of randomness.
    n_points : int
        Number of points, which is the number of vertices (>= 3).
    grid : int
        Side of the lattice; coordinates are integers in [0, grid - 1].
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
    rng = _rng(rng)
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

    Returns
    -------
    polygon : Contour
        The polygon (grid coordinates, y down).
    curved : Contour
        The smooth closed curve made from the same vertices.
    params : dict
        Those of :func:`attneave_polygon` and of :func:`smooth_closed`
        (``method, samples_per_edge``), with ``tries`` counting every draw.
    """
    rng = _rng(rng)
    n_points, grid, min_angle, max_angle, max_tries = _check_attneave(n_points, grid, min_angle, max_angle, max_tries)
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
        (:func:`stimuli.curves.qic.qic_spline`): clothoid segments, G2
        except at the few vertices where that would loop or swing out.
    samples_per_edge : int
        Points per polygon side in the output (>= 2).

    Returns
    -------
    contour : Contour
        ``N * samples_per_edge`` points; with ``'cubic'`` and ``'qic'`` the
        vertex ``i`` is point ``i * samples_per_edge`` exactly (before
        re-orientation, which keeps the first point). Not checked for
        simplicity.
    params : dict
        ``method, samples_per_edge``.

    References
    ----------
    .. [1] Lee, E. T. Y. (1989). Choosing nodes in parametric curve
           interpolation. Computer-Aided Design 21(6), 363-370.
    """
    p = np.asarray(getattr(points, "points", points), dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3:
        raise InputError(f"points: expected an (N, 2) array with N >= 3, got shape {p.shape}")
    m = _int(samples_per_edge, "samples_per_edge", lo=2)
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


class _NoCurve(InputError):
    """The smoothing did not converge for these vertices (draw another polygon)."""


# Robust QIC settings tried in turn, (corner_turn, max_tangent_deviation): the
# default rule first; where its curve still leaves the polygon's box or crosses itself, G0
# corners at turns over 90 degrees and tangents held closer to the bisector.
_QIC_STEPS = ((np.pi, None), (0.5 * np.pi, 0.125 * np.pi), (0.5 * np.pi, 0.0))


def _qic(p, m):
    from stimuli.curves.qic import ConvergenceError, qic_spline

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


# ------------------------------------------------------------ radial frequency


def _as_list(value, name):
    if value is None:
        return None
    if np.ndim(value) == 0:
        return [value]
    return list(value)


def radial_frequency_radius(theta, r0, frequencies, amplitudes, phases):
    """``r0 * (1 + sum_k A_k sin(w_k theta + phi_k))`` at angles `theta` (radians)."""
    theta = np.asarray(theta, dtype=float)
    s = np.zeros_like(theta)
    for w, a, ph in zip(frequencies, amplitudes, phases):
        s = s + a * np.sin(w * theta + ph)
    return r0 * (1.0 + s)


def radial_frequency(rng=None, r0=100.0, frequency=5, amplitude=0.1, phase=None, n=1024):
    """A radial-frequency (RF) pattern (Wilkinson, Wilson & Habak, 1998).

    ``r(theta) = r0 * (1 + sum_k A_k sin(w_k theta + phi_k))``, sampled at `n`
    equally spaced polar angles ``theta_j = 2 pi j / n``. The point at angle
    theta is ``(r cos(theta), -r sin(theta))``: theta runs counter-clockwise
    on the screen from the +x axis, and the pattern is centred on (0, 0).

    Parameters
    ----------
    rng : numpy.random.Generator, optional
        Draws the phases that are not given (uniform in [0, 2 pi)).
    r0 : float
        Mean radius (> 0), in the output's units (pixels when placed natively).
    frequency : int or list of int
        Radial frequencies w_k (cycles per revolution, >= 1).
    amplitude : float or list of float
        Amplitudes A_k (>= 0), one per frequency; their sum must be < 1 so
        that the radius stays positive (the pattern is then star-shaped,
        hence simple).
    phase : float or list of float, optional
        Phases phi_k in radians; drawn from `rng` when None.
    n : int
        Number of points.

    Returns
    -------
    contour : Contour
    params : dict
        ``r0, frequency, amplitude, phase (lists), n, centre``.

    References
    ----------
    .. [1] Wilkinson, F., Wilson, H. R., & Habak, C. (1998). Detection and
           recognition of radial frequency patterns. Vision Research 38(22),
           3555-3568.

    Examples
    --------
    >>> c, p = radial_frequency(r0=100, frequency=3, amplitude=0.2, phase=0.0, n=360)
    >>> float(np.hypot(*c.points[0])), p["frequency"]
    (100.0, [3])
    """
    r0 = as_number(r0, "r0", gt=0)
    freqs = [_int(f, f"frequency[{i}]", lo=1) for i, f in enumerate(_as_list(frequency, "frequency"))]
    amps = [as_number(a, f"amplitude[{i}]", ge=0) for i, a in enumerate(_as_list(amplitude, "amplitude"))]
    if len(freqs) == 0:
        raise InputError("frequency: give at least one radial frequency")
    if len(amps) != len(freqs):
        raise InputError(f"amplitude: give one amplitude per frequency ({len(freqs)}), got {len(amps)}")
    if sum(amps) >= 1:
        raise InputError(f"amplitude: the amplitudes must sum to < 1 so the radius stays positive, got {sum(amps):g}")
    if phase is None:
        phases = [float(x) for x in _rng(rng).uniform(0.0, 2 * np.pi, size=len(freqs))]
    else:
        phases = [as_number(x, f"phase[{i}]") for i, x in enumerate(_as_list(phase, "phase"))]
        if len(phases) != len(freqs):
            raise InputError(f"phase: give one phase per frequency ({len(freqs)}), got {len(phases)}")
    n = _int(n, "n", lo=8)
    th = _angles(n)
    r = radial_frequency_radius(th, r0, freqs, amps, phases)
    c = Contour(_polar(r, th), simple=True)
    return c, dict(r0=r0, frequency=freqs, amplitude=amps, phase=phases, n=n, centre=[0.0, 0.0])


# ------------------------------------------------------------ Fourier shapes


def fourier_shape(rng, kind="radial", r0=100.0, amplitude=0.1, falloff=1.5, harmonics=8, n=1024, max_tries=100):
    """A random Fourier shape whose harmonic amplitudes fall off as a power law.

    Parameters
    ----------
    rng : numpy.random.Generator
    kind : {'radial', 'elliptic'}
        ``'radial'``: ``r(theta) = r0 * (1 + sum_{k=2}^{K} a_k cos(k theta) +
        b_k sin(k theta))`` with ``a_k, b_k ~ N(0, (amplitude * k**-falloff)**2)``;
        draws whose radius dips below ``0.1 * r0`` are redrawn (the shape is
        then star-shaped, hence simple). ``'elliptic'``: the elliptic Fourier
        form (Kuhl & Giardina, 1982) ``x(t) = r0 cos t + sum_k (a_k cos kt +
        b_k sin kt)``, ``y(t) = -r0 sin t + sum_k (c_k cos kt + d_k sin kt)``
        with the four coefficients ``~ N(0, (r0 * amplitude * k**-falloff)**2)``;
        draws that cross themselves are redrawn.
    r0 : float
        Radius of the base circle (> 0).
    amplitude : float
        Standard deviation scale of the coefficients (>= 0).
    falloff : float
        Power-law exponent of the fall-off with harmonic number k (>= 0).
    harmonics : int
        Highest harmonic K (>= 2).
    n : int
        Number of points, equally spaced in theta (or t).
    max_tries : int
        Draws before giving up.

    Returns
    -------
    contour : Contour
    params : dict
        The inputs, ``tries``, ``centre`` and the coefficients drawn:
        ``coefficients`` is a list of ``[k, a_k, b_k]`` (radial) or
        ``[k, a_k, b_k, c_k, d_k]`` (elliptic).

    References
    ----------
    .. [1] Zahn, C. T., & Roskies, R. Z. (1972). Fourier descriptors for plane
           closed curves. IEEE Transactions on Computers C-21(3), 269-281.
    .. [2] Kuhl, F. P., & Giardina, C. R. (1982). Elliptic Fourier features of
           a closed contour. Computer Graphics and Image Processing 18(3),
           236-258.
    """
    rng = _rng(rng)
    if kind not in ("radial", "elliptic"):
        raise InputError(f"kind: expected 'radial' or 'elliptic', got {kind!r}")
    r0 = as_number(r0, "r0", gt=0)
    amplitude = as_number(amplitude, "amplitude", ge=0)
    falloff = as_number(falloff, "falloff", ge=0)
    K = _int(harmonics, "harmonics", lo=2)
    n = _int(n, "n", lo=8)
    max_tries = _int(max_tries, "max_tries", lo=1)
    if n < 4 * K:
        raise InputError(f"n: need at least 4 points per cycle of the highest harmonic ({4 * K}), got {n}")
    k = np.arange(2, K + 1)
    sd = amplitude * k.astype(float) ** -falloff
    th = _angles(n)
    ck = np.cos(np.outer(th, k))
    sk = np.sin(np.outer(th, k))
    for tries in range(1, max_tries + 1):
        if kind == "radial":
            a, b = rng.normal(size=(2, len(k))) * sd
            r = r0 * (1.0 + _mv(ck, a) + _mv(sk, b))
            if r.min() < 0.1 * r0:
                continue
            c = Contour(_polar(r, th))
            coef = np.column_stack([k, a, b])
        else:
            a, b, cc, d = rng.normal(size=(4, len(k))) * (r0 * sd)
            x = r0 * np.cos(th) + _mv(ck, a) + _mv(sk, b)
            y = -r0 * np.sin(th) + _mv(ck, cc) + _mv(sk, d)
            c = Contour(np.column_stack([x, y]))
            if not c.is_simple():
                continue
            coef = np.column_stack([k, a, b, cc, d])
        coefs = [[int(row[0])] + [float(v) for v in row[1:]] for row in coef]
        params = dict(kind=kind, r0=r0, amplitude=amplitude, falloff=falloff, harmonics=K, n=n,
                      max_tries=max_tries, tries=tries, coefficients=coefs, centre=[0.0, 0.0])
        return c, params
    raise InputError(f"fourier_shape: no simple {kind} shape in {max_tries} tries; lower the amplitude")


# ------------------------------------------------------------ superformula


def superformula_radius(phi, m, n1, n2, n3, a=1.0, b=1.0):
    """Gielis' superformula ``(|cos(m phi/4)/a|**n2 + |sin(m phi/4)/b|**n3) ** (-1/n1)``."""
    phi = np.asarray(phi, dtype=float)
    t = m * phi / 4.0
    return (np.abs(np.cos(t) / a) ** n2 + np.abs(np.sin(t) / b) ** n3) ** (-1.0 / n1)


def superformula(m=5, n1=2.0, n2=7.0, n3=7.0, a=1.0, b=1.0, scale=100.0, n=1024):
    """A closed curve from the superformula (Gielis, 2003).

    ``r(phi) = scale * (|cos(m phi / 4) / a|**n2 + |sin(m phi / 4) / b|**n3) ** (-1 / n1)``
    at `n` equally spaced angles, the point at phi being
    ``(r cos(phi), -r sin(phi))`` (counter-clockwise on the screen, centred on
    (0, 0)). With ``n1, n2, n3, a, b > 0`` the radius is finite and positive,
    so the curve is star-shaped and simple.

    Parameters
    ----------
    m : float
        Rotational symmetry (>= 0). The curve closes after one turn when m is
        an even integer, or an odd integer with ``a == b`` and ``n2 == n3``.
    n1, n2, n3, a, b : float
        Shape exponents and axes (> 0).
    scale : float
        Multiplies the radius (> 0).
    n : int
        Number of points.

    Returns
    -------
    contour : Contour
    params : dict
        ``m, n1, n2, n3, a, b, scale, n, centre``.

    Raises
    ------
    InputError
        Parameters for which the curve does not close after one turn.

    References
    ----------
    .. [1] Gielis, J. (2003). A generic geometric transformation that unifies
           a wide range of natural and abstract shapes. American Journal of
           Botany 90(3), 333-338.
    """
    m = as_number(m, "m", ge=0)
    n1, n2, n3, a, b = (as_number(v, name, gt=0) for v, name in zip((n1, n2, n3, a, b), ("n1", "n2", "n3", "a", "b")))
    scale = as_number(scale, "scale", gt=0)
    n = _int(n, "n", lo=8)
    # one turn closes only if r and its one-sided slopes agree at 0 and 2*pi
    probe = np.array([0.0, 1e-3, 2 * np.pi, 2 * np.pi + 1e-3])
    rp = superformula_radius(probe, m, n1, n2, n3, a, b)
    if not np.allclose(rp[[0, 1]], rp[[2, 3]], rtol=1e-9, atol=0):
        raise InputError(
            f"m: the superformula with m={m:g} does not close after one turn; use an even integer m, "
            f"or an odd integer with a == b and n2 == n3"
        )
    phi = _angles(n)
    r = scale * superformula_radius(phi, m, n1, n2, n3, a, b)
    c = Contour(_polar(r, phi), simple=True)
    return c, dict(m=m, n1=n1, n2=n2, n3=n3, a=a, b=b, scale=scale, n=n, centre=[0.0, 0.0])


# ------------------------------------------------------------ smooth blobs


def blob(rng, r0=100.0, sigma=0.2, width=0.6, n=1024):
    """A smooth random blob: a circle whose log-radius is smoothed noise.

    ``log r(theta) = log r0 + g(theta)`` with g a periodic Gaussian random
    function of correlation width `width` (radians): harmonic k >= 2 gets a
    complex normal coefficient scaled by ``exp(-(k * width)**2 / 2)`` (the
    spectrum of white noise smoothed by a Gaussian of s.d. `width`), and g is
    scaled to root-mean-square `sigma`. Harmonics whose weight is below 1e-3
    are left out. The radius is positive, so the blob is star-shaped and
    simple.

    Parameters
    ----------
    rng : numpy.random.Generator
    r0 : float
        Geometric-mean radius (> 0).
    sigma : float
        RMS of the log-radius (>= 0; 0 gives a circle).
    width : float
        Correlation width in radians (> 0); smaller is bumpier.
    n : int
        Number of points, equally spaced in theta.

    Returns
    -------
    contour : Contour
    params : dict
        ``r0, sigma, width, n, centre, coefficients`` (``[k, re, im]`` as
        drawn, before the scaling to `sigma`).
    """
    rng = _rng(rng)
    r0 = as_number(r0, "r0", gt=0)
    sigma = as_number(sigma, "sigma", ge=0)
    width = as_number(width, "width", gt=0)
    n = _int(n, "n", lo=8)
    kmax = max(2, int(math.floor(math.sqrt(2 * math.log(1e3)) / width)))
    kmax = min(kmax, n // 4)
    k = np.arange(2, kmax + 1)
    z = rng.normal(size=(2, len(k)))
    coef = (z[0] + 1j * z[1]) * np.exp(-0.5 * (k * width) ** 2)
    th = _angles(n)
    g = _mv(np.cos(np.outer(th, k)), coef.real) - _mv(np.sin(np.outer(th, k)), coef.imag)
    rms = float(np.sqrt(np.mean(g**2)))
    g = g * (sigma / rms) if rms > 0 else g
    r = r0 * np.exp(g)
    c = Contour(_polar(r, th), simple=True)
    coefs = [[int(kk), float(a), float(b)] for kk, a, b in zip(k, z[0], z[1])]
    return c, dict(r0=r0, sigma=sigma, width=width, n=n, centre=[0.0, 0.0], coefficients=coefs)


# ------------------------------------------------------------ files


def contour_from_csv(path, resample=None):
    """A closed contour from a CSV file with columns ``x, y``.

    The points are taken as they are (image pixels, y down); the recipes
    rescale and centre them onto the canvas.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    resample : int, optional
        Resample to this many equally spaced points (e.g. a pixel-traced
        contour); by default the points are kept.

    Returns
    -------
    contour : Contour
    params : dict
        ``n_points`` (as read), ``n`` (as returned), ``centre`` (the centre
        of the bounding box).

    Raises
    ------
    InputError
        Unreadable file, missing columns, non-finite values, fewer than 3
        distinct points, or a contour that crosses itself.
    """
    c = Contour.from_csv(path, closed=True, simple=True)
    n_read = c.n
    if resample is not None:
        c = c.resample(n=_int(resample, "resample", lo=3))
        if not c.is_simple():
            raise InputError(f"{path}: resampled to {c.n} points the contour crosses itself; use more points")
    x0, y0, x1, y1 = c.bbox
    return c, dict(n_points=int(n_read), n=int(c.n), centre=[(x0 + x1) / 2.0, (y0 + y1) / 2.0])
