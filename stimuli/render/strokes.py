"""Strokes: outlines and fragments as the region within ``width / 2`` of a
polyline, built with shapely's ``buffer`` and filled by the exact
rasteriser. Round joins and caps are polygonised by shapely with
``quad_segs`` chosen so that the polygon departs from the true arc by less
than 1e-3 px (recorded in the result).
"""

from __future__ import annotations

import math

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.render.paint import colours, paint_image, resolve_dtype, result_record
from attneave.stimuli.render.raster import ring_accumulation, sum_dtype
from attneave.stimuli.render.rings import is_single_ring, resolve_shape, rings_from_geometry
from attneave.stimuli.validate import as_number, as_points

# Largest departure of shapely's polygonised round joins/caps from the arc.
_ARC_TOLERANCE = 1e-3
_JOINS = {"round": "round", "mitre": "mitre", "miter": "mitre", "bevel": "bevel"}
_CAPS = {"round": "round", "flat": "flat", "butt": "flat", "square": "square"}


def _choice(value, table, name):
    key = str(value).lower()
    if key not in table:
        raise InputError(f"{name}: expected one of {', '.join(sorted(set(table.values())))}, got {value!r}")
    return table[key]


def _quad_segs(radius, quad_segs):
    """Segments per quarter circle keeping round joins/caps within tolerance."""
    if quad_segs is not None:
        q = int(quad_segs)
        if q < 1 or q != quad_segs:
            raise InputError(f"quad_segs: expected a positive integer, got {quad_segs!r}")
        return q
    # sagitta of a chord spanning (pi/2)/q is r (1 - cos(pi/(4q))) ~ r pi^2 / (32 q^2)
    return max(8, math.ceil(math.pi * math.sqrt(radius / (32.0 * _ARC_TOLERANCE))))


def _stroke(geoms, width, join, cap, mitre_limit, quad_segs):
    import shapely

    half = 0.5 * width
    parts = [
        g.buffer(half, quad_segs=quad_segs, join_style=join, cap_style=cap, mitre_limit=mitre_limit)
        for g in geoms
    ]
    return parts[0] if len(parts) == 1 else shapely.union_all(parts)


def render_outline(
    points,
    width,
    size=None,
    *,
    shape=None,
    closed=None,
    join="round",
    cap="flat",
    mitre_limit=4.0,
    quad_segs=None,
    figure=0.0,
    ground=1.0,
    dtype=None,
):
    """Render a contour's outline as a stroke of given width, exactly antialiased.

    The stroke is the set of points within ``width / 2`` of the polyline
    (with the chosen joins and caps), built with shapely's ``buffer`` and
    filled with the exact rasteriser of :func:`coverage`. This is the region
    an SVG renderer strokes with ``stroke-width = width``.

    Parameters
    ----------
    points : Contour or (N, 2) array
        ``(x, y)`` points in image pixels (y down, pixel centres at integer
        coordinates); a closed contour does not repeat its first point.
    width : float
        Stroke width in pixels (> 0).
    size, shape
        Image size, as in :func:`render_silhouette`.
    closed : bool, optional
        Whether the outline is closed. Default: the contour's own `closed`
        attribute if it has one, else True.
    join : {'round', 'mitre', 'bevel'}, optional
        Corner joins ('miter' accepted).
    cap : {'flat', 'round', 'square'}, optional
        Ends of an open outline ('butt' accepted).
    mitre_limit : float, optional
        Mitre length / half-width beyond which a mitre is cut (same ratio as
        SVG's ``stroke-miterlimit``; shapely squares the cut mitre off at
        that length where SVG falls back to a bevel).
    quad_segs : int, optional
        Segments per quarter circle of round joins and caps. Default: the
        smallest count (at least 8) keeping every chord within 1e-3 px of
        the true arc.
    figure, ground, dtype
        As in :func:`render_silhouette`.

    Returns
    -------
    dict
        ``img``, ``kind`` ('outline'), ``size``, ``shape``, ``figure``,
        ``ground``, ``dtype``, ``points``, ``closed``, ``width``, ``join``,
        ``cap``, ``mitre_limit``, ``quad_segs``, ``area`` (exact area of the
        stroke polygon, px^2, whether or not inside the image),
        ``stroke_rings`` (the stroke polygon's rings, (N, 2) arrays).

    Raises
    ------
    InputError
        Bad points, width, size, colours, join or cap.
    """
    import shapely

    if closed is None:
        closed = bool(getattr(points, "closed", True))
    pts = as_points(points, "points", min_points=3 if closed else 2)
    if closed and len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    width = as_number(width, "width", gt=0)
    h, w = resolve_shape(size, shape)
    f, g = colours(figure, ground)
    dt = resolve_dtype(dtype)
    join = _choice(join, _JOINS, "join")
    cap = _choice(cap, _CAPS, "cap")
    mitre_limit = as_number(mitre_limit, "mitre_limit", gt=0)
    q = _quad_segs(width / 2, quad_segs)
    geom = shapely.LinearRing(pts) if closed else shapely.LineString(pts)
    stroke = _stroke([geom], width, join, cap, mitre_limit, q)
    rings = rings_from_geometry(stroke)
    acc = ring_accumulation(rings, h, w, oriented=True, dtype=sum_dtype(dt, h, w)) if rings else None
    img = paint_image(acc, h, w, f, g, dt)
    return result_record(
        "outline", img, h, w, f, g, dt, points=pts, closed=bool(closed), width=width,
        join=join, cap=cap, mitre_limit=mitre_limit, quad_segs=q, area=float(stroke.area),
        stroke_rings=rings,
    )


