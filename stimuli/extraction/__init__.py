"""Contours from images: reading, segmentation (Otsu, threshold, mask,
alpha, GrabCut), sub-pixel tracing and the scale-space description."""

from stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "METHODS": ".core",
    "SIGMA_FRACTION": ".core",
    "MIN_SIGMA": ".core",
    "Extraction": ".core",
    "ContourInfo": ".core",
    "read_image": ".core",
    "extract": ".core",
    "extract_contours": ".core",
    "default_sigma": ".core",
    "smooth": ".core",
    "contour_curvature": ".core",
    "describe": ".core",
    "curvature_peaks": ".core",
    "IMAGE_SUFFIXES": ".core",
})
