"""Log-aesthetic arcs given by their end curvatures: the segments of the G2
log-aesthetic spline (:mod:`stimuli.curves.lac_spline`).

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
arc's length.

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

import numpy as np

__all__ = [
    "is_zero_alpha", "graph_value", "graph_inverse", "arc_curvature", "arc_turn", "arc_singular_point", "graded_rule", "quadrature_groups",
    "arc_integrals",
]

# Gauss-Legendre nodes per panel, and the geometric grading of the panels
# towards t*: panel edges at t* + (end - t*) * SIGMA**k, k = 0..LEVELS
# (finer far from t*, where a long panel meets the arc's whole oscillation)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
_GL_X_WIDE, _GL_W_WIDE = np.polynomial.legendre.leggauss(24)  # arcs far from t*, on [-1, 1]
_EDGES = np.r_[1.0, 0.7, 0.45, 0.25, 0.25 * 0.2 ** np.arange(1, 9), 0.0]  # 1 .. 0, far end towards t*


def is_zero_alpha(alpha):
    """Whether alpha is treated as 0 (Nielsen's spiral, g = log|k|)."""
    return abs(alpha) < 1e-12


def _v(k, alpha):
    """The graph variable ``g(k) = sign(k)|k|**(-alpha)`` (alpha < 0)."""
    return np.sign(k) * np.abs(k) ** (-alpha)


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
    k0 = np.asarray(k0, dtype=float)
    k1 = np.asarray(k1, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ell = np.log(k1 / k0)
    if is_zero_alpha(alpha):
        return k0, ell
    return k0, np.expm1(-alpha * ell)


def _params(t, k0, k1, alpha):
    """(t, same sign?, same-sign parameters a, b, and for alpha < 0 the
    graph variable at both ends, else None) of arcs, as arrays."""
    t = np.asarray(t, dtype=float)
    k0 = np.asarray(k0, dtype=float)
    k1 = np.asarray(k1, dtype=float)
    same = k0 * k1 > 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a, b = _same_sign_params(np.where(same, k0, 1.0), np.where(same, k1, 1.0), alpha)
    if alpha < 0 and not is_zero_alpha(alpha):
        return t, same, a, b, _v(k0, alpha), _v(k1, alpha)
    return t, same, a, b, None, None


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
    t, same, a, b, v0, v1 = _params(t, k0, k1, alpha)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ks = a * np.exp(b * t) if is_zero_alpha(alpha) else a * np.exp(-np.log1p(t * b) / alpha)
        if v0 is None:
            return np.where(same, ks, np.nan)
        v = v0 + t * (v1 - v0)
        return np.where(same, ks, np.sign(v) * np.abs(v) ** (-1.0 / alpha))


def arc_turn(t, k0, k1, alpha):
    """``Theta(t) = int_0^t kappa(u) du`` on the unit parameter (multiply by
    the arc's length for the tangent's turn). NaN where no arc of this alpha
    has these end curvatures (alpha >= 0 with k0, k1 not of one sign).

    Examples
    --------
    >>> float(arc_turn(1.0, 1.0, 3.0, -1.0))           # clothoid: the mean curvature
    2.0
    >>> round(float(arc_turn(1.0, 1.0, np.e, 0.0)), 12)   # alpha = 0: (e - 1) / 1
    1.718281828459
    """
    t, same, a, b, v0, v1 = _params(t, k0, k1, alpha)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if not np.any(same):
            ts = 0.0
        elif is_zero_alpha(alpha):
            ts = a * np.where(b == 0, t, np.expm1(b * t) / b)
        else:
            A = np.log1p(t * b)
            q = 1.0 - 1.0 / alpha
            core = A / b if q == 0 else np.expm1(q * A) / (q * b)
            ts = a * np.where(b == 0, t, core)
        if v0 is None:
            return np.where(same, ts, np.nan)
        if np.all(same):
            return ts
        p1 = 1.0 - 1.0 / alpha  # p + 1
        dv = v1 - v0
        v = v0 + t * dv
        return np.where(same, ts, np.where(dv == 0, 0.0, (np.abs(v) ** p1 - np.abs(v0) ** p1) / (p1 * dv)))


def arc_singular_point(k0, k1, alpha):
    """Unit parameter where the graph variable ``g(kappa)`` would reach 0
    (inside [0, 1] at an inflection; +-inf when there is none)."""
    k0 = np.asarray(k0, dtype=float)
    k1 = np.asarray(k1, dtype=float)
    same = k0 * k1 > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        if is_zero_alpha(alpha):
            ts = np.full(k0.shape, np.inf)
        else:
            _, b = _same_sign_params(np.where(same, k0, 1.0), np.where(same, k1, 1.0), alpha)
            ts = np.where(b == 0, np.inf, -1.0 / b)
        if alpha < 0:
            v0, v1 = _v(k0, alpha), _v(k1, alpha)
            to = np.where(v0 == v1, np.inf, v0 / (v0 - v1))
        else:
            to = np.full(k0.shape, np.inf)
    return np.where(same, ts, to)


def graded_rule(a, b, tstar):
    """Quadrature nodes and weights on the intervals ``[a, b]`` (one per row),
    graded geometrically towards ``clip(tstar, a, b)`` from both sides.

    Returns
    -------
    nodes, weights : ndarray, shape (R, Q)

    Examples
    --------
    >>> x, w = graded_rule(np.array([0.0]), np.array([1.0]), np.array([0.3]))
    >>> round(float(np.sum(w * np.sqrt(np.abs(x - 0.3)))), 11)   # a sqrt kink at 0.3
    0.49998585722
    >>> round(2 / 3 * (0.3 ** 1.5 + 0.7 ** 1.5), 11)
    0.49998585722
    """
    a = np.asarray(a, dtype=float)[:, None]
    b = np.asarray(b, dtype=float)[:, None]
    c = np.clip(np.nan_to_num(np.asarray(tstar, dtype=float), nan=1.0, posinf=2.0, neginf=-1.0)[:, None], a, b)
    f = _EDGES[None, :]
    left = c - (c - a) * f   # a .. c
    right = c + (b - c) * f  # b .. c
    lo = np.concatenate((left[:, :-1], right[:, 1:]), axis=1)
    hi = np.concatenate((left[:, 1:], right[:, :-1]), axis=1)
    half = 0.5 * (hi - lo)
    mid = 0.5 * (hi + lo)
    nodes = (mid[:, :, None] + half[:, :, None] * _GL_X).reshape(a.shape[0], -1)
    weights = (np.abs(half)[:, :, None] * _GL_W).reshape(a.shape[0], -1)
    return nodes, weights


def quadrature_groups(lo, hi, tstar):
    """Quadrature rules for the intervals ``[lo, hi]`` (one per row) of arcs
    whose graph variable vanishes at `tstar`.

    Intervals whose `tstar` lies at least their own length beyond them see
    an integrand analytic on a wide ellipse: one 24-point Gauss rule does.
    The rest get :func:`graded_rule`.

    Returns
    -------
    list of (rows, nodes, weights)
        Row indices and their nodes and weights, shape (len(rows), Q).
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    tstar = np.asarray(tstar, dtype=float)
    span = hi - lo
    easy = ~((tstar > lo - span) & (tstar < hi + span))
    out = []
    rows = np.flatnonzero(easy)
    if rows.size:
        half = 0.5 * span[rows, None]
        out.append((rows, lo[rows, None] + half * (1.0 + _GL_X_WIDE), half * _GL_W_WIDE))
    rows = np.flatnonzero(~easy)
    if rows.size:
        out.append((rows, *graded_rule(lo[rows], hi[rows], tstar[rows])))
    return out


def arc_integrals(theta0, k0, k1, L, alpha, derivatives=False):
    """Chord of each arc, its turn and (optionally) their derivatives.

    Parameters
    ----------
    theta0, k0, k1, L : ndarray, shape (M,)
        Start tangent angle, end curvatures and length of each arc.
    alpha : float
    derivatives : bool

    Returns
    -------
    dict
        ``z`` (complex chord: end minus start point), ``turn`` (``L Theta(1)``)
        and with `derivatives` ``z_L``, ``z_u0``, ``z_u1`` (``z_theta0`` is
        ``1j * z``), ``turn_u0``, ``turn_u1`` (``turn_L`` is ``Theta(1)``),
        the derivatives in the end curvatures' graph variables
        (:func:`graph_value`), in closed form (central differences for
        nearly circular arcs).
    """
    M = k0.size
    out = {}
    for rows, x, w in quadrature_groups(np.zeros(M), np.ones(M), arc_singular_point(k0, k1, alpha)):
        part = _integrals_on(x, w, theta0[rows], k0[rows], k1[rows], L[rows], alpha, derivatives)
        for key, val in part.items():
            if key not in out:
                out[key] = np.empty(M, dtype=val.dtype)
            out[key][rows] = val
    return out


def _integrals_on(x, w, theta0, k0, k1, L, alpha, derivatives):
    """:func:`arc_integrals` with the quadrature nodes `x` and weights `w`
    (one row per arc) on [0, 1]."""
    Th = arc_turn(x, k0[:, None], k1[:, None], alpha)
    e = np.exp(1j * (theta0[:, None] + L[:, None] * Th)) * w
    z = L * e.sum(axis=1)
    T1 = arc_turn(1.0, k0, k1, alpha)
    out = {"z": z, "Theta1": T1, "turn": L * T1}
    if not derivatives:
        return out
    out["z_L"] = z / L + 1j * L * (Th * e).sum(axis=1)
    # derivatives in the graph variables u = g(k) (in which the equations
    # stay smooth where a node's curvature passes through 0): with u linear
    # in t and kappa = g^-1(u), d kappa/d u0 = (1 - t) kappa'(t) / du, and
    # integrating by parts (derived here)
    #   d Theta(t)/d u0 = ((1 - t) kappa(t) - k0 + Theta(t)) / du,
    #   d Theta(t)/d u1 = (t kappa(t) - Theta(t)) / du,   du = u1 - u0;
    # nearly circular arcs (|du| small: the quotient cancels) take central
    # differences instead
    u0, u1 = graph_value(k0, alpha), graph_value(k1, alpha)
    du = u1 - u0
    scale = np.maximum(np.abs(u0), np.abs(u1))
    far = np.abs(du) > 1e-5 * np.maximum(scale, 1e-6)
    for key in ("z_u0", "z_u1", "turn_u0", "turn_u1"):
        out[key] = np.empty(k0.size, dtype=complex if key[0] == "z" else float)
    if far.any():
        f = np.flatnonzero(far)
        kap = arc_curvature(x[f], k0[f, None], k1[f, None], alpha)
        d = du[f, None]
        for name, dTh, dT1 in (
            ("u0", ((1.0 - x[f]) * kap - k0[f, None] + Th[f]) / d, (T1[f] - k0[f]) / du[f]),
            ("u1", (x[f] * kap - Th[f]) / d, (k1[f] - T1[f]) / du[f]),
        ):
            out["z_" + name][f] = 1j * L[f] * L[f] * (dTh * e[f]).sum(axis=1)
            out["turn_" + name][f] = L[f] * dT1
    if not far.all():
        c = np.flatnonzero(~far)
        for key, val in _central_differences(x[c], e[c], k0[c], k1[c], L[c], alpha).items():
            out[key][c] = val
    return out


def _central_differences(x, e, k0, k1, L, alpha):
    """The derivatives of :func:`_integrals_on` in u0, u1 by central
    differences of the closed-form Theta (relative step 1e-6)."""
    u0, u1 = graph_value(k0, alpha), graph_value(k1, alpha)
    scale = np.maximum(np.abs(u0), np.abs(u1))
    positive = alpha > 0 and not is_zero_alpha(alpha)  # u > 0: relative steps
    out = {}
    for name, k, u, other, first in (("u0", k0, u0, k1, True), ("u1", k1, u1, k0, False)):
        h = 1e-6 * (u if positive else np.maximum(np.maximum(np.abs(u), 1e-3 * scale), 1e-6))
        sg = np.where(k < 0, -1.0, 1.0)
        kp, km = graph_inverse(u + h, alpha, sg), graph_inverse(u - h, alpha, sg)
        args_p = (kp, other) if first else (other, kp)
        args_m = (km, other) if first else (other, km)
        dTh = (arc_turn(x, args_p[0][:, None], args_p[1][:, None], alpha)
               - arc_turn(x, args_m[0][:, None], args_m[1][:, None], alpha)) / (2 * h[:, None])
        out["z_" + name] = 1j * L * L * (dTh * e).sum(axis=1)
        out["turn_" + name] = L * (arc_turn(1.0, *args_p, alpha) - arc_turn(1.0, *args_m, alpha)) / (2 * h)
    return out
