"""Interpolating splines through points: the QIC spline and polynomial
baselines.

The **QIC spline** (quantity-of-information continuous; Ziatdinov, DESIGN.md)
passes through the given points with curvature continuity (G2), and every
segment between two consecutive points is a clothoid (Euler spiral), whose
curvature is linear in arc length and so monotone: no curvature extremum,
hence no spurious information, appears between the points.

Method. The unknowns are the tangent angles at the points. Given them, each
segment is the G1 Hermite clothoid of Bertolazzi & Frego (2015) between its
two points (:mod:`stimuli.curves.euler`), whose curvature at both ends is a
function of the two end angles; curvature continuity at every point is one
equation per point. The whole system (node angles and, per segment, the
Bertolazzi-Frego parameter A with its closure equation) is solved by damped
Newton's method; eliminating A segment by segment (implicit function
theorem) leaves a tridiagonal system in the node angles, cyclic for closed
curves. Everything is vectorised over segments; the work per iteration is
O(N). The iteration count is bounded and failure raises
:class:`ConvergenceError`, never returns a silently bad curve.

**Baselines** (the paper's Figs. 8-10): cubic splines (periodic, not-a-knot,
natural) and interpolating splines of degree 2-5 with chord-length
parametrisation (:class:`scipy.interpolate.CubicSpline`,
:func:`scipy.interpolate.make_interp_spline`).

Coordinates: points are ``(x, y)`` in image pixels (x = column, y = row,
y down) unless ``y_down=False``. Reported curvature follows the project's
geometric sign: for a closed curve positive where it is convex whatever the
order of the points; for an open curve positive where it turns left on the
screen (counter-clockwise as seen). Tangent angles stored on the spline
objects (``theta``) are in the input coordinates: radians from +x towards +y.

References
----------
.. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids", Math. Meth.
       Appl. Sci. 38(5), 881-897, 2015.
.. [2] E. Bertolazzi and M. Frego, "Interpolating clothoid splines with
       curvature continuity", Math. Meth. Appl. Sci. 41(4), 1723-1737, 2018.
.. [3] R. Ziatdinov, "Visual perception, quantity of information function and
       the concept of the quantity of information continuous splines".
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.linalg.lapack import dgtsv as _dgtsv

from stimuli.curves.euler import _segment_state, clothoid_points, guess_A, wrap_angle
from stimuli.curves.metrics import SampledCurve, curve_metrics
from stimuli.errors import InputError
from stimuli.io import as_points

__all__ = [
    "ConvergenceError",
    "QICSpline",
    "PolynomialSpline",
    "qic_spline",
    "polynomial_spline",
    "fit_spline",
    "METHODS",
]

METHODS = ("qic", "cubic", "cubic-natural", "poly2", "poly3", "poly4", "poly5", "lac-g1")


# chord / segment length below which a segment counts as degenerate (length -> inf)
_MIN_X0 = 1e-6


class ConvergenceError(InputError):
    """The QIC spline could not be computed for these points.

    Raised when damped Newton does not reach the tolerance within its
    iteration bound (typical of jagged or randomly ordered points). A
    subclass of :class:`~stimuli.errors.InputError`, so the command line
    reports it in one line with exit status 2.
    """


# ----------------------------------------------------------------------------
# validation and geometry helpers


def _as_points(points, closed, what="points"):
    P = as_points(points, what)
    need = 3 if closed else 2
    if len(P) < need:
        raise InputError(f"{what}: a {'closed' if closed else 'open'} spline needs at least {need} points, got {len(P)}")
    nxt = np.concatenate((P[1:], P[:1])) if closed else P[1:]
    same = (nxt == P[: len(nxt)]).all(axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % len(P)
        hint = " (a closed curve must not repeat its first point at the end)" if closed and j == 0 else ""
        raise InputError(f"{what}: rows {i} and {j} are the same point; consecutive points must differ{hint}")
    return P


def _geometric_sign(P, closed, y_down):
    """Factor turning d(theta)/ds in the input coordinates into the
    project's geometric curvature sign."""
    if closed:
        x, y = P[:, 0], P[:, 1]
        area2 = float(x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1])
        if area2 != 0.0:
            # a traversal whose signed area is positive in these coordinates
            # turns positively at its convex points, in any handedness
            return 1.0 if area2 > 0 else -1.0
    return -1.0 if y_down else 1.0


