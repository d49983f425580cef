"""An honest verdict on an extracted outline: ``ok``, ``suspect`` (with every
reason) or ``failed``.

Each measure below has a threshold in :data:`THRESHOLDS`; an outline is
``suspect`` when any measure crosses its threshold, and the reason names
the measure and its value:

``frame``
    Fraction of the outline's length that runs along the image's frame
    (within 1 px of the edge): an object cut by the frame, or a region of
    background merged into the object.
``fill``
    The object's area over the image's: almost none (a speck) or almost all
    of it (the background taken for the object).
``contrast``
    How well the colours just inside and just outside the outline differ,
    as ``|mean_in - mean_out| / sqrt((var_in + var_out) / 2)`` over 3-px
    bands in CIE Lab (a d'): an outline along no visible edge.
``competing``
    With ``objects='largest'``: the next object's area over the largest's;
    two objects of similar size make "the object" ambiguous.
``agreement``
    Photo methods: the IoU of the two hypotheses the method compared (see
    :mod:`stimuli.extraction.photo`); they disagree when the answer is
    unstable.
``decoder``
    The image decoder reported corrupt or truncated data.

A ``failed`` outline is one the extraction could not give at all (no
object, unreadable file); it is decided by the caller.

The thresholds were set on the development photos (horses and objects, each
group checked with thresholds chosen on the other) so that outlines marked
``ok`` have an IoU of at least 0.8 with the true object nine times in ten;
see ``benchmarks/validate_photos.py``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["THRESHOLDS", "Verdict", "judge", "frame_contact", "boundary_contrast"]

#: Thresholds of the verdict's measures (see the module notes).
THRESHOLDS = dict(frame=0.05, fill_min=0.002, fill_max=0.7, contrast=0.8, competing=0.5, agreement=0.95)


@dataclass
class Verdict:
    """The verdict on one image's outline(s).

    Attributes
    ----------
    status : {'ok', 'suspect'}
    reasons : list of str
        One per measure that crossed its threshold (empty when ok).
    measures : dict
        frame, fill, contrast, competing, agreement (None where it does not
        apply) and decoder (the decoder's messages).
    """

    status: str
    reasons: list = field(default_factory=list)
    measures: dict = field(default_factory=dict)

    @property
    def reason(self):
        """The reasons as one line."""
        return "; ".join(self.reasons)


def frame_contact(contour, shape):
    """Fraction of a closed contour's length within 1 px of the image's edge.

    Parameters
    ----------
    contour : Contour
        ``(x, y)`` image pixels (y down, pixel centres at integers; the
        image's edge is at -0.5 and ``width - 0.5``).
    shape : (H, W)

    Returns
    -------
    float in [0, 1]

    Examples
    --------
    >>> import numpy as np
    >>> from stimuli.geometry.contour import Contour
    >>> sq = Contour(np.array([[-0.5, -0.5], [9.5, -0.5], [9.5, 9.5], [-0.5, 9.5]]))
    >>> frame_contact(sq, (100, 100))  # two of its four sides lie on the frame
    0.5
    """
    h, w = shape[:2]
    p = contour.points
    near = (p[:, 0] <= 0.5) | (p[:, 0] >= w - 1.5) | (p[:, 1] <= 0.5) | (p[:, 1] >= h - 1.5)
    both = near & np.roll(near, -1)
    seg = contour.segment_lengths()
    total = float(seg.sum())
    return float(seg[both].sum() / total) if total > 0 else 0.0


def boundary_contrast(image, mask, band=3):
    """d' of the colours in bands just inside and just outside a mask's boundary.

    Parameters
    ----------
    image : ndarray
        Grey, RGB or RGBA (RGB order), any depth.
    mask : (H, W) bool ndarray
    band : int
        Band width in px.

    Returns
    -------
    float
        ``|mean_in - mean_out| / sqrt((var_in + var_out) / 2)`` in CIE Lab
        (the vector difference of the means over the total variances); 0
        when either band is empty.
    """
    import cv2

    from stimuli.extraction.grabcut import to_bgr8

    lab = cv2.cvtColor(to_bgr8(image), cv2.COLOR_BGR2Lab).astype(np.float32)
    m = np.ascontiguousarray(mask, dtype=np.uint8)
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * band + 1, 2 * band + 1))
    inner = m.astype(bool) & ~cv2.erode(m, k, borderType=cv2.BORDER_REPLICATE).astype(bool)
    outer = cv2.dilate(m, k).astype(bool) & ~m.astype(bool)
    if not inner.any() or not outer.any():
        return 0.0
    a, b = lab[inner], lab[outer]
    spread = np.sqrt(0.5 * (a.var(axis=0).sum() + b.var(axis=0).sum()))
    return float(np.linalg.norm(a.mean(axis=0) - b.mean(axis=0)) / max(spread, 1e-6))


def judge(image, extraction, decoder=(), thresholds=None):
    """The verdict on an extraction (see the module notes for the measures).

    Parameters
    ----------
    image : ndarray
        The image the outline was extracted from.
    extraction : stimuli.extraction.Extraction
    decoder : sequence of str
        The decoder's warnings (:attr:`stimuli.extraction.imageio.ImageFile.warnings`).
    thresholds : dict, optional
        Overrides of :data:`THRESHOLDS`.

    Returns
    -------
    Verdict
    """
    th = {**THRESHOLDS, **(thresholds or {})}
    c = extraction.contours[0]
    h, w = extraction.mask.shape
    p = extraction.params
    frame = max(frame_contact(k, (h, w)) for k in extraction.contours)
    fill = float(c.area / (h * w))
    contrast = boundary_contrast(image, extraction.mask)
    areas = p.get("candidate_areas") or []
    competing = areas[1] / areas[0] if p.get("objects") == "largest" and len(areas) > 1 and areas[0] else None
    agreement = p.get("agreement")
    reasons = []
    if frame > th["frame"]:
        reasons.append(f"touches the image frame over {100 * frame:.0f}% of its outline")
    if fill < th["fill_min"]:
        reasons.append(f"fills only {100 * fill:.2g}% of the image")
    elif fill > th["fill_max"]:
        reasons.append(f"fills {100 * fill:.0f}% of the image")
    if contrast < th["contrast"]:
        reasons.append(f"low contrast across the boundary (d'={contrast:.2f})")
    if competing is not None and competing >= th["competing"]:
        reasons.append(f"competing region of {100 * competing:.0f}% of the object's size")
    if agreement is not None and agreement < th["agreement"]:
        reasons.append(f"the method's hypotheses disagree (IoU {agreement:.2f})")
    if decoder:
        reasons.append("decoder: " + " | ".join(decoder))
    measures = dict(frame=frame, fill=fill, contrast=contrast, competing=competing, agreement=agreement,
                    decoder=list(decoder))
    return Verdict("suspect" if reasons else "ok", reasons, measures)
