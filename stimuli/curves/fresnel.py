"""Generalized Fresnel integrals: the moments int_0^1 t^k exp(i(a t^2/2 + b t + c)) dt
that a clothoid segment's position and its derivatives are made of.

Used by the clothoid segments of :mod:`attneave.stimuli.curves.euler` (G1
Hermite interpolation, the QIC spline's Newton steps) and by
:func:`attneave.stimuli.curves.euler.fresnel_moments`, their public form.

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

__all__ = ["complex_moments", "fresnel_moments"]

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


def complex_moments(a, b, nk=3, c=None):
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
    I = complex_moments(a.ravel(), b.ravel(), nk, c.ravel())
    return I.real.reshape((nk,) + shape), I.imag.reshape((nk,) + shape)
