"""Clothoid (Euler spiral) segments: generalized Fresnel integrals, G1 Hermite
interpolation and evaluation.

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

import bisect
from math import factorial

import numpy as np
from scipy.special import fresnel

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

# Three regions of (a, b):
# - |a| < _A_SERIES and |b| <= _B_SERIES: Gauss-Legendre quadrature (the
#   integrand turns by at most |a|/2 + |b| <= 4 radians; 6-14 nodes reach
#   the rounding floor, and one exponential per node costs less than the
#   double power series used before);
# - |a| < _A_RECUR and |b| > _B_SERIES: power series in a over the moments of
#   exp(i b t), which come from a forward recurrence; its error growth
#   ~ m!/|b|^m is harmless only while the a-coefficients are tiny;
# - otherwise: the Fresnel closed form, whose higher moments lose about
#   (b/a)**2 ulp as a -> 0 (they only enter Jacobians).
_A_SERIES = 2.0
_A_RECUR = 0.5
_B_SERIES = 3.0
_NA_MAX = 22


def wrap_angle(angle):
    """Wrap angles to the interval (-pi, pi]."""
    angle = np.asarray(angle, dtype=float)
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)


def _terms_needed(x, nmax, tol=1e-17):
    """Smallest n with x**n / n! < tol (the first omitted term of a series
    in x), capped at nmax."""
    if x <= 0.0:
        return 1
    return min(bisect.bisect_right(_TERM_THRESHOLDS, x) + 1, nmax)


# x**n / n! < 1e-17  <=>  x < (1e-17 n!)**(1/n); increasing in n
_TERM_THRESHOLDS = [(1e-17 * factorial(n)) ** (1.0 / n) for n in range(1, 80)]


def _gauss_rule(q):
    """Gauss-Legendre nodes t on [0, 1] as the (q, 3) matrix of the phase's
    terms (t**2 / 2, t, 1), and the weights of the moments t**k, k < 3, as a
    (3, q) matrix."""
    x, w = np.polynomial.legendre.leggauss(q)
    t = 0.5 * (x + 1.0)
    return np.column_stack((0.5 * t * t, t, np.ones(q))), np.stack([0.5 * w * t**k for k in range(3)])


# a threaded BLAS (OpenBLAS) wakes its threads for products of a few 1e5
# multiply-adds and more (here 3.6e5 still ran on the calling thread, 6e5 took
# milliseconds on the loaded machine): the quadrature's products are cut into
# column blocks below that
_MATMUL_WORK = 1 << 17


def _narrow_matmul(A, B):
    """``A @ B`` for a small A and a wide B, in column blocks that a threaded
    BLAS computes on the calling thread."""
    cols = max(1, _MATMUL_WORK // A.size)
    if B.shape[1] <= cols:
        return A @ B
    out = np.empty((A.shape[0], B.shape[1]))
    for j in range(0, B.shape[1], cols):
        out[:, j : j + cols] = A @ B[:, j : j + cols]
    return out


# Gauss-Legendre nodes by the phase bound p = |a|/2 + |b| of a family: the
# smallest rule whose error against mpmath quadrature stayed below 4e-16 on
# random (a, b) with that bound (at p = 4, the series region's corner, 13
# nodes already did); few nodes for the tiny phases of dense sampling
_GAUSS_BOUNDS = (0.05, 0.1, 0.25, 0.5, 1.0, 2.0)
_GAUSS_RULES = [_gauss_rule(q) for q in (6, 7, 8, 9, 10, 12, 14)]


def _moments_fresnel(a, b, nk):
    """I_k(a, b) for |a| not small, via the Fresnel integrals C and S."""
    sgn = np.sign(a)
    a = np.abs(a)
    b = b * sgn
    sq = np.sqrt(np.pi * a)
    u = np.concatenate([b / sq, (a + b) / sq])
    S, C = fresnel(u)
    m = a.size
    E = (C[m:] - C[:m]) + 1j * (S[m:] - S[:m])
    # completing the square: a t^2/2 + b t = (pi/2) u^2 - b^2/(2a)
    I0 = (np.pi / sq) * np.exp(-0.5j * np.pi * (b / sq) ** 2) * E
    out = [I0]
    if nk > 1:
        e1 = np.exp(1j * (0.5 * a + b))
        # d/dt exp(iq) = i (a t + b) exp(iq) and d/dt (t exp(iq)) give the
        # recurrences for the first and second moments
        I1 = (-1j * (e1 - 1.0) - b * I0) / a
        out.append(I1)
        if nk > 2:
            out.append((-1j * (e1 - I0) - b * I1) / a)
    out = np.stack(out)
    return np.where(sgn < 0, np.conj(out), out)


def _moments_gauss(a, b, nk, c, p):
    """I_k(a, b) exp(i c) for small |a| and |b|: Gauss-Legendre quadrature
    of an integrand that is entire and turns by at most a few radians (one
    complex exponential per node and segment, two small matrix products).
    `p` bounds the range of the phase, |a|/2 + |b|."""
    t3, tw = _GAUSS_RULES[bisect.bisect_left(_GAUSS_BOUNDS, p)]
    abc = np.empty((3, a.size))
    abc[0], abc[1], abc[2] = a, b, 0.0 if c is None else c
    # the phase at every node as one small product, exponentiated in place,
    # and the weighted sums as a real product over (real, imaginary) pairs:
    # a few numpy calls whatever the number of segments
    z = np.zeros((t3.shape[0], a.size), dtype=complex)
    small = 2 * a.size * tw.size <= _MATMUL_WORK  # both products in one block
    z.imag = t3 @ abc if small else _narrow_matmul(t3, abc)
    np.exp(z, out=z)
    w = tw[:nk]
    return (w @ z.view(float) if small else _narrow_matmul(w, z.view(float))).view(complex)


_A_COEF = np.array([(0.5j) ** n / factorial(n) for n in range(_NA_MAX)])


def _moments_recurrence(a, b, nk):
    """I_k(a, b) for small |a| and larger |b|: series in a over the moments
    M_m(b) = int_0^1 t^m exp(i b t) dt computed by forward recurrence."""
    na = _terms_needed(0.5 * float(np.max(np.abs(a))), _NA_MAX)
    mmax = 2 * (na - 1) + nk - 1
    e = np.exp(1j * b)
    ib = 1j * b
    M = np.empty((mmax + 1, a.size), dtype=complex)
    M[0] = (e - 1.0) / ib
    for m in range(1, mmax + 1):
        M[m] = (e - m * M[m - 1]) / ib
    apow = a[None, :] ** np.arange(na)[:, None] * _A_COEF[:na, None]
    out = np.empty((nk, a.size), dtype=complex)
    for k in range(nk):
        out[k] = np.sum(apow * M[k : k + 2 * na : 2], axis=0)
    return out


def _moments(a, b, nk=3, c=None):
    """Complex moments I_k(a, b) = int_0^1 t^k exp(i(a t^2/2 + b t)) dt,
    k < nk, for 1-D float arrays a, b, times exp(i c) when the array `c`
    is given. Returns an (nk, M) complex array."""
    absa = np.abs(a)
    absb = np.abs(b)
    bound = 0.5 * absa
    bound += absb  # the phase's range on [0, 1] is at most |a|/2 + |b|
    p = float(np.maximum.reduce(bound)) if a.size else 0.0
    if p < 1.0:  # then |a| < 2 and |b| < 1: all in the quadrature region
        return _moments_gauss(a, b, nk, c, p)
    smallb = absb <= _B_SERIES
    series = (absa < _A_SERIES) & smallb
    if series.all():
        return _moments_gauss(a, b, nk, c, p)
    recur = (absa < _A_RECUR) & ~smallb
    big = ~(series | recur)
    if big.all():
        out = _moments_fresnel(a, b, nk)
        return out if c is None else out * np.exp(1j * c)
    out = np.empty((nk, a.size), dtype=complex)
    for mask, fn in ((big, _moments_fresnel), (recur, _moments_recurrence)):
        if mask.any():
            out[:, mask] = fn(a[mask], b[mask], nk)
    if c is not None:
        out *= np.exp(1j * c)
    if series.any():
        p = float(bound[series].max())
        out[:, series] = _moments_gauss(a[series], b[series], nk, None if c is None else c[series], p)
    return out


def fresnel_moments(a, b, c=0.0, nk=3):
    """Generalized Fresnel integrals X_k, Y_k.

    ``X_k(a, b, c) = int_0^1 t**k cos(a t**2 / 2 + b t + c) dt`` and
    ``Y_k`` the same with ``sin``, for ``k = 0 .. nk-1``.

    Parameters
    ----------
    a, b, c : array_like
        Broadcast together.
    nk : {1, 2, 3}
        Number of moments.

    Returns
    -------
    X, Y : ndarray
        Shape ``(nk,) + broadcast shape``.

    Notes
    -----
    For ``|a| < 2`` and ``|b| <= 3`` Gauss-Legendre quadrature (6 to 14
    nodes, by the phase bound ``|a|/2 + |b|``); for ``|a| < 0.5`` and
    ``|b| > 3`` a power series in ``a`` whose moments of ``exp(i b t)`` come from a forward recurrence; otherwise the
    Fresnel integrals (:func:`scipy.special.fresnel`) after completing the
    square, with recurrences for ``k = 1, 2``. ``X_0, Y_0`` are accurate to
    about 1e-14 absolute for ``|a|, |b|`` up to tens; ``X_2, Y_2`` lose
    about ``(b/a)**2`` ulp more in the Fresnel region.

    References
    ----------
    .. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids", Math.
           Meth. Appl. Sci. 38(5), 881-897, 2015 (Section 3).
    """
    if nk not in (1, 2, 3):
        raise ValueError("nk must be 1, 2 or 3")
    a, b, c = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, c)))
    shape = a.shape
    I = _moments(a.ravel(), b.ravel(), nk, c.ravel())
    return I.real.reshape((nk,) + shape), I.imag.reshape((nk,) + shape)


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
    I = _moments(2.0 * A, NN[0], 3 if derivatives else 1, phi0)
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
        I = _moments(2.0 * A, delta - A, 3, phi0)
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
        I0 = _moments((dk.ravel() * sf) * sf, k.ravel() * sf, 1, t0.ravel())[0] * sf
        x = x0 + I0.real.reshape(shape)
        y = y0 + I0.imag.reshape(shape)
    theta = t0 + k * s + 0.5 * dk * s * s
    return x, y, theta, k + dk * s
