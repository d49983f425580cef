"""Curves of the seed paper: natural-equation families (clothoid,
pseudospirals, log-aesthetic curves and their generalisation, superspirals,
constant-information curves), Euler-spiral segments, log-aesthetic segments,
splines through points (QIC, log-aesthetic and polynomial), two-point G1
Hermite curves, and the metrics that compare them.

The curve families are available directly (``attneave.stimuli.curves.clothoid(...)``);
the rest lives in the sub-modules: ``natural`` (:class:`Curve` and the integrator),
``clothoid``, ``pseudospiral``, ``superspiral``, ``constant_info``, ``checks``
(argument limits and the arc-length grid), ``euler`` and ``fresnel`` (clothoid
segments and their Fresnel moments), ``lac/`` (``aesthetic``: LAC and GLAC; ``gamma``:
the LAC's closed form; ``g1``: the G1 LAC spline; ``arc``, ``newton``, ``spline``:
the G2 LAC spline), ``qic/`` (the QIC spline: ``spline``, ``robust``, ``newton``,
``rule``, ``kernel``, ``result``), ``points``, ``polynomial``, ``splines``
(:func:`~attneave.stimuli.curves.splines.fit_spline`), ``biangular`` and ``metrics``.
"""

from attneave.stimuli.curves.clothoid import clothoid  # noqa: F401
from attneave.stimuli.curves.constant_info import (  # noqa: F401
    constant_info,
    constant_info_curvature,
    constant_info_domain,
)
from attneave.stimuli.curves.lac.aesthetic import glac, log_aesthetic  # noqa: F401  (the families are the package's face)
from attneave.stimuli.curves.natural import FAMILIES, Curve, integrate_natural  # noqa: F401
from attneave.stimuli.curves.pseudospiral import pseudospiral  # noqa: F401
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
