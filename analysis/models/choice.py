"""The discrete-choice (conditional-logit) model of clicks along contours.

All functions take plain arrays. A stimulus is described by its ``n`` equally
spaced contour points (the points of :func:`attneave.stimuli.geometry.information.surprisal`);
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
:mod:`attneave.analysis.simulate.observers` draw clicks from exactly this model, so the fit is
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

The same model with several predictors (``p(j) ∝ exp(sum_k beta_k x_kj)``)
is fitted jointly by :func:`fit_choice`, with Wald intervals and a
likelihood-ratio test of each predictor against the model without it (does
concavity add anything beyond surprisal?).
"""

from __future__ import annotations

import numpy as np
import scipy.optimize
import scipy.stats

__all__ = ["BETA_BOUND", "standardize", "point_index", "block_moments", "loglik", "fit_beta", "profile_ci", "fit_choice"]

#: The search bound of every fitted coefficient, pooled, per participant, per stimulus or joint:
#: on standardised predictors, beta = 20 makes a point one sd above another e^20 times as likely
#: to be clicked, which no finite set of clicks can tell from infinity (a fit there is flagged
#: ``at_bound``, not estimated). One bound for all fits, so that summary.json never shows two.
BETA_BOUND = 20.0


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


#: Most elements of a (rows, n) block of contour values held at once: the pairs of a fit are
#: processed in blocks of rows so that memory stays O(pairs + block), whatever clicks x n.
BLOCK_ELEMENTS = 1 << 20


