"""Figure-ground for photographs: automatic, box- and scribble-assisted.

The object is found by GrabCut [1]_ on an edge-preserving (bilateral)
smoothing of the photo, which flattens texture that would otherwise split
GrabCut's colour models, at most :data:`WORK_PIXELS` pixels in the
automatic search and :data:`ASSISTED_WORK_PIXELS` with a box or scribbles
(larger photos are reduced and the mask brought back to full size):

* automatic (no box, no scribbles): GrabCut from the photo inset by 5 %
  (:func:`~attneave.stimuli.extraction.figure_ground.grabcut.inset_box`) from six starts: box
  mode's four (:mod:`attneave.stimuli.extraction.figure_ground.boxcut`), CIE Lab on the
  smoothed photo (:data:`AUTO_FIRST`) and CIE Lab from the frame's central
  ellipse of :data:`AUTO_CORE` (0.4) of its size ('lab_centre'); the
  hypothesis whose outline's colours part best (colour error alone: the
  object need not reach the inset frame) is the answer, its agreement
  (IoU) with the next best a measure of how sure it is (it feeds the
  verdict). The small central start is for an object that fills a small
  part of the photo (a bus, a monitor, a person: 5-11 % of it): every other
  start begins with an object model that is mostly background, and GrabCut
  then keeps a large part of the background or loses the object, while the
  colour error may prefer a small patch of distinct colour. That is why
  the five starts generalised on horses and not on objects: their median
  IoU on the development objects, 0.701, stood on four photos of single
  objects from the GrabCut database (20-54 % of the photo, IoU 0.90-0.99),
  three of them in half A (0.802 there, 0.420 on half B), while objects
  not seen gave 0.517.
  The start and its size were chosen by cross-validation
  (``benchmarks/cv_auto.py``: rules chosen on one half of the development
  photos, measured on the other; mask IoU): the five starts with one Lab
  ellipse of 0.2-0.6 added, or an ellipse alone, chosen on half A gave on
  half B medians 0.757 horses and 0.710 objects (the ellipse of 0.4), chosen
  on B gave on A 0.778 and 0.700 (0.3); on all photos 0.4 scores best
  (0.779 / 0.718). ``validate_photos.py`` (traced outlines): horses 0.780
  (halves 0.788 / 0.759; the five starts 0.764, 0.772 / 0.758), objects
  0.722 (0.802 / 0.711; before 0.701, 0.802 / 0.422); mean IoU horses
  0.722 -> 0.721, objects 0.616 -> 0.683; 13 photos up and 6 down by more
  than 0.01; one GrabCut more per photo. Fewer starts were tried too
  (``cv_auto.py --subsets``, every subset of the five with or without one
  ellipse): chosen on A, box mode's Lab start with the band and the
  ellipse of 0.4, two GrabCuts instead of six, gave on B 0.763 and 0.671
  (chosen on B, three starts gave 0.778 / 0.700 on A), but on all objects
  a mean of 0.631 against 0.684 (share under 0.5 0.29 against 0.24): not
  taken, as objects are where the automatic search fails. Other starts were tried
  in the ellipse's place (an earlier version of ``cv_auto.py``; median IoU
  of the start alone on all photos, horses / objects): Otsu on the
  spectral-residual saliency as probable object (Lab, RGB) 0.11 / 0.36,
  on the distance to the frame's colours (8 k-means centres) 0.75 / 0.42,
  the inset frame as probable background only 0.67 / 0.62, the 0.7
  ellipse on the smoothed photo 0.75 / 0.54, the 0.4 ellipse in RGB 0.74 /
  0.66 (the Lab ellipse of 0.4: 0.75 / 0.70); added to the five, none kept
  both objects' halves as high (half B 0.42-0.65 against 0.71). Before
  these, starting GrabCut from the geodesic distance to the photo's frame
  through the colour gradient (the background prior of Wei et al. 2012,
  Otsu on it as probable object) gave 0.500 / 0.434 on objects and 0.726 /
  0.739 on horses (mask level): not kept;
* a box ``(x, y, width, height)``: outside is background; GrabCut runs
  from four starts (:mod:`attneave.stimuli.extraction.figure_ground.boxcut`: CIE Lab with a band
  of :data:`~attneave.stimuli.extraction.figure_ground.boxcut.BOX_BAND` of the box's size along
  its inside held as probable background; plain GrabCut on the RGB photo;
  Lab and RGB from the box's central ellipse, which keeps the background
  between a horse's legs out of the first object model) and the
  hypothesis whose outline's colours part best (colour error) without
  falling short of a side of the box is the answer; its agreement is the
  IoU with the next best. On the development photos
  (``benchmarks/validate_photos.py``, one box per photo: the mask's box
  plus 5 %) the median IoU is 0.792 for horses (halves A / B 0.793 /
  0.791; plain GrabCut from the same box 0.721, halves 0.758 / 0.709;
  the previous single Lab-band answer 0.736, halves 0.769 / 0.689) and
  0.773 for objects (mean 0.802; halves 0.821 / 0.768; plain GrabCut
  0.764, mean 0.764, halves 0.797 / 0.761; the previous answer 0.812,
  halves 0.877 / 0.791): the choice helps horses on both halves and is
  level or worse on the objects' medians (B: two of its eight photos).
  GrabCut's random start (its colour models begin by k-means) moves these
  figures: with seeds 0-4 (``benchmarks/grabcut_seeds.py``, attneave's
  and the anchor's alike) box mode's medians range 0.778-0.792 (horses)
  and 0.766-0.776 (objects), plain GrabCut's 0.682-0.721 and 0.761-0.774,
  box mode above it at every seed in both groups; the automatic search's
  0.759-0.764 and 0.687-0.710. (The anchor's figures before it was seeded,
  0.701 / 0.761 and 0.721 / 0.798 in two runs, depended on what had run
  before it in the process.)
  The targets (0.80 horses, 0.88 objects) are not met. Tried and dropped: guided-filter and SLIC
  superpixel snapping of the mask and 10 GrabCut iterations (51 photos:
  median level or lower), more starts (cores of 0.6 and 0.8, GrabCut on
  a copy reduced to 0.7x, Lab from the plain box: the choice no better;
  RGB with the band: one objects photo better, level elsewhere), GrabCut on a copy
  enlarged 1.5-2x (13 horses: gains and losses of up to 0.4 IoU photo by
  photo, mean level). A second round (all 95 photos; median IoU per half
  horses A / B, objects A / B, against 0.794 / 0.790, 0.877 / 0.766; none
  kept): every start on the photo enlarged 2x (INTER_CUBIC) when under
  100 kpx, mask brought back by area averaging: 0.819 / 0.782, objects
  unchanged (27 horses better, 27 worse; 4-5x the time); a second GrabCut (Lab, sure
  object inside the answer eroded by 3 % of the box, probable on a band of
  that width, fresh colour models): 0.801 / 0.797, 0.878 / 0.765, but 10
  horses worse against 3 better; consensus of the starts (3 of those with a
  boundary): 0.775 / 0.741, 0.863 / 0.786 (the chosen start beats the vote;
  GrabCut from the vote, sure where all agree, was lower still on a
  mask-level screen); a fifth start on the first three principal components
  of Lab and the local spread of L at 1.5 and 4 px: 0.810 / 0.790, 0.816 /
  0.766 (it mends a few gross failures on horses, but moves three objects
  off their boundary); the first and the last together: 0.819 / 0.801,
  0.816 / 0.766. No gain was significant photo by photo (Wilcoxon p >= 0.35 on
  horses; the second GrabCut's loss p = 0.05). A third round (mask level,
  photos reduced to 250 kpx; none kept): a graph cut of GrabCut's energy
  with a star-shape constraint (Veksler 2008, centred on the chosen mask's
  deepest point; ``scipy.sparse.csgraph.maximum_flow``) started from the
  chosen mask raised objects to 0.800 but dropped horses to 0.698 (a leg is
  not star-shaped from the body's centre on a pixel grid); the same cut
  without the constraint 0.771 / 0.779; OneCut (Tang et al. 2013: the L1
  overlap of colour histograms, 16-64 bins per channel, with ballooning
  inside the box) 0.68 at best on objects; adding edge support, boundary
  gradient or contact with the box's sides to the score, or preferring one
  start unless another scores clearly lower, moved no half's median by more
  than 0.016 and raised none on both; tightness pinpointing (after
  Lempitsky et al. 2009: where the mask falls short of a side of the box
  shrunk by BOX_BAND, the most object-like pixel on that side held as sure
  object and GrabCut run again) changed 16 of 45 photos, 7 up and 9 down;
  every start on a bilateral- or Gaussian-smoothed copy, or a pixel vote
  of each start over the raw, smoothed and 0.8x copies, swung the horse
  halves' medians by +0.03 / -0.05 and lowered the horses' mean (thin legs
  are lost to smoothing); a fifth and sixth start from the geodesic
  distance to the box's sides through the colour gradient (Wei et al.
  2012's background prior, Otsu on it as probable object; in Lab and RGB),
  or from OpenCV's fine-grained saliency, raised the horses' median
  (0.798 -> 0.801 / 0.808, holes counted) and lowered the objects'
  (0.771 -> 0.761 / 0.763; means 0.802 -> 0.777 / 0.771), as the texture
  start did; each start's stability (IoU with itself on a copy smoothed at
  0.8 px or reduced to 0.8x) tracks IoU across photos (r = 0.68 and 0.58)
  but, added to the score, chose no better within a photo (no half's
  median up, horses' down by up to 0.06); GrabCut on a crop around the box
  (the box widened by 0.25, 0.5 or 1 times its size, so that the background
  model is learnt near the object) was level (medians within 0.009); the
  automatic search's own start (Lab on the smoothed photo) as a fifth
  hypothesis moved horses' half A 0.793 -> 0.807 and left the other three
  halves within 0.001 (objects' median of 17 photos 0.773 -> 0.821 by
  its middle photo alone; 9 horses up, 4 down, two by 0.16-0.22; means
  level; Wilcoxon p = 0.61): not kept. The
  best of all these hypotheses per
  photo, chosen with the truth, reaches a median of 0.817 on objects and the
  best of the four starts 0.81 on horses: the targets lie beyond GrabCut's
  colour models on these photos, not in the choice among them. A learned
  salient-object network (method ``model``, the user's file) reaches them:
  with an IS-Net network and the same boxes, 0.891 horses and 0.934
  objects (:mod:`attneave.stimuli.extraction.figure_ground.model`).
  Box and scribble modes reduce a photo only above
  :data:`ASSISTED_WORK_PIXELS` (0.5 Mpx; the automatic search keeps
  :data:`WORK_PIXELS`): GrabCut at full size, as the anchor runs it, on the
  eight objects photos of 0.27-0.49 Mpx raised five (one cross 0.305 ->
  0.735) and lowered two (a start other than the best won on one, 0.884 ->
  0.820), objects mean IoU 0.780 -> 0.803, median 0.771 (halves 0.820 /
  0.766), share under 0.5 from 0.12 to 0.06; horses unchanged (one photo
  is that large).
  When every hypothesis finds (nearly) nothing or the whole box, GrabCut
  runs again with the box's central fifth held as object (a person
  centres the box on the object); the mask never leaves the box;
* scribbles: a label image of the photo's size (see :func:`read_scribbles`)
  whose object strokes are sure object and background strokes sure
  background; with a box they refine it, alone the object is sought near
  the object strokes.

The largest object is kept with its holes (the outline is traced around
them; ``extract(..., holes=True)`` traces them too). Points and boxes are in
image pixels (x = column, y = row, y down).

References
----------
.. [1] Rother, C., Kolmogorov, V., & Blake, A. (2004). "GrabCut":
       interactive foreground extraction using iterated graph cuts.
       ACM Trans. Graphics 23(3), 309-314.
.. [2] Tomasi, C., & Manduchi, R. (1998). Bilateral filtering for gray and
       color images. ICCV, 839-846.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction.figure_ground.boxcut import BOX_BAND, box_hypotheses, choose_hypothesis
from attneave.stimuli.extraction.figure_ground.grabcut import (
    BGD,
    FGD,
    PR_BGD,
    PR_FGD,
    box_labels,
    check_box,
    fill_holes,
    grabcut,
    inset_box,
    largest_part,
    to_bgr8,
)

__all__ = ["WORK_PIXELS", "ASSISTED_WORK_PIXELS", "AUTO_FIRST", "AUTO_CORE", "BOX_BAND", "SCRIBBLE_OBJECT",
           "SCRIBBLE_BACKGROUND", "PhotoMask", "segment_photo", "read_scribbles", "mask_iou", "box_around"]

#: The automatic search runs on at most this many pixels (larger photos are reduced).
WORK_PIXELS = 250_000
#: Box and scribble modes run on at most this many pixels: a person's box or strokes are drawn
#: on the full photo, and reducing the 0.27-0.49 Mpx development photos to WORK_PIXELS lowered
#: five of eight of them (see the module notes); 1 Mpx took 45 s per box on an 8 Mpx photo.
ASSISTED_WORK_PIXELS = 500_000
#: The automatic search's own hypothesis (GrabCut in CIE Lab on the smoothed photo from the inset
#: frame), taken when no hypothesis found a boundary.
AUTO_FIRST = "lab_smooth"
#: The automatic search's start for an object that fills a small part of the photo
#: ('lab_centre'): GrabCut in CIE Lab from the central ellipse of this fraction of the inset
#: frame's width and height (chosen by cross-validation, ``benchmarks/cv_auto.py``).
AUTO_CORE = 0.4
#: Scribble colours (RGB): object strokes pure red, background strokes pure blue.
SCRIBBLE_OBJECT = (255, 0, 0)
SCRIBBLE_BACKGROUND = (0, 0, 255)


@dataclass
class PhotoMask:
    """An object mask found in a photo, with how sure the method is.

    Attributes
    ----------
    mask : (H, W) bool ndarray
        The object (largest part, its holes kept), at the photo's size.
    agreement : float
        IoU of the two hypotheses the method compared (1 = identical).
    params : dict
        mode ('auto', 'box', 'scribbles', 'box+scribbles'), box, scale
        (of the working copy), iterations, agreement, competing (auto:
        the second-largest part GrabCut found over the largest).
    """

    mask: np.ndarray
    agreement: float
    params: dict = field(default_factory=dict)


def mask_iou(a, b):
    """Intersection over union of two boolean masks (1 when both are empty)."""
    union = np.count_nonzero(a | b)
    return 1.0 if union == 0 else np.count_nonzero(a & b) / union


def segment_photo(image, box=None, scribbles=None, iterations=5, name="image"):
    """Find the object in a photo (see the module notes).

    Parameters
    ----------
    image : ndarray
        Grey, RGB or RGBA (RGB order), any depth.
    box : (x, y, width, height), optional
        Image pixels; the object lies inside.
    scribbles : (H, W) uint8 ndarray, optional
        0 unmarked, 1 object, 2 background (as :func:`read_scribbles` gives).
    iterations : int
        GrabCut iterations per hypothesis (default 5).
    name : str
        Names the image in messages.

    Returns
    -------
    PhotoMask

    Raises
    ------
    InputError
        A box outside the image, scribbles of another size or with no
        object stroke (when there is no box).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> img = rng.normal(60, 8, (80, 100, 3))
    >>> img[20:60, 30:75] = rng.normal((200, 40, 40), 8, (40, 45, 3))
    >>> res = segment_photo(np.clip(img, 0, 255).astype(np.uint8))
    >>> int(res.mask.sum()), res.params["mode"]
    (1800, 'auto')
    """
    import cv2

    bgr = to_bgr8(image)
    h, w = bgr.shape[:2]
    if box is not None:
        box = check_box(box, bgr.shape, name, "box")
    if scribbles is not None:
        scribbles = np.asarray(scribbles)
        if scribbles.shape != (h, w):
            raise InputError(f"{name}: scribbles of {scribbles.shape[1]}x{scribbles.shape[0]} pixels for a "
                             f"{w}x{h} image; expected the same size")
        if box is None and not np.any(scribbles == 1):
            raise InputError(f"{name}: the scribbles hold no object stroke (pure red) and there is no box")
    limit = WORK_PIXELS if box is None and scribbles is None else ASSISTED_WORK_PIXELS
    scale = min(1.0, float(np.sqrt(limit / (h * w))))
    small = bgr if scale == 1.0 else cv2.resize(bgr, (max(2, round(w * scale)), max(2, round(h * scale))),
                                                interpolation=cv2.INTER_AREA)
    sh, sw = small.shape[:2]
    sx, sy = sw / w, sh / h
    smooth = cv2.bilateralFilter(small, 7, 40, 5)

    def shrink(b):
        # a box that leaves some background at full size leaves some on the
        # working copy too (rounding outwards could cover it all, and GrabCut
        # then has no background to learn from)
        x, y, bw, bh = b
        x0, y0 = int(np.floor(x * sx)), int(np.floor(y * sy))
        x1, y1 = min(sw, int(np.ceil((x + bw) * sx))), min(sh, int(np.ceil((y + bh) * sy)))
        x0, y0 = max(x0, int(x > 0)), max(y0, int(y > 0))
        x1, y1 = min(x1, sw - int(x + bw < w)), min(y1, sh - int(y + bh < h))
        return (x0, y0, max(2, x1 - x0), max(2, y1 - y0))

    sbox = None if box is None else shrink(box)
    # `answer` is the mask; `check`, another hypothesis, measures how sure it is
    competing = None
    if scribbles is not None:
        marks = scribbles if scale == 1.0 else cv2.resize(scribbles, (sw, sh), interpolation=cv2.INTER_NEAREST)
        labels = _scribble_labels(marks, sbox)
        check = largest_part(grabcut(smooth, labels=labels, iterations=iterations))
        answer = largest_part(grabcut(small, labels=labels, iterations=iterations))
        mode = "scribbles" if box is None else "box+scribbles"
    elif sbox is not None:
        # several GrabCut hypotheses; the one whose outline separates colours
        # best and reaches the box's sides is the answer (see boxcut)
        masks = box_hypotheses(small, sbox, iterations)
        chosen, scores = choose_hypothesis(small[:, :, ::-1], sbox, masks)
        if chosen is None:
            # every hypothesis took (nearly) nothing or the whole box: a person's box
            # is centred on the object, so its core is held as object
            answer = check = largest_part(grabcut(smooth, labels=_core_labels(smooth.shape, sbox),
                                                  iterations=iterations))
        else:
            answer, check = masks[chosen], _next_best(masks, scores, chosen)
        mode = "box"
    else:
        # box mode's starts from the inset frame, GrabCut in CIE Lab on the
        # smoothed photo, and in Lab from a small central ellipse (an object
        # that fills a small part of the photo: the other starts' first object
        # model is then mostly background); the hypothesis whose outline's
        # colours part best is the answer (the frame is no box a person drew:
        # no gap penalty)
        inset = inset_box(smooth.shape)
        smooth_lab = cv2.cvtColor(smooth, cv2.COLOR_BGR2LAB)
        extra = {AUTO_FIRST: (smooth_lab, "box"),
                 "lab_centre": (cv2.cvtColor(small, cv2.COLOR_BGR2LAB), "core", AUTO_CORE)}
        raws = box_hypotheses(small, inset, iterations, extra=extra, parts="all")
        masks = {k: largest_part(r) for k, r in raws.items()}
        chosen, scores = choose_hypothesis(small[:, :, ::-1], inset, masks, gap=False)
        chosen = chosen or AUTO_FIRST
        answer, check = masks[chosen], _next_best(masks, scores, chosen)
        competing = _runner_up(raws[chosen])
        mode = "auto"
    # the two hypotheses' outlines, holes aside, are compared (the verdict's threshold is set on that)
    agreement = mask_iou(fill_holes(answer), fill_holes(check))
    mask = answer
    if scale != 1.0:
        mask = cv2.resize(mask.astype(np.float32), (w, h), interpolation=cv2.INTER_LINEAR) > 0.5
    if box is not None:
        # outside the box is background by definition (upsampling may spill over)
        x, y, bw, bh = box
        inside = np.zeros((h, w), bool)
        inside[y : y + bh, x : x + bw] = True
        mask &= inside
    params = dict(mode=mode, box=None if box is None else list(box), scale=scale, iterations=int(iterations),
                  agreement=float(agreement), competing=competing)
    if mode in ("box", "auto"):
        params.update(hypothesis=chosen, scores=scores)
    return PhotoMask(mask, float(agreement), params)


def _next_best(masks, scores, chosen):
    """The mask of the best-scoring hypothesis after `chosen` (`chosen`'s own when no other found a boundary)."""
    rest = sorted((v, k) for k, v in scores.items() if k != chosen and np.isfinite(v))
    return masks[rest[0][1] if rest else chosen]


def _core_labels(shape, box, core=0.2):
    """GrabCut labels: background outside `box`, probably object inside, sure object on an ellipse
    of `core` times the box's size at its centre."""
    import cv2

    labels = box_labels(shape, box)
    x, y, bw, bh = box
    centre = (int(round(x + bw / 2)), int(round(y + bh / 2)))
    axes = (max(1, int(core * bw / 2)), max(1, int(core * bh / 2)))
    cv2.ellipse(labels, centre, axes, 0, 0, 360, FGD, thickness=-1)
    return labels


def _runner_up(mask):
    """The second-largest 8-connected part's area over the largest's (0 if there is one part)."""
    import cv2

    n, _, stats, _ = cv2.connectedComponentsWithStats(np.ascontiguousarray(mask, dtype=np.uint8), connectivity=8)
    areas = np.sort(stats[1:, cv2.CC_STAT_AREA])[::-1]
    return float(areas[1] / areas[0]) if len(areas) > 1 else 0.0


def box_around(mask, margin=0.05):
    """The box ``(x, y, width, height)`` of a mask's pixels, widened by `margin` of its size on every
    side (as a person would draw it) and kept 1 px inside the image (GrabCut needs some outside)."""
    ys, xs = np.nonzero(mask)
    h, w = mask.shape
    x0, x1, y0, y1 = xs.min(), xs.max() + 1, ys.min(), ys.max() + 1
    mx, my = margin * (x1 - x0), margin * (y1 - y0)
    x0, y0 = max(1, int(round(x0 - mx))), max(1, int(round(y0 - my)))
    x1, y1 = min(w - 1, int(round(x1 + mx))), min(h - 1, int(round(y1 + my)))
    return (x0, y0, max(2, x1 - x0), max(2, y1 - y0))


def _scribble_labels(marks, box):
    """GrabCut labels from scribbles (1 object, 2 background) and an optional box."""
    import cv2

    h, w = marks.shape
    if box is not None:
        labels = box_labels((h, w), box)
    else:
        # without a box: probably object within the hull of the object strokes
        labels = np.full((h, w), PR_BGD, np.uint8)
        pts = np.column_stack(np.nonzero(marks == 1)[::-1]).astype(np.int32)
        cv2.fillConvexPoly(labels, cv2.convexHull(pts), PR_FGD)
    labels[marks == 1] = FGD
    labels[marks == 2] = BGD
    return labels


def read_scribbles(path, shape=None):
    """Read a scribble image: object strokes pure red, background strokes pure blue.

    Parameters
    ----------
    path : str or Path
        A PNG (RGB or RGBA) of the photo's size. Pixels near pure red
        ``(255, 0, 0)`` are object, near pure blue ``(0, 0, 255)``
        background (each channel within 60 of the pure value); every other
        pixel, and every transparent one, is unmarked.
    shape : (H, W), optional
        The photo's size; a scribble image of another size is refused.

    Returns
    -------
    (H, W) uint8 ndarray
        0 unmarked, 1 object, 2 background.

    Raises
    ------
    InputError
        Unreadable, not colour, of the wrong size, or with no stroke at all.
    """
    from attneave.stimuli.extraction.imageio import full_scale, read_image

    img = read_image(path)
    if img.ndim != 3 or img.shape[2] not in (3, 4):
        raise InputError(f"{path}: scribbles must be an RGB or RGBA image (object strokes red, background blue)")
    if shape is not None and img.shape[:2] != tuple(shape[:2]):
        raise InputError(f"{path}: scribbles of {img.shape[1]}x{img.shape[0]} pixels, expected the photo's size "
                         f"{shape[1]}x{shape[0]}")
    f = img[:, :, :3].astype(np.float64) * (255.0 / full_scale(img.dtype))
    opaque = img[:, :, 3] > 0 if img.shape[2] == 4 else np.ones(img.shape[:2], bool)

    def near(rgb):
        return opaque & np.all(np.abs(f - np.array(rgb)) <= 60, axis=2)

    out = np.zeros(img.shape[:2], np.uint8)
    out[near(SCRIBBLE_OBJECT)] = 1
    out[near(SCRIBBLE_BACKGROUND)] = 2
    if not out.any():
        raise InputError(f"{path}: no scribble found (object strokes pure red, background strokes pure blue)")
    return out
