"""Segmentation: the object mask (Otsu, threshold, mask, alpha, GrabCut) and the
grey field on which its sub-pixel contour is traced.

Masks are ``(H, W)`` bool arrays; row ``i``, column ``j`` is the pixel centred at
``(x, y) = (j, i)`` (y down).
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction.imageio import full_scale, split_channels

__all__ = ["METHODS", "POLARITIES", "PLAIN_ETA", "OPTION_METHODS", "NoObject", "Segmentation", "segment",
           "grabcut_mask", "image_kind", "check_method_options"]

METHODS = ("auto", "otsu", "threshold", "mask", "alpha", "grabcut", "photo", "model", "rembg")
#: Otsu's between-class share of the grey variance above which ``auto``
#: takes an image for one object on a plain background (renders, scans,
#: product shots); below it, for a photograph.
PLAIN_ETA = 0.97
POLARITIES = ("auto", "dark", "light")
#: The methods each method-specific option applies to (any other method refuses it), for
#: :func:`attneave.stimuli.extraction.extract` and ``attneave extract`` alike (:func:`check_method_options`).
#: ``model_file`` is the Python API's ``model`` dict (``--model-file``, ``--rembg-model`` and their companions).
OPTION_METHODS = {
    "threshold": ("threshold", "alpha"), "rect": ("grabcut",), "grabcut_iterations": ("auto", "photo", "grabcut"),
    "boxes": ("auto", "photo", "model", "rembg"), "scribbles": ("auto", "photo"), "model_file": ("model", "rembg"),
    "model_size": ("model",), "model_mean": ("model",), "model_std": ("model",), "rembg_model": ("rembg",),
}


def check_method_options(method, given, cli=False, names=None):
    """Refuse options that do not apply to `method` (one rule for the Python API and the command line).

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    given : dict
        Option name (a key of :data:`OPTION_METHODS`) -> value; None is "not given".
    cli : bool
        Name the options as ``attneave extract`` flags (``--rect``, ``--method grabcut``) rather than
        as the Python parameters (``rect``, ``method='grabcut'``).
    names : dict, optional
        Python names of options whose parameter is called otherwise (e.g. ``model_file`` -> ``model``).

    Raises
    ------
    InputError
        ``rect needs method 'grabcut', not 'otsu'`` (or, with `cli`, ``--rect applies to
        --method grabcut only, not --method otsu``).
    """
    bad = [k for k, v in given.items() if v is not None and method not in OPTION_METHODS[k]]
    if not bad:
        return
    need = OPTION_METHODS[bad[0]]
    same = [k for k in bad if OPTION_METHODS[k] == need]
    if cli:  # the wording the command's users (and tests) know
        label = ", ".join(f"--{k.replace('_', '-')}" for k in same)
        *first, last = need
        verb = "apply" if "," in label else "applies"
        raise InputError(f"{label} {verb} to --method {', '.join(first) + ' or ' if first else ''}{last} only, "
                         f"not --method {method}")
    label = ", ".join(dict.fromkeys((names or {}).get(k, k) for k in same))
    *first, last = (repr(m) for m in need)
    verb = "need" if "," in label or label.endswith("s") else "needs"
    raise InputError(f"{label} {verb} method {', '.join(first) + ' or ' if first else ''}{last}, not {method!r}")


class NoObject(InputError):
    """The image is readable but holds no usable object (a per-file failure)."""


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


#: Widest line (px) along the whole image edge that is taken for a drawn frame, not an object.
MAX_FRAME_LINE = 3


def _frame_line(light):
    """Width (px) of a drawn frame line along the image's edge in the two-class image `light`, or 0.

    A frame is ``d`` outermost rings of pixels (1 <= d <= :data:`MAX_FRAME_LINE`)
    that are all of one class, with the ring just inside them mostly of
    the other class (the page or screen the figure is drawn on). Such a
    line encloses everything: taken as an object, its filled outline is
    the whole image and the figure inside it is never found.
    """
    h, w = light.shape
    v = light[0, 0]
    for d in range(MAX_FRAME_LINE + 1):  # ring d = MAX_FRAME_LINE must be page
        if h < 2 * d + 4 or w < 2 * d + 4:
            return 0
        ring = np.concatenate([light[d, d : w - d], light[h - 1 - d, d : w - d],
                               light[d + 1 : h - 1 - d, d], light[d + 1 : h - 1 - d, w - 1 - d]])
        if np.all(ring == v):
            continue
        # ring d is the first that is not all frame: the frame is d rings wide if ring d is mostly page
        return d if d > 0 and np.count_nonzero(ring == v) < 0.5 * ring.size else 0
    return 0


def _without_frame(light, polarity):
    """(object mask, polarity, frame width): `light` split into object and background, a drawn frame
    line along the image's edge (:func:`_frame_line`) ignored for the polarity and taken as background."""
    d = _frame_line(light)
    inner = light[d : light.shape[0] - d, d : light.shape[1] - d] if d else light
    pol = _polarity_from_border(inner) if polarity == "auto" else polarity
    on = light if pol == "light" else ~light
    if d and on[0, 0]:
        on = on.copy()
        on[:d], on[-d:], on[:, :d], on[:, -d:] = False, False, False, False
    return on, pol, d


