"""Statistics of clicks along contours.

All functions take plain arrays. A stimulus is described by its ``n`` equally
spaced contour points (the points of :func:`stimuli.information.surprisal`);
a click is described by its stimulus and its arc position ``t`` in [0, 1),
and, for the choice model, by the index ``j = round(n * t) mod n`` of the
nearest of the n points.

The choice model
----------------
A click on stimulus s lands on point j with probability

    p(j) = exp(beta * z_sj) / sum_i exp(beta * z_si),

where ``z_s`` is the prediction (surprisal, or a rival) standardised over the
stimulus's n points (mean 0, population sd 1; a constant prediction gives
z = 0, which carries no information). Because the points are equally spaced,
this discrete choice is the same as a density over t that is constant on each
point's arc of length 1/n: ``p(t) = n * p(j)``. The simulated observers of
:mod:`analysis.observers` draw clicks from exactly this model, so the fit is
consistent with them. Log-likelihoods are reported for the discrete choice
(a uniform observer scores ``-log n`` per click); add ``log n`` per click for
the density over t.

The log-likelihood of the clicks of one group (the whole data set, one
participant or one stimulus) depends on them only through ``A = sum z`` at
the clicks and the counts ``M_s`` of clicks per stimulus::

    l(beta)  = beta * A - sum_s M_s * log sum_i exp(beta * z_si)
    l'(beta) = A - sum_s M_s * E_s[z]            (the score)
    -l''     = sum_s M_s * Var_s[z]              (Fisher information)

with E and Var under p. ``l`` is concave, so the score has one root, found
here by Newton's method safeguarded by bisection (vectorised over groups);
the Wald interval uses the Fisher information and the profile-likelihood
interval solves ``l(beta) = l(beta_hat) - chi2_1(level)/2`` with
:func:`scipy.optimize.brentq`.

The group test
--------------
Each participant's effect is the mean of z over that participant's clicks.
It is the score statistic of the model at beta = 0 divided by the number of
clicks (so it is the locally most powerful per-participant statistic); under
the null of clicks uniform along the contour it has expectation exactly 0,
since z has mean 0 over the points; and it stays finite with any number of
clicks, where a per-participant ML beta does not (it is infinite when all of
a participant's few clicks fall on the highest-z points). The effects are
compared across participants by their one-sample t statistic. This two-stage
"summary statistics" approach treats participants as a random effect (Holmes
& Friston 1998); the same test across stimuli (each stimulus's mean z) is the
items analysis that treats stimuli as random (Clark 1973). A crossed mixed
model would combine both; it is not fitted here, so no dependency is added.

The t statistic is not referred to the t distribution: on stimuli whose
surprisal is spiky (polygons: z up to ~10 at a few corners) a participant's
mean z over few clicks is strongly right-skewed, and the t-test is then too
liberal (false-positive rates of 0.10-0.40 at alpha = 0.05 were measured
with 1-10 clicks per participant on the Attneave polygon set). A signed-rank
test would be no better: it assumes effects symmetric around 0. Instead the
statistic is calibrated by Monte Carlo under the exact null of uniform
clicking with the observed design (:func:`mean_z_test`): each click keeps its
stimulus and participant and its point is redrawn uniformly among the
stimulus's n points, R times; ``p = (1 + #{null >= t}) / (1 + R)``,
one-sided, since the hypothesis is that clicks favour high surprisal. This is
an exact test of uniform clicking for every design (its size is at most
alpha up to the resolution 1/(1+R)). The t statistic, Cohen's d_z and the t
interval of the mean are kept as descriptive values.

References
----------
.. [1] Holmes, A. P., & Friston, K. J. (1998). Generalisability, random
       effects and population inference. NeuroImage 7, S754.
.. [2] Clark, H. H. (1973). The language-as-fixed-effect fallacy. Journal of
       Verbal Learning and Verbal Behavior 12, 335-359.
.. [3] Norman, J. F., Phillips, F., & Ross, H. E. (2001). Information
       concentration along the boundary contours of naturally shaped solid
       objects. Perception 30, 1285-1294.
"""

from __future__ import annotations

import numpy as np
import scipy.optimize
import scipy.special
import scipy.stats

__all__ = [
    "standardize",
    "point_index",
    "circular_kde",
    "fit_beta",
    "profile_ci",
    "blur_kernel",
    "fit_beta_blurred",
    "loglik",
    "circular_spearman",
    "shift_indices",
    "mean_rho_null",
    "peak_chance",
    "peak_hits",
    "midrank_percentile",
    "group_test",
    "t_statistic",
    "mean_z_null",
    "mean_z_test",
]


