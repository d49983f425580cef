"""Sub-pixel tracing of an object's boundary: marching squares on its grey crop
(local mid-level, 3x3 pre-smoothing and its de-biasing) or on a binary mask
(staircase smoothed along the arc); and the objects of a segmented image
(:func:`trace_objects`: outer contours and holes, chosen by size) in the
:class:`Extraction` that :mod:`attneave.stimuli.extraction.outlines` returns
and re-exports.

Rings are ``(N, 2)`` arrays of ``(x, y)`` image pixels (y down, pixel centres
at integer coordinates), closed, first point not repeated.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction.scalespace import fourier_smooth
from attneave.stimuli.extraction.segment import NoObject
from attneave.stimuli.geometry.contour import Contour

__all__ = ["LOCAL_RADIUS", "PRESMOOTH_SHIFT", "ring_area", "trace_grey", "trace_mask", "finish_ring", "Extraction",
           "trace_objects"]


def _rings_from_find_contours(field, level, offset):
    from skimage.measure import find_contours

    rings = []
    for c in find_contours(field, level, fully_connected="high"):
        if len(c) < 4 or not np.array_equal(c[0], c[-1]):
            continue  # open pieces cannot occur on a padded crop; skip defensively
        xy = np.column_stack([c[:-1, 1] + offset[0], c[:-1, 0] + offset[1]])
        rings.append(xy)
    return rings


def ring_area(p):
    """Signed area of a ring (x, y), y down: positive when counter-clockwise on the screen."""
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


def trace_grey(field, level, obj, cls, n_filled, offset, presmooth, local_level, near_mask=False):
    """Rings of one object's boundary on its grey crop `field` (object above `level`).

    `obj` marks the crop's pixels that count as object (the object with its
    holes filled, or the object alone when holes are wanted), `cls` the
    pixels of the object class (any object); `offset` is the crop's (x, y).

    Returns (rings, presmoothed, local): the first of (local level, 3x3
    average), (global level, 3x3 average), (global level, raw) that keeps
    the object whole: its traced area within 2 % of its pixel count or,
    with `near_mask` (a mask from elsewhere, e.g. a photo's figure-ground,
    which may be a pixel off the field's edge), its outer ring within the
    pixels next to the mask's boundary (:func:`_near_mask`).
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
        whole = rings and (_near_mask(rings, obj, (offset[0] + pad, offset[1] + pad)) if near_mask
                           else _same_topology(rings, n_filled))
        if i == len(tries) - 1 or whole:
            return rings, smooth, local
    raise AssertionError("unreachable")  # pragma: no cover


def _same_topology(rings, n):
    """Whether pre-smoothing kept the object whole (did not cut a thin neck).

    `n` is the object's pixel count with its holes filled.
    """
    a = max(abs(ring_area(r)) for r in rings)
    # the traced area differs from the pixel count by well under a pixel per
    # boundary pixel; losing a part of the object costs far more
    return abs(a - n) <= 0.02 * n + 2.0


def _near_mask(rings, obj, origin):
    """Whether the rings (an outline and its holes) differ from the mask `obj` (a crop whose
    pixel (0, 0) is at `origin` (x, y)) only on pixels next to the mask's boundary: the outline
    moved within a pixel of the mask's own, and lost or gained no part."""
    import cv2

    shift = 4  # 1/16 px
    pts = [np.round((r - np.asarray(origin, float)) * (1 << shift)).astype(np.int32) for r in rings]
    raster = np.zeros(obj.shape, np.uint8)
    cv2.fillPoly(raster, pts, 1, lineType=cv2.LINE_8, shift=shift)  # even-odd: holes stay empty
    m = obj.view(np.uint8)
    k3 = np.ones((3, 3), np.uint8)
    band = cv2.dilate(m, k3) > cv2.erode(m, k3, borderType=cv2.BORDER_CONSTANT, borderValue=1)
    off = (raster.view(bool) != obj) & ~band
    return int(np.count_nonzero(off)) <= 2


def trace_mask(obj, offset):
    """Rings (staircase outlines) of a binary object, before smoothing."""
    e = np.pad(obj.astype(np.float64), 1)
    return _rings_from_find_contours(e, 0.5, (offset[0] - 1, offset[1] - 1))


#: Shift towards the centre of curvature, per unit curvature (px^2), of the
#: level line of an edge averaged over 3x3 pixels and traced by marching
#: squares: measured on exact-coverage discs of radius 20 to 400 px
#: (0.48 to 0.50).
PRESMOOTH_SHIFT = 0.49


def finish_ring(ring, name, mask_sigma, debias, shape):
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
    return fourier_smooth(q, min(sigma, c.perimeter / 16), c.perimeter)


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
        or the value given), class_medians (Otsu), frame_line (the width
        in px of a frame line drawn along the image's edge that was set
        aside, 0 for none; 'otsu', 'threshold', 'mask'), level (the global
        contour level, in image units), subpixel ('grey': traced on grey
        levels, or 'mask': a two-valued image), presmooth and local_level
        (per object, whether each refinement was used), objects, min_area,
        min_hole_area, holes, holes_dropped, mask_sigma, object_areas (pixel
        counts, holes filled), candidate_areas (the largest object and
        those of at least half its size: they compete), n_objects_found
        (separate objects in the image; islands inside holes are part of
        their object), shape, source; with ``method='auto'`` resolved (the
        method chosen); with the photo method mode, box (boxes), scale,
        iterations, agreement and competing (see
        :func:`attneave.stimuli.extraction.figure_ground.photo.segment_photo`).
    """

    contours: list
    holes: list
    mask: np.ndarray
    params: dict = field(default_factory=dict)

    @property
    def contour(self):
        """The first (largest) contour."""
        return self.contours[0]


def trace_objects(seg, name, objects, min_area, holes, min_hole_area, mask_sigma, presmooth, local_level):
    """The outlines (and holes) of the objects of a segmentation, as an :class:`Extraction`.

    `seg` is a :func:`~attneave.stimuli.extraction.segment.segment` result;
    the other arguments are :func:`attneave.stimuli.extraction.outlines.extract`'s,
    checked. Objects smaller than `min_area` px (holes: `min_hole_area`) are
    set aside; `objects` says which of the rest are kept.

    Raises
    ------
    NoObject
        No pixel, or every pixel, belongs to the object class.
    InputError
        A negative or non-finite `min_area`.
    """
    import cv2

    on, params, field_, level = seg.on, seg.params, seg.field, seg.level
    h, w = on.shape
    if min_area is None:
        min_area = max(9.0, 1e-4 * h * w)
    if not np.isfinite(min_area) or min_area < 0:
        raise InputError(f"min_area must be >= 0, got {min_area}")
    min_hole_area = float(min_area if min_hole_area is None else min_hole_area)
    n_on = int(np.count_nonzero(on))
    if n_on == 0:
        raise NoObject("no object: no pixel belongs to the object class")
    if n_on == on.size:
        raise NoObject("everything is object: no background pixel")

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
        # objects of half the largest's size or more are measured too: they compete (verdict)
        cand = [k for k in order if approx[k] >= 0.5 * approx[order[0]] - 4]
    else:
        cand = [k for k in order if approx[k] >= 0.5 * min_area - 4]
    sil = {k: silhouette(k) for k in cand}
    size = {k: int(np.count_nonzero(sil[k][1])) for k in cand}
    cand.sort(key=lambda k: -size[k])  # stable: ties keep the scan order
    chosen = [k for k in cand if size[k] >= min_area]
    if not chosen:
        biggest = max(size.values()) if size else int(max(approx))
        raise NoObject(f"no object of at least {min_area:g} px (largest has {biggest} px)")
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
            rings, smoothed_ok, was_local = trace_grey(
                field_(r0, r1, c0, c1), level, obj, on[r0:r1, c0:c1], n_filled, (c0, r0),
                presmooth, local_level, seg.near_mask,
            )
            presmoothed.append(smoothed_ok)
            localised.append(was_local)
        else:
            rings = trace_mask(obj, (c0, r0))
        if not rings:
            raise NoObject(f"object of {n_filled} px gave no closed contour")
        areas_r = np.array([ring_area(r) for r in rings])
        k_out = int(np.argmax(np.abs(areas_r)))
        outer_sign = np.sign(areas_r[k_out])
        hole_rings = [r for i, r in enumerate(rings) if i != k_out and np.sign(areas_r[i]) != outer_sign]
        debias = field_ is not None and presmoothed[-1]
        sigma_m = mask_sigma if field_ is None else 0.0
        contours.append(finish_ring(rings[k_out], name, sigma_m, debias, (h, w)))
        hl = []
        if holes:
            for r in hole_rings:
                if abs(ring_area(r)) < min_hole_area:
                    dropped += 1
                    continue
                hl.append(finish_ring(r, name, sigma_m, debias, (h, w)))
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
        candidate_areas=[size[k] for k in cand if size[k] >= min_area],
        shape=[int(h), int(w)],
        source=name,
    )
    return Extraction(contours, hole_lists, mask, params)
