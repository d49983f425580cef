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

from attneave.analysis.argnames import arg
from attneave.analysis.budget import choose_models, plan
from attneave.analysis.clicks.mapping import PREDICTORS, map_clicks, predict
from attneave.analysis.fitting import (
    degenerate_warnings,
    effect_size,
    group_tests,
    joint_fit,
    joint_warnings,
    model_table,
)
from attneave.analysis.models.design import design
from attneave.analysis.models.mixed import fit_mixed, moment_sds
from attneave.analysis.progress import Progress
from attneave.analysis.report.summary import build_summary, jsonable
from attneave.analysis.report.tables import (
    BANDWIDTH_FRACTION,
    PEAK_FRACTION,
    click_features,
    correlation,
    participant_table,
    stimulus_table,
)
from attneave.analysis.threads import one_blas_thread
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number

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


def analyze(clicks, stimset, n=None, model=None, coords="image", scale=1.0, tolerance=None, bandwidth=None,
            peak_tolerance=None, permutations=1000, grid=1024, seed=0, level=0.95, A=None, b=None,
            click_sd=None, predictions=None, group_simulations=1999, predictors=("surprisal",), length_unit=None,
            mixed=True, progress=None, models=None, quiet=False, workers=1):
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
        (:func:`attneave.analysis.models.mixed.fit_mixed`); False is
        `models` without ``mixed``.
    progress : bool, optional
        A progress bar on stderr (default: when stderr is a terminal).
        Every stage longer than about 2 s is written to stderr as a line as
        well, terminal or log (:class:`attneave.stimuli.progress.Stages`).
    models : str or sequence of str, optional
        The models to run, among :data:`attneave.analysis.budget.MODELS`
        (``choice,rivals,joint,blurred,mixed,group``; ``choice`` always
        runs). Default: all that fit in the memory available (one left out
        is recorded with the reason); a named model that does not fit is
        refused. ``summary["models_skipped"]`` says which were left out and
        why.
    quiet : bool
        No progress on stderr at all.
    workers : int
        Local processes for the predictions
        (:func:`attneave.analysis.clicks.mapping.predict`; the same result for
        any number). The stages after them run in this process.

    Returns
    -------
    Analysis

    Raises
    ------
    InputError
        A run that would not fit in the memory available (refused before
        any heavy allocation, naming the option to change: ``-n``,
        ``--grid`` or ``--models``); `clicks` that is no DataFrame with the four columns, a `stimset`
        that is no StimulusSet or stimulus-set directory, `predictions` that
        are no :func:`~attneave.analysis.clicks.mapping.predict` output for `stimset` or
        whose n, model, A, b or length unit differ from those given, any
        argument out of range; one line naming the parameter (the flag when
        ``attneave analyze`` called it).
    """

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
    workers = _whole("workers", workers, 1)
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
    chosen, named = choose_models(models)
    if not mixed:
        chosen.discard("mixed")
    n_used = n if predictions is None else next(iter(predictions.values())).n if predictions else 3
    run, skipped = plan(chosen, named, dict(
        n_stimuli=len(stimset.ids), n=n_used, n_clicks=len(clicks), grid=grid, permutations=permutations,
        n_participants=clicks["participant"].nunique(), n_predictors=len(predictors)))
    if click_sd is None:  # nothing to run or skip: the blurred fit is asked for by click_sd
        skipped.pop("blurred", None)
        run.discard("blurred")
    elif "blurred" not in run:
        click_sd = None  # the plain fit, as the summary records
    if "group" not in run:
        group_simulations = 0
    bar = Progress(progress, quiet=quiet)
    try:
        with one_blas_thread():  # many small matrices: see attneave.analysis.threads
            if predictions is None:
                bar.stage("predictions")
                total = max(len(stimset.ids), 1)
                made = [0]

                def advance(k):
                    made[0] += k
                    bar.sub(made[0] / total)

                predictions = predict(stimset, n=n, model=model, A=A, b=b, length_unit=length_unit,
                                      workers=workers, progress=advance)
            return _analyze(clicks, stimset, predictions, run, skipped, bar, coords, scale, tolerance, bandwidth,
                            peak_tolerance, permutations, grid, seed, level, click_sd, group_simulations, predictors)
    finally:
        bar.close()


def _analyze(clicks, stimset, predictions, run, skipped, bar, coords, scale, tolerance, bandwidth, peak_tolerance,
             permutations, grid, seed, level, click_sd, group_simulations, predictors):
    """The stages of :func:`analyze` after the arguments are checked and the predictions made."""
    import pandas as pd

    ids = list(stimset.ids)
    bar.stage("mapping clicks")
    mapped = map_clicks(clicks, predictions, coords=coords, scale=scale, tolerance=tolerance)
    used = ~mapped["excluded"].to_numpy()
    d = design(mapped, predictions, ids)
    bar.stage("choice models")
    models, main, pci, same = model_table(d, level, click_sd, rivals="rivals" in run)
    joint = joint_fit(d, predictors, level) if "joint" in run else {}
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
    summary["models_run"] = sorted(run - set(skipped))
    from attneave.analysis.clicks.drawn import drawn_summary  # fragments, dots, cat: what was shown

    summary["drawn_parts"] = drawn_summary(predictions, mapped)
    summary["models_skipped"] = dict(sorted(skipped.items()))
    if "mixed" in run:
        bar.stage("mixed model")
        # the optimiser starts from the spread of the per-unit slopes: fewer steps than from a fixed guess
        sds = [moment_sds(t["beta_hat"].where(~t["beta_at_bound"].astype(bool)), t["beta_se"]) for t in (per_p, per_s)]
        m = summary["mixed"] = fit_mixed(d.Z, d.sidx, d.pidx, d.j, d.G, level=level, start=main["beta"], start_sd=sds)
        if d.U and not m["estimable"]:
            summary["warnings"].append(m["note"])
        elif d.U and not m["converged"]:
            summary["warnings"].append("the mixed model's optimiser did not report convergence: treat its "
                                       "estimates as doubtful")
    elif skipped.get("mixed", "").startswith("left out"):
        summary["warnings"].append(f"the mixed model was {skipped['mixed']}")
    summary["warnings"] += list(getattr(stimset, "warnings", ())) + degenerate_warnings(d, main, tests)
    summary["warnings"] += joint_warnings(joint, main)
    from attneave.analysis.clicks.exclusions import exclusion_report

    excluded = exclusion_report(out)  # here, not only in the command: a library call is told as well
    if excluded:
        summary["warnings"].append(excluded)
    profiles = dict(t=corr["t"], density=corr["density"], z=corr["z"], ids=ids)
    return Analysis(out, per_s, per_p, models, jsonable(summary), predictions, profiles, stimset)


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
