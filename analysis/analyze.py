"""The analysis of a click file against a stimulus set.

:func:`analyze` maps every click (:mod:`analysis.mapping`), indexes the used
ones once (:class:`Design`) and builds each result from a small function
that returns one table or one block of the summary: the choice models
(:func:`model_table`), the participants (:func:`participant_table`), the
stimuli (:func:`stimulus_table`), and the group tests
(:func:`group_tests`). The outputs are written by
:func:`analysis.report.write_analysis`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from stimuli.errors import InputError
from stimuli.io import as_number

from .blurred import fit_beta_blurred
from .choice import fit_beta, fit_choice, profile_ci
from .circular import circular_kde, circular_spearman, mean_rho_null, peak_chance, peak_hits, shift_indices
from .effect import TOP_FRACTION, top_share, top_weights
from .group import group_test, mean_z_nulls, mean_z_test
from .mixed import fit_mixed
from .mapping import DEFAULT_TOLERANCE_FRACTION, PREDICTORS, REASONS, map_clicks, predict

__all__ = ["Analysis", "Design", "analyze", "model_table", "participant_table", "stimulus_table", "group_tests",
           "DEFAULTS", "jsonable"]

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
BANDWIDTH_FRACTION = 0.02
PEAK_FRACTION = 0.02


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


@dataclass
class Design:
    """The used clicks as indices into stimuli, participants and points.

    ``sidx, pidx, j`` (U,) stimulus, participant and point of each used click,
    ``t`` its arc position, ``zc`` the z of the tested prediction there;
    ``Z`` (S, n) that prediction standardised, ``Zs`` every predictor's z;
    ``Ms`` (S,) clicks per stimulus, ``Mgs`` (G, S) per participant and
    stimulus, ``Cs`` (S, n) per stimulus and point.
    """

    ids: list
    participants: list
    sidx: np.ndarray
    pidx: np.ndarray
    t: np.ndarray
    j: np.ndarray
    zc: np.ndarray
    perim: np.ndarray
    npts: int
    Z: np.ndarray
    Zs: dict
    sign: np.ndarray
    Ms: np.ndarray
    Mgs: np.ndarray
    Cs: np.ndarray

    @property
    def S(self):
        return len(self.ids)

    @property
    def G(self):
        return len(self.participants)

    @property
    def U(self):
        return len(self.t)

    @property
    def constant(self):
        return np.all(self.Z == 0, axis=1)


def _positive(name, value, allow_none=True):
    if value is None and allow_none:
        return None
    return as_number(value, name, gt=0)


def _whole(name, value, minimum):
    if not (isinstance(value, (int, np.integer)) and value >= minimum):
        raise InputError(f"{name} must be a whole number >= {minimum}, got {value!r}")
    return int(value)


def mean_by(index, size, values, mask=None):
    """Mean of `values` per group `index` (NaN for a group without values)."""
    w = np.ones(len(index)) if mask is None else mask.astype(float)
    num = np.bincount(index, weights=values * w, minlength=size)
    den = np.bincount(index, weights=w, minlength=size)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / den, np.nan)


def design(mapped, predictions, ids):
    """Index the used clicks of `mapped` (from :func:`map_clicks`)."""
    import pandas as pd

    used = ~mapped["excluded"].to_numpy()
    sindex = {s: i for i, s in enumerate(ids)}
    part_all = mapped["participant"].to_numpy(dtype=object)
    participants = sorted(set(pd.unique(part_all)) - {""})
    S, G = len(ids), len(participants)
    sidx = mapped["stimulus_id"].map(sindex).to_numpy()[used].astype(np.int64)
    pidx = pd.Categorical(part_all[used], categories=participants).codes.astype(np.int64)
    j = mapped["point"].to_numpy()[used].astype(np.int64)
    npts = predictions[ids[0]].n
    return Design(
        ids=ids, participants=participants, sidx=sidx, pidx=pidx, t=mapped["t"].to_numpy()[used], j=j,
        zc=mapped["z"].to_numpy()[used], perim=np.array([predictions[s].perimeter for s in ids]), npts=npts,
        Z=np.stack([predictions[s].z["surprisal"] for s in ids]),
        Zs={k: np.stack([predictions[s].z[k] for s in ids]) for k in PREDICTORS},
        sign=np.stack([predictions[s].sign for s in ids]),
        Ms=np.bincount(sidx, minlength=S).astype(float),
        Mgs=np.bincount(pidx * S + sidx, minlength=G * S).reshape(G, S).astype(float),
        Cs=np.bincount(sidx * npts + j, minlength=S * npts).reshape(S, npts).astype(float),
    )


def distinct_predictors(Zs, names):
    """The predictors of `names` whose z differs from every earlier one's on some stimulus.

    Returns the kept names and, for each dropped one, the name it duplicates.
    """
    kept, same = [], {}
    for k in names:
        twin = next((q for q in kept if np.allclose(Zs[k], Zs[q], rtol=0, atol=1e-9)), None)
        if twin is None:
            kept.append(k)
        else:
            same[k] = twin
    return kept, same


def model_table(d, level=0.95, click_sd=None):
    """The pooled choice model fitted with each distinct predictor alone, and uniform clicking.

    Returns
    -------
    models : pandas.DataFrame
        ``model, tested, n_params, beta_hat, se, ci_low, ci_high, loglik,
        at_bound, aic, delta_aic``; one row per predictor whose z differs
        from the others' (see :func:`distinct_predictors`).
    main : dict
        The fit of the tested prediction, surprisal (:func:`analysis.choice.fit_beta`).
    profile : (low, high)
        Its profile-likelihood interval (NaN with `click_sd`).
    same : dict
        Predictors left out because they equal another one.
    """
    import pandas as pd

    kept, same = distinct_predictors(d.Zs, PREDICTORS)
    rows, fits = [], {}
    for k in kept:
        if click_sd is None:
            Ak = d.Zs[k][d.sidx, d.j].sum() if d.U else 0.0
            f = fit_beta(d.Zs[k], Ak, d.Ms, level=level)
        else:
            f = fit_beta_blurred(d.Zs[k], d.Cs, click_sd / (d.perim / d.npts), level=level)
        fits[k] = f
        rows.append(dict(model=k, tested=k == "surprisal", n_params=1, beta_hat=f["beta"], se=f["se"],
                         ci_low=f["ci_low"], ci_high=f["ci_high"], loglik=f["loglik"], at_bound=f["at_bound"]))
    main = fits["surprisal"]
    rows.append(dict(model="uniform", tested=False, n_params=0, beta_hat=0.0, se=np.nan, ci_low=np.nan,
                     ci_high=np.nan, loglik=main["loglik0"], at_bound=False))
    models = pd.DataFrame(rows)
    models["aic"] = 2 * models["n_params"] - 2 * models["loglik"]
    models["delta_aic"] = models["aic"] - models["aic"].min()
    pci = (profile_ci(d.Z, d.zc.sum(), d.Ms, main["beta"], level=level) if d.U and click_sd is None
           else (np.nan, np.nan))
    return models, main, pci, same


def joint_fit(d, names, level=0.95):
    """The choice model with the predictors `names` fitted jointly (:func:`analysis.choice.fit_choice`).

    Returns a dict name -> ``coef, se, ci_low, ci_high, lr_stat, lr_p,
    at_bound``; the likelihood-ratio test of each predictor compares the
    model with all of them to the model without it.
    """
    X = np.stack([d.Zs[k] for k in names], axis=2)
    A = X[d.sidx, d.j].sum(axis=0) if d.U else np.zeros(len(names))
    f = fit_choice(X, A, d.Ms, names=names, level=level)
    return {k: dict(coef=f["coef"][i], se=f["se"][i], ci_low=f["ci_low"][i], ci_high=f["ci_high"][i],
                    lr_stat=f["lr_stat"][i], lr_p=f["lr_p"][i], at_bound=bool(f["at_bound"][i]))
            for i, k in enumerate(names)}


def effect_size(d, fraction=TOP_FRACTION):
    """Share of the used clicks on the top points by surprisal, chance and lift (:mod:`analysis.effect`).

    Clicks on stimuli with a constant prediction are left out. Returns the
    summary's dict and the per-stimulus shares.
    """
    W = top_weights(d.Z, fraction)
    live = ~d.constant[d.sidx]
    out = top_share(W, d.sidx[live], d.j[live], fraction)
    per_s = mean_by(d.sidx, d.S, W[d.sidx, d.j])
    per_s[d.constant] = np.nan
    return out, per_s


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
        n_stimuli=(d.Mgs > 0).sum(axis=1),
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

    S, ids = d.S, d.ids
    fs = fit_beta(d.Z, np.bincount(d.sidx, weights=d.zc, minlength=S), np.diag(d.Ms), level=level)
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


def group_tests(d, per_p, seed, group_simulations, level=0.95, progress=None):
    """The group (participants), items (stimuli) and descriptive tests of the summary."""
    # the Monte Carlo nulls of the group and items tests: one stream of their own, so that the
    # correlation's null does not change with them; one set of draws serves both groupings
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(6,)).spawn(1)[0])
    R = int(group_simulations)
    nulls = mean_z_nulls(d.Z, d.sidx, {"participant": (d.pidx, d.G), "stimulus": (d.sidx, d.S)}, R, rng,
                         observed_z=d.zc, progress=progress)
    g = mean_z_test(d.Z, d.sidx, d.pidx, d.zc, n_units=d.G, level=level, null=nulls["participant"])
    g["test"] = f"one-sample t statistic of per-participant mean z, Monte Carlo null under uniform clicking (R = {R})"
    g["effect"] = "per-participant mean z (standardised surprisal) at used clicks; 0 under uniform clicking"
    g["null"] = ("each used click keeps its stimulus and participant and is redrawn uniformly among the "
                 "stimulus's n points (beta = 0); p = (1 + #{null t >= t}) / (1 + R), one-sided (greater)")
    s = mean_z_test(d.Z, d.sidx, d.sidx, d.zc, n_units=d.S, level=level, null=nulls["stimulus"])
    s["test"] = f"one-sample t statistic of per-stimulus mean z, Monte Carlo null under uniform clicking (R = {R})"
    s["effect"] = "per-stimulus mean z at used clicks (items analysis; stimuli with constant prediction left out)"
    bound = per_p["beta_at_bound"].astype(bool).to_numpy() if d.G else np.zeros(0, bool)
    b = group_test(per_p["beta_hat"].to_numpy()[~bound] if d.G else np.empty(0), level=level)
    b["effect"] = "per-participant ML beta (participants whose beta hit the search bound left out)"
    b["n_at_bound"] = int(bound.sum())
    # ML betas from a participant's few clicks are far from normal (and those at the bound are
    # left out), so the t distribution does not hold here: descriptive only, no p_value
    b["p_value_parametric"] = b.pop("p_value")
    b["note"] = ("descriptive: the t distribution is not calibrated for per-participant betas (measured "
                 "false-positive rates 0.19-0.50 at alpha = 0.05 under uniform clicking on polygons); "
                 "the test of the effect is 'group'")
    auc = group_test(per_p["auc"].to_numpy() - 0.5, level=level)
    peak = group_test((per_p["peak_hit_rate"] - per_p["peak_chance"]).to_numpy(), level=level)
    ci = per_p.attrs.get("concave_informative", np.ones(d.G, bool))
    conc = group_test(np.where(ci, (per_p["concave_click_share"] - per_p["concave_length_share"]).to_numpy(),
                               np.nan), level=level)
    return dict(group=g, by_stimulus=s, participant_beta=b, auc=auc, peaks=peak, concave=conc)


def analyze(clicks, stimset, n=100, model="paper", coords="image", scale=1.0, tolerance=None, bandwidth=None,
            peak_tolerance=None, permutations=1000, grid=1024, seed=0, level=0.95, A=0.25, b=None,
            click_sd=None, predictions=None, group_simulations=1999, predictors=("surprisal",), length_unit=None,
            mixed=True, progress=None):
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
        Form of the surprisal model (both give the same standardised z).
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
        given, the pooled fits use the choice model observed through that
        error (:func:`analysis.blurred.fit_beta_blurred`); otherwise, and
        always for the per-participant and per-stimulus betas, the plain
        model, whose beta_hat is attenuated by click noise.
    predictions : dict, optional
        Precomputed :func:`analysis.mapping.predict` output (same n, model).
    group_simulations : int
        Monte Carlo replicates R of the null of the group test and the items
        test (:func:`analysis.group.mean_z_test`). The smallest possible p is
        ``1 / (1 + R)``; 0 skips the simulation (p-values None; the
        parametric ones remain).
    predictors : sequence of str
        Predictors fitted jointly (:func:`joint_fit`), among
        :data:`analysis.mapping.PREDICTORS`; e.g. ``("surprisal",
        "concavity")`` asks whether concavity adds anything beyond surprisal.
    length_unit : str, optional
        Unit of arc length of the surprisal model, passed to
        :func:`stimuli.geometry.information.surprisal` when given (its
        default otherwise); recorded in the summary.
    mixed : bool
        Fit the mixed conditional logit with crossed random slopes
        (:func:`analysis.mixed.fit_mixed`).
    progress : bool, optional
        A progress bar on stderr (default: when stderr is a terminal).

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
    permutations = _whole("--permutations", permutations, 0)
    group_simulations = _whole("--group-simulations", group_simulations, 0)
    grid = _whole("--grid", grid, 8)
    if not 0 < level < 1:
        raise InputError(f"level must be in (0, 1), got {level!r}")
    predictors = _predictor_names(predictors)
    bar = _Progress(progress)
    if predictions is None:
        bar.stage("predictions")
        predictions = predict(stimset, n=n, model=model, A=A, b=b, length_unit=length_unit)
    ids = list(stimset.ids)
    bar.stage("mapping clicks")
    mapped = map_clicks(clicks, predictions, coords=coords, scale=scale, tolerance=tolerance)
    used = ~mapped["excluded"].to_numpy()
    d = design(mapped, predictions, ids)
    bar.stage("choice models")
    models, main, pci, same = model_table(d, level, click_sd)
    joint = joint_fit(d, predictors, level)
    effect, top_by_stimulus = effect_size(d)

    bw_px = bandwidth * np.ones(d.S) if bandwidth is not None else BANDWIDTH_FRACTION * d.perim
    pk_px = peak_tolerance * np.ones(d.S) if peak_tolerance is not None else PEAK_FRACTION * d.perim
    pct = mapped["surprisal_percentile"].to_numpy()[used] / 100.0
    feats = click_features(d, predictions, pk_px)
    per_p = participant_table(d, mapped, pct, feats, level)
    bar.stage("correlations")
    corr = correlation(d, bw_px, grid, permutations, seed)
    per_s = stimulus_table(d, mapped, predictions, stimset, pct, feats, corr, bw_px, pk_px, level)
    per_s.insert(per_s.columns.get_loc("mean_z") + 1, "top_share", top_by_stimulus)

    out = mapped.copy()
    ph = pd.array([pd.NA] * len(out), dtype="Int64")
    ph[np.flatnonzero(used)] = feats["hit"].astype(int)
    out.insert(out.columns.get_loc("excluded"), "peak_hit", ph)

    bar.stage("Monte Carlo group and items tests")
    tests = group_tests(d, per_p, seed, group_simulations, level, progress=bar.sub)
    summary = _summary(d, mapped, main, pci, models, tests, corr, feats, predictions, level,
                       dict(coords=coords, scale=scale, tolerance=tolerance, bandwidth=bandwidth,
                            peak_tolerance=peak_tolerance, permutations=permutations, grid=grid, seed=seed,
                            group_simulations=group_simulations, click_sd=click_sd))
    summary["effect"] = effect
    summary["predictors"] = joint
    summary["predictors_note"] = ("fitted jointly: p(j) ~ exp(sum_k coef_k z_kj); lr_p tests each predictor "
                                  "against the model without it (chi-square, 1 df; clicks treated as independent)")
    summary["models_left_out"] = {k: f"same standardised values as {v}" for k, v in same.items()}
    summary["models_note"] = ("the von Mises form of surprisal is not a rival: after standardisation it equals the "
                              "paper's form; models.csv lists only predictors whose z differ")
    if mixed:
        bar.stage("mixed model")
        summary["mixed"] = fit_mixed(d.Z, d.sidx, d.pidx, d.j, d.G, level=level, start=main["beta"])
    bar.close()
    profiles = dict(t=corr["t"], density=corr["density"], z=corr["z"], ids=ids)
    return Analysis(out, per_s, per_p, models, jsonable(summary), predictions, profiles, stimset)


def _summary(d, mapped, main, pci, models, tests, corr, feats, predictions, level, p):
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


def _predictor_names(names):
    if isinstance(names, str):
        names = [v.strip() for v in names.split(",") if v.strip()]
    names = list(names)
    bad = [k for k in names if k not in PREDICTORS]
    if bad or not names or len(set(names)) != len(names):
        raise InputError(f"--predictors must be distinct names among {','.join(PREDICTORS)}, got {','.join(names)!r}")
    return names


class _Progress:
    """Stages of the analysis on a tqdm bar on stderr; `sub` reports a stage's own progress (0..1)."""

    def __init__(self, enabled):
        import sys

        from tqdm import tqdm

        self.bar = tqdm(total=1000, desc="analyze", file=sys.stderr, disable=None if enabled is None else not enabled,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}", leave=False)
        self.done = 0
        # share of the run each stage takes (measured on 1,000,000 clicks), so the bar moves evenly
        self.weights = {"predictions": 40, "mapping clicks": 250, "choice models": 100, "correlations": 60,
                        "Monte Carlo group and items tests": 450, "mixed model": 100}
        self.current = None

    def stage(self, name):
        self._finish()
        self.current = name
        self.start = self.done
        self.bar.set_description(f"analyze: {name}")

    def sub(self, fraction):
        self.bar.update(int(self.start + fraction * self.weights.get(self.current, 0)) - self.done)
        self.done = int(self.start + fraction * self.weights.get(self.current, 0))

    def _finish(self):
        if self.current is not None:
            self.sub(1.0)

    def close(self):
        self._finish()
        self.bar.close()


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
