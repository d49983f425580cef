"""The result of a G2 log-aesthetic spline fit: :class:`LACG2Spline`
(arcs, nodes, corners, sampling and metrics), and :func:`solved_spline`,
which makes one from a solution of :class:`~attneave.stimuli.curves.lac.newton.LACSystem`.

Built by :func:`attneave.stimuli.curves.lac.spline.lac_spline` and by the robust QIC
spline's log-aesthetic form (:mod:`attneave.stimuli.curves.qic.lac`); see those
modules for the mathematics.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from attneave.stimuli.curves.checks import check_samples
from attneave.stimuli.curves.lac.arc import (
    arc_curvature,
    arc_singular_point,
    arc_turn,
    piece_chords,
)
from attneave.stimuli.curves.metrics import SampledCurve, SplineMeasures

__all__ = ["LACG2Spline", "solved_spline"]


@dataclass(frozen=True)
class LACG2Spline(SplineMeasures):
    """A G2 spline of log-aesthetic arcs through points (see :func:`lac_spline`).

    Attributes
    ----------
    points : ndarray, shape (N, 2)
    closed : bool
    alpha : float
        Slope of every segment's log curvature graph.
    theta : ndarray, shape (n,)
        Tangent angle at every node (input coordinates, unwrapped along the
        curve); n = N.
    kappa : ndarray, shape (n,)
        Curvature at every node, ``d theta / ds`` in the input coordinates
        (1/px), shared by the segments that meet there.
    length : ndarray, shape (M,)
        Length of every segment (px).
    sign : float
        Factor from input-coordinate to geometric curvature.
    iterations : int
        Newton iterations, summed over the continuation.
    alphas : tuple of float
        The alphas solved for on the way (the last is `alpha`).
    closure_error : float
        Largest miss of a segment's end point, relative to the curve's size.
    g2_error : float
        Largest relative curvature jump at a node as evaluated from both
        segments' formulas (rounding only: the curvature is shared).
    seconds : float
    method : str
        'lac'.
    corners, corner_kinds : tuple
        Nodes where the curve is not G2 and their kinds ('G1': tangent
        held, curvature jumps; 'G0': tangent breaks, natural ends), as in
        :class:`~attneave.stimuli.curves.qic.result.QICSpline`; empty for
        :func:`lac_spline`, whose every node is G2.
    end_kappa : ndarray, shape (M,) or None
        Curvature at the end of every segment where it may differ from the
        next node's (a spline with G1 or G0 nodes); None: ``kappa[b]``.
        `theta` and `kappa` are then the values where each segment starts.
    """

    points: np.ndarray
    closed: bool
    alpha: float
    theta: np.ndarray
    kappa: np.ndarray
    length: np.ndarray
    sign: float
    iterations: int
    alphas: tuple
    closure_error: float
    g2_error: float
    seconds: float = 0.0
    method: str = "lac"
    corners: tuple = ()
    corner_kinds: tuple = ()
    end_kappa: np.ndarray | None = None

    @property
    def n_points(self):
        return len(self.points)

    @property
    def node_curvature(self):
        """Geometric curvature at every node (1/px; where a segment starts)."""
        return self.sign * self.kappa

    @property
    def start(self):
        """Index of the point at which each segment starts."""
        return np.arange(self.length.size)

    @property
    def theta0(self):
        """Tangent angle where each segment starts (input coordinates)."""
        return self.theta[: self.length.size]

    def _end_kappa(self):
        b = self._ends()[1]
        return self.kappa[b] if self.end_kappa is None else self.end_kappa

    @property
    def end_curvature(self):
        """Geometric curvature at the end of each segment (1/px)."""
        return self.sign * self._end_kappa()

    @cached_property
    def segment_turn(self):
        """Range of the tangent angle on each segment (radians): curvature is
        monotone on an arc, so the angle is extreme at its ends or at its
        inflection."""
        k0, k1 = self.kappa[: self.length.size], self._end_kappa()
        t = np.clip(arc_singular_point(k0, k1, self.alpha), 0.0, 1.0)
        at = np.stack([np.zeros_like(t), t, np.ones_like(t)])
        turn = self.length * arc_turn(at, k0, k1, self.alpha)
        return np.ptp(turn, axis=0)

    def _ends(self):
        a = np.arange(self.length.size)
        b = (a + 1) % len(self.points) if self.closed else a + 1
        return a, b

    def sample(self, samples=32):
        """Sample every segment at `samples` points equally spaced in arc
        length, both ends included.

        Returns
        -------
        SampledCurve
        """
        samples = check_samples(samples, self.length.size)
        a, b = self._ends()
        M = a.size
        t = np.linspace(0.0, 1.0, samples)
        k1 = self._end_kappa()
        k0, L, th0 = self.kappa[a], self.length, self.theta[a]
        # the position: each stretch between samples by the graded rule, summed
        lo = np.broadcast_to(t[:-1], (M, samples - 1)).ravel()
        hi = np.broadcast_to(t[1:], (M, samples - 1)).ravel()
        dz = piece_chords(th0, k0, k1, L, self.alpha, lo, hi, np.repeat(np.arange(M), samples - 1))
        dz = dz.reshape(M, samples - 1)
        z = self.points[a, 0] + 1j * self.points[a, 1]
        Z = np.concatenate((z[:, None], z[:, None] + np.cumsum(dz, axis=1)), axis=1)
        # each segment ends on the next point: put it there exactly
        Z[:, -1] = self.points[b, 0] + 1j * self.points[b, 1]
        theta = th0[:, None] + L[:, None] * arc_turn(t[None, :], k0[:, None], k1[:, None], self.alpha)
        kappa = arc_curvature(t[None, :], k0[:, None], k1[:, None], self.alpha)
        s = (np.r_[0.0, np.cumsum(L)[:-1]][:, None] + L[:, None] * t[None, :]).ravel()
        return SampledCurve(s=s, x=Z.real.ravel(), y=Z.imag.ravel(), curvature=self.sign * kappa.ravel(),
                            segment=np.repeat(a, samples), theta=theta.ravel(), closed=self.closed,
                            breaks=tuple(self.corners))



def solved_spline(system, x, P, closed, alpha, sign, iterations, alphas, t_start, **fields):
    """The :class:`LACG2Spline` of a solution `x` of `system` (its frame's
    units undone), with its closure and G2 errors; `fields` (corners and
    their kinds, method) are passed on."""
    th, k, L = system.split(x)
    h = system.h
    arc = system.integrals(x, alpha)
    size = float(np.max(np.ptp(P, axis=0))) or 1.0
    closure = float(np.max(np.abs(arc["z"] - system.D))) * h / size
    kend = arc_curvature(1.0, k[system.ua], k[system.ub], alpha)
    kmax = float(np.max(np.abs(k))) or 1.0
    g2 = float(np.max(np.abs(kend - k[system.ub]))) / kmax
    n = len(P)
    return LACG2Spline(
        points=P, closed=closed, alpha=alpha, theta=th[:n].copy(), kappa=k[:n] / h, length=L * h,
        sign=sign, iterations=int(iterations), alphas=tuple(alphas), closure_error=closure, g2_error=g2,
        seconds=time.perf_counter() - t_start,
        end_kappa=k[system.ub] / h if system.joints else None, **fields,
    )
