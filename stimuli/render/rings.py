"""Shapes as rings for the rasteriser: image sizes, rings from contours, arrays
or shapely polygons, and their orientation so that holes subtract.

Points are ``(x, y)`` in image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).
"""

from __future__ import annotations


import numpy as np

from stimuli.errors import InputError
from stimuli.geometry.polyline import shoelace
from stimuli.validate import as_points

def resolve_shape(size=None, shape=None):
    """Return (height, width) from `size` (int or (width, height)) or `shape`."""
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
    return [_ring(r, f"{name}[{k}]") for k, r in enumerate(items)], False


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
    must not cross one another for this to be the even-odd region.
    """
    if len(rings) == 1:
        r = rings[0]
        return [r if shoelace(r) >= 0 else r[::-1]]
    from matplotlib.path import Path as MplPath

    paths = [MplPath(r) for r in rings]
    out = []
    for i, r in enumerate(rings):
        depth = sum(
            1 for j, p in enumerate(paths) if j != i and p.contains_point(r[0], radius=0.0)
        )
        want = 1.0 if depth % 2 == 0 else -1.0
        out.append(r if shoelace(r) * want >= 0 else r[::-1])
    return out
