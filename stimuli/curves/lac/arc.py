"""Log-aesthetic arcs given by their end curvatures: the segments of the G2
log-aesthetic spline (:mod:`attneave.stimuli.curves.lac.spline`).

A log-aesthetic curve of slope alpha has ``rho**alpha`` linear in arc length
(eq. 9: ``rho = (lam alpha s + 1)**(1/alpha)``; ``log rho`` linear when
alpha = 0), i.e. ``ds / d(log rho) = rho**alpha / lam``: its log
curvature-radius graph is a straight line of slope alpha. So an arc of length
L, with the unit parameter ``t = s / L``, is fixed by its end curvatures
``k0, k1``:

    g(kappa(t)) = (1 - t) g(k0) + t g(k1),   g(k) = sign(k) |k|**(-alpha)
    (g = log|k| when alpha = 0),

and its curvature is monotone because g is. For alpha < 0 g is continuous
through ``k = 0``, so an arc may pass through an inflection (curvature
``sign(v)|v|**p``, ``p = -1/alpha``; alpha = -1 is the clothoid, curvature
linear in t); on each side of it the log curvature graph is the same line
(``|rho|``). This is the symmetric continuation of the S-shaped LAC of
Gobithaasan, Yip & Miura (2014), written here in this form (derived here, as
are the formulas below). For alpha >= 0 no arc has an inflection: k0 and k1
must have the same sign.

The turning ``Theta(t) = int_0^t kappa`` is in closed form (derived here):

- same sign, alpha != 0: ``c = (k1/k0)**(-alpha) - 1``, ``q = 1 - 1/alpha``,
  ``Theta = k0 ((1 + t c)**q - 1) / (q c)`` (``k0 log(1 + t c)/c`` for
  alpha = 1), with expm1/log1p so that nearly circular arcs lose nothing;
- same sign, alpha = 0: ``l = log(k1/k0)``, ``Theta = k0 (exp(l t) - 1)/l``;
- an inflection (alpha < 0): with ``v = g(kappa)`` linear in t,
  ``Theta = (|v(t)|**(p+1) - |v0|**(p+1)) / ((p + 1)(v1 - v0))``.

The position ``L int_0^t exp(i (theta0 + L Theta))`` is integrated by
Gauss-Legendre on panels graded geometrically towards the point ``t*`` where
``v = 0`` (the inflection, or where the arc's curvature would vanish or blow
up beyond its ends), so that the weak singularity of ``|v|**p`` costs no
accuracy: the result agrees with adaptive quadrature to about 1e-14 of the
arc's length. The grading goes as deep as the singularity's order asks
(:func:`grading_levels`: fewer panels for alpha near 0, whose arcs are
smoother at t*).

Evaluation cost. Newton evaluates the arcs many times with few arcs
(12-80): :class:`ArcIntegrals` computes every arc's parameters once, the
nodes of all arcs of one rule and one kind in one pass, Theta(1) in the
same pass, and keeps the quadrature so that the derivatives, asked only at
the points Newton steps from, reuse it.

Angles are in the input coordinates (radians from +x towards +y), curvature
is ``d theta / ds`` in the same coordinates.

References
----------
.. [1] R. U. Gobithaasan, S. W. Yip and K. T. Miura, "Log-aesthetic curves
       for shape completion problem", J. Applied Mathematics 2014, 960302.
.. [2] N. Yoshida and T. Saito, "Interactive aesthetic curve segments",
       The Visual Computer 22(9-11), 896-905, 2006.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from attneave.stimuli.curves.lac.quadrature import LEVELS, quadrature_groups

__all__ = [
    "is_zero_alpha", "graph_value", "graph_inverse", "arc_curvature", "arc_turn", "arc_singular_point",
    "grading_levels", "piece_chords", "arc_integrals", "ArcIntegrals",
]

def is_zero_alpha(alpha):
    """Whether alpha is treated as 0 (Nielsen's spiral, g = log|k|)."""
    return abs(alpha) < 1e-12


def _v(k, alpha):
    """The graph variable ``g(k) = sign(k)|k|**(-alpha)`` (alpha < 0)."""
    return np.copysign(np.abs(k) ** (-alpha), k)


def graph_value(k, alpha):
    """The graph variable ``u = g(k)`` in which a LAC arc is linear:
    ``sign(k)|k|**(-alpha)`` for alpha < 0, ``|k|**(-alpha)`` for alpha > 0
    and ``log|k|`` for alpha = 0 (the sign of k is then kept apart).

    Examples
    --------
    >>> float(graph_value(-2.0, -1.0)), float(graph_value(4.0, 0.5))
    (-2.0, 0.5)
    """
    k = np.asarray(k, dtype=float)
    if is_zero_alpha(alpha):
        return np.log(np.abs(k))
    if alpha > 0:
        return np.abs(k) ** (-alpha)
    return _v(k, alpha)


def graph_inverse(u, alpha, sign=1.0):
    """Curvature from the graph variable (inverse of :func:`graph_value`);
    `sign` is the curvature's sign for alpha >= 0."""
    u = np.asarray(u, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if is_zero_alpha(alpha):
            return sign * np.exp(u)
        if alpha > 0:
            return sign * u ** (-1.0 / alpha)
        return np.sign(u) * np.abs(u) ** (-1.0 / alpha)


def _same_sign_params(k0, k1, alpha):
    """(a, b) of same-sign arcs (callers silence floating-point warnings)."""
    ell = np.log(k1 / k0)
    if is_zero_alpha(alpha):
        return k0, ell
    return k0, np.expm1(-alpha * ell)


def _params(k0, k1, alpha):
    """(same sign?, same-sign parameters a, b, and for alpha < 0 the graph
    variable at both ends, else None) of arcs, as arrays."""
    k0 = np.asarray(k0, dtype=float)
    k1 = np.asarray(k1, dtype=float)
    same = k0 * k1 > 0
    with np.errstate(all="ignore"):
        a, b = _same_sign_params(np.where(same, k0, 1.0), np.where(same, k1, 1.0), alpha)
        if alpha < 0 and not is_zero_alpha(alpha):
            return same, a, b, _v(k0, alpha), _v(k1, alpha)
    return same, a, b, None, None


# The closed forms of the module notes, on arcs of one kind (callers broadcast
# t against the parameters and silence floating-point warnings): same sign
# (a = k0 and b from _same_sign_params) and through an inflection (v0 and
# dv = v1 - v0, alpha < 0). The turn's helpers also return what the
# curvature at the same t shares with it (log1p(t b), resp. v(t)).

def _turn_same(t, a, b, alpha):
    if is_zero_alpha(alpha):
        return a * np.where(b == 0, t, np.expm1(b * t) / b), None
    A = np.log1p(t * b)
    q = 1.0 - 1.0 / alpha
    core = A / b if q == 0 else np.expm1(q * A) / (q * b)
    return a * np.where(b == 0, t, core), A


def _curvature_same(t, a, b, alpha, A=None):
    if is_zero_alpha(alpha):
        return a * np.exp(b * t)
    return a * np.exp(-(np.log1p(t * b) if A is None else A) / alpha)


def _turn_inflected(t, v0, dv, alpha):
    p1 = 1.0 - 1.0 / alpha  # p + 1
    v = v0 + t * dv
    return np.where(dv == 0, 0.0, (np.abs(v) ** p1 - np.abs(v0) ** p1) / (p1 * dv)), v


def _curvature_inflected(v, alpha):
    return np.copysign(np.abs(v) ** (-1.0 / alpha), v)


def _turn(t, same, a, b, v0, v1, alpha):
    """:func:`arc_turn` from the arcs' parameters (:func:`_params`)."""
    ts = _turn_same(t, a, b, alpha)[0] if np.any(same) else 0.0
    if v0 is None:
        return np.where(same, ts, np.nan)
    if np.all(same):
        return ts
    return np.where(same, ts, _turn_inflected(t, v0, v1 - v0, alpha)[0])


def _singular_point(same, b, v0, v1, alpha):
    """:func:`arc_singular_point` from the arcs' parameters (:func:`_params`)."""
    shape = np.shape(same)
    ts = np.full(shape, np.inf) if is_zero_alpha(alpha) else np.where(b == 0, np.inf, -1.0 / b)
    to = np.where(v0 == v1, np.inf, v0 / (v0 - v1)) if v0 is not None else np.full(shape, np.inf)
    return np.where(same, ts, to)


def arc_curvature(t, k0, k1, alpha):
    """Curvature at unit parameter(s) `t` of the arcs with end curvatures
    `k0`, `k1` (broadcast).

    Examples
    --------
    >>> float(arc_curvature(0.5, 1.0, 3.0, -1.0))      # alpha = -1: linear
    2.0
    >>> round(float(arc_curvature(0.5, 1.0, 4.0, 0.0)), 12)   # alpha = 0: geometric mean
    2.0
    """
    t = np.asarray(t, dtype=float)
    same, a, b, v0, v1 = _params(k0, k1, alpha)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ks = _curvature_same(t, a, b, alpha)
        if v0 is None:
            return np.where(same, ks, np.nan)
        return np.where(same, ks, _curvature_inflected(v0 + t * (v1 - v0), alpha))


def arc_turn(t, k0, k1, alpha):
    """``Theta(t) = int_0^t kappa(u) du`` on the unit parameter (multiply by
    the arc's length for the tangent's turn). NaN where no arc of this alpha
    has these end curvatures (alpha >= 0 with k0, k1 not of one sign).

    Examples
    --------
    >>> round(float(arc_turn(1.0, 1.0, 3.0, -1.0)), 12)   # clothoid: the mean curvature
    2.0
    >>> round(float(arc_turn(1.0, 1.0, np.e, 0.0)), 12)   # alpha = 0: (e - 1) / 1
    1.718281828459
    """
    t = np.asarray(t, dtype=float)
    params = _params(k0, k1, alpha)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _turn(t, *params, alpha)


def arc_singular_point(k0, k1, alpha):
    """Unit parameter where the graph variable ``g(kappa)`` would reach 0
    (inside [0, 1] at an inflection; +-inf when there is none)."""
    same, _, b, v0, v1 = _params(k0, k1, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        return _singular_point(same, b, v0, v1, alpha)


def grading_levels(alpha):
    """Geometric levels of :func:`~attneave.stimuli.curves.lac.quadrature.graded_rule` that arcs of this alpha need.

    Near ``t*`` an arc's turn behaves like ``|t - t*|**beta``, ``beta = 1 -
    1/alpha`` (alpha < 0: the graph variable ``|v|**(p + 1)``, at an
    inflection or where a same-sign arc's curvature would vanish), so the
    panel that ends at ``t*`` (length ``l`` of a side's length) holds a
    singular part of order ``l**(beta + 1)``; its Gauss rule's error is a
    small fraction of that. Levels are added until ``l**(beta + 1) <=
    1e-16`` (derived here): 8 for alpha = -2 (beta = 1.5, the deepest), 7
    for the clothoid, 4 for alpha = -0.3; alpha >= 0 (curvature that blows
    up at t*) takes all 8. The rule then agrees with the deepest one to
    rounding (about 4e-16 of the arc's length on arcs turning by up to 100
    radians).

    Examples
    --------
    >>> [grading_levels(a) for a in (-2.0, -1.0, -0.5, -0.3, 0.0, 1.0)]
    [8, 7, 5, 4, 8, 8]
    """
    if alpha >= 0 or is_zero_alpha(alpha):
        return LEVELS
    beta = 1.0 - 1.0 / alpha
    levels = math.ceil(math.log(1e-16 ** (1.0 / (beta + 1.0)) / 0.25) / math.log(0.2))
    return min(max(levels, 1), LEVELS)


def _quadrature_blocks(params, alpha, lo, hi, arcs=None, ends=False):
    """The quadrature of pieces ``[lo, hi]`` (unit parameter) of arcs with
    parameters `params` (:func:`_params`), in blocks of one rule
    (:func:`~attneave.stimuli.curves.lac.quadrature.quadrature_groups`) and one kind (same-sign curvature, or
    through an inflection, or no arc of this alpha: NaN).

    Yields
    ------
    rows, arcs, kind, nodes, weights, turn, share
        The pieces and their arcs (`arcs`: each piece's arc; default: one
        piece per arc), whether of one sign, the rule, Theta at the nodes
        and what the curvature there shares with it (see :func:`_turn_same`);
        with `ends`, turn and share have one more column: t = 1 (Theta(1)
        from the same pass).
    """
    same, a, b, v0, v1 = params
    tstar = _singular_point(same, b, v0, v1, alpha)
    for rows, x, w in quadrature_groups(lo, hi, tstar if arcs is None else tstar[arcs], grading_levels(alpha)):
        of = rows if arcs is None else arcs[rows]
        one_sign = same[of]
        for kind in (True, False):
            pick = one_sign if kind else ~one_sign
            if not pick.any():
                continue
            r, ar = rows[pick], of[pick]
            xk = x if x.shape[0] == 1 else x[pick]
            wk = w if w.shape[0] == 1 else w[pick]
            xt = np.concatenate((xk, np.ones((xk.shape[0], 1))), axis=1) if ends else xk
            if kind:
                Th, share = _turn_same(xt, a[ar, None], b[ar, None], alpha)
            elif v0 is not None:
                Th, share = _turn_inflected(xt, v0[ar, None], (v1 - v0)[ar, None], alpha)
            else:
                Th, share = np.full((r.size, xt.shape[1]), np.nan), None
            yield r, ar, kind, xk, wk, Th, share


def piece_chords(theta0, k0, k1, L, alpha, lo, hi, arcs):
    """Chords ``L int_lo^hi exp(i theta(t)) dt`` of pieces of arcs (each
    piece by the rule of :func:`~attneave.stimuli.curves.lac.quadrature.quadrature_groups`).

    Parameters
    ----------
    theta0, k0, k1, L : ndarray, shape (M,)
        Start tangent angle, end curvatures and length of each arc.
    alpha : float
    lo, hi : ndarray, shape (R,)
        The pieces on the unit parameter.
    arcs : ndarray of int, shape (R,)
        The arc of each piece.

    Returns
    -------
    ndarray of complex, shape (R,)

    Examples
    --------
    Two halves of a unit-curvature clothoid arc (alpha = -1) of length pi: quarter circles.

    >>> one, halves = np.ones(1), (np.array([0, 0.5]), np.array([0.5, 1]))
    >>> dz = piece_chords(0 * one, one, one, np.pi * one, -1.0, *halves, np.zeros(2, int))
    >>> np.round(dz, 12).tolist()
    [(1+1j), (-1+1j)]
    """
    theta0, L = np.asarray(theta0, dtype=float), np.asarray(L, dtype=float)
    dz = np.empty(np.shape(lo), dtype=complex)
    with np.errstate(all="ignore"):
        params = _params(k0, k1, alpha)
        for r, ar, _, _, w, Th, _ in _quadrature_blocks(params, alpha, lo, hi, np.asarray(arcs)):
            dz[r] = L[ar] * (np.exp(1j * (theta0[ar, None] + L[ar, None] * Th)) * w).sum(axis=1)
    return dz


def arc_integrals(theta0, k0, k1, L, alpha, derivatives=False):
    """Chord of each arc, its turn and (optionally) their derivatives.

    Parameters
    ----------
    theta0, k0, k1, L : ndarray, shape (M,)
        Start tangent angle, end curvatures and length of each arc.
    alpha : float
    derivatives : bool
        Compute the derivatives now (otherwise on first access).

    Returns
    -------
    ArcIntegrals
        A mapping: ``z`` (complex chord: end minus start point), ``turn``
        (``L Theta(1)``), ``Theta1`` and the derivatives ``z_L``, ``z_u0``,
        ``z_u1`` (``z_theta0`` is ``1j * z``), ``turn_u0``, ``turn_u1``
        (``turn_L`` is ``Theta(1)``), in the end curvatures' graph variables
        (:func:`graph_value`), in closed form (central differences for
        nearly circular arcs).

    Examples
    --------
    A clothoid arc (alpha = -1) of constant curvature 1 and length pi: a half circle.

    >>> out = arc_integrals(np.zeros(1), np.ones(1), np.ones(1), np.array([np.pi]), -1.0)
    >>> complex(np.round(out["z"][0], 12)), float(out["turn"][0]) == np.pi
    (2j, True)
    """
    arcs = ArcIntegrals(theta0, k0, k1, L, alpha)
    if derivatives:
        arcs.derive()
    return arcs


_VALUES = ("z", "Theta1", "turn")
_DERIVATIVES = ("z_L", "z_u0", "z_u1", "turn_u0", "turn_u1")


class ArcIntegrals(Mapping):
    """The chords and turns of log-aesthetic arcs (see :func:`arc_integrals`),
    keeping their quadrature (nodes, turns and phase factors), so that the
    derivatives come from the same evaluation when they are first asked
    for: Newton needs them only at the points it steps from, which its line
    search has just evaluated.

    The arcs are evaluated in blocks of one quadrature rule and one kind
    (same-sign curvature, or through an inflection), each with its own
    closed form.
    """

    def __init__(self, theta0, k0, k1, L, alpha):
        theta0, k0, k1, L = (np.asarray(v, dtype=float) for v in (theta0, k0, k1, L))
        self.alpha, self.k0, self.k1, self.L = alpha, k0, k1, L
        z = np.empty(k0.size, dtype=complex)
        self.blocks = []
        with np.errstate(all="ignore"):
            self._params = _params(k0, k1, alpha)
            T1 = np.empty(k0.size)
            for r, _, kind, x, w, Th, share in _quadrature_blocks(self._params, alpha, 0.0, 1.0, ends=True):
                T1[r] = Th[:, -1]
                Th = Th[:, :-1]
                share = None if share is None else share[:, :-1]
                e = np.exp(1j * (theta0[r, None] + L[r, None] * Th)) * w
                esum = e.sum(axis=1)
                z[r] = L[r] * esum
                self.blocks.append((r, kind, x, Th, e, esum, share))
        self.values = {"z": z, "Theta1": T1, "turn": L * T1}

    def __getitem__(self, key):
        if key in _DERIVATIVES:
            self.derive()
        return self.values[key]

    def __iter__(self):
        return iter(_VALUES + _DERIVATIVES)

    def __len__(self):
        return len(_VALUES) + len(_DERIVATIVES)

    def derive(self):
        """Add the derivatives (once)."""
        if "z_L" in self.values:
            return
        alpha, k0, k1, L = self.alpha, self.k0, self.k1, self.L
        _, a, b, _, _ = self._params
        z, T1 = self.values["z"], self.values["Theta1"]
        out = {key: np.empty(k0.size, dtype=complex if key[0] == "z" else float) for key in _DERIVATIVES}
        # derivatives in the graph variables u = g(k) (in which the equations
        # stay smooth where a node's curvature passes through 0): with u linear
        # in t and kappa = g^-1(u), d kappa/d u0 = (1 - t) kappa'(t) / du, and
        # integrating by parts (derived here)
        #   d Theta(t)/d u0 = ((1 - t) kappa(t) - k0 + Theta(t)) / du,
        #   d Theta(t)/d u1 = (t kappa(t) - Theta(t)) / du,   du = u1 - u0;
        # nearly circular arcs (|du| small: the quotient cancels) take central
        # differences instead
        with np.errstate(all="ignore"):  # 0/0 where no arc of this alpha exists: NaN, rejected by Newton
            u0, u1 = graph_value(k0, alpha), graph_value(k1, alpha)
            du = u1 - u0
            scale = np.maximum(np.abs(u0), np.abs(u1))
            far = np.abs(du) > 1e-5 * np.maximum(scale, 1e-6)
            fr = np.flatnonzero(far)
            out["turn_u0"][fr] = L[fr] * ((T1[fr] - k0[fr]) / du[fr])
            out["turn_u1"][fr] = L[fr] * ((k1[fr] - T1[fr]) / du[fr])
            # sums over every arc's nodes of Theta e, kappa e and t kappa e (with the
            # sum of e, z / L, they give both integrals of dTheta e, in fewer passes
            # over the nodes than dTheta itself), then the derivatives of all arcs at once
            ST, Sk, Sxk = (np.empty(k0.size, dtype=complex) for _ in range(3))
            for r, kind, x, Th, e, _, share in self.blocks:
                ST[r] = (Th * e).sum(axis=1)
                if kind:
                    kap = _curvature_same(x, a[r, None], b[r, None], alpha, share)
                else:
                    kap = _curvature_inflected(share, alpha) if share is not None else np.nan
                ke = kap * e
                Sk[r], Sxk[r] = ke.sum(axis=1), (x * ke).sum(axis=1)
            out["z_L"][:] = z / L + 1j * L * ST
            c = 1j * L[fr] * L[fr] / du[fr]
            out["z_u0"][fr] = c * (Sk[fr] - Sxk[fr] - k0[fr] * (z[fr] / L[fr]) + ST[fr])
            out["z_u1"][fr] = c * (Sxk[fr] - ST[fr])
            if not far.all():  # nearly circular arcs: central differences
                for r, _, x, Th, e, _, _ in self.blocks:
                    near = ~far[r]
                    if near.any():
                        rc = r[near]
                        xc = np.broadcast_to(x, Th.shape)[near]
                        for key, val in _central_differences(xc, e[near], k0[rc], k1[rc], L[rc], alpha).items():
                            out[key][rc] = val
        self.values.update(out)


def _central_differences(x, e, k0, k1, L, alpha):
    """The derivatives of :class:`ArcIntegrals` in u0, u1 by central
    differences of the closed-form Theta (relative step 1e-6): the four
    shifted arcs, at the nodes `x` (shape (C, Q)) and at t = 1, in one
    evaluation."""
    u0, u1 = graph_value(k0, alpha), graph_value(k1, alpha)
    scale = np.maximum(np.abs(u0), np.abs(u1))
    positive = alpha > 0 and not is_zero_alpha(alpha)  # u > 0: relative steps
    steps, starts, ends = [], [], []
    for k, u, first in ((k0, u0, True), (k1, u1, False)):
        h = 1e-6 * (u if positive else np.maximum(np.maximum(np.abs(u), 1e-3 * scale), 1e-6))
        sg = np.where(k < 0, -1.0, 1.0)
        kp, km = graph_inverse(u + h, alpha, sg), graph_inverse(u - h, alpha, sg)
        steps.append(h)
        starts += [kp, km] if first else [k0, k0]
        ends += [k1, k1] if first else [kp, km]
    C = k0.size
    t = np.tile(np.concatenate((x, np.ones((C, 1))), axis=1), (4, 1))
    Th = arc_turn(t, np.concatenate(starts)[:, None], np.concatenate(ends)[:, None], alpha).reshape(4, C, -1)
    out = {}
    for i, name in enumerate(("u0", "u1")):
        h = steps[i]
        plus, minus = Th[2 * i], Th[2 * i + 1]
        dTh = (plus[:, :-1] - minus[:, :-1]) / (2 * h[:, None])
        out["z_" + name] = 1j * L * L * (dTh * e).sum(axis=1)
        out["turn_" + name] = L * (plus[:, -1] - minus[:, -1]) / (2 * h)
    return out
