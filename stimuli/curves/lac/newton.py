"""Newton for the G2 log-aesthetic spline (:mod:`attneave.stimuli.curves.lac.spline`):
the equations of every segment, their sparse Jacobian, damped Newton and
continuation in alpha.

Unknowns: the tangent angle and the curvature's graph variable
``u = g(kappa)`` (:func:`attneave.stimuli.curves.lac.arc.graph_value`) at every node,
and every segment's length. Each segment's three equations (turn, chord)
involve only its two nodes and its length, so the Jacobian is block-banded
(cyclic for closed curves) and solved by SuperLU (``scipy.sparse``), or by
dense LU where the system is small (up to 96 unknowns: N = 20 with its corners).

Cost. Every Newton iteration evaluates the arcs' integrals once more than
it steps: the derivatives at the point it steps from come from the line
search's accepted evaluation (:class:`~attneave.stimuli.curves.lac.arc.ArcIntegrals`
derives them on first access), and the spline's closure and G2 errors from
the last one (:meth:`LACSystem.integrals`). The Jacobian's sparsity pattern
(and how CSC orders it) is built once per system and sign of alpha.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.sparse import csc_matrix
from scipy.sparse.linalg import MatrixRankWarning, spsolve

from attneave.stimuli.curves.lac.arc import arc_integrals, graph_inverse, graph_value, is_zero_alpha

__all__ = ["LACSystem", "continue_in_alpha"]

# continuation in alpha: smallest step, most Newton solves, and the largest
# ratio of node curvatures before the branch counts as diverging
_MIN_STEP = 1e-3
_MAX_SOLVES = 40
_MAX_SPREAD = 1e12
# systems up to this size are solved dense (numpy's LU): 60 x 60 (N = 20) in 26 us against
# 43 us for building the CSC matrix and SuperLU; at 120 (N = 40) SuperLU is faster (59 vs 72 us)
_DENSE = 96


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
    g1 : dict of int to float, optional
        G1 nodes: node -> its tangent angle, held fixed; the curvature may
        jump there (each side has its own).
    g0 : sequence of int, optional
        G0 corners: each side of the node has its own tangent angle and a
        natural end (zero curvature; alpha < 0 only).
    wrap : ndarray, shape (M,), optional
        Per segment, what is added to the tangent angle at its end node to
        give the angle reached along the segment (default: 2 pi wind on the
        segment that closes the curve).

    Notes
    -----
    The unknowns ``x = (theta, u, L)`` hold one tangent angle per node plus
    one for the incoming side of every G0 corner, one graph variable per
    node plus one for the incoming side of every G1 or G0 node, and every
    segment's length. Held angles and natural ends are linear equations
    ``x[col] = value`` that hold from the start (Newton keeps them exactly),
    so the system stays square: 3 equations per segment, 2 unknowns per
    node.
    """

    def __init__(self, P, closed, wind=0, g1=None, g0=(), wrap=None):
        self.closed = closed
        self.h = float(np.mean(np.hypot(*np.diff(np.vstack([P, P[:1]]) if closed else P, axis=0).T)))
        Q = (P - P[0]) / self.h
        n = self.n = len(P)
        self.M = n if closed else n - 1
        self.a = np.arange(self.M)
        self.b = (self.a + 1) % n if closed else self.a + 1
        zq = Q[:, 0] + 1j * Q[:, 1]
        self.D = zq[self.b] - zq[self.a]
        # the tangent after the last segment of a closed curve is theta_0 + 2 pi wind
        self.wrap = (np.asarray(wrap, dtype=float) if wrap is not None
                     else np.where(self.b == 0, 2 * np.pi * wind, 0.0) if closed else np.zeros(self.M))
        self.sign = 1.0  # the curvature's sign for alpha >= 0 (set by newton)
        g1 = dict(g1 or {})
        g0 = sorted(set(g0))
        split_u = sorted(set(g1) | set(g0))
        t_in, u_in = np.arange(n), np.arange(n)
        t_in[g0] = n + np.arange(len(g0))
        u_in[split_u] = n + np.arange(len(split_u))
        self.nt, self.nu = n + len(g0), n + len(split_u)
        # the columns of each segment's start and end angle and graph variable
        self.ta, self.tb = self.a, t_in[self.b]
        self.ua, self.ub = self.a, u_in[self.b]
        # linear equations x[col] = value: held angles, natural ends (zero graph variable)
        fixed = [(int(i), float(v)) for i, v in g1.items()]
        fixed += [(self.nt + int(c), 0.0) for i in g0 for c in (i, u_in[i])]
        self.joints = bool(g1 or g0)
        self.fixed_cols = np.array([c for c, _ in fixed], dtype=int)
        self.fixed_vals = np.array([v for _, v in fixed], dtype=float)
        self._csc = {}  # the Jacobian's sparsity pattern, per sign of alpha (jacobian)
        self._last = None  # (alpha, x, integrals) of the last newton's result (integrals)

    def split(self, x):
        nt, nu = self.nt, self.nu
        return x[:nt], x[nt:nt + nu], x[nt + nu:]

    def free_graph(self, u):
        """The graph variables not held at zero by a natural end."""
        keep = np.ones(u.size, bool)
        keep[self.fixed_cols[self.fixed_cols >= self.nt] - self.nt] = False
        if not self.closed:
            keep[[0, self.n - 1]] = False
        return u[keep]

    def residual(self, x, alpha, derivatives=False):
        """Residuals at x = (theta, u, L), u the node curvatures' graph
        variables (:func:`~attneave.stimuli.curves.lac.arc.graph_value`), and the arcs'
        integrals."""
        th, u, L = self.split(x)
        if not (np.all(np.isfinite(x)) and np.all(L > 0)):
            return None, None
        if alpha > 0 and not is_zero_alpha(alpha) and not np.all(u > 0):
            return None, None
        k = graph_inverse(u, alpha, self.sign)
        with np.errstate(all="ignore"):
            arc = arc_integrals(th[self.ta], k[self.ua], k[self.ub], L, alpha, derivatives)
        nf = self.fixed_cols.size
        F = np.empty(3 * self.M + nf + (0 if self.closed else 2))
        F[0:3 * self.M:3] = th[self.tb] + self.wrap - th[self.ta] - arc["turn"]
        F[1:3 * self.M:3] = arc["z"].real - self.D.real
        F[2:3 * self.M:3] = arc["z"].imag - self.D.imag
        F[3 * self.M:3 * self.M + nf] = x[self.fixed_cols] - self.fixed_vals
        if not self.closed:
            n = self.n
            F[-2], F[-1] = (u[0], u[n - 1]) if alpha < 0 else (u[0] - u[1], u[n - 1] - u[n - 2])
        if not np.all(np.isfinite(F)):
            return None, None
        return F, arc

    def _structure(self, alpha):
        """The Jacobian's entries (rows, columns) in the order of
        :meth:`_values`, its constant values at the end, its size and
        (:func:`_csc_pattern`) how CSC orders them; per sign of alpha (the
        open ends' equations depend on it, nothing else does)."""
        key = alpha < 0
        if key in self._csc:
            return self._csc[key]
        n, M, nt, nu = self.n, self.M, self.nt, self.nu
        r = 3 * np.arange(M)
        ka, kb, Lc = nt + self.ua, nt + self.ub, nt + nu + np.arange(M)
        # turn equation: theta_b, theta_a, u0, u1, L; chord equations (real,
        # imaginary part): theta_a, u0, u1, L
        rows = [r, r, r, r, r] + [r + off for off in (1, 2) for _ in range(4)]
        cols = [self.tb, self.ta, ka, kb, Lc] + [self.ta, ka, kb, Lc] * 2
        size = 3 * M
        nf = self.fixed_cols.size
        rows.append(size + np.arange(nf))
        cols.append(self.fixed_cols)
        tail = [np.ones(nf)]
        size += nf
        if not self.closed:
            i0, i1 = size, size + 1
            if alpha < 0:
                rows.append(np.array([i0, i1]))
                cols.append(np.array([nt, nt + n - 1]))
                tail.append(np.ones(2))
            else:
                rows.append(np.array([i0, i0, i1, i1]))
                cols.append(np.array([nt, nt + 1, nt + n - 1, nt + n - 2]))
                tail.append(np.array([1.0, -1.0, 1.0, -1.0]))
            size += 2
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        out = self._csc[key] = (rows, cols, np.concatenate([np.ones(M), -np.ones(M)]), np.concatenate(tail), size,
                                _csc_pattern(rows, cols, size))
        return out

    def _values(self, arc, alpha):
        """The Jacobian's values in the order of :meth:`_structure` (d/d theta_a
        of the chord z is i z)."""
        _, _, head, tail, _, _ = self._structure(alpha)
        z, zu0, zu1, zL = arc["z"], arc["z_u0"], arc["z_u1"], arc["z_L"]
        return np.concatenate((head, -arc["turn_u0"], -arc["turn_u1"], -arc["Theta1"],
                               -z.imag, zu0.real, zu1.real, zL.real, z.real, zu0.imag, zu1.imag, zL.imag, tail))

    def jacobian(self, arc, alpha):
        """The sparse Jacobian (CSC) at the arcs' integrals `arc`."""
        rows, cols, _, _, size, pattern = self._structure(alpha)
        data = self._values(arc, alpha)
        if pattern is None:  # repeated entries (summed): assemble from coordinates
            return csc_matrix((data, (rows, cols)), shape=(size, size))
        order, indices, indptr = pattern
        return csc_matrix((data[order], indices, indptr), shape=(size, size))

    def step(self, arc, alpha, F):
        """The Newton step ``-J^-1 F`` (NaN where J is singular): dense LU
        for small systems (where SuperLU's set-up costs more than the
        solve), else SuperLU."""
        rows, cols, _, _, size, pattern = self._structure(alpha)
        if size <= _DENSE and pattern is not None:
            J = np.zeros((size, size))
            J[rows, cols] = self._values(arc, alpha)
            try:
                return np.linalg.solve(J, -F)
            except np.linalg.LinAlgError:
                return np.full(size, np.nan)
        return spsolve(self.jacobian(arc, alpha), -F)

    def newton(self, xk, alpha, tol, max_iter):
        """Damped Newton from xk = (theta, kappa, L), in the graph variables
        of this alpha. Returns (xk, iterations, converged, residual)."""
        if alpha >= 0:
            if self.joints:
                raise ValueError("G1 and G0 joints need alpha < 0 (natural ends)")
            self.sign = 1.0 if np.sum(self.split(xk)[1]) >= 0 else -1.0
        th, k, L = self.split(xk)
        x = np.concatenate((th, graph_value(k, alpha), L))
        x, it, ok, res, arc = self._newton(x, alpha, tol, max_iter)
        th, u, L = self.split(x)
        xk = np.concatenate((th, graph_inverse(u, alpha, self.sign), L))
        self._last = (alpha, xk, arc)
        return xk, it, ok, res

    def integrals(self, x, alpha):
        """The arcs' integrals (:func:`~attneave.stimuli.curves.lac.arc.arc_integrals`)
        at x = (theta, kappa, L): the last Newton evaluation's where x is what
        :meth:`newton` returned (the same numbers), else computed."""
        if self._last is not None and self._last[0] == alpha and np.array_equal(self._last[1], x):
            return self._last[2]
        th, k, L = self.split(x)
        return arc_integrals(th[self.ta], k[self.ua], k[self.ub], L, alpha)

    def _newton(self, x, alpha, tol, max_iter):
        with warnings.catch_warnings():
            # a singular Jacobian gives NaNs (SuperLU warns), handled as a failed step
            warnings.simplefilter("ignore", MatrixRankWarning)
            return self._damped_newton(x, alpha, tol, max_iter)

    def _damped_newton(self, x, alpha, tol, max_iter):
        F, arc = self.residual(x, alpha)
        if F is None:
            return x, 0, False, np.inf, None
        merit = float(F @ F)
        n, nt = self.n, self.nt
        for it in range(max_iter + 1):
            res = float(np.max(np.abs(F)))
            if res <= tol or it == max_iter:
                return x, it, res <= tol, res, arc
            # the derivatives at x come from the evaluation that gave F (the
            # accepted trial's), computed only now that Newton steps from x
            dx = self.step(arc, alpha, F)
            if not np.all(np.isfinite(dx)):
                return x, it, False, res, arc
            # the linear equations (held angles, natural and open ends) hold at
            # the start: keep them exactly (the sparse solve leaves rounding in them)
            dx[self.fixed_cols] = 0.0
            if not self.closed:
                if alpha < 0:
                    dx[nt] = dx[nt + n - 1] = 0.0
                else:
                    dx[nt], dx[nt + n - 1] = dx[nt + 1], dx[nt + n - 2]
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
                Ft, arc_t = self.residual(xt, alpha)
                if Ft is not None and float(Ft @ Ft) <= (1.0 - 1e-4 * step) * merit:
                    break
                step *= 0.5
            else:
                # no decrease: the rounding floor, or a failure
                return x, it, res <= 1e3 * tol, res, arc
            x, F, arc, merit = xt, Ft, arc_t, float(Ft @ Ft)
        return x, max_iter, False, float(np.max(np.abs(F))), arc  # pragma: no cover


def _csc_pattern(rows, cols, size):
    """How :class:`~scipy.sparse.csc_matrix` orders entries given by
    coordinates: (order of the entries, row indices, column pointers), so
    that each Newton step builds its Jacobian from the values alone (the
    same matrix as from coordinates); None where an entry repeats (summed)."""
    ref = csc_matrix((np.arange(1.0, rows.size + 1.0), (rows, cols)), shape=(size, size))
    if ref.nnz != rows.size:
        return None
    return ref.data.astype(np.intp) - 1, ref.indices, ref.indptr


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
            kabs = np.abs(system.free_graph(system.split(x)[1]))
            if kabs.size and kabs.min() < _MAX_SPREAD ** -1 * kabs.max():
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
