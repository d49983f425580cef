"""Log-aesthetic curves in closed form: positions through the incomplete
gamma function (Ziatdinov, Yoshida & Kim 2012), and the generalised
log-aesthetic curves (GLAC) of Miura & Gobithaasan.

A log-aesthetic curve (the seed paper's eq. 9) has radius of curvature
``rho(s) = (lam alpha s + 1)**(1/alpha)`` (``exp(lam s)`` when alpha = 0)
and tangent angle ``theta(s) = ((lam alpha s + 1)**p - 1) / (lam alpha p)``
with ``p = (alpha - 1)/alpha``, so that ``rho = 1`` and ``theta = 0`` at
``s = 0``. Its position ``z(s) = int_0^s exp(i theta(u)) du`` is, with
``tau = (lam alpha u + 1)**p`` and ``c = lam alpha p = lam (alpha - 1)``,

    z(s) = exp(-i/c) / c * int_1^tau(s) t**a exp(i t / c) dt,   a = 1/(alpha - 1),

and the substitution ``w = -i t / c`` (a rotation of the path, on which the
principal branches agree) turns the integral into the generalised incomplete
gamma function:

    int_1^tau t**a exp(i t/c) dt = (i c)**(a + 1) * Gamma(a + 1; -i/c, -i tau/c),

``Gamma(b; w0, w1) = int_w0^w1 t**(b-1) exp(-t) dt`` (mpmath's
``gammainc(b, w0) - gammainc(b, w1)``, evaluated at 30 digits). alpha = 0 (Nielsen's
spiral) is the limit ``b -> 0`` and becomes the exponential integral E1;
alpha = 1 (the logarithmic spiral) is elementary,
``z = ((1 + lam s)**(1 + i/lam) - 1) / (lam + i)``; lam = 0 is the unit
circle. This is the paper's result written for the arc-length form of eq. 9
(the paper states it for the tangent-angle form; both have the same lam,
``rho(psi) = ((alpha - 1) lam psi + 1)**(1/(alpha - 1))``); the special
cases are derived here in the same way.

The closed form is exact but costly: 1-5 ms of mpmath per arc length at 30
digits, and near alpha = 1, where ``b = alpha/(alpha - 1)`` is large and
the two incomplete gammas (of size about ``Gamma(b)``) cancel to thousands
of digits, seconds (alpha = 0.999 took 19 s for 201 points) or never (a
curve with large lam and small alpha ran for minutes). :func:`lac_position`
therefore integrates ``exp(i theta)`` of the closed-form tangent angle by
16-point Gauss-Legendre on panels (:func:`_panel_quadrature`): within
3e-15 of the arc length of the closed form on the 90 cases compared (13
alphas from -2 to 3, 0.985-1.05 among them; lam -3 to 100; arc lengths on
both sides of 0) and 4e-16 at arc lengths within 1e-14 of the pole, in
0.3 ms against the closed form's 4 ms (medians). The closed form (``_gamma_form``) is the reference
the tests hold both to, and the answer where the panels would exceed
``_MAX_PANELS`` (a curve winding thousands of times).

References
----------
.. [1] R. Ziatdinov, N. Yoshida and T. Kim, "Analytic parametric equations
       of log-aesthetic curves in terms of incomplete gamma functions",
       Computer Aided Geometric Design 29(2), 129-140, 2012.
.. [2] K. T. Miura and R. U. Gobithaasan, "Aesthetic design with
       log-aesthetic curves and surfaces", and R. U. Gobithaasan and
       K. T. Miura, "Aesthetic spiral for design", Sains Malaysiana 40(11),
       1301-1305, 2011 (GLAC).
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["lac_theta", "lac_position", "lac_domain_end", "log_rho"]

_DPS = 30  # mpmath digits: the difference of two incomplete gammas may cancel
_MAX_EXTRA_DPS = 3000  # digits beyond _DPS the closed form may need (a few ms per value)
_MAX_ANCHORS = 64  # closed-form evaluations per call (about 1-5 ms each)
_GL_T, _GL_W = np.polynomial.legendre.leggauss(16)
_MAX_PANELS = 200_000  # panel quadrature's budget (about 0.1 s); beyond it the closed form
_LN2 = float(np.log(2.0))
# alpha = 0 with |lam| below this: the E1 form in mpmath (double precision
# loses about 1e-16/|lam| to the phase 1/lam, measured: 1e-14 at lam = 1e-2,
# 8e-11 at 1e-6, and every digit below lam = 1e-16)
_NIELSEN_MP_BELOW = 1e-2


def lac_theta(s, alpha, lam):
    """Tangent angle of the eq. 9 LAC at arc length `s` (theta(0) = 0).

    Examples
    --------
    >>> round(float(lac_theta(1.0, -1.0, 0.5)), 12)   # clothoid: kappa = 1 - s/2
    0.75
    """
    s = np.asarray(s, dtype=float)
    if lam == 0:
        return s.copy()
    if alpha == 0:
        return -np.expm1(-lam * s) / lam
    if alpha == 1:
        with np.errstate(divide="ignore"):  # base 0 at a domain end: L = -inf
            return np.log1p(lam * s) / lam
    # theta = expm1((alpha - 1) * Q) / (lam (alpha - 1)) with Q = log1p(lam alpha s) / alpha
    # = lam s * log1p(x)/x: stable for every alpha, however small (no 1/alpha times a
    # rounded log1p of an underflowing product)
    den = lam * (alpha - 1.0)
    if abs(den) < np.finfo(float).tiny:
        # lam (alpha - 1) underflows (lam subnormal): 0/0 gave NaN. With y = (alpha - 1) Q,
        # theta = Q/lam * expm1(y)/y = s * log1p(x)/x * expm1(y)/y, with no division by it
        y = (alpha - 1.0) * log_rho(s, alpha, lam)
        with np.errstate(divide="ignore", invalid="ignore"):
            e = np.where(np.abs(y) < 1e-10, 1.0 + 0.5 * y, np.expm1(y) / y)
        return s * _log1p_ratio(lam * alpha * s) * e
    return np.expm1((alpha - 1.0) * log_rho(s, alpha, lam)) / den


def _log1p_ratio(x):
    """``log1p(x) / x`` (1 at x = 0), accurate for tiny and subnormal x."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.log1p(x) / x
    # below 1e-10 the series 1 - x/2 is exact to rounding; x = -1 gives -inf (log1p(-1))
    return np.where(np.abs(x) < 1e-10, 1.0 - 0.5 * x, r)


