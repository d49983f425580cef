"""The analysis of a click file against a stimulus set.

:func:`analyze` maps every click (:mod:`attneave.analysis.clicks.mapping`), indexes the used
ones once (:func:`attneave.analysis.models.design.design`) and builds each result from a
small function that returns one table or one block of the summary: the
choice models (:func:`model_table`, :func:`joint_fit`), the effect size
(:func:`effect_size`), the participants and stimuli
(:mod:`attneave.analysis.report.tables`), the group tests (:func:`group_tests`), the mixed
model (:func:`attneave.analysis.models.mixed.fit_mixed`) and the summary
(:mod:`attneave.analysis.report.summary`). The outputs are written by
:func:`attneave.analysis.report.outputs.write_analysis`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number

from attneave.analysis.argnames import arg
from attneave.analysis.models.blurred import fit_beta_blurred
from attneave.analysis.models.choice import fit_beta, fit_choice, profile_ci
from attneave.analysis.models.design import design, mean_by
from attneave.analysis.models.effect import TOP_FRACTION, top_share, top_weights
from attneave.analysis.models.group import group_test, mean_z_nulls, mean_z_test
from attneave.analysis.clicks.mapping import PREDICTORS, map_clicks, predict
from attneave.analysis.models.mixed import fit_mixed
from attneave.analysis.progress import Progress
from attneave.analysis.report.summary import build_summary, jsonable
from attneave.analysis.report.tables import BANDWIDTH_FRACTION, PEAK_FRACTION, click_features, correlation, participant_table, stimulus_table

__all__ = ["Analysis", "analyze", "model_table", "joint_fit", "effect_size", "group_tests", "DEFAULTS"]

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


# Bounds of the size and scale arguments: far beyond any real design, and
# small enough that no argument can ask for gigabytes or overflow a float.
MAX_POINTS = 100_000  # -n: points per contour
MAX_REPLICATES = 100_000  # --permutations, --group-simulations
MAX_GRID = 65_536  # --grid
MAX_PX = 1e6  # --tolerance, --bandwidth, --peak-tolerance, --click-sd (px)
MIN_CLICK_SD = 1e-3  # px; less is no localisation error at all


def _positive(name, value, allow_none=True, lo=None, hi=MAX_PX):
    name = arg(name)
    if value is None and allow_none:
        return None
    v = as_number(value, name, gt=0)
    if (lo is not None and v < lo) or v > hi:
        raise InputError(f"{name} must be from {lo if lo is not None else 0:g} to {hi:g} px, got {value!r}")
    return v


def _whole(name, value, minimum, maximum=None):
    name = arg(name)
    try:  # the one rule for integers (attneave.stimuli.validate), in this module's words
        value = as_int(value, name, lo=minimum)
    except InputError:
        raise InputError(f"{name} must be a whole number >= {minimum}, got {value!r}") from None
    if maximum is not None and value > maximum:
        raise InputError(f"{name} must be at most {maximum:,}, got {value:,}")
    return value


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
        The fit of the tested prediction, surprisal (:func:`attneave.analysis.models.choice.fit_beta`).
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
    """The choice model with the predictors `names` fitted jointly (:func:`attneave.analysis.models.choice.fit_choice`).

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
    """Share of the used clicks on the top points by surprisal, chance and lift (:mod:`attneave.analysis.models.effect`).

    Clicks on stimuli with a constant prediction are left out. Returns the
    summary's dict and the per-stimulus shares.
    """
    W = top_weights(d.Z, fraction)
    live = ~d.constant[d.sidx]
    out = top_share(W, d.sidx[live], d.j[live], fraction)
    per_s = mean_by(d.sidx, d.S, W[d.sidx, d.j])
    per_s[d.constant] = np.nan
    return out, per_s


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


