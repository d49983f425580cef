"""Statistics of clicks along contours, simulated observers and recovery of their effect.

The expected values come from the mathematics, not from the code: a two-point
choice model has a closed-form ML estimate and Fisher information, a wrapped
normal density, Spearman's rho computed by scipy on rolled arrays, the
measure of a union of arcs, and the null distribution of a t-test.
"""

import numpy as np
import pytest
import scipy.stats
from hypothesis import given, settings
from hypothesis import strategies as st

from attneave.analysis.analyze import analyze
from attneave.analysis.clicks.mapping import map_clicks, predict
from attneave.analysis.models import blurred, choice, circular, group
from attneave.analysis.simulate.observers import power, simulate, simulate_indices
from attneave.stimuli import Contour
from attneave.stimuli.stimulus_set import StimulusSet


# --------------------------------------------------------------------- shapes
def _rf(n_lobes, amp, phase=0.0, r=120.0, centre=(256.0, 256.0), m=360):
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    rr = r * (1 + amp * np.sin(n_lobes * th + phase))
    return np.c_[centre[0] + rr * np.cos(th), centre[1] + rr * np.sin(th)]


def _polygon(k, seed, r=140.0, centre=(256.0, 256.0)):
    """A star-shaped random polygon (concave vertices guaranteed by the radius spread)."""
    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * np.pi, k))
    rr = r * rng.uniform(0.45, 1.0, k)
    return np.c_[centre[0] + rr * np.cos(th), centre[1] + rr * np.sin(th)]


def _ellipse(a, b, m=360, centre=(256.0, 256.0)):
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return np.c_[centre[0] + a * np.cos(th), centre[1] + b * np.sin(th)]


def _set(shapes, size=(512, 512)):
    ids = list(shapes)
    return StimulusSet(".", None, ids, {k: Contour(v, name=k) for k, v in shapes.items()},
                       {k: size for k in ids}, {k: None for k in ids})


@pytest.fixture(scope="module")
def ten():
    """Ten stimuli: ellipses, radial-frequency shapes and polygons."""
    shapes = {}
    for i in range(3):
        shapes[f"ell{i}"] = _ellipse(150, 60 + 25 * i)
    for i in range(4):
        shapes[f"rf{i}"] = _rf(3 + i, 0.1 + 0.03 * i, phase=0.3 * i)
    for i in range(3):
        shapes[f"poly{i}"] = _polygon(9 + 2 * i, seed=i)
    s = _set(shapes)
    return s, predict(s, n=100)


# ------------------------------------------------------------------ basics
def test_standardize_mean_zero_sd_one_and_constant_zero():
    rng = np.random.default_rng(0)
    u = rng.normal(3, 2, size=(4, 50))
    z = choice.standardize(u)
    np.testing.assert_allclose(z.mean(axis=1), 0, atol=1e-12)
    np.testing.assert_allclose(z.std(axis=1), 1, atol=1e-12)
    # a circle's surprisal is constant up to rounding: no amplified noise
    assert np.all(choice.standardize(5.0 + 1e-14 * rng.normal(size=50)) == 0)


def test_point_index_rounds_to_nearest_of_n_points_circularly():
    assert choice.point_index([0.0, 0.004, 0.006, 0.996, 0.5], 100).tolist() == [0, 0, 1, 0, 50]


def test_circular_kde_is_the_wrapped_normal():
    h, t0, m = 0.05, 0.97, 2000
    d = circular.circular_kde([t0], h, m=m)
    g = np.arange(m) / m
    k = np.arange(-3, 4)[:, None]
    wrapped = scipy.stats.norm.pdf(g[None, :] - t0 + k, scale=h).sum(axis=0)
    # linear binning of one position onto a grid of 2000 moves it by < 1/4000
    np.testing.assert_allclose(d, wrapped, atol=2e-3 * wrapped.max())
    assert d.mean() == pytest.approx(1.0, abs=1e-12)  # integrates to 1 over t


def test_circular_kde_groups_and_empty_group():
    d = circular.circular_kde([0.1, 0.2, 0.7], [0.02, 0.05, 0.1], m=256, group=[0, 0, 2], n_groups=3)
    assert d.shape == (3, 256)
    np.testing.assert_allclose(np.nanmean(d[[0, 2]], axis=1), 1.0, atol=1e-12)
    assert np.isnan(d[1]).all()


