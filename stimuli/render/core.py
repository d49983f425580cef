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
A cumulative sum down each column (done with ``cv2.integral``, several
times faster than ``np.cumsum``) then gives, in every pixel, the integral
``w`` of the winding number over the pixel square, and the coverage is
``min(|w|, 1)``: exact for a simple ring and for holes (rings are oriented
by nesting so that holes subtract); a self-intersecting ring is filled by
the non-zero rule, exact except in the pixels where it crosses itself.
Pieces left or right of the image are dropped (they affect no image column)
and pieces above or below it are flattened onto its top or bottom edge, so
shapes that touch or cross the border are clipped exactly. The only error is
floating point (about 1e-13 px^2 per pixel); values within 1e-10 of 0 or 1
are snapped so that figure and ground colours come out exactly.

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

Speed: a 512 x 512 image of a 500-vertex polygon takes about 0.3 ms as
uint8 and 0.5 ms as float64 (see ``benchmarks/bench_render.py``).

References
----------
.. [1] R. Levien, "Inside the fastest font renderer in the world" (font-rs),
       2016.
.. [2] S. Barrett, stb_truetype.h, version 2 rasteriser.
"""

from __future__ import annotations

import math
import threading
from pathlib import Path

import numpy as np

from stimuli.errors import InputError
from stimuli.io import as_number, as_points, atomic_write

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
# Coverage within this of 0 or 1 is round-off and is snapped (px^2).
_SNAP = 1e-10


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


def _is_single_ring(obj):
    if hasattr(obj, "points"):
        return True
    if isinstance(obj, np.ndarray):
        return obj.ndim == 2 and obj.shape[1:] == (2,)
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
    pts = as_points(obj, name)
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]  # tolerate a repeated closing point
    if _distinct_at_most_two(pts):
        raise InputError(f"{name}: a ring needs at least 3 distinct points")
    return pts


def _distinct_at_most_two(pts):
    """True if `pts` holds fewer than 3 distinct points (cheaper than np.unique)."""
    other = (pts != pts[0]).any(axis=1)
    if not other.any():
        return True
    p1 = pts[int(np.argmax(other))]
    return not (other & (pts != p1).any(axis=1)).any()


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
    s = (x[:-1] * y[1:]).sum() - (x[1:] * y[:-1]).sum() + x[-1] * y[0] - x[0] * y[-1]
    return 0.5 * float(s)


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
#
# Rings travel as one "stream" of points per coordinate: every ring is closed
# by repeating its first point, and the pieces joining one ring's last point
# to the next ring's first point are flagged in `bridge` and never counted.
# Grid crossings are inserted into the stream, so that the two pieces meeting
# at a crossing share one computed point (no cracks, no double counting).


def _stream(rings):
    """(x, y, bridge) of closed rings, shifted by +0.5 so that pixel (i, j)
    is the square [j, j+1] x [i, i+1]. `bridge` is None for one ring."""
    if len(rings) == 1:
        r = rings[0]
        p = np.concatenate([r, r[:1]]) + 0.5
        return np.ascontiguousarray(p[:, 0]), np.ascontiguousarray(p[:, 1]), None
    parts, flags = [], []
    for r in rings:
        parts += [r, r[:1]]
        f = np.zeros(len(r) + 1, bool)
        f[-1] = True
        flags.append(f)
    p = np.concatenate(parts) + 0.5
    return (
        np.ascontiguousarray(p[:, 0]),
        np.ascontiguousarray(p[:, 1]),
        np.concatenate(flags)[:-1],
    )


def _refine(a, b, lo, hi, bridge):
    """Insert the points where a stream crosses ``a = integer`` in [lo, hi].

    Crossing points carry exactly integral `a`; `b` is interpolated from the
    start of the piece, so original vertices are kept bit for bit.
    """
    a0, a1 = a[:-1], a[1:]
    first = np.floor(np.minimum(a0, a1))
    first += 1.0
    np.maximum(first, lo, out=first)
    last = np.ceil(np.maximum(a0, a1))
    last -= 1.0
    np.minimum(last, hi, out=last)
    n = last - first
    n += 1.0
    np.maximum(n, 0.0, out=n)
    if bridge is not None:
        n[bridge] = 0.0
    cnt = n.astype(np.intp)
    cnt += 1
    total = int(cnt.sum())
    if total == len(a0):
        return a, b, bridge
    k = np.repeat(np.arange(len(a0)), cnt)
    pos = np.cumsum(cnt)
    pos -= cnt  # new index of each old point
    up = a1 > a0
    step = np.where(up, 1.0, -1.0)
    # value of crossing j (j = 1, 2, ...) is e0 + step * (new index)
    e0 = np.where(up, first - 1.0, last + 1.0)
    e0 -= step * pos
    b0 = b[:-1]
    da = a1 - a0
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = (b[1:] - b0) / da
    slope[da == 0.0] = 0.0
    na = np.empty(total + 1)
    nb = np.empty(total + 1)
    v = np.arange(total, dtype=float)
    v *= step[k]
    v += e0[k]
    na[:-1] = v
    na[pos] = a0
    na[-1] = a[-1]
    v -= a0[k]
    v *= slope[k]
    v += b0[k]
    nb[:-1] = v
    nb[pos] = b0
    nb[-1] = b[-1]
    if bridge is not None:
        flags = np.zeros(total, bool)
        flags[pos[bridge]] = True
        bridge = flags
    return na, nb, bridge


def _accumulate(x, y, bridge, h, w, extra=None):
    """Cut a stream at the pixel grid and integrate the winding number.

    Returns ``(win, r0, c0, area)`` or None when nothing reaches the image:
    `win` is the winding integral over each pixel of the box whose top-left
    pixel is (r0, c0) (0 outside the box), a view of a scratch buffer to be
    used before the next call; `area` is its sum.
    """
    import cv2

    # Columns: pieces left or right of the image affect no image column.
    x, y, bridge = _refine(x, y, 0.0, float(w), bridge)
    # Rows: pieces above the image are flattened onto its top edge (their
    # cover reaches every row below), pieces below it onto its bottom edge
    # (they add nothing inside, but they keep the box reaching the bottom
    # row when the shape runs off the bottom of the image).
    y, x, bridge = _refine(y, x, 0.0, float(h), bridge)
    np.clip(y, 0.0, float(h), out=y)
    x0 = x[:-1]
    dx = x[1:] - x0
    xm = x0 + x[1:]
    xm *= 0.5
    ym = y[:-1] + y[1:]
    ym *= 0.5
    keep = (xm >= 0.0) & (xm < w) & (dx != 0.0)
    if bridge is not None:
        keep &= ~bridge
    xm, ym, dx = xm[keep], ym[keep], dx[keep]
    col = xm.astype(np.intp)  # xm >= 0: truncation is floor
    row = ym.astype(np.intp)
    # A piece adds the signed area between itself and its pixel's bottom
    # side to its pixel, and the rest of its cover (dx * fy) to the pixel
    # below; summing down each column gives the winding integral.
    bottom = ym - row
    bottom *= dx
    top = dx - bottom
    if extra is not None and len(extra[0]):
        er, ec, ea = extra
        row = np.concatenate([row, er])
        col = np.concatenate([col, ec])
        top = np.concatenate([top, ea])
        bottom = np.concatenate([bottom, -ea])
    if len(row) == 0:
        return None
    r0, c0 = int(row.min()), int(col.min())
    if r0 >= h:  # everything lies below the image
        return None
    row -= r0
    col -= c0
    bh, bw = int(row.max()) + 1, int(col.max()) + 1
    # cv2.integral is a vectorised 2-D prefix sum, several times faster than
    # np.cumsum. Each contribution v is entered as +v in its column and -v in
    # the next, so the prefix sum along rows gives v in that column alone and
    # the table is the column-wise cumulative sum we want.
    stride = bw + 1
    idx = row * stride
    idx += col
    flat = np.concatenate([idx, idx + 1, idx + stride, idx + (stride + 1)])
    acc = _workspace("acc", (bh + 1) * stride, zeroed=True)
    try:
        np.add.at(acc, flat, np.concatenate([top, -top, bottom, -bottom]))
        table = _workspace("sum", (bh + 2) * (stride + 1)).reshape(bh + 2, stride + 1)
        cv2.integral(acc.reshape(bh + 1, stride), table, sdepth=cv2.CV_64F)
    finally:
        # leave the scratch buffer all zero for the next call
        if 8 * len(flat) < acc.size:
            acc[flat] = 0.0
        else:
            acc.fill(0.0)
    # Pieces on the bottom edge sit in row h, outside the image.
    bh = min(bh, h - r0)
    # Pixel i of a column holds its own top part and every part above it.
    # (No np.dot here: OpenBLAS threads stall for milliseconds on a busy
    # machine, and float-by-int dots are slow anyway.)
    below = (bh - row).astype(np.float64)
    np.maximum(below, 0.0, out=below)
    top *= below
    below -= 1.0
    np.maximum(below, 0.0, out=below)
    bottom *= below
    area = float(top.sum() + bottom.sum())
    return table[1 : bh + 1, 1 : bw + 1], r0, c0, area


_TLS = threading.local()


def _workspace(name, n, zeroed=False):
    """A per-thread float64 scratch buffer of `n` elements, reused across calls.

    Fresh multi-megabyte arrays cost page faults on every call (glibc hands
    freed big blocks back to the system), which took longer than the
    rasterising itself. A `zeroed` buffer is all zero on return and must be
    left so by the caller. The buffers never leave this module: everything
    returned to callers is computed from them into new arrays.
    """
    if n > _WORKSPACE_MAX:  # huge images: do not keep hundreds of MB around
        return (np.zeros if zeroed else np.empty)(n)
    buf = getattr(_TLS, name, None)
    if buf is None or buf.size < n:
        buf = (np.zeros if zeroed else np.empty)(max(n, 1 << 18))
        setattr(_TLS, name, buf)
    return buf[:n]


_WORKSPACE_MAX = 1 << 23  # elements (64 MB) per scratch buffer and thread


def _box_coverage(acc):
    """(cov, r0, c0): cov = min(|winding integral|, 1), a new array over the box.

    Values within 1e-10 of 0 or 1 are round-off (+-1e-15) and are snapped to
    0 or 1, so that ground and figure colours come out exactly: a grey level
    on a half-integer, e.g. 0.5 * 255, would otherwise round differently
    inside and outside the box.
    """
    import cv2

    if acc is None:
        return None, 0, 0
    win, r0, c0, _ = acc
    cov = cv2.absdiff(win, 0.0)  # a new contiguous array
    cv2.min(cov, 1.0, dst=cov)  # overlapping rings give > 1
    cv2.threshold(cov, _SNAP, 0.0, cv2.THRESH_TOZERO, dst=cov)
    ones = cv2.threshold(cov, 1.0 - _SNAP, 1.0, cv2.THRESH_BINARY)[1]
    cv2.max(cov, ones, dst=cov)
    return cov, r0, c0


def _ring_acc(rings, h, w, oriented=False, orient=True):
    if orient and not oriented:
        rings = _orient_rings(rings)
    x, y, bridge = _stream(rings)
    return _accumulate(x, y, bridge, h, w)


def _ring_coverage(rings, h, w, oriented=False, orient=True):
    return _box_coverage(_ring_acc(rings, h, w, oriented, orient))


def _disc_terms(centers, radius, h, w):
    """Chord polygons and circular-segment corrections of exact discs.

    Each circle is cut where it crosses a grid line (and at its four extreme
    points); the polygon through the cuts is rasterised exactly, and each
    arc's circular segment ``R^2/2 (d - sin d)`` lies in the one pixel that
    holds the arc, so it is added there. Returns (rings, extra) with rings in
    image coordinates and extra = (row, col, area).
    """
    rings, rows, cols, areas = [], [], [], []
    r = float(radius)
    quad = np.array([r, 0.0, -r, 0.0]), np.array([0.0, r, 0.0, -r])
    for cx, cy in centers + 0.5:
        # Only grid lines of the image (edges included) need cuts: an arc
        # outside the image spans the same columns as its chord (arcs are
        # monotone between the extreme points) and its segment is dropped.
        gx = np.arange(max(math.floor(cx - r) + 1, 0), min(math.ceil(cx + r), w + 1), dtype=float)
        gy = np.arange(max(math.floor(cy - r) + 1, 0), min(math.ceil(cy + r), h + 1), dtype=float)
        hx = np.sqrt(np.maximum(r * r - (gx - cx) ** 2, 0.0))
        hy = np.sqrt(np.maximum(r * r - (gy - cy) ** 2, 0.0))
        px = np.concatenate([gx, gx, cx + hy, cx - hy, cx + quad[0]])
        py = np.concatenate([cy + hx, cy - hx, gy, gy, cy + quad[1]])
        ang = np.arctan2(py - cy, px - cx)
        order = np.argsort(ang, kind="stable")
        ang, px, py = ang[order], px[order], py[order]
        d = np.diff(np.append(ang, ang[0] + 2.0 * np.pi))
        keep = d > 0.0
        ang, px, py, d = ang[keep], px[keep], py[keep], d[keep]
        # increasing angle with y down: positive shoelace, +1 inside
        rings.append(np.column_stack([px - 0.5, py - 0.5]))
        mid = ang + 0.5 * d
        rows.append(np.floor(cy + r * np.sin(mid)).astype(np.intp))
        cols.append(np.floor(cx + r * np.cos(mid)).astype(np.intp))
        areas.append(0.5 * r * r * (d - np.sin(d)))
    row, col, area = (np.concatenate(v) for v in (rows, cols, areas))
    inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
    return rings, (row[inside], col[inside], area[inside])


def _disc_acc(centers, radius, h, w):
    rings, extra = _disc_terms(centers, radius, h, w)
    x, y, bridge = _stream(rings)
    return _accumulate(x, y, bridge, h, w, extra)


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
        do not cross one another. If False they are used as given (a hole
        must then run opposite to its outer ring).

    Returns
    -------
    cov : (height, width) float64 array
        Fraction in [0, 1] of each pixel square
        ``[j - 0.5, j + 0.5] x [i - 0.5, i + 0.5]`` inside the shape. Parts of
        the shape outside the image are clipped away exactly. Values within
        1e-10 of 0 or 1 are round-off and are snapped.

    Notes
    -----
    What is computed is ``min(|w|, 1)`` where ``w`` is the integral of the
    winding number over the pixel. That is the exact coverage for a simple
    ring and for properly nested holes; a self-intersecting ring is filled
    by the non-zero rule, exactly except in the pixels where it crosses
    itself (where lobes of opposite winding partly cancel).

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
    A unit square with corners at pixel centres covers a quarter of four
    pixels; shifted by half a pixel it covers pixel (0, 0) exactly:

    >>> sq = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
    >>> coverage(sq, (2, 3)).tolist()
    [[0.25, 0.25, 0.0], [0.25, 0.25, 0.0]]
    >>> coverage(sq - 0.5, (2, 2)).tolist()
    [[1.0, 0.0], [0.0, 0.0]]
    """
    h, w = _resolve_shape(shape=shape)
    rings, oriented = _as_rings(rings)
    return _dense(_ring_coverage(rings, h, w, oriented=oriented, orient=orient), h, w)


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

    Examples
    --------
    A disc of diameter 1 inscribed in pixel (3, 3) covers pi/4 of it:

    >>> cov = disc_coverage([(3.0, 3.0)], 0.5, (7, 7))
    >>> bool(np.isclose(cov[3, 3], np.pi / 4)), float(cov.sum() - cov[3, 3])
    (True, 0.0)
    """
    h, w = _resolve_shape(shape=shape)
    centers = as_points(centers, "centers")
    radius = as_number(radius, "radius", gt=0)
    return _dense(_box_coverage(_disc_acc(centers, radius, h, w)), h, w)


# ---------------------------------------------------------------------------
# Images


_SCALE = {np.dtype(np.float64): 1.0, np.dtype(np.uint8): 255.0, np.dtype(np.uint16): 65535.0}


def _resolve_dtype(dtype):
    try:
        dt = np.dtype(np.float64 if dtype is None else dtype)
    except TypeError:
        raise InputError(f"dtype: expected 'float64', 'uint8' or 'uint16', got {dtype!r}") from None
    if dt not in _SCALE:
        raise InputError(f"dtype: expected 'float64', 'uint8' or 'uint16', got {dtype!r}")
    return dt


def _colour(value, name):
    """A grey level or an RGB triple in [0, 1], as a tuple of floats."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and 0.0 <= value <= 1.0:
        return (float(value),)
    try:
        v = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a grey level or an (r, g, b) triple in [0, 1], got {value!r}") from None
    if v.ndim != 1 or len(v) not in (1, 3) or not np.all((v >= 0.0) & (v <= 1.0)):
        raise InputError(f"{name}: expected a grey level or an (r, g, b) triple in [0, 1], got {value!r}")
    return tuple(float(c) for c in v)


