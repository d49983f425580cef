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

A canvas may be given in degrees of visual angle (``width_deg``,
``height_deg``, ``margin_deg``) with the display's scale: ``px_per_deg``, or
``viewing_distance_cm`` with ``screen_width_cm`` and ``screen_width_px``
(:func:`canvas_in_pixels`); the images are then made at that many pixels
and ``attneave experiment`` shows them at that size in degrees. A shape's
size given in degrees (``r0_deg``) is pixels at that scale and places the
shape ``native``, since ``fit`` would rescale it
(:mod:`attneave.stimuli.batch.degrees`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["Canvas", "place", "px_per_degree", "canvas_in_pixels", "canvas_base", "DEGREE_KEYS", "SCALE_KEYS"]

#: The canvas keys in degrees and the pixel key each gives.
DEGREE_KEYS = {"width_deg": "width", "height_deg": "height", "margin_deg": "margin"}
#: The keys that give the display's scale (px per degree).
SCALE_KEYS = ("px_per_deg", "viewing_distance_cm", "screen_width_cm", "screen_width_px")


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
                f"or, for a size given in px, use placement: fit")
    return placed, dict(placement=placement, scale=scale, offset=[float(offset[0]), float(offset[1])])



def px_per_degree(px_per_mm, distance_mm):
    """Pixels per degree of visual angle at the centre of gaze: ``px_per_mm * 2 * distance_mm * tan(0.5 deg)``.

    The size of the central degree used as a linear scale (PsychoPy's
    ``'deg'`` units); the same arithmetic as
    ``attneave.analysis.experiment.calibration.px_per_degree``, which the
    experiment page uses (the stimuli package does not import analysis).

    Examples
    --------
    >>> round(px_per_degree(1.0, 572.943), 4)    # 57.29 cm: 1 cm (10 mm) per degree
    10.0
    """
    return float(px_per_mm) * 2.0 * float(distance_mm) * math.tan(math.radians(0.5))


def canvas_in_pixels(values):
    """A canvas mapping with its sizes in degrees turned into pixels (the mapping is not changed).

    Parameters
    ----------
    values : dict
        Canvas keys as given. ``width_deg``, ``height_deg``, ``margin_deg``
        give ``width``, ``height`` (rounded to whole pixels) and ``margin``
        at ``px_per_deg``, or at the scale of ``viewing_distance_cm`` with
        ``screen_width_cm`` and ``screen_width_px`` (a screen of that width
        in cm showing that many pixels).

    Returns
    -------
    dict
        With ``width``, ``height``, ``margin`` and ``px_per_deg`` filled in
        where degrees were given.

    Raises
    ------
    ValueError
        A size in degrees without a scale; a scale given twice that
        disagrees; a size given in pixels and in degrees that disagree.

    Examples
    --------
    >>> canvas_in_pixels({"width_deg": 8, "height_deg": 8, "margin_deg": 0.5, "px_per_deg": 40})["width"]
    320
    >>> round(canvas_in_pixels({"width_deg": 10, "height_deg": 10, "viewing_distance_cm": 57.3,
    ...                         "screen_width_cm": 50, "screen_width_px": 1920})["px_per_deg"], 3)
    38.404
    """
    if not isinstance(values, dict):
        return values
    out = dict(values)
    given_deg = [k for k in DEGREE_KEYS if out.get(k) is not None]
    screen = [k for k in SCALE_KEYS[1:] if out.get(k) is not None]
    if not given_deg and not screen:
        return out
    ppd = out.get("px_per_deg")
    if screen:
        if len(screen) != 3:
            missing = [k for k in SCALE_KEYS[1:] if k not in screen]
            raise ValueError(f"{', '.join(screen)} without {' and '.join(missing)}: the scale needs all three "
                             "(or px_per_deg)")
        for k in screen:
            if isinstance(out[k], bool) or not isinstance(out[k], (int, float)) or not math.isfinite(out[k]) \
                    or out[k] <= 0:
                raise ValueError(f"{k}: expected a positive number, got {out[k]!r}")
        from_screen = px_per_degree(out["screen_width_px"] / (10.0 * out["screen_width_cm"]),
                                    10.0 * out["viewing_distance_cm"])
        if ppd is not None and not math.isclose(ppd, from_screen, rel_tol=1e-9):
            raise ValueError(f"px_per_deg {ppd!r} disagrees with viewing_distance_cm, screen_width_cm and "
                             f"screen_width_px ({from_screen:.6g} px/deg); give one scale")
        ppd = out["px_per_deg"] = from_screen
    if not given_deg:
        return out
    if ppd is None:
        raise ValueError(f"{', '.join(given_deg)} in degrees needs the display's scale: px_per_deg, or "
                         "viewing_distance_cm with screen_width_cm and screen_width_px")
    if isinstance(ppd, bool) or not isinstance(ppd, (int, float)) or not math.isfinite(ppd) or ppd <= 0:
        raise ValueError(f"px_per_deg: expected a positive number, got {ppd!r}")
    for key in given_deg:
        deg, px_key = out[key], DEGREE_KEYS[key]
        if isinstance(deg, bool) or not isinstance(deg, (int, float)) or not math.isfinite(deg) or deg < 0:
            raise ValueError(f"{key}: expected a number of degrees >= 0, got {deg!r}")
        px = deg * ppd if px_key == "margin" else int(round(deg * ppd))
        if out.get(px_key) is not None and not math.isclose(out[px_key], px, rel_tol=1e-9, abs_tol=1e-9):
            raise ValueError(f"{px_key} {out[px_key]!r} px and {key} {deg!r} (= {px:.6g} px at {ppd:.6g} px/deg) "
                             f"disagree; give one of them")
        out[px_key] = px
    return out


def canvas_base(base, override):
    """The top-level canvas less what a condition's canvas gives anew in other units.

    A condition that gives ``width`` (px) overrides a top-level
    ``width_deg`` as well as ``width``; one that gives any of the scale's
    keys replaces the whole scale.

    Examples
    --------
    >>> canvas_base({"width": 320, "width_deg": 8, "px_per_deg": 40}, {"width": 128})
    {'px_per_deg': 40}
    """
    base = dict(base)
    if not isinstance(override, dict):
        return base
    for deg, px in DEGREE_KEYS.items():
        if deg in override or px in override:
            base.pop(deg, None)
            base.pop(px, None)
    if any(k in override for k in SCALE_KEYS):
        for k in SCALE_KEYS:
            base.pop(k, None)
    return base
