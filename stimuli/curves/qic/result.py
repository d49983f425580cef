"""The result of a QIC spline fit: :class:`QICSpline` (segments, nodes,
corners, sampling and metrics).

Built by :func:`attneave.stimuli.curves.qic.spline.qic_spline`; see that module for the
mathematics.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from attneave.stimuli.curves.checks import check_samples
from attneave.stimuli.curves.euler import clothoid_points
from attneave.stimuli.curves.metrics import SampledCurve, SplineMeasures
from attneave.stimuli.curves.qic import kernel as qic_kernel
from attneave.stimuli.curves.qic.newton import tangent_range

__all__ = ["QICSpline"]


@dataclass(frozen=True)
class QICSpline(SplineMeasures):
    """A spline of clothoid segments through points (see :func:`qic_spline`).

    Attributes
    ----------
    points : ndarray, shape (N, 2)
        The interpolated points (image pixels, y down unless ``y_down`` was
        False).
    closed : bool
    x0, y0, theta0 : ndarray, shape (M,)
        Start point and tangent angle (input coordinates) of each segment.
    k0, dk, length : ndarray, shape (M,)
        Start curvature and curvature rate, in the input coordinates'
        sign (d theta / ds), and length of each segment (px).
    start : ndarray of int, shape (M,)
        Index of the point at which each segment starts.
    sign : float
        Factor from input-coordinate curvature to geometric curvature.
    iterations : int
        Newton iterations (summed over pieces and rounds).
    g2_error : float
        Largest curvature jump at a G2 node divided by the largest
        |curvature|, as solved.
    closure_error : float
        Largest segment end-point miss relative to the curve's size.
    corners : tuple of int
        Nodes where the curve is not G2 (sorted).
    corner_kinds : tuple of str
        'G1' (tangent continuous, curvature jumps) or 'G0' (tangent breaks)
        for each of `corners`.
    seconds : float
        Time taken by the fit.
    method : str
        'qic' (robust) or 'qic-g2' (pure).
    """

    points: np.ndarray
    closed: bool
    x0: np.ndarray
    y0: np.ndarray
    theta0: np.ndarray
    k0: np.ndarray
    dk: np.ndarray
    length: np.ndarray
    start: np.ndarray
    sign: float
    iterations: int
    g2_error: float
    closure_error: float
    corners: tuple = field(default_factory=tuple)
    corner_kinds: tuple = field(default_factory=tuple)
    seconds: float = 0.0
    method: str = "qic"

    @property
    def n_points(self):
        return len(self.points)

    @cached_property
    def segment_turn(self):
        """Range of the tangent angle on each segment (radians; computed when first asked)."""
        A = 0.5 * self.dk * self.length**2  # theta(s) - theta0 = k0 L tau + A tau**2, tau = s / L
        lo, hi = tangent_range(self.k0 * self.length + A, A)
        return hi - lo

    @property
    def node_curvature(self):
        """Geometric curvature at the start of each segment (1/px)."""
        return self.sign * self.k0

    @property
    def end_curvature(self):
        """Geometric curvature at the end of each segment (1/px)."""
        return self.sign * (self.k0 + self.dk * self.length)

    def sample(self, samples=32):
        """Sample every segment at `samples` points equally spaced in arc
        length, both end points included.

        Returns
        -------
        SampledCurve
        """
        samples = check_samples(samples, self.length.size)
        return self._samples(np.full(self.length.size, samples))

    def sample_by_turn(self, max_step=0.1, max_samples=32):
        """Sample every segment at points equally spaced in arc length, as
        few as keep the tangent's change between neighbours at most
        `max_step` radians (at least 3, at most `max_samples`, both ends
        included; the cap wins): cheap where the curve is smooth (used by
        the crossing test of the robust rule).

        Returns
        -------
        SampledCurve
        """
        if qic_kernel.LIB is not None and max_step > 0:
            return self._samples(None, max_step, max_samples)
        # curvature is linear on a segment: its largest |k| is at an end, and
        # |k| * (L / steps) bounds the tangent's change between neighbours
        kmax = np.maximum(np.abs(self.k0), np.abs(self.k0 + self.dk * self.length))
        steps = np.ceil(np.minimum(self.length * kmax / max_step, max_samples))
        return self._samples(np.clip(steps.astype(np.int64) + 1, 3, max(int(max_samples), 3)))

    def _samples(self, counts, max_step=0.0, max_samples=0):
        """`counts` (int64, >= 2 each) points per segment, equally spaced in
        arc length (None: as :meth:`sample_by_turn` chooses them, by the kernel)."""
        # each segment ends on the next point: put it there exactly, not to
        # round-off, so that joins are not tiny zig-zags
        end = self.points[(self.start + 1) % len(self.points)]
        if qic_kernel.LIB is not None:
            counts, (s, x, y, th, k) = qic_kernel.sample_segments(
                counts, max_step, max_samples, self.x0, self.y0, self.theta0, self.k0, self.dk, self.length,
                end[:, 0], end[:, 1], self.sign,
            )
        else:
            j = np.repeat(np.arange(counts.size), counts)
            first = np.r_[0, np.cumsum(counts)[:-1]]
            s_loc = self.length[j] * ((np.arange(j.size) - first[j]) / (counts[j] - 1))
            x, y, th, k = clothoid_points(self.x0[j], self.y0[j], self.theta0[j], self.k0[j], self.dk[j], s_loc)
            last = first + counts - 1
            x[last], y[last] = end[:, 0], end[:, 1]
            s = np.r_[0.0, np.cumsum(self.length)[:-1]][j] + s_loc
            k = self.sign * k
        return SampledCurve(s=s, x=x, y=y, curvature=k, segment=np.repeat(self.start, counts), theta=th,
                            closed=self.closed, breaks=tuple(self.corners))
