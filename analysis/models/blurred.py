"""The choice model observed through localisation error of the clicks.

A click chosen at point j lies uniformly on that point's arc and is displaced
along the contour by Gaussian error; :func:`blur_kernel` gives where it is
observed and :func:`fit_beta_blurred` fits beta through that kernel.
"""

from __future__ import annotations

import numpy as np
import scipy.optimize
import scipy.special
import scipy.stats

from attneave.analysis.models.choice import BETA_BOUND

__all__ = ["blur_kernel", "fit_beta_blurred"]


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


def fit_beta_blurred(Z, C, sd_points, bound=BETA_BOUND, level=0.95):
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
        n_clicks, at_bound, converged``. ``at_bound`` is True when the
        likelihood at a bound is as high as at the optimiser's point (it
        still rises there: near-separation); ``beta`` is then the bound and
        ``se`` and the interval are NaN.
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
    b, fun = float(res.x[0]), float(res.fun)
    # Near-separation (clicks only on each contour's top point): the likelihood keeps rising
    # towards the bound, but so slowly that L-BFGS-B stops at beta ~ 10-13 with a vanishing
    # gradient, which would pass for an estimate. If the likelihood at a bound is as high as at
    # that point, its supremum lies at or beyond the bound: report the bound, flagged.
    for edge in (bound, -bound):
        f_edge = nll([edge])[0]
        if f_edge <= fun + 1e-9 * max(1.0, abs(fun)):
            b, fun = edge, f_edge
    h = 1e-4
    info = (nll([b + h])[1][0] - nll([b - h])[1][0]) / (2 * h)
    at_bound = abs(b) >= bound - 1e-9
    # at the bound beta is no estimate and has no interval (as in attneave.analysis.models.choice.fit_beta)
    se = 1 / np.sqrt(info) if info > 0 and not at_bound else np.nan
    zc = scipy.stats.norm.ppf(0.5 + level / 2)
    ll = -fun + const
    lr = max(2 * (ll - ll0), 0.0)
    out.update(beta=b, se=se, ci_low=b - zc * se, ci_high=b + zc * se, loglik=ll, lr_stat=lr,
               lr_p=float(scipy.stats.chi2.sf(lr, 1)), at_bound=bool(at_bound),
               converged=bool(res.success))
    return out