def standardize(u, axis=-1, rtol=1e-9):
    """Standardise values along `axis`: mean 0, population sd 1.

    Parameters
    ----------
    u : array_like
        Predictions at the n points of each stimulus.
    axis : int
        The axis of the points.
    rtol : float
        A prediction whose sd is below ``rtol * max(1, |mean|)`` is treated as
        constant (a circle's surprisal, up to rounding) and gets z = 0
        everywhere rather than amplified rounding noise.

    Returns
    -------
    ndarray
        z, same shape as `u`.

    Examples
    --------
    >>> standardize([1.0, 2.0, 3.0]).round(4).tolist()
    [-1.2247, 0.0, 1.2247]
    >>> standardize([5.0, 5.0, 5.0]).tolist()
    [0.0, 0.0, 0.0]
    """
    u = np.asarray(u, dtype=float)
    mean = u.mean(axis=axis, keepdims=True)
    sd = u.std(axis=axis, keepdims=True)
    const = sd <= rtol * np.maximum(1.0, np.abs(mean))
    return np.where(const, 0.0, (u - mean) / np.where(const, 1.0, sd))


def point_index(t, n):
    """Index of the nearest of n equally spaced points (point j at t = j/n)."""
    return np.mod(np.rint(np.asarray(t, dtype=float) * n).astype(np.int64), n)