# ----------------------------------------------------------------------------
# the QIC solver


def _initial_angles(phi, r, closed, t_start=None, t_end=None):
    """End angles of every segment relative to its chord: tangent of the
    circle through each point and its two neighbours; natural ends get the
    small-angle clothoid with zero end curvature (phi0 = -phi1/2)."""
    m = phi.size
    if closed:
        phip = np.concatenate((phi[-1:], phi[:-1]))
        rp = np.concatenate((r[-1:], r[:-1]))
        t = wrap_angle(phi - phip)
        # inscribed angle: lies between 0 and the turn t, so no wrapping
        beta = np.arctan2(rp * np.sin(t), r + rp * np.cos(t))
        p0 = beta - t
        p1 = np.concatenate((beta[1:], beta[:1]))
        return p0, p1
    p0 = np.zeros(m)
    p1 = np.zeros(m)
    if m > 1:
        t = wrap_angle(phi[1:] - phi[:-1])
        beta = np.arctan2(r[:-1] * np.sin(t), r[1:] + r[:-1] * np.cos(t))
        p1[:-1] = beta
        p0[1:] = beta - t
    if t_start is not None:
        p0[0] = wrap_angle(t_start - phi[0])
    if t_end is not None:
        p1[-1] = wrap_angle(t_end - phi[-1])
    if t_start is None:
        p0[0] = -0.5 * p1[0] if (m > 1 or t_end is not None) else 0.0
    if t_end is None:
        p1[-1] = -0.5 * p0[-1] if (m > 1 or t_start is not None) else 0.0
    return p0, p1


def _residual(st, closed, free_start, free_end, prev=None):
    k0, k1 = st["k0"], st["k1"]
    if closed:
        return k1[prev] - k0
    F = np.empty(k0.size + 1)
    F[1:-1] = k1[:-1] - k0[1:]
    F[0] = k0[0] if free_start else 0.0
    F[-1] = k1[-1] if free_end else 0.0
    return F


def _linear_system(st, F, closed, free_start, free_end, prev=None):
    """Tridiagonal Newton system in the node-angle increments, A eliminated."""
    k0t0, k0t1, k1t0, k1t1 = st["k0_t0"], st["k0_t1"], st["k1_t0"], st["k1_t1"]
    k0r, k1r = st["k0_r"], st["k1_r"]
    if closed:
        sub = k1t0[prev]
        diag = k1t1[prev] - k0t0
        sup = -k0t1
        rhs = k0r - F - k1r[prev]
        return sub, diag, sup, rhs
    n = k0t0.size + 1
    sub = np.zeros(n)
    diag = np.ones(n)
    sup = np.zeros(n)
    rhs = np.zeros(n)
    sub[1:-1] = k1t0[:-1]
    diag[1:-1] = k1t1[:-1] - k0t0[1:]
    sup[1:-1] = -k0t1[1:]
    rhs[1:-1] = -(F[1:-1] + k1r[:-1] - k0r[1:])
    if free_start:
        diag[0], sup[0], rhs[0] = k0t0[0], k0t1[0], -(F[0] + k0r[0])
    if free_end:
        sub[-1], diag[-1], rhs[-1] = k1t0[-1], k1t1[-1], -(F[-1] + k1r[-1])
    return sub, diag, sup, rhs


def _solve_tridiagonal(sub, diag, sup, rhs, cyclic):
    """Solve a (cyclic) tridiagonal system; sub[i] multiplies x[i-1] and
    sup[i] multiplies x[i+1] (indices modulo n when cyclic). LAPACK's
    ``dgtsv`` (Gaussian elimination with partial pivoting), with
    Sherman-Morrison for the two corner entries of a cyclic system.
    Returns NaNs if the matrix is singular."""
    n = diag.size
    if not cyclic or n < 3:
        if n == 1:
            return rhs / diag
        *_, x, info = _dgtsv(sub[1:], diag, sup[:-1], rhs[:, None])
        return x[:, 0] if info == 0 else np.full(n, np.nan)
    top, bottom = sub[0], sup[-1]  # J[0, n-1] and J[n-1, 0]
    gamma = -diag[0] if diag[0] != 0 else 1.0
    d = diag.copy()
    d[0] -= gamma
    d[-1] -= top * bottom / gamma
    b = np.zeros((n, 2))
    b[:, 0] = rhs
    b[0, 1], b[-1, 1] = gamma, bottom
    *_, yz, info = _dgtsv(sub[1:], d, sup[:-1], b)
    if info != 0:
        return np.full(n, np.nan)
    y, z = yz[:, 0], yz[:, 1]
    vy = y[0] + top / gamma * y[-1]
    vz = z[0] + top / gamma * z[-1]
    return y - (vy / (1.0 + vz)) * z


