"""attneave: information along shape contours, for perception research.

Make Attneave-style stimuli, predict where the information on a contour lies
(curvature and surprisal: Attneave 1954; Feldman & Singh 2005; Ziatdinov's
eq. 4-7), build QIC splines, extract contours from images, and test the
prediction against the points participants chose.

The short public API is importable from here; names are imported on first
use, so ``import attneave`` is cheap. The full library lives in

``attneave.stimuli``
    Everything about a shape: contours, curvature and surprisal, curves and
    splines, stimulus generators, rendering, extraction, batch configs.
``attneave.analysis``
    Everything about people: click files, choice models, reports, simulated
    observers, the point-selection experiment.
``attneave.papers``
    The seed paper's figures, each reproduced by a function.

See ``docs/design.md`` for the conventions (coordinates, units, files,
errors) every module follows.

Examples
--------
>>> import attneave
>>> t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
>>> circle = attneave.Contour(np.c_[50 * np.cos(t), 50 * np.sin(t)])
>>> s = attneave.surprisal(circle, n=200)
>>> bool(np.ptp(s.surprisal) < 1e-9)
True
"""

from attneave.stimuli import __version__  # noqa: F401  (one version, kept in attneave.stimuli)
from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "Contour": "attneave.stimuli.geometry.contour",
    "InputError": "attneave.stimuli.errors",
    "surprisal": "attneave.stimuli.geometry.information",
    "surprisal_paper": "attneave.stimuli.geometry.information",
    "surprisal_vonmises": "attneave.stimuli.geometry.information",
    "find_peaks": "attneave.stimuli.geometry.information",
    "qic_spline": "attneave.stimuli.curves.splines",
    "fit_spline": "attneave.stimuli.curves.splines",
    "polynomial_spline": "attneave.stimuli.curves.splines",
    "curves": "attneave.stimuli.curves",
    "load_config": "attneave.stimuli.batch.config",
    "run_batch": "attneave.stimuli.batch.runner",
    "extract": "attneave.stimuli.extraction",
    "extract_contours": "attneave.stimuli.extraction",
    "read_stimulus_set": "attneave.stimuli.stimulus_set",
    "analyze": "attneave.analysis.analyze",
    "read_clicks": "attneave.analysis.clicks.read",
    "simulate": "attneave.analysis.simulate.observers",
    "power": "attneave.analysis.simulate.observers",
    "build_experiment": "attneave.analysis.experiment",
    "kernel_status": "attneave.info",
})
