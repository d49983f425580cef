"""Placing contours on the canvas of a stimulus.

Every shape is made in its generator's own units and then placed on the
canvas: ``placement='fit'`` (default) scales it uniformly so that its
bounding box fills the canvas less ``margin`` on the tighter side and
centres the box on the image centre ``((width - 1) / 2, (height - 1) / 2)``
(:func:`attneave.stimuli.render.fit_to_image`); ``placement='native'`` keeps the
generator's units as pixels (e.g. an RF pattern's ``r0`` in px) and puts
the generator's centre (the polar origin, the grid centre) on the image
centre. Points are ``(x, y)`` in image pixels, y down, pixel centres at
integers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["Canvas", "place"]


@dataclass(frozen=True)
class Canvas:
    """The image a stimulus is drawn on.

    Attributes
    ----------
    width, height : int
        Image size in pixels.
    margin : float
        Pixels between the shape's bounding box and the image edge (for
        ``placement='fit'``).
    """

    width: int = 512
    height: int = 512
    margin: float = 32.0

    def __post_init__(self):
        for name in ("width", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, np.integer)) and v > 0):
                raise InputError(f"canvas.{name}: must be a positive integer, got {v!r}")
        if not (np.isfinite(self.margin) and 0 <= self.margin and 2 * self.margin < min(self.width, self.height)):
            raise InputError(
                f"canvas.margin: must be >= 0 and less than half the smaller side, got {self.margin!r}"
            )

    @property
    def size(self):
        """``(width, height)``."""
        return (int(self.width), int(self.height))

    @property
    def centre(self):
        """The image centre ``((width - 1) / 2, (height - 1) / 2)`` in pixel coordinates."""
        return np.array([(self.width - 1) / 2.0, (self.height - 1) / 2.0])



def place(contours, centre, canvas, placement="fit"):
    """Place contours (one transform for all) on the canvas.

    Parameters
    ----------
    contours : list of Contour
        In the generator's units (y down).
    centre : (2,) array_like
        The generator's centre (used by ``'native'``).
    canvas : Canvas
    placement : {'fit', 'native'}
        See the module docstring.

    Returns
    -------
    placed : list of Contour
        In image pixels: ``points * scale + offset``.
    params : dict
        ``placement, scale, offset``.
    """
    if placement == "fit":
        from attneave.stimuli.render import fit_to_image

        allp = np.vstack([c.points for c in contours])
        f = fit_to_image(allp, size=canvas.size, margin=canvas.margin)
        scale, offset = float(f["scale"]), np.asarray(f["offset"], float)
    elif placement == "native":
        scale, offset = 1.0, canvas.centre - np.asarray(centre, float)
    else:
        raise InputError(f"placement: expected 'fit' or 'native', got {placement!r}")
    placed = [c.transformed(scale, offset) for c in contours]
    if placement == "native":
        # a shape cut off by the image edge is not the stimulus the contour file describes
        lo = np.min([c.points.min(axis=0) for c in placed], axis=0)
        hi = np.max([c.points.max(axis=0) for c in placed], axis=0)
        if lo[0] < -0.5 or lo[1] < -0.5 or hi[0] > canvas.width - 0.5 or hi[1] > canvas.height - 0.5:
            raise InputError(
                f"placement: native: the shape spans x {lo[0]:.1f}..{hi[0]:.1f}, y {lo[1]:.1f}..{hi[1]:.1f} px, "
                f"outside the {canvas.width}x{canvas.height} canvas; make it smaller, the canvas larger, "
                f"or use placement: fit")
    return placed, dict(placement=placement, scale=scale, offset=[float(offset[0]), float(offset[1])])

