"""attneave.stimuli: shapes, curvature and the information they carry.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down,
pixel centres at integer coordinates). See DESIGN.md for every convention.
"""

__version__ = "0.1.0"

from .contour import Contour, turning_angles  # noqa: E402
from .errors import InputError  # noqa: E402
from .information import (  # noqa: E402
    find_peaks,
    surprisal,
    surprisal_paper,
    surprisal_vonmises,
)
from .splines import ConvergenceError, fit_spline, polynomial_spline, qic_spline  # noqa: E402
from . import curves, recipes  # noqa: E402
from .extract import describe, extract, extract_contours, read_image  # noqa: E402
from .render import coverage, fit_to_image, render_silhouette  # noqa: E402

__all__ = [
    "ConvergenceError",
    "Contour",
    "coverage",
    "curves",
    "describe",
    "extract",
    "extract_contours",
    "fit_to_image",
    "read_image",
    "recipes",
    "render_silhouette",
    "fit_spline",
    "polynomial_spline",
    "qic_spline",
    "InputError",
    "find_peaks",
    "surprisal",
    "surprisal_paper",
    "surprisal_vonmises",
    "turning_angles",
]
