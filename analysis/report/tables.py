"""The per-stimulus and per-participant tables of an analysis, and the correlation profiles."""

from __future__ import annotations

import numpy as np

from attneave.analysis.models.choice import fit_beta
from attneave.analysis.models.circular import (
    circular_kde,
    circular_spearman,
    mean_rho_null,
    peak_chance,
    peak_hits,
    shift_indices,
)
from attneave.analysis.models.design import mean_by

__all__ = ["BANDWIDTH_FRACTION", "PEAK_FRACTION", "click_features", "participant_table", "correlation",
           "stimulus_table"]

BANDWIDTH_FRACTION = 0.02
PEAK_FRACTION = 0.02


def click_features(d, predictions, pk_px):
    """Per used click: percentile of its surprisal, peak hit, concave/convex; per stimulus: peak chance."""
    ids = d.ids
    chance = np.array([peak_chance(predictions[s].peak_t, pk_px[i] / d.perim[i]) for i, s in enumerate(ids)])
    npeaks = np.array([len(predictions[s].result.peaks) for s in ids])
    hit = np.zeros(d.U, bool)
    order = np.argsort(d.sidx, kind="stable")
    bounds = np.searchsorted(d.sidx[order], np.arange(d.S + 1))
    for i, s in enumerate(ids):
        sel = order[bounds[i]:bounds[i + 1]]
        if len(sel):
            hit[sel] = peak_hits(d.t[sel], predictions[s].peak_t, pk_px[i] / d.perim[i])
    return dict(hit=hit, chance=chance, npeaks=npeaks, has_peaks=npeaks[d.sidx] > 0,
                concave=d.sign[d.sidx, d.j] < 0, convex=d.sign[d.sidx, d.j] > 0,
                concave_len=(d.sign < 0).mean(axis=1), convex_len=(d.sign > 0).mean(axis=1))


def participant_table(d, mapped, pct, feats, level=0.95):
    """One row per participant in the file (also those without a used click)."""
    import pandas as pd

    G = d.G
    constant = d.constant
    ng = np.bincount(d.pidx, minlength=G).astype(float)
    fg = fit_beta(d.Z, np.bincount(d.pidx, weights=d.zc, minlength=G), d.Mgs, level=level) if G else None
    # a participant whose used clicks all fell on stimuli with constant prediction (z = 0
    # everywhere) has no measured effect: an exact 0 would enter the group tests as data
    informative = np.bincount(d.pidx, weights=(~constant[d.sidx]).astype(float), minlength=G) > 0
    all_counts = mapped["participant"].value_counts()
    p, G_ = d.pidx, G
    per_p = pd.DataFrame(dict(
        participant=d.participants,
        n_clicks=[int(all_counts.get(q, 0)) for q in d.participants],
        n_used=ng.astype(int),
        n_stimuli=np.diff(d.Mgs.indptr),
        mean_z=np.where(informative, mean_by(p, G_, d.zc), np.nan),
        beta_hat=fg["beta"] if G else [],
        beta_se=fg["se"] if G else [],
        beta_at_bound=fg["at_bound"] if G else [],
        auc=np.where(informative, mean_by(p, G_, pct), np.nan),
        peak_hit_rate=mean_by(p, G_, feats["hit"].astype(float), feats["has_peaks"]),
        peak_chance=mean_by(p, G_, feats["chance"][d.sidx], feats["has_peaks"]),
        concave_click_share=mean_by(p, G_, feats["concave"].astype(float)),
        concave_length_share=mean_by(p, G_, feats["concave_len"][d.sidx]),
    ))
    per_p.insert(3, "n_excluded", per_p["n_clicks"] - per_p["n_used"])
    # concavity is measured only on stimuli with both concave and other points
    cl = feats["concave_len"]
    per_p.attrs["concave_informative"] = np.bincount(
        d.pidx, weights=((cl > 0) & (cl < 1))[d.sidx].astype(float), minlength=G) > 0
    return per_p