def block_moments(beta, Z, rows=None, block=BLOCK_ELEMENTS):
    """log-sum-exp, E and Var of z under p ∝ exp(beta z), row by row.

    beta (P,), Z (S, n), rows (P,) indices into Z (default ``arange(S)``) -> lse (P,), E (P,), V (P,).
    Row r uses ``Z[rows[r]]``: the pairs of one stimulus share its n values, and only a block of
    rows is expanded at a time.
    """
    Z = np.asarray(Z, dtype=float)
    beta = np.asarray(beta, dtype=float)
    rows = np.arange(len(beta)) if rows is None else np.asarray(rows)
    P = len(rows)
    if P > len(Z) and np.all(beta == beta[0]):
        # one beta for all (the start and the null of every fit): a row's moments depend on its
        # stimulus alone, so each stimulus once, then gathered (1,000,000 pairs -> 5,000 rows)
        lse, E, V = block_moments(np.full(len(Z), beta[0]), Z, None, block)
        return lse[rows], E[rows], V[rows]
    lse, E, V = np.empty(P), np.empty(P), np.empty(P)
    # the largest beta * z of a row is beta times the row's max (beta >= 0) or min: no pass for it
    zmax, zmin = (Z.max(axis=1), Z.min(axis=1)) if Z.shape[1] else (np.zeros(len(Z)), np.zeros(len(Z)))
    step = max(1, block // max(Z.shape[1], 1))

    def one(a):
        sl = slice(a, min(a + step, P))
        r, b = rows[sl], beta[sl]
        Zb = Z[r]
        mx = np.where(b >= 0, b * zmax[r], b * zmin[r])
        x = Zb * b[:, None]
        x -= mx[:, None]
        w = np.exp(x, out=x)
        sw = w.sum(axis=1)
        e = np.einsum("pn,pn->p", w, Zb) / sw
        w *= Zb
        w *= Zb
        lse[sl] = np.log(sw) + mx
        E[sl] = e
        V[sl] = np.maximum(w.sum(axis=1) / sw - e * e, 0.0)

    starts = range(0, P, step)
    if len(starts) < 4:
        for a in starts:
            one(a)
    else:
        # blocks are independent and numpy runs them without the GIL: two threads, disjoint slices,
        # the same values as one (a fit of 1,000,000 pairs x 100 points evaluates 100 blocks per step)
        from attneave.analysis.threads import ordered_map

        for _ in ordered_map(lambda i: one(starts[i]), len(starts)):
            pass
    return lse, E, V


def _pairs(M):
    """The (group, stimulus, count) triples of the non-zero counts of M (G, S), dense or scipy.sparse."""
    import scipy.sparse

    if scipy.sparse.issparse(M):
        c = scipy.sparse.coo_matrix(M)
        keep = c.data != 0
        return c.row[keep].astype(np.int64), c.col[keep].astype(np.int64), c.data[keep].astype(float)
    g, s = np.nonzero(M)
    return g, s, M[g, s]


def _as_counts(M):
    """M as a 2-d (G, S) array or scipy.sparse matrix of floats (a (S,) vector is one group)."""
    import scipy.sparse

    if scipy.sparse.issparse(M):
        return scipy.sparse.csr_matrix(M, dtype=float)
    return np.atleast_2d(np.asarray(M, dtype=float))


def _row_sums(M):
    return np.asarray(M.sum(axis=1), dtype=float).ravel()


def loglik(beta, Z, A, M):
    """Log-likelihood of the discrete choice model for each group.

    Parameters
    ----------
    beta : float or (G,) array_like
    Z : (S, n) array_like
        Standardised predictions at the n points of each stimulus.
    A : float or (G,) array_like
        Sum of z over each group's clicks.
    M : (S,) or (G, S) array_like or scipy.sparse matrix
        Number of clicks of each group on each stimulus (sparse for many
        groups and stimuli: only the non-zero counts are used).

    Returns
    -------
    float or (G,) ndarray
    """
    scalar = np.ndim(beta) == 0 and np.ndim(A) == 0 and np.ndim(M) == 1
    M = _as_counts(M)
    G = M.shape[0]
    beta = np.broadcast_to(np.atleast_1d(np.asarray(beta, dtype=float)), (G,))
    g, s, m = _pairs(M)
    lse, _, _ = block_moments(beta[g], Z, s)
    ll = beta * np.broadcast_to(np.atleast_1d(A), (G,)) - np.bincount(g, weights=m * lse, minlength=G)
    return float(ll[0]) if scalar else ll


def fit_beta(Z, A, M, bound=BETA_BOUND, level=0.95, tol=1e-10, max_iter=200):
    """Maximum-likelihood beta of ``p(j) ∝ exp(beta * z_j)`` for one or many groups.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions (see :func:`standardize`).
    A : float or (G,) array_like
        Sum of z at each group's clicks.
    M : (S,) or (G, S) array_like or scipy.sparse matrix
        Clicks of each group on each stimulus (sparse, e.g. ``diags(M_s)``
        for one group per stimulus: memory grows with the non-zero counts,
        not with groups x stimuli).
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
        ``ci_high`` (Wald; NaN, as ``se``, for a fit at the bound), ``loglik``, ``loglik0`` (beta = 0, the uniform
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
    M = _as_counts(M)
    G = len(A)
    N = _row_sums(M)
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
        _, E, V = block_moments(b[gi], Z, ps[keep])
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
    # at the bound beta is no estimate, so neither is a Wald interval around it (it would even
    # reach past the bound, e.g. [12.6, 27.4]); no SE or interval, as in fit_choice
    se[uninformative | above | below] = np.nan
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


def profile_ci(Z, A, M, beta_hat, level=0.95, bound=BETA_BOUND):
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


def _newton_choice(X, A, M, max_iter=100, tol=1e-10, bound=BETA_BOUND):
    """ML coefficients of the multi-predictor choice model by damped Newton steps.

    X (S, n, K), A (K,), M (S,) -> (beta (K,), loglik, info (K, K), converged).
    The log-likelihood is concave, so a Newton step halved until the
    likelihood rises converges from 0; coefficients are kept within
    ``[-bound, bound]`` so that a separable design stops at a finite point.
    """
    K = X.shape[2]

    def value(b):
        x = X @ b  # (S, n)
        mx = x.max(axis=1, keepdims=True)
        w = np.exp(x - mx)
        sw = w.sum(axis=1)
        p = w / sw[:, None]
        E = np.einsum("sn,snk->sk", p, X)
        ll = float(b @ A - M @ (np.log(sw) + mx[:, 0]))
        g = A - M @ E
        C = np.einsum("s,sn,snk,snl->kl", M, p, X, X) - np.einsum("s,sk,sl->kl", M, E, E)
        return ll, g, C

    b = np.zeros(K)
    ll, g, C = value(b)
    converged = False
    for _ in range(max_iter):
        try:
            step = np.linalg.solve(C + 1e-12 * np.eye(K), g)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(C, g, rcond=None)[0]
        t = 1.0
        while t > 1e-8:
            nb = np.clip(b + t * step, -bound, bound)
            nll, ng, nC = value(nb)
            if nll >= ll - 1e-12 * max(1.0, abs(ll)):
                break
            t /= 2
        done = abs(nll - ll) <= tol * max(1.0, abs(ll)) and np.max(np.abs(nb - b)) <= 1e-7 * (1 + np.max(np.abs(b)))
        b, ll, g, C = nb, nll, ng, nC
        if done:
            converged = True
            break
    return b, ll, C, converged


def fit_choice(X, A, M, names=None, level=0.95, bound=BETA_BOUND):
    """Joint ML fit of the choice model with several predictors.

    ``p(j) ∝ exp(sum_k beta_k * x_sjk)`` over the n points of each stimulus
    (a conditional logit whose choice sets are the contour points). Each
    predictor is tested by the likelihood ratio of the full model against the
    model without it (chi-square, 1 df): whether it adds anything beyond the
    others.

    Parameters
    ----------
    X : (S, n, K) array_like
        Predictors at the points of each stimulus (standardised, see
        :func:`standardize`).
    A : (K,) array_like
        Sum of each predictor at the clicks.
    M : (S,) array_like
        Clicks per stimulus.
    names : list of str, optional
        Predictor names (default ``x0, x1, ...``).
    level : float
        Confidence level of the Wald intervals.
    bound : float
        Largest absolute coefficient (a fit that reaches it is flagged).

    Returns
    -------
    dict
        ``names``, ``coef``, ``se``, ``ci_low``, ``ci_high``, ``lr_stat``,
        ``lr_p`` (each (K,) ndarray), ``at_bound`` ((K,) bool), ``loglik``,
        ``loglik0`` (all coefficients 0), ``converged``, ``n_clicks``.

    Examples
    --------
    Two points, one predictor: the odds of the points are ``exp(2 beta)``,
    so 3 clicks against 1 give ``beta = log(3) / 2``.

    >>> X = np.array([[[1.0], [-1.0]]])
    >>> round(float(fit_choice(X, [3 - 1], [4.0])["coef"][0]), 6), round(float(np.log(3) / 2), 6)
    (0.549306, 0.549306)
    """
    X = np.asarray(X, dtype=float)
    A = np.asarray(A, dtype=float)
    M = np.asarray(M, dtype=float)
    S, n, K = X.shape
    names = list(names) if names is not None else [f"x{k}" for k in range(K)]
    keep = M > 0
    X, M = X[keep], M[keep]
    N = float(M.sum())
    ll0 = -float(M @ np.log(np.full(len(M), n)))
    b, ll, C, conv = _newton_choice(X, A, M, bound=bound)
    with np.errstate(invalid="ignore", divide="ignore"):
        try:
            cov = np.linalg.inv(C)
            se = np.sqrt(np.where(np.diag(cov) > 0, np.diag(cov), np.nan))
        except np.linalg.LinAlgError:
            se = np.full(K, np.nan)
    zc = scipy.stats.norm.ppf(0.5 + level / 2)
    lr = np.full(K, np.nan)
    for k in range(K):
        rest = [i for i in range(K) if i != k]
        ll_k = _newton_choice(X[:, :, rest], A[rest], M, bound=bound)[1] if rest else ll0
        lr[k] = max(2 * (ll - ll_k), 0.0)
    at_bound = np.abs(b) >= bound * (1 - 1e-9)
    se = np.where(at_bound, np.nan, se)
    return dict(names=names, coef=b, se=se, ci_low=b - zc * se, ci_high=b + zc * se, lr_stat=lr,
                lr_p=scipy.stats.chi2.sf(lr, 1), at_bound=at_bound, loglik=ll, loglik0=ll0, converged=conv,
                n_clicks=N)
