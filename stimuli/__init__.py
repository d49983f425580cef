"""attneave.stimuli: shapes, curvature and the information they carry.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down,
pixel centres at integer coordinates). See docs/design.md ("Coordinates", "Units") for every convention.

Sub-packages, each named after what it holds:

``geometry``
    :class:`Contour` and the information model (eq. 4-7).
``curves``
    Natural-equation curves, Euler spirals, log-aesthetic curves, splines
    and their metrics.
``shapes``
    Stimulus generators, deformations, information-guided stimuli.
``render``
    The exact-coverage rasteriser, strokes, placement, PNG and SVG files.
``extraction``
    Contours from images: reading, segmentation, sub-pixel tracing, scale
    space.
``batch``
    YAML batch configs, recipes and the batch runner.

:mod:`attneave.stimuli.stimulus_set` owns the stimulus-set directory format.
Names below are imported on first use, so ``import stimuli`` is cheap.
"""

#: The one version of the package (pyproject.toml reads it from here).
__version__ = "0.2.0"

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "Contour": ".geometry.contour",
    "turning_angles": ".geometry.polyline",
    "InputError": ".errors",
    "find_peaks": ".geometry.information",
    "surprisal": ".geometry.information",
    "surprisal_paper": ".geometry.information",
    "surprisal_vonmises": ".geometry.information",
    "ConvergenceError": ".curves.splines",
    "fit_spline": ".curves.splines",
    "polynomial_spline": ".curves.splines",
    "qic_spline": ".curves.splines",
    "curves": ".curves",
    "recipes": ".batch.recipes",
    "describe": ".extraction",
    "extract": ".extraction",
    "extract_contours": ".extraction",
    "read_image": ".extraction",
    "coverage": ".render",
    "fit_to_image": ".render",
    "render_silhouette": ".render",
})
