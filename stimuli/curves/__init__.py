"""Curves of the seed paper: natural-equation families (clothoid,
pseudospirals, log-aesthetic curves and their generalisation, superspirals,
constant-information curves), Euler-spiral segments, log-aesthetic segments,
splines through points (QIC, log-aesthetic and polynomial), two-point G1
Hermite curves, and the metrics that compare them.

The curve families are available directly (``attneave.stimuli.curves.clothoid(...)``);
the rest lives in the sub-modules: ``natural`` (the integrator, clothoid,
pseudospiral), ``aesthetic`` (LAC, GLAC), ``lac_gamma`` (the LAC's closed
form), ``superspiral``, ``constant_info``, ``euler`` (clothoid segments),
``lac`` (LAC segments, G1 LAC spline), ``lac_arc``, ``lac_quadrature``, ``lac_newton`` and
``lac_spline`` (the G2 LAC spline), ``points``, ``qic_newton``, ``qic``,
``polynomial``, ``splines`` (:func:`fit_spline`), ``biangular`` and
``metrics``.
"""

from attneave.stimuli.curves.lac.aesthetic import glac, log_aesthetic  # noqa: F401  (the families are the package's face)
from attneave.stimuli.curves.constant_info import (  # noqa: F401
    constant_info,
    constant_info_curvature,
    constant_info_domain,
)
from attneave.stimuli.curves.natural import FAMILIES, Curve, clothoid, integrate_natural, pseudospiral  # noqa: F401
from attneave.stimuli.curves.superspiral import superspiral  # noqa: F401

__all__ = [
    "FAMILIES",
    "Curve",
    "clothoid",
    "constant_info",
    "constant_info_curvature",
    "constant_info_domain",
    "glac",
    "integrate_natural",
    "log_aesthetic",
    "pseudospiral",
    "superspiral",
]
