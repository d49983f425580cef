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
clicks, M: their number), so the mode over (u, v, beta) is found by Newton's
method whose Hessian is diagonal in u and in v apart from the sparse (G, S)
block of cell curvatures (a participant meets only the stimuli they saw).
The larger of the two blocks is eliminated by its Schur complement, so each
step costs one dense solve of size ``min(G, S) + 1`` and memory grows with
the cells, never with G x S or (G + S)^2. ``log sum_i exp(b z_si)`` and its
first three derivatives in b are tabulated per stimulus on a fine grid, in
blocks computed only where slopes fall, and interpolated by cubic Hermite
polynomials (relative error below 1e-9 for the fits here), so an evaluation
costs O(cells) whatever n. The approximate marginal log-likelihood is
maximised over (log sd_participant, log sd_stimulus) with
:func:`scipy.optimize.minimize` (L-BFGS-B) and its analytic gradient: the
envelope theorem for the mode, and ``d log det H = tr(H^-1 dH)`` for the
curvature, whose change through the mode is carried by the third cumulant
at each cell (selected elements of ``H^-1`` come from the Schur complement).
beta is integrated out with a flat prior (the Laplace analogue of REML:
beta is found jointly with the random effects at the mode, so the outer
problem has two dimensions). The interval of beta is Wald's, from the beta
element of the inverse curvature at the mode, with t quantiles on
``min(G, S) - 1`` degrees of freedom (the smaller set of random units limits
what is known about the mean slope).

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

from attneave.analysis.models.choice import block_moments
from attneave.analysis.models.cumulants import CumulantTable

__all__ = ["CumulantTable", "fit_mixed", "laplace_loglik", "moment_sds"]

_LOG_SD_BOUNDS = (-7.0, np.log(5.0))

#: Big-block units per dense chunk of the Schur complement (chunk x (small + 1) values at a time).
_CHUNK = 4096

#: Values of C (big x (small + 1)) up to which a state keeps its rows (64 MB).
_KEEP_ROWS = 1 << 23


class _Cells:
    """The cells of a crossed design, the larger set of units ("big", eliminated) first.

    ``cb, cs`` big and small unit of each cell (sorted by big unit), ``ts`` its table row, ``A, M``
    its sum of z and clicks; ``nb, ns`` the sizes; ``big_is_participant`` which set is which.
    """

    def __init__(self, cp, cs, ts, A, M, G, S):
        self.big_is_participant = G >= S
        big, small = (cp, cs) if self.big_is_participant else (cs, cp)
        self.nb, self.ns = (G, S) if self.big_is_participant else (S, G)
        order = np.lexsort((small, big))
        self.cb, self.cs, self.ts, self.A, self.M = big[order], small[order], ts[order], A[order], M[order]
        self.ptr = np.searchsorted(self.cb, np.arange(self.nb + 1))


def _dense_rows(cells, w, b0, b1):
    """Rows b0:b1 of C (big x (small + 1)): cell curvatures, and the beta column."""
    R = cells.ns + 1
    c0, c1 = cells.ptr[b0], cells.ptr[b1]
    rows = cells.cb[c0:c1] - b0
    out = np.zeros((b1 - b0, R))
    out[rows, cells.cs[c0:c1]] = w[c0:c1]  # one cell per (big, small) pair
    out[:, R - 1] = np.bincount(rows, weights=w[c0:c1], minlength=b1 - b0)
    return out


def _row_chunks(cells, st):
    """(b0, b1, rows b0:b1 of C) for the curvatures of state `st`: kept from its Schur complement
    when C is small, rebuilt chunk by chunk otherwise."""
    kept = st.get("rows")
    for k, b0 in enumerate(range(0, cells.nb, _CHUNK)):
        b1 = min(b0 + _CHUNK, cells.nb)
        yield b0, b1, (kept[k] if kept else _dense_rows(cells, st["w"], b0, b1))