def _colours(figure, ground):
    f, g = _colour(figure, "figure"), _colour(ground, "ground")
    if len(f) != len(g):
        f, g = (f * 3 if len(f) == 1 else f), (g * 3 if len(g) == 1 else g)
    return f, g


def _plain(c):
    return c[0] if len(c) == 1 else c


def _paint(box, h, w, figure, ground, dtype):
    """Blend ground and figure by coverage into an image of `dtype`.

    Integer images are ``rint(scale * (ground + cov * (figure - ground)))``,
    the same operations as :func:`to_uint8` / :func:`to_uint16` applied to
    the float image, so both routes give identical pixels.
    """
    cov, r0, c0 = box
    scale = _SCALE[dtype]
    integer = dtype != np.float64
    n = len(figure)
    img = np.empty((h, w) if n == 1 else (h, w, n), dtype)
    for ch in range(n):
        g = ground[ch]
        fill = np.rint(g * scale) if integer else g
        if n == 1:
            img.fill(fill)
        else:
            img[..., ch] = fill
        if cov is None:
            continue
        # the last channel may overwrite the coverage array (it is ours)
        v = np.multiply(cov, figure[ch] - g, out=cov if ch == n - 1 else None)
        v += g
        if integer:
            v *= scale
            np.rint(v, out=v)
        sub = img[r0 : r0 + cov.shape[0], c0 : c0 + cov.shape[1]]
        if n == 1:
            sub[...] = v
        else:
            sub[..., ch] = v
    return img


