"""The point-selection experiment: a self-contained browser page (and a PsychoPy export).

``attneave experiment SET -o DIR`` turns a stimulus set into a directory that
runs in any browser from ``file://`` or a static host, collects the points
participants select on each contour (Attneave 1954; Norman et al. 2001;
De Winter & Wagemans 2008) and offers them as a click file in image pixels
that ``attneave analyze`` reads as it is.

Modules
-------
options
    The validated settings (pydantic) and how they are read from YAML and flags.
calibration
    Screen calibration and visual-angle arithmetic.
order
    The seeded PRNG, trial order and the Latin square of participant lists,
    identical to the page's JavaScript.
build
    Writing the experiment directory atomically.
selection
    Which stimuli (practice, lists), their images checked, the background,
    a set's degrees.
pages
    The pages' settings (JSON) and templates: index.html and, with
    ``--jspsych``, the jsPsych 8 timeline page and its plugin.
jatos
    The JATOS study archive (``.jzip``).
psychopy
    The PsychoPy export (conditions, images, the Coder script).
psyexp, psyexp_code, psychopy_text
    Its Builder experiment (``.psyexp``, also for Pavlovia), the Python and
    JavaScript of its Code components, and what the two share.
"""

from attneave.analysis.experiment.build import build_experiment
from attneave.analysis.experiment.options import ExperimentOptions

__all__ = ["build_experiment", "ExperimentOptions"]