def analyze(clicks, stimset, n=None, model=None, coords="image", scale=1.0, tolerance=None, bandwidth=None,
            peak_tolerance=None, permutations=1000, grid=1024, seed=0, level=0.95, A=None, b=None,
            click_sd=None, predictions=None, group_simulations=1999, predictors=("surprisal",), length_unit=None,
            mixed=True, progress=None):
    """Analyse clicks against the information predicted along the contours.

    Parameters
    ----------
    clicks : pandas.DataFrame
        Columns ``participant, stimulus_id, x, y`` (text or numbers) and any
        others (kept), e.g. from :func:`attneave.analysis.clicks.read.read_clicks`.
    stimset : StimulusSet, str or Path
        From :func:`attneave.stimuli.stimulus_set.read_stimulus_set`, or the
        directory to read it from.
    n : int, optional
        Equally spaced points per contour for the prediction (default 100;
        with `predictions`, theirs).
    model : {'paper', 'vonmises'}, optional
        Form of the surprisal model (both give the same standardised z;
        default 'paper'; with `predictions`, theirs).
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
    A, b : float, optional
        Parameters of the surprisal model (default: A = 0.25, b the
        model's default; with `predictions`, theirs).
    click_sd : float, optional
        Localisation error of clicks along the contour (sd in px). When
        given, the pooled fits use the choice model observed through that
        error (:func:`attneave.analysis.models.blurred.fit_beta_blurred`); otherwise, and
        always for the per-participant and per-stimulus betas, the plain
        model, whose beta_hat is attenuated by click noise.
    predictions : dict, optional
        Precomputed :func:`attneave.analysis.clicks.mapping.predict` output for `stimset`.
        Its n, model, A, b and length unit are the analysis's: leave those
        arguments out (None), or give the same values; a different value
        is refused rather than ignored.
    group_simulations : int
        Monte Carlo replicates R of the null of the group test and the items
        test (:func:`attneave.analysis.models.group.mean_z_test`). The smallest possible p is
        ``1 / (1 + R)``; 0 skips the simulation (p-values None; the
        parametric ones remain).
    predictors : sequence of str
        Predictors fitted jointly (:func:`joint_fit`), among
        :data:`attneave.analysis.clicks.mapping.PREDICTORS`; e.g. ``("surprisal",
        "concavity")`` asks whether concavity adds anything beyond surprisal.
    length_unit : str, optional
        Unit of arc length of the surprisal model, passed to
        :func:`attneave.stimuli.geometry.information.surprisal` when given (its
        default otherwise); recorded in the summary.
    mixed : bool
        Fit the mixed conditional logit with crossed random slopes
        (:func:`attneave.analysis.models.mixed.fit_mixed`).
    progress : bool, optional
        A progress bar on stderr (default: when stderr is a terminal). Where
        there is no bar and there are 100,000 clicks or more, each stage is
        written to stderr as one line instead.

    Returns
    -------
    Analysis

    Raises
    ------
    InputError
        `clicks` that is no DataFrame with the four columns, a `stimset`
        that is no StimulusSet or stimulus-set directory, `predictions` that
        are no :func:`~attneave.analysis.clicks.mapping.predict` output for `stimset` or
        whose n, model, A, b or length unit differ from those given, any
        argument out of range; one line naming the parameter (the flag when
        ``attneave analyze`` called it).
    """
    import pandas as pd

    from attneave.analysis.clicks.mapping import check_clicks, check_predictions

    tolerance = _positive("tolerance", tolerance)
    bandwidth = _positive("bandwidth", bandwidth)
    peak_tolerance = _positive("peak_tolerance", peak_tolerance)
    click_sd = _positive("click_sd", click_sd, lo=MIN_CLICK_SD)
    scale = _positive("scale", scale, allow_none=False, hi=np.inf)
    if n is not None:
        n = _whole("n", n, 3, MAX_POINTS)
    permutations = _whole("permutations", permutations, 0, MAX_REPLICATES)
    group_simulations = _whole("group_simulations", group_simulations, 0, MAX_REPLICATES)
    grid = _whole("grid", grid, 8, MAX_GRID)
    seed = _whole("seed", seed, 0, 2**63 - 1)
    level = as_number(level, arg("level"))
    if not 0 < level < 1:
        raise InputError(f"{arg('level')} must be in (0, 1), got {level!r}")
    predictors = _predictor_names(predictors)
    check_clicks(clicks)
    stimset = _stimulus_set(stimset)
    if predictions is None:
        n = DEFAULTS["n"] if n is None else n
        model = DEFAULTS["model"] if model is None else model
        A = 0.25 if A is None else A
    else:
        _same_as_predictions(check_predictions(predictions), predictions, stimset,
                             dict(n=n, model=model, A=A, b=b, length_unit=length_unit))
    # a run of 100,000 clicks or more takes long enough to report its stages in a log too
    bar = Progress(progress, announce=len(clicks) >= 100_000)
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
    summary = build_summary(d, mapped, main, pci, models, tests, corr, feats, predictions, level,
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
        m = summary["mixed"] = fit_mixed(d.Z, d.sidx, d.pidx, d.j, d.G, level=level, start=main["beta"])
        if d.U and not m["estimable"]:
            summary["warnings"].append(m["note"])
        elif d.U and not m["converged"]:
            summary["warnings"].append("the mixed model's optimiser did not report convergence: treat its "
                                       "estimates as doubtful")
    summary["warnings"] += list(getattr(stimset, "warnings", ())) + degenerate_warnings(d, main, tests)
    summary["warnings"] += joint_warnings(joint, main)
    from attneave.analysis.clicks.exclusions import exclusion_report

    excluded = exclusion_report(out)  # here, not only in the command: a library call is told as well
    if excluded:
        summary["warnings"].append(excluded)
    bar.close()
    profiles = dict(t=corr["t"], density=corr["density"], z=corr["z"], ids=ids)
    return Analysis(out, per_s, per_p, models, jsonable(summary), predictions, profiles, stimset)


#: Fewest used clicks for which the pooled fit's Wald interval is taken at face value.
MIN_CLICKS = 10


def degenerate_warnings(d, main, tests):
    """Warnings for a design too small or too extreme for some results to mean what they seem to.

    Parameters
    ----------
    d : Design
    main : dict
        The pooled fit (:func:`attneave.analysis.models.choice.fit_beta`).
    tests : dict
        From :func:`group_tests`.

    Returns
    -------
    list of str
        One sentence each: too few used clicks for the pooled interval, a
        pooled beta at its search bound (near-separation), fewer than 2
        participants (or stimuli) for the group (items) test.
    """
    out = []
    if d.U == 0:
        return out
    if d.U < MIN_CLICKS:
        out.append(f"only {d.U} used click{'s' if d.U != 1 else ''}: the pooled beta_hat and its interval rest on "
                   f"too few clicks (fewer than {MIN_CLICKS}) to be trusted")
    if main.get("at_bound"):
        out.append(f"the pooled beta_hat ({main['beta']:g}) is the bound of its search, not an estimate: the "
                   "likelihood keeps increasing past it (near-separation: clicks almost only on the most, or least, "
                   "surprising points); report the effect (top share) and the group test")
    for key, unit, test in (("group", "participants", "group test"), ("by_stimulus", "stimuli", "items test")):
        n = tests[key].get("n") or 0
        if n < 2:
            out.append(f"the {test} needs at least 2 {unit} with usable clicks and has {n}: its t and p are "
                       "not computed")
    return out


def joint_warnings(joint, main):
    """A warning when the joint fit cannot tell some of its predictors apart.

    Predictors whose standardised values are constant or collinear on the
    clicked stimuli (``concavity`` on convex shapes; ``abs_curvature`` and
    ``convexity`` on shapes without concavities)
    have a singular information matrix: their coefficients are not identified
    and come without SE or interval, which the table alone does not explain.

    Parameters
    ----------
    joint : dict
        From :func:`joint_fit`.
    main : dict
        The pooled fit of surprisal alone (no warning when it has no information at all).

    Returns
    -------
    list of str
    """
    if len(joint) < 2 or not np.isfinite(main.get("beta", np.nan)):
        return []
    bad = [k for k, v in joint.items() if not v["at_bound"] and not np.isfinite(v["se"])]
    if not bad:
        return []
    return [f"the joint fit cannot tell {', '.join(bad)} apart from the other predictors: their standardised "
            "values are constant or collinear on the clicked stimuli, so their coefficients are not identified (no "
            "SE or interval); fit them one at a time (models.csv) or drop one"]


def _stimulus_set(stimset):
    """A StimulusSet, read from its directory when `stimset` is a path."""
    import os

    from attneave.stimuli.stimulus_set import StimulusSet, read_stimulus_set

    if isinstance(stimset, (str, os.PathLike)) and not isinstance(stimset, bytes):
        return read_stimulus_set(stimset)
    if not isinstance(stimset, StimulusSet):
        raise InputError(f"stimset: expected a StimulusSet or a stimulus-set directory, got {type(stimset).__name__}")
    return stimset


def _same_as_predictions(ids, predictions, stimset, given):
    """Refuse predictions of other stimuli, or made with other parameters than those given."""
    if set(ids) != set(stimset.ids):
        other = sorted(set(ids) ^ set(stimset.ids))
        raise InputError(f"predictions: they are not those of this stimulus set (ids differ: "
                         f"{', '.join(map(str, other[:5]))}{', ...' if len(other) > 5 else ''})")
    if not ids:
        return
    used = predictions[ids[0]].result.params
    for key, value in given.items():
        have = used.get(key)
        if value is None or have is None:
            continue
        same = value == have if isinstance(value, str) or isinstance(have, str) else np.isclose(value, have)
        if not same:
            raise InputError(f"{arg(key)} is {value!r} but the predictions were made with {key} = {have!r}: "
                             f"leave {arg(key)} out to use theirs, or predict again with {key}={value!r}")


def _predictor_names(names):
    if isinstance(names, str):
        names = [v.strip() for v in names.split(",") if v.strip()]
    names = list(names)
    bad = [k for k in names if k not in PREDICTORS]
    if bad or not names or len(set(names)) != len(names):
        raise InputError(f"{arg('predictors')} must be distinct names among {','.join(PREDICTORS)}, got {','.join(names)!r}")
    return names
