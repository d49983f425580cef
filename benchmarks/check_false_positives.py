"""False-positive rate and recovery of the analysis, through the whole pipeline.

Slow check (not a test): for many seeds, simulated observers click on a
hand-built set of 10 stimuli (ellipses, radial-frequency shapes, polygons),
20 participants x 10 clicks per stimulus; every click is placed on the contour,
displaced by noise, mapped back and analysed exactly as `attneave analyze`
does (in memory; files are not the point here).

* beta = 0 (uniform clicking): the share of experiments whose group test has
  p < alpha must lie within [0.02, 0.08] at alpha = 0.05. The other tests of
  the summary are reported too (the pooled likelihood-ratio test treats
  clicks as independent; it is valid here because simulated participants do
  not differ).
* beta = 1.5: mean and sd of beta_hat over seeds at several click-noise
  levels, with the plain model (noise blurs clicks across neighbouring
  contour points and attenuates beta_hat) and with the localisation-error
  model (``click_sd`` = the simulated noise).

Usage::

    python benchmarks/check_false_positives.py [--seeds 400] [--alpha 0.05]

Exit status 0 when the group test's rate is within [0.02, 0.08], else 1.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import scipy.stats

from analysis.mapping import predict
from analysis.observers import simulate
from analysis.report import analyze
from analysis.stimulus_set import StimulusSet
from stimuli import Contour


def stimulus_set():
    th = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    c = np.array([256.0, 256.0])
    shapes = {}
    for i in range(3):
        shapes[f"ell{i}"] = np.c_[c[0] + 150 * np.cos(th), c[1] + (60 + 25 * i) * np.sin(th)]
    for i in range(4):
        r = 120 * (1 + (0.1 + 0.03 * i) * np.sin((3 + i) * th + 0.3 * i))
        shapes[f"rf{i}"] = np.c_[c[0] + r * np.cos(th), c[1] + r * np.sin(th)]
    for i in range(3):
        rng = np.random.default_rng(i)
        a = np.sort(rng.uniform(0, 2 * np.pi, 9 + 2 * i))
        r = 140 * rng.uniform(0.45, 1.0, len(a))
        shapes[f"poly{i}"] = np.c_[c[0] + r * np.cos(a), c[1] + r * np.sin(a)]
    ids = list(shapes)
    return StimulusSet(".", None, ids, {k: Contour(v, name=k) for k, v in shapes.items()},
                       {k: (512, 512) for k in ids}, {k: None for k in ids})


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=400)
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--noise", type=float, default=1.0, help="click noise (px) under the null")
    ap.add_argument("--recovery-seeds", type=int, default=100)
    args = ap.parse_args(argv)

    s = stimulus_set()
    pred = predict(s, n=100)
    keys = {
        "group t-test (per-participant mean z)": ("group", "p_value"),
        "group Wilcoxon": ("group", "wilcoxon", "p_value"),
        "items t-test (per-stimulus mean z)": ("by_stimulus", "p_value"),
        "t-test of per-participant beta": ("participant_beta", "p_value"),
        "pooled likelihood-ratio test": ("lr_test", "p_value"),
        "mean Spearman rho, circular shifts (one-sided)": ("spearman", "p_value"),
        "AUC - 0.5 across participants": ("auc", "test_vs_half", "p_value"),
        "peak hits - chance across participants": ("peaks", "excess_test", "p_value"),
    }
    pvals = {k: [] for k in keys}
    betas, ses = [], []
    t0 = time.perf_counter()
    for seed in range(args.seeds):
        df, _ = simulate(pred, participants=20, clicks=10, beta=0.0, seed=seed, noise=args.noise)
        sm = analyze(df, s, predictions=pred, permutations=200, seed=seed).summary
        for k, path in keys.items():
            v = sm
            for p in path:
                v = v[p]
            pvals[k].append(np.nan if v is None else v)
        betas.append(sm["beta_hat"])
        ses.append(sm["beta_se"])
    dt = time.perf_counter() - t0
    print(f"beta = 0: {args.seeds} simulated experiments (20 participants x 10 stimuli x 10 clicks, "
          f"noise {args.noise:g} px), full pipeline, {dt:.1f} s ({1000 * dt / args.seeds:.0f} ms each)")
    print(f"{'test':50s} {'rate':>6s}  95% CI (Clopper-Pearson)")
    rates = {}
    for k, v in pvals.items():
        v = np.asarray(v, float)
        v = v[np.isfinite(v)]
        hits = int((v < args.alpha).sum())
        lo, hi = scipy.stats.binomtest(hits, len(v)).proportion_ci(0.95)
        rates[k] = hits / len(v)
        print(f"{k:50s} {hits / len(v):6.3f}  [{lo:.3f}, {hi:.3f}]  (n = {len(v)})")
    b = np.asarray(betas)
    print(f"beta_hat under the null: mean {b.mean():+.4f}, sd {b.std(ddof=1):.4f}, "
          f"mean reported SE {np.mean(ses):.4f} (1/sqrt(2000) = {1 / np.sqrt(2000):.4f})")

    print(f"\nbeta = 1.5: beta_hat over {args.recovery_seeds} seeds by click noise")
    for noise in (0.0, 1.0, 2.0, 4.0):
        for click_sd in (None, noise) if noise > 0 else (None,):
            bh, pv, cover = [], [], []
            for seed in range(args.recovery_seeds):
                df, _ = simulate(pred, participants=20, clicks=10, beta=1.5, seed=10_000 + seed, noise=noise)
                sm = analyze(df, s, predictions=pred, permutations=0, click_sd=click_sd).summary
                bh.append(sm["beta_hat"])
                pv.append(sm["group"]["p_value"])
                cover.append(sm["beta_ci"][0] <= 1.5 <= sm["beta_ci"][1])
            bh = np.asarray(bh)
            label = "plain model" if click_sd is None else f"click_sd = {click_sd:g} px"
            print(f"  noise {noise:3.1f} px, {label:20s}: beta_hat mean {bh.mean():.3f}, sd {bh.std(ddof=1):.3f}, "
                  f"within 20% of 1.5 in {np.mean(np.abs(bh - 1.5) < 0.3):4.0%}, 95% CI covers 1.5 in "
                  f"{np.mean(cover):4.0%}, max group p {max(pv):.2g}")
    main_rate = rates["group t-test (per-participant mean z)"]
    ok = 0.02 <= main_rate <= 0.08
    print(f"\ngroup test false-positive rate {main_rate:.3f}: {'within' if ok else 'OUTSIDE'} [0.02, 0.08]")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