def _paint_uint8(acc, h, w, figure, ground):
    """Fast 8-bit image straight from the winding integral.

    ``cv2.convertScaleAbs(win, alpha=255)`` gives ``rint(255 * min(|win|, 1))``
    in one pass (the absolute value and the saturation are exactly the
    coverage rule of :func:`coverage`); a lookup table then blends ground and
    figure. Rounding twice can put a pixel one level away from
    :func:`to_uint8` of the float image.
    """
    import cv2

    n = len(figure)
    img = np.empty((h, w) if n == 1 else (h, w, n), np.uint8)
    k = np.arange(256.0)
    luts = [np.rint(255.0 * g + (f - g) * k).astype(np.uint8) for f, g in zip(figure, ground)]
    for ch in range(n):
        if n == 1:
            img.fill(luts[0][0])
        else:
            img[..., ch] = luts[ch][0]
    if acc is None:
        return img
    win, r0, c0, _ = acc
    sub = img[r0 : r0 + win.shape[0], c0 : c0 + win.shape[1]]
    if n == 1:
        cv2.convertScaleAbs(win, sub, 255.0)
        if np.array_equal(luts[0], 255.0 - k):  # black on white: much faster than a LUT
            cv2.bitwise_not(sub, dst=sub)
        elif not np.array_equal(luts[0], k):
            cv2.LUT(sub, luts[0], dst=sub)
    else:
        u = cv2.convertScaleAbs(win, alpha=255.0)
        for ch in range(n):
            sub[..., ch] = cv2.LUT(u, luts[ch])
    return img


