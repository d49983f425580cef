"""Contours of objects in photographs and silhouettes, to sub-pixel accuracy.

Points are ``(x, y)`` floats in image pixels: x = column, y = row, y points
down, pixel centres at integer coordinates (OpenCV's convention), in the
input image's own pixel grid. Every contour returned is closed (the first
point is not repeated), stored counter-clockwise as seen on the screen.

The pipeline
------------
1. **Read** (:func:`read_image`): PNG, JPEG, TIFF, BMP; grey, RGB or RGBA;
   8 or 16 bit (or float TIFF). Colour is reduced to luminance
   ``0.299 R + 0.587 G + 0.114 B`` in the image's own units; the alpha
   channel is used only by ``method='alpha'``.
2. **Segment** (``method``), giving a boolean object mask and, where the
   image has grey levels, an iso-level for the sub-pixel step:

   ``'otsu'`` (default)
       Photographs and antialiased renders of one object on a plain
       background. Otsu's threshold splits the grey levels in two classes;
       the contour level is then the midpoint of the two classes' medians
       (robust to the few edge pixels, so an antialiased edge is found at
       its 50 % coverage line, not at wherever Otsu's split fell). The
       object is the class that touches the image border less
       (``polarity='auto'``), or the ``'dark'`` / ``'light'`` one.
   ``'threshold'``
       When you know the level (e.g. a calibrated grey value or a render
       with known ground and figure); ``threshold`` is in the image's units
       (0-255 for 8 bit, 0-65535 for 16 bit) and is the contour level.
   ``'mask'``
       A binary silhouette of either polarity (MPEG-7 style, a
       segmentation exported from another tool). Pixels above the midpoint
       of the image's range are "on"; the object is the class touching the
       border less, or given by ``polarity``.
   ``'alpha'``
       Cut-outs with transparency (PNG with an alpha channel): the object
       is where alpha exceeds ``threshold`` (default half of full opacity);
       an antialiased alpha edge gives a sub-pixel contour.
   ``'grabcut'``
       Objects on cluttered or textured backgrounds that a single threshold
       cannot separate. OpenCV's GrabCut (Rother et al. 2004), initialised
       with ``rect=(x, y, width, height)`` or, by default, with the image
       inset by 5 % on every side. Slow (seconds per megapixel) and not
       deterministic across OpenCV versions; check the overlay.

3. **Clean up**: 8-connected objects; the largest one
   (``objects='largest'``) or every object of at least ``min_area``
   pixels (``objects='all'``, largest first). Holes are traced apart and
   returned only when asked (``holes=True``); the outer contour is the
   boundary of the object with its holes filled, so a hole is never taken
   for it. An object that touches the image border is closed along the
   border (at the image edge, ``x = -0.5`` or ``x = width - 0.5``, ...).
4. **Sub-pixel contour**: marching squares
   (:func:`skimage.measure.find_contours`) on the grey image, run only on
   a crop around the chosen object in which every pixel more than a pixel
   from its edge keeps its side of the level, so that nothing but this
   object's boundary is traced and its shape cannot change. Three
   refinements make it accurate on antialiased edges: each edge is traced
   at the local midpoint of the object's and the background's grey levels
   (``local_level``; under a graded background a single level moves the
   edge), after a 3x3 average that makes the edge profile linear between
   pixel centres (``presmooth``), whose known curvature-dependent shift is
   then removed. On exact-coverage renders the contour is accurate to
   about 0.004 px RMS. A two-valued image (a binary mask, whatever the
   method) has no grey levels to interpolate: its marching-squares outline
   (a staircase) is smoothed lightly along the arc (``mask_sigma`` px,
   default 1) instead.
5. **Curvature and surprisal** (:func:`describe`): the contour is
   smoothed along its arc with a periodic Gaussian whose scale is tied to
   the shape, ``sigma = SIGMA_FRACTION * perimeter`` (1 %) unless given, at
   least ``MIN_SIGMA`` px; curvature is the Gaussian-derivative curvature
   at that scale (:func:`stimuli.contour.gaussian_curvature`); surprisal
   (:func:`stimuli.information.surprisal`) is computed on the smoothed
   contour resampled at ``n`` points (or a spacing in px).

References
----------
.. [1] Otsu, N. (1979). A threshold selection method from gray-level
       histograms. IEEE Trans. SMC 9(1), 62-66.
.. [2] Lorensen, W. E., & Cline, H. E. (1987). Marching cubes: a high
       resolution 3D surface construction algorithm. SIGGRAPH 21(4).
.. [3] Rother, C., Kolmogorov, V., & Blake, A. (2004). "GrabCut":
       interactive foreground extraction using iterated graph cuts.
       ACM Trans. Graphics 23(3), 309-314.
.. [4] Mokhtarian, F., & Mackworth, A. K. (1992). A theory of multiscale,
       curvature-based shape representation for planar curves. IEEE PAMI
       14(8), 789-805.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stimuli.geometry.contour import Contour, gaussian_curvature
from stimuli.errors import InputError

__all__ = [
    "METHODS",
    "SIGMA_FRACTION",
    "MIN_SIGMA",
    "Extraction",
    "ContourInfo",
    "read_image",
    "extract",
    "extract_contours",
    "default_sigma",
    "smooth",
    "contour_curvature",
    "describe",
    "curvature_peaks",
    "IMAGE_SUFFIXES",
]

METHODS = ("otsu", "threshold", "mask", "alpha", "grabcut")
POLARITIES = ("auto", "dark", "light")
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")

#: Default curvature/smoothing scale as a fraction of the contour's perimeter.
SIGMA_FRACTION = 0.01
#: Smallest default smoothing scale, in pixels (pixel noise sets this floor).
MIN_SIGMA = 1.0
#: Default smoothing (px of arc length) of a binary mask's staircase outline.
MASK_SIGMA = 1.0


# --------------------------------------------------------------------------- reading
def read_image(path):
    """Read an image file as it is stored (no colour management, no EXIF rotation).

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF or BMP file; grey, RGB or RGBA; 8 or 16 bit
        (32-bit float TIFF also works).

    Returns
    -------
    ndarray
        ``(H, W)`` for grey, ``(H, W, 3)`` RGB or ``(H, W, 4)`` RGBA
        (channels in RGB order, not OpenCV's BGR), in the file's own dtype
        (uint8, uint16 or float32). Row ``i``, column ``j`` is the pixel
        centred at ``(x, y) = (j, i)``.

    Raises
    ------
    InputError
        The file does not exist, is empty, or cannot be decoded (corrupt or
        not an image), naming the file.
    """
    import cv2

    path = Path(path)
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (IsADirectoryError, PermissionError, OSError) as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if data.size == 0:
        raise InputError(f"{path}: empty file, expected a PNG, JPEG, TIFF or BMP image")
    img = _quiet_imdecode(cv2, data)
    if img is None or img.size == 0:
        raise InputError(f"{path}: not a readable image (corrupt, or not PNG, JPEG, TIFF or BMP)")
    if img.ndim == 3:
        if img.shape[2] == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
        elif img.shape[2] == 4:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA)
        elif img.shape[2] == 1:
            img = img[:, :, 0]
    return img


def _quiet_imdecode(cv2, data):
    """cv2.imdecode without OpenCV's own warnings on stderr (we raise instead)."""
    log = getattr(getattr(cv2, "utils", None), "logging", None)
    if log is None:  # pragma: no cover - very old OpenCV
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    old = log.getLogLevel()
    log.setLogLevel(log.LOG_LEVEL_SILENT)
    try:
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    finally:
        log.setLogLevel(old)


def _load(image_or_path):
    """(array, name) from a path or an array."""
    if isinstance(image_or_path, (str, Path)):
        return read_image(image_or_path), str(image_or_path)
    try:
        img = np.asarray(image_or_path)
    except Exception:  # noqa: BLE001 - anything that is not an array
        raise InputError("image: expected a path or an array") from None
    return img, "image"


def _split_channels(img, name):
    """Grey (float, image units) and alpha (or None) of an image array."""
    if img.dtype == bool:
        img = img.astype(np.uint8)
    if not (np.issubdtype(img.dtype, np.integer) or np.issubdtype(img.dtype, np.floating)):
        raise InputError(f"{name}: pixel type {img.dtype} is not numeric")
    if img.ndim == 2:
        grey, alpha = img, None
    elif img.ndim == 3 and img.shape[2] in (1, 2, 3, 4):
        c = img.shape[2]
        alpha = img[:, :, c - 1] if c in (2, 4) else None
        if c <= 2:
            grey = img[:, :, 0]
        else:
            rgb = img[:, :, :3].astype(np.float32)
            grey = rgb[:, :, 0] * np.float32(0.299) + rgb[:, :, 1] * np.float32(0.587) + rgb[:, :, 2] * np.float32(0.114)
    else:
        raise InputError(f"{name}: expected a grey (H, W), RGB or RGBA (H, W, 3|4) image, got shape {img.shape}")
    if min(grey.shape) < 2:
        raise InputError(f"{name}: image of {grey.shape[1]}x{grey.shape[0]} pixels is too small")
    if np.issubdtype(grey.dtype, np.floating) and not np.isfinite(grey).all():
        raise InputError(f"{name}: image has NaN or infinite pixels")
    return grey, alpha


def _full_scale(dtype):
    if np.issubdtype(dtype, np.integer):
        return float(np.iinfo(dtype).max)
    return 1.0


# ------------------------------------------------------------------- result types
@dataclass
class Extraction:
    """Contours extracted from one image, with everything that was resolved.

    Attributes
    ----------
    contours : list of Contour
        Outer contours, largest object first (one with
        ``objects='largest'``); ``(x, y)`` image pixels, y down, closed,
        counter-clockwise on the screen.
    holes : list of list of Contour
        For each contour, the contours of its holes (empty lists unless
        ``holes=True``); also counter-clockwise on the screen.
    mask : (H, W) bool ndarray
        The pixels inside the chosen objects' outer contours (holes
        filled); with ``holes=True``, the objects' own pixels (holes, and
        anything inside them, cleared).
    params : dict
        Every resolved parameter: method, polarity, threshold (Otsu's split
        or the value given), class_medians (Otsu), level (the global
        contour level, in image units), subpixel ('grey': traced on grey
        levels, or 'mask': a two-valued image), presmooth and local_level
        (per object, whether each refinement was used), objects, min_area,
        min_hole_area, holes, holes_dropped, mask_sigma, object_areas (pixel
        counts, holes filled), n_objects_found (separate objects in the
        image; islands inside holes are part of their object), shape,
        source.
    """

    contours: list
    holes: list
    mask: np.ndarray
    params: dict = field(default_factory=dict)

    @property
    def contour(self):
        """The first (largest) contour."""
        return self.contours[0]


# ----------------------------------------------------------------- segmentation
def _histogram_stats(grey):
    """Otsu threshold, the medians of the two classes, and the grey range.

    Returns (threshold, median_low, median_high, lo, hi, n_values) in image
    units; the low class is ``grey <= threshold``. `n_values` is the number
    of distinct grey levels, counted up to 3.
    """
    from skimage.filters import threshold_otsu

    if grey.dtype == np.uint8:
        import cv2

        counts = cv2.calcHist([grey], [0], None, [256], [0, 256]).ravel().astype(float)
        centres = np.arange(256, dtype=float)
        nz = np.flatnonzero(counts)
        lo, hi = float(nz[0]), float(nz[-1])
        if lo == hi:
            return lo, lo, hi, lo, hi, 1
        counts, centres = counts[nz[0] : nz[-1] + 1], centres[nz[0] : nz[-1] + 1]
        t = float(threshold_otsu(hist=(counts, centres)))
        cum = np.cumsum(counts)
        k = int(np.searchsorted(centres, t, side="right"))  # low class: centres[:k]

        def med(a, b):
            c = cum[a:b] - (cum[a - 1] if a else 0.0)
            return float(centres[a + int(np.searchsorted(c, 0.5 * c[-1]))])

        return t, med(0, k), med(k, len(centres)), lo, hi, min(len(nz), 3)
    lo, hi = float(grey.min()), float(grey.max())
    if lo == hi:
        return lo, lo, hi, lo, hi, 1
    n_values = 2 if not np.any((grey != lo) & (grey != hi)) else 3
    g = grey
    if g.size > 2_000_000:  # a regular subsample is plenty for two medians
        step = int(np.ceil(np.sqrt(g.size / 1_000_000)))
        g = g[::step, ::step]
    t = float(threshold_otsu(g))
    low = g[g <= t]
    high = g[g > t]
    if low.size == 0 or high.size == 0:
        return t, lo, hi, lo, hi, n_values
    return t, float(np.median(low)), float(np.median(high)), lo, hi, n_values


def _polarity_from_border(on):
    """'light' if the 'on' pixels touch the image border less than the others."""
    border = np.concatenate([on[0], on[-1], on[1:-1, 0], on[1:-1, -1]])
    frac = border.mean()
    if frac < 0.5:
        return "light"
    if frac > 0.5:
        return "dark"
    return "light" if on.mean() <= 0.5 else "dark"


def _grabcut(image, rect, iterations, name):
    import cv2

    img = image
    if img.ndim == 3 and img.shape[2] in (2, 4):
        img = img[:, :, : img.shape[2] - 1]
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[:, :, 0]
    if img.dtype != np.uint8:
        f = img.astype(np.float64)
        img = np.clip(np.round(255 * (f - f.min()) / max(np.ptp(f), 1e-12)), 0, 255).astype(np.uint8)
    bgr = cv2.cvtColor(img, cv2.COLOR_GRAY2BGR) if img.ndim == 2 else np.ascontiguousarray(img[:, :, ::-1])
    h, w = bgr.shape[:2]
    if rect is None:
        mx, my = max(1, round(0.05 * w)), max(1, round(0.05 * h))
        rect = (mx, my, w - 2 * mx, h - 2 * my)
    try:
        rect = tuple(int(v) for v in rect)
    except (TypeError, ValueError):
        raise InputError(f"{name}: rect must be (x, y, width, height), got {rect!r}") from None
    if len(rect) != 4:
        raise InputError(f"{name}: rect must be (x, y, width, height), got {rect!r}")
    x, y, rw, rh = rect
    if rw < 2 or rh < 2 or x < 0 or y < 0 or x + rw > w or y + rh > h:
        raise InputError(f"{name}: rect {rect} must be (x, y, width, height) inside the {w}x{h} image")
    gc = np.zeros((h, w), np.uint8)
    bgd = np.zeros((1, 65), np.float64)
    fgd = np.zeros((1, 65), np.float64)
    cv2.grabCut(bgr, gc, rect, bgd, fgd, int(iterations), cv2.GC_INIT_WITH_RECT)
    return (gc == cv2.GC_FGD) | (gc == cv2.GC_PR_FGD), rect


class _Segmentation:
    """The object mask, and the grey field the sub-pixel contour is traced on.

    ``on`` is the boolean mask of object pixels. ``field(r0, r1, c0, c1)``
    returns a float32 crop in which the object is *above* ``level`` (the
    grey levels, negated for a dark object), or ``field`` is None when the
    image is two-valued (a mask: traced as a staircase, then smoothed).
    """

    def __init__(self, on, params, source=None, sign=1.0, level=0.5):
        self.on = on
        self.params = params
        self._source = source
        self._sign = sign
        # float32 halves the memory traffic of the per-pixel steps (its
        # resolution, 1e-7 of the value, is far below any edge noise); the
        # level is rounded to a float32 so that "above" is exact
        self.level = float(np.float32(sign * level)) if source is not None else sign * level
        self.field = None if source is None else self._field

    def _field(self, r0, r1, c0, c1):
        src = self._source[r0:r1, c0:c1]
        if src.ndim == 3:  # luminance of the crop only, in float
            f = src[:, :, :3].astype(np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
        else:
            f = src.astype(np.float32)
        if self._sign < 0:
            np.negative(f, out=f)
        return f


def _segment(img, method, threshold, polarity, name, rect=None, grabcut_iterations=5):
    """Segment an image array: a `_Segmentation` (raises `_Failure` if there is nothing to separate)."""
    import cv2

    params = dict(method=method, polarity=polarity)
    if img.dtype == bool:
        img = img.astype(np.uint8)
    if method == "grabcut":
        _split_channels(img, name)  # validates the array
        on, rect = _grabcut(img, rect, grabcut_iterations, name)
        params.update(polarity="grabcut", threshold=None, level=None, rect=list(rect),
                      iterations=int(grabcut_iterations))
        return _Segmentation(on, params)
    if method == "alpha":
        _, alpha = _split_channels(img, name)
        if alpha is None:
            raise InputError(f"{name}: method 'alpha' needs an image with an alpha channel (RGBA or grey+alpha)")
        src = np.ascontiguousarray(alpha)
        level = 0.5 * _full_scale(src.dtype) if threshold is None else float(threshold)
        params.update(polarity="opaque", threshold=level, level=level)
        on = src > level
        lo, hi = float(src.min()), float(src.max())
        two_valued = lo == hi or not np.any((src != lo) & (src != hi))
        return _Segmentation(on, params) if two_valued else _Segmentation(on, params, src, 1.0, level)

    # a grey image for the statistics and the mask: for 8-bit colour the
    # rounded 8-bit luminance (same split and medians to within half a grey
    # level, from an exact 256-bin histogram); the crop's float luminance is
    # what the contour is traced on
    if img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] in (3, 4):
        if min(img.shape[:2]) < 2:
            raise InputError(f"{name}: image of {img.shape[1]}x{img.shape[0]} pixels is too small")
        grey = cv2.cvtColor(np.ascontiguousarray(img[:, :, :3]), cv2.COLOR_RGB2GRAY)
        source = img
    else:
        grey, _ = _split_channels(img, name)
        source = grey
    t, med_lo, med_hi, lo, hi, n_values = _histogram_stats(np.ascontiguousarray(grey))
    if method == "mask":
        level = 0.5 * (lo + hi)
        params.update(threshold=level, level=level)
        if lo == hi:
            pol = "light" if polarity == "auto" else polarity
            on = np.full(grey.shape, (lo > 0) if pol == "light" else (lo == 0))
            params["polarity"] = pol
            return _Segmentation(on, params)
        light = grey > level
        pol = _polarity_from_border(light) if polarity == "auto" else polarity
        params["polarity"] = pol
        return _Segmentation(light if pol == "light" else ~light, params)

    if lo == hi:
        hint = ""
        if img.ndim == 3 and img.shape[2] in (2, 4):
            hint = "; it has an alpha channel: use method 'alpha'"
        raise _Failure(f"uniform image (every pixel is {lo:g}): no object to separate from a background{hint}")
    if method == "otsu":
        level = 0.5 * (med_lo + med_hi)
        if not lo <= level < hi:
            level = t
        params.update(threshold=t, class_medians=[med_lo, med_hi])
    elif method == "threshold":
        if threshold is None:
            raise InputError(f"{name}: method 'threshold' needs a threshold value")
        level = float(threshold)
        params["threshold"] = level
        if level < lo or level >= hi:
            if polarity == "auto":
                what = "the whole image is on one side of the threshold"
            elif (polarity == "light") == (level < lo):
                what = "every pixel is object"
            else:
                what = "no pixel is object"
            raise _Failure(f"threshold {level:g} is outside the image's range [{lo:g}, {hi:g}]: {what}")
    else:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    light = grey > level
    pol = _polarity_from_border(light) if polarity == "auto" else polarity
    params.update(polarity=pol, level=level)
    on = light if pol == "light" else ~light
    if n_values <= 2:
        return _Segmentation(on, params)
    return _Segmentation(on, params, source, 1.0 if pol == "light" else -1.0, level)


class _Failure(InputError):
    """The image is readable but holds no usable object (a per-file failure)."""


# ------------------------------------------------------------------ sub-pixel
def _rings_from_find_contours(field, level, offset):
    from skimage.measure import find_contours

    rings = []
    for c in find_contours(field, level, fully_connected="high"):
        if len(c) < 4 or not np.array_equal(c[0], c[-1]):
            continue  # open pieces cannot occur on a padded crop; skip defensively
        xy = np.column_stack([c[:-1, 1] + offset[0], c[:-1, 0] + offset[1]])
        rings.append(xy)
    return rings


def _shoelace_area(p):
    x, y = p[:, 0], p[:, 1]
    return -0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


#: Half-width (px) of the window in which the local object and background
#: grey levels are measured for ``local_level`` (in blocks of 4 px: the
#: window is 5 x 5 blocks, 20 px square).
LOCAL_RADIUS = 10
_BLOCK = 4


def _local_level_field(field, level, obj, cls):
    """`field` shifted so that `level` is the local midpoint of object and background.

    The object's and the background's grey levels are averaged over a
    20 px window, using only pixels at least 3 px from the edge (so that
    the edge's own transition does not count); where either is missing the
    global level is kept. The averages vary slowly, so they are taken on
    4 x 4 blocks and interpolated back (bilinear).
    """
    import cv2

    k5 = np.ones((5, 5), np.uint8)
    fg = cv2.erode((cls & obj).view(np.uint8), k5, borderType=cv2.BORDER_CONSTANT, borderValue=0)
    bg = cv2.erode((~cls & ~obj).view(np.uint8), k5, borderType=cv2.BORDER_CONSTANT, borderValue=0)
    h, w = field.shape
    hb, wb = max(1, -(-h // _BLOCK)), max(1, -(-w // _BLOCK))
    fgf, bgf = fg.astype(np.float32), bg.astype(np.float32)
    win = (2 * (LOCAL_RADIUS // _BLOCK) + 1,) * 2
    # block means (cv2's area resampling), then window sums of them; the
    # ratios below do not depend on the normalisation
    ft, fc, bt, bc = (
        cv2.boxFilter(cv2.resize(a, (wb, hb), interpolation=cv2.INTER_AREA), -1, win, normalize=False,
                      borderType=cv2.BORDER_CONSTANT)
        for a in (field * fgf, fgf, field * bgf, bgf)
    )
    eps = 0.5 / (_BLOCK * _BLOCK)
    ok = (fc > eps) & (bc > eps)
    mid = np.full((hb, wb), level, np.float32)
    mid[ok] = 0.5 * (ft[ok] / fc[ok] + bt[ok] / bc[ok])
    # back to pixels: the same resampling geometry in reverse (bilinear)
    up = cv2.resize(mid, (w, h), interpolation=cv2.INTER_LINEAR)
    return field - up + level


def _trace_grey(field, level, obj, cls, n_filled, offset, presmooth, local_level):
    """Rings of one object's boundary on its grey crop `field` (object above `level`).

    `obj` marks the crop's pixels that count as object (the object with its
    holes filled, or the object alone when holes are wanted), `cls` the
    pixels of the object class (any object); `offset` is the crop's (x, y).

    Returns (rings, presmoothed, local): the first of (local level, 3x3
    average), (global level, 3x3 average), (global level, raw) that keeps
    the object whole.
    """
    import cv2

    above = np.nextafter(np.float32(level), np.float32(np.inf))
    pad = 2
    tries = []
    if local_level and presmooth:
        # pixels away from the edge keep their side of the level, so that only
        # this object's boundary is traced and its topology cannot change
        shifted = _local_level_field(field, level, obj, cls)
        k3 = np.ones((3, 3), np.uint8)
        inner = cv2.erode(obj.view(np.uint8), k3, borderType=cv2.BORDER_CONSTANT, borderValue=1).view(bool)
        outer = cv2.erode((~obj).view(np.uint8), k3, borderType=cv2.BORDER_CONSTANT, borderValue=1).view(bool)
        np.maximum(shifted, above, out=shifted, where=inner)
        np.minimum(shifted, level, out=shifted, where=outer)
        tries.append((shifted, True, True))
    # every other pixel is held at or below the level, so only this object's
    # boundary is traced; object pixels are held (just) above it, which only
    # matters where the 8-bit mask and the float field disagree by rounding
    def forced():
        np.minimum(field, level, out=field, where=~obj)  # field is a fresh array: modify in place
        np.maximum(field, above, out=field, where=obj)
        return field

    if presmooth:
        tries.append((forced, True, False))
    tries.append((forced, False, False))
    offset = (offset[0] - pad, offset[1] - pad)
    for i, (f, smooth, local) in enumerate(tries):
        if callable(f):
            f = f()
        e = np.pad(f, pad, mode="edge")
        # object pixels on the image border get mirrored neighbours below the
        # level, which closes the contour exactly on the image edge
        for strip in (e[:pad], e[-pad:], e[pad:-pad, :pad], e[pad:-pad, -pad:]):
            np.minimum(strip, 2 * level - strip, out=strip)
        if smooth:
            e = cv2.blur(e, (3, 3), borderType=cv2.BORDER_REPLICATE)
        rings = _rings_from_find_contours(e, level, offset)
        if i == len(tries) - 1 or (rings and _same_topology(rings, n_filled)):
            return rings, smooth, local
    raise AssertionError("unreachable")  # pragma: no cover


def _same_topology(rings, n):
    """Whether pre-smoothing kept the object whole (did not cut a thin neck).

    `n` is the object's pixel count with its holes filled.
    """
    a = max(abs(_shoelace_area(r)) for r in rings)
    # the traced area differs from the pixel count by well under a pixel per
    # boundary pixel; losing a part of the object costs far more
    return abs(a - n) <= 0.02 * n + 2.0


def _trace_mask(obj, offset):
    """Rings (staircase outlines) of a binary object, before smoothing."""
    e = np.pad(obj.astype(np.float64), 1)
    return _rings_from_find_contours(e, 0.5, (offset[0] - 1, offset[1] - 1))


#: Shift towards the centre of curvature, per unit curvature (px^2), of the
#: level line of an edge averaged over 3x3 pixels and traced by marching
#: squares: measured on exact-coverage discs of radius 20 to 400 px
#: (0.48 to 0.50).
PRESMOOTH_SHIFT = 0.49


def _finish(ring, name, mask_sigma, debias, shape):
    """The Contour of a traced ring: staircase smoothed, or pre-smoothing bias removed."""
    if mask_sigma > 0:
        ring = _smooth_ring(ring, mask_sigma)
    if debias:
        ring = _debias(ring, shape)
    return Contour(ring, name=name)


def _debias(p, shape, sigma=2.0):
    """Undo the 3x3 average's shift of a traced ring towards its centres of curvature.

    The shift is ``PRESMOOTH_SHIFT`` times the curvature vector (which points
    to the centre of curvature whatever the ring's orientation), taken at a
    `sigma` px scale from periodic Gaussian derivatives of the ring
    resampled at about 1 px; it is capped at 0.5 px (sharp corners), and no
    point leaves the image.
    """
    d = np.roll(p, -1, axis=0) - p
    seg = np.hypot(d[:, 0], d[:, 1])
    s = np.concatenate(([0.0], np.cumsum(seg)))
    length = s[-1]
    sigma = min(sigma, length / 16)
    m = max(64, int(np.ceil(length / min(1.0, sigma / 2))))
    su = np.arange(m) * (length / m)
    ring = np.vstack([p, p[:1]])
    z = np.fft.fft(np.interp(su, s, ring[:, 0]) + 1j * np.interp(su, s, ring[:, 1]))
    w = 2 * np.pi * np.fft.fftfreq(m, d=length / m)
    zg = z * np.exp(-0.5 * (w * sigma) ** 2)
    d1 = np.fft.ifft(zg * (1j * w))
    d2 = np.fft.ifft(zg * (-(w**2)))
    speed2 = (d1 * d1.conj()).real
    # curvature vector: the part of d2 normal to the tangent, over speed^2
    along = (d2 * d1.conj()).real / speed2
    kv = (d2 - along * d1) / speed2
    kv *= PRESMOOTH_SHIFT
    mag = np.abs(kv)
    kv = np.where(mag > 0.5, kv * (0.5 / np.maximum(mag, 1e-300)), kv)
    sv = np.append(su, length)
    kv = np.append(kv, kv[0])
    q = p - np.column_stack([np.interp(s[:-1], sv, kv.real), np.interp(s[:-1], sv, kv.imag)])
    # where the object is cut by the image border the corners are sharp; the
    # object cannot reach beyond the image edge
    h, w_ = shape
    np.clip(q[:, 0], -0.5, w_ - 0.5, out=q[:, 0])
    np.clip(q[:, 1], -0.5, h - 0.5, out=q[:, 1])
    return q


def _smooth_ring(p, sigma):
    """Periodic Gaussian smoothing of a closed ring along its arc (sigma in px)."""
    c = Contour(p, orient=False)
    m = max(int(np.ceil(c.perimeter / 0.5)), 16)
    q = c.resample(n=m).points
    # a tiny outline (a pixel or two) must keep its size
    return _fourier_smooth(q, min(sigma, c.perimeter / 16), c.perimeter)


def _fourier_smooth(q, sigma, length):
    n = len(q)
    w = 2 * np.pi * np.fft.fftfreq(n, d=length / n)
    g = np.exp(-0.5 * (w * sigma) ** 2)
    z = np.fft.ifft(np.fft.fft(q[:, 0] + 1j * q[:, 1]) * g)
    return np.column_stack([z.real, z.imag])


def extract(
    image_or_path,
    method="otsu",
    threshold=None,
    polarity="auto",
    objects="largest",
    min_area=None,
    holes=False,
    min_hole_area=None,
    mask_sigma=MASK_SIGMA,
    presmooth=True,
    local_level=True,
    rect=None,
    grabcut_iterations=5,
    name=None,
):
    """Extract the sub-pixel outer contour(s) of the object(s) in an image.

    Parameters
    ----------
    image_or_path : str, Path or ndarray
        An image file (see :func:`read_image`) or an array: ``(H, W)`` grey
        or bool, ``(H, W, 3)`` RGB, ``(H, W, 4)`` RGBA (RGB order).
    method : {'otsu', 'threshold', 'mask', 'alpha', 'grabcut'}
        How the object is separated from the background; see the module
        notes for when to use each. Default 'otsu'.
    threshold : float, optional
        'threshold': the grey level of the object's edge (required), in the
        image's units. 'alpha': the alpha level (default half of opaque).
    polarity : {'auto', 'dark', 'light'}
        Which class is the object for 'otsu', 'threshold' and 'mask'.
        'auto' (default): the class that touches the image border less.
    objects : {'largest', 'all'}
        The largest object only (default) or every object of at least
        `min_area` pixels, largest first.
    min_area : float, optional
        Smallest object, in pixels counted with its holes filled; default
        ``max(9, 1e-4 * H * W)``.
    holes : bool
        Also trace the holes of each object (returned apart, in
        ``Extraction.holes``).
    min_hole_area : float, optional
        Smallest hole kept, in pixels (default `min_area`); smaller ones
        are counted in ``params['holes_dropped']``.
    mask_sigma : float
        Smoothing along the arc (px) of the staircase outline of a
        two-valued (binary) image. Default 1.
    presmooth : bool
        Average the grey field over 3x3 pixels before marching squares
        (default True). Linear interpolation between pixel centres is exact
        only where the edge profile is linear; on an exact-coverage render
        the raw profile is linear over one pixel only, and the traced edge
        wobbles by 0.05 px RMS. The 3x3 average makes the profile linear
        over three pixels (0.004 px RMS about the mean on a disk of radius
        90). It also moves the level line towards the centre of curvature
        by ``PRESMOOTH_SHIFT * k`` (0.49 px^2 times the curvature k); each
        point is moved back along its normal by that amount, with k taken
        at a 2 px scale. If the average would cut the object (a neck
        thinner than about 1.5 px), the raw field is traced instead;
        ``params['presmooth']`` records which, per object.
    local_level : bool
        With `presmooth`, trace each edge at the midpoint of the object's
        and the background's grey levels measured within about
        ``LOCAL_RADIUS`` (10) px of it, rather than at one level for the whole image (default
        True). Under uneven lighting or a graded background a global level
        sits off the local midpoint, which moves a sharp edge by up to the
        width of its transition (three pixels after the 3x3 average); the
        local midpoint keeps it on the 50 % line. Pixels more than a pixel
        from the edge keep their side of the level, so the object's shape
        cannot change; ``params['local_level']`` records, per object,
        whether it was used (it is not if it would cut the object).
    rect : (x, y, width, height), optional
        'grabcut' initial rectangle; default the image inset by 5 %.
    grabcut_iterations : int
        Iterations of GrabCut (default 5).
    name : str, optional
        Names the image in messages and the contours (default: the path,
        or 'image' for an array).

    Returns
    -------
    Extraction
        Contours (``(x, y)`` image pixels, y down, pixel centres at
        integers, closed, counter-clockwise on the screen), holes, the
        object mask and every resolved parameter.

    Raises
    ------
    InputError
        Unreadable file, bad parameter, or an image without a usable object
        (uniform, no object, everything object), with one line naming the
        image and the reason.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:64, :64]
    >>> img = ((xx - 30.0) ** 2 + (yy - 32.0) ** 2 <= 20.0 ** 2).astype(np.uint8) * 255
    >>> ex = extract(img)
    >>> ex.params["method"], ex.params["polarity"], len(ex.contours)
    ('otsu', 'light', 1)
    >>> bool(abs(ex.contour.area - img.astype(bool).sum()) < 0.01 * img.astype(bool).sum())
    True
    """
    if method not in METHODS:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if polarity not in POLARITIES:
        raise InputError(f"unknown polarity {polarity!r}; expected one of {', '.join(POLARITIES)}")
    if objects not in ("largest", "all"):
        raise InputError(f"objects must be 'largest' or 'all', got {objects!r}")
    if not (np.isfinite(mask_sigma) and mask_sigma >= 0):
        raise InputError(f"mask_sigma must be >= 0, got {mask_sigma}")
    img, default_name = _load(image_or_path)
    name = default_name if name is None else str(name)
    try:
        return _extract(img, name, method, threshold, polarity, objects, min_area, holes, min_hole_area,
                        mask_sigma, presmooth, local_level, rect, grabcut_iterations)
    except _Failure as exc:
        raise _Failure(f"{name}: {exc}") from None


def _extract(img, name, method, threshold, polarity, objects, min_area, holes, min_hole_area, mask_sigma,
             presmooth, local_level, rect, grabcut_iterations):
    import cv2

    seg = _segment(img, method, threshold, polarity, name, rect, grabcut_iterations)
    on, params, field_, level = seg.on, seg.params, seg.field, seg.level
    h, w = on.shape
    if min_area is None:
        min_area = max(9.0, 1e-4 * h * w)
    if not np.isfinite(min_area) or min_area < 0:
        raise InputError(f"min_area must be >= 0, got {min_area}")
    min_hole_area = float(min_area if min_hole_area is None else min_hole_area)
    n_on = int(np.count_nonzero(on))
    if n_on == 0:
        raise _Failure("no object: no pixel belongs to the object class")
    if n_on == on.size:
        raise _Failure("everything is object: no background pixel")

    # outer boundaries of the 8-connected objects (far faster than labelling
    # every pixel); an object's size is its pixel count with holes filled
    on8 = np.ascontiguousarray(on, dtype=np.uint8)
    outlines, _ = cv2.findContours(on8, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    # Pick's theorem: pixels = polygon area + boundary pixels / 2 + 1 (exact
    # for a simple outline; only a pre-filter, exact counts follow)
    approx = np.array([cv2.contourArea(c) + 0.5 * len(c) + 1.0 for c in outlines])

    # the grey path measures local grey levels up to LOCAL_RADIUS px away
    margin = 2 + (LOCAL_RADIUS if field_ is not None and local_level else 0)

    def silhouette(k):
        x, y, bw, bh = cv2.boundingRect(outlines[k])
        r0, c0 = max(y - margin, 0), max(x - margin, 0)
        r1, c1 = min(y + bh + margin, h), min(x + bw + margin, w)
        filled = np.zeros((r1 - r0, c1 - c0), np.uint8)
        cv2.drawContours(filled, outlines, k, 1, thickness=-1, offset=(-c0, -r0))
        return (r0, r1, c0, c1), filled.view(bool)

    order = np.argsort(-approx, kind="stable")
    if objects == "largest":
        cand = [k for k in order if approx[k] >= 0.8 * approx[order[0]] - 4]
    else:
        cand = [k for k in order if approx[k] >= 0.5 * min_area - 4]
    sil = {k: silhouette(k) for k in cand}
    size = {k: int(np.count_nonzero(sil[k][1])) for k in cand}
    cand.sort(key=lambda k: -size[k])  # stable: ties keep the scan order
    chosen = [k for k in cand if size[k] >= min_area]
    if not chosen:
        biggest = max(size.values()) if size else int(max(approx))
        raise _Failure(f"no object of at least {min_area:g} px (largest has {biggest} px)")
    if objects == "largest":
        chosen = chosen[:1]

    contours, hole_lists, dropped, presmoothed, localised = [], [], 0, [], []
    mask = np.zeros((h, w), bool)
    for k in chosen:
        (r0, r1, c0, c1), filled = sil[k]
        obj = filled
        if holes:
            # the object itself: the 8-connected part of the filled outline
            # that holds the outline (islands inside holes are not part of it)
            part = (on[r0:r1, c0:c1] & filled).view(np.uint8)
            _, lab = cv2.connectedComponents(part, connectivity=8)
            x0, y0 = outlines[k][0, 0]
            obj = lab == lab[y0 - r0, x0 - c0]
        mask[r0:r1, c0:c1] |= obj
        n_filled = size[k]
        if field_ is not None:
            rings, smoothed_ok, was_local = _trace_grey(
                field_(r0, r1, c0, c1), level, obj, on[r0:r1, c0:c1], n_filled, (c0, r0),
                presmooth, local_level,
            )
            presmoothed.append(smoothed_ok)
            localised.append(was_local)
        else:
            rings = _trace_mask(obj, (c0, r0))
        if not rings:
            raise _Failure(f"object of {n_filled} px gave no closed contour")
        areas_r = np.array([_shoelace_area(r) for r in rings])
        k_out = int(np.argmax(np.abs(areas_r)))
        outer_sign = np.sign(areas_r[k_out])
        hole_rings = [r for i, r in enumerate(rings) if i != k_out and np.sign(areas_r[i]) != outer_sign]
        debias = field_ is not None and presmoothed[-1]
        sigma_m = mask_sigma if field_ is None else 0.0
        contours.append(_finish(rings[k_out], name, sigma_m, debias, (h, w)))
        hl = []
        if holes:
            for r in hole_rings:
                if abs(_shoelace_area(r)) < min_hole_area:
                    dropped += 1
                    continue
                hl.append(_finish(r, name, sigma_m, debias, (h, w)))
        hole_lists.append(hl)

    params.update(
        subpixel="grey" if field_ is not None else "mask",
        presmooth=presmoothed if field_ is not None else None,
        local_level=localised if field_ is not None else None,
        objects=objects,
        min_area=float(min_area),
        min_hole_area=min_hole_area,
        holes=bool(holes),
        holes_dropped=dropped,
        mask_sigma=float(mask_sigma) if field_ is None else None,
        n_objects_found=len(outlines),
        object_areas=[size[k] for k in chosen],
        shape=[int(h), int(w)],
        source=name,
    )
    return Extraction(contours, hole_lists, mask, params)


def extract_contours(image_or_path, method="otsu", threshold=None, polarity="auto", objects="largest",
                     min_area=None, holes=False, **kwargs):
    """Sub-pixel outer contours of the object(s) in an image (stable entry point).

    The same as ``extract(...).contours``; see :func:`extract` for the
    parameters. This signature is what recipes (``from_image``) call; it
    will stay compatible.

    Returns
    -------
    list of Contour
        Outer contours, largest first; ``(x, y)`` in the image's pixels (x =
        column, y = row, y down, pixel centres at integers), closed, first
        point not repeated, counter-clockwise on the screen.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 50), np.uint8); img[10:30, 5:25] = 200
    >>> [c] = extract_contours(img)
    >>> [round(float(v), 1) for v in c.bbox]
    [4.5, 9.5, 24.5, 29.5]
    """
    return extract(image_or_path, method=method, threshold=threshold, polarity=polarity, objects=objects,
                   min_area=min_area, holes=holes, **kwargs).contours


# --------------------------------------------------------- curvature & surprisal
def default_sigma(contour, fraction=SIGMA_FRACTION, minimum=MIN_SIGMA):
    """The default smoothing/curvature scale of a contour, in px of arc length.

    ``max(fraction * perimeter, minimum)``: 1 % of the perimeter, so the
    scale follows the shape (the same object photographed twice as large is
    smoothed at twice the pixel scale, i.e. identically), and never below
    1 px, the scale of pixel noise.
    """
    c = contour if isinstance(contour, Contour) else Contour(contour)
    return float(max(fraction * c.perimeter, minimum))


def _resolve_sigma(c, sigma):
    if sigma is None:
        return default_sigma(c)
    sigma = float(sigma)
    if not (np.isfinite(sigma) and sigma > 0):
        raise InputError(f"sigma must be > 0 px, got {sigma}")
    return sigma


def smooth(contour, sigma=None, spacing=None):
    """A closed contour smoothed along its arc by a periodic Gaussian.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    sigma : float, optional
        Scale in px of arc length; default :func:`default_sigma`.
    spacing : float, optional
        Spacing of the returned points in px (default: about 1 px, and at
        most ``sigma / 4``).

    Returns
    -------
    Contour
        Equally spaced (in the input's arc length) points of the smoothed
        curve, starting at the smoothed first point, counter-clockwise on the
        screen. A circle of radius R shrinks by about ``sigma**2 / (2 R)``.
    """
    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("smoothing is for closed contours")
    sigma = _resolve_sigma(c, sigma)
    if spacing is None:
        spacing = min(1.0, sigma / 4)
    m = max(int(np.ceil(c.perimeter / spacing)), 16)
    q = c.resample(n=m).points
    return Contour(_fourier_smooth(q, sigma, c.perimeter), orient=False, name=c.name)


def contour_curvature(contour, sigma=None):
    """Curvature (1/px, positive where convex) at a contour's own points.

    Gaussian-derivative curvature at scale `sigma` (default
    :func:`default_sigma`, 1 % of the perimeter), computed on the contour
    resampled at equal arc-length steps and read back at each point's arc
    position (``Contour.curvature(method='gaussian')``).
    """
    c = contour if isinstance(contour, Contour) else Contour(contour)
    return c.curvature(method="gaussian", sigma=_resolve_sigma(c, sigma))


@dataclass
class ContourInfo:
    """Curvature and surprisal of an extracted contour, with its parameters.

    Attributes
    ----------
    contour : Contour
        The contour as given (e.g. extracted), image pixels, y down.
    smoothed : Contour
        It smoothed at `sigma` (about 1 px spacing).
    sigma : float
        The smoothing/curvature scale in px of arc length.
    surprisal : stimuli.information.SurprisalResult
        Surprisal at `n` equally spaced points of the smoothed contour
        (its ``table()`` has the columns of ``attneave surprisal``).
    curvature : ndarray
        Gaussian-derivative curvature at scale `sigma` at the same points
        (1/px, positive where convex).
    params : dict
        sigma, sigma_fraction (None if sigma was given), and the surprisal
        parameters (model, n, ds, length, A, b, ...).
    """

    contour: Contour
    smoothed: Contour
    sigma: float
    surprisal: object
    curvature: np.ndarray
    params: dict = field(default_factory=dict)


def describe(contour, n=None, spacing=None, sigma=None, model="paper", A=0.25, b=None, bits=False,
             prominence=None, length_unit=None):
    """Smooth a closed contour at its own scale, then curvature and surprisal.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    n, spacing : optional
        Sampling of the surprisal (default ``n=100``); see
        :func:`stimuli.information.surprisal`.
    sigma : float, optional
        Smoothing scale in px of arc length (default 1 % of the perimeter,
        at least 1 px).
    model, A, b, bits, length_unit
        As in :func:`stimuli.information.surprisal` (`length_unit` None: its
        default).
    prominence : float, optional
        Smallest prominence of a surprisal peak. Default: 5 % of the
        surprisal's range or of the surprisal step from the mean turn
        ``2 pi / n`` to twice it, whichever is larger, so that a circle's
        pixel noise yields no peaks (as :func:`curvature_peaks`).

    Returns
    -------
    ContourInfo
    """
    from stimuli.geometry.information import surprisal

    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("describe() is for closed contours")
    s = _resolve_sigma(c, sigma)
    q = c.resample(n=max(int(np.ceil(c.perimeter / min(1.0, s / 4))), 16)).points
    sm = Contour(_fourier_smooth(q, s, c.perimeter), orient=False, name=c.name)
    unit = {} if length_unit is None else {"length_unit": length_unit}
    res = surprisal(sm, n=n, spacing=spacing, model=model, A=A, b=b, bits=bits, prominence=prominence, **unit)
    if prominence is None:
        res = _with_default_prominence(res, model, A, bits)
    # the Gaussian-derivative curvature of the same samples is the smoothed
    # curve's curvature; read it at the surprisal's arc positions
    k = gaussian_curvature(q, s)
    t_sm = sm.t()
    kk = np.interp(res.t, np.append(t_sm, 1.0), np.append(k, k[0]))
    params = dict(sigma=s, sigma_fraction=SIGMA_FRACTION if sigma is None else None, **res.params)
    return ContourInfo(c, sm, s, res, kk, params)


def _with_default_prominence(res, model, A, bits):
    """Peaks again with prominence 5 % of max(range of u, u(2 mu) - u(mu)), mu = 2 pi / n."""
    import dataclasses

    from stimuli.geometry.information import find_peaks, surprisal_paper, surprisal_vonmises

    n = res.params["n"]
    mu = 2 * np.pi / n
    if model == "paper":
        ref = surprisal_paper(np.array([mu, 2 * mu]), res.params["ds_in_unit"], n, A=A, b=res.params["b"], bits=bits)
    else:
        ref = surprisal_vonmises(np.array([mu, 2 * mu]), n, b=res.params["b"], bits=bits)
    prominence = 0.05 * max(float(np.ptp(res.surprisal)), float(abs(ref[1] - ref[0])))
    peaks, _ = find_peaks(res.surprisal, closed=True, prominence=prominence)
    return dataclasses.replace(res, peaks=peaks, params={**res.params, "prominence": prominence})


def curvature_peaks(contour, sigma=None, prominence=None, minima=False):
    """Curvature maxima (or minima) of a closed contour, located between samples.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    sigma : float, optional
        Curvature scale in px of arc length (default :func:`default_sigma`).
    prominence : float, optional
        Minimum prominence in 1/px. Default: 5 % of the curvature's range
        or of the mean curvature of a closed curve, ``2 pi / perimeter``,
        whichever is larger, so that a circle's pixel noise yields no
        extrema.
    minima : bool
        Find minima (the most concave places) instead of maxima.

    Returns
    -------
    dict
        ``t`` (arc positions in [0, 1) from the first point), ``s`` (px),
        ``points`` ((K, 2) ``(x, y)`` on the contour), ``curvature`` (1/px)
        and ``sigma``, ordered from the most extreme. Each extremum is the
        vertex of a parabola fitted to the curvature over +-sigma/2 around
        the best sample, so that its place is not limited by the sampling or
        by pixel noise on a flat maximum.
    """
    from stimuli.geometry.information import find_peaks

    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("curvature_peaks() is for closed contours")
    s = _resolve_sigma(c, sigma)
    m = max(int(np.ceil(c.perimeter / min(1.0, s / 4))), 16)
    q = c.resample(n=m).points
    k = gaussian_curvature(q, s)
    sign = -1.0 if minima else 1.0
    if prominence is None:
        prominence = 0.05 * max(float(np.ptp(k)), 2 * np.pi / c.perimeter)
    idx, _ = find_peaks(sign * k, closed=True, prominence=prominence)
    ds = c.perimeter / m
    half = int(np.clip(round(s / ds), 2, m // 4))
    off = np.arange(-half, half + 1)
    pos = []
    for i in idx:
        y = sign * k[(i + off) % m]
        a2, a1, _a0 = np.polyfit(off.astype(float), y, 2)
        d = -a1 / (2 * a2) if a2 < 0 else 0.0
        pos.append(i + float(np.clip(d, -half, half)))
    pos = np.mod(np.asarray(pos, float), m)
    t = pos / m
    kv = np.interp(pos, np.arange(m + 1), np.append(k, k[0]))
    return dict(t=t, s=t * c.perimeter, points=c.point_at(t), curvature=kv, sigma=s, prominence=float(prominence))
