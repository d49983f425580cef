"""Placing points in an image: scale and centre them on the canvas."""

from __future__ import annotations

import math

import numpy as np

from stimuli.errors import InputError
from stimuli.validate import as_number, as_points
from stimuli.render.rings import resolve_shape

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
        Bad points, size or margin, or points whose bounding box is a single
        point.

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
            margin = float(margin)
        except (TypeError, ValueError):
            raise InputError(f"margin: expected a number of pixels, got {margin!r}") from None
        if not (math.isfinite(margin) and 0 <= margin < 0.5 * min(w, h)):
            raise InputError(f"margin: must be >= 0 and less than half the smaller image side, got {margin!r}")
        if not np.any(extent > 0):
            raise InputError("points: all points coincide; cannot scale them to the image")
        room = np.array([w, h], float) - 2.0 * margin
        with np.errstate(divide="ignore"):
            scale = float(np.min(np.where(extent > 0, room / np.where(extent > 0, extent, 1.0), np.inf)))
    else:
        scale = as_number(scale, "scale", gt=0)
    centre = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
    offset = centre - scale * (lo + hi) / 2.0
    return {
        "points": pts * scale + offset,
        "scale": scale,
        "offset": offset,
        "size": (w, h),
        "margin": None if margin is None else float(margin),
    }
