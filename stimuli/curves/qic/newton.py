"""The Newton solver behind the QIC spline: node tangent angles such that the
clothoid segments between consecutive points join with curvature continuity.

The unknowns are the tangent angles at the nodes. Given them, each segment is
the G1 Hermite clothoid of Bertolazzi & Frego (2015) between its two points
(:mod:`attneave.stimuli.curves.euler`), whose curvature at both ends is a function of
the two end angles; curvature continuity at every node is one equation per
node. The node angles and, per segment, the Bertolazzi-Frego parameter A with
its closure equation are solved by damped Newton; eliminating A segment by
segment (implicit function theorem) leaves a tridiagonal system in the node
angles, cyclic for closed curves. A node may instead be *held*: its tangent
stays at its initial value and its curvature equation is dropped (a G1 node,
where curvature may jump). Newton starts from the solution of the
small-angle (cubic) approximation of the same equations, a linear
tridiagonal system (:func:`small_angle_start`). Everything is vectorised
over segments; the work per iteration is O(N).

References
----------
.. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids", Math. Meth.
       Appl. Sci. 38(5), 881-897, 2015.
.. [2] E. Bertolazzi and M. Frego, "Interpolating clothoid splines with
       curvature continuity", Math. Meth. Appl. Sci. 41(4), 1723-1737, 2018.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dgtsv as _dgtsv

from attneave.stimuli.curves.euler import add_derivatives, guess_A, segment_state

__all__ = ["NewtonResult", "small_angle_start", "solve_nodes", "solve_tridiagonal", "tangent_range"]


def _residual(st, closed, free_start, free_end, prev, held):
    k0, k1 = st["k0"], st["k1"]
    if closed:
        F = k1[prev] - k0
    else:
        F = np.empty(k0.size + 1)
        np.subtract(k1[:-1], k0[1:], out=F[1:-1])
        F[0] = k0[0] if free_start else 0.0
        F[-1] = k1[-1] if free_end else 0.0
    if held is not None:
        F[held] = 0.0
    return F


def _linear_system(st, F, closed, free_start, free_end, prev, held):
    """Tridiagonal Newton system in the node-angle increments, A eliminated.
    A held node's row is the identity: its increment stays zero."""
    dK = st["dK"]  # (k0, k1) by (theta0, theta1, r)
    if closed:
        k1p = dK[1][:, prev]  # the previous segment's end, at every node
        sub = k1p[0]
        diag = k1p[1] - dK[0, 0]
        sup = -dK[0, 1]
        rhs = dK[0, 2] - F
        rhs -= k1p[2]
    else:
        (k0t0, k0t1, k0r), (k1t0, k1t1, k1r) = dK
        n = k0t0.size + 1
        sub = np.zeros(n)
        diag = np.ones(n)
        sup = np.zeros(n)
        rhs = np.zeros(n)
        sub[1:-1] = k1t0[:-1]
        np.subtract(k1t1[:-1], k0t0[1:], out=diag[1:-1])
        np.negative(k0t1[1:], out=sup[1:-1])
        rhs[1:-1] = -(F[1:-1] + k1r[:-1] - k0r[1:])
        if free_start:
            diag[0], sup[0], rhs[0] = k0t0[0], k0t1[0], -(F[0] + k0r[0])
        if free_end:
            sub[-1], diag[-1], rhs[-1] = k1t0[-1], k1t1[-1], -(F[-1] + k1r[-1])
    if held is not None:
        sub[held], diag[held], sup[held], rhs[held] = 0.0, 1.0, 0.0, 0.0
    return sub, diag, sup, rhs


def solve_tridiagonal(sub, diag, sup, rhs, cyclic):
    """Solve a (cyclic) tridiagonal system.

    ``sub[i]`` multiplies ``x[i-1]`` and ``sup[i]`` multiplies ``x[i+1]``
    (indices modulo n when `cyclic`). LAPACK's ``dgtsv`` (Gaussian
    elimination with partial pivoting), with Sherman-Morrison for the two
    corner entries of a cyclic system. Returns NaNs if the matrix is
    singular.

    Examples
    --------
    >>> import numpy as np
    >>> x = solve_tridiagonal(np.ones(4), 4 * np.ones(4), np.ones(4), np.arange(4.0), True)
    >>> J = 4 * np.eye(4) + np.roll(np.eye(4), 1, 1) + np.roll(np.eye(4), -1, 1)
    >>> bool(np.allclose(J @ x, np.arange(4.0)))
    True
    """
    n = diag.size
    if not cyclic or n < 3:
        if n == 1:
            return rhs / diag
        *_, x, info = _dgtsv(sub[1:], diag, sup[:-1], rhs[:, None])
        return x[:, 0] if info == 0 else np.full(n, np.nan)
    top, bottom, d0 = float(sub[0]), float(sup[-1]), float(diag[0])  # J[0, n-1], J[n-1, 0]
    gamma = -d0 if d0 != 0 else 1.0
    d = diag.copy()
    d[0] = d0 - gamma
    d[-1] -= top * bottom / gamma
    # both right-hand sides in one call: the system's and the correction's
    b = np.zeros((2, n))
    b[0] = rhs
    b[1, 0], b[1, -1] = gamma, bottom
    *_, yz, info = _dgtsv(sub[1:], d, sup[:-1], b.T, 0, 1, 0, 1)
    if info != 0:
        return np.full(n, np.nan)
    y, z = yz.T
    f = top / gamma
    vy = y[0] + f * y[-1]
    vz = z[0] + f * z[-1]
    return y - (vy / (1.0 + vz)) * z