def _polarity_from_border(on):
    """'light' if the 'on' pixels touch the image border less than the others."""
    border = np.concatenate([on[0], on[-1], on[1:-1, 0], on[1:-1, -1]])
    frac = border.mean()
    if frac < 0.5:
        return "light"
    if frac > 0.5:
        return "dark"
    return "light" if on.mean() <= 0.5 else "dark"


def _on_colour_edge(img, on, params):
    """A photo's figure-ground mask `on`, to be traced on the photo's colour edge where it is sharp."""
    from attneave.stimuli.extraction.figure_ground.colour_edge import ColourEdgeSource

    return Segmentation(on, params, ColourEdgeSource(img, on), 1.0, 0.5, near_mask=True)


def grabcut_mask(image, rect, iterations, name):
    """GrabCut from a box (default: the image inset by 5 %): (object mask, the box used)."""
    from attneave.stimuli.extraction.figure_ground.grabcut import check_box, grabcut, inset_box, to_bgr8

    bgr = to_bgr8(image)
    rect = check_box(inset_box(bgr.shape) if rect is None else rect, bgr.shape, name)
    return grabcut(bgr, box=rect, iterations=iterations), rect


class Segmentation:
    """The object mask, and the grey field the sub-pixel contour is traced on.

    ``on`` is the boolean mask of object pixels. ``field(r0, r1, c0, c1)``
    returns a float32 crop in which the object is *above* ``level`` (the
    grey levels, negated for a dark object), or ``field`` is None when the
    image is two-valued (a mask: traced as a staircase, then smoothed).
    ``near_mask``: the mask was found by other means than the field (a
    photo's figure-ground traced on its colour edge), so the traced outline
    is held near the mask (:func:`attneave.stimuli.extraction.trace.trace_grey`).
    """

    def __init__(self, on, params, source=None, sign=1.0, level=0.5, near_mask=False):
        self.on = on
        self.params = params
        self.near_mask = near_mask
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


def image_kind(img, name="image"):
    """What ``method='auto'`` does with an image: 'otsu', 'alpha' or 'photo'.

    'alpha' for a cut-out (an alpha channel that is partly transparent and
    partly opaque); 'otsu' for a two-valued image (a mask, a silhouette),
    one object on a plain background (Otsu's two classes hold at least
    :data:`PLAIN_ETA` of the grey variance) or two flat tones apart from an
    antialiased rim (:func:`_two_tone`: a small render); 'photo' otherwise.
    """
    if img.dtype == bool:
        return "otsu"
    grey, alpha = split_channels(img, name)
    if alpha is not None:
        full = full_scale(alpha.dtype)
        if float(alpha.min()) < 0.5 * full < float(alpha.max()):
            return "alpha"
    step = max(1, int(np.ceil(np.sqrt(grey.size / 1e6))))  # a regular subsample of about 1 Mpx is plenty
    g = np.asarray(grey[::step, ::step], np.float64).ravel()
    lo, hi = g.min(), g.max()
    if lo == hi or not np.any((g != lo) & (g != hi)):
        return "otsu"
    t, *_ = _histogram_stats(np.ascontiguousarray(grey))
    low = g <= t
    w0 = low.mean()
    if w0 in (0.0, 1.0):
        return "otsu"
    eta = w0 * (1 - w0) * (g[low].mean() - g[~low].mean()) ** 2 / g.var()
    if eta >= PLAIN_ETA:
        return "otsu"
    # a small antialiased render or silhouette: its rim of mixed pixels is a large share of the
    # image (eta 0.9 at 48 px) though everything off the rim is one of two tones
    return "otsu" if _two_tone(grey[::step, ::step], t) else "photo"  # the same ~1 Mpx subsample


#: Share of the pixels off the rim between the two classes that must lie within
#: TWO_TONE_TOL of the image's range from their class's median for :func:`_two_tone`.
TWO_TONE_SHARE = 0.99
TWO_TONE_TOL = 0.03


def _two_tone(grey, t, rim=2):
    """Whether an image is two flat tones apart from a rim of `rim` px along their boundary.

    An antialiased silhouette (a render, a small PNG or a high-quality JPEG
    of one) is; a photograph of an object on a plain background is not (its
    shading, texture and noise lie off the two tones): on the 95 development
    photos none is, while 96-100 % of renders of MPEG-7 shapes at 32-64 px
    are (JPEG at quality 75 rings beyond the rim, and stays a photo).
    """
    import cv2

    g = np.asarray(grey, np.float64)
    low = g <= t
    k = np.ones((2 * rim + 1, 2 * rim + 1), np.uint8)
    lo8 = low.astype(np.uint8)
    off = cv2.dilate(lo8, k) == cv2.erode(lo8, k)  # not within `rim` px of the other class
    if not off.any() or low.all() or not low.any():
        return False
    dev = np.where(low, np.abs(g - np.median(g[low])), np.abs(g - np.median(g[~low])))[off]
    return bool(np.mean(dev <= TWO_TONE_TOL * (g.max() - g.min())) >= TWO_TONE_SHARE)


