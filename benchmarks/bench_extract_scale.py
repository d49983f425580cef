"""Benchmark: ``attneave extract`` at corpus scale.

1. 200 small generated silhouettes extracted on a Dask LocalCluster (two
   single-threaded workers in this process) and with ``--workers 1``: every
   file compared byte for byte (they must be identical), and both times
   (median of ``--repeat`` runs) and their ratio. Anchor: the same 200
   images read, thresholded (Otsu) and traced by ``cv2.findContours`` alone.
2. ``--count`` (default 20,000) 64 x 64 silhouettes (polygons, discs)
   extracted by the command line in a child process with ``--workers 2``,
   once: wall time, images per second, the peak resident memory of the
   child (``os.wait4``'s ``ru_maxrss``, the largest single process; target
   under 500 MB, and not growing with the count: the summary is streamed
   from per-image records, :mod:`attneave.stimuli.extraction.corpus`) and
   the largest sum over the command and its workers (sampled every 0.5 s).
   Anchor: the same images through ``cv2.findContours`` in this process.

The machine's load is printed before and after (the figures are only
comparable on a quiet machine).

Usage: nice -n 10 python benchmarks/bench_extract_scale.py [--count 20000] [--size 64] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
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


def anchor(paths):
    """Seconds to read, threshold (Otsu) and trace the outer contours of `paths` with OpenCV alone."""
    import cv2

    t0 = time.perf_counter()
    for p in paths:
        img = cv2.imread(str(p), cv2.IMREAD_GRAYSCALE)
        _, mask = cv2.threshold(img, 0, 255, cv2.THRESH_BINARY_INV + cv2.THRESH_OTSU)
        cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return time.perf_counter() - t0


def compare_dask(tmp, repeat):
    import shutil
    import statistics

    from dask.distributed import Client, LocalCluster

    from attneave.stimuli.extraction.pipeline import extract_images

    imgs = sorted(str(p) for p in silhouettes(tmp / "in200", 200, 64).iterdir())
    t_one, t_dask, t_cv, same = [], [], [], True
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as c, \
            Client(c) as client:
        for _ in range(repeat):
            for d in ("one", "dask"):
                shutil.rmtree(tmp / d, ignore_errors=True)
            t0 = time.perf_counter()
            extract_images(imgs, tmp / "one", workers=1, progress=False, method="otsu", as_frame=False)
            t_one.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            extract_images(imgs, tmp / "dask", scheduler=client, progress=False, method="otsu", as_frame=False)
            t_dask.append(time.perf_counter() - t0)
            t_cv.append(anchor(imgs))
            a = {p.name: p.read_bytes() for p in (tmp / "one").iterdir()}
            b = {p.name: p.read_bytes() for p in (tmp / "dask").iterdir()}
            same = same and a.keys() == b.keys() and all(a[k] == b[k] for k in a)
    one, dask, cv = (statistics.median(t) for t in (t_one, t_dask, t_cv))
    print(f"200 images (median of {repeat}): --workers 1 {one:.2f} s, LocalCluster(2 workers) {dask:.2f} s "
          f"(ratio {dask / one:.2f}); anchor cv2 threshold+findContours {cv:.3f} s (--workers 1 / anchor "
          f"{one / cv:.0f}x); {len(a)} files, byte-identical: {same}")
    return same


def _tree_rss_kb(pid):
    """Resident kB of `pid` and its children (the workers), from /proc."""
    total = 0
    for p in [pid, *_children(pid)]:
        try:
            with open(f"/proc/{p}/statm") as f:
                total += int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024
        except OSError:
            pass
    return total


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(c) for c in f.read().split()]
    except OSError:
        return []


def large(tmp, count, size):
    t0 = time.perf_counter()
    src = silhouettes(tmp / "many", count, size)
    t_make = time.perf_counter() - t0
    cmd = [str(Path(sys.executable).with_name("attneave")), "extract", str(src), "-o", str(tmp / "out"),
           "--method", "otsu", "--workers", "2", "--quiet"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
    tree = 0
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            break
        tree = max(tree, _tree_rss_kb(proc.pid))
        time.sleep(0.5)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    peak_mb = usage.ru_maxrss / 1024
    rows = sum(1 for _ in open(tmp / "out" / "summary.csv")) - 1
    t_cv = anchor(sorted(src.iterdir()))
    print(f"{count} images of {size}x{size} px ({t_make:.0f} s to make), run once: {wall:.0f} s, "
          f"{count / wall:.0f} images/s (anchor cv2 threshold+findContours {t_cv:.1f} s, ratio {wall / t_cv:.0f}); "
          f"peak RSS {peak_mb:.0f} MB (largest process; target < 500), command+workers {tree / 1024:.0f} MB "
          f"(sampled); summary rows {rows}; exit {proc.returncode}")
    return peak_mb < 500 and rows == count and proc.returncode == 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=20000)
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    header("extract at corpus scale")
    with tempfile.TemporaryDirectory() as d:
        ok = compare_dask(Path(d), args.repeat)
        ok = large(Path(d), args.count, args.size) and ok
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