# ------------------------------------------------------------- the choice model
def test_fit_beta_two_points_closed_form():
    # z = (-1, +1): p(+1) = e^b / (e^b + e^-b), so b_hat = atanh(2q - 1) = ln(m2/m1)/2
    # and the Fisher information per click is Var(z) = 1 - tanh(b)^2.
    Z = np.array([[-1.0, 1.0]])
    m1, m2 = 30.0, 70.0
    f = choice.fit_beta(Z, m2 - m1, np.array([m1 + m2]))
    b = 0.5 * np.log(m2 / m1)
    assert f["beta"] == pytest.approx(b, abs=1e-10)
    assert f["se"] == pytest.approx(1 / np.sqrt(100 * (1 - np.tanh(b) ** 2)), rel=1e-10)
    ll = m2 * np.log(0.7) + m1 * np.log(0.3)
    assert f["loglik"] == pytest.approx(ll, abs=1e-9)
    assert f["loglik0"] == pytest.approx(100 * np.log(0.5), abs=1e-9)
    # profile interval: the log-likelihood falls by chi2_1(0.95)/2 at both ends
    lo, hi = choice.profile_ci(Z, m2 - m1, np.array([100.0]), f["beta"])
    for e in (lo, hi):
        assert choice.loglik(e, Z, m2 - m1, np.array([100.0])) == pytest.approx(ll - 3.841458820694124 / 2, abs=1e-8)
    assert lo < f["beta"] < hi


def test_fit_beta_score_is_the_derivative_of_the_loglik():
    rng = np.random.default_rng(1)
    Z = choice.standardize(rng.normal(size=(5, 40)))
    M = np.array([3.0, 0, 7, 2, 5])
    A = 4.2
    f = choice.fit_beta(Z, A, M)
    eps = 1e-5
    d = (choice.loglik(f["beta"] + eps, Z, A, M) - choice.loglik(f["beta"] - eps, Z, A, M)) / (2 * eps)
    assert d == pytest.approx(0.0, abs=1e-6)
    d2 = (choice.loglik(f["beta"] + 1e-3, Z, A, M) - 2 * f["loglik"] + choice.loglik(f["beta"] - 1e-3, Z, A, M)) / 1e-6
    assert 1 / np.sqrt(-d2) == pytest.approx(f["se"], rel=1e-4)


def test_fit_beta_vectorised_equals_one_at_a_time_and_flags_bounds():
    rng = np.random.default_rng(2)
    Z = choice.standardize(rng.normal(size=(3, 20)))
    A = np.array([2.0, -5.0, 0.0, Z[0].max() * 4])
    M = np.array([[4.0, 3, 2], [1, 6, 2], [0, 0, 0], [4, 0, 0]])
    f = choice.fit_beta(Z, A, M)
    for g in range(2):
        assert f["beta"][g] == pytest.approx(choice.fit_beta(Z, A[g], M[g])["beta"], abs=1e-9)
    assert np.isnan(f["beta"][2])  # no clicks: no estimate
    assert f["at_bound"][3] and f["beta"][3] == 20.0  # all clicks on the highest point: ML is +inf


def test_blur_kernel_sums_to_one_and_has_the_variance_of_a_rounded_shift():
    assert blurred.blur_kernel(50, 0.0)[0] == 1.0
    w = blurred.blur_kernel(200, 3.0)
    d = np.where(np.arange(200) < 100, np.arange(200), np.arange(200) - 200)
    assert w.sum() == pytest.approx(1.0, abs=1e-12)
    assert (w * d).sum() == pytest.approx(0.0, abs=1e-12)  # symmetric
    # round(U + e), U uniform on a unit interval, e ~ N(0, s^2): var = s^2 + E[f(1-f)] = s^2 + 1/6
    assert (w * d * d).sum() == pytest.approx(9 + 1 / 6, abs=1e-6)


def test_blurred_fit_without_error_is_the_plain_fit():
    rng = np.random.default_rng(6)
    Z = choice.standardize(rng.normal(size=(4, 30)))
    C = rng.poisson(2.0 * np.exp(Z)).astype(float)
    plain = choice.fit_beta(Z, (C * Z).sum(), C.sum(axis=1))
    fit = blurred.fit_beta_blurred(Z, C, 0.0)
    assert fit["beta"] == pytest.approx(plain["beta"], abs=1e-6)
    assert fit["se"] == pytest.approx(plain["se"], rel=1e-4)
    assert fit["loglik"] == pytest.approx(plain["loglik"], abs=1e-6)