def small_angle_start(p0i, p1i, r, closed, free_start=True, free_end=True, held=None):
    """Node-angle increments that make the spline G2 to first order in the
    angles: the starting point of :func:`solve_nodes`.

    For small end angles (relative to the chord) a clothoid segment is close
    to the cubic whose tangent angle is ``phi0 + (delta - A) tau + A tau**2``
    with ``A = 3 (phi0 + phi1)``, so its end curvatures are
    ``k0 = -(4 phi0 + 2 phi1) / r`` and ``k1 = (2 phi0 + 4 phi1) / r``.
    Curvature continuity at every free node (and zero curvature at free
    ends) is then a linear tridiagonal system, cyclic for closed curves,
    diagonally dominant. Held nodes and given end tangents keep a zero
    increment. Its error is third order in the angles, so Newton starts
    far closer than from the circle tangents (on smooth curves through 30
    points, a relative curvature jump of about 2e-3 instead of 0.6: two
    iterations instead of three).

    Parameters
    ----------
    p0i, p1i, r, closed, free_start, free_end, held
        As in :func:`solve_nodes`.

    Returns
    -------
    ndarray, shape (N,)

    Examples
    --------
    A regular polygon's circle tangents are already G2: nothing moves.

    >>> import numpy as np
    >>> p = np.full(6, -np.pi / 6)
    >>> bool(np.allclose(small_angle_start(p, -p, np.ones(6), True), 0))
    True
    """
    w = 2.0 / r
    s = p0i + p1i
    c0 = (s + p0i) * w  # 2 phi0 + phi1 and its weight, start of segment
    c1 = (s + p1i) * w  # phi0 + 2 phi1, end of segment
    if closed:
        prev = np.arange(-1, w.size - 1)
        sub, sup = w[prev], w
        diag = sub + w
        diag *= 2.0
        rhs = c1[prev]
        rhs += c0
        np.negative(rhs, out=rhs)
    else:
        n = p0i.size + 1
        sub, diag, sup, rhs = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
        sub[1:], sup[:-1] = w, w
        diag[:-1] += 2.0 * w
        diag[1:] += 2.0 * w
        rhs[:-1] -= c0
        rhs[1:] -= c1
        if not free_start:
            sup[0], diag[0], rhs[0] = 0.0, 1.0, 0.0
        if not free_end:
            sub[-1], diag[-1], rhs[-1] = 0.0, 1.0, 0.0
    if held is not None:
        sub, diag, sup, rhs = sub.copy(), diag.copy(), sup.copy(), rhs.copy()
        sub[held], diag[held], sup[held], rhs[held] = 0.0, 1.0, 0.0, 0.0
    return solve_tridiagonal(sub, diag, sup, rhs, closed)


@dataclass
class NewtonResult:
    """What :func:`solve_nodes` found: node-angle increments ``d``, segment
    parameters ``A``, the segment state ``st`` at the solution, ``iterations``,
    ``ok`` (converged), ``g2`` (largest curvature jump at a free node over
    max |k|) and ``closure`` (largest closure residual)."""

    d: np.ndarray
    A: np.ndarray
    st: dict
    iterations: int
    ok: bool
    g2: float
    closure: float


