"""Interpolating polynomial splines through points with chord-length
parametrisation: the baselines of the seed paper's Figs. 8-10 (cubic splines,
periodic, not-a-knot or natural, and splines of degree 2-5), which add
curvature extrema between the points.

Built on :class:`scipy.interpolate.CubicSpline` and
:func:`scipy.interpolate.make_interp_spline`. Points are ``(x, y)`` in image
pixels (y down); reported curvature follows the project's geometric sign.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from attneave.stimuli.curves.checks import check_samples
from attneave.stimuli.curves.metrics import SampledCurve, curve_metrics
from attneave.stimuli.curves.points import geometric_sign, spline_points
from attneave.stimuli.errors import InputError

__all__ = ["PolynomialSpline", "polynomial_spline"]


@dataclass(frozen=True)
class PolynomialSpline:
    """A parametric polynomial interpolating spline (x(u), y(u)) with
    chord-length parameter u (see :func:`polynomial_spline`).

    Attributes
    ----------
    points : ndarray, shape (N, 2)
    closed : bool
    degree : int
    bc_type : str
    knots : ndarray
        Parameter value at each point (cumulative chord length, px); for a
        closed curve one more, for the return to the first point.
    spline : object
        The scipy spline, called as ``spline(u, nu)``.
    sign : float
    seconds : float
    method : str
    """

    points: np.ndarray
    closed: bool
    degree: int
    bc_type: str
    knots: np.ndarray
    spline: object
    sign: float
    seconds: float = 0.0
    method: str = "cubic"
    iterations: int = 0

    @property
    def n_points(self):
        return len(self.points)

    def sample(self, samples=32):
        """Sample each interval between consecutive points at `samples`
        equally spaced parameter values, both ends included; arc length by
        5-point Gauss-Legendre quadrature of the speed between samples.

        Curvature is NaN where the parametric speed vanishes (a cusp, e.g.
        when points double back): it is undefined there."""
        samples = check_samples(samples, len(self.knots) - 1)
        kn = self.knots
        u = kn[:-1, None] + (kn[1:] - kn[:-1])[:, None] * np.linspace(0.0, 1.0, samples)[None, :]
        uf = u.ravel()
        P = self.spline(uf)
        d1 = self.spline(uf, 1)
        d2 = self.spline(uf, 2)
        speed2 = d1[:, 0] ** 2 + d1[:, 1] ** 2
        with np.errstate(divide="ignore", invalid="ignore"):  # a cusp: k undefined, NaN
            k = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed2**1.5
        # arc length between successive samples (per segment, then chained)
        g, w = np.polynomial.legendre.leggauss(5)
        a, b = u[:, :-1], u[:, 1:]
        mid, half = 0.5 * (a + b), 0.5 * (b - a)
        q = mid[..., None] + half[..., None] * g
        dq = self.spline(q.ravel(), 1)
        sp = np.hypot(dq[:, 0], dq[:, 1]).reshape(q.shape)
        ds = np.sum(sp * w, axis=-1) * half
        seg_len = ds.sum(axis=1)
        s_loc = np.concatenate([np.zeros((ds.shape[0], 1)), np.cumsum(ds, axis=1)], axis=1)
        offs = np.r_[0.0, np.cumsum(seg_len)[:-1]]
        s = (offs[:, None] + s_loc).ravel()
        theta = np.arctan2(d1[:, 1], d1[:, 0]).reshape(u.shape)
        theta = np.unwrap(theta, axis=1).ravel()
        seg = np.repeat(np.arange(len(kn) - 1), samples)
        return SampledCurve(
            s=s, x=P[:, 0], y=P[:, 1], curvature=self.sign * k, segment=seg, theta=theta,
            closed=self.closed,
        )

    def metrics(self, samples=32):
        """:func:`~attneave.stimuli.curves.metrics.curve_metrics` of :meth:`sample`."""
        out = curve_metrics(self.sample(samples))
        out["iterations"] = 0
        return out


def polynomial_spline(points, degree=3, closed=True, bc_type=None, y_down=True):
    """Interpolating polynomial spline with chord-length parametrisation.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (y down).
    degree : {2, 3, 4, 5}
    closed : bool
        Closed curves use periodic end conditions.
    bc_type : {None, 'not-a-knot', 'natural'}
        Open curves: end conditions. ``None`` is not-a-knot (scipy's
        default knot placement for :func:`~scipy.interpolate.make_interp_spline`);
        ``'natural'`` (zero second derivative) is for cubics only.
    y_down : bool
        Only the sign of reported curvature for open curves depends on it.

    Returns
    -------
    PolynomialSpline

    Raises
    ------
    InputError
        Bad points or an unknown degree or end condition.
    """
    t0 = time.perf_counter()
    P = spline_points(points, closed)
    if degree not in (2, 3, 4, 5):
        raise InputError(f"degree: expected 2, 3, 4 or 5, got {degree!r}")
    if closed and bc_type not in (None, "periodic"):
        raise InputError(f"bc_type: a closed spline is periodic, got {bc_type!r}")
    if not closed and bc_type not in (None, "not-a-knot", "natural"):
        raise InputError(f"bc_type: expected 'not-a-knot' or 'natural', got {bc_type!r}")
    if bc_type == "natural" and degree != 3:
        raise InputError("bc_type: 'natural' end conditions are for cubic splines (degree 3)")
    Q = np.vstack([P, P[:1]]) if closed else P
    if len(Q) <= degree and not closed:
        raise InputError(f"points: a degree-{degree} open spline needs at least {degree + 1} points, got {len(P)}")
    u = np.r_[0.0, np.cumsum(np.hypot(*np.diff(Q, axis=0).T))]
    from scipy.interpolate import CubicSpline, make_interp_spline

    if closed:
        bc = "periodic"
        spl = CubicSpline(u, Q, bc_type="periodic") if degree == 3 else make_interp_spline(u, Q, k=degree, bc_type="periodic")
    elif degree == 3:
        bc = bc_type or "not-a-knot"
        spl = CubicSpline(u, Q, bc_type=bc)
    else:
        bc = "not-a-knot"
        spl = make_interp_spline(u, Q, k=degree)
    method = {2: "poly2", 3: "cubic", 4: "poly4", 5: "poly5"}[degree]
    if degree == 3 and bc == "natural":
        method = "cubic-natural"
    return PolynomialSpline(
        points=P, closed=closed, degree=degree, bc_type=bc, knots=u, spline=spl,
        sign=geometric_sign(P, closed, y_down), seconds=time.perf_counter() - t0, method=method,
    )
