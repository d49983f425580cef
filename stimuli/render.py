"""Rendering contours to images with exact area-coverage antialiasing.

Points are ``(x, y)`` floats in image pixels: x = column, y = row, y points
down, and pixel ``(i, j)`` (row ``i``, column ``j``) is the unit square
``[j - 0.5, j + 0.5] x [i - 0.5, i + 0.5]`` centred on ``(x, y) = (j, i)``
(OpenCV's convention). The grey level of a pixel is the exact fraction of
that square covered by the shape, blended between ``ground`` and ``figure``.

How the coverage is computed
----------------------------
The rasteriser is the "signed area accumulation" of font rasterisers
(font-rs, stb_truetype), vectorised with numpy. Every polygon edge is split
where it crosses a pixel-grid line, so each piece lies in one pixel. A
piece from ``(x0, y0)`` to ``(x1, y1)`` inside pixel ``(r, c)`` adds the
exact signed area between itself and the pixel's bottom side,
``(x1 - x0) * (1 - ym)`` with ``ym`` its mean height in the pixel, to that
pixel, and the rest of its "cover", ``(x1 - x0) * ym``, to the pixel below.
A cumulative sum down each column then gives, in every pixel, the integral
of the winding number over the pixel square: for rings that do not cross
one another, oriented so that holes subtract, this is the exact covered
area. Pieces left or right of the image are dropped (they affect no image
column) and pieces above it are flattened onto its top edge, so shapes that
touch or cross the border are clipped exactly. The only error is floating
point (about 1e-12 px^2 per pixel).

Discs (:func:`render_dots`) are exact too: the circle is cut where it
crosses grid lines, the polygon through those points is accumulated as
above, and each cut arc adds its circular segment ``R^2/2 (d - sin d)`` to
the one pixel that contains it.

Strokes (:func:`render_outline`, :func:`render_fragments`) are the region
within ``width / 2`` of the polyline, built with shapely's ``buffer`` and
then filled by the same exact rasteriser. Round joins and caps are
polygonised by shapely; ``quad_segs`` is chosen so that the polygon departs
from the true arc by less than 1e-3 px (recorded in the result).

Colours are grey levels in [0, 1] or RGB triples in [0, 1]; float images
are in [0, 1] and :func:`to_uint8` / :func:`to_uint16` quantise them.

The SVG written by :func:`write_svg` uses the same coordinates as the
contour files: its shapes sit in a group with ``transform="translate(0.5
0.5)"``, because in SVG the centre of pixel ``j`` is at user unit
``j + 0.5``. Rasterised at one user unit per pixel it matches the PNG.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from .errors import InputError
from .io import atomic_write

__all__ = [
    "coverage",
    "disc_coverage",
    "fit_to_image",
    "render_silhouette",
    "render_outline",
    "render_fragments",
    "render_dots",
    "to_uint8",
    "to_uint16",
    "write_png",
    "svg_text",
    "write_svg",
]

# Largest departure of shapely's polygonised round joins/caps from the arc.
_ARC_TOLERANCE = 1e-3


# ---------------------------------------------------------------------------
# Input handling


def _resolve_shape(size=None, shape=None):
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


def _as_points(obj, name="points", min_points=1):
    pts = getattr(obj, "points", obj)
    try:
        pts = np.asarray(pts, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected an (N, 2) array of (x, y) points") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError(f"{name}: expected an (N, 2) array of (x, y) points, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        row = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InputError(f"{name}: row {row}: coordinates must be finite, got {pts[row].tolist()}")
    if len(pts) < min_points:
        raise InputError(f"{name}: need at least {min_points} point(s), got {len(pts)}")
    return pts


def _is_single_ring(obj):
    if hasattr(obj, "points"):
        return True
    try:
        a = np.asarray(obj, dtype=float)
    except (TypeError, ValueError):
        return False
    return a.ndim == 2 and a.shape[1:] == (2,)


def _as_rings(obj, name="rings"):
    """Rings from a contour, an (N, 2) array, a list of them, or a shapely polygon.

    Returns (rings, oriented): `oriented` is True when the rings come from a
    shapely geometry already oriented so that holes subtract.
    """
    geom_type = getattr(obj, "geom_type", None)
    if geom_type in ("Polygon", "MultiPolygon", "GeometryCollection"):
        return _rings_from_geometry(obj), True
    if _is_single_ring(obj):
        return [_ring(obj, name)], False
    try:
        items = list(obj)
    except TypeError:
        raise InputError(f"{name}: expected an (N, 2) array, a Contour or a list of them") from None
    if not items:
        raise InputError(f"{name}: no rings given")
    return [_ring(r, f"{name}[{k}]") for k, r in enumerate(items)], False


def _ring(obj, name):
    pts = _as_points(obj, name)
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]  # tolerate a repeated closing point
    if len(np.unique(pts, axis=0)) < 3:
        raise InputError(f"{name}: a ring needs at least 3 distinct points, got {len(pts)}")
    return pts


def _rings_from_geometry(geom):
    """Exterior and interior rings of a shapely (Multi)Polygon, holes reversed."""
    from shapely.geometry.polygon import orient

    rings = []
    for poly in getattr(geom, "geoms", [geom]):
        if poly.geom_type == "MultiPolygon":
            rings.extend(_rings_from_geometry(poly))
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


def _shoelace(p):
    """Raw shoelace sum of a closed ring in the coordinates given."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _orient_rings(rings):
    """Orient rings so that nesting depth parity decides fill (holes subtract).

    A ring inside an even number of other rings gets a positive shoelace sum
    (it adds), one inside an odd number a negative one (it subtracts). Rings
    must not cross one another for this to be the even-odd region.
    """
    if len(rings) == 1:
        r = rings[0]
        return [r if _shoelace(r) >= 0 else r[::-1]]
    from matplotlib.path import Path as MplPath

    paths = [MplPath(r) for r in rings]
    out = []
    for i, r in enumerate(rings):
        depth = sum(
            1 for j, p in enumerate(paths) if j != i and p.contains_point(r[0], radius=0.0)
        )
        want = 1.0 if depth % 2 == 0 else -1.0
        out.append(r if _shoelace(r) * want >= 0 else r[::-1])
    return out


