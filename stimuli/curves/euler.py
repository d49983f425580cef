"""Clothoid (Euler spiral) segments: G1 Hermite interpolation and evaluation
(their generalized Fresnel integrals are in :mod:`attneave.stimuli.curves.fresnel`;
:func:`fresnel_moments` is re-exported here).

A clothoid is a curve whose curvature is linear in arc length,
``kappa(s) = k + dk * s``, so its tangent angle is quadratic,
``theta(s) = theta0 + k*s + dk*s**2/2``. Every function here is vectorised
over many segments at once.

Coordinates are plain Cartesian: angles are measured from the +x axis towards
the +y axis and curvature is ``d theta / d s``. With image pixels (y down) that
means positive angles and curvature turn clockwise *on the screen*; the spline
layer (:mod:`attneave.stimuli.curves.splines`) converts to the project's geometric sign.

The G1 Hermite problem (given two points and a tangent angle at each, find
``k``, ``dk`` and the length ``L``) is solved as in Bertolazzi & Frego (2015):
in the frame of the chord, with ``phi0``, ``phi1`` the end angles relative to
the chord (wrapped to (-pi, pi]) and ``delta = phi1 - phi0``, the tangent
angle at ``tau = s / L`` is ``A tau**2 + (delta - A) tau + phi0`` and the
single unknown ``A`` solves ``g(A) = Y0(2A, delta - A, phi0) = 0``. Then
``L = r / X0(2A, delta - A, phi0)``, ``k = (delta - A) / L`` and
``dk = 2 A / L**2``. Newton's method from their polynomial initial guess
converges in a few iterations for every admissible pair of angles.

References
----------
.. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids",
       Mathematical Methods in the Applied Sciences 38(5), 881-897, 2015.
       https://doi.org/10.1002/mma.3114
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.fresnel import complex_moments, fresnel_moments  # fresnel_moments: re-exported
from attneave.stimuli.curves.qic import kernel as qic_kernel

__all__ = [
    "fresnel_moments",
    "g1_hermite",
    "clothoid_points",
    "guess_A",
    "segment_state",
    "add_derivatives",
    "wrap_angle",
]

def wrap_angle(angle):
    """Wrap angles to the interval (-pi, pi]."""
    angle = np.asarray(angle, dtype=float)
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)



_CF = (2.989696028701907, 0.716228953608281, -0.458969738821509,
       -0.502821153340377, 0.261062141752652, -0.045854475238709)


def guess_A(phi0, phi1):
    """Initial guess for the G1 parameter A (Bertolazzi & Frego 2015, eq. 19).

    A fitted polynomial refining the small-angle root ``3 (phi0 + phi1)``.
    """
    X = np.asarray(phi0) / np.pi
    Y = np.asarray(phi1) / np.pi
    xy = X * Y
    X2, Y2 = X * X, Y * Y
    return (np.asarray(phi0) + np.asarray(phi1)) * (
        _CF[0] + xy * (_CF[1] + xy * _CF[2]) + (_CF[3] + xy * _CF[4]) * (X2 + Y2)
        + _CF[5] * (X2 * X2 + Y2 * Y2)
    )


def segment_state(phi0, phi1, A, r, derivatives=True):
    """Everything about a family of segments at a (not necessarily solved) A.

    ``phi0``, ``phi1``: end angles relative to the chord; ``r``: chord
    lengths. Returns a dict with ``G`` (the closure residual Y0), ``X0``,
    ``L``, ``k0``, ``k1`` (curvature at start and end; also stacked as
    ``K``, shape (2, M)), the given ``phi0`` and ``delta = phi1 - phi0``
    and, with `derivatives`, ``G_A``, ``G_0``, ``G_1``
    (partial derivatives of G with respect to A and the two end angles) and,
    for q in k0, k1, L, the derivatives along the closure constraint (A
    eliminated by the implicit function theorem): ``q_t0``, ``q_t1`` with
    respect to the start and end tangent angle, and ``q_r``, the
    first-order change that brings G to zero at fixed angles. At a solved A
    (G = 0) the ``q_t*`` are the derivatives of the G1 Hermite solution.
    ``derivatives='later'`` keeps what :func:`add_derivatives` needs to add
    them without recomputing the moments (Newton's line search rejects or
    finishes at many states).
    """
    delta = phi1 - phi0
    # N0 = delta - A and N1 = delta + A, stacked: k0 and k1 in one division
    NN = delta + _MINUS_PLUS * A
    I = complex_moments(2.0 * A, NN[0], 3 if derivatives else 1, phi0)
    X0, Y0 = I[0].real, I[0].imag
    L = r / X0
    K = NN / L
    st = {"G": Y0, "X0": X0, "L": L, "K": K, "k0": K[0], "k1": K[1], "phi0": phi0, "delta": delta}
    if derivatives:
        st["pending"] = (I, NN, r)
        if derivatives != "later":
            add_derivatives(st)
    return st


# per unit of (theta0, theta1, r) the k0 and k1 rows of the state's
# derivatives gain Xr * (_K_BASE -+ dA), dA the change of A along G
_K_BASE = np.array([-1.0, 1.0, 0.0])[:, None]
_K_SIGN = np.array([-1.0, 1.0])[:, None, None]
_MINUS_PLUS = _K_SIGN[:, 0]


def add_derivatives(st, full=True):
    """Add the derivatives of :func:`segment_state` to a state computed with
    ``derivatives='later'`` (in place; returns `st`).

    Always adds ``dK``, shape (2, 3, M): the derivatives of (k0, k1) by
    (theta0, theta1, r), and ``dA``, shape (3, M): those of A along the
    closure constraint. With `full`, also the named ``G_*``, ``k0_*``,
    ``k1_*`` and ``L_*`` of :func:`segment_state` (Newton on the nodes needs
    only the stacked ones).
    """
    pending = st.pop("pending", None)
    if pending is None:
        return st
    I, NN, r = pending
    X0, Y0 = st["X0"], st["G"]
    X1, Y1, X2, Y2 = I[1].real, I[1].imag, I[2].real, I[2].imag
    # (a, b, c) = (2A, delta - A, phi0) move by (2, -1, 0) per unit of A,
    # (0, -1, 1) per unit of theta0 and (0, 1, 0) per unit of theta1;
    # dX0/d(a, b, c) = -(Y2/2, Y1, Y0) and dY0/d(a, b, c) = (X2/2, X1, X0)
    gA = X2 - X1
    # rows: dG per unit of theta0, theta1 and G itself; divided by -dG/dA,
    # the change of A that keeps G (or brings it to 0)
    dA = np.empty((3, X0.size))
    np.subtract(X0, X1, out=dA[0])
    dA[1], dA[2] = X1, Y0
    if full:
        st["G_A"], st["G_0"], st["G_1"] = gA, dA[0].copy(), X1
    dA *= -1.0 / gA
    st["dA"] = dA
    # dX0 along G = const per unit of theta0, theta1 and to G = 0
    dX = (Y1 - Y2) * dA
    dX[0] += Y1 - Y0
    dX[1] -= Y1
    # k0 = N0 X0 / r and k1 = N1 X0 / r with N0 = delta - A, N1 = delta + A
    dK = (NN / r)[:, None] * dX
    dK += (_K_BASE + _K_SIGN * dA) * (X0 / r)
    st["dK"] = dK
    if full:
        st["k0_t0"], st["k0_t1"], st["k0_r"] = dK[0]
        st["k1_t0"], st["k1_t1"], st["k1_r"] = dK[1]
        st["L_t0"], st["L_t1"], st["L_r"] = (-st["L"] / X0) * dX
    return st


class ClothoidConvergenceError(ValueError):
    """The G1 Newton iteration did not converge."""


def g1_hermite(x0, y0, theta0, x1, y1, theta1, tol=1e-14, max_iter=20, derivatives=False):
    """Clothoid segments through two points with given end tangent angles.

    Vectorised: every argument broadcasts.

    Parameters
    ----------
    x0, y0, theta0 : array_like
        Start point and tangent angle (radians, from +x towards +y).
    x1, y1, theta1 : array_like
        End point and tangent angle.
    tol : float
        Newton stops when ``|g(A)| <= tol`` for every segment.
    max_iter : int
        Bound on Newton iterations.
    derivatives : bool
        Also return the derivatives of the start and end curvature, of
        ``dk`` and of ``L`` with respect to ``theta0`` and ``theta1``
        (implicit function theorem on the G1 system).

    Returns
    -------
    dict
        ``k`` (start curvature), ``dk`` (curvature rate), ``L`` (length),
        ``k1`` (end curvature ``k + dk L``), ``A``, ``iterations``; with
        `derivatives` also ``dk0_dtheta0``, ``dk0_dtheta1``,
        ``dk1_dtheta0``, ``dk1_dtheta1``, ``dL_dtheta0``, ``dL_dtheta1``,
        ``ddk_dtheta0``, ``ddk_dtheta1``.

    Raises
    ------
    ValueError
        If the two points coincide or the inputs are not finite.
    ClothoidConvergenceError
        If Newton does not reach `tol` in `max_iter` iterations.

    Notes
    -----
    The end angles are taken relative to the chord and wrapped to
    (-pi, pi], which selects the solution of Bertolazzi & Frego (the one
    without extra full turns).

    References
    ----------
    .. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids",
           Math. Meth. Appl. Sci. 38(5), 881-897, 2015.

    Examples
    --------
    >>> import numpy as np
    >>> r = g1_hermite(0, 0, 0, 1, 1, np.pi / 2)   # a quarter circle
    >>> round(float(r["k"]), 12), round(float(r["dk"]), 12)
    (1.0, 0.0)
    """
    args = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x0, y0, theta0, x1, y1, theta1)))
    shape = args[0].shape
    x0, y0, t0, x1, y1, t1 = (v.ravel() for v in args)
    if not all(np.isfinite(v).all() for v in (x0, y0, t0, x1, y1, t1)):
        raise ValueError("g1_hermite: inputs must be finite")
    dx, dy = x1 - x0, y1 - y0
    r = np.hypot(dx, dy)
    if (r == 0).any():
        raise ValueError("g1_hermite: the two end points coincide")
    phi = np.arctan2(dy, dx)
    phi0 = wrap_angle(t0 - phi)
    phi1 = wrap_angle(t1 - phi)
    delta = phi1 - phi0
    A = guess_A(phi0, phi1)
    it = 0
    while True:
        I = complex_moments(2.0 * A, delta - A, 3, phi0)
        g = I[0].imag
        if np.all(np.abs(g) <= tol) or it >= max_iter:
            break
        A = A - g / (I[2].real - I[1].real)
        it += 1
    if not np.all(np.abs(g) <= tol):
        raise ClothoidConvergenceError(
            f"g1_hermite: Newton did not converge in {max_iter} iterations "
            f"(max |g| = {np.max(np.abs(g)):.3g})"
        )
    st = segment_state(phi0, phi1, A, r, derivatives=derivatives)
    L = st["L"]
    out = {
        "k": st["k0"], "dk": 2.0 * A / L**2, "L": L, "k1": st["k1"], "A": A,
    }
    if derivatives:
        out.update(
            dk0_dtheta0=st["k0_t0"], dk0_dtheta1=st["k0_t1"],
            dk1_dtheta0=st["k1_t0"], dk1_dtheta1=st["k1_t1"],
            dL_dtheta0=st["L_t0"], dL_dtheta1=st["L_t1"],
            # dk = (k1 - k0) / L
            ddk_dtheta0=(st["k1_t0"] - st["k0_t0"]) / L - (st["k1"] - st["k0"]) / L**2 * st["L_t0"],
            ddk_dtheta1=(st["k1_t1"] - st["k0_t1"]) / L - (st["k1"] - st["k0"]) / L**2 * st["L_t1"],
        )
    out = {key: (v.reshape(shape) if isinstance(v, np.ndarray) else v) for key, v in out.items()}
    out["iterations"] = it
    return out


def clothoid_points(x0, y0, theta0, k, dk, s, compiled=True):
    """Points of clothoids at arc lengths `s`.

    Parameters
    ----------
    x0, y0, theta0 : array_like
        Start point and tangent angle.
    k, dk : array_like
        Start curvature and curvature rate.
    s : array_like
        Arc lengths from the start; broadcast with the other arguments.
    compiled : bool
        Use the compiled kernel where it was built (default). It gives NaN
        for a clothoid whose tangent turns by more than about 8000 rad
        (never a spline's segment); False: the numpy evaluation, which has
        no such bound.

    Returns
    -------
    x, y, theta, curvature : ndarray
        Closed form ``x + i y = x0 + i y0 + s exp(i theta0) I_0(dk s**2, k s)``
        with the Fresnel integrals of :func:`fresnel_moments`.
    """
    x0, y0, t0, k, dk, s = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (x0, y0, theta0, k, dk, s))
    )
    shape = s.shape
    sf = s.ravel()
    if compiled and qic_kernel.LIB is not None:
        # the compiled kernel: the same integral summed per point, without numpy's temporaries
        x, y = qic_kernel.clothoid_xy(*(np.ascontiguousarray(v).ravel() for v in (x0, y0, t0, k, dk, sf)))
        x, y = x.reshape(shape), y.reshape(shape)
    else:
        I0 = complex_moments((dk.ravel() * sf) * sf, k.ravel() * sf, 1, t0.ravel())[0] * sf
        x = x0 + I0.real.reshape(shape)
        y = y0 + I0.imag.reshape(shape)
    theta = t0 + k * s + 0.5 * dk * s * s
    return x, y, theta, k + dk * s
