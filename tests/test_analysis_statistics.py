"""Regression tests from an audit of the statistics and outputs of ``attneave analyze``."""

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.analyze import analyze
from attneave.analysis.clicks.mapping import PREDICTORS, predict
from attneave.analysis.models.blurred import fit_beta_blurred
from attneave.analysis.models.choice import BETA_BOUND, fit_beta, standardize
from attneave.analysis.report.html import render
from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set


@pytest.fixture(scope="module")
def circle_ellipse(tmp_path_factory):
    """A circle and an ellipse written to and read back from a stimulus-set directory.

    Writing rounds the contour coordinates (as any set read from files), which leaves the
    circle's curvature varying by ~1e-6 of its size.
    """
    d = tmp_path_factory.mktemp("circ")
    th = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    write_stimulus_set(d, {"circle": np.c_[100 + 50 * np.cos(th), 100 + 50 * np.sin(th)],
                           "ellipse": np.c_[100 + 70 * np.cos(th), 100 + 30 * np.sin(th)]}, size=(200, 200))
    ss = read_stimulus_set(d)
    return ss, predict(ss, n=100)


def _clicks(pred, sid, points, participant="P1"):
    """Clicks at the given point indices of stimulus `sid` (on the contour, image pixels)."""
    pr = pred[sid]
    xy = pr.contour.point_at(np.asarray(points, dtype=float) / pr.n)
    return pd.DataFrame(dict(participant=participant, stimulus_id=sid, x=xy[:, 0], y=xy[:, 1]))


def test_every_predictor_is_constant_on_a_circle_read_from_file(circle_ellipse):
    # old: abs_curvature, convexity and extremum_proximity standardised the circle's rounding
    # noise to sd 1, so every click on a circle counted against the rivals (not against surprisal)
    _, pred = circle_ellipse
    for k in PREDICTORS:
        assert not np.any(pred["circle"].z[k]), k
    # a real shape keeps its variation
    assert np.std(pred["ellipse"].z["abs_curvature"]) == pytest.approx(1.0)


def test_uniform_clicks_on_a_circle_do_not_change_the_model_comparison(circle_ellipse):
    ss, pred = circle_ellipse
    rng = np.random.default_rng(0)
    ell = pd.concat([_clicks(pred, "ellipse", rng.integers(0, 100, 30), f"P{p}") for p in range(3)])
    circ = pd.concat([_clicks(pred, "circle", rng.integers(0, 100, 30), f"P{p}") for p in range(3)])
    kw = dict(predictions=pred, group_simulations=0, permutations=0, mixed=False)
    a = analyze(ell, ss, **kw).models.set_index("model")["loglik"]
    b = analyze(pd.concat([ell, circ]), ss, **kw).models.set_index("model")["loglik"]
    # clicks on a stimulus without information cost every model the same: -log n each
    assert (b - a).to_numpy() == pytest.approx(np.full(len(a), -90 * np.log(100)), abs=1e-6)


def test_surprisal_percentile_of_a_constant_prediction_is_50(circle_ellipse):
    # old: the circle's raw surprisal, equal up to rounding, was ranked (percentiles 30 to 98)
    ss, pred = circle_ellipse
    a = analyze(_clicks(pred, "circle", np.arange(0, 100, 7)), ss, predictions=pred, group_simulations=0,
                permutations=0, mixed=False)
    assert np.all(a.clicks["surprisal_percentile"] == 50.0)
    assert a.per_stimulus.set_index("stimulus_id").loc["circle", "auc"] == 0.5


def test_fit_at_the_bound_has_no_se_or_interval():
    # old: a Wald interval around the bound, e.g. [12.6, 27.4], reaching past the bound itself
    Z = standardize(np.array([[0.0, 1.0, 2.0, 3.0, 10.0]]))
    f = fit_beta(Z, 6 * Z[0, 4], np.array([6.0]))
    assert f["at_bound"] and f["beta"] == BETA_BOUND
    assert np.isnan(f["se"]) and np.isnan(f["ci_low"]) and np.isnan(f["ci_high"])
    C = np.zeros((1, 5))
    C[0, 4] = 6
    for sd in (0.0, 0.1, 1.0):
        # old: L-BFGS-B stopped at beta ~ 10-13, not flagged, with an interval of +-1e5
        g = fit_beta_blurred(Z, C, sd)
        assert g["at_bound"] and g["beta"] == BETA_BOUND, sd
        assert np.isnan(g["se"]) and np.isnan(g["ci_low"]) and np.isnan(g["ci_high"])
    C2 = np.array([[1.0, 1.0, 1.0, 1.0, 2.0]])  # not separated: a finite estimate, as before
    g = fit_beta_blurred(Z, C2, 0.1)
    assert not g["at_bound"] and g["ci_low"] < g["beta"] < g["ci_high"]
    # an ordinary fit keeps its interval
    h = fit_beta(Z, Z[0].sum() + Z[0, 4], np.array([6.0]))
    assert not h["at_bound"] and h["ci_low"] < h["beta"] < h["ci_high"]


