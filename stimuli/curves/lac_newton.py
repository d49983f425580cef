"""Newton for the G2 log-aesthetic spline (:mod:`stimuli.curves.lac_spline`):
the equations of every segment, their sparse Jacobian, damped Newton and
continuation in alpha.

Unknowns: the tangent angle and the curvature's graph variable
``u = g(kappa)`` (:func:`stimuli.curves.lac_arc.graph_value`) at every node,
and every segment's length. Each segment's three equations (turn, chord)
involve only its two nodes and its length, so the Jacobian is block-banded
(cyclic for closed curves) and solved by SuperLU (``scipy.sparse``).
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import MatrixRankWarning, spsolve

from stimuli.curves.lac_arc import arc_integrals, graph_inverse, graph_value, is_zero_alpha

__all__ = ["LACSystem", "continue_in_alpha"]

# continuation in alpha: smallest step, most Newton solves, and the largest
# ratio of node curvatures before the branch counts as diverging
_MIN_STEP = 1e-3
_MAX_SOLVES = 40
_MAX_SPREAD = 1e12


class LACSystem:
    """The equations of a G2 LAC spline through points, in a frame where the
    mean chord is 1, and damped Newton on them.

    Parameters
    ----------
    P : ndarray, shape (N, 2)
        The points.
    closed : bool
    wind : int
        Turning number of a closed curve (the tangent after the last segment
        is theta_0 + 2 pi wind).
    """

    def __init__(self, P, closed, wind):
        self.closed = closed
        self.h = float(np.mean(np.hypot(*np.diff(np.vstack([P, P[:1]]) if closed else P, axis=0).T)))
        Q = (P - P[0]) / self.h
        self.n = len(P)
        self.M = self.n if closed else self.n - 1
        self.a = np.arange(self.M)
        self.b = (self.a + 1) % self.n if closed else self.a + 1
        zq = Q[:, 0] + 1j * Q[:, 1]
        self.D = zq[self.b] - zq[self.a]
        # the tangent after the last segment of a closed curve is theta_0 + 2 pi wind
        self.wrap = np.where(self.b == 0, 2 * np.pi * wind, 0.0) if closed else np.zeros(self.M)
        self.sign = 1.0  # the curvature's sign for alpha >= 0 (set by newton)

    def split(self, x):
        n = self.n
        return x[:n], x[n:2 * n], x[2 * n:]

    def residual(self, x, alpha, derivatives=False):
        """Residuals at x = (theta, u, L), u the node curvatures' graph
        variables (:func:`~stimuli.curves.lac_arc.graph_value`), and the arcs'
        integrals."""
        th, u, L = self.split(x)
        a, b = self.a, self.b
        if not (np.all(np.isfinite(x)) and np.all(L > 0)):
            return None, None
        if alpha > 0 and not is_zero_alpha(alpha) and not np.all(u > 0):
            return None, None
        k = graph_inverse(u, alpha, self.sign)
        with np.errstate(all="ignore"):
            arc = arc_integrals(th[a], k[a], k[b], L, alpha, derivatives)
        F = np.empty(3 * self.M + (0 if self.closed else 2))
        F[0:3 * self.M:3] = th[b] + self.wrap - th[a] - arc["turn"]
        F[1:3 * self.M:3] = arc["z"].real - self.D.real
        F[2:3 * self.M:3] = arc["z"].imag - self.D.imag
        if not self.closed:
            n = self.n
            F[-2], F[-1] = (u[0], u[-1]) if alpha < 0 else (u[0] - u[1], u[n - 1] - u[n - 2])
        if not np.all(np.isfinite(F)):
            return None, None
        return F, arc

    def jacobian(self, arc, alpha):
        n, M, a, b = self.n, self.M, self.a, self.b
        r = 3 * np.arange(M)
        ka, kb, Lc = n + a, n + b, 2 * n + np.arange(M)
        zt = 1j * arc["z"]
        rows, cols, vals = [], [], []

        def put(rr, cc, vv):
            rows.append(rr)
            cols.append(cc)
            vals.append(vv)

        # turn equation
        put(r, b, np.ones(M))
        put(r, a, -np.ones(M))
        put(r, ka, -arc["turn_u0"])
        put(r, kb, -arc["turn_u1"])
        put(r, Lc, -arc["Theta1"])
        # chord equations (real and imaginary parts)
        for off, part in ((1, np.real), (2, np.imag)):
            put(r + off, a, part(zt))
            put(r + off, ka, part(arc["z_u0"]))
            put(r + off, kb, part(arc["z_u1"]))
            put(r + off, Lc, part(arc["z_L"]))
        size = 3 * M
        if not self.closed:
            i0, i1 = size, size + 1
            if alpha < 0:
                put(np.array([i0, i1]), np.array([n, 2 * n - 1]), np.ones(2))
            else:
                put(np.array([i0, i0, i1, i1]), np.array([n, n + 1, 2 * n - 1, 2 * n - 2]),
                    np.array([1.0, -1.0, 1.0, -1.0]))
            size += 2
        return csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size))

    def newton(self, xk, alpha, tol, max_iter):
        """Damped Newton from xk = (theta, kappa, L), in the graph variables
        of this alpha. Returns (xk, iterations, converged, residual)."""
        n = self.n
        if alpha >= 0:
            self.sign = 1.0 if np.sum(xk[n:2 * n]) >= 0 else -1.0
        x = np.concatenate((xk[:n], graph_value(xk[n:2 * n], alpha), xk[2 * n:]))
        x, it, ok, res = self._newton(x, alpha, tol, max_iter)
        return np.concatenate((x[:n], graph_inverse(x[n:2 * n], alpha, self.sign), x[2 * n:])), it, ok, res

    def _newton(self, x, alpha, tol, max_iter):
        F, _ = self.residual(x, alpha)
        if F is None:
            return x, 0, False, np.inf
        merit = float(F @ F)
        n = self.n
        for it in range(max_iter + 1):
            res = float(np.max(np.abs(F)))
            if res <= tol or it == max_iter:
                return x, it, res <= tol, res
            # derivatives only where Newton steps from (trials are most evaluations)
            _, arc = self.residual(x, alpha, derivatives=True)
            with warnings.catch_warnings():
                # a singular Jacobian gives NaNs, handled below
                warnings.simplefilter("ignore", MatrixRankWarning)
                dx = spsolve(self.jacobian(arc, alpha), -F)
            if not np.all(np.isfinite(dx)):
                return x, it, False, res
            if not self.closed:
                # the end conditions are linear and hold at the start: keep
                # them exactly (the sparse solve leaves rounding in them)
                if alpha < 0:
                    dx[n] = dx[2 * n - 1] = 0.0
                else:
                    dx[n], dx[2 * n - 1] = dx[n + 1], dx[2 * n - 2]
            th, u, L = self.split(x)
            dth, du, dL = self.split(dx)
            # keep within the linearisation: angles (and alpha = 0's log
            # curvatures) by at most 1, lengths (and alpha > 0's u > 0) shrink
            # by at most a factor 5
            big = float(np.max(np.abs(np.concatenate((dth, du if is_zero_alpha(alpha) else [])))))
            step = min(1.0, 1.0 / max(big, 1e-300))
            shrink = np.concatenate((dL / L, du / u if alpha > 0 and not is_zero_alpha(alpha) else []))
            if shrink.size and shrink.min() < -0.8:
                step = min(step, 0.8 / -shrink.min())
            for _ in range(40):
                xt = x + step * dx
                Ft, _ = self.residual(xt, alpha)
                if Ft is not None and float(Ft @ Ft) <= (1.0 - 1e-4 * step) * merit:
                    break
                step *= 0.5
            else:
                # no decrease: the rounding floor, or a failure
                return x, it, res <= 1e3 * tol, res
            x, F, merit = xt, Ft, float(Ft @ Ft)
        return x, max_iter, False, float(np.max(np.abs(F)))  # pragma: no cover


def continue_in_alpha(system, x0, alpha, tol, max_iter):
    """Solve at a start alpha from the guess (-1, where the clothoid spline
    is the solution, or 0 for alpha >= 0: arcs of alpha < 0 may inflect and
    the way through alpha = 0 is closed to them), then step towards alpha,
    halving the step where Newton fails and growing it where it succeeds.

    Returns
    -------
    x, iterations, converged, residual, alphas
        The last solution reached (theta, kappa, L in the system's frame),
        Newton iterations in all, whether alpha was reached, the last
        residual and the alphas solved for.
    """
    a = 0.0 if alpha >= 0 else -1.0
    x, total, ok, res = system.newton(x0, a, tol, max_iter)
    alphas = [a]
    if not ok:
        return x, total, False, res, alphas
    step = 0.5
    n = system.n
    for _ in range(_MAX_SOLVES):
        if a == alpha:
            break
        nxt = min(a + step, alpha) if alpha > a else max(a - step, alpha)
        # a step that converges does so in a few iterations: fail fast otherwise
        xt, it, ok, res = system.newton(x, nxt, tol, min(max_iter, 12))
        total += it
        if ok:
            x, a = xt, nxt
            alphas.append(a)
            step *= 1.5
            kabs = np.abs(x[n:2 * n])
            if kabs.min() < _MAX_SPREAD ** -1 * kabs.max():
                # a node's curvature diverging (or vanishing) on the way: the
                # solution branch ends before alpha
                return x, total, False, res, alphas
        else:
            step *= 0.5
            if step < _MIN_STEP:
                return x, total, False, res, alphas
    else:
        return x, total, False, res, alphas
    return x, total, True, res, alphas
