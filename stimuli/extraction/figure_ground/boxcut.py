"""Box-assisted figure-ground: several GrabCut hypotheses from one box, and
the choice among them by a score that needs no ground truth.

GrabCut [1]_ from a box is unstable on photos where the object fills only
part of its box (a horse: legs apart, background between them and under
its belly): which background it keeps depends on the colour space and on
how its colour models start. So box mode runs GrabCut from
:data:`HYPOTHESES` (CIE Lab or RGB; started from the whole box as object,
from the box with its inner band held as probable background, or from the
box's central ellipse, :func:`~attneave.stimuli.extraction.figure_ground.grabcut.core_labels`)
and keeps the hypothesis of the lowest :func:`hypothesis_score`: the
colour error of its outline (:func:`~attneave.stimuli.extraction.quality.colour_error`:
how much the colours just inside and just outside overlap) plus a penalty
for falling short of a side of the box by more than :data:`GAP_FREE` of the
box's size (a person draws the box close around the object, so an outline
that stops well short of a side has lost a part: legs, a tail). A
hypothesis that found no boundary (nothing, or nearly the whole box) is
never chosen.

On the development photos (``benchmarks/validate_photos.py``, halves A and
B of each group; the weights chosen on a grid, each half checked): see the
module notes of :mod:`attneave.stimuli.extraction.figure_ground.photo` for the figures.

Boxes are ``(x, y, width, height)`` in image pixels (x = column, y = row,
y down).

References
----------
.. [1] Rother, C., Kolmogorov, V., & Blake, A. (2004). "GrabCut":
       interactive foreground extraction using iterated graph cuts.
       ACM Trans. Graphics 23(3), 309-314.
"""

from __future__ import annotations

import os

import numpy as np

from attneave.stimuli.extraction.figure_ground.grabcut import box_labels, core_labels, fill_holes, grabcut, largest_part

__all__ = ["BOX_BAND", "CORE", "GAP_FREE", "GAP_WEIGHT", "HYPOTHESES", "box_hypotheses", "hypothesis_score",
           "choose_hypothesis"]

#: The fraction of the box's size along each of its sides held as probable background by the
#: 'band' start (a box drawn with a 5 % margin around the object leaves 0.05 / 1.1 of its size
#: empty on each side).
BOX_BAND = 0.045
#: The 'core' start: the central ellipse's axes as a fraction of the box's.
CORE = 0.7
#: A hypothesis may fall short of a side of the box by this fraction of the box's size unpenalised.
GAP_FREE = 0.12
#: Weight of the shortfall beyond GAP_FREE against the colour error (both fractions).
GAP_WEIGHT = 0.5
#: The hypotheses (name: colour space, start). 'box': the whole box probable object; 'band': the
#: box's inner BOX_BAND probable background; 'core': only the central ellipse probable object.
HYPOTHESES = {"lab_band": ("lab", "band"), "rgb_box": ("rgb", "box"), "lab_core": ("lab", "core"),
              "rgb_core": ("rgb", "core")}


def box_hypotheses(bgr, box, iterations=5, extra=None, parts="largest"):
    """The object as each of :data:`HYPOTHESES` finds it.

    Parameters
    ----------
    bgr : (H, W, 3) uint8 ndarray
        The photo in BGR order (as :func:`~attneave.stimuli.extraction.figure_ground.grabcut.to_bgr8` gives).
    box : (x, y, width, height)
        Image pixels, inside the image.
    iterations : int
        GrabCut iterations per hypothesis.
    extra : dict, optional
        More hypotheses, name -> (image, start) or (image, 'core', size): a
        3-channel 8-bit image of the photo's size (another colour space or a
        smoothed copy) and a start ``'box'``, ``'band'`` or ``'core'`` (the
        central ellipse of `size` times the box's size; default :data:`CORE`).
    parts : {'largest', 'all'}
        Keep each mask's largest part (its holes kept), or every part
        GrabCut found.

    Returns
    -------
    dict
        Hypothesis name -> (H, W) bool mask.
    """
    from concurrent.futures import ThreadPoolExecutor

    import cv2

    images = {"rgb": bgr, "lab": cv2.cvtColor(bgr, cv2.COLOR_BGR2LAB)}
    starts = {name: (images[space], start, CORE) for name, (space, start) in HYPOTHESES.items()}
    starts.update({name: (*how, CORE)[:3] for name, how in (extra or {}).items()})

    def run(img, start, core):
        if start == "box":
            raw = grabcut(img, box=box, iterations=iterations)
        else:
            labels = box_labels(img.shape, box, BOX_BAND) if start == "band" else core_labels(img.shape, box, core)
            raw = grabcut(img, labels=labels, iterations=iterations)
        return largest_part(raw) if parts == "largest" else raw

    # OpenCV releases the GIL and seeds each thread's generator in grabcut(),
    # so the starts run side by side and give what they give one by one
    with ThreadPoolExecutor(min(len(starts), os.cpu_count() or 1)) as pool:
        futures = {name: pool.submit(run, *how) for name, how in starts.items()}
        return {name: f.result() for name, f in futures.items()}


