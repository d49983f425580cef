"""The exact area-coverage rasteriser.

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

Discs (:func:`disc_coverage`) are exact too: the circle is cut where it
crosses grid lines, the polygon through those points is accumulated as
above, and each cut arc adds its circular segment ``R^2/2 (d - sin d)`` to
the one pixel that contains it.

8-bit images of at least 65536 pixels are integrated in float32 (error
below 1e-5 of a pixel, three orders under one grey level; see
:func:`sum_dtype`); everything else in float64. Temporaries live in
per-thread scratch buffers (:mod:`stimuli.render.workspace`).

Speed: a 512 x 512 8-bit image of a 500-vertex polygon takes about 0.25 ms
of CPU for a smooth blob and 0.9 ms for a spiky star (27,000 pieces) when
the caches are warm, and about 0.55 / 1.2 ms when other work has run in
between, as in ``benchmarks/bench_render.py`` (2-core AMD EPYC under load);
callgrind counts 4.3 and 15.8 million instructions. The time goes into
many small numpy calls (each a few microseconds when the caches are cold)
and four ``np.add.at`` over the pieces, not into arithmetic.

References
----------
.. [1] R. Levien, "Inside the fastest font renderer in the world" (font-rs),
       2016.
.. [2] S. Barrett, stb_truetype.h, version 2 rasteriser.
"""

from __future__ import annotations

import math

import numpy as np

from stimuli.validate import as_number, as_points
from stimuli.render.rings import as_rings, orient_rings, resolve_shape
from stimuli.render.workspace import ramp, scratch

# Coverage within this of 0 or 1 is round-off and is snapped (px^2).
_SNAP = 1e-10
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


def _refine(a, b, lo, hi, bridge, out):
    """Insert the points where a stream crosses ``a = integer`` in [lo, hi].

    Crossing points carry exactly integral `a`; `b` is interpolated from the
    start of the piece, so original vertices are kept bit for bit. The
    result lives in the scratch buffer named `out` (see :func:`scratch`).
    """
    m = len(a) - 1
    a0, a1 = a[:-1], a[1:]
    first, last, d, step = scratch("refine", (4, m))
    # first and last integer strictly inside each piece, clipped to [lo, hi]
    np.minimum(a0, a1, out=first)
    np.floor(first, out=first)
    first += 1.0
    np.maximum(first, lo, out=first)
    np.maximum(a0, a1, out=last)
    np.ceil(last, out=last)
    last -= 1.0
    np.minimum(last, hi, out=last)
    np.subtract(last, first, out=d)  # crossings - 1
    np.maximum(d, -1.0, out=d)
    if bridge is not None:
        d[bridge] = -1.0
    cnt, pos = scratch("refine_i", (2, m), np.intp)
    np.copyto(cnt, d, casting="unsafe")
    cnt += 2  # new points per piece: its start and its crossings
    cnt.cumsum(out=pos)
    total = int(pos[-1])
    if total == m:
        return a, b, bridge
    pos -= cnt  # new index of each old point
    # k[j]: the old piece that new point j lies on (np.repeat without a new array)
    k = scratch("refine_k", total, np.intp)
    k.fill(0)
    k[pos[1:]] = 1
    k.cumsum(out=k)
    # crossing j of piece i (j counted in the new stream) is e[i] + step[i] * j:
    # first, first + 1, ... where `a` grows, last, last - 1, ... where it falls
    up = np.greater(a1, a0, out=scratch("refine_up", m, np.bool_))
    np.copyto(step, up)
    step += step
    step -= 1.0
    last += 1.0
    first -= 1.0
    np.copyto(last, first, where=up)
    e = np.subtract(last, np.multiply(step, pos, out=d), out=last)
    slope = np.subtract(b[1:], b[:-1], out=d)
    da = np.subtract(a1, a0, out=first)
    # where da == 0 the piece has no crossing and its slope is never used
    np.divide(slope, da, out=slope, where=da != 0.0)
    na, nb = scratch(out, (2, total + 1))
    tmp = scratch("refine_t", total)
    v = step.take(k, out=na[:-1])
    v *= ramp(total)
    v += e.take(k, out=tmp)
    u = np.subtract(v, a0.take(k, out=tmp), out=nb[:-1])
    u *= slope.take(k, out=tmp)
    u += b[:-1].take(k, out=tmp)
    na[pos] = a0
    na[-1] = a[-1]
    nb[pos] = b[:-1]
    nb[-1] = b[-1]
    if bridge is not None:
        flags = np.zeros(total, bool)
        flags[pos[bridge]] = True
        bridge = flags
    return na, nb, bridge