def test_pooled_fit_at_bound_in_summary_and_models(circle_ellipse):
    ss, pred = circle_ellipse
    top = int(np.argmax(pred["ellipse"].z["surprisal"]))
    a = analyze(_clicks(pred, "ellipse", [top] * 12), ss, predictions=pred, group_simulations=0,
                permutations=0, mixed=False)
    s = a.summary
    assert s["beta_at_bound"] and s["beta_se"] is None and s["beta_ci"] == [None, None]
    row = a.models.set_index("model").loc["surprisal"]
    assert row["at_bound"] and np.isnan(row["ci_low"]) and np.isnan(row["ci_high"])
    # the same through click localisation error (old: a Wald interval of about +-1800 around the bound)
    b = analyze(_clicks(pred, "ellipse", [top] * 12), ss, predictions=pred, group_simulations=0,
                permutations=0, mixed=False, click_sd=1.0).summary
    assert b["beta_at_bound"] and b["beta_ci"] == [None, None]
    assert any("bound of its search" in w for w in b["warnings"])


def test_report_uses_the_level_escapes_p_and_names_unclicked_stimuli(circle_ellipse):
    ss, pred = circle_ellipse
    top = np.argsort(pred["ellipse"].z["surprisal"])[-10:]
    rng = np.random.default_rng(1)
    clicks = pd.concat([_clicks(pred, "ellipse", rng.choice(top, 20), f"P{p}") for p in range(4)])
    a = analyze(clicks, ss, predictions=pred, group_simulations=1999, permutations=0, mixed=False, level=0.9)
    page = render(a, dict(a.summary, version="x", date="d"), [])
    assert "90% CI" in page and "95% CI" not in page
    # the circle was not clicked: no estimate, rather than an 'infinite SE'
    assert "n/a (no used clicks)" in page and "infinite SE" not in page
    # a p-value below .001 is written as text, not as the start of a tag
    assert "p &lt; .001" in page and "p < .001" not in page


def test_joint_fit_of_collinear_predictors_is_warned(circle_ellipse):
    # on a convex set abs_curvature and convexity are the same predictor: their joint coefficients
    # are not identified, which the table (coefficients without intervals) did not say
    ss, pred = circle_ellipse
    rng = np.random.default_rng(2)
    clicks = pd.concat([_clicks(pred, "ellipse", rng.integers(0, 100, 20), f"P{p}") for p in range(3)])
    kw = dict(predictions=pred, group_simulations=0, permutations=0, mixed=False)
    a = analyze(clicks, ss, predictors=("surprisal", "abs_curvature", "convexity"), **kw)
    assert any("not identified" in w and "convexity" in w for w in a.summary["warnings"])
    b = analyze(clicks, ss, predictors=("surprisal", "extremum_proximity"), **kw)
    assert not any("not identified" in w for w in b.summary["warnings"])


def test_a_library_call_is_told_when_most_clicks_are_excluded():
    # the ">20% excluded" warning was added by the command only: analyze() called from Python said
    # nothing about 3 of 4 clicks falling outside the image
    import tempfile

    th = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    d = tempfile.mkdtemp()
    write_stimulus_set(d, {"e": np.c_[50 + 30 * np.cos(th), 50 + 15 * np.sin(th)]}, size=(100, 100))
    clicks = pd.DataFrame(dict(participant=["p"] * 4, stimulus_id=["e"] * 4, x=["80", "500", "600", "700"],
                               y=["50", "50", "50", "50"]))
    res = analyze(clicks, read_stimulus_set(d), n=40, permutations=9, group_simulations=0)
    assert any(w.startswith("75% of the clicks (3 of 4) were excluded: outside_image 3")
               for w in res.summary["warnings"])