def log_rho(s, alpha, lam):
    """``ln rho(s)`` of the eq. 9 LAC: ``lam s`` (alpha = 0) or
    ``ln(lam alpha s + 1) / alpha``, computed as ``lam s * log1p(x)/x`` with
    ``x = lam alpha s`` so that it tends to the alpha = 0 value continuously
    (no cancellation or underflow for alpha as small as 1e-308).

    Examples
    --------
    >>> float(log_rho(3.0, 1e-300, 1.0))   # the alpha -> 0 limit, lam s
    3.0
    """
    s = np.asarray(s, dtype=float)
    if lam == 0:
        return np.zeros_like(s)
    if alpha == 0:
        return lam * s
    x = lam * alpha * s
    with np.errstate(divide="ignore", invalid="ignore"):
        # x = -1 (an end of the domain): ln(0)/alpha, -inf (rho = 0) for alpha > 0,
        # +inf (rho = inf, curvature 0) for alpha < 0
        return np.where(x == -1.0, -np.inf if alpha > 0 else np.inf, lam * s * _log1p_ratio(x))


def lac_domain_end(alpha, lam):
    """Arc length where ``lam alpha s + 1`` reaches 0 (the curve's end on
    that side), or None when the domain is unbounded."""
    if lam == 0 or alpha == 0:
        return None
    return -1.0 / (lam * alpha)


