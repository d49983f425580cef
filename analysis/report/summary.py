"""The JSON summary of an analysis: counts, fits, tests and every resolved parameter."""

from __future__ import annotations

import math

import numpy as np

from attneave.analysis.clicks.mapping import DEFAULT_TOLERANCE_FRACTION, REASONS
from attneave.analysis.report.tables import BANDWIDTH_FRACTION, PEAK_FRACTION

__all__ = ["build_summary", "jsonable"]


def build_summary(d, mapped, main, pci, models, tests, corr, feats, predictions, level, p):
    """The JSON summary: counts, the tested model's fit, every test and every resolved parameter."""
    U, ok = d.U, corr["ok"]
    hit, has_peaks, sidx = feats["hit"], feats["has_peaks"], d.sidx
    ng = np.bincount(d.pidx, minlength=d.G)
    tol, bw, pk, click_sd = p["tolerance"], p["bandwidth"], p["peak_tolerance"], p["click_sd"]
    first = predictions[d.ids[0]].result.params
    summary = dict(
        # the key is absent from results of a library that predates the unit
        length_unit=first.get("length_unit", "px"),
        n_clicks=int(len(mapped)),
        n_used=int(U),
        n_excluded=int(mapped["excluded"].sum()),
        exclusions={r: int((mapped["reason"] == r).sum()) for r in REASONS},
        n_participants=d.G,
        n_participants_used=int((ng > 0).sum()),
        n_stimuli=d.S,
        n_stimuli_clicked=int((d.Ms > 0).sum()),
        beta_hat=main["beta"],
        beta_se=main["se"],
        beta_ci=[main["ci_low"], main["ci_high"]],
        beta_ci_method=f"Wald ({level:g}, Fisher information)",
        beta_profile_ci=list(pci),
        beta_at_bound=main["at_bound"],
        lr_test=dict(statistic=main["lr_stat"], df=1, p_value=main["lr_p"],
                     note="pooled likelihood-ratio test against uniform clicking; treats clicks as independent"),
        group=tests["group"],
        by_stimulus=tests["by_stimulus"],
        participant_beta=tests["participant_beta"],
        models={row.model: dict(beta_hat=row.beta_hat, se=row.se, ci=[row.ci_low, row.ci_high], loglik=row.loglik,
                                aic=row.aic, delta_aic=row.delta_aic, n_params=int(row.n_params),
                                tested=bool(row.tested))
                for row in models.itertuples()},
        spearman=dict(mean_rho=corr["mean_rho"], p_value=corr["p_mean"], n_stimuli=int(ok.sum()),
                      n_significant=int((corr["p"][ok] < 0.05).sum()), shifts_per_stimulus=int(len(corr["shifts"])),
                      grid=p["grid"], alternative="greater"),
        peaks=dict(hit_rate=float(hit[has_peaks].mean()) if has_peaks.any() else None,
                   chance=float(feats["chance"][sidx][has_peaks].mean()) if has_peaks.any() else None,
                   n_clicks=int(has_peaks.sum()), excess_test=tests["peaks"]),
        auc=dict(value=float(np.mean(mapped["surprisal_percentile"].to_numpy()[~mapped["excluded"].to_numpy()])
                             / 100) if U else None, test_vs_half=tests["auc"]),
        concave=dict(click_share=float(feats["concave"].mean()) if U else None,
                     length_share=float(feats["concave_len"][sidx].mean()) if U else None,
                     convex_click_share=float(feats["convex"].mean()) if U else None,
                     convex_length_share=float(feats["convex_len"][sidx].mean()) if U else None,
                     excess_test=tests["concave"]),
        params=dict(
            n=int(d.npts), model=first["model"], length_unit=first.get("length_unit", "px"), A=first.get("A"), b=first.get("b"), units=first.get("units"),
            coords=p["coords"], scale=float(p["scale"]),
            tolerance=dict(px=tol, rule=f"{tol:g} px" if tol is not None
                           else f"{DEFAULT_TOLERANCE_FRACTION:g} x image diagonal"),
            bandwidth=dict(px=bw, rule=f"{bw:g} px" if bw else
                           f"{BANDWIDTH_FRACTION:g} x perimeter (kernel sd in arc length)"),
            peak_tolerance=dict(px=pk, rule=f"{pk:g} px" if pk else
                                f"{PEAK_FRACTION:g} x perimeter (arc length each side)"),
            permutations=int(p["permutations"]), grid=int(p["grid"]), seed=int(p["seed"]), level=float(level),
            group_simulations=int(p["group_simulations"]),
            click_sd=click_sd,
            choice_model="p(j) = exp(beta z_j) / sum_i exp(beta z_i) over the n points; z = standardised surprisal"
            + ("" if click_sd is None else f"; observed through Gaussian error of sd {click_sd:g} px along the contour"),
        ),
        warnings=[],
    )
    if U == 0:
        summary["warnings"].append("no usable clicks: every row was excluded; see clicks.csv for the reasons")
    if d.constant.any():
        summary["warnings"].append(
            f"{int(d.constant.sum())} stimulus/stimuli with constant surprisal (e.g. circles): z = 0, no information")
    return summary


def jsonable(obj):
    """NaN/inf -> None and numpy scalars -> Python, recursively."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj
