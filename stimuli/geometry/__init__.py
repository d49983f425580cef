"""Contours and the information they carry: :class:`Contour` (curvature,
resampling, orientation) and the quantity-of-information model (eq. 4-7)."""

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "Contour": ".contour",
    "turning_angles": ".polyline",
    "gaussian_curvature": ".polyline",
    "shoelace": ".polyline",
    "surprisal": ".information",
    "surprisal_paper": ".information",
    "surprisal_vonmises": ".information",
    "surprisal_from_points": ".information",
    "find_peaks": ".information",
    "SurprisalResult": ".information",
    "MODELS": ".information",
    "LENGTH_UNITS": ".information",
    "length_scale": ".information",
})