def _newton(p0i, p1i, r, closed, free_start, free_end, tol, max_iter):
    """Damped Newton on node-angle increments and segment parameters A."""
    n = p0i.size if closed else p0i.size + 1
    A = guess_A(p0i, p1i)
    d = np.zeros(n)
    idx = np.arange(n)
    nxt = np.r_[idx[1:], 0] if closed else idx[1:]
    prev = np.r_[n - 1, idx[:-1]]
    m = p0i.size

    def state(d, A):
        st = _segment_state(p0i + d[:m], p1i + d[nxt], A, r)
        if not (st["X0"].min() > 0 and np.isfinite(st["L"]).all()):
            return None, None, np.inf
        F = _residual(st, closed, free_start, free_end, prev)
        return st, F, float(F @ F + st["G"] @ st["G"])

    def residuals(st, F):
        kmax = max(np.abs(st["k0"]).max(), np.abs(st["k1"]).max())
        return float(kmax), float(np.abs(F).max()), float(np.abs(st["G"]).max())

    st, F, merit = state(d, A)
    if st is None:
        raise ConvergenceError("QIC spline: the initial guess gives a degenerate segment")
    it = 0
    while True:
        kmax, fres, gres = residuals(st, F)
        if fres <= tol * kmax and gres <= 1e-14:
            break
        if it >= max_iter:
            break
        sub, diag, sup, rhs = _linear_system(st, F, closed, free_start, free_end, prev)
        dd = _solve_tridiagonal(sub, diag, sup, rhs, closed)
        if not np.all(np.isfinite(dd)):
            break
        dA = -(st["G"] + st["G_0"] * dd[:m] + st["G_1"] * dd[nxt]) / st["G_A"]
        # a step of more than one radian in any angle leaves the region where
        # the linearisation means anything
        step = min(1.0, 1.0 / max(float(np.max(np.abs(dd))), 1e-300))
        accepted = False
        for _ in range(30):
            st_t, F_t, m_t = state(d + step * dd, A + step * dA)
            if st_t is not None and m_t <= (1.0 - 1e-4 * step) * merit:
                accepted = True
                break
            step *= 0.5
        it += 1
        if not accepted:
            break
        d, A, st, F, merit = d + step * dd, A + step * dA, st_t, F_t, m_t
    kmax, fres, gres = residuals(st, F)
    # the rounding floor can stop the last halving short of tol: accept what
    # is still far inside the documented guarantee
    ok = (fres <= max(tol, 1e-11) * kmax or fres <= 1e-14) and gres <= 1e-13
    return d, A, st, it, ok, fres / kmax if kmax > 0 else 0.0, gres


