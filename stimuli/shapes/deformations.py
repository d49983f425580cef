"""Matched concave / convex deformations of a contour (Barenholtz et al., 2003).

A change detection experiment compares a base shape with a copy changed in
one place, the change either making a concavity (the ``concave`` condition)
or a convexity (the ``convex`` condition), the two changes being of the same
size. Here both are made by displacing the same point(s) by the same vector
field, once inward and once outward::

    concave = base - v,   convex = base + v

Why this matches the area change exactly: the area of a polygon is linear in
each vertex. Moving vertex i alone by v changes the signed area by
``(1/2) v x (p[i+1] - p[i-1])`` (a dot product with the area gradient), so
``-v`` and ``+v`` change it by equal and opposite amounts. When several
vertices move (a smooth bump) the area picks up the quadratic term
``(1/2) sum v[i] x v[i+1]``, which vanishes when every displacement is
parallel; bumps therefore displace all their vertices along ONE direction,
the outward normal at the bump's centre, with a smooth profile. The
displacement magnitude (the largest vertex move) is the same ``d`` in both
versions, and ``|area change|`` agrees to floating-point round-off.

Three modes:

``edge`` (polygons; the default of the recipe)
    A new vertex is put on a side of the polygon (at `position` along it);
    the base stimulus has it as an invisible straight-angle vertex. Moving it
    inward by `d` along the side's normal makes a new concave vertex,
    outward a new convex one.
``vertex`` (polygons)
    An existing vertex is moved by `d` along the normal of the chord joining
    its neighbours, inward (concave version: the vertex is concave after the
    move) or outward (convex version: convex after the move). Which of the
    two changes its sign depends on the vertex; it is recorded.
``bump`` (smooth, densely sampled contours)
    Vertices within arc length `width` of a centre move along the centre's
    outward normal by ``d * (1 - (s/width)**2)**6`` (s the arc distance from
    the centre): a dent (concave version) or a bulge (convex version). The
    profile is C5 where it meets the contour. Its curvature at the centre is
    ``12 d / width**2`` and at most ``6.71 d / width**2`` on the flanks, so
    on a stretch of curvature kappa the dent is concave at its centre while
    the bulge's flanks stay convex when ``width**2`` is between
    ``6.71 d / kappa`` and ``12 d / kappa``. With ``width=None`` each candidate
    centre gets ``width = 0.9 * sqrt(12 d / kappa)``, kappa being the mean
    curvature near the centre, and the flanks are then checked.

A place is valid when both versions are simple, the moved vertex (the
centre) has a negative turning angle in the concave version and a positive
one in the convex version (beyond `min_turn`), and no other vertex changes
the sign of its turning angle, except that in ``bump`` mode the dent's
concave run around the centre may cover several vertices. The convex version
therefore has exactly the concavities of the base, and the concave version
those plus one. Places are tried in an order drawn from the `rng`, and the
first valid one is used.

Points are ``(x, y)`` in image pixels (y down), closed contours
counter-clockwise on the screen; "outward" is the direction that increases
the enclosed area.

References
----------
.. [1] Barenholtz, E., Cohen, E. H., Feldman, J., & Singh, M. (2003).
       Detection of change in shape: an advantage for concavities.
       Cognition 89(1), 1-9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.shapes.deformation_checks import check_deformation  # re-exported: this module is its public home
from attneave.stimuli.validate import as_int, as_number, as_rng

__all__ = [
    "Deformation",
    "MODES",
    "outward_normal",
    "area_gradient",
    "insert_vertex",
    "move_vertex",
    "bump_profile",
    "deform_at",
    "check_deformation",
    "deform",
]

MODES = ("edge", "vertex", "bump")
_BUMP_POWER = 6
# curvature of the profile (1 - u^2)^6 at its centre, times width^2
_BUMP_CENTRE = 2.0 * _BUMP_POWER


@dataclass
class Deformation:
    """A base contour and its matched concave and convex versions.

    Attributes
    ----------
    base, concave, convex : Contour
        Same number of points, the same except near `index` (image pixels,
        y down, counter-clockwise on the screen).
    index : int
        The moved vertex (the bump's centre) in all three.
    params : dict
        Every resolved parameter: ``mode, displacement, index, t`` (arc
        position of the moved vertex in the base), ``direction`` (unit
        outward vector), ``area_change`` (predicted ``|dA|``),
        ``area_change_concave, area_change_convex`` (measured, signed),
        ``turning_angle_base/concave/convex`` at the vertex (radians),
        ``moved`` (number of vertices moved), and per mode ``edge,
        position`` or ``width``; ``candidates_tried``.
    """

    base: Contour
    concave: Contour
    convex: Contour
    index: int
    params: dict = field(default_factory=dict)


def _as_closed(contour, name="contour", orient=False):
    """A closed `Contour` from a Contour or an (N, 2) array of ``(x, y)`` points
    (image pixels, y down), taken as a closed ring in the order given (made
    counter-clockwise on the screen if `orient`)."""
    if isinstance(contour, Contour):
        if not contour.closed:
            raise InputError(f"{name}: a closed contour is needed, got an open one")
        if orient and contour.signed_area < 0:
            return Contour(contour.points, True, name=contour.name)
        return contour
    try:
        return Contour(contour, True, orient=orient)
    except InputError as exc:
        raise InputError(f"{name}: {exc}") from None


def _vertex(index, n, name="index"):
    """A vertex index in [-n, n) (negative counts from the end) as one in [0, n)."""
    return as_int(index, name, lo=-n, hi=n - 1) % n


def area_gradient(points, index):
    """Gradient of `Contour.signed_area` with respect to vertex `index`.

    ``(1/2) * (-(y[i+1] - y[i-1]), x[i+1] - x[i-1])``: moving the vertex by v
    changes the signed area by exactly ``v . gradient``.
    """
    p = np.asarray(points, dtype=float)
    n = len(p)
    c = p[(index + 1) % n] - p[(index - 1) % n]
    return 0.5 * np.array([-c[1], c[0]])


def outward_normal(points, index):
    """Unit vector normal to the chord ``p[i+1] - p[i-1]``, pointing outward.

    Outward means the side that increases the area of a contour stored
    counter-clockwise on the screen.
    """
    g = area_gradient(points, index)
    norm = math.hypot(*g)
    if norm == 0:
        raise InputError(f"vertex {index}: its neighbours coincide, so it has no normal")
    return g / norm


def insert_vertex(contour, edge, position=0.5):
    """The same closed contour with a vertex added on side `edge`.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed, points ``(x, y)`` in image pixels (y down).
    edge : int
        Side from vertex `edge` to vertex ``edge + 1`` (in [-N, N);
        negative counts from the end).
    position : float
        Fraction of the way along the side, in (0, 1).

    Returns
    -------
    Contour
        With the new vertex at index ``edge + 1``; same shape and area.

    Raises
    ------
    InputError
        Bad points, an `edge` that is not a vertex index, or `position`
        outside (0, 1).
    """
    contour = _as_closed(contour)
    p = contour.points
    n = len(p)
    edge = _vertex(edge, n, "edge")
    position = as_number(position, "position", gt=0, lt=1)
    a, b = p[edge], p[(edge + 1) % n]
    q = a + position * (b - a)
    out = np.vstack([p[: edge + 1], q[None, :], p[edge + 1 :]])
    return Contour(out, True, orient=False, name=contour.name)


def move_vertex(contour, index, vector):
    """The contour with vertex `index` moved by `vector` (orientation kept).

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Points ``(x, y)`` in image pixels (y down); an array is taken as a
        closed contour.
    index : int
        The vertex moved, in [-N, N) (negative counts from the end).
    vector : (2,) array_like
        The move ``(dx, dy)`` in pixels (finite).

    Returns
    -------
    Contour
        A new contour, open or closed as the input; the input is unchanged.

    Raises
    ------
    InputError
        Bad points, an index that is not a vertex, or a bad vector.

    Examples
    --------
    >>> sq = Contour([[0, 0], [0, 10], [10, 10], [10, 0]])
    >>> move_vertex(sq, 1, (-5, 0)).points[1].tolist()
    [-5.0, 10.0]
    """
    if not isinstance(contour, Contour):
        contour = _as_closed(contour)
    index = _vertex(index, contour.n)
    try:
        v = np.asarray(vector, dtype=float)
    except (TypeError, ValueError):
        v = None
    if v is None or v.shape != (2,) or not np.isfinite(v).all():
        raise InputError(f"vector: expected a finite (dx, dy) pair, got {vector!r}")
    p = contour.points.copy()
    p[index] = p[index] + v
    return Contour(p, contour.closed, orient=False, name=contour.name)


def bump_profile(s, width):
    """``(1 - (s/width)**2)**6`` for ``|s| < width``, else 0 (1 at s = 0)."""
    u = np.asarray(s, dtype=float) / width
    return np.where(np.abs(u) < 1, np.clip(1 - u * u, 0, None) ** _BUMP_POWER, 0.0)


def _arc_offsets(contour, index):
    """Signed arc distance of every vertex from vertex `index`, in (-L/2, L/2]."""
    s = contour.arclength()
    L = contour.perimeter
    d = s - s[index]
    return d - L * np.round(d / L)


def deform_at(contour, index, displacement, mode="vertex", width=None):
    """Concave and convex versions of `contour` moved at vertex `index`.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed, counter-clockwise on the screen (image pixels, y down). For
        ``mode='edge'`` pass the contour with the vertex already inserted
        (:func:`insert_vertex`); the move itself is the same as ``'vertex'``.
    index : int
        The vertex moved (the bump's centre), in [-N, N) (negative counts
        from the end).
    displacement : float
        Distance `d` in pixels the vertex (the bump's centre) moves (> 0).
    mode : {'vertex', 'edge', 'bump'}
    width : float
        Half-width of the bump in pixels of arc length (``'bump'`` only).

    Returns
    -------
    concave, convex : Contour
    info : dict
        ``direction`` (unit outward vector), ``moved`` (vertices moved),
        ``area_change`` (predicted ``|dA|`` in px^2).

    Raises
    ------
    InputError
        Bad points or parameters, naming them; a contour that runs
        clockwise on the screen; a vertex whose neighbours coincide (it has
        no normal).
    """
    contour = _as_closed(contour)
    if contour.signed_area < 0:
        raise InputError("contour: runs clockwise on the screen, so 'outward' would point in; reverse the points "
                         "or pass Contour(points), which orients them")
    index = _vertex(index, contour.n)
    d = as_number(displacement, "displacement", gt=0)
    if mode not in MODES:
        raise InputError(f"mode: expected one of {', '.join(MODES)}, got {mode!r}")
    if mode == "bump":
        if width is None:
            raise InputError("width: must be > 0 for a bump, got None")
        width = as_number(width, "width", gt=0)
    p = contour.points
    n0 = outward_normal(p, index)
    if mode in ("vertex", "edge"):
        v = d * n0
        concave = move_vertex(contour, index, -v)
        convex = move_vertex(contour, index, v)
        predicted = abs(float(v @ area_gradient(p, index)))
        moved = 1
    elif mode == "bump":
        w = bump_profile(_arc_offsets(contour, index), width)
        V = (d * w)[:, None] * n0[None, :]
        concave = Contour(p - V, True, orient=False, name=contour.name)
        convex = Contour(p + V, True, orient=False, name=contour.name)
        q_prev = np.roll(p, 1, axis=0)
        q_next = np.roll(p, -1, axis=0)
        c = q_next - q_prev
        # sum_i V_i . area_gradient_i (the quadratic term is 0: V_i are parallel)
        predicted = abs(float(np.sum(V[:, 0] * (-0.5 * c[:, 1]) + V[:, 1] * (0.5 * c[:, 0]))))
        moved = int(np.count_nonzero(w))
    else:
        raise InputError(f"mode: expected one of {', '.join(MODES)}, got {mode!r}")
    return concave, convex, dict(direction=[float(n0[0]), float(n0[1])], moved=moved, area_change=predicted)


def _auto_width(contour, index, d, cum_turn, s, L):
    """Bump half-width from the curvature kappa around the centre.

    The dent's centre is concave when ``12 d / width**2 > kappa`` there, so
    the width is set 10% below ``sqrt(12 d / kappa)``, kappa being the mean
    curvature over the middle half of the window (a few fixed-point steps).
    The flanks are left to :func:`check_deformation`. None where the contour
    is not convex there, or the bump would span a quarter of the contour.
    """
    h = L / 20.0
    for _ in range(5):
        q = h / 4.0
        kappa = (_interp_periodic(cum_turn, s, L, s[index] + q) - _interp_periodic(cum_turn, s, L, s[index] - q)) / (2 * q)
        if not kappa > 0:
            return None
        h = 0.9 * math.sqrt(_BUMP_CENTRE * d / kappa)
        if h > L / 4:
            return None
    return h


def _interp_periodic(cum_turn, s, L, x):
    """Cumulative turning at arc length x (any real), turning 2*pi per lap."""
    laps = math.floor(x / L)
    r = x - laps * L
    ss = np.append(s, L)
    tt = np.append(cum_turn, cum_turn[0] + 2 * np.pi)
    return float(np.interp(r, ss, tt)) + laps * 2 * np.pi


def deform(contour, rng, mode="edge", displacement=10.0, position=0.5, width=None, min_turn=0.0):
    """Matched concave and convex deformations at a place drawn from `rng`.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed and simple, in image pixels (y down); one that runs clockwise
        on the screen is re-oriented (``base`` is then in the new order).
    rng : numpy.random.Generator or int
        Orders the candidate places (sides, vertices or bump centres); an
        integer is a seed.
    mode : {'edge', 'vertex', 'bump'}
        See the module docstring.
    displacement : float
        Distance in pixels the moved vertex (bump centre) travels (> 0).
    position : float
        Where on the side the new vertex goes (``'edge'``), in (0, 1).
    width : float, optional
        Bump half-width in pixels (``'bump'``); None picks it per place.
    min_turn : float
        Minimum |turning angle| in degrees at the moved vertex in both
        versions (>= 0).

    Returns
    -------
    Deformation

    Raises
    ------
    InputError
        No valid place on this contour (the message says why the last
        candidate failed), or bad parameters.

    Examples
    --------
    >>> import numpy as np
    >>> sq = Contour([[0, 0], [0, 100], [100, 100], [100, 0]])
    >>> dfm = deform(sq, np.random.default_rng(0), mode="edge", displacement=10)
    >>> float(dfm.base.area - dfm.concave.area), float(dfm.convex.area - dfm.base.area)
    (500.0, 500.0)
    """
    contour = _as_closed(contour, orient=True)
    rng = as_rng(rng)
    if mode not in MODES:
        raise InputError(f"mode: expected one of {', '.join(MODES)}, got {mode!r}")
    d = as_number(displacement, "displacement", gt=0)
    position = as_number(position, "position", **(dict(gt=0, lt=1) if mode == "edge" else {}))
    if width is not None:
        width = as_number(width, "width", gt=0)
    min_turn = as_number(min_turn, "min_turn", ge=0, lt=180)
    if not contour.is_simple():
        contour.require_simple()
    min_turn_rad = math.radians(float(min_turn))
    n = contour.n
    order = rng.permutation(n)
    reason = "no candidate"
    if mode == "bump":
        s = contour.arclength()
        L = contour.perimeter
        cum_turn = np.concatenate([[0.0], np.cumsum(contour.turning_angles()[1:])])
    for tried, cand in enumerate(order, start=1):
        cand = int(cand)
        extra = {}
        window = None
        if mode == "edge":
            base = insert_vertex(contour, cand, position)
            index = cand + 1
            extra = dict(edge=cand, position=float(position))
            h = None
        else:
            base = contour
            index = cand
            h = None
            if mode == "bump":
                h = float(width) if width is not None else _auto_width(contour, cand, d, cum_turn, s, L)
                if h is None:
                    reason = "the contour is not convex around any candidate centre"
                    continue
                extra = dict(width=h, width_auto=width is None)
        try:
            concave, convex, info = deform_at(base, index, d, mode=mode, width=h)
        except InputError as exc:
            reason = str(exc)
            continue
        if mode == "bump":
            window = bump_profile(_arc_offsets(base, index), h) > 0
        ok, reason = check_deformation(base, concave, convex, index, window=window, min_turn=min_turn_rad)
        if not ok:
            continue
        ta = [float(base.turning_angles()[index]), float(concave.turning_angles()[index]),
              float(convex.turning_angles()[index])]
        params = dict(
            mode=mode,
            displacement=d,
            min_turn=float(min_turn),
            index=int(index),
            t=float(base.t()[index]),
            direction=info["direction"],
            moved=info["moved"],
            area_change=info["area_change"],
            area_change_concave=float(concave.signed_area - base.signed_area),
            area_change_convex=float(convex.signed_area - base.signed_area),
            turning_angle_base=ta[0],
            turning_angle_concave=ta[1],
            turning_angle_convex=ta[2],
            candidates_tried=tried,
            **extra,
        )
        return Deformation(base, concave, convex, int(index), params)
    hint = {
        "edge": "try a smaller displacement",
        "vertex": "try a larger displacement (a vertex flips sign only if it is less than that from its "
                  "neighbours' chord) or mode 'edge'",
        "bump": "try another displacement or width; a bump needs a smooth stretch that is convex (on a "
                "straight side a bulge always has concave feet), so use mode 'edge' for polygons",
    }[mode]
    raise InputError(f"deformation: no place on this contour for a {mode} change of {d:g} px ({reason}); {hint}")