# ---------------------------------------------------------------------------
# The exact rasteriser


def _split(a0, b0, a1, b1, lo, hi):
    """Split segments where coordinate `a` crosses an integer in [lo, hi].

    Returns the pieces (a0, b0, a1, b1) in order along each segment; the
    crossing points carry exactly integral `a`, and both pieces meeting at a
    crossing share bit-identical coordinates.
    """
    amin = np.minimum(a0, a1)
    amax = np.maximum(a0, a1)
    first = np.maximum(np.floor(amin) + 1.0, lo)
    last = np.minimum(np.ceil(amax) - 1.0, hi)
    n = last - first + 1.0
    np.maximum(n, 0.0, out=n)
    n = n.astype(np.intp)
    total = int(n.sum())
    if total == 0:
        return a0, b0, a1, b1
    k = np.repeat(np.arange(len(a0)), n + 1)
    start = np.cumsum(n + 1) - (n + 1)
    m = np.arange(len(k)) - start[k]
    nk = n[k]
    inc = (a1 > a0)[k]
    firstk, lastk = first[k], last[k]
    a0k, b0k = a0[k], b0[k]
    da = a1 - a0
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.where(da != 0.0, (b1 - b0) / da, 0.0)[k]
    mf = m.astype(float)
    # crossing j along a segment: first + j going up, last - j going down
    end_cross = np.where(inc, firstk + mf, lastk - mf)
    start_cross = np.where(inc, end_cross - 1.0, end_cross + 1.0)
    has_start = m > 0
    has_end = m < nk
    pa0 = np.where(has_start, start_cross, a0k)
    pa1 = np.where(has_end, end_cross, a1[k])
    pb0 = np.where(has_start, b0k + (start_cross - a0k) * slope, b0k)
    pb1 = np.where(has_end, b0k + (end_cross - a0k) * slope, b1[k])
    return pa0, pb0, pa1, pb1


def _ring_edges(rings):
    """Edge arrays (x0, y0, x1, y1) of closed rings, shifted by +0.5.

    After the shift pixel (i, j) is the square [j, j+1] x [i, i+1].
    """
    p = np.concatenate(rings) + 0.5
    q = np.concatenate([np.roll(r, -1, axis=0) for r in rings]) + 0.5
    return p[:, 0], p[:, 1], q[:, 0], q[:, 1]


