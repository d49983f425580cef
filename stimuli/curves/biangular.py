"""Two-point G1 Hermite interpolation in biangular coordinates, after
Ziatdinov, Kim & Nabiyev (2015), and its comparison with the clothoid G1
Hermite curve on the same end conditions.

Biangular coordinates of a point X with respect to the poles P0 and P1 are
the two angles ``t0 = angle(P1 - P0, X - P0)`` and ``t1 = angle(P0 - P1,
X - P1)``; by the law of sines ``|X - P0| = |P1 - P0| sin t1 / sin(t0 + t1)``.
A circular arc through P0 and P1 is ``t0 + t1 = const`` (the inscribed angle
theorem). Given the tangent angles at the ends, ``phi0`` (at P0, from the
chord) and ``phi1`` (at P1, from the reversed chord), the curve used here is
the straight line in the biangular plane through ``(phi0, 0)`` and
``(0, phi1)``:

    t0 / phi0 + t1 / phi1 = 1,

traced by ``t0 = phi0 (1 - u)``, ``t1 = phi1 u``, u in [0, 1]. It leaves P0
along ``phi0`` and reaches P1 along ``phi1`` (G1), and it is the circular arc
when ``phi0 = phi1``. **Derived here**: the paper's own family could not be
consulted; this is the simplest biangular curve that meets the G1 data and
reproduces the circle. Its curvature, in closed form from the derivatives of
the parametrisation, is monotone only for part of the C-shaped end
conditions (on a 61 x 61 grid of ``phi0, phi1`` with ``phi0 + phi1 < pi``:
84 % of the cases with ``max/min <= 1.5``, 29 % of those with a ratio over
5); :func:`biangular_g1` says which (``monotone``), and
:func:`compare_g1_hermite` sets it beside the clothoid, whose curvature is
always monotone (linear).

Points are ``(x, y)`` in any Cartesian coordinates (image pixels: y down);
angles from +x towards +y; curvature is ``d theta / ds`` in those
coordinates.

References
----------
.. [1] R. Ziatdinov, T. Kim and R. I. Nabiyev, "Two-point G1 Hermite
       interpolation in biangular coordinates", Journal of Computational and
       Applied Mathematics 287, 97-110, 2015.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.euler import clothoid_points, g1_hermite
from attneave.stimuli.curves.points import end_angles
from attneave.stimuli.errors import InputError

__all__ = ["biangular_g1", "compare_g1_hermite"]

_GL_T, _GL_W = np.polynomial.legendre.leggauss(8)


def _frame(p0, theta0, p1, theta1):
    p0 = np.asarray(p0, dtype=float).reshape(2)
    p1 = np.asarray(p1, dtype=float).reshape(2)
    if not (np.all(np.isfinite(p0)) and np.all(np.isfinite(p1)) and np.isfinite(theta0) and np.isfinite(theta1)):
        raise InputError("biangular_g1: points and angles must be finite")
    r, chord, f0, f1 = end_angles(p0, theta0, p1, theta1)
    if r == 0:
        raise InputError("biangular_g1: the two end points coincide")
    if not f0 * f1 < 0 or abs(f0) + abs(f1) >= np.pi:
        raise InputError(
            "biangular_g1: the end tangents must lie on the same side of the chord and meet in front of "
            f"it (a C-shaped curve with phi0 + phi1 < pi); got phi0 = {f0:.4g}, phi1 = {-f1:.4g} rad"
        )
    side = 1.0 if f0 > 0 else -1.0
    return p0, r, chord, side, abs(f0), abs(f1)


def _derivatives(u, a0, a1):
    """z, z', z'' of the unit-chord curve at parameters u (z = rho e^{i t0})."""
    d = a1 - a0
    N = np.sin(a1 * u)
    g = a0 + d * u
    D = np.sin(g)
    N1, N2 = a1 * np.cos(a1 * u), -(a1**2) * N
    D1, D2 = d * np.cos(g), -(d**2) * D
    rho = N / D
    rho1 = (N1 * D - N * D1) / D**2
    rho2 = (N2 * D - N * D2) / D**2 - 2 * D1 * (N1 * D - N * D1) / D**3
    w = -a0  # d t0 / du
    e = np.exp(1j * a0 * (1.0 - u))
    return rho * e, (rho1 + 1j * rho * w) * e, (rho2 + 2j * rho1 * w - rho * w * w) * e


