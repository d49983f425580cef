"""Coverage of the mixed model's interval, and the participant-only test under item variance.

Simulated experiments on a stimulus set of polygons and radial-frequency
shapes (n points each): every participant clicks every stimulus K times,
by the choice model with slope ``beta + u_p + v_s`` (u_p ~ N(0, sd_p**2),
v_s ~ N(0, sd_s**2), crossed). For each experiment:

* the mixed conditional logit (:func:`attneave.analysis.models.mixed.fit_mixed`): does its
  interval cover the true mean slope beta? (target: >= 93% of runs at 95%);
* under a true mean slope of 0 with the same variances, the rejection rate of
  the participant-only group test (:func:`attneave.analysis.models.group.mean_z_test`, Monte
  Carlo null of uniform clicking, one-sided, alpha = 0.05), which treats
  stimuli as fixed, and of the mixed model (its interval excludes 0, upper
  side, i.e. the same one-sided alpha of 0.025 + 0.025).

Usage: ``python benchmarks/check_mixed_coverage.py [--runs 200] [--participants 16] [--stimuli 16]
[--clicks 6] [--beta 0.3] [--sd-participant 0.2] [--sd-stimulus 0.4]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.stats

from attneave.analysis.clicks.mapping import predict
from attneave.analysis.models.group import mean_z_test
from attneave.analysis.models.mixed import CumulantTable, fit_mixed
from attneave.stimuli import Contour
from attneave.stimuli.stimulus_set import StimulusSet

from _machine import header


def stimulus_z(count, n, seed):
    rng = np.random.default_rng(seed)
    shapes = {}
    th = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    for i in range(count):
        if i % 2:
            k = rng.integers(8, 14)
            a = np.sort(rng.uniform(0, 2 * np.pi, k))
            r = 140 * rng.uniform(0.45, 1.0, k)
            shapes[f"poly{i}"] = np.c_[256 + r * np.cos(a), 256 + r * np.sin(a)]
        else:
            r = 120 * (1 + rng.uniform(0.1, 0.3) * np.sin(rng.integers(3, 7) * th + rng.uniform(0, 6)))
            shapes[f"rf{i}"] = np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]
    ids = list(shapes)
    s = StimulusSet(".", None, ids, {k: Contour(v) for k, v in shapes.items()}, {k: (512, 512) for k in ids},
                    {k: None for k in ids})
    pred = predict(s, n=n)
    return np.stack([pred[k].z["surprisal"] for k in ids])


def experiment(rng, Z, beta, sd_p, sd_s, G, K):
    S, n = Z.shape
    u, v = rng.normal(0, sd_p, G), rng.normal(0, sd_s, S)
    b = beta + u[:, None] + v[None, :]  # (G, S)
    x = b[:, :, None] * Z[None, :, :]
    p = np.exp(x - x.max(axis=2, keepdims=True))
    cdf = np.cumsum(p, axis=2)
    cdf /= cdf[:, :, -1:]
    r = rng.random((G, S, K))
    j = (r[..., None] > cdf[:, :, None, :]).sum(axis=3)
    stim = np.broadcast_to(np.arange(S)[None, :, None], (G, S, K)).ravel()
    part = np.broadcast_to(np.arange(G)[:, None, None], (G, S, K)).ravel()
    return stim, part, np.minimum(j, n - 1).ravel()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--participants", type=int, default=16)
    ap.add_argument("--stimuli", type=int, default=16)
    ap.add_argument("--clicks", type=int, default=6)
    ap.add_argument("-n", type=int, default=60)
    ap.add_argument("--beta", type=float, default=0.3)
    ap.add_argument("--sd-participant", type=float, default=0.2)
    ap.add_argument("--sd-stimulus", type=float, default=0.4)
    ap.add_argument("--group-simulations", type=int, default=999)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    header("check_mixed_coverage: crossed random slopes, mixed model vs participant-only test")
    Z = stimulus_z(args.stimuli, args.n, args.seed)
    table = CumulantTable(Z)
    rng = np.random.default_rng(args.seed + 1)
    G, K = args.participants, args.clicks
    t0 = time.perf_counter()
    cover, fp_group, fp_mixed, est = [], [], [], []
    for _ in range(args.runs):
        st, pa, j = experiment(rng, Z, args.beta, args.sd_participant, args.sd_stimulus, G, K)
        f = fit_mixed(Z, st, pa, j, table=table)
        cover.append(f["ci_low"] <= args.beta <= f["ci_high"])
        est.append((f["beta"], f["sd_participant"], f["sd_stimulus"]))
        st, pa, j = experiment(rng, Z, 0.0, args.sd_participant, args.sd_stimulus, G, K)
        g = mean_z_test(Z, st, pa, Z[st, j], n_units=G, replicates=args.group_simulations, rng=rng)
        fp_group.append(g["p_value"] <= 0.05)
        f0 = fit_mixed(Z, st, pa, j, table=table)
        fp_mixed.append(f0["ci_low"] > 0 or f0["ci_high"] < 0)
    dt = time.perf_counter() - t0
    R = args.runs

    def rate(v):
        k = int(np.sum(v))
        lo, hi = scipy.stats.binomtest(k, R).proportion_ci(0.95)
        return f"{k / R:.3f} [{lo:.3f}, {hi:.3f}] ({k}/{R})"

    e = np.array(est)
    print(f"design: {G} participants x {args.stimuli} stimuli x {K} clicks, n = {args.n}; beta = {args.beta}, "
          f"sd_participant = {args.sd_participant}, sd_stimulus = {args.sd_stimulus}; {R} runs each ({dt:.0f} s)")
    print(f"mixed model, 95% interval covers the true mean slope:       {rate(cover)}   target >= 0.93")
    print(f"  median estimates: beta {np.median(e[:, 0]):.3f}, sd_participant {np.median(e[:, 1]):.3f}, "
          f"sd_stimulus {np.median(e[:, 2]):.3f}")
    print("true mean slope 0 (same variances), rejection at alpha = 0.05:")
    print(f"  participant-only group test (Monte Carlo, one-sided):    {rate(fp_group)}   (> 0.05: too liberal)")
    print(f"  mixed model (95% interval excludes 0, two-sided):        {rate(fp_mixed)}")


if __name__ == "__main__":
    main()