def sum_dtype(image_dtype, h, w):
    """The float type to integrate in, for an image of `image_dtype` and size h x w.

    8-bit images of at least ``FLOAT32_MIN_PIXELS`` pixels integrate in
    float32: the coverage comes out within about 1e-5 (three orders below
    1/255) and the integration, the one pass over the whole box, moves half
    the memory. Smaller 8-bit images gain nothing from it and keep float64,
    as do float and 16-bit images (exact to about 1e-13).
    """
    if np.dtype(image_dtype) == np.uint8 and h * w >= FLOAT32_MIN_PIXELS:
        return np.float32
    return np.float64


FLOAT32_MIN_PIXELS = 1 << 16


def accumulate(x, y, bridge, h, w, extra=None, dtype=np.float64):
    """Cut a stream at the pixel grid and integrate the winding number.

    Returns ``(win, r0, c0, area)`` or None when nothing reaches the image:
    `win` is the winding integral over each pixel of the box whose top-left
    pixel is (r0, c0) (0 outside the box), of `dtype` (float64 or float32),
    a view of a scratch buffer to be used before the next call; `area` is
    its sum, computed in float64 whatever `dtype`.
    """
    import cv2

    # The box of pixels the pieces can reach, from the stream's extent: no
    # pass over the pieces needed. Rows are floor(y) with y clipped to
    # [0, h] (row h, the bottom edge, lies outside the image); columns are
    # floor(x) for x in [0, w).
    xlo, xhi = float(np.minimum.reduce(x)), float(np.maximum.reduce(x))
    ylo, yhi = float(np.minimum.reduce(y)), float(np.maximum.reduce(y))
    if ylo >= h or xhi <= 0.0 or xlo >= w:
        return None
    r0, r1 = int(max(ylo, 0.0)), int(min(yhi, float(h)))
    c0, c1 = int(max(xlo, 0.0)), int(min(xhi, w - 1.0))
    clip_y = ylo < 0.0 or yhi > h
    clip_x = xlo < 0.0 or xhi >= w
    # Columns: pieces left or right of the image affect no image column.
    x, y, bridge = _refine(x, y, 0.0, float(w), bridge, "cols")
    # Rows: pieces above the image are flattened onto its top edge (their
    # cover reaches every row below), pieces below it onto its bottom edge
    # (they add nothing inside, but they keep the box reaching the bottom
    # row when the shape runs off the bottom of the image).
    y, x, bridge = _refine(y, x, 0.0, float(h), bridge, "rows")
    if clip_y:
        np.minimum(y, float(h), out=y)
        np.maximum(y, 0.0, out=y)
    m = len(x) - 1
    pieces = scratch("pieces", (3, m))
    dx, xm, ym = pieces
    np.subtract(x[1:], x[:-1], out=dx)
    np.add(x[1:], x[:-1], out=xm)
    xm *= 0.5
    np.add(y[1:], y[:-1], out=ym)
    ym *= 0.5
    if clip_x or bridge is not None:
        # Pieces left or right of the image and bridges between rings add
        # nothing: their width is set to 0 and they are parked in the image,
        # which is cheaper than compacting every array.
        keep, inside = scratch("keep", (2, m), np.bool_)
        np.greater_equal(xm, 0.0, out=keep)
        keep &= np.less(xm, w, out=inside)
        if bridge is not None:
            keep &= ~bridge
        dx *= keep
        np.minimum(xm, w - 1.0, out=xm)
        np.maximum(xm, 0.0, out=xm)
    cells = scratch("cells", (2, m), np.intp)
    np.copyto(cells, pieces[:0:-1], casting="unsafe")  # (ym, xm) >= 0: truncation is floor
    row, col = cells
    # A piece adds the signed area between itself and its pixel's bottom
    # side to its pixel (top), and the rest of its cover (dx * fy) to the
    # pixel below (bottom); summing down each column gives the winding
    # integral.
    bottom = np.subtract(ym, row, out=ym)
    bottom *= dx
    if extra is not None and len(extra[0]):
        er, ec, ea = extra  # a disc's circular segments: +ea in one pixel only
        row, col = np.concatenate([row, er]), np.concatenate([col, ec])
        dx, bottom = np.concatenate([dx, np.zeros(len(ea))]), np.concatenate([bottom, -ea])
    row -= r0
    col -= c0
    bh, bw = r1 - r0 + 1, c1 - c0 + 1
    # cv2.integral is a vectorised 2-D prefix sum, several times faster than
    # np.cumsum. Each contribution v is entered as +v in its column and -v in
    # the next, so the prefix sum along rows gives v in that column alone and
    # the table is the column-wise cumulative sum we want. (This also keeps
    # every partial sum near the winding integral, as float32 needs.)
    stride = bw + 1
    idx = np.multiply(row, stride, out=scratch("idx", len(row), np.intp))
    idx += col
    dtype = np.dtype(dtype).type
    # ufunc.at is 50x slower when it has to cast: deposits in `dtype`
    t, b = scratch("deposits", (2, len(row)), dtype)
    np.subtract(dx, bottom, out=t)
    np.copyto(b, bottom)
    acc = scratch("acc", (bh + 1) * stride, dtype, zeroed=True)
    try:
        np.add.at(acc, idx, t)
        np.subtract.at(acc[1:], idx, t)
        np.add.at(acc[stride:], idx, b)
        np.subtract.at(acc[stride + 1 :], idx, b)
        table = scratch("sum", (bh + 2, stride + 1), dtype)
        depth = cv2.CV_32F if dtype is np.float32 else cv2.CV_64F
        cv2.integral(acc.reshape(bh + 1, stride), table, sdepth=depth)
    finally:
        # leave the scratch buffer all zero for the next call, by the
        # cheaper of four scatters and one fill
        if 16 * len(idx) < acc.size:
            for shift in (0, 1, stride, stride + 1):
                acc[shift:][idx] = 0.0
        else:
            acc.fill(0.0)
    # Pieces on the bottom edge sit in row h, outside the image.
    bh = min(bh, h - r0)
    # Pixel i of a column holds its own top part and every part above it, so
    # a piece's top counts in the (bh - row) pixels from its row down and its
    # bottom in one fewer: area = sum(dx * (bh - row)) - sum(bottom), in
    # float64 whatever `dtype` (row <= bh always, and a piece in row bh lies
    # on the bottom edge and has no bottom part). No np.dot: OpenBLAS threads
    # stall for milliseconds on a busy machine.
    prod = np.multiply(dx, row, out=scratch("area", len(row)))
    add = np.add.reduce
    area = bh * float(add(dx)) - float(add(prod)) - float(add(bottom))
    return table[1 : bh + 1, 1 : bw + 1], r0, c0, area


def box_coverage(acc):
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


def ring_accumulation(rings, h, w, oriented=False, orient=True, dtype=np.float64):
    """:func:`accumulate` of rings (oriented by nesting unless `oriented`)."""
    if orient and not oriented:
        rings = orient_rings(rings)
    x, y, bridge = _stream(rings)
    return accumulate(x, y, bridge, h, w, dtype=dtype)


def _ring_coverage(rings, h, w, oriented=False, orient=True):
    return box_coverage(ring_accumulation(rings, h, w, oriented, orient))


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


def disc_accumulation(centers, radius, h, w, dtype=np.float64):
    """:func:`accumulate` of exact discs (chord polygons plus circular segments)."""
    rings, extra = _disc_terms(centers, radius, h, w)
    x, y, bridge = _stream(rings)
    return accumulate(x, y, bridge, h, w, extra, dtype)


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
    h, w = resolve_shape(shape=shape)
    rings, oriented = as_rings(rings)
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
    h, w = resolve_shape(shape=shape)
    centers = as_points(centers, "centers")
    radius = as_number(radius, "radius", gt=0)
    return _dense(box_coverage(disc_accumulation(centers, radius, h, w)), h, w)
