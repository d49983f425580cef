"""Contours from images: reading (:mod:`.imageio`), segmentation
(:mod:`.segment`: Otsu, threshold, mask, alpha, GrabCut), sub-pixel tracing
(:mod:`.trace`), figure-ground for photographs (:mod:`.figure_ground`:
automatic, GrabCut, one box per object, learned networks, the boxes and
scribbles a user draws), the outline of each object (:mod:`.outlines`), its
verdict (:mod:`.verdict`, photo measures in :mod:`.quality`), the
scale-space description (:mod:`.scalespace`), the overlay drawing
(:mod:`.overlays`) and the per-image pipeline of ``attneave extract``
(:mod:`.pipeline`)."""

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "METHODS": ".segment",
    "SIGMA_FRACTION": ".scalespace",
    "MIN_SIGMA": ".scalespace",
    "Extraction": ".outlines",
    "ContourInfo": ".scalespace",
    "read_image": ".imageio",
    "extract": ".outlines",
    "extract_contours": ".outlines",
    "default_sigma": ".scalespace",
    "smooth": ".scalespace",
    "contour_curvature": ".scalespace",
    "describe": ".scalespace",
    "curvature_peaks": ".scalespace",
    "IMAGE_SUFFIXES": ".imageio",
    "overlay": ".overlays",
    "extract_images": ".pipeline",
    "open_image": ".imageio",
    "judge": ".verdict",
    "Verdict": ".verdict",
})