# -------------------------------------------------------- circular-shift null
def test_circular_spearman_matches_scipy_on_every_shift():
    rng = np.random.default_rng(3)
    m = 64
    d = rng.normal(size=m).cumsum()
    u = rng.normal(size=m).cumsum()
    u[5] = u[6]  # a tie
    shifts = np.arange(1, m)
    rho, null, p = circular.circular_spearman(d, u, shifts)
    assert rho == pytest.approx(scipy.stats.spearmanr(d, u).statistic, abs=1e-12)
    for k in (1, 7, 33, 63):
        assert null[k - 1] == pytest.approx(scipy.stats.spearmanr(d, np.roll(u, k)).statistic, abs=1e-12)
    assert p == pytest.approx((1 + (null >= rho - 1e-12).sum()) / m)


def test_circular_spearman_detects_alignment_and_not_a_shifted_copy():
    g = np.arange(512) / 512
    u = np.cos(4 * np.pi * g) + 0.3 * np.cos(6 * np.pi * g)
    rho, _, p = circular.circular_spearman(u, u, circular.shift_indices(512, 1000))
    assert rho == pytest.approx(1.0) and p == pytest.approx(1 / 512)
    rho2, _, p2 = circular.circular_spearman(np.roll(u, 64), u, circular.shift_indices(512, 1000))
    assert p2 > 0.05


def test_shift_indices():
    assert circular.shift_indices(10, 100).tolist() == list(range(1, 10))
    s = circular.shift_indices(1024, 1000)
    assert len(s) == 1000 and s.min() >= 1 and s.max() <= 1023 and len(set(s)) == 1000
    assert len(circular.shift_indices(1024, 0)) == 0


# -------------------------------------------------------------- peaks and AUC
def test_peak_chance_is_the_measure_of_the_union_of_arcs():
    assert circular.peak_chance([0.0, 0.5], 0.1) == pytest.approx(0.4)
    assert circular.peak_chance([0.0, 0.05], 0.1) == pytest.approx(0.25)
    assert circular.peak_chance([0.95, 0.05], 0.1) == pytest.approx(0.3)  # across t = 0
    assert circular.peak_chance(np.arange(10) / 10, 0.1) == pytest.approx(1.0)
    assert circular.peak_chance([], 0.1) == 0.0
    # a Monte Carlo check of the same measure
    t = np.random.default_rng(4).uniform(size=200_000)
    pk = [0.1, 0.13, 0.6, 0.98]
    assert circular.peak_hits(t, pk, 0.04).mean() == pytest.approx(circular.peak_chance(pk, 0.04), abs=0.005)


def test_midrank_percentile_is_percentileofscore_mean():
    ref = np.array([1.0, 2, 2, 3, 5, 8, 8, 8])
    for v in (0.5, 1, 2, 4, 8, 9):
        assert circular.midrank_percentile([v], ref)[0] == pytest.approx(scipy.stats.percentileofscore(ref, v, kind="mean"))


def test_group_test_is_the_one_sample_t_test():
    v = np.array([0.3, -0.1, 0.5, 0.2, 0.4, np.nan])
    g = group.group_test(v)
    ref = scipy.stats.ttest_1samp(v[:5], 0.0)
    assert g["statistic"] == pytest.approx(ref.statistic) and g["p_value"] == pytest.approx(ref.pvalue)
    assert g["effect_size"] == pytest.approx(v[:5].mean() / v[:5].std(ddof=1)) and g["df"] == 4
    assert "wilcoxon" not in g
    one = group.group_test(v, alternative="greater")
    assert one["p_value"] == pytest.approx(ref.pvalue / 2)  # t > 0 here


def test_t_statistic_ranks_samples_without_spread():
    assert group.t_statistic(np.array([0.3, -0.1, 0.5])) == pytest.approx(scipy.stats.ttest_1samp([0.3, -0.1, 0.5], 0).statistic)
    np.testing.assert_array_equal(group.t_statistic(np.array([[2.0, -1.0, 0.0], [2.0, -1.0, 0.0]]), axis=0),
                                  [np.inf, -np.inf, 0.0])
    assert np.isnan(group.t_statistic(np.array([1.0])))