def _render(acc, h, w, figure, ground, dtype):
    """Image of `dtype` from an accumulation (see :func:`_accumulate`)."""
    if dtype == np.uint8:
        return _paint_uint8(acc, h, w, figure, ground)
    return _paint(_box_coverage(acc), h, w, figure, ground, dtype)


def _result(kind, img, h, w, figure, ground, dtype, **params):
    out = {
        "img": img,
        "kind": kind,
        "size": (w, h),
        "shape": (h, w),
        "figure": _plain(figure),
        "ground": _plain(ground),
        "dtype": dtype.name,
    }
    out.update(params)
    return out


def render_silhouette(
    contour_or_points, size=None, *, shape=None, figure=0.0, ground=1.0, dtype=None, orient=True
):
    """Render a filled silhouette with exact area-coverage antialiasing.

    Parameters
    ----------
    contour_or_points : Contour, (N, 2) array, list of them, or shapely polygon
        The outline as ``(x, y)`` points in image pixels (x = column, y = row,
        y down, pixel centres at integer coordinates), first point not
        repeated. A list of rings makes one shape; a ring inside an odd
        number of others is a hole.
    size : int or (int, int), optional
        Image ``(width, height)`` (an int for a square). Give this or `shape`.
    shape : (int, int), optional
        Image ``(height, width)``, the numpy way round.
    figure, ground : float or (float, float, float), optional
        Grey levels (or RGB triples) in [0, 1] of the shape and of the
        background. Default black (0) on white (1).
    dtype : {None, 'float64', 'uint8', 'uint16'}, optional
        Image type; None gives float64 in [0, 1]. 'uint16' is exactly
        :func:`to_uint16` of the float image. 'uint8' takes a faster route:
        the coverage is rounded to 1/255 (half to even) and then figure and
        ground are blended and rounded, so a pixel can differ from
        :func:`to_uint8` of the float image by one level (where the value
        is a tie, such as exact half coverage, or for grey levels).
    orient : bool, optional
        See :func:`coverage`.

    Returns
    -------
    dict
        ``img`` ((height, width) or (height, width, 3) array; RGB order),
        ``kind`` ('silhouette'), ``size`` (width, height), ``shape``
        (height, width), ``figure``, ``ground``, ``dtype``, ``rings`` (the
        rings drawn, as (N, 2) arrays), ``orient``, ``area`` (the integral
        of the winding number over the image, px^2: the exact area of the
        shape inside the image for a simple ring or properly nested holes,
        i.e. the sum of the coverage).

    Raises
    ------
    InputError
        Bad points, size, colours or dtype.

    Examples
    --------
    >>> sq = np.array([(0.5, 0.5), (2.5, 0.5), (2.5, 2.5), (0.5, 2.5)])
    >>> render_silhouette(sq, size=4)["img"].tolist()[1]
    [1.0, 0.0, 0.0, 1.0]
    """
    h, w = _resolve_shape(size, shape)
    f, g = _colours(figure, ground)
    dt = _resolve_dtype(dtype)
    rings, oriented = _as_rings(contour_or_points, "contour_or_points")
    acc = _ring_acc(rings, h, w, oriented=oriented, orient=orient)
    area = 0.0 if acc is None else acc[3]
    img = _render(acc, h, w, f, g, dt)
    return _result("silhouette", img, h, w, f, g, dt, rings=rings, orient=bool(orient), area=area)


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
    h, w = _resolve_shape(size, shape)
    f, g = _colours(figure, ground)
    dt = _resolve_dtype(dtype)
    join = _choice(join, _JOINS, "join")
    cap = _choice(cap, _CAPS, "cap")
    mitre_limit = as_number(mitre_limit, "mitre_limit", gt=0)
    q = _quad_segs(width / 2, quad_segs)
    geom = shapely.LinearRing(pts) if closed else shapely.LineString(pts)
    stroke = _stroke([geom], width, join, cap, mitre_limit, q)
    rings = _rings_from_geometry(stroke)
    acc = _ring_acc(rings, h, w, oriented=True) if rings else None
    img = _render(acc, h, w, f, g, dt)
    return _result(
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

    if _is_single_ring(polylines):
        raise InputError("polylines: expected a list of (M, 2) arrays, got a single array")
    try:
        items = list(polylines)
    except TypeError:
        raise InputError("polylines: expected a list of (M, 2) arrays") from None
    lines = [as_points(p, f"polylines[{k}]", min_points=2) for k, p in enumerate(items)]
    width = as_number(width, "width", gt=0)
    h, w = _resolve_shape(size, shape)
    f, g = _colours(figure, ground)
    dt = _resolve_dtype(dtype)
    cap = _choice(cap, _CAPS, "cap")
    join = _choice(join, _JOINS, "join")
    mitre_limit = as_number(mitre_limit, "mitre_limit", gt=0)
    q = _quad_segs(width / 2, quad_segs)
    if lines:
        stroke = _stroke([shapely.LineString(p) for p in lines], width, join, cap, mitre_limit, q)
        rings = _rings_from_geometry(stroke)
        area = float(stroke.area)
    else:
        rings, area = [], 0.0
    acc = _ring_acc(rings, h, w, oriented=True) if rings else None
    img = _render(acc, h, w, f, g, dt)
    return _result(
        "fragments", img, h, w, f, g, dt, polylines=lines, width=width, cap=cap, join=join,
        mitre_limit=mitre_limit, quad_segs=q, area=area, stroke_rings=rings,
    )


def render_dots(points, radius, size=None, *, shape=None, figure=0.0, ground=1.0, dtype=None):
    """Render dots as discs with exact area coverage.

    The coverage of every pixel by a disc is computed exactly (to floating
    point), not from a polygonised circle: see :func:`disc_coverage`.

    Parameters
    ----------
    points : Contour or (M, 2) array
        Dot centres ``(x, y)`` in image pixels (y down, pixel centres at
        integer coordinates).
    radius : float
        Dot radius in pixels (> 0).
    size, shape, figure, ground, dtype
        As in :func:`render_silhouette`.

    Returns
    -------
    dict
        ``img``, ``kind`` ('dots'), ``size``, ``shape``, ``figure``,
        ``ground``, ``dtype``, ``centers``, ``radius``.

    Notes
    -----
    Where two dots overlap their coverages add and are clipped at 1: exact
    except in the few pixels that both circles cross.
    """
    centers = as_points(points, "points")
    radius = as_number(radius, "radius", gt=0)
    h, w = _resolve_shape(size, shape)
    f, g = _colours(figure, ground)
    dt = _resolve_dtype(dtype)
    img = _render(_disc_acc(centers, radius, h, w), h, w, f, g, dt)
    return _result("dots", img, h, w, f, g, dt, centers=centers, radius=radius)


def fit_to_image(points, size, margin=None, scale=None):
    """Scale and centre points into an image.

    The bounding box of the points is scaled by `scale` (default: as large
    as fits inside the image less `margin` on every side) and centred on the
    image centre ``((width - 1) / 2, (height - 1) / 2)``. The image spans
    ``[-0.5, width - 0.5] x [-0.5, height - 0.5]`` in pixel coordinates.

    Parameters
    ----------
    points : Contour or (N, 2) array
        ``(x, y)`` points (any units; y down as in images).
    size : int or (int, int)
        Image ``(width, height)``.
    margin : float, optional
        Free space in pixels between the bounding box and each image edge,
        used to choose the scale. Default: 10% of the smaller image side.
    scale : float, optional
        Fixed scale factor (pixels per input unit); the points are then only
        centred and `margin` is ignored.

    Returns
    -------
    dict
        ``points`` ((N, 2) array in image pixels), ``scale``, ``offset``
        ((2,) array, image = points * scale + offset), ``size``, ``margin``.

    Raises
    ------
    InputError
        Bad points, size or margin, or points whose bounding box is a single
        point.

    Examples
    --------
    >>> fit_to_image([(0, 0), (1, 0), (1, 1), (0, 1)], size=12, margin=1)["points"].tolist()
    [[0.5, 0.5], [10.5, 0.5], [10.5, 10.5], [0.5, 10.5]]
    """
    pts = as_points(points, "points")
    h, w = _resolve_shape(size)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    extent = hi - lo
    if scale is None:
        if margin is None:
            margin = 0.1 * min(w, h)
        try:
            margin = float(margin)
        except (TypeError, ValueError):
            raise InputError(f"margin: expected a number of pixels, got {margin!r}") from None
        if not (math.isfinite(margin) and 0 <= margin < 0.5 * min(w, h)):
            raise InputError(f"margin: must be >= 0 and less than half the smaller image side, got {margin!r}")
        if not np.any(extent > 0):
            raise InputError("points: all points coincide; cannot scale them to the image")
        room = np.array([w, h], float) - 2.0 * margin
        with np.errstate(divide="ignore"):
            scale = float(np.min(np.where(extent > 0, room / np.where(extent > 0, extent, 1.0), np.inf)))
    else:
        scale = as_number(scale, "scale", gt=0)
    centre = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
    offset = centre - scale * (lo + hi) / 2.0
    return {
        "points": pts * scale + offset,
        "scale": scale,
        "offset": offset,
        "size": (w, h),
        "margin": None if margin is None else float(margin),
    }


# ---------------------------------------------------------------------------
# Output


def _check_unit(img, name="image"):
    a = np.asarray(img, dtype=float)
    if a.size:
        lo, hi = a.min(), a.max()  # NaN propagates into both
        if np.isnan(lo) or np.isnan(hi):
            raise InputError(f"{name}: contains NaN values")
        if lo < -1e-9 or hi > 1.0 + 1e-9:
            raise InputError(f"{name}: float values must lie in [0, 1], got [{lo:g}, {hi:g}]")
    return a


def _quantise(img, top, dtype):
    a = _check_unit(img)
    m = np.multiply(a, float(top), out=np.empty(a.shape))
    np.rint(m, out=m)  # -0.0 and top + 3e-7 round into range after the check
    return m.astype(dtype)


def to_uint8(img):
    """Quantise an image to 8 bits: ``rint(255 * img)`` for floats in [0, 1].

    uint8 input is returned unchanged, uint16 input is rescaled
    (``rint(v / 257)``).

    Raises
    ------
    InputError
        Float values outside [0, 1] or not finite; other dtypes.
    """
    img = np.asarray(img)
    if img.dtype == np.uint8:
        return img
    if img.dtype == np.uint16:
        return np.rint(img / 257.0).astype(np.uint8)
    if not np.issubdtype(img.dtype, np.floating):
        raise InputError(f"image: expected floats in [0, 1], uint8 or uint16, got {img.dtype}")
    return _quantise(img, 255, np.uint8)


def to_uint16(img):
    """Quantise an image to 16 bits: ``rint(65535 * img)`` for floats in [0, 1].

    uint16 input is returned unchanged, uint8 input is rescaled exactly
    (``v * 257``, so that 255 becomes 65535).

    Raises
    ------
    InputError
        Float values outside [0, 1] or not finite; other dtypes.
    """
    img = np.asarray(img)
    if img.dtype == np.uint16:
        return img
    if img.dtype == np.uint8:
        return img.astype(np.uint16) * np.uint16(257)
    if not np.issubdtype(img.dtype, np.floating):
        raise InputError(f"image: expected floats in [0, 1], uint8 or uint16, got {img.dtype}")
    return _quantise(img, 65535, np.uint16)


def _image_of(image):
    return image["img"] if isinstance(image, dict) else image


def _parent_exists(path):
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"{path}: output directory {path.parent} does not exist")
    return path


