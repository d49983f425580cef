"""Log-aesthetic curve (LAC) segments inside a control triangle, and a G1
LAC spline (the seed paper's Fig. 7).

A log-aesthetic curve has a straight log-curvature graph of slope alpha. In
the paper's eq. 9 form, with arc length s and radius of curvature rho,
``rho(s) = exp(lam s)`` (alpha = 0) or ``(lam alpha s + 1)**(1/alpha)``; as a
function of the tangent angle psi (Yoshida & Saito 2006) that is
``rho(psi) = exp(lam psi)`` (alpha = 1) or
``((alpha - 1) lam psi + 1)**(1/(alpha - 1))``. alpha = -1 is the clothoid,
0 Nielsen's spiral, 1 the logarithmic spiral, 2 the circle involute.

The G1 segment of Yoshida & Saito: given two end points and their tangent
directions, the tangents meet at the apex of a control triangle; the segment
turns by the triangle's exterior angle ``theta_e = pi - apex angle`` and,
for a chosen alpha, a single parameter lam (found by a bracketed root
search) makes the chord of the standard-form curve ``P(psi) = int_0^psi
rho(t) exp(i t) dt`` meet the triangle's base angles; a similarity maps it
into place. Not every triangle is drawable for every alpha; such spans, and
spans whose tangents need an inflection (no triangle), fall back to the G1
clothoid of :func:`attneave.stimuli.curves.euler.g1_hermite`, and are listed.

Coordinates as in :mod:`attneave.stimuli.curves.splines`: points ``(x, y)`` in image pixels
(y down); reported curvature uses the project's geometric sign.

References
----------
.. [1] N. Yoshida and T. Saito, "Interactive aesthetic curve segments",
       The Visual Computer 22(9-11), 896-905, 2006.
.. [2] R. Ziatdinov, N. Yoshida and T. Kim, "Analytic parametric equations
       of log-aesthetic curves in terms of incomplete gamma functions",
       CAGD 29(2), 129-140, 2012.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from attneave.stimuli.curves.checks import check_samples
from attneave.stimuli.curves.euler import clothoid_points, g1_hermite
from attneave.stimuli.curves.lac.gamma import lac_position, lac_theta
from attneave.stimuli.curves.metrics import SampledCurve, curve_metrics
from attneave.stimuli.curves.points import circle_tangents, end_angles, geometric_sign, spline_points
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number

__all__ = [
    "LACNotDrawable",
    "lac_rho",
    "lac_psi",
    "lac_length",
    "lac_standard_end",
    "lac_segment",
    "lac_segment_points",
    "LACSpline",
    "lac_g1_spline",
]

class LACNotDrawable(ValueError):
    """No log-aesthetic segment of this alpha fits the control triangle."""


def _kind(alpha):
    if abs(alpha) < 1e-12:
        return 0
    if abs(alpha - 1.0) < 1e-12:
        return 1
    return 2


def lac_rho(psi, alpha, lam):
    """Radius of curvature of the standard-form LAC (rho = 1 at psi = 0) as a
    function of the tangent angle psi."""
    psi = np.asarray(psi, dtype=float)
    if lam == 0:
        return np.ones_like(psi)
    if _kind(alpha) == 1:
        return np.exp(lam * psi)
    return ((alpha - 1.0) * lam * psi + 1.0) ** (1.0 / (alpha - 1.0))


def lac_psi(s, alpha, lam):
    """Tangent angle of the standard-form LAC at arc length s (closed form;
    the same curve as eq. 9's, :func:`attneave.stimuli.curves.lac.gamma.lac_theta`)."""
    if _kind(alpha) == 0:
        alpha = 0.0
    elif _kind(alpha) == 1:
        alpha = 1.0
    return lac_theta(s, alpha, lam)


def _s_of_psi(psi, alpha, lam):
    psi = np.asarray(psi, dtype=float)
    if lam == 0:
        return psi.copy()
    k = _kind(alpha)
    if k == 0:
        return -np.log1p(-lam * psi) / lam
    if k == 1:
        return np.expm1(lam * psi) / lam
    return np.expm1(alpha / (alpha - 1.0) * np.log1p((alpha - 1.0) * lam * psi)) / (lam * alpha)


def lac_length(theta_e, alpha, lam):
    """Arc length of the standard-form LAC from psi = 0 to psi = theta_e."""
    return float(_s_of_psi(theta_e, alpha, lam))


def _rho_s(s, alpha, lam):
    s = np.asarray(s, dtype=float)
    if lam == 0:
        return np.ones_like(s)
    k = _kind(alpha)
    if k == 0:
        return np.exp(lam * s)
    return np.exp(np.log1p(lam * alpha * s) / alpha)


def lac_standard_end(theta_e, alpha, lam):
    """End point ``int_0^theta_e rho(psi) exp(i psi) d psi`` of the standard
    form, as a complex number: the incomplete-gamma closed form
    (:func:`attneave.stimuli.curves.lac.gamma.lac_position`) at the arc length where
    the tangent has turned by `theta_e`."""
    return complex(_position(np.array([lac_length(theta_e, alpha, lam)]), alpha, lam)[0])


def _position(s, alpha, lam):
    """Closed-form position of the standard form at arc lengths `s`."""
    if _kind(alpha) == 0:
        alpha = 0.0
    elif _kind(alpha) == 1:
        alpha = 1.0
    return lac_position(s, alpha, lam)


def _solve_lam(theta_e, beta, alpha):
    """lam >= 0 such that the standard form's chord leaves at angle beta
    (theta_e/2 <= beta < theta_e)."""
    def f(lam):
        E = lac_standard_end(theta_e, alpha, lam)
        return np.angle(E) - beta

    if beta - 0.5 * theta_e < 1e-13:
        return 0.0
    if alpha < 1.0 and _kind(alpha) != 1:
        lam_max = 1.0 / ((1.0 - alpha) * theta_e)
        for k in range(1, 15):
            hi = lam_max * (1.0 - 10.0**-k)
            if f(hi) > 0:
                break
        else:
            raise LACNotDrawable(f"alpha={alpha}: base angles {beta:.4g}, {theta_e - beta:.4g} out of reach")
    else:
        hi = 1.0
        while f(hi) <= 0:
            hi *= 4.0
            if hi > 1e8:
                raise LACNotDrawable(f"alpha={alpha}: base angles {beta:.4g}, {theta_e - beta:.4g} out of reach")
    return brentq(f, 0.0, hi, xtol=1e-15, rtol=1e-14, maxiter=200)


def lac_segment(p0, theta0, p1, theta1, alpha=0.0):
    """The Yoshida-Saito log-aesthetic segment between two points with given
    tangent directions.

    Parameters
    ----------
    p0, p1 : (x, y)
        End points (any Cartesian coordinates).
    theta0, theta1 : float
        Tangent angles at the ends (radians, from +x towards +y).
    alpha : float
        Slope of the log-curvature graph.

    Returns
    -------
    dict
        ``lam``, ``theta_e`` (total turn, radians), ``length``, ``turn``
        (+1 turning towards +y, -1 the other way), ``forward`` (whether the
        standard form runs from p0), ``scale``, ``rotation`` and the inputs;
        feed it to :func:`lac_segment_points`.

    Raises
    ------
    LACNotDrawable
        If the tangents do not form a triangle with the chord (an inflection
        or a turn of pi or more is needed) or no lam reaches its base angles.
    """
    p0 = np.asarray(p0, dtype=float)
    p1 = np.asarray(p1, dtype=float)
    r, phi, f0, f1 = end_angles(p0, theta0, p1, theta1)
    if r == 0:
        raise LACNotDrawable("end points coincide")
    if not (f0 * f1 < 0):
        raise LACNotDrawable("the end tangents need an inflection (no control triangle)")
    turn = 1.0 if f1 > 0 else -1.0
    bs, be = -turn * f0, turn * f1
    theta_e = bs + be
    if theta_e >= np.pi:
        raise LACNotDrawable("the segment would turn by pi or more (no control triangle)")
    forward = bs >= be
    beta = bs if forward else be
    lam = _solve_lam(theta_e, beta, float(alpha))
    E = lac_standard_end(theta_e, float(alpha), lam)
    scale = r / abs(E)
    return {
        "p0": p0, "p1": p1, "theta0": float(theta0), "theta1": float(theta1), "alpha": float(alpha),
        "lam": float(lam), "theta_e": float(theta_e), "beta": float(beta), "turn": turn,
        "forward": bool(forward), "scale": float(scale), "chord_angle": phi,
        "length": float(scale * lac_length(theta_e, float(alpha), lam)),
    }


def lac_segment_points(seg, n=32):
    """Sample a segment from :func:`lac_segment` at `n` points equally spaced
    in arc length, from p0 to p1.

    Returns
    -------
    s, x, y, curvature : ndarray
        Arc length from p0, positions, and curvature ``d theta / ds`` in the
        input coordinates (positive turning towards +y).
    """
    alpha, lam, theta_e = seg["alpha"], seg["lam"], seg["theta_e"]
    S = lac_length(theta_e, alpha, lam)
    s = np.linspace(0.0, S, n)
    Z = _position(s, alpha, lam)
    rho = _rho_s(s, alpha, lam)
    turn, beta, phi, sc = seg["turn"], seg["beta"], seg["chord_angle"], seg["scale"]
    if seg["forward"]:
        Zt = Z if turn > 0 else np.conj(Z)
        w = complex(*seg["p0"]) + sc * np.exp(1j * (phi - turn * beta)) * Zt
    else:
        # the standard form runs backwards from p1, turning the other way
        Zt = Z if -turn > 0 else np.conj(Z)
        w = complex(*seg["p1"]) + sc * np.exp(1j * (phi + np.pi + turn * beta)) * Zt
        w, rho = w[::-1], rho[::-1]
    curvature = turn / (sc * rho)
    return s * sc, w.real, w.imag, curvature


@dataclass(frozen=True)
class LACSpline:
    """A G1 spline of log-aesthetic segments (clothoids where no LAC fits).

    Attributes
    ----------
    points : ndarray, shape (N, 2)
    closed : bool
    alpha : float
    theta : ndarray
        Tangent angle at every point (input coordinates).
    segments : list of dict
        Per segment: ``kind`` ('lac' or 'clothoid') and its parameters.
    fallback_segments : tuple of int
        Start indices of the spans drawn as clothoids.
    sign : float
        Factor from input-coordinate to geometric curvature.
    seconds : float
    """

    points: np.ndarray
    closed: bool
    alpha: float
    theta: np.ndarray
    segments: list
    fallback_segments: tuple
    sign: float
    seconds: float = 0.0
    method: str = "lac-g1"
    iterations: int = 0
    extra: dict = field(default_factory=dict)

    @property
    def n_points(self):
        return len(self.points)

    def sample(self, samples=32):
        """Sample every segment at `samples` points equally spaced in arc
        length, both ends included. Returns a
        :class:`~attneave.stimuli.curves.metrics.SampledCurve`."""
        samples = check_samples(samples, len(self.segments))
        parts = []
        offset = 0.0
        for i, seg in enumerate(self.segments):
            if seg["kind"] == "lac":
                s, x, y, k = lac_segment_points(seg, samples)
            else:
                s = np.linspace(0.0, seg["L"], samples)
                x, y, _, k = clothoid_points(seg["x0"], seg["y0"], seg["theta0"], seg["k"], seg["dk"], s)
            parts.append((s + offset, x, y, k, np.full(samples, i)))
            offset += s[-1]
        s, x, y, k, g = (np.concatenate(v) for v in zip(*parts))
        return SampledCurve(s=s, x=x, y=y, curvature=self.sign * k, segment=g, theta=None, closed=self.closed)

    def metrics(self, samples=32):
        out = curve_metrics(self.sample(samples))
        out.update(iterations=0, fallback_segments=list(self.fallback_segments))
        return out


def lac_g1_spline(points, closed=True, alpha=0.0, tangents=None, y_down=True):
    """G1 spline of Yoshida-Saito log-aesthetic segments through points.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (y down).
    closed : bool
    alpha : float
        Slope of the log-curvature graph of every segment (default 0).
    tangents : array_like, shape (N,), optional
        Tangent angle at each point (input coordinates, radians). Default:
        the tangent of the circle through the point and its neighbours.
    y_down : bool
        Only the sign of reported curvature for open curves depends on it.

    Returns
    -------
    LACSpline
        With ``fallback_segments``: spans drawn as G1 clothoids because they
        need an inflection or no LAC of this alpha fits their triangle.

    Notes
    -----
    Curvature is monotone on every segment (LAC and clothoid alike) but only
    tangent-continuous (G1) at the points: curvature jumps there.
    """
    t0 = time.perf_counter()
    P = spline_points(points, closed)
    alpha = as_number(alpha, "alpha")  # a string or list raised a bare TypeError
    if tangents is None:
        theta = circle_tangents(P, closed)
    else:
        try:
            theta = np.asarray(tangents, dtype=float)
        except (TypeError, ValueError):  # strings, dicts: name the parameter, not float()
            theta = np.full(1, np.nan)
        if theta.shape != (len(P),) or not np.all(np.isfinite(theta)):
            raise InputError(f"tangents: expected {len(P)} finite angles")
    n = len(P)
    m = n if closed else n - 1
    segments, fallback = [], []
    for i in range(m):
        j = (i + 1) % n
        try:
            seg = lac_segment(P[i], theta[i], P[j], theta[j], alpha)
            seg["kind"] = "lac"
        except LACNotDrawable:
            c = g1_hermite(P[i, 0], P[i, 1], theta[i], P[j, 0], P[j, 1], theta[j])
            seg = {"kind": "clothoid", "x0": P[i, 0], "y0": P[i, 1], "theta0": theta[i],
                   "k": float(c["k"]), "dk": float(c["dk"]), "L": float(c["L"])}
            fallback.append(i)
        segments.append(seg)
    return LACSpline(
        points=P, closed=closed, alpha=float(alpha), theta=theta, segments=segments,
        fallback_segments=tuple(fallback), sign=geometric_sign(P, closed, y_down),
        seconds=time.perf_counter() - t0,
    )