def test_mean_z_test_statistic_and_exact_null_on_two_points():
    # one stimulus with z = (-1, +1); P participants x 1 click. Under uniform clicking each
    # participant's mean z is +-1 with probability 1/2, so t depends only on the number k of
    # +1: the exact one-sided p is P(Binomial(P, 1/2) >= k) (t increases with k).
    Z = np.array([[-1.0, 1.0]])
    P = 8
    unit = np.arange(P)
    stim = np.zeros(P, np.int64)
    z = np.array([1.0] * 6 + [-1.0] * 2)  # k = 6
    g = group.mean_z_test(Z, stim, unit, z, replicates=19999, rng=np.random.default_rng(0))
    ref = scipy.stats.ttest_1samp(z, 0.0)
    assert g["statistic"] == pytest.approx(ref.statistic)
    assert g["p_value_parametric"] == pytest.approx(ref.pvalue / 2)
    exact = scipy.stats.binom.sf(5, P, 0.5)  # 37/256 = 0.1445
    assert abs(g["p_value"] - exact) < 4 * np.sqrt(exact * (1 - exact) / 19999)
    assert g["alternative"] == "greater" and g["simulations"] == 19999 and g["n"] == P
    # every participant on +1: t = +inf (no spread), p = P(all +1) = 1/256, never below 1/(1+R)
    g = group.mean_z_test(Z, stim, unit, np.ones(P), replicates=199, rng=np.random.default_rng(0))
    assert g["statistic"] == np.inf and 1 / 200 <= g["p_value"] <= 0.05


@pytest.fixture(scope="module")
def spiky():
    """Curved Attneave & Arnoult shapes through 6 random vertices: surprisal z up to ~9.5
    at a few points, so that a participant's mean z over few clicks is strongly skewed."""
    from attneave.stimuli.batch.recipes import Canvas, make

    shapes = {}
    for i in range(4):
        [_, curved] = make("attneave_polygon", 1954 + i, canvas=Canvas(width=256, height=256, margin=16),
                           n_points=6, version="both")
        shapes[f"a{i}"] = curved.contour.points
    pred = predict(_set(shapes, size=(256, 256)), n=100)
    return np.stack([p.z["surprisal"] for p in pred.values()])


@pytest.mark.parametrize("P, K, stimuli", [(20, 1, [0, 1, 2, 3]), (30, 1, [1])])
def test_calibrated_group_test_holds_its_level_with_few_clicks_on_spiky_stimuli(spiky, P, K, stimuli):
    """False-positive rate of the group test under uniform clicking, small designs.

    1000 simulated experiments, each with its own Monte Carlo null (R = 199), as
    `analyze` does; reject when p <= 0.05. A correct test rejects with probability
    10/200 = 0.05 (at most), so the count is Binomial(1000, 0.05): sd 6.9, and
    P(rate in [0.02, 0.08]) = 0.99998. The old test (the t distribution, two-sided)
    rejects here in 0.13-0.14 (20 x 1 x 4) and ~0.4 (30 x 1 x 1) of experiments;
    P(Binomial(1000, 0.126) <= 80) = 2e-6, so the assertion fails for it -- checked
    below on the same experiments."""
    Z = spiky[stimuli]
    S = len(stimuli)
    rng = np.random.default_rng(2024)
    stim = np.tile(np.repeat(np.arange(S), K), P)
    unit = np.repeat(np.arange(P), S * K)
    E = 1000
    new = np.zeros(E, bool)
    old = np.zeros(E, bool)
    for e in range(E):
        z = Z[stim, rng.integers(0, Z.shape[1], len(stim))]  # uniform clicking
        g = group.mean_z_test(Z, stim, unit, z, n_units=P, replicates=199, rng=rng)
        new[e] = g["p_value"] <= 0.05
        old[e] = scipy.stats.ttest_1samp(np.bincount(unit, weights=z) / np.bincount(unit), 0.0).pvalue < 0.05
    assert 0.02 <= new.mean() <= 0.08, new.mean()
    assert old.mean() > 0.1, old.mean()  # the stimuli do reproduce the liberal t-test


# ------------------------------------------------------------ the predictors
def test_paper_and_vonmises_forms_standardise_to_the_same_z(ten):
    # both are a constant minus a positive multiple of cos(a - 2*pi/n): the von Mises form is
    # no rival (so analyze does not fit it)
    from attneave.stimuli.geometry.information import surprisal

    s, pred = ten
    for sid, p in pred.items():
        vm = surprisal(s.contours[sid], n=100, model="vonmises").surprisal
        np.testing.assert_allclose(p.z["surprisal"], choice.standardize(vm), atol=1e-9)
        assert "vonmises" not in p.z


