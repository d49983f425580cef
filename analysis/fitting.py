"""The model-fitting stage of :func:`attneave.analysis.analyze.analyze`.

Each function builds one table or one block of the summary from the design
(:func:`attneave.analysis.models.design.design`): the choice models
(:func:`model_table`, :func:`joint_fit`), the effect size
(:func:`effect_size`), the group tests (:func:`group_tests`), and the
warnings for designs too small or too extreme for some results to mean what
they seem to.
"""

from __future__ import annotations

import numpy as np

from attneave.analysis.clicks.mapping import PREDICTORS
from attneave.analysis.models.blurred import fit_beta_blurred
from attneave.analysis.models.choice import fit_beta, fit_choice, profile_ci
from attneave.analysis.models.design import mean_by
from attneave.analysis.models.effect import TOP_FRACTION, top_share, top_weights
from attneave.analysis.models.group import group_test, mean_z_nulls, mean_z_test

__all__ = ["distinct_predictors", "model_table", "joint_fit", "effect_size", "group_tests", "MIN_CLICKS",
           "degenerate_warnings", "joint_warnings"]


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


def model_table(d, level=0.95, click_sd=None, rivals=True):
    """The pooled choice model fitted with each distinct predictor alone, and uniform clicking.

    With `rivals` False only the tested prediction (surprisal) and uniform clicking.

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

    kept, same = distinct_predictors(d.Zs, PREDICTORS if rivals else ["surprisal"])
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