def solve_nodes(p0i, p1i, r, closed, free_start=True, free_end=True, held=None, tol=1e-12, max_iter=50,
                max_halvings=30):
    """Damped Newton on the node-angle increments and segment parameters A.

    Parameters
    ----------
    p0i, p1i : ndarray, shape (M,)
        Initial end angles of every segment relative to its chord.
    r : ndarray, shape (M,)
        Chord lengths (scaled to a mean of about 1).
    closed : bool
        N = M nodes (cyclic system) or N = M + 1 (open).
    free_start, free_end : bool
        Open curves: natural end (zero curvature) or a held end tangent.
    held : ndarray of bool, shape (N,), optional
        Nodes whose tangent stays at its initial value (G1 nodes).
    tol : float
        Stop when every curvature jump at a free node is below ``tol`` times
        max |k| and every segment closes to 1e-14 of its chord.
    max_iter : int
    max_halvings : int
        Step halvings of the line search per iteration before giving up.

    Returns
    -------
    NewtonResult or None
        None when the initial guess already gives a degenerate segment.
    """
    m = p0i.size
    n = m if closed else m + 1
    nxt = np.arange(1, m + 1) % n  # the end node of every segment
    prev = np.arange(-1, n - 1)  # index -1 is the last node

    def state(d, A):
        # derivatives only for a state Newton steps from (most trials are
        # rejected or final)
        st = segment_state(p0i + d[:m], p1i + d[nxt], A, r, derivatives="later")
        # X0 > 0 keeps L = r / X0 positive (a NaN fails it); then only an
        # overflow can make it infinite
        if not (np.minimum.reduce(st["X0"]) > 0 and np.maximum.reduce(st["L"]) < np.inf):
            return None, None, np.inf
        F = _residual(st, closed, free_start, free_end, prev, held)
        G = st["G"]
        return st, F, float(F @ F + G @ G)

    def converged(st, F):
        kmax = float(np.maximum.reduce(np.abs(st["K"]), axis=None))
        fres = float(np.maximum.reduce(np.abs(F)))
        gres = float(np.maximum.reduce(np.abs(st["G"])))
        return kmax, fres, gres, fres <= tol * kmax and gres <= 1e-14

    d = small_angle_start(p0i, p1i, r, closed, free_start, free_end, held)
    # beyond a radian the linearisation means nothing (as for Newton's
    # steps): start from the circle tangents instead
    if np.maximum.reduce(np.abs(d)) <= 1.0:
        # the small-angle segment's A (as good as guess_A's polynomial from
        # here: the same Newton iterations on smooth curves)
        A = p0i + d[:m]
        A += p1i
        A += d[nxt]
        A *= 3.0
    else:
        d = np.zeros(n)
        A = guess_A(p0i, p1i)
    st, F, merit = state(d, A)
    if st is None and d.any():
        d = np.zeros(n)
        A = guess_A(p0i, p1i)
        st, F, merit = state(d, A)
    if st is None:
        return None
    it = 0
    while True:
        kmax, fres, gres, done = converged(st, F)
        if done or it >= max_iter:
            break
        add_derivatives(st, full=False)
        sub, diag, sup, rhs = _linear_system(st, F, closed, free_start, free_end, prev, held)
        dd = solve_tridiagonal(sub, diag, sup, rhs, closed)
        big = float(np.maximum.reduce(np.abs(dd)))
        if not big < np.inf:  # NaN or infinite: a singular system
            break
        # the change of A that keeps each segment closed to first order
        rows = st["dA"]
        dA = rows[0] * dd[:m]
        dA += rows[2]
        dA += rows[1] * dd[nxt]
        # a step of more than one radian in any angle leaves the region where
        # the linearisation means anything
        step = min(1.0, 1.0 / max(big, 1e-300))
        accepted = False
        for _ in range(max_halvings):
            d_t, A_t = (d + dd, A + dA) if step == 1.0 else (d + step * dd, A + step * dA)
            st_t, F_t, m_t = state(d_t, A_t)
            if st_t is not None and m_t <= (1.0 - 1e-4 * step) * merit:
                accepted = True
                break
            step *= 0.5
        it += 1
        if not accepted:
            break
        d, A, st, F, merit = d_t, A_t, st_t, F_t, m_t
    # the rounding floor can stop the last halving short of tol: accept what
    # is still far inside the documented guarantee
    ok = (fres <= max(tol, 1e-11) * kmax or fres <= 1e-14) and gres <= 1e-13
    return NewtonResult(d, A, st, it, ok, fres / kmax if kmax > 0 else 0.0, gres)


def tangent_range(delta, A):
    """Lowest and highest value on [0, 1] of the tangent angle along
    segments, ``theta(tau) - theta(0) = (delta - A) tau + A tau**2``, in the
    normalised form of :func:`solve_nodes` (``tau = s / L``, ``A = dk L**2 / 2``,
    ``delta`` the turn from start to end).

    Returns
    -------
    lo, hi : ndarray
        Both bracket 0 (the start) and `delta` (the end).

    Examples
    --------
    >>> import numpy as np
    >>> lo, hi = tangent_range(np.array([0.0]), np.array([1.0]))  # turns back to its start
    >>> float(lo[0]), float(hi[0])
    (-0.25, 0.0)
    """
    # the vertex of the parabola, clipped to the segment
    tv = np.zeros_like(A)
    np.divide(A - delta, 2 * A, out=tv, where=A != 0)
    np.clip(tv, 0.0, 1.0, out=tv)
    th_v = (delta - A) * tv + A * tv * tv
    hi = np.maximum(np.maximum(0.0, delta), th_v)
    lo = np.minimum(np.minimum(0.0, delta), th_v)
    return lo, hi