def hypothesis_score(image, mask, box, gap=True):
    """How doubtful a box-mode mask is: lower is better, inf when it found no boundary.

    Parameters
    ----------
    image : ndarray
        The photo (grey, RGB or RGBA in RGB order).
    mask : (H, W) bool ndarray
        Its holes are filled before it is measured.
    box : (x, y, width, height)
    gap : bool
        Penalise falling short of the box's sides (a box a person drew
        around the object); False for the automatic search's inset frame,
        which the object need not reach.

    Returns
    -------
    float
        ``colour_error + GAP_WEIGHT * max(0, box_gap - GAP_FREE)`` (the
        second term with `gap` only)
        (:func:`~attneave.stimuli.extraction.quality.colour_error`,
        :func:`~attneave.stimuli.extraction.quality.box_gap`); inf for a mask that
        is empty, covers less than 3 % or more than 97 % of the box, or has
        no colour error (no core or ring).

    Examples
    --------
    >>> import numpy as np
    >>> truth = np.zeros((80, 80), bool); truth[20:60, 20:60] = True
    >>> img = np.where(truth, 230, 30).astype(np.uint8)  # a light square on a dark ground
    >>> float(hypothesis_score(img, truth, (18, 18, 44, 44)))
    0.0
    >>> # a box reaching 20 px further down: the outline falls 22 px (of 64) short of its bottom
    >>> round(float(hypothesis_score(img, truth, (18, 18, 44, 64))), 4)  # 0.5 * (22 / 64 - 0.12)
    0.1119
    >>> hypothesis_score(img, np.zeros((80, 80), bool), (18, 18, 44, 44))
    inf
    """
    from attneave.stimuli.extraction.quality import box_gap, colour_error
    from attneave.stimuli.geometry.contour import Contour

    x, y, bw, bh = box
    mask = fill_holes(mask)
    fill = np.count_nonzero(mask) / (bw * bh)
    if not 0.03 <= fill <= 0.97:
        return float("inf")
    err = colour_error(image, mask)
    if not np.isfinite(err):
        return float("inf")
    if not gap:
        return float(err)
    # the mask's extent as the outline of its outer pixels (edges half a pixel beyond their centres)
    ys, xs = np.nonzero(mask)
    x0, x1, y0, y1 = xs.min() - 0.5, xs.max() + 0.5, ys.min() - 0.5, ys.max() + 0.5
    extent = Contour(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))
    return float(err + GAP_WEIGHT * max(0.0, box_gap(extent, box) - GAP_FREE))


def choose_hypothesis(image, box, masks, gap=True):
    """The hypothesis of the lowest :func:`hypothesis_score`, with every score.

    Parameters
    ----------
    image : ndarray
        The photo (RGB order).
    box : (x, y, width, height)
    masks : dict
        Name -> mask, as :func:`box_hypotheses` gives.
    gap : bool
        As for :func:`hypothesis_score`.

    Returns
    -------
    name : str or None
        None when no hypothesis found a boundary (every score inf).
    scores : dict
        Name -> score (rounded to 4 decimals; inf where none).
    """
    scores = {k: hypothesis_score(image, m, box, gap) for k, m in masks.items()}
    best = min(scores, key=scores.get)
    return (best if np.isfinite(scores[best]) else None), {k: round(v, 4) for k, v in scores.items()}
