"""A mixed conditional logit with crossed random slopes for participants and stimuli.

Participant p clicks point j of stimulus s with probability

    p(j) = exp(b_ps z_sj) / sum_i exp(b_ps z_si),   b_ps = beta + u_p + v_s,

with ``u_p ~ N(0, sd_participant**2)`` and ``v_s ~ N(0, sd_stimulus**2)``
independent (crossed random slopes). ``beta`` is the mean slope: what a new
participant shows on a new stimulus. The group test across participants
treats stimuli as fixed, and is too liberal when slopes vary across stimuli
(Clark 1973); this model generalises over both.

Estimation: the Laplace approximation of the marginal likelihood. Given
(u, v) the log-likelihood is a sum over cells (p, s) of
``l_ps(b) = b A_ps - M_ps log sum_i exp(b z_si)`` (A: sum of z at the cell's
clicks, M: their number), so the mode over (u, v) is found by Newton's
method whose Hessian is diagonal in u and in v apart from the (G, S) block of
cell curvatures; the u block is eliminated by its Schur complement, so each
step costs one S x S solve. ``log sum_i exp(b z_si)`` and its first three
derivatives in b are tabulated per stimulus on a fine grid and interpolated
by cubic Hermite polynomials (relative error below 1e-9 for the fits here),
so an evaluation costs O(cells) whatever n. The approximate marginal
log-likelihood is maximised over (log sd_participant, log
sd_stimulus) with :func:`scipy.optimize.minimize`, beta being integrated
out with a flat prior (the Laplace analogue of REML: beta is found jointly
with the random effects at the mode, so the outer problem has two
dimensions). The interval of beta is Wald's, from the beta element of the
inverse curvature at the mode, with t quantiles on ``min(G, S) - 1`` degrees
of freedom (the smaller set of random units limits what is known about the
mean slope).

References
----------
.. [1] Breslow, N. E., & Clayton, D. G. (1993). Approximate inference in
       generalized linear mixed models. JASA 88, 9-25.
.. [2] Baayen, R. H., Davidson, D. J., & Bates, D. M. (2008). Mixed-effects
       modeling with crossed random effects for subjects and items.
       Journal of Memory and Language 59, 390-412.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CumulantTable", "fit_mixed"]

_LOG_SD_BOUNDS = (-7.0, np.log(5.0))


class CumulantTable:
    """``K_s(b) = log sum_i exp(b z_si)`` and its derivatives, tabulated per stimulus.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    bound : float
        Slopes are tabulated on ``[-bound, bound]``; beyond it K is extended
        linearly (slope E at the bound, V = 0), which keeps the likelihood
        concave and bounded.
    step : float
        Grid step.
    """

    def __init__(self, Z, bound=12.0, step=0.01):
        Z = np.asarray(Z, dtype=float)
        self.bound, self.step = float(bound), float(step)
        b = np.arange(-bound, bound + step / 2, step)
        S, n = Z.shape
        self.K = np.empty((S, len(b)))
        self.E = np.empty((S, len(b)))
        self.V = np.empty((S, len(b)))
        self.T = np.empty((S, len(b)))
        for s in range(S):  # (grid, n) at a time: memory stays small
            x = b[:, None] * Z[s][None, :]
            mx = x.max(axis=1, keepdims=True)
            w = np.exp(x - mx)
            sw = w.sum(axis=1)
            p = w / sw[:, None]
            E = np.einsum("gn,n->g", p, Z[s])
            d = Z[s][None, :] - E[:, None]
            self.K[s] = np.log(sw) + mx[:, 0]
            self.E[s] = E
            self.V[s] = (p * d * d).sum(axis=1)
            self.T[s] = (p * d * d * d).sum(axis=1)

    def __call__(self, s, b):
        """K, E = K', V = K'' at slopes `b` of stimuli `s` (arrays of one shape)."""
        bc = np.clip(b, -self.bound, self.bound)
        x = (bc + self.bound) / self.step
        i = np.minimum(np.floor(x).astype(np.int64), self.K.shape[1] - 2)
        t = x - i
        h = self.step
        t2, t3 = t * t, t * t * t
        h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2

        def herm(F, dF):
            return h00 * F[s, i] + h10 * h * dF[s, i] + h01 * F[s, i + 1] + h11 * h * dF[s, i + 1]

        K, E, V = herm(self.K, self.E), herm(self.E, self.V), herm(self.V, self.T)
        out = b != bc
        if out.any():
            K = np.where(out, K + E * (b - bc), K)
            V = np.where(out, 0.0, V)
        return K, E, V