def test_circle_has_no_information():
    # a regular 64-gon sampled at its own 64 vertices turns by 2*pi/64 everywhere:
    # surprisal is constant up to rounding, and z must be 0, not amplified rounding noise
    th = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    s = _set({"disc": np.c_[256 + 100 * np.cos(th), 256 + 100 * np.sin(th)]})
    p = predict(s, n=64)["disc"]
    assert np.all(p.z["surprisal"] == 0) and np.all(p.z["abs_curvature"] == 0)


# ---------------------------------------------------------- simulated observers
def test_simulated_clicks_lie_on_the_contour_and_map_back_to_their_point(ten):
    _, pred = ten
    df, params = simulate(pred, participants=3, clicks=5, beta=1.0, seed=7)
    assert params["n"] == 100 and len(df) == 3 * 10 * 5
    m = map_clicks(df, pred)
    assert not m["excluded"].any()
    assert m["distance"].max() < 1e-6
    assert (m["point"] == m["true_point"]).all()
    np.testing.assert_allclose(np.mod(m["t"] - m["true_t"] + 0.5, 1) - 0.5, 0, atol=1e-9)


def test_simulation_is_deterministic_and_nested_in_participants(ten):
    _, pred = ten
    a, _ = simulate(pred, 4, 3, 1.2, seed=11, noise=2.0)
    b, _ = simulate(pred, 4, 3, 1.2, seed=11, noise=2.0)
    c, _ = simulate(pred, 6, 3, 1.2, seed=11, noise=2.0)
    assert a.equals(b)
    assert a.equals(c.iloc[: len(a)].reset_index(drop=True))


def test_recovery_beta_1_5(ten):
    """20 participants x 10 clicks on 10 stimuli: p < 0.001, beta_hat within 20% of 1.5.

    Without click noise the clicks follow the fitted model exactly (noise
    blurs clicks across neighbouring points and attenuates beta_hat, most on
    polygons whose surprisal sits on single points; see the next test)."""
    s, pred = ten
    df, _ = simulate(pred, participants=20, clicks=10, beta=1.5, seed=2024)
    res = analyze(df, s, predictions=pred, permutations=200)
    sm = res.summary
    assert sm["n_used"] == 2000
    assert sm["group"]["p_value"] < 0.001
    assert abs(sm["beta_hat"] - 1.5) < 0.2 * 1.5
    assert sm["beta_ci"][0] < sm["beta_hat"] < sm["beta_ci"][1]
    assert sm["auc"]["value"] > 0.6 and sm["peaks"]["hit_rate"] > sm["peaks"]["chance"]


def test_click_noise_attenuates_beta_but_keeps_the_test_valid(ten):
    s, pred = ten
    df0, _ = simulate(pred, participants=20, clicks=10, beta=1.5, seed=1)
    df2, _ = simulate(pred, participants=20, clicks=10, beta=1.5, seed=1, noise=2.0)
    b0 = analyze(df0, s, predictions=pred, permutations=0).summary
    b2 = analyze(df2, s, predictions=pred, permutations=0).summary
    assert 0 < b2["beta_hat"] < b0["beta_hat"]
    assert b2["group"]["p_value"] < 0.001


def test_localisation_error_model_recovers_beta_under_click_noise(ten):
    s, pred = ten
    df, _ = simulate(pred, participants=20, clicks=10, beta=1.5, seed=1, noise=2.0)
    sm = analyze(df, s, predictions=pred, permutations=0, click_sd=2.0).summary
    assert abs(sm["beta_hat"] - 1.5) < 0.1 * 1.5
    assert sm["params"]["click_sd"] == 2.0


def test_beta_zero_gives_beta_hat_within_four_standard_errors(ten):
    """Under beta = 0 the Fisher information is exactly N (Var z = 1), so SE = 1/sqrt(N)."""
    s, pred = ten
    df, _ = simulate(pred, participants=20, clicks=10, beta=0.0, seed=99, noise=1.0)
    sm = analyze(df, s, predictions=pred, permutations=0).summary
    se0 = 1 / np.sqrt(sm["n_used"])
    assert sm["beta_se"] == pytest.approx(se0, rel=0.02)
    assert abs(sm["beta_hat"]) < 4 * se0  # 4 SE = 0.089 for 2000 clicks
    assert abs(sm["auc"]["value"] - 0.5) < 4 * np.sqrt(1 / 12 / 2000)