def write_png(path, image, bit_depth=8):
    """Write an image as PNG, atomically (temporary name, then rename).

    Parameters
    ----------
    path : str or Path
        Output file; its directory must exist.
    image : array or dict
        (height, width) grey or (height, width, 3) RGB image: floats in
        [0, 1], uint8 or uint16; or a result dict of a ``render_*`` function.
    bit_depth : {8, 16}
        Bits per channel written.

    Returns
    -------
    Path
        The file written. The bytes depend only on the pixels (OpenCV's PNG
        encoder with default settings writes no time stamp).

    Raises
    ------
    InputError
        Bad image, bit depth or output directory.
    """
    import cv2

    img = np.asarray(_image_of(image))
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] != 3) or img.size == 0:
        raise InputError(f"{path}: image must be (height, width) or (height, width, 3), got shape {img.shape}")
    if bit_depth == 8:
        img = to_uint8(img)
    elif bit_depth == 16:
        img = to_uint16(img)
    else:
        raise InputError(f"{path}: bit_depth must be 8 or 16, got {bit_depth!r}")
    if img.ndim == 3:
        img = np.ascontiguousarray(img[..., ::-1])  # OpenCV wants BGR
    ok, buf = cv2.imencode(".png", img)
    if not ok:  # pragma: no cover - OpenCV failure
        raise InputError(f"{path}: OpenCV could not encode the image as PNG")
    path = _parent_exists(path)
    with atomic_write(path, "wb") as fh:
        fh.write(buf.tobytes())
    return path


