"""Shapes as rings for the rasteriser: image sizes, rings from contours, arrays
or shapely polygons, and their orientation so that holes subtract.

Points are ``(x, y)`` in image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.polyline import shoelace
from attneave.stimuli.validate import as_points

#: Largest image side in pixels, and largest number of pixels, that is
#: rendered: OpenCV's limits for image files (``CV_IO_MAX_IMAGE_WIDTH``,
#: ``CV_IO_MAX_IMAGE_PIXELS``), beyond which a PNG could not be read back.
MAX_SIDE = 1 << 20
MAX_PIXELS = 1 << 30


def resolve_shape(size=None, shape=None):
    """Return (height, width) from `size` (int or (width, height)) or `shape`.

    Raises
    ------
    InputError
        Not exactly one of them, sides that are not positive integers, a side
        above :data:`MAX_SIDE` or more than :data:`MAX_PIXELS` pixels.
    """
    if (size is None) == (shape is None):
        raise InputError("give exactly one of size=(width, height) and shape=(height, width)")
    if size is not None:
        if np.ndim(size) == 0:
            w = h = size
        else:
            if len(size) != 2:
                raise InputError(f"size: expected an int or (width, height), got {size!r}")
            w, h = size
    else:
        if np.ndim(shape) == 0 or len(shape) != 2:
            raise InputError(f"shape: expected (height, width), got {shape!r}")
        h, w = shape
    try:
        hi, wi = int(h), int(w)
    except (TypeError, ValueError):
        raise InputError(f"size: width and height must be integers, got {w!r}, {h!r}") from None
    if hi != h or wi != w or hi < 1 or wi < 1:
        raise InputError(f"size: width and height must be positive integers, got {w!r}, {h!r}")
    if max(hi, wi) > MAX_SIDE or hi * wi > MAX_PIXELS:
        raise InputError(f"size: {wi} x {hi} is too large; an image may have sides up to {MAX_SIDE} px "
                         f"and up to {MAX_PIXELS} ({MAX_PIXELS / 1e9:.2f} G) pixels")
    return hi, wi


def is_single_ring(obj):
    if hasattr(obj, "points"):
        return True
    if isinstance(obj, np.ndarray):
        return obj.ndim == 2 and obj.shape[1:] == (2,)
    try:
        a = np.asarray(obj, dtype=float)
    except (TypeError, ValueError):
        return False
    return a.ndim == 2 and a.shape[1:] == (2,)


def as_rings(obj, name="rings"):
    """Rings from a contour, an (N, 2) array, a list of them, or a shapely polygon.

    Returns (rings, oriented): `oriented` is True when the rings come from a
    shapely geometry already oriented so that holes subtract.

    Raises
    ------
    InputError
        Bad points, a ring with fewer than 3 distinct points, or two rings
        that cross each other (see :func:`check_apart`).
    """
    geom_type = getattr(obj, "geom_type", None)
    if geom_type in ("Polygon", "MultiPolygon", "GeometryCollection"):
        return rings_from_geometry(obj), True
    if is_single_ring(obj):
        return [_ring(obj, name)], False
    try:
        items = list(obj)
    except TypeError:
        raise InputError(f"{name}: expected an (N, 2) array, a Contour or a list of them") from None
    if not items:
        raise InputError(f"{name}: no rings given")
    rings = [_ring(r, f"{name}[{k}]") for k, r in enumerate(items)]
    if len(rings) > 1:
        check_apart(rings, name)
    return rings, False


def check_apart(rings, name="rings"):
    """Refuse rings of one shape that cross each other.

    The rings of a shape must be nested (holes, islands in holes) or apart;
    they may touch but not coincide. Where two cross, orienting them by nesting (or as given)
    makes winding numbers of 2 or of opposite signs, and the painted region
    and its area (the winding integral) no longer agree. A ring that
    crosses only itself is allowed (it is filled by the non-zero rule).

    Raises
    ------
    InputError
        Naming the two rings.
    """
    import shapely

    polys = np.array([shapely.Polygon(r) for r in rings], dtype=object)
    i, j = np.triu_indices(len(rings), 1)
    with np.errstate(all="ignore"):
        try:
            hit = shapely.overlaps(polys[i], polys[j]) | shapely.equals(polys[i], polys[j])
        except shapely.errors.GEOSException:  # pragma: no cover - GEOS refusing a degenerate ring
            return
    if hit.any():
        a, b = int(i[hit][0]), int(j[hit][0])
        raise InputError(
            f"{name}: rings {a} and {b} cross each other or coincide; the rings of one shape must be nested (holes) or apart: "
            "draw them as separate shapes, or merge them first (e.g. with shapely's union or symmetric_difference)"
        )


def _ring(obj, name):
    pts = as_points(obj, name)
    if len(pts) > 1 and pts[0].tolist() == pts[-1].tolist():
        pts = pts[:-1]  # tolerate a repeated closing point
    if _distinct_at_most_two(pts):
        raise InputError(f"{name}: a ring needs at least 3 distinct points")
    return pts


def _distinct_at_most_two(pts):
    """True if `pts` holds fewer than 3 distinct points (cheaper than np.unique)."""
    if len({tuple(q) for q in pts[:3].tolist()}) == 3:  # the usual case, without numpy calls
        return False
    other = (pts != pts[0]).any(axis=1)
    if not other.any():
        return True
    p1 = pts[int(np.argmax(other))]
    return not (other & (pts != p1).any(axis=1)).any()


def rings_from_geometry(geom):
    """Exterior and interior rings of a shapely (Multi)Polygon, holes reversed."""
    from shapely.geometry.polygon import orient

    rings = []
    for poly in getattr(geom, "geoms", [geom]):
        if poly.geom_type == "MultiPolygon":
            rings.extend(rings_from_geometry(poly))
            continue
        if poly.geom_type != "Polygon" or poly.is_empty:
            continue
        # sign=1: exterior with positive shoelace, holes negative; that is
        # the orientation whose accumulated winding is +1 inside.
        poly = orient(poly, sign=1.0)
        for ring in [poly.exterior, *poly.interiors]:
            pts = np.asarray(ring.coords, dtype=float)[:-1, :2]
            if len(pts) >= 3:
                rings.append(pts)
    return rings


def orient_rings(rings):
    """Orient rings so that nesting depth parity decides fill (holes subtract).

    A ring inside an even number of other rings gets a positive shoelace sum
    (it adds), one inside an odd number a negative one (it subtracts). Rings
    must not cross one another for this to be the even-odd region (see
    :func:`check_apart`); they may touch (a hole whose corner lies on the
    outer ring is still inside it).
    """
    if len(rings) == 1:
        r = rings[0]
        return [r if shoelace(r) >= 0 else r[::-1]]
    import shapely

    polys = np.array([shapely.Polygon(r) for r in rings], dtype=object)
    try:
        inside = shapely.contains(polys[None, :], polys[:, None])  # [i, j]: ring i inside ring j
    except shapely.errors.GEOSException:  # pragma: no cover - a self-crossing ring GEOS refuses
        from matplotlib.path import Path as MplPath

        paths = [MplPath(r) for r in rings]
        inside = np.array([[p.contains_point(r[0], radius=0.0) for p in paths] for r in rings])
    np.fill_diagonal(inside, False)
    out = []
    for i, r in enumerate(rings):
        depth = int(inside[i].sum())
        want = 1.0 if depth % 2 == 0 else -1.0
        out.append(r if shoelace(r) * want >= 0 else r[::-1])
    return out


def check_alternating(rings, name="rings"):
    """Refuse rings given as they are (``orient=False``) whose directions do
    not alternate with nesting depth: a hole running the same way as the
    ring around it makes a winding number of 2 (painted as 1, counted twice
    in the area)."""
    flipped = [a is not b for a, b in zip(orient_rings(rings), rings)]
    if any(flipped) and not all(flipped):
        k = next(i for i, f in enumerate(flipped) if f != flipped[0])
        raise InputError(f"{name}: with orient=False every hole must run opposite to the ring around it; "
                         f"ring {k} does not (or pass orient=True)")