def test_false_positive_rate_of_the_group_test(ten):
    """Reduced check (index space, 2000 experiments); the full pipeline is in
    benchmarks/check_false_positives.py."""
    _, pred = ten
    table, info = power(pred, 0.0, participants=[20], clicks=10, simulations=2000, seed=5)
    fpr = table["power"].iloc[0]
    assert 0.02 <= fpr <= 0.08, fpr  # binomial sd at 0.05 is 0.005
    assert "Monte Carlo" in info["test"] and info["group_simulations"] == 1999


def test_power_rises_with_participants_and_beta(ten):
    _, pred = ten
    t1, info = power(pred, 0.05, participants=[4, 16], clicks=2, simulations=300, seed=1)
    assert t1["power"].iloc[1] > t1["power"].iloc[0]
    t2, _ = power(pred, 0.3, participants=[4, 16], clicks=2, simulations=300, seed=1)
    assert (t2["power"].to_numpy() >= t1["power"].to_numpy()).all()
    assert info["required_participants"] in (None, 4, 16)


def test_uniform_clicking_matches_length_shares(ten):
    s, pred = ten
    j, _, _ = simulate_indices(np.stack([p.z["surprisal"] for p in pred.values()]), 1, 4000, 0.0, seed=3)
    sign = np.stack([p.sign for p in pred.values()])
    share = (sign[np.arange(10)[:, None], j[0]] < 0).mean(axis=1)
    expect = (sign < 0).mean(axis=1)
    assert (expect[7:] > 0).all()  # the polygons have concave parts
    np.testing.assert_allclose(share, expect, atol=4 * np.sqrt(0.25 / 4000))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 40), st.integers(1, 60), st.sampled_from([0, 1, 3]))
def test_average_ranks_equal_scipys_rankdata_with_ties_nan_and_constant_rows(seed, rows, m, decimals):
    """Rounded values make ties (decimals 0: many); one row holds a NaN, one is constant."""
    from attneave.analysis.models.circular import average_ranks

    rng = np.random.default_rng(seed)
    x = np.round(rng.standard_normal((rows, m)), decimals)
    x[0] = 1.5
    if rows > 1:
        x[-1, rng.integers(0, m)] = np.nan
    np.testing.assert_array_equal(average_ranks(x), scipy.stats.rankdata(x, axis=1))


@pytest.mark.parametrize("clicks_per_cell", [1, 2])
def test_monte_carlo_sums_of_a_complete_design_as_a_grid_equal_the_general_sums(monkeypatch, clicks_per_cell):
    """Every participant on every stimulus: a participant's cells are one column of a grid, summed
    in the order bincount adds them, so the nulls are the same to the last bit."""
    rng = np.random.default_rng(8)
    S, G, n = 30, 7, 20
    Z = choice.standardize(rng.gamma(1.0, size=(S, n)))
    stim = np.repeat(np.arange(S), G * clicks_per_cell)
    part = np.tile(np.repeat(np.arange(G), clicks_per_cell), S)
    shuffle = rng.permutation(len(stim))
    stim, part = stim[shuffle], part[shuffle]
    units = {"participant": (part, G), "stimulus": (stim, S)}
    z = Z[stim, rng.integers(0, n, len(stim))]
    grid = group.mean_z_nulls(Z, stim, units, 199, np.random.default_rng(1), observed_z=z, max_elements=2000)
    monkeypatch.setattr(group, "_GRID", False)
    general = group.mean_z_nulls(Z, stim, units, 199, np.random.default_rng(1), observed_z=z, max_elements=2000)
    for k in units:
        assert np.array_equal(grid[k][0], general[k][0]) and grid[k][1] == general[k][1]
    # the grid path was taken: participants cycle within each stimulus's cells
    cells = np.unique(np.c_[stim, part], axis=0)
    assert group._cycles(cells[:, 1], G) and not group._cycles(cells[:-1, 1], G)
    # the observed statistic from first principles: each participant's mean z, then t across them
    means = np.array([z[part == q].mean() for q in range(G)])
    assert grid["participant"][1] == pytest.approx(means.mean() * np.sqrt(G) / means.std(ddof=1), rel=1e-12)