def correlation(d, bw_px, grid, permutations, seed):
    """Click density along each contour against the prediction: Spearman with circular shifts.

    Returns the density and interpolated z profiles, per-stimulus rho and p,
    and the mean rho over stimuli with its p.
    """
    S = d.S
    dens = circular_kde(d.t, bw_px / d.perim, m=grid, group=d.sidx, n_groups=S)
    gt = np.arange(grid) / grid
    tp = np.append(np.arange(d.npts) / d.npts, 1.0)
    zgrid = np.stack([np.interp(gt, tp, np.append(d.Z[i], d.Z[i, 0])) for i in range(S)])
    shifts = shift_indices(grid, permutations)
    rho, prho = np.full(S, np.nan), np.full(S, np.nan)
    null = np.full((S, len(shifts)), np.nan)
    ok = (d.Ms > 0) & ~d.constant
    if ok.any():
        rho[ok], null[ok], prho[ok] = circular_spearman(dens[ok], zgrid[ok], shifts)
    rng = np.random.default_rng(seed)
    mean_null = mean_rho_null(null[ok], rng) if ok.any() and len(shifts) else np.empty(0)
    mean_rho = float(np.nanmean(rho[ok])) if ok.any() else np.nan
    p_mean = (1 + (mean_null >= mean_rho - 1e-12).sum()) / (1 + len(mean_null)) if len(mean_null) else np.nan
    return dict(t=gt, density=dens, z=zgrid, rho=rho, p=prho, ok=ok, shifts=shifts, mean_rho=mean_rho,
                p_mean=p_mean)


def stimulus_table(d, mapped, predictions, stimset, pct, feats, corr, bw_px, pk_px, level=0.95):
    """One row per stimulus of the set (also those without a used click)."""
    import pandas as pd
    import scipy.sparse

    S, ids = d.S, d.ids
    # one group per stimulus: a sparse diagonal, never an S x S matrix
    fs = fit_beta(d.Z, np.bincount(d.sidx, weights=d.zc, minlength=S), scipy.sparse.diags(d.Ms, format="csr"),
                  level=level)
    n_rows = mapped["stimulus_id"].value_counts()
    G1 = max(d.G, 1)
    parts = np.bincount(np.unique(d.sidx * G1 + d.pidx) // G1, minlength=S)
    s_ = d.sidx
    per_s = pd.DataFrame(dict(
        stimulus_id=ids,
        n_clicks=[int(n_rows.get(s, 0)) for s in ids],
        n_used=d.Ms.astype(int),
        n_participants=parts,
        perimeter_px=d.perim,
        n_points=d.npts,
        ds_px=d.perim / d.npts,
        constant_prediction=d.constant,
        surprisal_sd=[float(np.std(predictions[s].predictors["surprisal"])) for s in ids],
        beta_hat=fs["beta"],
        beta_se=fs["se"],
        beta_at_bound=fs["at_bound"],
        mean_z=mean_by(s_, S, d.zc),
        spearman_rho=corr["rho"],
        spearman_p=corr["p"],
        n_shifts=len(corr["shifts"]),
        bandwidth_px=bw_px,
        n_peaks=feats["npeaks"],
        peak_tolerance_px=pk_px,
        peak_hit_rate=mean_by(s_, S, feats["hit"].astype(float)),
        peak_chance=feats["chance"],
        auc=mean_by(s_, S, pct),
        concave_click_share=mean_by(s_, S, feats["concave"].astype(float)),
        concave_length_share=feats["concave_len"],
        convex_click_share=mean_by(s_, S, feats["convex"].astype(float)),
        convex_length_share=feats["convex_len"],
    ))
    per_s.loc[feats["npeaks"] == 0, "peak_hit_rate"] = np.nan
    mani = stimset.manifest
    if mani is not None:
        for col in ("condition", "generator", "parent_id"):
            if col in mani.columns:
                per_s[col] = mani[col].to_numpy()
    return per_s