def render_fragments(
    polylines,
    width,
    size=None,
    *,
    shape=None,
    cap="flat",
    join="round",
    mitre_limit=4.0,
    quad_segs=None,
    figure=0.0,
    ground=1.0,
    dtype=None,
):
    """Render open polylines (contour fragments) as strokes, exactly antialiased.

    Each fragment is stroked as in :func:`render_outline` (shapely buffer of
    half the width, flat caps by default so that the visible length equals
    the fragment length); overlapping strokes are merged (union) so no pixel
    is counted twice.

    Parameters
    ----------
    polylines : list of (M, 2) arrays
        Fragments as ``(x, y)`` points in image pixels (y down, pixel centres
        at integer coordinates), each with at least 2 points.
    width : float
        Stroke width in pixels (> 0).
    size, shape, cap, join, mitre_limit, quad_segs, figure, ground, dtype
        As in :func:`render_outline`.

    Returns
    -------
    dict
        ``img``, ``kind`` ('fragments'), ``size``, ``shape``, ``figure``,
        ``ground``, ``dtype``, ``polylines``, ``width``, ``cap``, ``join``,
        ``mitre_limit``, ``quad_segs``, ``area`` (exact area of the union of
        strokes, px^2), ``stroke_rings`` (its rings, (N, 2) arrays).

    Raises
    ------
    InputError
        Bad polylines, width, size, colours, cap or join.
    """
    import shapely

    if is_single_ring(polylines):
        raise InputError("polylines: expected a list of (M, 2) arrays, got a single array")
    try:
        items = list(polylines)
    except TypeError:
        raise InputError("polylines: expected a list of (M, 2) arrays") from None
    lines = [as_points(p, f"polylines[{k}]", min_points=2) for k, p in enumerate(items)]
    width = as_number(width, "width", gt=0)
    h, w = resolve_shape(size, shape)
    f, g = colours(figure, ground)
    dt = resolve_dtype(dtype)
    cap = _choice(cap, _CAPS, "cap")
    join = _choice(join, _JOINS, "join")
    mitre_limit = as_number(mitre_limit, "mitre_limit", gt=0)
    q = _quad_segs(width / 2, quad_segs)
    if lines:
        stroke = _stroke([shapely.LineString(p) for p in lines], width, join, cap, mitre_limit, q)
        rings = rings_from_geometry(stroke)
        area = float(stroke.area)
    else:
        rings, area = [], 0.0
    acc = ring_accumulation(rings, h, w, oriented=True, dtype=sum_dtype(dt, h, w)) if rings else None
    img = paint_image(acc, h, w, f, g, dt)
    return result_record(
        "fragments", img, h, w, f, g, dt, polylines=lines, width=width, cap=cap, join=join,
        mitre_limit=mitre_limit, quad_segs=q, area=area, stroke_rings=rings,
    )