def _mode(table, ts, cs, cp, A, M, G, S, sp, ss, u, v, beta, iters=100, tol=1e-9):
    """Joint mode of (u, v, beta) of the penalised log-likelihood, given the two sds.

    Cells: stimulus `cs` (row `ts` of the table), participant `cp`, sum of z
    `A` and clicks `M`. Newton steps, halved until the (concave) objective
    rises, so that any start converges. The u block of the Hessian is
    diagonal and is eliminated by its Schur complement, leaving an
    (S + 1) x (S + 1) system in (v, beta).

    Returns u, v, beta, the objective at the mode, the log-determinant of
    minus its Hessian, and the variance of beta (the beta element of the
    inverse of minus the Hessian).
    """
    import scipy.linalg

    def parts(u, v, beta):
        b = beta + u[cp] + v[cs]
        K, E, V = table(ts, b)
        f = float((b * A - M * K).sum() - (u @ u) / (2 * sp**2) - (v @ v) / (2 * ss**2))
        w = M * V
        hu = np.bincount(cp, weights=w, minlength=G)
        hv = np.bincount(cs, weights=w, minlength=S)
        C = np.empty((G, S + 1))
        C[:, :S] = np.bincount(cp * S + cs, weights=w, minlength=G * S).reshape(G, S)
        C[:, S] = hu
        huu = hu + 1 / sp**2
        B = np.diag(np.r_[hv + 1 / ss**2, w.sum()])
        B[:S, S] = B[S, :S] = hv
        # the Schur complement of the diagonal u block (einsum rather than a BLAS product:
        # multithreaded BLAS on these small matrices is 10x slower on a busy machine)
        schur = B - np.einsum("pa,pb->ab", C, C / huu[:, None])
        return f, A - M * E, huu, C, scipy.linalg.cho_factor(schur)

    f, g, huu, C, chol = parts(u, v, beta)
    for _ in range(iters):
        gu = np.bincount(cp, weights=g, minlength=G) - u / sp**2
        gw = np.r_[np.bincount(cs, weights=g, minlength=S) - v / ss**2, g.sum()]
        # Cholesky solves: numpy's general solve wakes multithreaded LAPACK, 100x slower here
        dw = scipy.linalg.cho_solve(chol, gw - np.einsum("p,pa->a", gu / huu, C))
        du = (gu - np.einsum("pa,a->p", C, dw)) / huu
        step = 1.0
        while step > 1e-6:
            nu, nv, nb = u + step * du, v + step * dw[:S], beta + step * dw[S]
            nf, ng, nhuu, nC, nchol = parts(nu, nv, nb)
            if nf >= f - 1e-12 * abs(f):
                break
            step /= 2
        done = step * max(np.abs(du).max(initial=0), np.abs(dw).max()) < tol
        u, v, beta, f, g, huu, C, chol = nu, nv, nb, nf, ng, nhuu, nC, nchol
        if done:
            break
    logdet = np.log(huu).sum() + 2 * np.log(np.diag(chol[0])).sum()
    e = np.zeros(S + 1)
    e[S] = 1.0
    var_beta = float(scipy.linalg.cho_solve(chol, e)[S])
    return u, v, beta, f, logdet, var_beta


