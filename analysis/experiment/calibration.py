"""Screen calibration and visual angle.

A browser knows sizes only in CSS pixels, whose physical size differs from
screen to screen. The page therefore asks the participant to match an
on-screen card to a real credit card (ISO/IEC 7810 ID-1: 85.60 mm x
53.98 mm), which gives CSS pixels per millimetre (Li et al. 2020, the
"virtual chinrest"). With the viewing distance ``d`` it converts degrees of
visual angle to CSS pixels the way PsychoPy's ``'deg'`` units do: a linear
scale equal to the size of the central degree,

    px_per_deg = px_per_mm * 2 * d_mm * tan(0.5 deg),

so that a stimulus of ``D`` degrees is ``D * px_per_deg`` pixels wide. The
exact size of a centred stimulus, ``2 * d * tan(D / 2)``, is larger by
0.25 % at ``D = 10`` deg and 1 % at ``D = 20`` deg (see
:func:`linear_error`). At ``d = 57.29 cm`` (``0.5 cm / tan(0.5 deg)`` = 57.294 cm) one degree is 1 cm (the reason
for the classic 57 cm viewing distance).

All pixel quantities here are CSS pixels (``device pixels /
devicePixelRatio``), the unit in which the page lays out the stimulus.

References
----------
.. [1] Li, Q., Joo, S. J., Yeatman, J. D. & Reinecke, K. (2020).
       Controlling for participants' viewing distance in large-scale,
       psychophysical online experiments using a virtual chinrest.
       Scientific Reports, 10, 904. https://doi.org/10.1038/s41598-019-57204-1
.. [2] ISO/IEC 7810:2019. Identification cards -- Physical characteristics
       (ID-1 format: 85.60 mm x 53.98 mm).
.. [3] Peirce, J. et al. (2019). PsychoPy2: Experiments in behavior made
       easy. Behavior Research Methods, 51, 195-203 (units 'deg' as a
       linear scale of the central degree).
"""

from __future__ import annotations

import math

__all__ = [
    "CARD_WIDTH_MM",
    "CARD_HEIGHT_MM",
    "px_per_mm_from_card",
    "px_per_degree",
    "degrees_to_px",
    "exact_degrees_to_mm",
    "linear_error",
]

#: Width of an ID-1 card (credit card, bank card), ISO/IEC 7810, in mm.
CARD_WIDTH_MM = 85.60
#: Height of an ID-1 card in mm.
CARD_HEIGHT_MM = 53.98


def _positive(value, name):
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def px_per_mm_from_card(card_width_px, card_width_mm=CARD_WIDTH_MM):
    """Pixels per millimetre from an on-screen card matched to a real one.

    Parameters
    ----------
    card_width_px : float
        Width of the on-screen card, in CSS pixels, once the participant has
        matched it to a real card held against the screen.
    card_width_mm : float
        Physical width of the card (85.60 mm for ID-1 cards).

    Returns
    -------
    float
        CSS pixels per millimetre.

    References
    ----------
    Li et al. (2020), see the module docstring.

    Examples
    --------
    >>> round(px_per_mm_from_card(323.5), 4)     # a 96-dpi screen: 3.7795 px/mm
    3.7792
    """
    return _positive(card_width_px, "card_width_px") / _positive(card_width_mm, "card_width_mm")


def px_per_degree(px_per_mm, distance_mm):
    """Pixels per degree of visual angle at the centre of gaze.

    ``px_per_mm * 2 * distance_mm * tan(0.5 deg)``: the size of the central
    degree, used as a linear scale (PsychoPy's ``'deg'`` units).

    Parameters
    ----------
    px_per_mm : float
        From :func:`px_per_mm_from_card`.
    distance_mm : float
        Eye-to-screen distance in millimetres.

    Returns
    -------
    float

    Examples
    --------
    >>> round(px_per_degree(1.0, 572.943), 4)    # 57.29 cm: 1 cm (10 mm) per degree
    10.0
    """
    return _positive(px_per_mm, "px_per_mm") * 2.0 * _positive(distance_mm, "distance_mm") * math.tan(math.radians(0.5))


def degrees_to_px(degrees, px_per_deg):
    """Size in pixels of a stimulus of `degrees` visual angle (linear scale).

    Parameters
    ----------
    degrees : float
    px_per_deg : float
        From :func:`px_per_degree` or given directly.

    Returns
    -------
    float
        ``degrees * px_per_deg``.
    """
    return _positive(degrees, "degrees") * _positive(px_per_deg, "px_per_deg")


def exact_degrees_to_mm(degrees, distance_mm):
    """Exact width in mm of a stimulus centred on the line of sight.

    Parameters
    ----------
    degrees : float
        Visual angle subtended by the whole stimulus.
    distance_mm : float

    Returns
    -------
    float
        ``2 * distance_mm * tan(degrees / 2)``.
    """
    return 2.0 * _positive(distance_mm, "distance_mm") * math.tan(math.radians(_positive(degrees, "degrees")) / 2.0)


def linear_error(degrees):
    """Relative size error of the linear scale against the exact size.

    Parameters
    ----------
    degrees : float
        Stimulus size in degrees.

    Returns
    -------
    float
        ``exact / linear - 1`` (independent of distance and screen):
        0.0025 at 10 deg, 0.010 at 20 deg.
    """
    d = _positive(degrees, "degrees")
    return math.tan(math.radians(d) / 2.0) / (d * math.tan(math.radians(0.5))) - 1.0