def _num(v):
    s = f"{float(v):.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _hex(c):
    c = (c,) * 3 if np.ndim(c) == 0 else tuple(c)
    return "#" + "".join(f"{int(np.rint(255.0 * v)):02x}" for v in c)


def _path_data(lines, closed):
    out = []
    for p in lines:
        coords = " ".join(f"{_num(x)} {_num(y)}" for x, y in p[1:])
        out.append(f"M {_num(p[0, 0])} {_num(p[0, 1])} L {coords}" + (" Z" if closed else ""))
    return " ".join(out)


def svg_text(result):
    """The SVG document (a str) of a ``render_*`` result.

    Shapes are drawn inside ``<g transform="translate(0.5 0.5)">`` so that
    the numbers in the file are the same ``(x, y)`` image-pixel coordinates
    as the contour files (pixel centres at integers), while SVG puts the
    centre of pixel ``j`` at user unit ``j + 0.5``. The document is
    ``width x height`` user units (one per pixel) with a ground rectangle.
    Silhouettes use ``fill-rule="evenodd"``; outlines and fragments are
    strokes with the same width, joins and caps, except that with mitre
    joins the exact stroke region is written as a filled path (SVG bevels a
    mitre beyond the limit where shapely squares it off); dots are circles.
    Colours are 8-bit hex. Checked with librsvg: the SVG rasterised at one
    unit per pixel matches the PNG with no shift (mean difference under 0.2
    grey levels; librsvg flattens arcs a little inside the true circle). Numbers have at most 6 decimals; no time stamps, so the
    same result always gives the same text.
    """
    kind = result.get("kind")
    w, h = result["size"]
    fig, gnd = _hex(result["figure"]), _hex(result["ground"])
    if kind == "silhouette":
        body = f'<path d="{_path_data(result["rings"], True)}" fill="{fig}" fill-rule="evenodd"/>'
    elif kind in ("outline", "fragments") and result["join"] == "mitre":
        # SVG bevels a mitre past the limit where GEOS squares it off, so
        # the exact stroke region is written as a filled path instead.
        rings = result["stroke_rings"]
        body = f'<path d="{_path_data(rings, True)}" fill="{fig}" fill-rule="evenodd"/>' if rings else ""
    elif kind in ("outline", "fragments"):
        closed = kind == "outline" and result["closed"]
        lines = [result["points"]] if kind == "outline" else result["polylines"]
        join = {"mitre": "miter"}.get(result["join"], result["join"])
        cap = {"flat": "butt"}.get(result["cap"], result["cap"])
        body = (
            f'<path d="{_path_data(lines, closed)}" fill="none" stroke="{fig}" '
            f'stroke-width="{_num(result["width"])}" stroke-linejoin="{join}" '
            f'stroke-linecap="{cap}" stroke-miterlimit="{_num(result["mitre_limit"])}"/>'
        )
    elif kind == "dots":
        r = _num(result["radius"])
        body = "\n".join(
            f'<circle cx="{_num(x)}" cy="{_num(y)}" r="{r}" fill="{fig}"/>' for x, y in result["centers"]
        )
    else:
        raise InputError(f"result: expected the dict of a render_* function, got kind {kind!r}")
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" '
        f'viewBox="0 0 {w} {h}">\n'
        "<!-- attneave: (x, y) in image pixels, pixel centres at integers, y down; "
        "translate(0.5 0.5) maps them to SVG user units -->\n"
        f'<rect x="0" y="0" width="{w}" height="{h}" fill="{gnd}"/>\n'
        f'<g transform="translate(0.5 0.5)">\n{body}\n</g>\n</svg>\n'
    )


def write_svg(path, result, size=None, *, figure=0.0, ground=1.0):
    """Write a plain SVG in the image's pixel coordinate system, atomically.

    Parameters
    ----------
    path : str or Path
        Output file; its directory must exist.
    result : dict or rings
        The dict returned by a ``render_*`` function (then `size`, `figure`
        and `ground` come from it), or rings of a silhouette as accepted by
        :func:`render_silhouette` (then `size` is required).
    size : int or (int, int), optional
        Image ``(width, height)`` for rings.
    figure, ground : float or RGB triple in [0, 1], optional
        Colours for rings.

    Returns
    -------
    Path
        The file written; see :func:`svg_text` for its content.
    """
    if not isinstance(result, dict):
        h, w = _resolve_shape(size)
        f, g = _colours(figure, ground)
        rings, _ = _as_rings(result, "rings")
        result = {"kind": "silhouette", "size": (w, h), "figure": _plain(f), "ground": _plain(g), "rings": rings}
    text = svg_text(result)
    path = _parent_exists(path)
    with atomic_write(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return path
