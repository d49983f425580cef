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

Discs (:mod:`attneave.stimuli.render.discs`) are exact too: the circle is cut where
it crosses grid lines, the polygon through those points is accumulated as
above, and each cut arc adds its circular segment ``R^2/2 (d - sin d)`` to
the one pixel that contains it (the `extra` deposits of :func:`accumulate`).

The numpy path integrates 8-bit images of at least 65536 pixels in float32
(error below 1e-5 of a pixel; :func:`sum_dtype`), all else in float64;
temporaries live in per-thread scratch buffers (:mod:`.workspace`).

Speed. The deposits and the 8-bit painting also exist in C (:mod:`.kernel`,
float64 throughout; ``attneave.stimuli.render.KERNEL`` says which path runs): the
numpy functions are the reference and the fallback, held to 1e-12 by a test.
8-bit silhouettes are painted band by band of rows (``coverage_bands.c``),
one plain float64 ring in one ctypes call. ``bench_render.py --n 1000``
(512 x 512 8-bit images, 500-vertex polygons, 2-core AMD EPYC, medians of
thread CPU time, three runs at load 1.1-1.3): rendering plus ``cv2.imwrite``
is 1.05-1.14x (blob) and 1.10-1.12x (spiky star) ``cv2.fillPoly(LINE_AA)``
plus ``cv2.imwrite``; the renderer takes 0.10 / 0.34 ms per image there
(callgrind: 2.3 / 4.5 M instructions per step, as fillPoly's). The numpy path
gave 1.74 / 1.82 when last measured (load 8-11): its time goes to a hundred
numpy calls, several microseconds each with cold caches.

References
----------
.. [1] R. Levien, "Inside the fastest font renderer in the world" (font-rs),
       2016.
.. [2] S. Barrett, stb_truetype.h, version 2 rasteriser.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.render import kernel
from attneave.stimuli.render.grid_cut import cut_pieces, ring_area, stream_box
from attneave.stimuli.render.kernel import LIB
from attneave.stimuli.render.rings import as_rings, check_alternating, orient_rings, resolve_shape
from attneave.stimuli.render.workspace import scratch

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
    """(p, bridge): closed rings as one stream, a (2, n) array of x and y
    rows shifted by +0.5 so that pixel (i, j) is the square [j, j+1] x
    [i, i+1]. `bridge` is None for one ring."""
    if len(rings) == 1:
        r = rings[0]
        n = len(r)
        p = scratch("stream", (2, n + 1))
        p[:, :n] = r.T
        p[:, n] = r[0]
        p += 0.5
        return p, None
    parts, flags = [], []
    for r in rings:
        parts += [r, r[:1]]
        f = np.zeros(len(r) + 1, bool)
        f[-1] = True
        flags.append(f)
    p = np.concatenate(parts).T + 0.5  # C-contiguous (2, n)
    return p, np.concatenate(flags)[:-1]


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


def accumulate(p, bridge, h, w, extra=None, dtype=np.float64, ring=None):
    """Cut a stream at the pixel grid and integrate the winding number.

    `p` is a (2, n) stream from :func:`_stream` (x and y rows). Returns
    ``(win, r0, c0, area, integrated)`` or None when nothing reaches the
    image: `win` covers the box whose top-left pixel is (r0, c0) (0 outside
    it), a view of a scratch buffer to be used before the next call; `area`
    is the winding integral over the image, in float64 (see
    :func:`cut_pieces` for `ring`). On the numpy path `win` is that integral
    per pixel, of `dtype` (float64 or float32), and `integrated` True; with
    the compiled kernel it holds float64 deposits, `integrated` is False,
    and :func:`winding` gives the integral.
    """
    if LIB is not None:
        return _accumulate_kernel(p, bridge, h, w, extra, ring)
    return _accumulate_numpy(p, bridge, h, w, extra, dtype, ring)


def _accumulate_kernel(p, bridge, h, w, extra, ring):
    ext = stream_box(p, h, w)
    if ext is None:
        return None
    box, clip_x, clip_y = ext
    dep, area = kernel.deposit(p, bridge, h, w, box)
    r0, c0 = box[0], box[2]
    if extra is not None and len(extra[0]):
        er, ec, ea = extra  # a disc's circular segments: +ea in one pixel only
        np.add.at(dep, (er - r0, ec - c0), ea)
        np.subtract.at(dep, (er - r0 + 1, ec - c0), ea)
        area += float(np.add.reduce(ea))
    # Pieces on the bottom edge sit in row h, outside the image.
    win = dep[: min(box[1] - r0 + 1, h - r0)]
    return win, r0, c0, ring_area(area, ring, clip_x or clip_y), False


def winding(acc):
    """The winding integral over the box of an accumulation (see
    :func:`accumulate`); deposits are integrated in place (once)."""
    win, _, _, _, integrated = acc
    return win if integrated else kernel.integrate(win)


def _accumulate_numpy(p, bridge, h, w, extra, dtype, ring):
    import cv2

    cut = cut_pieces(p, bridge, h, w, ring)
    if cut is None:
        return None
    pc, (r0, r1, c0, c1), _, area = cut
    m = pc.shape[1]
    dep, cell = pc[1:3], scratch("refine", (2, m))
    np.copyto(cell, pc[3:5])
    bh, bw = r1 - r0 + 1, c1 - c0 + 1
    # cv2.integral, a vectorised 2-D prefix sum several times faster than
    # np.cumsum, gives the column-wise cumulative sum we want if each
    # deposit v is entered as +v in its column and -v in the next, so that
    # the prefix sum along rows gives v in that column alone. (This also
    # keeps every partial sum near the winding integral, as float32 needs.)
    # Few deposits are entered twice by ufunc.at (about 20 instructions
    # each); many are entered once and the difference between neighbouring
    # columns is taken in one pass over the box (`diff`). Spare columns take
    # the (zero) deposits of pieces on the right edge and, with `diff`, a
    # zero column on the left.
    stride = bw + 2
    size = (bh + 1) * stride
    diff = 16 * m > size
    # flat index of the top deposit, then of the bottom one (exact in float)
    top = np.multiply(cell[1], stride, out=cell[1])
    top += cell[0]
    top -= r0 * stride + c0 - diff
    np.add(top, stride, out=cell[0])
    idx = scratch("idx", (2, m), np.intp)
    np.copyto(idx, cell[::-1], casting="unsafe")
    dtype = np.dtype(dtype).type
    if dtype is not np.float64:  # ufunc.at is 50x slower when it has to cast
        dep, dep64 = scratch("deposits", (2, m), dtype), dep
        np.copyto(dep, dep64)
    idx, dep = idx.reshape(-1), dep.reshape(-1)
    if extra is not None and len(extra[0]):
        er, ec, ea = extra  # a disc's circular segments: +ea in one pixel only
        ie = (er - r0) * stride + (ec - c0 + diff)
        idx = np.concatenate([idx, ie, ie + stride])
        dep = np.concatenate([dep, ea.astype(dtype), -ea.astype(dtype)])
        area += float(np.add.reduce(ea))
    acc = scratch("acc", size, dtype, zeroed=True)
    depth = cv2.CV_32F if dtype is np.float32 else cv2.CV_64F
    table = scratch("sum", (bh + 2, stride + 1 - diff), dtype)
    try:
        np.add.at(acc, idx, dep)
        if diff:
            grid = acc.reshape(bh + 1, stride)
            d = scratch("diff", (bh + 1, stride - 1), dtype)
            cv2.subtract(grid[:, 1:], grid[:, :-1], dst=d)
            cv2.integral(d, table, sdepth=depth)
        else:
            np.subtract.at(acc[1:], idx, dep)
            cv2.integral(acc.reshape(bh + 1, stride), table, sdepth=depth)
    finally:
        # leave the scratch buffer all zero for the next call, by the
        # cheaper of scatters and one fill
        if 8 * len(idx) < size:
            acc[idx] = 0.0
            if not diff:
                acc[1:][idx] = 0.0
        else:
            acc.fill(0.0)
    # Pieces on the bottom edge sit in row h, outside the image.
    bh = min(bh, h - r0)
    return table[1 : bh + 1, 1 : bw + 1], r0, c0, area, True


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
    win, r0, c0 = winding(acc), acc[1], acc[2]
    if win.size <= 4:
        # OpenCV takes a (1, 1) array for a scalar and returns a (4, 1) one: numpy for tiny boxes
        cov = np.minimum(np.abs(win), 1.0)
        cov[cov <= _SNAP] = 0.0
        cov[cov > 1.0 - _SNAP] = 1.0
        return cov, r0, c0
    cov = cv2.absdiff(win, 0.0)  # a new contiguous array
    cv2.min(cov, 1.0, dst=cov)  # overlapping rings give > 1
    cv2.threshold(cov, _SNAP, 0.0, cv2.THRESH_TOZERO, dst=cov)
    ones = cv2.threshold(cov, 1.0 - _SNAP, 1.0, cv2.THRESH_BINARY)[1]
    cv2.max(cov, ones, dst=cov)
    return cov, r0, c0


def ring_stream(rings, oriented=False, orient=True):
    """(p, bridge, ring): the stream of rings (oriented by nesting unless
    `oriented`) and, for one ring left as given, that ring (see
    :func:`cut_pieces`)."""
    # One ring is never reversed: only the sign of its area depends on it.
    single = orient and not oriented and len(rings) == 1
    if orient and not oriented and not single:
        rings = orient_rings(rings)
    elif not orient and not oriented and len(rings) > 1:
        check_alternating(rings)
    p, bridge = _stream(rings)
    return p, bridge, rings[0] if single else None


def ring_accumulation(rings, h, w, oriented=False, orient=True, dtype=np.float64):
    """:func:`accumulate` of rings (oriented by nesting unless `oriented`)."""
    p, bridge, ring = ring_stream(rings, oriented, orient)
    return accumulate(p, bridge, h, w, dtype=dtype, ring=ring)


def _ring_coverage(rings, h, w, oriented=False, orient=True):
    return box_coverage(ring_accumulation(rings, h, w, oriented, orient))


def dense_coverage(box, h, w):
    """The (h, w) float64 coverage image of :func:`box_coverage`'s result."""
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
        ring inside an odd number of other rings is a hole. They must be
        nested or apart (they may touch): rings that cross each other or
        coincide are refused.
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
        Non-finite coordinates, a ring with fewer than 3 distinct points,
        rings that cross each other, or a bad shape (see
        :func:`attneave.stimuli.render.rings.resolve_shape` for the size limits).

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
    return dense_coverage(_ring_coverage(rings, h, w, oriented=oriented, orient=orient), h, w)