def circular_kde(t, bandwidth, m=1024, group=None, n_groups=None):
    """Circular kernel density of positions along a closed contour.

    A wrapped Gaussian kernel, evaluated on a grid of `m` equally spaced
    positions: the positions are binned linearly onto the grid and convolved
    in the Fourier domain with the wrapped Gaussian, whose Fourier
    coefficients are exactly ``exp(-2 * pi**2 * k**2 * h**2)``.

    Parameters
    ----------
    t : (N,) array_like
        Arc positions in [0, 1) (fractions of the perimeter).
    bandwidth : float or (G,) array_like
        Kernel sd ``h`` in units of t (bandwidth in pixels of arc length
        divided by the perimeter), per group if an array.
    m : int
        Grid size; the grid is ``t = arange(m) / m``.
    group : (N,) array_like of int, optional
        Group (stimulus) of each position, in ``range(n_groups)``.
    n_groups : int, optional
        Number of groups (default ``max(group) + 1``).

    Returns
    -------
    (m,) or (G, m) ndarray
        Density with respect to t (it integrates to 1 over [0, 1), so a
        uniform density is 1). A group without positions gets NaN.
    """
    t = np.mod(np.asarray(t, dtype=float), 1.0)
    single = group is None
    group = np.zeros(len(t), np.int64) if single else np.asarray(group, dtype=np.int64)
    G = 1 if single else int(n_groups if n_groups is not None else (group.max() + 1 if len(group) else 0))
    pos = t * m
    lo = np.floor(pos).astype(np.int64)
    frac = pos - lo
    lo %= m
    hi = (lo + 1) % m
    base = group * m
    hist = np.bincount(base + lo, weights=1.0 - frac, minlength=G * m)
    hist += np.bincount(base + hi, weights=frac, minlength=G * m)
    hist = hist.reshape(G, m)
    counts = hist.sum(axis=1, keepdims=True)
    k = np.fft.rfftfreq(m, d=1.0 / m)
    h = np.broadcast_to(np.asarray(bandwidth, dtype=float), (G,))[:, None]
    kernel = np.exp(-2.0 * np.pi**2 * k[None, :] ** 2 * h**2)
    dens = np.fft.irfft(np.fft.rfft(hist, axis=1) * kernel, n=m, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        dens = dens * m / counts
    dens[counts[:, 0] == 0] = np.nan
    return dens[0] if single else dens


# ----------------------------------------------------------------- the choice model
def _moments(beta, Z):
    """log-sum-exp, E and Var of z under p ∝ exp(beta z), row by row.

    beta (P,), Z (P, n) -> lse (P,), E (P,), V (P,).
    """
    x = beta[:, None] * Z
    mx = x.max(axis=1, keepdims=True)
    w = np.exp(x - mx)
    sw = w.sum(axis=1)
    E = np.einsum("pn,pn->p", w, Z) / sw
    E2 = np.einsum("pn,pn->p", w, Z * Z) / sw
    lse = np.log(sw) + mx[:, 0]
    return lse, E, np.maximum(E2 - E * E, 0.0)


def _pairs(M):
    """The (group, stimulus, count) triples of the non-zero counts of M (G, S)."""
    g, s = np.nonzero(M)
    return g, s, M[g, s]


def loglik(beta, Z, A, M):
    """Log-likelihood of the discrete choice model for each group.

    Parameters
    ----------
    beta : float or (G,) array_like
    Z : (S, n) array_like
        Standardised predictions at the n points of each stimulus.
    A : float or (G,) array_like
        Sum of z over each group's clicks.
    M : (S,) or (G, S) array_like
        Number of clicks of each group on each stimulus.

    Returns
    -------
    float or (G,) ndarray
    """
    scalar = np.ndim(beta) == 0 and np.ndim(A) == 0 and np.ndim(M) == 1
    M = np.atleast_2d(np.asarray(M, dtype=float))
    G = M.shape[0]
    beta = np.broadcast_to(np.atleast_1d(np.asarray(beta, dtype=float)), (G,))
    g, s, m = _pairs(M)
    lse, _, _ = _moments(beta[g], np.asarray(Z, dtype=float)[s])
    ll = beta * np.broadcast_to(np.atleast_1d(A), (G,)) - np.bincount(g, weights=m * lse, minlength=G)
    return float(ll[0]) if scalar else ll


def fit_beta(Z, A, M, bound=20.0, level=0.95, tol=1e-10, max_iter=200):
    """Maximum-likelihood beta of ``p(j) ∝ exp(beta * z_j)`` for one or many groups.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions (see :func:`standardize`).
    A : float or (G,) array_like
        Sum of z at each group's clicks.
    M : (S,) or (G, S) array_like
        Clicks of each group on each stimulus.
    bound : float
        Search interval ``[-bound, bound]``; when the likelihood still rises
        at the bound (e.g. every click of a group on its highest-z point), the
        estimate is the bound and ``at_bound`` is True.
    level : float
        Confidence level of the Wald interval.

    Returns
    -------
    dict of ndarray (scalars when `A` is a scalar)
        ``beta``, ``se`` (from the Fisher information at beta), ``ci_low``,
        ``ci_high`` (Wald), ``loglik``, ``loglik0`` (beta = 0, the uniform
        observer), ``lr_stat`` (2*(loglik - loglik0)), ``lr_p`` (chi-square,
        1 df), ``n_clicks``, ``at_bound``, ``converged``, ``iterations``.
        Groups without clicks or without information (all z = 0) get NaN.

    Examples
    --------
    >>> Z = standardize(np.array([[0.0, 1.0, 2.0, 3.0]]))
    >>> M = np.array([4.0])  # one click on each point
    >>> float(fit_beta(Z, Z.sum(), M)["beta"])  # uniform choices: beta = 0
    0.0
    """
    Z = np.asarray(Z, dtype=float)
    scalar = np.ndim(A) == 0 and np.ndim(M) == 1
    A = np.atleast_1d(np.asarray(A, dtype=float))
    M = np.atleast_2d(np.asarray(M, dtype=float))
    G = len(A)
    N = M.sum(axis=1)
    # only the (group, stimulus) pairs with clicks enter the likelihood: memory
    # grows with them, not with groups x stimuli
    pg, ps, pm = _pairs(M)

    def score_info(b, sel=None):
        """Score and information of groups `sel` (all) at their betas `b`."""
        if sel is None:
            sel = np.arange(G)
        where = np.full(G, -1)
        where[sel] = np.arange(len(sel))
        keep = where[pg] >= 0
        gi = where[pg[keep]]
        _, E, V = _moments(b[gi], Z[ps[keep]])
        k = len(sel)
        return (A[sel] - np.bincount(gi, weights=pm[keep] * E, minlength=k),
                np.bincount(gi, weights=pm[keep] * V, minlength=k))

    g_lo, _ = score_info(np.full(G, -bound))
    g_hi, _ = score_info(np.full(G, bound))
    _, info0 = score_info(np.zeros(G))
    uninformative = (N == 0) | (info0 <= 1e-12 * np.maximum(N, 1))
    beta = np.zeros(G)
    lo = np.full(G, -bound)
    hi = np.full(G, bound)
    above = g_hi >= 0  # still rising at +bound
    below = g_lo <= 0  # already falling at -bound
    active = ~(uninformative | above | below)
    converged = ~active.copy()
    iters = np.zeros(G, int)
    scale = np.maximum(N, 1.0)
    for it in range(max_iter):
        if not active.any():
            break
        idx = np.flatnonzero(active)
        g, h = score_info(beta[idx], idx)
        small = np.abs(g) <= tol * scale[idx]
        lo[idx] = np.where(g > 0, beta[idx], lo[idx])
        hi[idx] = np.where(g > 0, hi[idx], beta[idx])
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = beta[idx] + g / h
        ok = np.isfinite(newton) & (newton > lo[idx]) & (newton < hi[idx])
        step = np.where(ok, newton, 0.5 * (lo[idx] + hi[idx]))
        done = small | (np.abs(step - beta[idx]) <= tol * (1 + np.abs(beta[idx])))
        beta[idx] = np.where(small, beta[idx], step)
        iters[idx] = it + 1
        converged[idx[done]] = True
        active[idx[done]] = False
    beta[above & ~uninformative] = bound
    beta[below & ~above & ~uninformative] = -bound
    beta[uninformative] = np.nan
    _, info = score_info(np.nan_to_num(beta))
    with np.errstate(divide="ignore", invalid="ignore"):
        se = 1.0 / np.sqrt(info)
    se[uninformative] = np.nan
    zc = scipy.stats.norm.ppf(0.5 + level / 2)
    ll = loglik(np.nan_to_num(beta), Z, A, M)
    ll0 = loglik(np.zeros(G), Z, A, M)
    ll = np.where(uninformative, ll0, ll)
    lr = np.maximum(2 * (ll - ll0), 0.0)
    out = dict(
        beta=beta,
        se=se,
        ci_low=beta - zc * se,
        ci_high=beta + zc * se,
        loglik=ll,
        loglik0=ll0,
        lr_stat=lr,
        lr_p=np.where(uninformative, np.nan, scipy.stats.chi2.sf(lr, 1)),
        n_clicks=N,
        at_bound=(above | below) & ~uninformative,
        converged=converged,
        iterations=iters,
    )
    if scalar:
        out = {k: (v[0].item() if hasattr(v[0], "item") else v[0]) for k, v in out.items()}
    return out


def profile_ci(Z, A, M, beta_hat, level=0.95, bound=20.0):
    """Profile-likelihood confidence interval of beta for one group.

    Solves ``l(beta) = l(beta_hat) - chi2_1(level) / 2`` on each side of the
    estimate with :func:`scipy.optimize.brentq`. A side on which the
    likelihood does not fall that far within ``[-bound, bound]`` is reported
    as the bound.

    Returns
    -------
    (low, high) : tuple of float
    """
    if not np.isfinite(beta_hat):
        return (np.nan, np.nan)
    target = loglik(beta_hat, Z, A, M) - scipy.stats.chi2.ppf(level, 1) / 2

    def f(b):
        return loglik(b, Z, A, M) - target

    low = -bound if f(-bound) > 0 else scipy.optimize.brentq(f, -bound, beta_hat, xtol=1e-10)
    high = bound if f(bound) > 0 else scipy.optimize.brentq(f, beta_hat, bound, xtol=1e-10)
    return (float(low), float(high))


# ------------------------------------------------ the model with localisation error
def blur_kernel(n, sd_points):
    """Probability that a click chosen at point j is observed at point j + d.

    The click lies uniformly on point j's arc (``t = (j + u) / n``, u in
    [-1/2, 1/2)) and is displaced along the contour by Gaussian error of sd
    `sd_points` (in units of the point spacing); it is observed at
    ``round(j + u + e)``. With ``G(v) = v * Phi(v) + phi(v)`` (an
    antiderivative of the normal cdf) and ``s = sd_points``::

        P(d) = s * (G((d + 1) / s) - 2 * G(d / s) + G((d - 1) / s)),

    wrapped around the n points of a closed contour.

    Parameters
    ----------
    n : int
        Points on the contour.
    sd_points : float
        Error sd in point spacings (click sd in px divided by ds).

    Returns
    -------
    (n,) ndarray
        ``P(d)`` for d = 0..n-1 (d taken modulo n); sums to 1.
    """
    if sd_points <= 0:
        w = np.zeros(n)
        w[0] = 1.0
        return w
    s = float(sd_points)
    reach = int(np.ceil(8 * s)) + 2
    d = np.arange(-reach, reach + 1, dtype=float)

    def G(v):
        return v * scipy.special.ndtr(v) + np.exp(-0.5 * v * v) / np.sqrt(2 * np.pi)

    p = s * (G((d + 1) / s) - 2 * G(d / s) + G((d - 1) / s))
    w = np.zeros(n)
    np.add.at(w, np.mod(d.astype(np.int64), n), np.maximum(p, 0.0))
    return w / w.sum()


def _blurred(beta, Z, logW):
    """log q and dq/dbeta / q of every point of every stimulus, in log space.

    logW (S, n, n): log P(observed k | chosen j) (circulant); the sums over j
    run through log-sum-exp so that extreme beta cannot underflow q.
    """
    x = beta * Z
    logp = x - scipy.special.logsumexp(x, axis=1, keepdims=True)
    E = (np.exp(logp) * Z).sum(axis=1, keepdims=True)
    a = logp[:, None, :] + logW  # (S, k, j)
    logq = scipy.special.logsumexp(a, axis=2)
    r = np.exp(a - logq[:, :, None])  # posterior of j given k
    return logq, (r * (Z - E)[:, None, :]).sum(axis=2)


def fit_beta_blurred(Z, C, sd_points, bound=20.0, level=0.95):
    """ML beta of the choice model observed through localisation error.

    A click chosen at point j of stimulus s is observed at point k with
    probability ``blur_kernel(n, sd_points[s])[(k - j) mod n]``, so point k is
    observed with probability ``q_k = sum_j p_j * P(k - j)``. The
    log-likelihood ``sum_k C_k * log q_k`` is maximised with
    :func:`scipy.optimize.minimize` (L-BFGS-B, analytic gradient
    ``sum_k C_k * q'_k / q_k``); the standard error comes from the observed
    information, the derivative of that gradient taken numerically. With
    ``sd_points = 0`` it is the model of :func:`fit_beta`.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    C : (S, n) array_like
        Clicks observed at each point.
    sd_points : float or (S,) array_like
        Localisation error sd in point spacings, per stimulus.

    Returns
    -------
    dict
        ``beta, se, ci_low, ci_high, loglik, loglik0, lr_stat, lr_p,
        n_clicks, at_bound, converged``.
    """
    Z = np.asarray(Z, dtype=float)
    C = np.asarray(C, dtype=float)
    S, n = Z.shape
    sd = np.broadcast_to(np.asarray(sd_points, dtype=float), (S,))
    j = np.arange(n)
    diff = np.mod(j[:, None] - j[None, :], n)  # k - j
    with np.errstate(divide="ignore"):
        logW = np.stack([np.log(blur_kernel(n, v))[diff] for v in sd])
    keep = (C.sum(axis=1) > 0) & np.any(Z != 0, axis=1)
    N = float(C.sum())
    ll0 = -N * np.log(n)
    out = dict(beta=np.nan, se=np.nan, ci_low=np.nan, ci_high=np.nan, loglik=ll0, loglik0=ll0, lr_stat=0.0,
               lr_p=np.nan, n_clicks=N, at_bound=False, converged=True)
    if not keep.any():
        return out
    Z, C, logW = Z[keep], C[keep], logW[keep]
    # clicks on stimuli without information are uniform whatever beta
    const = -(N - float(C.sum())) * np.log(n)

    def nll(b):
        logq, score = _blurred(float(b[0]), Z, logW)
        return -float((C * logq).sum()), np.array([-float((C * score).sum())])

    res = scipy.optimize.minimize(nll, x0=[0.0], jac=True, method="L-BFGS-B", bounds=[(-bound, bound)],
                                  options=dict(ftol=1e-14, gtol=1e-10, maxiter=200))
    b = float(res.x[0])
    h = 1e-4
    info = (nll([b + h])[1][0] - nll([b - h])[1][0]) / (2 * h)
    se = 1 / np.sqrt(info) if info > 0 else np.nan
    zc = scipy.stats.norm.ppf(0.5 + level / 2)
    ll = -float(res.fun) + const
    lr = max(2 * (ll - ll0), 0.0)
    out.update(beta=b, se=se, ci_low=b - zc * se, ci_high=b + zc * se, loglik=ll, lr_stat=lr,
               lr_p=float(scipy.stats.chi2.sf(lr, 1)), at_bound=bool(abs(b) >= bound - 1e-9),
               converged=bool(res.success))
    return out


# ----------------------------------------------------------- circular-shift null
def shift_indices(m, permutations):
    """Circular shifts (in grid steps) used as the null distribution.

    All ``m - 1`` non-zero shifts when ``permutations >= m - 1``; otherwise
    `permutations` shifts spread evenly over them (a systematic sample, so
    the result needs no random numbers).
    """
    if permutations <= 0:
        return np.empty(0, np.int64)
    if permutations >= m - 1:
        return np.arange(1, m, dtype=np.int64)
    return np.unique(np.rint(np.arange(1, permutations + 1) * m / (permutations + 1)).astype(np.int64))


def _quantise(x, digits=9):
    """Round each row to `digits` decimals of its largest magnitude.

    Values that differ only by floating-point noise (a density's far tails,
    which an FFT leaves at +-1e-17 instead of 0; a prediction interpolated
    from equal values) become ties, so ranks do not depend on rounding.
    """
    scale = np.nanmax(np.abs(x), axis=1, keepdims=True)
    scale = np.where(scale > 0, scale, 1.0)
    return np.round(x / scale, digits)


def circular_spearman(density, prediction, shifts):
    """Spearman correlation of two circular profiles and its circular-shift null.

    Spearman's rho is Pearson's correlation of the ranks (average ranks for
    ties; values equal to 9 digits of the row's largest magnitude are ties).
    Shifting the
    prediction circularly permutes its ranks without changing their mean or
    spread, so the correlations of all m shifts are one circular
    cross-correlation of the centred ranks, computed by FFT.

    Parameters
    ----------
    density, prediction : (m,) or (S, m) array_like
        Profiles on the same grid of m positions, one row per stimulus.
    shifts : (K,) array_like of int
        Shifts (in grid steps) forming the null, e.g. from
        :func:`shift_indices`.

    Returns
    -------
    rho : float or (S,) ndarray
        Observed correlation (NaN where a profile is constant).
    null : (K,) or (S, K) ndarray
        Correlation with the prediction shifted by each of `shifts`.
    p : float or (S,) ndarray
        One-sided p-value for a positive correlation,
        ``(1 + #{null >= rho}) / (1 + K)`` (NaN without shifts).
    """
    d = _quantise(np.atleast_2d(np.asarray(density, dtype=float)))
    u = _quantise(np.atleast_2d(np.asarray(prediction, dtype=float)))
    m = d.shape[1]
    rd = scipy.stats.rankdata(d, axis=1)
    ru = scipy.stats.rankdata(u, axis=1)
    rd -= rd.mean(axis=1, keepdims=True)
    ru -= ru.mean(axis=1, keepdims=True)
    norm = np.sqrt((rd * rd).sum(axis=1) * (ru * ru).sum(axis=1))
    # c[k] = sum_i rd[i] * ru[i - k]: the prediction shifted forward by k steps
    c = np.fft.irfft(np.fft.rfft(rd, axis=1) * np.conj(np.fft.rfft(ru, axis=1)), n=m, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        r = c / norm[:, None]
    r[norm <= 0] = np.nan
    r = np.clip(r, -1.0, 1.0)
    shifts = np.asarray(shifts, dtype=np.int64)
    rho = r[:, 0]
    null = r[:, shifts]
    K = len(shifts)
    if K:
        # rounding in the FFT must not break ties with the observed value
        p = (1 + (null >= rho[:, None] - 1e-12).sum(axis=1)) / (1 + K)
        p = np.where(np.isfinite(rho), p, np.nan)
    else:
        p = np.full(len(rho), np.nan)
    if np.ndim(density) == 1:
        return float(rho[0]), null[0], float(p[0])
    return rho, null, p


def mean_rho_null(null, rng, replicates=None):
    """Null distribution of the mean correlation over stimuli.

    Each replicate draws one shift per stimulus independently from that
    stimulus's null (shifting each prediction by its own random amount).

    Parameters
    ----------
    null : (S, K) ndarray
        Per-stimulus null correlations (rows with NaN are skipped).
    rng : numpy.random.Generator
    replicates : int, optional
        Default K.

    Returns
    -------
    (R,) ndarray
    """
    null = null[np.isfinite(null).all(axis=1)]
    S, K = null.shape
    if S == 0 or K == 0:
        return np.empty(0)
    R = K if replicates is None else int(replicates)
    pick = rng.integers(0, K, size=(R, S))
    return null[np.arange(S)[None, :], pick].mean(axis=1)


# ------------------------------------------------------------------------ peaks
def peak_chance(peak_t, tol):
    """Fraction of a closed contour within `tol` (arc fraction) of any peak.

    The union of the windows ``[p - tol, p + tol]`` around the sorted peaks
    measures ``sum_i min(2 * tol, gap_i)``, gap_i being the arc from peak i to
    the next one.

    Examples
    --------
    >>> peak_chance([0.0, 0.5], 0.1)
    0.4
    >>> round(peak_chance([0.0, 0.05], 0.1), 10)  # overlapping windows
    0.25
    """
    p = np.sort(np.mod(np.asarray(peak_t, dtype=float), 1.0))
    if len(p) == 0:
        return 0.0
    gaps = np.diff(np.append(p, p[0] + 1.0))
    return float(min(1.0, np.minimum(2 * tol, gaps).sum()))


def peak_hits(t, peak_t, tol):
    """Whether each position lies within `tol` (arc fraction) of a peak."""
    t = np.asarray(t, dtype=float)
    p = np.asarray(peak_t, dtype=float)
    if len(p) == 0:
        return np.zeros(len(t), bool)
    d = np.abs(np.mod(t[:, None] - p[None, :] + 0.5, 1.0) - 0.5)
    return (d <= tol + 1e-12).any(axis=1)


def midrank_percentile(values, reference):
    """Percentile (0-100) of each value among `reference`, ties counted half.

    ``100 * (#{reference < v} + #{reference == v} / 2) / len(reference)``;
    averaged over values it is 100 times the AUC (Mann-Whitney) of the values
    against the reference. Values that differ by less than 1e-9 of the
    reference's range count as equal, so rounding noise on straight edges
    does not rank points that the model holds equal.
    """
    ref = np.asarray(reference, dtype=float)
    v = np.asarray(values, dtype=float)
    eps = 1e-9 * max(float(np.ptp(ref)), np.finfo(float).tiny) if len(ref) else 0.0
    r = np.sort(ref)
    less = np.searchsorted(r, v - eps, side="left")
    leq = np.searchsorted(r, v + eps, side="right")
    return 100.0 * (less + 0.5 * (leq - less)) / len(r)


# ------------------------------------------------------------------------ tests
def group_test(values, level=0.95, alternative="two-sided"):
    """One-sample t-test of per-unit effects (e.g. per participant) against 0.

    Valid when the effects are close to normal; for per-unit mean z, whose
    distribution under the null can be far from normal (few clicks on stimuli
    with spiky surprisal), use :func:`mean_z_test`, which calibrates the same
    statistic by Monte Carlo.

    Parameters
    ----------
    values : array_like
        One effect per participant (NaN ignored).
    level : float
        Confidence level of the (two-sided) interval of the mean.
    alternative : {'two-sided', 'greater', 'less'}
        Alternative hypothesis of the p-value.

    Returns
    -------
    dict
        ``test`` ('one-sample t-test'), ``statistic`` (t), ``df``,
        ``p_value``, ``alternative``, ``effect_size`` (Cohen's d_z = mean /
        sd), ``mean``, ``sd``, ``ci_low``, ``ci_high`` (of the mean), ``n``.
        NaN where there are too few values or no spread.
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = len(v)
    out = dict(test="one-sample t-test", statistic=np.nan, df=n - 1 if n >= 2 else None, p_value=np.nan,
               alternative=alternative, effect_size=np.nan, effect_size_name="cohen_dz",
               mean=float(v.mean()) if n else np.nan, sd=np.nan, ci_low=np.nan, ci_high=np.nan, n=n)
    if n >= 2:
        sd = float(v.std(ddof=1))
        out["sd"] = sd
        # a spread at rounding level is no spread: the t statistic would be noise
        if sd > 1e-12 * max(1.0, abs(float(v.mean()))):
            res = scipy.stats.ttest_1samp(v, 0.0, alternative=alternative)
            out["statistic"] = float(res.statistic)
            out["p_value"] = float(res.pvalue)
            out["effect_size"] = float(v.mean() / sd)
            half = scipy.stats.t.ppf(0.5 + level / 2, n - 1) * sd / np.sqrt(n)
            out["ci_low"], out["ci_high"] = float(v.mean() - half), float(v.mean() + half)
    return out


def t_statistic(v, axis=0):
    """One-sample t statistic against 0 along `axis`, defined for every sample.

    ``mean * sqrt(k) / sd`` (sd with ddof = 1) for k >= 2 values; where the
    values do not spread (sd = 0) it is ``+inf`` for a positive mean,
    ``-inf`` for a negative one and 0 for all zeros, so that a Monte Carlo
    null can rank every replicate. NaN for k < 2.
    """
    v = np.asarray(v, dtype=float)
    k = v.shape[axis]
    if k < 2:
        return np.full(np.delete(v.shape, axis), np.nan) if v.ndim > 1 else np.float64(np.nan)
    m = v.mean(axis=axis)
    sd = v.std(axis=axis, ddof=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = m * np.sqrt(k) / sd
    return np.where(sd > 0, t, np.where(m > 0, np.inf, np.where(m < 0, -np.inf, 0.0)))


def _unit_means(Z, stimulus, unit, n_units):
    """The design of the mean-z statistic.

    Returns the informative units (at least one click on a stimulus whose
    prediction is not constant), the clicks on non-constant stimuli (the only
    ones whose z can differ from 0), their unit's row among the informative
    units as a sparse indicator, and each informative unit's number of clicks
    (all its clicks, including those with z = 0 by construction).
    """
    import scipy.sparse

    Z = np.asarray(Z, dtype=float)
    stimulus = np.asarray(stimulus, dtype=np.int64)
    unit = np.asarray(unit, dtype=np.int64)
    if n_units is None:
        n_units = int(unit.max()) + 1 if len(unit) else 0
    varies = np.any(Z != 0, axis=1)
    live = varies[stimulus]
    informative = np.bincount(unit[live], minlength=n_units) > 0
    counts = np.bincount(unit, minlength=n_units).astype(float)[informative]
    row = np.cumsum(informative) - 1
    k = int(informative.sum())
    sel = np.flatnonzero(live)
    ind = scipy.sparse.csr_matrix((np.ones(len(sel)), (row[unit[sel]], np.arange(len(sel)))), shape=(k, len(sel)))
    return informative, sel, ind, counts


def mean_z_null(Z, stimulus, unit, n_units=None, replicates=1999, rng=None, observed_z=None,
                max_elements=1 << 22):
    """t statistics of per-unit mean z under uniform clicking, for a fixed design.

    Each click keeps its stimulus and unit (participant or stimulus); its
    contour point is redrawn uniformly among the stimulus's n points
    (``p = 1/n``, the choice model at beta = 0), and the statistic is
    recomputed exactly as for the data: each informative unit's mean z over
    all its clicks, then :func:`t_statistic` across those units. The draws
    are made for all replicates at once, in chunks of at most `max_elements`
    (clicks x replicates) values.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus, unit : (U,) array_like of int
        Stimulus and unit of each used click.
    n_units : int, optional
    replicates : int
        Null replicates R.
    rng : numpy.random.Generator, optional
    observed_z : (U,) array_like, optional
        z at the observed clicks; its statistic is computed by the same code
        (same summation order), so that ties with replicates are exact.

    Returns
    -------
    null : (R,) ndarray
    observed : float
        NaN if `observed_z` is not given.
    informative : (n_units,) ndarray of bool
    """
    Z = np.asarray(Z, dtype=float)
    rng = np.random.default_rng() if rng is None else rng
    informative, sel, ind, counts = _unit_means(Z, stimulus, unit, n_units)
    S, n = Z.shape
    base = (np.asarray(stimulus, dtype=np.int64)[sel] * n)[:, None]
    flat = Z.ravel()
    R = int(replicates)

    def stat(zc):  # zc (clicks, columns) -> t of each column
        return t_statistic(np.asarray(ind @ zc) / counts[:, None], axis=0)

    observed = np.nan
    if observed_z is not None:
        observed = float(stat(np.asarray(observed_z, dtype=float)[sel][:, None])[0])
    null = np.empty(R)
    step = max(1, int(max_elements // max(len(sel), 1)))
    for a in range(0, R, step):
        b = min(R, a + step)
        idx = rng.integers(0, n, size=(len(sel), b - a), dtype=np.int32 if n < 2**31 else np.int64)
        null[a:b] = stat(flat[base + idx])
    return null, observed, informative


def mean_z_test(Z, stimulus, unit, z, n_units=None, replicates=1999, rng=None, level=0.95):
    """Test whether clicks favour high z: per-unit mean z across units, calibrated by Monte Carlo.

    The statistic is the one-sample t of the units' mean z (0 under uniform
    clicking). Its null distribution is simulated under the exact null of
    uniform clicking with the observed design (:func:`mean_z_null`), because
    with few clicks per unit on stimuli whose z is spiky (polygons) the mean
    z is strongly right-skewed and the t distribution makes the test too
    liberal. The p-value is one-sided (the hypothesis is that clicks favour
    high surprisal): ``(1 + #{null >= t}) / (1 + R)``, which never falls
    below ``1 / (1 + R)``.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus, unit : (U,) array_like of int
        Stimulus and unit (participant, or stimulus for the items analysis)
        of each used click.
    z : (U,) array_like
        z at each used click (``Z[stimulus, point]``).
    replicates : int
        Monte Carlo replicates R (0: only the parametric values).
    rng : numpy.random.Generator, optional

    Returns
    -------
    dict
        ``test``, ``statistic`` (t), ``p_value`` (Monte Carlo), ``alternative``
        ('greater'), ``simulations`` (R), ``p_value_parametric`` (one-sided
        t distribution, descriptive), ``df``, ``effect_size`` (Cohen's d_z),
        ``mean``, ``sd``, ``ci_low``, ``ci_high`` (t interval of the mean,
        descriptive), ``n`` (informative units).
    """
    z = np.asarray(z, dtype=float)
    stimulus = np.asarray(stimulus, dtype=np.int64)
    unit = np.asarray(unit, dtype=np.int64)
    if n_units is None:
        n_units = int(unit.max()) + 1 if len(unit) else 0
    R = int(replicates)
    null, obs, informative = mean_z_null(Z, stimulus, unit, n_units, R, rng, observed_z=z)
    sums = np.bincount(unit, weights=z, minlength=n_units)
    cnt = np.bincount(unit, minlength=n_units)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = np.where(informative, sums / cnt, np.nan)
    out = group_test(v, level=level, alternative="greater")
    out["p_value_parametric"] = out.pop("p_value")
    out["statistic"] = obs
    if R > 0 and not np.isnan(obs):
        # rounding must not break a tie between the data and a replicate
        tol = 1e-9 * max(1.0, abs(obs)) if np.isfinite(obs) else 0.0
        p = (1 + np.count_nonzero(null >= obs - tol)) / (1 + R)
    else:
        p = np.nan
    out.update(test=f"one-sample t statistic of mean z across units, Monte Carlo null under uniform clicking "
                    f"(R = {R})", p_value=p, simulations=R, alternative="greater")
    return out
