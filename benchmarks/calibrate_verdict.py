"""Can a photographed outline be marked ``ok``? Calibrate the verdict's thresholds offline.

Reads the per-photo CSV of ``benchmarks/validate_photos.py --csv`` (one row
per photo and mode with its IoU against the true mask, the verdict's
measures and the half ``A``/``B`` the photo belongs to) and, per mode
(``--modes``, default ``auto,box``; ``rembg,rembg-box`` for a learned
network's outlines, whose ``uncertainty`` is measured too):

1. the Spearman correlation of each measure with the IoU (all photos);
2. for each half in turn as the tuning half: every rule "ok when each of
   up to ``--max-measures`` measures is on its good side of a threshold"
   (thresholds at the tuning half's deciles of each measure; the good side
   is fixed in advance: :data:`GOOD`) that passes the tuning half with a
   margin (ok precision, i.e. share of IoU >= 0.8, at least
   ``--tune-precision`` and no ok below ``--tune-min`` IoU, with at least
   ``--min-ok`` ok); the one giving the most ok is then checked on the
   other half against the Must show of issue 10 (precision >= 0.9, no ok
   below IoU 0.5).

With ``--clean`` only the outlines that no other reason of the verdict
makes ``suspect`` (their ``reason`` is empty but for "cannot be
verified") are candidates: a rule for them is what decides ``ok``, and
the precision printed is that of the outlines the verdict would then mark
``ok`` (the learned networks' rule was calibrated so).

A rule that holds on the half it was not chosen on, in both directions, is
a candidate for the verdict of that mode; otherwise its photographs stay
``unverifiable`` (see :mod:`attneave.stimuli.extraction.verdict`). When both
halves chose the same measures, the rule of the stricter threshold of
each (an outline ok by it is ok by both) is printed with its figures on
each half: that is the rule the verdict uses for box mode.

Usage: python benchmarks/calibrate_verdict.py PHOTOS.csv [--max-measures 3] [--tune-precision 0.95]
       [--tune-min 0.6] [--min-ok 3] [--measures colour_error,box_gap] [--modes rembg,rembg-box] [--clean]
"""

from __future__ import annotations

import argparse
import itertools
import sys

import numpy as np

#: Each measure's good side: +1 higher is better, -1 lower is better.
GOOD = dict(frame=-1, contrast=+1, competing=-1, agreement=+1, colour_error=-1, edge_support=+1, box_contact=-1,
            box_gap=-1, uncertainty=-1)
#: What the Must show asks of the outlines marked ok.
MUST_PRECISION, MUST_MIN = 0.9, 0.5


def passes(values, good, threshold):
    """Whether each row is on the good side of `threshold` (a measure that does not apply passes)."""
    return np.isnan(values) | (good * values >= good * threshold)


def figures(sel, iou):
    """(ok count, ok precision, smallest ok IoU) of the selected rows."""
    n = int(sel.sum())
    return (n, float(np.mean(iou[sel] >= 0.8)), float(iou[sel].min())) if n else (0, float("nan"), float("nan"))


