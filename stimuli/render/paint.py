"""Images from coverage: filled silhouettes and dots, blended between
``ground`` and ``figure`` grey levels or RGB colours in [0, 1].

Points are ``(x, y)`` in image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).
"""

from __future__ import annotations

import math

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.render import kernel, raster
from attneave.stimuli.render.discs import disc_accumulation
from attneave.stimuli.render.grid_cut import ring_area, stream_box
from attneave.stimuli.render.raster import box_coverage, ring_accumulation, ring_stream, sum_dtype, winding
from attneave.stimuli.render.rings import MAX_PIXELS, MAX_SIDE, as_rings, resolve_shape
from attneave.stimuli.validate import as_number, as_points

# ---------------------------------------------------------------------------
# Images


_SCALE = {np.dtype(np.float64): 1.0, np.dtype(np.uint8): 255.0, np.dtype(np.uint16): 65535.0}
# dtype.name is computed in Python by numpy (tens of microseconds when the
# caches are cold, as long as the rest of a small render): look it up
_NAMES = {dt: dt.name for dt in _SCALE}
_BY_NAME = {None: np.dtype(np.float64), **{name: dt for dt, name in _NAMES.items()}}


def resolve_dtype(dtype):
    """The numpy dtype of an image: None (float64), 'float64', 'uint8' or 'uint16'."""
    if isinstance(dtype, str) or dtype is None:
        dt = _BY_NAME.get(dtype)
        if dt is not None:
            return dt
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


def colours(figure, ground):
    """Figure and ground as tuples of equal length (grey, or RGB if either is)."""
    f, g = _colour(figure, "figure"), _colour(ground, "ground")
    if len(f) != len(g):
        f, g = (f * 3 if len(f) == 1 else f), (g * 3 if len(g) == 1 else g)
    return f, g


def plain_colour(c):
    """A colour tuple as the user gave it: a float for grey, a triple for RGB."""
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


def level_tables(figure, ground):
    """None for black on white (the kernel paints 255 - level, much faster
    than a table), else the (channels, 256) uint8 colour of each coverage
    level ``rint(255 * coverage)``: ``rint(255 * (ground + level / 255 *
    (figure - ground)))``."""
    if len(figure) == 1 and figure == (0.0,) and ground == (1.0,):
        return None
    k = np.arange(256.0)
    return np.array([np.rint(255.0 * g + (f - g) * k) for f, g in zip(figure, ground)], np.uint8)


def silhouette_u8(rings, oriented, orient, h, w, figure, ground):
    """(img, area): rings as an 8-bit image through the compiled kernel,
    which paints every pixel band by band (see :mod:`.kernel`); one ring
    goes straight from its points, several through the stream of
    :func:`ring_stream` (oriented by nesting unless `oriented`)."""
    n = len(figure)
    img = np.empty((h, w) if n == 1 else (h, w, n), np.uint8)
    luts = level_tables(figure, ground)
    if len(rings) == 1:
        area = kernel.ring_u8(np.ascontiguousarray(rings[0], np.float64), orient and not oriented, img, luts)
        if area == area:
            return img, area
    # several rings, or one the ring entry does not take as it is (a
    # repeated point at its end), or memory ran out
    p, bridge, ring = ring_stream(rings, oriented, orient)
    ext = stream_box(p, h, w)
    clipped = ext is not None and (ext[1] or ext[2])
    return img, ring_area(kernel.stream_u8(p, bridge, img, luts), ring, clipped)


_F64, _U8 = np.dtype(np.float64), np.dtype(np.uint8)
# the largest square the fast path draws; larger ones go through resolve_shape's checks
_MAX_U8_SIDE = min(MAX_SIDE, math.isqrt(MAX_PIXELS))


