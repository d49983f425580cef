"""Benchmark: ``attneave extract`` at corpus scale.

1. 200 small generated silhouettes extracted on a Dask LocalCluster (two
   single-threaded workers in this process) and with ``--workers 1``: every
   file compared byte for byte (they must be identical), and both times.
2. ``--count`` (default 20,000) 64 x 64 silhouettes (polygons, discs)
   extracted by the command line in a child process with ``--workers 2``:
   wall time, images per second and the peak resident memory of the child
   processes (``resource.getrusage(RUSAGE_CHILDREN)``; target under 500 MB,
   and not growing with the count: the summary is streamed from per-image
   records, :mod:`attneave.stimuli.extraction.corpus`).

The machine's load is printed before and after (the figures are only
comparable on a quiet machine).

Usage: nice -n 10 python benchmarks/bench_extract_scale.py [--count 20000] [--size 64]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from _machine import header  # noqa: E402


def silhouettes(folder, n, size):
    from test_extract_scale import _silhouettes  # the tests' generator: the same shapes

    return _silhouettes(Path(folder), n, size=size)


def compare_dask(tmp):
    from dask.distributed import Client, LocalCluster

    from attneave.stimuli.extraction.pipeline import extract_images

    imgs = sorted(str(p) for p in silhouettes(tmp / "in200", 200, 64).iterdir())
    t0 = time.perf_counter()
    extract_images(imgs, tmp / "one", workers=1, progress=False, method="otsu", as_frame=False)
    t_one = time.perf_counter() - t0
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as c, \
            Client(c) as client:
        t0 = time.perf_counter()
        extract_images(imgs, tmp / "dask", scheduler=client, progress=False, method="otsu", as_frame=False)
        t_dask = time.perf_counter() - t0
    a = {p.name: p.read_bytes() for p in (tmp / "one").iterdir()}
    b = {p.name: p.read_bytes() for p in (tmp / "dask").iterdir()}
    same = a.keys() == b.keys() and all(a[k] == b[k] for k in a)
    print(f"200 images: --workers 1 {t_one:.1f} s, LocalCluster(2 workers) {t_dask:.1f} s; "
          f"{len(a)} files, byte-identical: {same}")
    return same


def large(tmp, count, size):
    t0 = time.perf_counter()
    src = silhouettes(tmp / "many", count, size)
    t_make = time.perf_counter() - t0
    cmd = [str(Path(sys.executable).with_name("attneave")), "extract", str(src), "-o", str(tmp / "out"),
           "--method", "otsu", "--workers", "2", "--quiet"]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    rows = sum(1 for _ in open(tmp / "out" / "summary.csv")) - 1
    print(f"{count} images of {size}x{size} px ({t_make:.0f} s to make): {wall:.0f} s, {count / wall:.0f} images/s, "
          f"peak RSS {peak_mb:.0f} MB (target < 500), summary rows {rows}")
    return peak_mb < 500 and rows == count


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=20000)
    ap.add_argument("--size", type=int, default=64)
    args = ap.parse_args(argv)
    header("extract at corpus scale")
    with tempfile.TemporaryDirectory() as d:
        ok = compare_dask(Path(d))
        ok = large(Path(d), args.count, args.size) and ok
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