def _pieces(x0, y0, x1, y1, h, w):
    """Cut edges at the pixel grid; return per-piece row, column and weights."""
    # Columns: pieces left or right of the image affect no image column.
    x0, y0, x1, y1 = _split(x0, y0, x1, y1, 0.0, float(w))
    xm = 0.5 * (x0 + x1)
    keep = (xm >= 0.0) & (xm < w) & (x0 != x1)
    x0, y0, x1, y1 = x0[keep], y0[keep], x1[keep], y1[keep]
    # Rows: pieces above the image are flattened onto its top edge (their
    # cover reaches every row below); pieces below it are dropped.
    y0, x0, y1, x1 = _split(y0, x0, y1, x1, 0.0, float(h))
    np.clip(y0, 0.0, h, out=y0)
    np.clip(y1, 0.0, h, out=y1)
    ym = 0.5 * (y0 + y1)
    keep = ym < h
    if not keep.all():
        x0, y0, x1, y1, ym = x0[keep], y0[keep], x1[keep], y1[keep], ym[keep]
    xm = 0.5 * (x0 + x1)
    col = xm.astype(np.intp)  # xm >= 0, so truncation is floor
    row = ym.astype(np.intp)
    # ym can equal an integer only for flat pieces lying on a grid line;
    # truncation then puts them in the pixel below, which is equivalent.
    fy = ym - row
    dx = x1 - x0
    return row, col, dx * (1.0 - fy), dx * fy


def _disc_terms(centers, radius, h, w):
    """Chord-polygon edges and circular-segment corrections of exact discs.

    Returns (edges, extra) with `edges` as from :func:`_ring_edges` (shifted)
    and `extra` = (row, col, area) of segment areas to add to single pixels.
    """
    xs0, ys0, xs1, ys1 = [], [], [], []
    rows, cols, areas = [], [], []
    r = float(radius)
    for cx, cy in centers + 0.5:
        # grid lines crossing the circle; points computed on the lines exactly
        gx = np.arange(math.floor(cx - r) + 1, math.ceil(cx + r))
        gy = np.arange(math.floor(cy - r) + 1, math.ceil(cy + r))
        hx = np.sqrt(np.maximum(r * r - (gx - cx) ** 2, 0.0))
        hy = np.sqrt(np.maximum(r * r - (gy - cy) ** 2, 0.0))
        px = np.concatenate([gx, gx, cx + hy, cx - hy, cx + np.array([r, 0.0, -r, 0.0])])
        py = np.concatenate([cy + hx, cy - hx, gy, gy, cy + np.array([0.0, r, 0.0, -r])])
        ang = np.arctan2(py - cy, px - cx)
        order = np.argsort(ang, kind="stable")
        ang, px, py = ang[order], px[order], py[order]
        d = np.diff(np.append(ang, ang[0] + 2.0 * np.pi))
        keep = d > 0.0
        ang, px, py, d = ang[keep], px[keep], py[keep], d[keep]
        qx, qy = np.roll(px, -1), np.roll(py, -1)
        xs0.append(px), ys0.append(py), xs1.append(qx), ys1.append(qy)
        mid = ang + 0.5 * d
        mx = cx + r * np.cos(mid)
        my = cy + r * np.sin(mid)
        rows.append(np.floor(my).astype(np.intp))
        cols.append(np.floor(mx).astype(np.intp))
        areas.append(0.5 * r * r * (d - np.sin(d)))
    edges = tuple(np.concatenate(v) for v in (xs0, ys0, xs1, ys1))
    row, col, area = (np.concatenate(v) for v in (rows, cols, areas))
    inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
    # The edges run counter-clockwise in (x, y) with y down, i.e. with a
    # positive shoelace sum: the orientation that accumulates +1 inside.
    return edges, (row[inside], col[inside], area[inside])


def _accumulate_box(edges, h, w, extra=None):
    """Exact winding integral over the bounding box of the pieces.

    Returns (acc, r0, c0): `acc` is float64 of the box's shape, the top-left
    pixel of the box is (r0, c0); everything outside the box is 0. Returns
    (None, 0, 0) when nothing falls in the image.
    """
    row, col, top, bottom = _pieces(*edges, h, w)
    if extra is not None and len(extra[0]):
        er, ec, ea = extra
        row = np.concatenate([row, er])
        col = np.concatenate([col, ec])
        top = np.concatenate([top, ea])
        bottom = np.concatenate([bottom, -ea])
    if len(row) == 0:
        return None, 0, 0
    r0, r1 = int(row.min()), int(row.max()) + 1
    c0, c1 = int(col.min()), int(col.max()) + 1
    bh, bw = r1 - r0, c1 - c0
    idx = (row - r0) * bw + (col - c0)
    acc = np.bincount(
        np.concatenate([idx, idx + bw]),
        weights=np.concatenate([top, bottom]),
        minlength=(bh + 1) * bw,
    ).reshape(bh + 1, bw)
    np.cumsum(acc, axis=0, out=acc)
    acc = acc[: min(bh, h - r0)]
    return acc, r0, c0