def fit_mixed(Z, stimulus, participant, j, n_participants=None, level=0.95, table=None, start=None):
    """Fit the mixed conditional logit with crossed random slopes (Laplace approximation).

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus, participant, j : (U,) array_like of int
        Stimulus, participant and point of each used click.
    n_participants : int, optional
    level : float
        Confidence level of the interval of beta.
    table : CumulantTable, optional
        Reused across fits on the same stimuli.
    start : float, optional
        Starting value of beta (e.g. the pooled estimate; default 0).

    Returns
    -------
    dict
        ``beta``, ``se``, ``ci_low``, ``ci_high``, ``df`` (of the t
        quantile), ``sd_participant``, ``sd_stimulus``, ``loglik`` (Laplace),
        ``converged``, ``n_participants``, ``n_stimuli`` (with clicks on a
        stimulus whose prediction varies), ``method``, ``estimable`` and
        ``note``. When the model is not estimable the estimates are NaN,
        ``estimable`` is False and ``note`` says why (one sentence, for a
        warning): fewer than 2 participants or 2 stimuli with usable clicks
        (a variance of random slopes cannot be told apart from the mean
        slope), near-separation (the likelihood of the mean slope still rises
        at the edge of the tabulated range, ``|beta| = table.bound``: clicks
        almost only on each contour's most, or least, surprising points), or
        a fit that fails numerically. It never raises on such data.
    """
    import scipy.optimize
    import scipy.stats

    Z = np.asarray(Z, dtype=float)
    S0, n = Z.shape
    stimulus = np.asarray(stimulus, dtype=np.int64)
    participant = np.asarray(participant, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    live = np.any(Z != 0, axis=1)[stimulus]
    stimulus, participant, j = stimulus[live], participant[live], j[live]
    out = dict(beta=np.nan, se=np.nan, ci_low=np.nan, ci_high=np.nan, df=None, sd_participant=np.nan,
               sd_stimulus=np.nan, loglik=np.nan, converged=False, n_participants=0, n_stimuli=0,
               method="Laplace approximation, crossed random slopes (participants, stimuli); Wald interval "
                      "with t quantiles on min(G, S) - 1 df", estimable=False, note=None)

    def refuse(why):
        out.update(note=f"mixed model not estimated: {why}")
        return out

    if len(stimulus) == 0:
        return refuse("no used click on a stimulus whose prediction varies")
    # renumber the units that have clicks
    su, s_of = np.unique(stimulus, return_inverse=True)
    pu, p_of = np.unique(participant, return_inverse=True)
    S, G = len(su), len(pu)
    out.update(n_participants=G, n_stimuli=S)
    if G < 2 or S < 2:
        unit, units, k = ("participant", "participants'", G) if G < 2 else ("stimulus", "stimuli's", S)
        return refuse(f"only {k} {unit} with usable clicks, so the {units} random slopes cannot be told apart "
                      "from the mean slope (it needs at least 2 participants and 2 stimuli); see the pooled fit")
    table = CumulantTable(Z) if table is None else table
    cells, inv = np.unique(p_of * S + s_of, return_inverse=True)
    A = np.bincount(inv, weights=Z[stimulus, j])
    M = np.bincount(inv).astype(float)
    cp, cs = cells // S, cells % S
    ts = su[cs]
    # near-separation: if the likelihood of a common slope still rises at the edge of the table (or
    # falls at its other edge) the mode lies beyond it (or at infinity) and the curvature vanishes there
    B = table.bound
    rising = A.sum() - (M * table(ts, np.full(len(ts), B))[1]).sum() >= 0
    falling = A.sum() - (M * table(ts, np.full(len(ts), -B))[1]).sum() <= 0
    if rising or falling:
        return refuse(f"the likelihood of the mean slope still {'rises' if rising else 'falls'} at beta = "
                      f"{B if rising else -B:g} (near-separation: clicks almost only on each contour's "
                      f"{'most' if rising else 'least'} surprising points), so it has no finite estimate; the "
                      "effect (top share) and the group test do not depend on it")
    b0 = 0.0 if start is None or not np.isfinite(start) else float(np.clip(start, -10, 10))
    state = dict(u=np.zeros(G), v=np.zeros(S), beta=b0, var=np.nan)

    def wrapped(theta):
        """Minus the Laplace log-likelihood of the two log sds; the modes warm-start the next call."""
        lsp, lss = theta
        sp, ss = np.exp(lsp), np.exp(lss)
        u, v, beta, ll, logdet, var = _mode(table, ts, cs, cp, A, M, G, S, sp, ss, state["u"], state["v"],
                                            state["beta"])
        if np.isfinite(u).all() and np.isfinite(v).all() and np.isfinite(beta):
            state.update(u=u, v=v, beta=beta, var=var)
        return -(ll - G * lsp - S * lss - 0.5 * logdet)

    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            res = scipy.optimize.minimize(wrapped, np.log([0.3, 0.3]), method="L-BFGS-B",
                                          bounds=[_LOG_SD_BOUNDS, _LOG_SD_BOUNDS],
                                          # finite-difference steps well above the inner solution's rounding
                                          options=dict(maxiter=200, ftol=1e-11, gtol=1e-5, eps=1e-5))
            wrapped(res.x)  # the modes at the optimum
    except (np.linalg.LinAlgError, FloatingPointError, ValueError) as exc:
        return refuse(f"its curvature matrix became singular during the fit ({exc}), as it does near "
                      "separation or when the clicks barely constrain the slopes")
    lsp, lss = res.x
    beta = state["beta"]
    if not (np.isfinite(beta) and np.isfinite(res.fun) and abs(beta) < B and state["var"] > 0):
        return refuse(f"the fit did not reach a finite mode inside |beta| < {B:g} (beta = {beta:.4g}), as "
                      "happens near separation")
    se = float(np.sqrt(state["var"])) if state["var"] > 0 else np.nan
    df = max(min(G, S) - 1, 1)
    q = scipy.stats.t.ppf(0.5 + level / 2, df)
    sp, ss = np.exp(lsp), np.exp(lss)
    out.update(beta=float(beta), se=se, ci_low=float(beta - q * se), ci_high=float(beta + q * se), df=int(df),
               sd_participant=float(sp) if lsp > _LOG_SD_BOUNDS[0] + 1e-3 else 0.0,
               sd_stimulus=float(ss) if lss > _LOG_SD_BOUNDS[0] + 1e-3 else 0.0,
               loglik=float(-res.fun), converged=bool(res.success), estimable=True)
    return out