@dataclass(frozen=True)
class QICSpline:
    """A G2 spline of clothoid segments through points (see :func:`qic_spline`).

    Attributes
    ----------
    points : ndarray, shape (N, 2)
        The interpolated points (image pixels, y down unless ``y_down`` was
        False).
    closed : bool
    x0, y0, theta0 : ndarray, shape (M,)
        Start point and tangent angle (input coordinates) of each segment.
    k0, dk, length : ndarray, shape (M,)
        Start curvature and curvature rate, in the input coordinates'
        sign (d theta / ds), and length of each segment (px).
    start : ndarray of int, shape (M,)
        Index of the point at which each segment starts.
    sign : float
        Factor from input-coordinate curvature to geometric curvature.
    iterations : int
        Newton iterations (summed over pieces when there are corners).
    g2_error : float
        Largest curvature jump at a smooth join divided by the largest
        |curvature|, as solved.
    closure_error : float
        Largest segment end-point miss relative to the curve's size.
    loops : int
        Segments whose tangent turns by more than pi.
    corners : tuple of int
        Points where a G0 corner was allowed.
    seconds : float
        Time taken by the fit.
    """

    points: np.ndarray
    closed: bool
    x0: np.ndarray
    y0: np.ndarray
    theta0: np.ndarray
    k0: np.ndarray
    dk: np.ndarray
    length: np.ndarray
    start: np.ndarray
    sign: float
    iterations: int
    g2_error: float
    closure_error: float
    loops: int
    corners: tuple = field(default_factory=tuple)
    seconds: float = 0.0
    method: str = "qic"

    @property
    def n_points(self):
        return len(self.points)

    @property
    def interior_extrema(self):
        """Curvature extrema strictly inside segments, counted on 32 samples
        per segment (zero by construction: curvature is linear in arc length
        on every segment)."""
        return self.metrics(32)["interior_extrema"]

    @property
    def node_curvature(self):
        """Geometric curvature at the start of each segment (1/px)."""
        return self.sign * self.k0

    @property
    def end_curvature(self):
        """Geometric curvature at the end of each segment (1/px)."""
        return self.sign * (self.k0 + self.dk * self.length)

    def sample(self, samples=32):
        """Sample every segment at `samples` points equally spaced in arc
        length, both end points included.

        Returns
        -------
        SampledCurve
        """
        samples = int(samples)
        if samples < 2:
            raise InputError(f"samples: expected at least 2 per segment, got {samples}")
        u = np.linspace(0.0, 1.0, samples)
        s_loc = self.length[:, None] * u[None, :]
        x, y, th, k = clothoid_points(
            self.x0[:, None], self.y0[:, None], self.theta0[:, None],
            self.k0[:, None], self.dk[:, None], s_loc,
        )
        offs = np.r_[0.0, np.cumsum(self.length)[:-1]]
        s = (offs[:, None] + s_loc).ravel()
        seg = np.repeat(self.start, samples)
        return SampledCurve(
            s=s, x=x.ravel(), y=y.ravel(), curvature=self.sign * k.ravel(), segment=seg,
            theta=th.ravel(), closed=self.closed, breaks=tuple(self.corners),
        )

    def metrics(self, samples=32):
        """:func:`~stimuli.curve_metrics.curve_metrics` of :meth:`sample`,
        with the solver's own figures (``iterations``, ``solver_g2_error``,
        ``closure_error``)."""
        out = curve_metrics(self.sample(samples))
        out.update(iterations=self.iterations, solver_g2_error=self.g2_error, closure_error=self.closure_error)
        return out


def _unit_angle(vec, what):
    v = np.asarray(vec, dtype=float).reshape(-1)
    if v.size == 1:
        raise InputError(f"{what}: expected a direction vector (dx, dy), got a single number")
    if v.size != 2 or not np.all(np.isfinite(v)) or np.hypot(*v) == 0:
        raise InputError(f"{what}: expected a non-zero finite direction vector (dx, dy)")
    return float(np.arctan2(v[1], v[0]))