def biangular_g1(p0, theta0, p1, theta1, n=65):
    """The biangular G1 Hermite curve between two points (see the module notes).

    Parameters
    ----------
    p0, p1 : (x, y)
        End points.
    theta0, theta1 : float
        Tangent angles at the ends (radians, from +x towards +y), the
        direction of travel from p0 to p1.
    n : int
        Samples, equally spaced in the biangular parameter u, ends included.

    Returns
    -------
    dict
        ``x, y, s`` (arc length from p0), ``curvature`` (d theta/ds),
        ``length``, ``phi0, phi1`` (end angles to the chord, radians),
        ``monotone`` (whether the curvature is monotone along the curve,
        judged on the samples) and ``u``.

    Raises
    ------
    InputError
        Coincident points, non-finite input, or end tangents that do not
        make a C-shaped curve (on opposite sides of the chord, or meeting
        behind it).

    Examples
    --------
    >>> c = biangular_g1((0, 0), np.pi / 4, (2, 0), -np.pi / 4)   # a circular arc
    >>> bool(np.allclose(c["curvature"], -1 / np.sqrt(2)))   # turning clockwise in (x, y)
    True
    """
    n = int(n)
    if n < 2:
        raise InputError(f"n: expected at least 2 samples, got {n}")
    p0, r, chord, side, a0, a1 = _frame(p0, theta0, p1, theta1)
    u = np.linspace(0.0, 1.0, n)
    z, z1, z2 = _derivatives(u, a0, a1)
    k = (np.conj(z1) * z2).imag / np.abs(z1) ** 3
    # arc length: 8-point Gauss-Legendre of |z'| between samples
    lo, hi = u[:-1], u[1:]
    q = 0.5 * (lo + hi)[:, None] + 0.5 * (hi - lo)[:, None] * _GL_T
    speed = np.abs(_derivatives(q.ravel(), a0, a1)[1]).reshape(q.shape)
    s = r * np.r_[0.0, np.cumsum((speed @ _GL_W) * 0.5 * (hi - lo))]
    if side < 0:
        z, k = np.conj(z), -k
    w = complex(*p0) + r * np.exp(1j * chord) * z
    w[-1] = complex(*np.asarray(p1, dtype=float))  # the end point exactly
    # similarity: rotation and translation keep d theta/ds, scaling by r divides it
    curvature = k / r
    dk = np.diff(curvature)
    tol = 1e-10 * float(np.max(np.abs(curvature)))
    return {
        "x": w.real, "y": w.imag, "s": s, "curvature": curvature, "length": float(s[-1]),
        "phi0": a0, "phi1": a1, "u": u, "monotone": bool(np.all(dk <= tol) or np.all(dk >= -tol)),
    }


def compare_g1_hermite(p0, theta0, p1, theta1, n=65):
    """The biangular curve and the clothoid (Bertolazzi & Frego's G1 Hermite
    solution, :func:`attneave.stimuli.curves.euler.g1_hermite`) on the same end
    conditions.

    Returns
    -------
    dict
        ``biangular`` and ``clothoid`` (each with ``x, y, s, curvature,
        length, monotone``), ``max_distance`` (largest distance from a
        biangular sample to the clothoid's samples, a dense one-sided
        Hausdorff distance: each sample's foot of the perpendicular on the
        clothoid, by Newton from the nearest of 8 n clothoid samples) and
        ``length_ratio`` (biangular / clothoid).

    Examples
    --------
    >>> c = compare_g1_hermite((0, 0), 0.5, (3, 0), -0.5)   # symmetric: both the same arc
    >>> c["max_distance"] < 1e-9
    True
    """
    b = biangular_g1(p0, theta0, p1, theta1, n)
    p0 = np.asarray(p0, dtype=float)
    p1 = np.asarray(p1, dtype=float)
    c = g1_hermite(p0[0], p0[1], theta0, p1[0], p1[1], theta1)
    L = float(c["L"])
    k0, dk = float(c["k"]), float(c["dk"])
    sc = np.linspace(0.0, L, 8 * n)
    x, y, _, k = clothoid_points(p0[0], p0[1], theta0, k0, dk, sc)
    # distance from each biangular sample to the clothoid: nearest sample,
    # then Newton on (c(s) - X) . t(s) = 0 (the foot of the perpendicular)
    X = b["x"] + 1j * b["y"]
    sj = sc[np.argmin(np.abs(X[:, None] - (x + 1j * y)[None, :]), axis=1)]
    for _ in range(4):
        cx, cy, th, kk = clothoid_points(p0[0], p0[1], theta0, k0, dk, sj)
        e = (cx + 1j * cy) - X
        t = np.exp(1j * th)
        f = (np.conj(t) * e).real
        fp = 1.0 + kk * (np.conj(1j * t) * e).real
        sj = np.clip(sj - f / fp, 0.0, L)
    cx, cy, _, _ = clothoid_points(p0[0], p0[1], theta0, k0, dk, sj)
    dist = np.abs(cx + 1j * cy - X)
    clothoid = {"x": x, "y": y, "s": sc, "curvature": k, "length": L, "monotone": True}
    return {"biangular": b, "clothoid": clothoid, "max_distance": float(dist.max()),
            "length_ratio": b["length"] / L}