def _mode(table, cells, lam_b, lam_s, xb, xs, beta, iters=100, tol=1e-9):
    """Joint mode of (big, small, beta) effects of the penalised log-likelihood, given the precisions.

    Newton steps, halved until the (concave) objective rises, so that any
    start converges. The big block of the Hessian is diagonal and is
    eliminated by its Schur complement, leaving a dense
    ``(small + 1) x (small + 1)`` system; the cross block is formed in chunks
    of big units, so no big x small array is held.

    Returns a dict: ``xb, xs, beta``, the objective ``f`` at the mode, ``logdet`` of minus its
    Hessian, ``D`` (the big diagonal), ``chol`` (of the Schur complement) and ``w`` (cell
    curvatures), for the variance of beta and the gradient.
    """
    import scipy.linalg

    c = cells
    R = c.ns + 1

    def parts(xb, xs, beta):
        bv = beta + xb[c.cb] + xs[c.cs]
        K, E, V = table(c.ts, bv)
        f = float((bv * c.A - c.M * K).sum() - lam_b * (xb @ xb) / 2 - lam_s * (xs @ xs) / 2)
        w = c.M * V
        D = np.bincount(c.cb, weights=w, minlength=c.nb) + lam_b
        hs = np.bincount(c.cs, weights=w, minlength=c.ns)
        B = np.diag(np.r_[hs + lam_s, w.sum()])
        B[:c.ns, c.ns] = B[c.ns, :c.ns] = hs
        # the solves and the gradient reuse the rows while they are small (rebuilt at each otherwise)
        rows = [] if c.nb * R <= _KEEP_ROWS else None
        for b0, b1, Cb in _row_chunks(c, dict(w=w)):
            B -= Cb.T @ (Cb / D[b0:b1, None])
            if rows is not None:
                rows.append(Cb)
        return dict(f=f, g=c.A - c.M * E, D=D, w=w, chol=scipy.linalg.cho_factor(B), rows=rows)

    def solve(st, rb, rr):
        """H^-1 (rb, rr) by the Schur complement."""
        t = rb / st["D"]
        rhs = rr.copy()
        for b0, b1, Cb in _row_chunks(c, st):
            rhs -= Cb.T @ t[b0:b1]
        dr = scipy.linalg.cho_solve(st["chol"], rhs)
        cd = np.empty(c.nb)
        for b0, b1, Cb in _row_chunks(c, st):
            cd[b0:b1] = Cb @ dr
        return (rb - cd) / st["D"], dr

    st = parts(xb, xs, beta)
    for _ in range(iters):
        g = st["g"]
        gb = np.bincount(c.cb, weights=g, minlength=c.nb) - lam_b * xb
        gr = np.r_[np.bincount(c.cs, weights=g, minlength=c.ns) - lam_s * xs, g.sum()]
        db, dr = solve(st, gb, gr)
        if max(np.abs(db).max(initial=0), np.abs(dr).max()) < tol:
            break  # at the mode: a step this small changes nothing reported, and costs an evaluation
        step = 1.0
        while step > 1e-6:
            nb_, ns_, nbeta = xb + step * db, xs + step * dr[:c.ns], beta + step * dr[c.ns]
            nst = parts(nb_, ns_, nbeta)
            if nst["f"] >= st["f"] - 1e-12 * abs(st["f"]):
                break
            step /= 2
        xb, xs, beta, st = nb_, ns_, nbeta, nst
    st.update(xb=xb, xs=xs, beta=beta, solve=lambda rb, rr: solve(st, rb, rr),
              logdet=np.log(st["D"]).sum() + 2 * np.log(np.diag(st["chol"][0])).sum())
    e = np.zeros(R)
    e[c.ns] = 1.0
    st["var_beta"] = float(scipy.linalg.cho_solve(st["chol"], e)[c.ns])
    return st


def _logdet_gradient(table, cells, st, lam_b, lam_s):
    """d log det H / d (log sd_big, log sd_small) at the mode `st` of :func:`_mode`.

    ``d log det H = tr(H^-1 dH)``: the prior precisions change directly
    (``d lam / d log sd = -2 lam``), and every cell's curvature ``M V(b_c)``
    changes through the mode, ``dx / d theta = H^-1 d grad / d theta``, by
    ``M V'(b_c) a_c' dx`` with ``a_c`` the cell's indicator of (big, small,
    beta); ``h_c = a_c' H^-1 a_c`` comes from the Schur complement, in
    chunks of big units.
    """
    import scipy.linalg

    c = cells
    R = c.ns + 1
    Sig = scipy.linalg.cho_solve(st["chol"], np.eye(R))
    D = st["D"]
    h = np.empty(len(c.cb))
    diag_b = np.empty(c.nb)
    for b0, b1, Cb in _row_chunks(c, st):
        Q = Cb / D[b0:b1, None]
        Y = Q @ Sig
        y2 = np.einsum("br,br->b", Y, Q)
        diag_b[b0:b1] = 1 / D[b0:b1] + y2
        c0, c1 = c.ptr[b0], c.ptr[b1]
        r, s = c.cb[c0:c1] - b0, c.cs[c0:c1]
        # (q_b - e_s - e_beta)' Sig (q_b - e_s - e_beta) + 1 / D_b
        h[c0:c1] = (diag_b[b0:b1][r] - 2 * Y[r, s] - 2 * Y[r, R - 1] + Sig[s, s] + 2 * Sig[s, R - 1]
                    + Sig[R - 1, R - 1])
    bv = st["beta"] + st["xb"][c.cb] + st["xs"][c.cs]
    dV = table.dV(c.ts, bv)
    out = []
    for which in ("big", "small"):
        if which == "big":
            rb, rr = 2 * lam_b * st["xb"], np.zeros(R)
            direct = -2 * lam_b * diag_b.sum()
        else:
            rb, rr = np.zeros(c.nb), np.r_[2 * lam_s * st["xs"], 0.0]
            direct = -2 * lam_s * np.trace(Sig[:c.ns, :c.ns])
        xb_d, xr_d = st["solve"](rb, rr)
        db = xb_d[c.cb] + xr_d[c.cs] + xr_d[c.ns]
        out.append(direct + float((c.M * dV * db * h).sum()))
    return out