def qic_spline(points, closed=True, *, end_tangents=(None, None), corners=(), tol=1e-12,
               max_iter=50, y_down=True):
    """Fit the QIC spline: a G2 spline of clothoid segments through points.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (x = column, y = row, y down). A
        closed curve must not repeat its first point at the end.
    closed : bool
        Closed curve (N segments) or open curve (N - 1 segments).
    end_tangents : (vector or None, vector or None)
        Open curves only: tangent direction ``(dx, dy)`` at the first and at
        the last point, in the input coordinates. ``None`` gives a natural
        end (zero curvature).
    corners : sequence of int
        Points where the spline may break its tangent (a G0 corner). The
        curve is split there into open pieces with natural ends.
    tol : float
        Newton stops when every curvature jump is below ``tol`` times the
        largest |curvature| and every segment closes to 1e-14 of its chord.
    max_iter : int
        Bound on Newton iterations (each with at most 30 step halvings).
    y_down : bool
        Whether y points down (image pixels). Only the sign of reported
        curvature for open curves depends on it.

    Returns
    -------
    QICSpline
        The segments, with ``iterations``, ``g2_error``, ``closure_error``,
        ``loops`` and ``seconds``. ``.sample(k)`` gives the curve, and
        ``.metrics(k)`` adds the interior curvature extrema counted on the
        samples (zero by construction).

    Raises
    ------
    InputError
        Bad points (non-finite, too few, repeated consecutive points) or
        options.
    ConvergenceError
        Newton did not converge within `max_iter` iterations, e.g. for
        jagged or randomly ordered points.

    Notes
    -----
    Scale invariant: the points are scaled by their mean chord length before
    solving. Each iteration costs O(N) (a tridiagonal, cyclic for closed
    curves, solve by LAPACK ``dgtsv`` and Sherman-Morrison).

    References
    ----------
    .. [1] E. Bertolazzi and M. Frego, "G1 fitting with clothoids", Math.
           Meth. Appl. Sci. 38(5), 881-897, 2015.
    .. [2] E. Bertolazzi and M. Frego, "Interpolating clothoid splines with
           curvature continuity", Math. Meth. Appl. Sci. 41(4), 2018.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> sp = qic_spline(np.c_[50 + 20 * np.cos(t), 50 - 20 * np.sin(t)])
    >>> round(float(sp.node_curvature[0]), 10)   # a circle of radius 20
    0.05
    """
    t_start = time.perf_counter()
    P = _as_points(points, closed)
    N = len(P)
    corners = sorted({int(c) for c in corners})
    for c in corners:
        if not (0 <= c < N):
            raise InputError(f"corners: index {c} out of range 0..{N - 1}")
    ts, te = end_tangents if end_tangents is not None else (None, None)
    if closed and (ts is not None or te is not None):
        raise InputError("end_tangents: only for open curves")
    ts = None if ts is None else _unit_angle(ts, "end_tangents[0]")
    te = None if te is None else _unit_angle(te, "end_tangents[1]")
    if not closed:
        corners = [c for c in corners if 0 < c < N - 1]

    # pieces: (node indices, closed?, start tangent, end tangent)
    if closed and not corners:
        pieces = [(np.arange(N), True, None, None)]
    elif closed:
        order = np.roll(np.arange(N), -corners[0])
        cuts = [int(np.flatnonzero(order == c)[0]) for c in corners] + [N]
        pieces = [(np.r_[order[a:b], order[b % N]], False, None, None) for a, b in zip(cuts[:-1], cuts[1:])]
    else:
        cuts = [0] + corners + [N - 1]
        pieces = [
            (np.arange(a, b + 1), False, ts if a == 0 else None, te if b == N - 1 else None)
            for a, b in zip(cuts[:-1], cuts[1:])
        ]

    segs = []
    total_it = 0
    worst_g2 = 0.0
    worst_close = 0.0
    size = float(np.max(np.ptp(P, axis=0))) or 1.0
    for idx, pclosed, t0, t1 in pieces:
        Q = P[idx]
        Qn = np.concatenate((Q[1:], Q[:1])) if pclosed else Q[1:]
        D = Qn - Q[: len(Qn)]
        r = np.hypot(D[:, 0], D[:, 1])
        h = float(np.mean(r))
        rn = r / h
        phi = np.arctan2(D[:, 1], D[:, 0])
        p0i, p1i = _initial_angles(phi, rn, pclosed, t0, t1)
        d, A, st, it, ok, g2, gres = _newton(
            p0i, p1i, rn, pclosed, t0 is None, t1 is None, tol, max_iter
        )
        total_it += it
        if not ok:
            raise ConvergenceError(
                f"QIC spline did not converge in {it} iterations (max curvature jump "
                f"{g2:.2g} of max |k|, closure {gres:.2g}); the points may be jagged, "
                "out of order or too sparse for a smooth curve"
            )
        if st["X0"].min() < _MIN_X0:
            # Newton can also "converge" towards a segment of unbounded length whose
            # curvature and closure residuals vanish with it (e.g. a closed curve
            # through collinear points): a bad curve, not a solution
            j = int(np.argmin(st["X0"]))
            raise ConvergenceError(
                f"QIC spline degenerates: the segment from point {int(idx[j])} would be "
                f"{1 / st['X0'][j]:.2g} times as long as its chord; the points may be "
                "collinear, out of order or too sparse for a smooth curve"
            )
        nseg = r.size
        nxt = np.r_[1 : d.size, 0] if pclosed else np.arange(1, d.size)
        p0 = p0i + d[:nseg]
        p1 = p1i + d[nxt]
        L = st["L"] * h
        k0 = st["k0"] / h
        dk = (st["k1"] - st["k0"]) / st["L"] / h**2
        # each segment ends at r (1, G / X0) in its chord frame: the miss is
        # r |G| / X0 (the tests check it independently by sampling)
        worst_close = max(worst_close, float(np.abs(r * st["G"] / st["X0"]).max()) / size)
        worst_g2 = max(worst_g2, g2)
        # loops: range of theta(tau) = p0 + (delta - A) tau + A tau^2 on [0, 1]
        delta = p1 - p0
        with np.errstate(divide="ignore", invalid="ignore"):
            tv = np.clip(np.where(A != 0, (A - delta) / (2 * A), 0.0), 0.0, 1.0)
        th_v = (delta - A) * tv + A * tv * tv
        hi = np.maximum(np.maximum(0.0, delta), th_v)
        lo = np.minimum(np.minimum(0.0, delta), th_v)
        segs.append((idx[:nseg], Q[:nseg], phi + p0, k0, dk, L, hi - lo))
    start = np.concatenate([s[0] for s in segs])
    # pieces of a closed curve with corners start at the first corner: put
    # the segments back in order from the first point
    order = np.argsort(start, kind="stable") if len(segs) > 1 else slice(None)
    start = start[order]
    Q0 = np.concatenate([s[1] for s in segs])[order]
    turning = np.concatenate([s[6] for s in segs])
    sp = QICSpline(
        points=P, closed=closed, x0=Q0[:, 0], y0=Q0[:, 1],
        theta0=np.concatenate([s[2] for s in segs])[order], k0=np.concatenate([s[3] for s in segs])[order],
        dk=np.concatenate([s[4] for s in segs])[order], length=np.concatenate([s[5] for s in segs])[order],
        start=start, sign=_geometric_sign(P, closed, y_down), iterations=total_it,
        g2_error=worst_g2, closure_error=worst_close, loops=int(np.count_nonzero(turning > np.pi)),
        corners=tuple(corners), seconds=time.perf_counter() - t_start,
    )
    return sp