def lac_position(s, alpha, lam):
    """Position ``x + i y = int_0^s exp(i theta(u)) du`` of the eq. 9 LAC,
    in closed form (see the module notes).

    Parameters
    ----------
    s : array_like
        Arc lengths (any sign) inside the domain ``lam alpha s + 1 >= 0``.
    alpha, lam : float
        Shape parameter and rate of eq. 9.

    Returns
    -------
    ndarray of complex
        Positions (y up: angles counter-clockwise), same shape as `s`.

    Raises
    ------
    InputError
        Non-finite parameters or an arc length outside the domain.

    Examples
    --------
    >>> z = lac_position([np.pi], 0.0, 0.0)        # lam = 0: the unit circle
    >>> bool(np.isclose(z[0], 2j))
    True
    >>> z = lac_position([1.0], 1.0, 0.5)           # alpha = 1: a logarithmic spiral
    >>> bool(np.isclose(z[0], (1.5 ** (1 + 2j) - 1) / (0.5 + 1j)))
    True
    """
    alpha = float(alpha)
    lam = float(lam)
    if not (np.isfinite(alpha) and np.isfinite(lam)):
        raise InputError(f"lac: alpha and lam must be finite, got alpha={alpha!r}, lam={lam!r}")
    s = np.asarray(s, dtype=float)
    smax = float(np.max(np.abs(s))) if s.size else 0.0
    if lam == 0 or abs(lam) * smax * smax <= 2.0**-60:
        # theta(s) = s - lam s^2/2 + ..., so the curve leaves the unit circle by at most
        # |lam| |s|^3 / 6 <= |s| 2**-60 / 6, below the rounding of z: the circle is exact. (The
        # closed form's digits grow as log(1/|lam|): at a subnormal lam, lam (alpha - 1)
        # underflowed to 0 and it raised OverflowError.)
        return 1j * -np.expm1(1j * s)
    if alpha == 0 and abs(lam) >= _NIELSEN_MP_BELOW:
        return _nielsen(s, lam)
    base = lam * alpha * s + 1.0
    if np.any(base < 0) or (alpha > 0 and np.any(base == 0)):
        raise InputError(f"lac: arc lengths leave the domain lam*alpha*s + 1 > 0 (alpha={alpha:g}, lam={lam:g})")
    if alpha == 1:
        # rho = 1 + lam s: z = int (1 + lam u)**(i/lam) du
        e = 1.0 + 1j / lam
        return np.expm1(e * np.log1p(lam * s)) / (lam * e)
    flat = s.ravel()
    z = _panel_quadrature(flat, alpha, lam)
    if z is not None:
        return z.reshape(s.shape)
    closed = _nielsen_mp if alpha == 0 else _gamma_form

    if flat.size <= _MAX_ANCHORS:
        return closed(flat, alpha, lam).reshape(s.shape)
    # a dense grid: the closed form at every k-th arc length (anchors) and,
    # from the nearest anchor below, 16-point Gauss-Legendre of exp(i theta)
    # over the short rest (exact to rounding for this smooth integrand)
    order = np.argsort(flat, kind="stable")
    u = flat[order]
    k = -(-u.size // _MAX_ANCHORS)
    anchors = np.r_[u[::k], u[-1]]
    za = closed(anchors, alpha, lam)
    j = np.minimum(np.searchsorted(anchors, u, side="right") - 1, anchors.size - 1)
    lo = anchors[j]
    half = 0.5 * (u - lo)
    q = (lo + half)[:, None] + half[:, None] * _GL_T[None, :]
    z = za[j] + (np.exp(1j * lac_theta(q, alpha, lam)) @ _GL_W) * half
    out = np.empty(flat.size, dtype=complex)
    out[order] = z
    return out.reshape(s.shape)


def _panel_quadrature(s, alpha, lam, max_panels=None):
    """``int_0^s exp(i theta(u)) du`` at the 1-D arc lengths `s` by 16-point
    Gauss-Legendre on panels between them and 0; None when that takes more
    than `max_panels` (default ``_MAX_PANELS``) panels.

    A panel is split (into at most 64 equal ones at a time) while theta
    turns on it by more than 0.5 rad, or while rho changes on it by more
    than a factor of 2 and theta by more than 1e-16 rad: on the panels left
    the integrand is a slow, nearly uniform rotation, which Gauss-Legendre
    integrates exactly to rounding, or so nearly constant (``|exp(i theta)
    - exp(i theta_a)| <= 1e-16``) that any rule of positive weights does. A
    curve that straightens out (large lam) is then a few panels, whatever
    rho does.
    """
    max_panels = _MAX_PANELS if max_panels is None else max_panels
    edges = np.unique(np.r_[s, 0.0])
    for _ in range(200):
        with np.errstate(all="ignore"):
            turn = np.abs(np.diff(lac_theta(edges, alpha, lam)))
            grow = np.abs(np.diff(log_rho(edges, alpha, lam)))
        finite = np.isfinite(turn) & np.isfinite(grow)
        parts = np.where(turn > 0.5, np.ceil(turn / 0.5), 1.0)
        parts = np.where((grow > _LN2) & (turn > 1e-16), np.maximum(parts, np.ceil(grow / _LN2)), parts)
        parts = np.where(finite, np.minimum(parts, 64), 4).astype(np.int64)
        if parts.max() == 1:
            break
        if parts.sum() > max_panels:
            return None
        # each panel cut into `parts` equal ones
        which = np.repeat(np.arange(edges.size - 1), parts)
        k = np.arange(which.size) - (np.cumsum(parts) - parts)[which]
        edges = np.r_[edges[which] + (edges[which + 1] - edges[which]) * k / parts[which], edges[-1]]
    else:
        return None
    half = 0.5 * np.diff(edges)
    q = (edges[:-1] + half)[:, None] + half[:, None] * _GL_T[None, :]
    with np.errstate(all="ignore"):
        z = np.r_[0.0, np.cumsum((np.exp(1j * lac_theta(q, alpha, lam)) @ _GL_W) * half)]
    return z[np.searchsorted(edges, s)] - z[np.searchsorted(edges, 0.0)]


def _gamma_form(s, alpha, lam):
    """:func:`_gamma_form_mp`, with mpmath's own failures (a series that does not
    converge) as one InputError naming alpha and lam."""
    import mpmath

    try:
        return _gamma_form_mp(s, alpha, lam)
    except mpmath.libmp.NoConvergence:
        raise InputError(
            f"alpha: the LAC's closed form does not converge for alpha={alpha:g}, lam={lam:g} "
            "(alpha near 1 is hardest); use alpha = 1 exactly, or alpha further from 1"
        ) from None


def _gamma_form_mp(s, alpha, lam):
    """The incomplete-gamma closed form at each of the 1-D arc lengths `s`.

    Every alpha-dependent quantity is formed in mpmath from the exact float
    alpha: ``b = alpha/(alpha - 1)`` and ``tau = exp(p log1p(lam alpha u))``.
    The naive ``(lam alpha u + 1)**p`` rounds the base to 1 once
    ``|lam alpha u|`` is below the working precision (alpha < ~1e-30 at
    30 digits), and the curve collapsed to the origin; ``p log1p(...)`` is
    ``(alpha - 1) lam u (1 + O(lam alpha u))``, exact to the working precision
    for any alpha down to the smallest float, so tiny alpha reaches the
    alpha = 0 limit (Nielsen's spiral) continuously.
    """
    import mpmath

    out = np.empty(s.shape, dtype=complex)
    # the two gammas are of size about |c|**-b and cancel: carry extra digits
    # (from the logarithms of the factors: their product may underflow to 0)
    dps = _DPS + int(max(0.0, -(np.log10(abs(lam)) + np.log10(abs(alpha - 1.0))))) * 2
    # and they can be far larger than that (about Gamma(b) for alpha near 1: 1e158 at
    # alpha = 1.01), while z is at most the arc length: measure the terms' size (their
    # magnitudes are right at any precision) and carry as many more digits as they exceed
    # the arc length by (without this, alpha = 1.01, lam = 100 gave z off by 0.86 at s = 1)
    scale = float(np.max(np.abs(s))) if s.size else 0.0
    if scale > 0:
        with mpmath.workdps(dps):
            al, lm = mpmath.mpf(alpha), mpmath.mpf(lam)
            b, p, c = al / (al - 1), (al - 1) / al, lm * (al - 1)
            mi = mpmath.mpc(0, -1)
            front = abs(mpmath.exp(mi / c) / c * mpmath.power(mpmath.mpc(0, c), b))
            u = s[np.argmax(np.abs(s))]
            tau = mpmath.exp(p * mpmath.log1p(lm * al * mpmath.mpf(float(u))))
            size = front * max(abs(mpmath.gammainc(b, mi / c)), abs(mpmath.gammainc(b, mi * tau / c)))
            excess = float(mpmath.log10(size / scale)) if size > 0 else 0.0
        if excess > _MAX_EXTRA_DPS:
            raise InputError(
                f"alpha: the LAC's closed form needs about {int(excess) + _DPS} digits for alpha={alpha:g}, "
                f"lam={lam:g} (its incomplete gammas cancel; alpha near 1 is hardest); "
                "use alpha = 1 exactly, or alpha further from 1, or a smaller |lam|"
            )
        dps += int(max(0.0, excess)) + 5
    with mpmath.workdps(dps):
        al = mpmath.mpf(alpha)
        lm = mpmath.mpf(lam)
        b = al / (al - 1)  # a + 1, without the cancellation of 1/(alpha - 1) + 1
        p = (al - 1) / al
        c = lm * (al - 1)
        mi = mpmath.mpc(0, -1)
        front = mpmath.exp(mi / c) / c * mpmath.power(mpmath.mpc(0, c), b)
        # upper incomplete gammas, differenced: mpmath's two-sided form does
        # not take b = 0, -1, -2, ... (alpha = 1/2, 2/3, ...)
        g0 = mpmath.gammainc(b, mi / c)
        for i, u in enumerate(s):
            if u == 0:
                out[i] = 0.0
                continue
            tau = mpmath.exp(p * mpmath.log1p(lm * al * mpmath.mpf(float(u))))
            out[i] = complex(front * (g0 - mpmath.gammainc(b, mi * tau / c)))
    return out


#: Below this |m| (alpha = 0), E1(i m) is its two-term series in ln m (next term m**2/4).
_NIELSEN_SERIES_BELOW = 1e-8


def _nielsen(s, lam):
    """alpha = 0: theta = (1 - exp(-lam s))/lam; with m = exp(-lam u)/lam,
    z = -exp(i/lam)/lam * (E1(i/lam) - E1(i m(s))) (derived as in the module notes).

    For lam > 0 and large lam s, m underflows (to 0 beyond lam s ~ 745, where
    E1 is infinite and z was NaN): there ``E1(i m) = -gamma - ln m - i pi/2 + i m + O(m**2)``
    with ``ln m = -lam s - ln lam`` exact, so z grows linearly in s, as the
    curve does (its tangent tends to the constant 1/lam)."""
    from scipy.special import exp1

    s = np.asarray(s, dtype=float)
    m0 = 1.0 / lam
    with np.errstate(under="ignore"):
        m = np.exp(-lam * s) / lam
    e = np.empty(s.shape, dtype=complex)
    tiny = (m < _NIELSEN_SERIES_BELOW) if lam > 0 else np.zeros(s.shape, dtype=bool)
    e[~tiny] = exp1(1j * m[~tiny])
    if tiny.any():
        log_m = -lam * s[tiny] - np.log(lam)
        e[tiny] = (-np.euler_gamma - log_m) + 1j * (m[tiny] - 0.5 * np.pi)
    return -np.exp(1j * m0) / lam * (exp1(1j * m0) - e)


def _nielsen_mp(s, alpha, lam):
    """:func:`_nielsen` in mpmath with ``2 log10(1/|lam|)`` extra digits, for
    small |lam| where the phase ``1/lam`` and the cancelling E1 terms defeat
    double precision (`alpha` is 0, taken for the signature of
    :func:`_gamma_form`)."""
    import mpmath

    out = np.empty(s.shape, dtype=complex)
    dps = _DPS + int(max(0.0, -np.log10(abs(lam)))) * 2
    with mpmath.workdps(dps):
        lm = mpmath.mpf(lam)
        i0 = mpmath.mpc(0, 1 / lm)
        front = -mpmath.exp(i0) / lm
        e0 = mpmath.e1(i0)
        for i, u in enumerate(s):
            if u == 0:
                out[i] = 0.0
                continue
            m = mpmath.exp(-lm * mpmath.mpf(float(u))) / lm
            out[i] = complex(front * (e0 - mpmath.e1(mpmath.mpc(0, m))))
    return out