def _cells_of(Z, stimulus, participant, j):
    """The cells (participant, stimulus) with clicks on stimuli whose prediction varies:
    (cp, cs, ts, A, M, G, S) with units renumbered among those with clicks."""
    stimulus = np.asarray(stimulus, dtype=np.int64)
    participant = np.asarray(participant, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    live = np.any(Z != 0, axis=1)[stimulus]
    stimulus, participant, j = stimulus[live], participant[live], j[live]
    su, s_of = np.unique(stimulus, return_inverse=True)
    _, p_of = np.unique(participant, return_inverse=True)
    S, G = len(su), int(p_of.max()) + 1 if len(p_of) else 0
    cells, inv = np.unique(p_of * max(S, 1) + s_of, return_inverse=True)
    A = np.bincount(inv, weights=Z[stimulus, j]) if len(inv) else np.zeros(0)
    M = np.bincount(inv).astype(float)
    cp, cs = cells // max(S, 1), cells % max(S, 1)
    return cp, cs, su[cs], A, M, G, S


def laplace_loglik(Z, stimulus, participant, j, sd_participant, sd_stimulus, table=None):
    """The Laplace log-likelihood that :func:`fit_mixed` maximises, and its analytic gradient.

    Parameters
    ----------
    Z : (S, n) array_like
    stimulus, participant, j : (U,) array_like of int
        As in :func:`fit_mixed` (at least 2 participants and 2 stimuli).
    sd_participant, sd_stimulus : float
        The sds of the random slopes (> 0).
    table : CumulantTable, optional

    Returns
    -------
    loglik : float
        Marginal log-likelihood of the two sds (beta integrated out with a
        flat prior), by the Laplace approximation at the joint mode.
    gradient : (2,) ndarray
        Its derivatives in ``log sd_participant`` and ``log sd_stimulus``.
    beta : float
        The mean slope at the mode.
    """
    Z = np.asarray(Z, dtype=float)
    cp, cs, ts, A, M, G, S = _cells_of(Z, stimulus, participant, j)
    if G < 2 or S < 2:
        raise ValueError("laplace_loglik needs clicks of at least 2 participants on 2 stimuli")
    table = CumulantTable(Z) if table is None else table
    cells = _Cells(cp, cs, ts, A, M, G, S)
    value, grad, st = _objective(table, cells, np.log([sd_participant, sd_stimulus]),
                                 np.zeros(cells.nb), np.zeros(cells.ns), 0.0)
    return -value, -grad, float(st["beta"])


def _objective(table, cells, theta, xb, xs, beta):
    """Minus the Laplace log-likelihood of theta = (log sd_participant, log sd_stimulus), its
    gradient, and the mode (started from xb, xs, beta)."""
    lsp, lss = theta
    lb, ls = (lsp, lss) if cells.big_is_participant else (lss, lsp)
    lam_b, lam_s = np.exp(-2 * lb), np.exp(-2 * ls)
    st = _mode(table, cells, lam_b, lam_s, xb, xs, beta)
    value = -(st["f"] - cells.nb * lb - cells.ns * ls - 0.5 * st["logdet"])
    d_b, d_s = _logdet_gradient(table, cells, st, lam_b, lam_s)
    # envelope theorem: at the mode only the explicit dependence on the sds counts
    g_b = -(lam_b * (st["xb"] @ st["xb"]) - cells.nb - 0.5 * d_b)
    g_s = -(lam_s * (st["xs"] @ st["xs"]) - cells.ns - 0.5 * d_s)
    return value, np.array([g_b, g_s] if cells.big_is_participant else [g_s, g_b]), st


def fit_mixed(Z, stimulus, participant, j, n_participants=None, level=0.95, table=None, start=None,
              start_sd=None):
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
    start_sd : (float, float), optional
        Starting values of ``sd_participant`` and ``sd_stimulus`` (e.g.
        :func:`moment_sds` of the per-unit slopes; default 0.3 each). Only
        the path of the optimiser depends on them, not its optimum.

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
    cp, cs, ts, A, M, G, S = _cells_of(Z, stimulus, participant, j)  # units renumbered among those with clicks
    out.update(n_participants=G, n_stimuli=S)
    if G < 2 or S < 2:
        unit, units, k = ("participant", "participants'", G) if G < 2 else ("stimulus", "stimuli's", S)
        return refuse(f"only {k} {unit} with usable clicks, so the {units} random slopes cannot be told apart "
                      "from the mean slope (it needs at least 2 participants and 2 stimuli); see the pooled fit")
    table = CumulantTable(Z) if table is None else table
    # near-separation: if the likelihood of a common slope still rises at the edge of the table (or
    # falls at its other edge) the mode lies beyond it (or at infinity) and the curvature vanishes there
    B = table.bound
    # the score at the edges, exactly (the table's value at its end nodes) without tabulating them
    rising = A.sum() - (M * block_moments(np.full(len(ts), B), table.Z, ts)[1]).sum() >= 0
    falling = A.sum() - (M * block_moments(np.full(len(ts), -B), table.Z, ts)[1]).sum() <= 0
    if rising or falling:
        return refuse(f"the likelihood of the mean slope still {'rises' if rising else 'falls'} at beta = "
                      f"{B if rising else -B:g} (near-separation: clicks almost only on each contour's "
                      f"{'most' if rising else 'least'} surprising points), so it has no finite estimate; the "
                      "effect (top share) and the group test do not depend on it")
    b0 = 0.0 if start is None or not np.isfinite(start) else float(np.clip(start, -10, 10))
    cells = _Cells(cp, cs, ts, A, M, G, S)
    state = dict(xb=np.zeros(cells.nb), xs=np.zeros(cells.ns), beta=b0, var=np.nan)

    def objective(theta):
        """_objective, the modes warm-starting the next call."""
        value, grad, st = _objective(table, cells, theta, state["xb"], state["xs"], state["beta"])
        if np.isfinite(st["xb"]).all() and np.isfinite(st["xs"]).all() and np.isfinite(st["beta"]):
            state.update(xb=st["xb"], xs=st["xs"], beta=st["beta"], var=st["var_beta"])
        return value, grad

    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            res = scipy.optimize.minimize(objective, _log_sd_start(start_sd), jac=True, method="L-BFGS-B",
                                          bounds=[_LOG_SD_BOUNDS, _LOG_SD_BOUNDS],
                                          options=dict(maxiter=200, ftol=1e-12, gtol=1e-7))
            objective(res.x)  # the modes at the optimum
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


def _log_sd_start(start_sd):
    """log of the starting sds, inside the bounds (0.3 each where not given or not finite)."""
    sd = np.array([0.3, 0.3] if start_sd is None else start_sd, dtype=float)
    sd = np.where(np.isfinite(sd) & (sd > 0), sd, 0.3)
    return np.clip(np.log(sd), _LOG_SD_BOUNDS[0] + 1.0, _LOG_SD_BOUNDS[1] - 0.5)


def moment_sds(beta, se):
    """Spread of true slopes among units, from their separately fitted slopes: the method of moments.

    ``var(beta_hat) - mean(se**2)``, the variance of the estimates less the
    part their sampling error explains (DerSimonian & Laird 1986), as an sd;
    floored at 0.01, so that it can start an optimiser in log sd.

    Parameters
    ----------
    beta, se : (k,) array_like
        Per-unit slopes and their standard errors; units with a NaN or an
        infinite value are left out.

    Returns
    -------
    float
        NaN with fewer than 3 usable units.

    References
    ----------
    .. [1] DerSimonian, R., & Laird, N. (1986). Meta-analysis in clinical
           trials. Controlled Clinical Trials 7, 177-188.

    Examples
    --------
    >>> round(moment_sds([0.0, 1.0, 2.0, 3.0], [0.5, 0.5, 0.5, 0.5]), 6)
    1.190238
    """
    b, e = np.asarray(beta, dtype=float), np.asarray(se, dtype=float)
    ok = np.isfinite(b) & np.isfinite(e)
    if ok.sum() < 3:
        return np.nan
    return float(np.sqrt(max(np.var(b[ok], ddof=1) - np.mean(e[ok] ** 2), 1e-4)))