def _plain_silhouette_u8(obj, size, figure, ground, orient):
    """:func:`render_silhouette`'s usual call, one float64 ring drawn 8-bit
    in a square image, with one numpy call and one call of the compiled
    kernel (which also checks the points: its NaN sends anything else to the
    validating path); None when the call is not of that kind.

    Small Python calls cost microseconds each when other work has evicted
    the caches, as in a batch that writes a PNG file after each image:
    there they made up half of the renderer's time.
    """
    pts = getattr(obj, "points", obj)
    if (type(pts) is not np.ndarray or pts.dtype != _F64 or pts.ndim != 2 or pts.shape[1] != 2 or size < 1
            or size > _MAX_U8_SIDE):
        return None
    f, g = colours(figure, ground)
    ring = pts.copy()  # C order; the result's ring, not the caller's array
    img = np.empty((size, size) if len(f) == 1 else (size, size, len(f)), np.uint8)
    area = kernel.ring_u8(ring, orient, img, level_tables(f, g))
    if area != area:
        return None
    return result_record("silhouette", img, size, size, f, g, _U8, rings=[ring], orient=orient, area=area)


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
    luts = level_tables(figure, ground)
    for ch in range(n):
        fill = 255 if luts is None else luts[ch][0]
        if n == 1:
            img.fill(fill)
        else:
            img[..., ch] = fill
    if acc is None:
        return img
    win, r0, c0, _, integrated = acc
    sub = img[r0 : r0 + win.shape[0], c0 : c0 + win.shape[1]]
    if not integrated:
        # the compiled kernel: prefix sum, coverage, rounding and blend in
        # one pass (colour images integrate first, then paint each channel)
        if n == 1:
            kernel.paint_u8(win, False, sub, None if luts is None else luts[0])
        else:
            winding(acc)
            for ch in range(n):
                kernel.paint_u8(win, True, sub[..., ch], luts[ch])
        return img
    if n == 1:
        cv2.convertScaleAbs(win, sub, 255.0)
        if luts is None:
            cv2.bitwise_not(sub, dst=sub)
        elif not np.array_equal(luts[0], np.arange(256)):
            cv2.LUT(sub, luts[0], dst=sub)
    else:
        u = cv2.convertScaleAbs(win, alpha=255.0)
        for ch in range(n):
            sub[..., ch] = cv2.LUT(u, luts[ch])
    return img


def paint_image(acc, h, w, figure, ground, dtype):
    """Image of `dtype` from an accumulation (see :func:`accumulate`)."""
    if dtype == np.uint8:
        return _paint_uint8(acc, h, w, figure, ground)
    return _paint(box_coverage(acc), h, w, figure, ground, dtype)


def result_record(kind, img, h, w, figure, ground, dtype, **params):
    """The dict every render function returns: the image and every resolved parameter."""
    out = {
        "img": img,
        "kind": kind,
        "size": (w, h),
        "shape": (h, w),
        "figure": plain_colour(figure),
        "ground": plain_colour(ground),
        "dtype": _NAMES[dtype],
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
        number of others is a hole. Rings of one shape must be nested or
        apart (they may touch); rings that cross each other or coincide are
        refused, since no orientation makes the painted region and its area
        agree there (merge them with shapely first).
    size : int or (int, int), optional
        Image ``(width, height)`` (an int for a square), sides up to
        ``MAX_SIDE`` (2**20) px and at most ``MAX_PIXELS`` (2**30) pixels
        (:mod:`attneave.stimuli.render.rings`). Give this or `shape`.
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
        See :func:`coverage`. With False a hole must run opposite to the
        ring around it, else the rings are refused (rings of one direction
        nested in each other add up to a winding number of 2, painted as 1
        but counted twice in `area`).

    Returns
    -------
    dict
        ``img`` ((height, width) or (height, width, 3) array; RGB order),
        ``kind`` ('silhouette'), ``size`` (width, height), ``shape``
        (height, width), ``figure``, ``ground``, ``dtype``, ``rings`` (the
        rings drawn, as (N, 2) arrays), ``orient``, ``area`` (the integral
        of the winding number over the image, px^2: the exact area of the
        shape inside the image for a simple ring or properly nested holes,
        i.e. the sum of the coverage; for a ring that crosses itself, the
        winding integral, which counts lobes of opposite winding with
        opposite signs).

    Raises
    ------
    InputError
        Bad points, size, colours or dtype; rings that cross each other or
        coincide.

    Examples
    --------
    >>> sq = np.array([(0.5, 0.5), (2.5, 0.5), (2.5, 2.5), (0.5, 2.5)])
    >>> render_silhouette(sq, size=4)["img"].tolist()[1]
    [1.0, 0.0, 0.0, 1.0]
    """
    if dtype == "uint8" and shape is None and type(size) is int and raster.LIB is not None:
        out = _plain_silhouette_u8(contour_or_points, size, figure, ground, bool(orient))
        if out is not None:
            return out
    h, w = resolve_shape(size, shape)
    f, g = colours(figure, ground)
    dt = resolve_dtype(dtype)
    rings, oriented = as_rings(contour_or_points, "contour_or_points")
    if dt == np.uint8 and raster.LIB is not None:
        img, area = silhouette_u8(rings, oriented, bool(orient), h, w, f, g)
    else:
        acc = ring_accumulation(rings, h, w, oriented=oriented, orient=orient, dtype=sum_dtype(dt, h, w))
        area = 0.0 if acc is None else acc[3]
        img = paint_image(acc, h, w, f, g, dt)
    return result_record("silhouette", img, h, w, f, g, dt, rings=rings, orient=bool(orient), area=area)


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
    h, w = resolve_shape(size, shape)
    f, g = colours(figure, ground)
    dt = resolve_dtype(dtype)
    img = paint_image(disc_accumulation(centers, radius, h, w, sum_dtype(dt, h, w)), h, w, f, g, dt)
    return result_record("dots", img, h, w, f, g, dt, centers=centers, radius=radius)