def _coverage_box(rings, h, w, oriented=False, orient=True, extra_edges=None, extra=None):
    """Coverage in [0, 1] over the bounding box: (cov, r0, c0) or (None, 0, 0)."""
    if rings:
        if orient and not oriented:
            rings = _orient_rings(rings)
        edges = _ring_edges(rings)
        if extra_edges is not None:
            edges = tuple(np.concatenate([a, b]) for a, b in zip(edges, extra_edges))
    else:
        edges = extra_edges
    acc, r0, c0 = _accumulate_box(edges, h, w, extra)
    if acc is None:
        return None, 0, 0
    if not (orient or oriented):
        np.abs(acc, out=acc)
    # Round-off can leave -1e-15 or 1 + 1e-15; overlapping rings give > 1.
    np.clip(acc, 0.0, 1.0, out=acc)
    return acc, r0, c0


def _dense(box, h, w):
    cov, r0, c0 = box
    out = np.zeros((h, w))
    if cov is not None:
        out[r0 : r0 + cov.shape[0], c0 : c0 + cov.shape[1]] = cov
    return out


def coverage(rings, shape, orient=True):
    """Exact area coverage of pixels by polygons.

    Parameters
    ----------
    rings : (N, 2) array, Contour, list of them, or shapely (Multi)Polygon
        Closed rings of ``(x, y)`` points in image pixels (x = column,
        y = row, y down, pixel centres at integer coordinates); the first
        point is not repeated at the end. Several rings make one shape: a
        ring inside an odd number of other rings is a hole.
    shape : (int, int)
        Image ``(height, width)``.
    orient : bool, optional
        If True (default), rings are re-oriented by nesting depth so that
        holes subtract, which gives the exact even-odd region for rings that
        do not cross one another. If False the rings are used as given and
        the coverage is ``min(|integral of the winding number|, 1)`` over
        each pixel (exact for one simple ring; an approximation only in
        pixels where a self-intersecting ring crosses itself).

    Returns
    -------
    cov : (height, width) float64 array
        Fraction in [0, 1] of each pixel square
        ``[j - 0.5, j + 0.5] x [i - 0.5, i + 0.5]`` inside the shape. Parts of
        the shape outside the image are clipped away exactly.

    Raises
    ------
    InputError
        Non-finite coordinates, a ring with fewer than 3 distinct points, or
        a bad shape.

    References
    ----------
    .. [1] R. Levien, "Inside the fastest font renderer in the world" (font-rs),
           2016. https://medium.com/@raphlinus/inside-the-fastest-font-renderer-in-the-world-75ae5270c445
    .. [2] S. Barrett, stb_truetype.h, version 2 rasteriser.

    Examples
    --------
    >>> cov = coverage([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)], (3, 3))
    >>> cov[:2, :2].tolist()
    [[0.25, 0.5], [0.5, 1.0]]
    """
    h, w = _resolve_shape(shape=shape)
    rings, oriented = _as_rings(rings)
    return _dense(_coverage_box(rings, h, w, oriented=oriented, orient=orient), h, w)


def disc_coverage(centers, radius, shape):
    """Exact area coverage of pixels by discs.

    Parameters
    ----------
    centers : (M, 2) array
        Disc centres ``(x, y)`` in image pixels (y down, pixel centres at
        integer coordinates).
    radius : float
        Disc radius in pixels (> 0).
    shape : (int, int)
        Image ``(height, width)``.

    Returns
    -------
    cov : (height, width) float64 array
        Exact covered fraction of each pixel (to floating point), clipped to
        [0, 1]. Where discs overlap the winding integrals add and are
        clipped at 1, exact except in pixels crossed by two circles.
    """
    h, w = _resolve_shape(shape=shape)
    centers = _as_points(centers, "centers")
    radius = _positive(radius, "radius")
    edges, extra = _disc_terms(centers, radius, h, w)
    return _dense(_coverage_box([], h, w, extra_edges=edges, extra=extra), h, w)


def _positive(value, name):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name}: must be a finite number > 0, got {value!r}")
    return v
