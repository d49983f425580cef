"""Curves of the seed paper: natural-equation families (clothoid,
pseudospirals, log-aesthetic curves, superspirals, constant-information
curves), Euler-spiral segments, log-aesthetic segments, splines through
points (QIC and polynomial) and the metrics that compare them.

The curve families are available directly (``stimuli.curves.clothoid(...)``);
the rest lives in the sub-modules ``natural``, ``euler``, ``lac``,
``splines`` and ``metrics``.
"""

from stimuli.curves.natural import (  # noqa: F401  (the families are the package's face)
    FAMILIES,
    Curve,
    clothoid,
    constant_info,
    constant_info_curvature,
    constant_info_domain,
    integrate_natural,
    log_aesthetic,
    pseudospiral,
    superspiral,
)

__all__ = [
    "FAMILIES",
    "Curve",
    "clothoid",
    "constant_info",
    "constant_info_curvature",
    "constant_info_domain",
    "integrate_natural",
    "log_aesthetic",
    "pseudospiral",
    "superspiral",
]