def best_rule(g, measures, max_measures, tune_precision, tune_min, min_ok):
    """The rule with the most ok on `g` that passes it with the margin: (measures, thresholds, figures) or None."""
    iou = g["iou"].to_numpy(float)
    cols = {m: g[m].to_numpy(float) for m in measures}
    grids = {m: np.unique(np.nanquantile(cols[m], np.linspace(0, 1, 11))) for m in measures}
    best = None
    for k in range(1, max_measures + 1):
        for combo in itertools.combinations(measures, k):
            for ths in itertools.product(*(grids[m] for m in combo)):
                sel = np.ones(len(g), bool)
                for m, t in zip(combo, ths):
                    sel &= passes(cols[m], GOOD[m], t)
                n, prec, low = figures(sel, iou)
                if n >= min_ok and prec >= tune_precision and low >= tune_min and (best is None or n > best[2][0]):
                    best = (combo, ths, (n, prec, low))
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--max-measures", type=int, default=3)
    ap.add_argument("--tune-precision", type=float, default=0.95)
    ap.add_argument("--tune-min", type=float, default=0.6)
    ap.add_argument("--min-ok", type=int, default=3)
    ap.add_argument("--measures", default=None, help="comma-separated: only rules on these measures (default all)")
    ap.add_argument("--modes", default="auto,box", help="comma-separated: the modes calibrated (default auto,box)")
    ap.add_argument("--clean", action="store_true",
                    help="only outlines that no other reason of the verdict makes suspect are candidates")
    args = ap.parse_args(argv)

    import pandas as pd
    from scipy.stats import spearmanr

    try:
        df = pd.read_csv(args.csv)
    except (OSError, ValueError) as exc:
        print(f"calibrate_verdict: {args.csv}: cannot read ({exc}); expected the CSV of validate_photos.py --csv",
              file=sys.stderr)
        return 2
    missing = {"mode", "iou", "half"} - set(df.columns)
    if missing:
        print(f"calibrate_verdict: {args.csv}: no column(s) {', '.join(sorted(missing))}; "
              "expected the CSV of validate_photos.py --csv", file=sys.stderr)
        return 2
    df = df[df["mode"].isin(args.modes.split(","))]
    if args.clean:
        # the verdict's other reasons, without the one the rule would lift ("... cannot be verified: ...")
        other = df["reason"].fillna("").str.split("; ").map(
            lambda parts: [r for r in parts if r and "cannot be verified" not in r])
        n_all = df.groupby(["mode", "half"]).size()
        df = df[other.map(len) == 0]
        for (mode, half), n in n_all.items():
            print(f"   {mode} half {half}: {int(((df['mode'] == mode) & (df.half == half)).sum())} of {n} outlines "
                  "with no other reason to be suspect")
    held = True
    for mode, g in df.groupby("mode", sort=True):
        allowed = args.measures.split(",") if args.measures else list(GOOD)
        measures = [m for m in GOOD if m in allowed and m in g and g[m].notna().sum() >= 10]
        print(f"== {mode}: {len(g)} outlines, {np.mean(g.iou >= 0.8):.2f} with IoU >= 0.8")
        rho = {m: spearmanr(g[m], g.iou, nan_policy="omit").statistic for m in measures}
        print("   Spearman rho with IoU: " + ", ".join(f"{m} {r:+.2f}" for m, r in rho.items()))
        chosen = []
        for tune, check in (("A", "B"), ("B", "A")):
            t, c = g[g.half == tune], g[g.half == check]
            rule = best_rule(t, measures, args.max_measures, args.tune_precision, args.tune_min, args.min_ok)
            if rule is None:
                print(f"   tuned on {tune}: no rule passes it with the margin")
                held = False
                continue
            combo, ths, (n, prec, low) = rule
            chosen.append(dict(zip(combo, ths)))
            sel = np.ones(len(c), bool)
            for m, th in zip(combo, ths):
                sel &= passes(c[m].to_numpy(float), GOOD[m], th)
            cn, cprec, clow = figures(sel, c.iou.to_numpy(float))
            ok = cn > 0 and cprec >= MUST_PRECISION and clow >= MUST_MIN
            held &= ok
            text = " and ".join(f"{m} {'>=' if GOOD[m] > 0 else '<='} {th:.3g}" for m, th in zip(combo, ths))
            print(f"   tuned on {tune}: {text}: ok {n}/{len(t)}, precision {prec:.2f}, min IoU {low:.2f}; "
                  f"on {check}: ok {cn}/{len(c)}, precision {cprec:.2f}, min IoU {clow:.2f} "
                  f"-> {'holds' if ok else 'fails'}")
        if len(chosen) == 2 and set(chosen[0]) == set(chosen[1]):
            # both halves chose the same measures: the stricter threshold of each, checked on each half
            strict = {m: min(chosen[0][m], chosen[1][m], key=lambda t: -GOOD[m] * t) for m in chosen[0]}
            text = " and ".join(f"{m} {'>=' if GOOD[m] > 0 else '<='} {th:.3g}" for m, th in strict.items())
            for half, c in g.groupby("half"):
                sel = np.ones(len(c), bool)
                for m, th in strict.items():
                    sel &= passes(c[m].to_numpy(float), GOOD[m], th)
                cn, cprec, clow = figures(sel, c.iou.to_numpy(float))
                print(f"   both rules ({text}) on {half}: ok {cn}/{len(c)}, precision {cprec:.2f}, min IoU {clow:.2f}")
    print("verdict: a rule held on the unseen half in every case" if held else
          "verdict: no rule held on the unseen half in every case; photographs stay unverifiable")
    return 0


if __name__ == "__main__":
    sys.exit(main())
