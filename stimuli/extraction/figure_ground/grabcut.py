"""GrabCut (Rother et al. 2004) as the extraction methods use it: 8-bit BGR
input, boxes checked against the image, initialisation from a box or a
label mask, and the tidy-up of its result.

Boxes are ``(x, y, width, height)`` in image pixels: the pixels of columns
``x .. x + width - 1`` and rows ``y .. y + height - 1`` (y down).

References
----------
.. [1] Rother, C., Kolmogorov, V., & Blake, A. (2004). "GrabCut":
       interactive foreground extraction using iterated graph cuts.
       ACM Trans. Graphics 23(3), 309-314.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["to_bgr8", "inset_box", "check_box", "box_labels", "core_labels", "grabcut", "largest_part",
           "fill_holes"]

#: GrabCut's labels (as cv2.GC_BGD, GC_FGD, GC_PR_BGD, GC_PR_FGD).
BGD, FGD, PR_BGD, PR_FGD = 0, 1, 2, 3
#: Seed of OpenCV's random generator before every GrabCut (its k-means start of the colour models):
#: the same photo gives the same outline. Other seeds give other answers (see
#: ``benchmarks/grabcut_seeds.py``: the development photos' medians move by a few hundredths).
SEED = 0


def to_bgr8(image):
    """An 8-bit BGR copy of a grey, grey+alpha, RGB or RGBA array (alpha dropped, other depths stretched)."""
    import cv2

    img = np.asarray(image)
    if img.dtype == bool:
        img = img.astype(np.uint8) * 255
    if img.ndim == 3 and img.shape[2] in (2, 4):
        img = img[:, :, : img.shape[2] - 1]
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[:, :, 0]
    if img.dtype != np.uint8:
        f = img.astype(np.float64)
        img = np.clip(np.round(255 * (f - f.min()) / max(np.ptp(f), 1e-12)), 0, 255).astype(np.uint8)
    return cv2.cvtColor(img, cv2.COLOR_GRAY2BGR) if img.ndim == 2 else np.ascontiguousarray(img[:, :, ::-1])


def inset_box(shape, fraction=0.05):
    """The box of an image of `shape` ``(H, W, ...)`` inset by `fraction` of its size on every side."""
    h, w = shape[:2]
    mx, my = max(1, round(fraction * w)), max(1, round(fraction * h))
    return (mx, my, w - 2 * mx, h - 2 * my)


def check_box(box, shape, name, what="rect"):
    """`box` as four ints ``(x, y, width, height)`` inside an image of `shape`; InputError otherwise."""
    h, w = shape[:2]
    try:
        vals = [float(v) for v in box]
    except (TypeError, ValueError):
        raise InputError(f"{name}: {what} must be (x, y, width, height), got {box!r}") from None
    if len(vals) != 4 or not all(np.isfinite(vals)):
        raise InputError(f"{name}: {what} must be four finite numbers (x, y, width, height), got {box!r}")
    x, y, bw, bh = (int(round(v)) for v in vals)
    if bw < 2 or bh < 2 or x < 0 or y < 0 or x + bw > w or y + bh > h:
        raise InputError(f"{name}: {what} ({x}, {y}, {bw}, {bh}) must be (x, y, width, height) of at least "
                         f"2x2 pixels inside the {w}x{h} image")
    return (x, y, bw, bh)


def box_labels(shape, box, band=0.0):
    """GrabCut labels for a box: sure background outside, probably object inside, probably background
    on the box's outer `band` (a fraction of its width and height, at least 1 px when `band` > 0).

    A person draws a box a little larger than the object, so a thin band
    along its inside is mostly background; holding it as *probable*
    background lets GrabCut learn the object's immediate surroundings
    while leaving it free to give the band back to the object where the
    object reaches the box.

    Parameters
    ----------
    shape : tuple
        ``(H, W, ...)`` of the image.
    box : (x, y, width, height)
        Image pixels, inside the image (as :func:`check_box` gives).
    band : float
        Fraction of the box's width (left and right) and height (top and
        bottom); 0 for none.

    Returns
    -------
    (H, W) uint8 ndarray
        ``BGD, FGD, PR_BGD, PR_FGD`` = 0, 1, 2, 3.

    Examples
    --------
    >>> box_labels((6, 8), (1, 1, 6, 4), band=0.2)
    array([[0, 0, 0, 0, 0, 0, 0, 0],
           [0, 2, 2, 2, 2, 2, 2, 0],
           [0, 2, 3, 3, 3, 3, 2, 0],
           [0, 2, 3, 3, 3, 3, 2, 0],
           [0, 2, 2, 2, 2, 2, 2, 0],
           [0, 0, 0, 0, 0, 0, 0, 0]], dtype=uint8)
    """
    labels = np.full(shape[:2], BGD, np.uint8)
    x, y, bw, bh = box
    if band > 0:
        labels[y : y + bh, x : x + bw] = PR_BGD
        bx, by = max(1, int(round(band * bw))), max(1, int(round(band * bh)))
        labels[y + by : y + bh - by, x + bx : x + bw - bx] = PR_FGD
    else:
        labels[y : y + bh, x : x + bw] = PR_FGD
    return labels


def core_labels(shape, box, core=0.7):
    """GrabCut labels for a box around an object that fills only part of it: sure background
    outside, probably object on the central ellipse of `core` times the box's width and height,
    probably background on the rest of the box.

    GrabCut learns its first colour models from the initial labels; with
    the whole box as probable object (:func:`box_labels`) an object that
    fills a third of its box (a horse: legs apart, background between
    them) gets an object model that is two thirds background, and the
    background inside the box then stays object. Starting from the box's
    centre instead, the object model begins mostly on the object, and the
    iterations give its outer parts (legs, tail) back to it where their
    colours are the object's.

    Parameters
    ----------
    shape, box
        As for :func:`box_labels`.
    core : float
        The ellipse's axes as a fraction of the box's width and height.

    Returns
    -------
    (H, W) uint8 ndarray
        The labels, as :func:`box_labels` gives them.

    Examples
    --------
    >>> core_labels((7, 9), (1, 1, 7, 5), core=0.6)
    array([[0, 0, 0, 0, 0, 0, 0, 0, 0],
           [0, 2, 2, 2, 2, 2, 2, 2, 0],
           [0, 2, 2, 2, 3, 3, 2, 2, 0],
           [0, 2, 3, 3, 3, 3, 3, 2, 0],
           [0, 2, 2, 2, 3, 3, 2, 2, 0],
           [0, 2, 2, 2, 2, 2, 2, 2, 0],
           [0, 0, 0, 0, 0, 0, 0, 0, 0]], dtype=uint8)
    """
    import cv2

    labels = np.full(shape[:2], BGD, np.uint8)
    x, y, bw, bh = box
    labels[y : y + bh, x : x + bw] = PR_BGD
    centre = (x + bw // 2, y + bh // 2)
    axes = (max(1, int(core * bw / 2)), max(1, int(core * bh / 2)))
    cv2.ellipse(labels, centre, axes, 0, 0, 360, PR_FGD, thickness=-1)
    return labels


def grabcut(bgr, box=None, labels=None, iterations=5):
    """Object pixels by GrabCut, from a box or from a label mask.

    Parameters
    ----------
    bgr : (H, W, 3) uint8 ndarray
        As :func:`to_bgr8` gives.
    box : (x, y, width, height), optional
        Outside it is background; inside, probably object.
    labels : (H, W) uint8 ndarray, optional
        Initial labels (``BGD, FGD, PR_BGD, PR_FGD`` = 0, 1, 2, 3); used when
        no box is given. Must hold some background (0 or 2) and some object
        (1 or 3).
    iterations : int

    Returns
    -------
    (H, W) bool ndarray
        Where GrabCut ends with (probable) object. If the initial labels
        leave no object or no background sample, the initial guess.
        The same input gives the same answer (OpenCV's random generator,
        which seeds GrabCut's colour models by k-means, is reset first).
    """
    import cv2

    cv2.setRNGSeed(SEED)

    bgd = np.zeros((1, 65), np.float64)
    fgd = np.zeros((1, 65), np.float64)
    if box is not None:
        gc = np.zeros(bgr.shape[:2], np.uint8)
        mode, rect = cv2.GC_INIT_WITH_RECT, tuple(int(v) for v in box)
    else:
        gc, mode, rect = labels.copy(), cv2.GC_INIT_WITH_MASK, None
    try:
        cv2.grabCut(bgr, gc, rect, bgd, fgd, int(iterations), mode)
    except cv2.error:  # no background (or object) sample to learn a colour model from
        if box is not None:
            x, y, w, h = rect
            gc[y : y + h, x : x + w] = PR_FGD
    return (gc == FGD) | (gc == PR_FGD)


def largest_part(mask):
    """The largest 8-connected part of a mask, its holes kept (all False if the mask is empty)."""
    import cv2

    m = np.ascontiguousarray(mask, dtype=np.uint8)
    n, lab, stats, _ = cv2.connectedComponentsWithStats(m, connectivity=8)
    if n <= 1:
        return np.zeros(m.shape, bool)
    return lab == 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))


def fill_holes(mask):
    """A mask with every region its outer outlines enclose filled."""
    import cv2

    outlines, _ = cv2.findContours(np.ascontiguousarray(mask, dtype=np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_NONE)
    filled = np.zeros(mask.shape, np.uint8)
    cv2.drawContours(filled, outlines, -1, 1, thickness=-1)
    return filled.astype(bool)