def segment(img, method, threshold, polarity, name, rect=None, grabcut_iterations=5, box=None, scribbles=None,
            model=None):
    """Segment an image array: a `Segmentation` (raises `NoObject` if there is nothing to separate).

    `box` and `scribbles` go to :func:`attneave.stimuli.extraction.figure_ground.photo.segment_photo`
    (and make ``auto`` a photo method); `model` is a dict of the arguments
    of :func:`attneave.stimuli.extraction.figure_ground.model.object_probability` (method ``model``) or
    :func:`attneave.stimuli.extraction.figure_ground.learned.network_probability` (method ``rembg``).
    """
    import cv2

    params = dict(method=method, polarity=polarity)
    if img.dtype == bool:
        img = img.astype(np.uint8)
    if method == "auto":
        method = "photo" if box is not None or scribbles is not None else image_kind(img, name)
        params["resolved"] = method
    if method == "photo":
        from attneave.stimuli.extraction.figure_ground.photo import segment_photo

        res = segment_photo(img, box=box, scribbles=scribbles, iterations=grabcut_iterations, name=name)
        params.update(polarity="photo", threshold=None, level=None, **res.params)
        return _on_colour_edge(img, res.mask, params)
    if method in ("model", "rembg"):
        from attneave.stimuli.extraction.figure_ground.learned import learned_probability

        prob, box, which = learned_probability(img, method, model, box, name)
        params.update(polarity="model", threshold=0.5, level=0.5, **which,
                      mode="auto" if box is None else "box", box=None if box is None else list(box))
        if box is not None and not np.any(prob > 0.5):
            # the person drew the box around an object: GrabCut's outline from it
            # beats none, and the verdict says whose outline it is
            seg = segment(img, "photo", threshold, polarity, name, box=box, scribbles=scribbles)
            seg.params.update(method=method, resolved="photo", **which, model_found_nothing=True)
            return seg
        return Segmentation(prob > 0.5, params, prob, 1.0, 0.5)
    if method == "grabcut":
        split_channels(img, name)  # validates the array
        on, rect = grabcut_mask(img, rect, grabcut_iterations, name)
        params.update(polarity="grabcut", threshold=None, level=None, rect=list(rect),
                      iterations=int(grabcut_iterations))
        return _on_colour_edge(img, on, params)
    if method == "alpha":
        _, alpha = split_channels(img, name)
        if alpha is None:
            raise InputError(f"{name}: method 'alpha' needs an image with an alpha channel (RGBA or grey+alpha)")
        src = np.ascontiguousarray(alpha)
        level = 0.5 * full_scale(src.dtype) if threshold is None else float(threshold)
        params.update(polarity="opaque", threshold=level, level=level)
        on = src > level
        lo, hi = float(src.min()), float(src.max())
        two_valued = lo == hi or not np.any((src != lo) & (src != hi))
        return Segmentation(on, params) if two_valued else Segmentation(on, params, src, 1.0, level)

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
        grey, _ = split_channels(img, name)
        source = grey
    t, med_lo, med_hi, lo, hi, n_values = _histogram_stats(np.ascontiguousarray(grey))
    if method == "mask":
        level = 0.5 * (lo + hi)
        params.update(threshold=level, level=level)
        if lo == hi:
            pol = "light" if polarity == "auto" else polarity
            on = np.full(grey.shape, (lo > 0) if pol == "light" else (lo == 0))
            params["polarity"] = pol
            return Segmentation(on, params)
        on, pol, frame = _without_frame(grey > level, polarity)
        params.update(polarity=pol, frame_line=frame)
        return Segmentation(on, params)

    if lo == hi:
        hint = ""
        if img.ndim == 3 and img.shape[2] in (2, 4):
            hint = "; it has an alpha channel: use method 'alpha'"
        raise NoObject(f"uniform image (every pixel is {lo:g}): no object to separate from a background{hint}")
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
            raise NoObject(f"threshold {level:g} is outside the image's range [{lo:g}, {hi:g}]: {what}")
    else:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    # a frame drawn around a figure (a scanned page, an exported silhouette) is neither the figure nor
    # the border's class: it is set aside, or it would be taken for an object enclosing everything
    on, pol, frame = _without_frame(grey > level, polarity)
    params.update(polarity=pol, level=level, frame_line=frame)
    if n_values <= 2:
        return Segmentation(on, params)
    return Segmentation(on, params, source, 1.0 if pol == "light" else -1.0, level)
