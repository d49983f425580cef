"""Benchmark: a 2000-stimulus batch with 1 and with 2 local worker processes.

The anchor is the same batch run in one process (``--workers 1``). The
script writes its own config to a temporary directory (Attneave polygons,
radial-frequency shapes and blobs, 256 x 256 px, 8-bit PNG + contour CSV),
runs ``attneave.stimuli.batch.run_batch`` with 1 and with 2 workers (``--repeat``
times each, interleaved so that a burst of load hits both), checks that
every run wrote byte-identical files, and prints the median wall time of
each and their ratio (target: speed-up >= 1.7 with 2 workers on 2 cores).

    python benchmarks/bench_batch.py [--n 2000] [--size 256] [--workers 2] [--repeat 3]

The machine, its load average and the library versions are printed first
(:mod:`_machine`), and the load again at the end: the speed-up can only
approach the number of workers when that many cores are free.
"""

from __future__ import annotations

import argparse
import hashlib
import statistics
import tempfile
import time
from pathlib import Path

from _machine import header, load

CONFIG = """\
seed: 2000
canvas: {{width: {size}, height: {size}, margin: 16}}
output: {{png_bit_depth: 8, svg: false}}
conditions:
  - name: poly
    recipe: attneave_polygon
    grid: {{n_points: [6, 10, 16, 24]}}
    repeats: {r_poly}
  - name: rf
    recipe: radial_frequency
    grid: {{frequency: [3, 5, 8, 12]}}
    repeats: {r_rf}
  - name: blob
    recipe: blob
    repeats: {r_blob}
"""


def _hashes(d):
    d = Path(d)
    return {p.relative_to(d).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(d.rglob("*")) if p.is_file()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000, help="stimuli in the batch (default 2000)")
    ap.add_argument("--size", type=int, default=256, help="image side in px (default 256)")
    ap.add_argument("--workers", type=int, default=2, help="workers of the parallel run (default 2)")
    ap.add_argument("--repeat", type=int, default=3, help="interleaved runs of each; medians reported (default 3)")
    args = ap.parse_args(argv)

    from attneave.stimuli.batch import run_batch

    r_poly = args.n // 12  # 4 cells
    r_rf = args.n // 12  # 4 cells
    r_blob = args.n - 4 * r_poly - 4 * r_rf
    text = CONFIG.format(size=args.size, r_poly=r_poly, r_rf=r_rf, r_blob=r_blob)
    with tempfile.TemporaryDirectory(prefix="bench_batch_") as tmp:
        cfg = Path(tmp) / "bench.yaml"
        cfg.write_text(text)
        header(f"bench_batch: {args.n} stimuli ({args.size}x{args.size} px PNG + contour CSV), "
               f"workers=1 (anchor) vs workers={args.workers}")
        times = {1: [], args.workers: []}
        for rep in range(args.repeat):  # interleaved, so that a burst of load hits both
            for w in times:
                dest = Path(tmp) / f"w{w}_{rep}"
                t0 = time.perf_counter()
                res = run_batch(cfg, dest, workers=w, progress=False)
                times[w].append(time.perf_counter() - t0)
                assert res.n_stimuli == args.n, res
                print(f"  run {rep + 1}, workers={w}: {times[w][-1]:8.2f} s  "
                      f"({1000 * times[w][-1] / args.n:6.2f} ms/stimulus)", flush=True)
        ref = _hashes(Path(tmp) / "w1_0")
        same = all(_hashes(Path(tmp) / f"w{w}_{rep}") == ref for w in times for rep in range(args.repeat))
        med = {w: statistics.median(t) for w, t in times.items()}
        ratio = med[1] / med[args.workers]
        print(f"  median of {args.repeat}: workers=1 (anchor) {med[1]:.2f} s, workers={args.workers} "
              f"{med[args.workers]:.2f} s; speed-up {ratio:.2f}x (target >= 1.7)")
        print(f"  byte-identical outputs across all runs: {same}; load average after: {load():.2f}")
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
