"""The analysis of a click file against a stimulus set, and its outputs.

:func:`analyze` maps every click (see :mod:`analysis.mapping`), computes the
statistics of :mod:`analysis.stats` per stimulus, per participant and for the
group, and returns an :class:`Analysis`. :func:`write_analysis` writes it:

``clicks.csv``
    Every input row, in input order, with its line in the file, the input
    columns as written, the mapping, ``peak_hit``, ``excluded`` and
    ``reason``.
``per_stimulus.csv``, ``per_participant.csv``
    One row per stimulus of the set / per participant in the file
    (including those without a usable click).
``models.csv``
    The choice model fitted with each predictor: beta, log-likelihood, AIC.
``summary.json``
    Counts (``n_clicks, n_used, n_excluded, exclusions`` by reason),
    ``beta_hat`` with its Wald and profile intervals, the group test, the
    model comparison, the correlation, peak, AUC and concavity results, and
    every resolved parameter.
``figures/*.png`` and ``report.html``
    The figures of :mod:`analysis.plots` and one self-contained page (images
    embedded as base64) showing them with the main tables.

Writing is all-or-nothing: everything is written into a fresh hidden
temporary directory beside the output directory, which is renamed into place
when complete (a rename within one file system is atomic). An interrupted or
failed run leaves at most that hidden directory, which is removed on any
error it can catch, and never a half-written output directory.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stimuli.errors import InputError
from stimuli.io import as_number

from . import stats
from .mapping import DEFAULT_TOLERANCE_FRACTION, PREDICTORS, REASONS, map_clicks, predict

__all__ = ["Analysis", "analyze", "write_analysis", "DEFAULTS"]

DEFAULTS = dict(
    n=100,
    model="paper",
    coords="image",
    scale=1.0,
    tolerance=None,
    bandwidth=None,
    peak_tolerance=None,
    permutations=1000,
    grid=1024,
    seed=0,
    level=0.95,
    group_simulations=1999,
)
_BANDWIDTH_FRACTION = 0.02
_PEAK_FRACTION = 0.02


@dataclass
class Analysis:
    """Everything `analyze` computed.

    Attributes
    ----------
    clicks : pandas.DataFrame
        Every input row with its mapping, ``excluded`` and ``reason``.
    per_stimulus, per_participant, models : pandas.DataFrame
    summary : dict
        JSON-ready (NaN as None).
    predictions : dict of str -> StimulusPrediction
    profiles : dict
        ``t`` (grid, m), ``density`` (S, m) click density along t,
        ``z`` (S, m) standardised surprisal interpolated on the grid,
        ``ids`` (S,).
    stimset : StimulusSet
    """

    clicks: object
    per_stimulus: object
    per_participant: object
    models: object
    summary: dict
    predictions: dict
    profiles: dict = field(default_factory=dict)
    stimset: object = None


def _positive(name, value, allow_none=True):
    if value is None and allow_none:
        return None
    return as_number(value, name, gt=0)


def analyze(clicks, stimset, n=100, model="paper", coords="image", scale=1.0, tolerance=None, bandwidth=None,
            peak_tolerance=None, permutations=1000, grid=1024, seed=0, level=0.95, A=0.25, b=None,
            click_sd=None, predictions=None, group_simulations=1999):
    """Analyse clicks against the information predicted along the contours.

    Parameters
    ----------
    clicks : pandas.DataFrame
        Columns ``participant, stimulus_id, x, y`` (text or numbers) and any
        others (kept), e.g. from :func:`analysis.clicks.read_clicks`.
    stimset : StimulusSet
        From :func:`stimuli.stimulus_set.read_stimulus_set`.
    n : int
        Equally spaced points per contour for the prediction.
    model : {'paper', 'vonmises'}
        Surprisal model under test.
    coords : {'image', 'centered'}, scale : float
        Coordinate system of the clicks (see :mod:`analysis.clicks`).
    tolerance : float, optional
        Largest click-contour distance in px (default 5% of the image
        diagonal).
    bandwidth : float, optional
        Kernel sd of the click density along the contour, in px of arc length
        (default 2% of each perimeter).
    peak_tolerance : float, optional
        A click within this arc length (px) of a predicted peak is a hit
        (default 2% of each perimeter).
    permutations : int
        Circular shifts in the null of the correlation (per stimulus).
    grid : int
        Positions along the contour at which density and prediction are
        correlated (the prediction is interpolated linearly between its n
        points).
    seed : int
        Seed of the random steps: the null of the mean correlation over
        stimuli and the Monte Carlo null of the group and items tests (each
        from its own stream derived from the seed).
    level : float
        Confidence level.
    A, b : float
        Parameters of the surprisal model.
    click_sd : float, optional
        Localisation error of clicks along the contour (sd in px). When
        given, the pooled fits (the tested model and its rivals) use the
        choice model observed through that error
        (:func:`analysis.stats.fit_beta_blurred`); otherwise, and always for
        the per-participant and per-stimulus betas, the plain model, whose
        beta_hat is attenuated by click noise.
    predictions : dict, optional
        Precomputed :func:`analysis.mapping.predict` output (same n, model).
    group_simulations : int
        Monte Carlo replicates R of the null of the group test and the items
        test (:func:`analysis.stats.mean_z_test`): each used click keeps its
        stimulus and participant and is redrawn uniformly among the
        stimulus's n points. The smallest possible p is ``1 / (1 + R)``;
        0 skips the simulation (p-values None; the parametric ones remain).

    Returns
    -------
    Analysis
    """
    import pandas as pd

    tolerance = _positive("--tolerance", tolerance)
    bandwidth = _positive("--bandwidth", bandwidth)
    peak_tolerance = _positive("--peak-tolerance", peak_tolerance)
    click_sd = _positive("--click-sd", click_sd)
    scale = _positive("--scale", scale, allow_none=False)
    if not (isinstance(permutations, (int, np.integer)) and permutations >= 0):
        raise InputError(f"--permutations must be a whole number >= 0, got {permutations!r}")
    if not (isinstance(group_simulations, (int, np.integer)) and group_simulations >= 0):
        raise InputError(f"--group-simulations must be a whole number >= 0, got {group_simulations!r}")
    if not (isinstance(grid, (int, np.integer)) and grid >= 8):
        raise InputError(f"--grid must be a whole number >= 8, got {grid!r}")
    if not 0 < level < 1:
        raise InputError(f"level must be in (0, 1), got {level!r}")
    if predictions is None:
        predictions = predict(stimset, n=n, model=model, A=A, b=b)
    ids = list(stimset.ids)
    S = len(ids)
    sindex = {s: i for i, s in enumerate(ids)}
    mapped = map_clicks(clicks, predictions, coords=coords, scale=scale, tolerance=tolerance)
    excluded = mapped["excluded"].to_numpy()
    used = ~excluded

    # ------------------------------------------------------------ indexing
    sidx_all = mapped["stimulus_id"].map(sindex).to_numpy()
    part_all = mapped["participant"].to_numpy(dtype=object)
    participants = sorted(set(pd.unique(part_all)) - {""})
    G = len(participants)
    sidx = sidx_all[used].astype(np.int64)
    pidx = pd.Categorical(part_all[used], categories=participants).codes.astype(np.int64)
    t = mapped["t"].to_numpy()[used]
    j = mapped["point"].to_numpy()[used].astype(np.int64)
    zc = mapped["z"].to_numpy()[used]
    U = len(t)

    perim = np.array([predictions[s].perimeter for s in ids])
    npts = predictions[ids[0]].n
    Zs = {k: np.stack([predictions[s].z[k] for s in ids]) for k in PREDICTORS}
    Z = np.stack([predictions[s].z["surprisal"] for s in ids])
    sign = np.stack([predictions[s].sign for s in ids])
    constant = np.all(Z == 0, axis=1)
    Ms = np.bincount(sidx, minlength=S).astype(float)
    Mgs = np.bincount(pidx * S + sidx, minlength=G * S).reshape(G, S).astype(float)
    Cs = np.bincount(sidx * npts + j, minlength=S * npts).reshape(S, npts).astype(float)

    # --------------------------------------------- choice model, pooled and rivals
    model_name = predictions[ids[0]].result.params["model"]
    models = []
    fits = {}
    for k in PREDICTORS:
        Ak = Zs[k][sidx, j].sum() if U else 0.0
        if click_sd is None:
            f = stats.fit_beta(Zs[k], Ak, Ms, level=level)
        else:
            f = stats.fit_beta_blurred(Zs[k], Cs, click_sd / (perim / npts), level=level)
        fits[k] = f
        models.append(dict(model=k, tested=k == model_name, n_params=1, beta_hat=f["beta"], se=f["se"],
                           ci_low=f["ci_low"], ci_high=f["ci_high"], loglik=f["loglik"], at_bound=f["at_bound"]))
    ll0 = fits[model_name]["loglik0"]
    models.append(dict(model="uniform", tested=False, n_params=0, beta_hat=0.0, se=np.nan, ci_low=np.nan,
                       ci_high=np.nan, loglik=ll0, at_bound=False))
    models = pd.DataFrame(models)
    models["aic"] = 2 * models["n_params"] - 2 * models["loglik"]
    models["delta_aic"] = models["aic"] - models["aic"].min()
    main = fits[model_name]
    if U and click_sd is None:
        pci = stats.profile_ci(Z, zc.sum(), Ms, main["beta"], level=level)
    else:
        pci = (np.nan, np.nan)

    # ---------------------------------------------------------- per participant
    Ag = np.bincount(pidx, weights=zc, minlength=G)
    ng = np.bincount(pidx, minlength=G).astype(float)
    fg = stats.fit_beta(Z, Ag, Mgs, level=level) if G else None
    pct = mapped["surprisal_percentile"].to_numpy()[used] / 100.0
    bw_px = bandwidth * np.ones(S) if bandwidth is not None else _BANDWIDTH_FRACTION * perim
    pk_px = peak_tolerance * np.ones(S) if peak_tolerance is not None else _PEAK_FRACTION * perim
    chance = np.array([stats.peak_chance(predictions[s].peak_t, pk_px[i] / perim[i]) for i, s in enumerate(ids)])
    npeaks = np.array([len(predictions[s].result.peaks) for s in ids])
    hit = np.zeros(U, bool)
    for i, s in enumerate(ids):
        sel = sidx == i
        if sel.any():
            hit[sel] = stats.peak_hits(t[sel], predictions[s].peak_t, pk_px[i] / perim[i])
    has_peaks = npeaks[sidx] > 0
    concave_click = sign[sidx, j] < 0
    convex_click = sign[sidx, j] > 0
    concave_len = (sign < 0).mean(axis=1)
    convex_len = (sign > 0).mean(axis=1)

    def by(index, size, values, mask=None):
        w = np.ones(len(index)) if mask is None else mask.astype(float)
        num = np.bincount(index, weights=values * w, minlength=size)
        den = np.bincount(index, weights=w, minlength=size)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(den > 0, num / den, np.nan)

    # a participant whose used clicks all fell on stimuli with constant prediction (z = 0
    # everywhere) has no measured effect: an exact 0 would enter the group tests as data
    informative = np.bincount(pidx, weights=(~constant[sidx]).astype(float), minlength=G) > 0
    # likewise for the concavity test: stimuli with both concave and other points
    concave_informative = np.bincount(pidx, weights=((concave_len > 0) & (concave_len < 1))[sidx].astype(float),
                                      minlength=G) > 0
    all_counts = pd.Series(part_all).value_counts()
    per_p = pd.DataFrame(
        dict(
            participant=participants,
            n_clicks=[int(all_counts.get(p, 0)) for p in participants],
            n_used=ng.astype(int),
            n_stimuli=(Mgs > 0).sum(axis=1),
            mean_z=np.where(informative, by(pidx, G, zc), np.nan),
            beta_hat=fg["beta"] if G else [],
            beta_se=fg["se"] if G else [],
            beta_at_bound=fg["at_bound"] if G else [],
            auc=np.where(informative, by(pidx, G, pct), np.nan),
            peak_hit_rate=by(pidx, G, hit.astype(float), has_peaks),
            peak_chance=by(pidx, G, chance[sidx], has_peaks),
            concave_click_share=by(pidx, G, concave_click.astype(float)),
            concave_length_share=by(pidx, G, concave_len[sidx]),
        )
    )
    per_p.insert(3, "n_excluded", per_p["n_clicks"] - per_p["n_used"])

    # ------------------------------------------------------------- per stimulus
    fs = stats.fit_beta(Z, np.bincount(sidx, weights=zc, minlength=S), np.diag(Ms), level=level)
    dens = stats.circular_kde(t, bw_px / perim, m=grid, group=sidx, n_groups=S)
    gt = np.arange(grid) / grid
    tp = np.append(np.arange(npts) / npts, 1.0)
    zgrid = np.stack([np.interp(gt, tp, np.append(Z[i], Z[i, 0])) for i in range(S)])
    shifts = stats.shift_indices(grid, permutations)
    rho = np.full(S, np.nan)
    prho = np.full(S, np.nan)
    null = np.full((S, len(shifts)), np.nan)
    ok = (Ms > 0) & ~constant
    if ok.any():
        r, nl, p = stats.circular_spearman(dens[ok], zgrid[ok], shifts)
        rho[ok], null[ok], prho[ok] = r, nl, p
    rng = np.random.default_rng(seed)
    mean_null = stats.mean_rho_null(null[ok], rng) if ok.any() and len(shifts) else np.empty(0)
    mean_rho = float(np.nanmean(rho[ok])) if ok.any() else np.nan
    p_mean_rho = (1 + (mean_null >= mean_rho - 1e-12).sum()) / (1 + len(mean_null)) if len(mean_null) else np.nan
    n_rows_s = mapped["stimulus_id"].value_counts()
    parts_s = np.bincount(np.unique(sidx * max(G, 1) + pidx) // max(G, 1), minlength=S)
    mani = stimset.manifest
    per_s = pd.DataFrame(
        dict(
            stimulus_id=ids,
            n_clicks=[int(n_rows_s.get(s, 0)) for s in ids],
            n_used=Ms.astype(int),
            n_participants=parts_s,
            perimeter_px=perim,
            n_points=npts,
            ds_px=perim / npts,
            constant_prediction=constant,
            surprisal_sd=[float(np.std(predictions[s].predictors["surprisal"])) for s in ids],
            beta_hat=fs["beta"],
            beta_se=fs["se"],
            beta_at_bound=fs["at_bound"],
            mean_z=by(sidx, S, zc),
            spearman_rho=rho,
            spearman_p=prho,
            n_shifts=len(shifts),
            bandwidth_px=bw_px,
            n_peaks=npeaks,
            peak_tolerance_px=pk_px,
            peak_hit_rate=by(sidx, S, hit.astype(float)),
            peak_chance=chance,
            auc=by(sidx, S, pct),
            concave_click_share=by(sidx, S, concave_click.astype(float)),
            concave_length_share=concave_len,
            convex_click_share=by(sidx, S, convex_click.astype(float)),
            convex_length_share=convex_len,
        )
    )
    per_s.loc[npeaks == 0, "peak_hit_rate"] = np.nan
    if mani is not None:
        for col in ("condition", "generator", "parent_id"):
            if col in mani.columns:
                per_s[col] = mani[col].to_numpy()

    # ---------------------------------------------------------- the clicks table
    out = mapped.copy()
    ph = pd.array([pd.NA] * len(out), dtype="Int64")
    ph[np.flatnonzero(used)] = hit.astype(int)
    out.insert(out.columns.get_loc("excluded"), "peak_hit", ph)

    # ------------------------------------------------------------------ summary
    counts = {r: int((mapped["reason"] == r).sum()) for r in REASONS}
    # the Monte Carlo nulls of the group and items tests: streams of their own, so that
    # the correlation's null above does not change with them
    rng_g, rng_s = (np.random.default_rng(c) for c in np.random.SeedSequence(seed, spawn_key=(6,)).spawn(2))
    g_test = stats.mean_z_test(Z, sidx, pidx, zc, n_units=G, replicates=group_simulations, rng=rng_g, level=level)
    g_test["test"] = ("one-sample t statistic of per-participant mean z, Monte Carlo null under uniform clicking "
                      f"(R = {int(group_simulations)})")
    g_test["effect"] = "per-participant mean z (standardised surprisal) at used clicks; 0 under uniform clicking"
    g_test["null"] = ("each used click keeps its stimulus and participant and is redrawn uniformly among the "
                      "stimulus's n points (beta = 0); p = (1 + #{null t >= t}) / (1 + R), one-sided (greater)")
    s_test = stats.mean_z_test(Z, sidx, sidx, zc, n_units=S, replicates=group_simulations, rng=rng_s, level=level)
    s_test["test"] = ("one-sample t statistic of per-stimulus mean z, Monte Carlo null under uniform clicking "
                      f"(R = {int(group_simulations)})")
    s_test["effect"] = "per-stimulus mean z at used clicks (items analysis; stimuli with constant prediction left out)"
    pb = per_p.loc[~per_p["beta_at_bound"].astype(bool), "beta_hat"].to_numpy() if G else np.empty(0)
    b_test = stats.group_test(pb, level=level)
    b_test["effect"] = "per-participant ML beta (participants whose beta hit the search bound left out)"
    b_test["n_at_bound"] = int(per_p["beta_at_bound"].astype(bool).sum()) if G else 0
    # ML betas from a participant's few clicks are far from normal (and those at the bound are
    # left out), so the t distribution does not hold here: descriptive only, no p_value
    b_test["p_value_parametric"] = b_test.pop("p_value")
    b_test["note"] = ("descriptive: the t distribution is not calibrated for per-participant betas (measured "
                      "false-positive rates 0.19-0.50 at alpha = 0.05 under uniform clicking on polygons); "
                      "the test of the effect is 'group'")
    auc_test = stats.group_test(per_p["auc"].to_numpy() - 0.5, level=level)
    peak_test = stats.group_test((per_p["peak_hit_rate"] - per_p["peak_chance"]).to_numpy(), level=level)
    conc_test = stats.group_test(np.where(concave_informative, (per_p["concave_click_share"]
                                                                 - per_p["concave_length_share"]).to_numpy(), np.nan),
                                 level=level)
    tol_rule = (f"{tolerance:g} px" if tolerance is not None
                else f"{DEFAULT_TOLERANCE_FRACTION:g} x image diagonal")
    first = predictions[ids[0]].result.params
    summary = dict(
        n_clicks=int(len(mapped)),
        n_used=int(U),
        n_excluded=int(excluded.sum()),
        exclusions=counts,
        n_participants=G,
        n_participants_used=int((ng > 0).sum()),
        n_stimuli=S,
        n_stimuli_clicked=int((Ms > 0).sum()),
        beta_hat=main["beta"],
        beta_se=main["se"],
        beta_ci=[main["ci_low"], main["ci_high"]],
        beta_ci_method=f"Wald ({level:g}, Fisher information)",
        beta_profile_ci=list(pci),
        beta_at_bound=main["at_bound"],
        lr_test=dict(statistic=main["lr_stat"], df=1, p_value=main["lr_p"],
                     note="pooled likelihood-ratio test against uniform clicking; treats clicks as independent"),
        group=g_test,
        by_stimulus=s_test,
        participant_beta=b_test,
        models={row.model: dict(beta_hat=row.beta_hat, se=row.se, ci=[row.ci_low, row.ci_high], loglik=row.loglik,
                                aic=row.aic, delta_aic=row.delta_aic, n_params=int(row.n_params),
                                tested=bool(row.tested))
                for row in models.itertuples()},
        spearman=dict(mean_rho=mean_rho, p_value=p_mean_rho, n_stimuli=int(ok.sum()),
                      n_significant=int((prho[ok] < 0.05).sum()), shifts_per_stimulus=int(len(shifts)), grid=grid,
                      alternative="greater"),
        peaks=dict(hit_rate=float(hit[has_peaks].mean()) if has_peaks.any() else None,
                   chance=float(chance[sidx][has_peaks].mean()) if has_peaks.any() else None,
                   n_clicks=int(has_peaks.sum()), excess_test=peak_test),
        auc=dict(value=float(pct.mean()) if U else None, test_vs_half=auc_test),
        concave=dict(click_share=float(concave_click.mean()) if U else None,
                     length_share=float(concave_len[sidx].mean()) if U else None,
                     convex_click_share=float(convex_click.mean()) if U else None,
                     convex_length_share=float(convex_len[sidx].mean()) if U else None,
                     excess_test=conc_test),
        params=dict(
            n=int(npts), model=first["model"], A=first.get("A"), b=first.get("b"), units=first.get("units"),
            coords=coords, scale=float(scale),
            tolerance=dict(px=tolerance, rule=tol_rule),
            bandwidth=dict(px=bandwidth, rule=f"{bandwidth:g} px" if bandwidth else
                           f"{_BANDWIDTH_FRACTION:g} x perimeter (kernel sd in arc length)"),
            peak_tolerance=dict(px=peak_tolerance, rule=f"{peak_tolerance:g} px" if peak_tolerance else
                                f"{_PEAK_FRACTION:g} x perimeter (arc length each side)"),
            permutations=int(permutations), grid=int(grid), seed=int(seed), level=float(level),
            group_simulations=int(group_simulations),
            click_sd=click_sd,
            choice_model="p(j) = exp(beta z_j) / sum_i exp(beta z_i) over the n points; z = standardised surprisal"
            + ("" if click_sd is None else f"; observed through Gaussian error of sd {click_sd:g} px along the contour"),
        ),
        warnings=[],
    )
    if U == 0:
        summary["warnings"].append("no usable clicks: every row was excluded; see clicks.csv for the reasons")
    if constant.any():
        summary["warnings"].append(
            f"{int(constant.sum())} stimulus/stimuli with constant surprisal (e.g. circles): z = 0, no information")
    profiles = dict(t=gt, density=dens, z=zgrid, ids=ids)
    return Analysis(out, per_s, per_p, models, _jsonable(summary), predictions, profiles, stimset)


def _jsonable(obj):
    """NaN/inf -> None and numpy scalars -> Python, recursively."""
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj


# --------------------------------------------------------------------- writing
def check_output_dir(out, force=False):
    """Raise `InputError` if `out` exists (unless `force`), is not a directory, or cannot be created."""
    out = Path(out)
    if out.exists():
        if not out.is_dir():
            raise InputError(f"{out}: exists and is not a directory")
        if any(out.iterdir()) and not force:
            raise InputError(f"{out}: directory exists and is not empty; choose another -o or pass --force")
    # found before the analysis runs, not after it
    anc = out.parent
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    if anc.exists() and not anc.is_dir():
        raise InputError(f"{out}: cannot be created, {anc} is not a directory")
    if anc.is_dir() and not os.access(anc, os.W_OK | os.X_OK):
        raise InputError(f"{out}: cannot be created, no permission to write in {anc}")


def write_analysis(analysis, out, figures=True, force=False, inputs=None):
    """Write the outputs of an analysis into directory `out`, all or nothing.

    Parameters
    ----------
    analysis : Analysis
    out : str or Path
        Output directory; created (with its parents). If it exists and is not
        empty it is replaced only with ``force=True``.
    figures : bool
        Draw the figures (the slowest part); without them ``report.html``
        still holds the tables.
    inputs : dict, optional
        Recorded in ``summary.json`` (e.g. the input paths as given).

    Returns
    -------
    Path
        `out`.
    """
    from stimuli import __version__
    from stimuli.io import atomic_write, write_table

    out = Path(out)
    check_output_dir(out, force)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    except OSError as exc:
        raise InputError(f"{out}: cannot be created ({exc.strerror or exc})") from None
    try:
        write_table(analysis.clicks, tmp / "clicks.csv")
        write_table(analysis.per_stimulus, tmp / "per_stimulus.csv")
        write_table(analysis.per_participant, tmp / "per_participant.csv")
        write_table(analysis.models, tmp / "models.csv")
        summary = dict(analysis.summary)
        summary["version"] = __version__
        if inputs:
            summary["inputs"] = {k: str(v) for k, v in inputs.items()}
        images = []
        if figures:
            from . import plots

            (tmp / "figures").mkdir()
            for name, png in plots.all_figures(analysis):
                with atomic_write(tmp / "figures" / name, "wb") as fh:
                    fh.write(png)
                images.append((name, png))
        summary["figures"] = [f"figures/{name}" for name, _ in images]
        with atomic_write(tmp / "summary.json", "w") as fh:
            json.dump(summary, fh, indent=2, sort_keys=True, allow_nan=False)
            fh.write("\n")
        with atomic_write(tmp / "report.html", "w") as fh:
            fh.write(_html(analysis, summary, images))
        os.chmod(tmp, 0o755)
        _swap_into_place(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out


def _swap_into_place(tmp, out):
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=out.parent))
        os.rmdir(old)
        os.replace(out, old)
        try:
            os.replace(tmp, out)
        except BaseException:
            os.replace(old, out)
            raise
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(tmp, out)


def _fmt(v, digits=4):
    if v is None:
        return "n/a"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def _html(analysis, summary, images):
    import base64
    import html

    s = summary
    g = s["group"]
    esc = html.escape
    rows = [
        ("clicks", s["n_clicks"]), ("used", s["n_used"]), ("excluded", s["n_excluded"]),
        ("participants (with a used click)", f"{s['n_participants']} ({s['n_participants_used']})"),
        ("stimuli (clicked)", f"{s['n_stimuli']} ({s['n_stimuli_clicked']})"),
        ("beta_hat (pooled ML)", f"{_fmt(s['beta_hat'])}, {s['beta_ci_method']} CI "
                                 f"[{_fmt(s['beta_ci'][0])}, {_fmt(s['beta_ci'][1])}], profile CI "
                                 f"[{_fmt(s['beta_profile_ci'][0])}, {_fmt(s['beta_profile_ci'][1])}]"),
        ("group test", f"{g['test']}: t = {_fmt(g['statistic'])} ({g['n']} participants), "
                       f"p = {_fmt(g['p_value'])} (one-sided, greater; t distribution with {g['df']} df "
                       f"would give {_fmt(g['p_value_parametric'])}), d_z = {_fmt(g['effect_size'])}, "
                       f"mean = {_fmt(g['mean'])}"),
        ("items test", f"per-stimulus mean z: t = {_fmt(s['by_stimulus']['statistic'])} "
                       f"({s['by_stimulus']['n']} stimuli), Monte Carlo p = {_fmt(s['by_stimulus']['p_value'])} "
                       f"(one-sided)"),
        ("Spearman (density vs surprisal)", f"mean rho = {_fmt(s['spearman']['mean_rho'])}, circular-shift p = "
                                            f"{_fmt(s['spearman']['p_value'])}; {s['spearman']['n_significant']} of "
                                            f"{s['spearman']['n_stimuli']} stimuli p < 0.05"),
        ("peak hit rate vs chance", f"{_fmt(s['peaks']['hit_rate'])} vs {_fmt(s['peaks']['chance'])}"),
        ("AUC (surprisal at clicks vs all points)", _fmt(s["auc"]["value"])),
        ("concave share: clicks vs length", f"{_fmt(s['concave']['click_share'])} vs "
                                            f"{_fmt(s['concave']['length_share'])}"),
    ]
    table = "\n".join(f"<tr><th>{esc(k)}</th><td>{esc(str(v))}</td></tr>" for k, v in rows)
    excl = "\n".join(f"<tr><th>{esc(k)}</th><td>{v}</td></tr>" for k, v in s["exclusions"].items())
    models = analysis.models.to_html(index=False, float_format=lambda x: f"{x:.6g}", border=0)
    per_s = analysis.per_stimulus.head(500).to_html(index=False, float_format=lambda x: f"{x:.4g}", border=0)
    per_p = analysis.per_participant.head(500).to_html(index=False, float_format=lambda x: f"{x:.4g}", border=0)
    figs = "\n".join(
        f'<figure><img alt="{esc(name)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'
        f"<figcaption>{esc(name)}</figcaption></figure>"
        for name, png in images
    )
    warn = "".join(f"<p class=warn>{esc(w)}</p>" for w in s.get("warnings", []))
    params = esc(json.dumps(s["params"], indent=1, sort_keys=True))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>attneave analysis</title>
<style>
body {{ font-family: sans-serif; margin: 2em; max-width: 1400px; }}
table {{ border-collapse: collapse; margin-bottom: 1.5em; font-size: 90%; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 3px 8px; text-align: left; }}
img {{ max-width: 100%; }} .warn {{ color: #a00; }} pre {{ background: #f6f6f6; padding: 1em; }}
</style></head><body>
<h1>Clicks against predicted information</h1>
{warn}
<h2>Summary</h2><table>{table}</table>
<h2>Exclusions (rows kept in clicks.csv with their reason)</h2><table>{excl}</table>
<h2>Models</h2>{models}
<h2>Figures</h2>{figs or '<p>(figures not drawn)</p>'}
<h2>Per stimulus</h2>{per_s}
<h2>Per participant</h2>{per_p}
<h2>Parameters</h2><pre>{params}</pre>
</body></html>
"""
