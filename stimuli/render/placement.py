"""Placing points in an image: scale and centre them on the canvas."""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.render.rings import resolve_shape
from attneave.stimuli.validate import as_number, as_points

#: Smallest bounding-box extent (in the points' units) that is scaled to an
#: image: far below any unit a shape is drawn in, far above the subnormal
#: range where floating point loses digits and the scale overflows.
MIN_EXTENT = 1e-150
#: Smallest extent relative to the largest coordinate: below it the points
#: differ by round-off only (as :class:`stimuli.Contour` requires).
MIN_RELATIVE_EXTENT = 1e-10


def fit_to_image(points, size, margin=None, scale=None):
    """Scale and centre points into an image.

    The bounding box of the points is scaled by `scale` (default: as large
    as fits inside the image less `margin` on every side) and centred on the
    image centre ``((width - 1) / 2, (height - 1) / 2)``. The image spans
    ``[-0.5, width - 0.5] x [-0.5, height - 0.5]`` in pixel coordinates.

    Parameters
    ----------
    points : Contour or (N, 2) array
        ``(x, y)`` points (any units; y down as in images).
    size : int or (int, int)
        Image ``(width, height)``.
    margin : float, optional
        Free space in pixels between the bounding box and each image edge,
        used to choose the scale. Default: 10% of the smaller image side.
    scale : float, optional
        Fixed scale factor (pixels per input unit); the points are then only
        centred and `margin` is ignored.

    Returns
    -------
    dict
        ``points`` ((N, 2) array in image pixels), ``scale``, ``offset``
        ((2,) array, image = points * scale + offset), ``size``, ``margin``.

    Raises
    ------
    InputError
        Bad points, size, margin or scale, points whose bounding box is a
        single point, or a bounding box whose larger side is below
        :data:`MIN_EXTENT` units or below :data:`MIN_RELATIVE_EXTENT` of
        the largest coordinate (its points differ by round-off only), or a
        `scale` that takes the points beyond the float range.

    Examples
    --------
    >>> fit_to_image([(0, 0), (1, 0), (1, 1), (0, 1)], size=12, margin=1)["points"].tolist()
    [[0.5, 0.5], [10.5, 0.5], [10.5, 10.5], [0.5, 10.5]]
    """
    pts = as_points(points, "points")
    h, w = resolve_shape(size)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    extent = hi - lo
    if scale is None:
        if margin is None:
            margin = 0.1 * min(w, h)
        try:
            margin = as_number(margin, "margin")
        except InputError:
            raise InputError(f"margin: expected a number of pixels, got {margin!r}") from None
        if not 0 <= margin < 0.5 * min(w, h):
            raise InputError(f"margin: must be >= 0 and less than half the smaller image side, got {margin!r}")
        if not np.any(extent > 0):
            raise InputError("points: all points coincide; cannot scale them to the image")
        span, far = float(extent.max()), float(np.abs(pts).max())
        if span < MIN_EXTENT or span < MIN_RELATIVE_EXTENT * far:
            raise InputError(
                f"points: the bounding box spans only {span:.3g} units (at coordinates up to {far:.3g}); "
                f"it must span at least {MIN_EXTENT:g} units and {MIN_RELATIVE_EXTENT:g} of the largest "
                "coordinate to be scaled to the image: rescale the points"
            )
        room = np.array([w, h], float) - 2.0 * margin
        with np.errstate(divide="ignore"):
            scale = float(np.min(np.where(extent > 0, room / np.where(extent > 0, extent, 1.0), np.inf)))
    else:
        scale = as_number(scale, "scale", gt=0)
    centre = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
    with np.errstate(over="ignore", invalid="ignore"):
        offset = centre - scale * (lo / 2.0 + hi / 2.0)
        out = pts * scale + offset
    if not (np.isfinite(out).all() and np.isfinite(offset).all()):
        raise InputError(f"scale: {scale:g} takes the points beyond the float range; use a smaller scale")
    return {
        "points": out,
        "scale": scale,
        "offset": offset,
        "size": (w, h),
        "margin": None if margin is None else float(margin),
    }
