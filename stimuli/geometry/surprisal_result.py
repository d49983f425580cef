"""The result of :func:`attneave.stimuli.geometry.information.surprisal`: per-point
turning angle, curvature and surprisal along a resampled contour, its peaks,
and every resolved parameter (re-exported by
:mod:`attneave.stimuli.geometry.information`, its public home).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.geometry.contour import Contour

__all__ = ["SurprisalResult"]


@dataclass
class SurprisalResult:
    """Per-point information along a resampled contour, with its parameters.

    Attributes
    ----------
    contour : Contour
        The contour resampled at `n` equally spaced points from the input's
        first point (image pixels, y down).
    s, t : ndarray
        Arc length (px) and arc position in [0, 1) of each point.
    turning_angle, curvature, surprisal : ndarray
        Per point; curvature in 1/px (turning angle / ds), surprisal in nats
        or bits.
    peaks : ndarray of int
        Peak indices, highest first.
    params : dict
        Every resolved parameter: model, n, ds (spacing in px), length (px),
        length_unit, unit_px (pixels per unit of length), ds_in_unit (the ds
        of eq. 4-5), A, b, closed, bits, units, prominence.
    """

    contour: Contour
    s: np.ndarray
    t: np.ndarray
    turning_angle: np.ndarray
    curvature: np.ndarray
    surprisal: np.ndarray
    peaks: np.ndarray
    params: dict = field(default_factory=dict)

    def is_peak(self):
        """(N,) int array, 1 on peaks."""
        flag = np.zeros(len(self.s), dtype=int)
        flag[self.peaks] = 1
        return flag

    def table(self):
        """Columns ``i, s, t, x, y, turning_angle, curvature, surprisal, peak, length_unit``.

        ``length_unit`` repeats ``params['length_unit']`` on every row, so a
        file carries the unit its surprisal values are in.
        """
        p = self.contour.points
        return {
            "i": np.arange(len(p)),
            "s": self.s,
            "t": self.t,
            "x": p[:, 0],
            "y": p[:, 1],
            "turning_angle": self.turning_angle,
            "curvature": self.curvature,
            "surprisal": self.surprisal,
            "peak": self.is_peak(),
            "length_unit": np.full(len(p), self.params.get("length_unit", ""), dtype=object),
        }