# ----------------------------------------------------------------------------
# polynomial baselines


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
        samples = int(samples)
        if samples < 2:
            raise InputError(f"samples: expected at least 2 per segment, got {samples}")
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
        """:func:`~stimuli.curve_metrics.curve_metrics` of :meth:`sample`."""
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
    P = _as_points(points, closed)
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
        sign=_geometric_sign(P, closed, y_down), seconds=time.perf_counter() - t0, method=method,
    )


def fit_spline(points, method="qic", closed=True, **kwargs):
    """Fit any of the spline methods by name.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (y down).
    method : str
        ``'qic'`` (:func:`qic_spline`), ``'cubic'`` (periodic when closed,
        not-a-knot when open), ``'cubic-natural'`` (open only),
        ``'poly2'`` .. ``'poly5'`` (:func:`polynomial_spline`; ``'poly3'``
        is the same curve as ``'cubic'``), ``'lac-g1'``
        (:func:`stimuli.lac.lac_g1_spline`).
    closed : bool
    **kwargs
        Passed to the fitting function.

    Returns
    -------
    QICSpline, PolynomialSpline or LACSpline
        Each has ``sample(k)``, ``metrics(k)``, ``iterations``, ``seconds``
        and ``method``.
    """
    if method == "qic":
        return qic_spline(points, closed, **kwargs)
    if method == "cubic":
        return polynomial_spline(points, 3, closed, **kwargs)
    if method == "cubic-natural":
        if closed:
            raise InputError("method 'cubic-natural' is for open curves (use --open)")
        return polynomial_spline(points, 3, False, bc_type="natural", **kwargs)
    if method in ("poly2", "poly3", "poly4", "poly5"):
        sp = polynomial_spline(points, int(method[-1]), closed, **kwargs)
        return replace(sp, method=method)
    if method == "lac-g1":
        from stimuli.curves.lac import lac_g1_spline

        return lac_g1_spline(points, closed, **kwargs)
    raise InputError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
