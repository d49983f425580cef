"""How much do the photo figures owe to GrabCut's random start?

GrabCut starts its colour models by k-means from OpenCV's random generator;
attneave seeds it (:data:`attneave.stimuli.extraction.figure_ground.grabcut.SEED`, 0) so that a
photo always gives the same outline, and ``validate_photos.py`` seeds its
anchor (plain ``cv2.grabCut`` from the same box) the same way. Another
seed gives other answers, on some photos a very different one (a horse:
IoU 0.73 with seed 0, 0 with seed 1). This script runs
``validate_photos.measure_photo`` with seeds 0 .. K-1 (attneave's GrabCuts
and the anchor's alike) and prints, per group and mode, the median IoU at
each seed and their range; then, per group, at how many seeds box mode's
median beats the anchor's.

Usage: python benchmarks/grabcut_seeds.py [DATA_DIR] [--seeds K] [--modes box,grabcut] [--workers N]
       [--limit N] [--csv OUT.csv]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from validate_photos import DEFAULT_DIR, map_tasks, measure_photo, photo_pairs  # noqa: E402

from _machine import header  # noqa: E402


def _measure(path, modes, seed):
    rows = measure_photo(path, modes, seed=seed)
    for r in rows:
        r["seed"] = seed
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DIR))
    ap.add_argument("--seeds", type=int, default=5, help="seeds 0 .. K-1 (default 5)")
    ap.add_argument("--modes", default="box,grabcut")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--csv", default=None, help="write one row per photo, mode and seed here")
    args = ap.parse_args(argv)

    import pandas as pd

    header("grabcut_seeds: photo figures under GrabCut's random start")
    data = Path(args.data)
    photos = [str(p) for p in photo_pairs(data)][: args.limit]
    if not photos or args.seeds < 1:
        print(f"grabcut_seeds: no NAME.jpg + NAME.mask.png pairs in {data}, or --seeds < 1", file=sys.stderr)
        return 2
    modes = args.modes.split(",")
    tasks = [(p, modes, k) for k in range(args.seeds) for p in photos]
    t0 = time.perf_counter()
    rows = [r for got in map_tasks(_measure, tasks, args.workers, chunksize=4) for r in got]
    df = pd.DataFrame(rows)
    print(f"{len(photos)} photos x {args.seeds} seeds, {time.perf_counter() - t0:.0f} s in all")
    med = df.groupby(["group", "mode", "seed"]).iou.median().unstack("seed")
    print("median IoU per seed")
    print(med.round(3).to_string())
    print("\nrange of the medians over seeds")
    for (group, mode), r in med.iterrows():
        print(f"{group:10s} {mode:9s} min {r.min():.3f}  median {r.median():.3f}  max {r.max():.3f}")
    if {"box", "grabcut"} <= set(modes):
        print()
        for group in med.index.get_level_values(0).unique():
            wins = int((med.loc[(group, "box")] > med.loc[(group, "grabcut")]).sum())
            print(f"{group}: box mode's median above plain GrabCut's at {wins} of {args.seeds} seeds")
    if args.csv:
        df.to_csv(args.csv, index=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
