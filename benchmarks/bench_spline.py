"""Benchmark: QIC spline fit against scipy's periodic cubic spline and libspiro.

For N = 30 and N = 1000 points on random smooth closed curves (radial Fourier
shapes, seeded), each of these is timed on the same points, interleaved
repeat by repeat so that machine load hits all alike:

- pure: ``qic_spline(points, robust=False)`` (the G2 clothoid spline,
  ``--method qic-g2``; every curvature jump below 1e-12 of max |k|);
- robust: ``qic_spline(points)`` (the default: the pure fit plus the robust
  rule's checks, which on these smooth shapes relax nothing);
- anchor: ``scipy.interpolate.CubicSpline(u, points, bc_type='periodic')``
  with the chord-length parameter ``u`` computed inside the timed call;
- libspiro, when the C library is installed (Debian package ``libspiro1``;
  a benchmark-only tool, loaded with ctypes): ``run_spiro`` + ``free_spiro``
  on the same points, all of type 'c' (G2 curve points), i.e. Raph Levien's
  G2 spiro spline solve.

Medians of all repeats (ms), never a best run, and the ratios pure /
libspiro (targets, issue 9: <= 2 at N = 30, <= 1 at N = 1000), robust / pure
(target <= 3) and pure / CubicSpline. The machine and its load average are
printed first (``benchmarks/_machine.py``), and which QIC solver ran: the
compiled kernel (``stimuli/curves/qic_solve.c``, ``KERNEL == 'c'``) or the
numpy reference (``ATTNEAVE_NUMPY_SPLINE=1``, or no C compiler at install).

Measured, issue 9's speed round of the robust mode (load average 1.55-1.80
on 2 shared cpus, AMD EPYC; five runs of this script each, alternating
between commit 524127d, before, and commit 6199f78, after; every figure a
median of its run, ranges over the five runs):

=====================  ===============  ===============
                       before           after
=====================  ===============  ===============
pure, N = 30           0.041 ms         0.040-0.041 ms
robust, N = 30         0.149-0.151 ms   0.095-0.097 ms
robust / pure, N = 30  3.64-3.65        2.39-2.41
pure, N = 1000         0.242-0.249 ms   0.239-0.241 ms
robust, N = 1000       0.631-0.649 ms   0.415-0.419 ms
robust / pure, 1000    2.60-2.61        1.74-1.75
=====================  ===============  ===============

Targets: robust / pure <= 3 (aim 2.5) at N = 30, <= 2.5 at N = 1000: met.
Instruction counts (``valgrind --tool=callgrind``, per call, the difference
of a run with 300 (N = 30) or 20 (N = 1000) calls and one with none, after
``gc.freeze()``, ``OPENBLAS_NUM_THREADS=1``, ``PYTHONHASHSEED=0``): robust
1.528 M -> 0.970 M at N = 30 (pure 0.385 M -> 0.387 M: 3.97 -> 2.51 x) and
8.31 M -> 5.45 M at N = 1000 (pure 2.885 M -> 2.887 M: 2.88 -> 1.89 x). The real-outline rows
(every 5th MPEG-7 mask, 70, at N = 12 / 20 / 40, 3 interleaved fits each,
thread CPU time; there the rule relaxes nodes and fits several times):
robust / pure 5.8-5.9 / 3.4-3.8 / 3.0-3.1 -> 4.3-4.5 / 2.5-2.9 / 2.2-2.3
(robust 0.36-0.37 / 0.24-0.28 / 0.26-0.27 -> 0.27 / 0.17-0.23 / 0.19-0.20
ms). On 100 jagged Attneave polygons (``validate_spline.py --jagged 100``,
half of the nodes relaxed; three runs each, alternating, same commits, load
1.3-1.6) robust 4.32-4.39 -> 3.61-3.63 ms per curve, robust / pure
21.4-21.5 -> 17.7-17.8 (the pure spline fails fast there; 0.2 ms); a third
of what remains is the segment-by-segment crossing search
(``attneave.stimuli.curves.metrics.self_crossing_segments``, shapely's STRtree),
another module's.

How: the rule's samples are made once per fit by the kernel
(``qic_kernel.turn_samples``: x, y in GEOS's layout and each segment's
distance from its chord, one buffer in and one out), shared by the bulge
and the crossing test; the polygon's turns, reference deviations and mean
chord come from one pass over its sides; the polygon's simplicity is asked
only when a curve crosses itself; straying nodes are sought only where one
reduction finds a deviation above the limit; no ``dataclasses.replace``
after a single fit; G0 corners' folds tested all at once; a segment's first
and last sample without the clothoid integral (the start, and the next
point where it is put anyway: two of three integrals on smooth curves, bit
for bit the same samples). The results are
the same: robust fits on the 350 MPEG-7 outlines at N = 12 / 20 / 40 / 80,
300 Attneave polygons and 20 smooth shapes (1720 fits, kernel) and on
every 2nd outline with the numpy path (1020 fits) have the same corners,
kinds and segments bit for bit, and ``validate_spline.py --halves`` prints
the same tables.

The kernel round before (commit 1e22b6d against 4bedff8, numpy solve, load
5.3-5.9): pure 0.202-0.215 -> 0.043-0.045 ms at N = 30 (libspiro
0.063-0.071 ms: 0.67-0.69 x, target 2 x) and 0.48-0.51 -> 0.25-0.26 ms at N
= 1000 (0.19-0.20 x libspiro, target 1 x); pure 1.90 M -> 0.385 M
instructions at N = 30 (libspiro through this script's ctypes wrapper 0.97
M) and 5.9 M -> 2.9 M at N = 1000 (libspiro 22 M).

Usage::

    python benchmarks/bench_spline.py [--repeat 200] [--shapes 5] [--seed 0] [--outlines DIR] [--every 5]
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import sys
import time
from pathlib import Path

import numpy as np
import shapely
from scipy.interpolate import CubicSpline

from attneave.stimuli.curves.qic import kernel as qic_kernel
from attneave.stimuli.curves.qic.spline import qic_spline
from attneave.stimuli.errors import InputError

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import header  # noqa: E402


def smooth_closed(rng, n, size=400.0):
    """n points on a random smooth closed radial-Fourier curve (pixels)."""
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    r = np.ones(n)
    for k in range(2, 6):
        r += rng.uniform(-0.25, 0.25) / k * np.cos(k * t + rng.uniform(0, 2 * np.pi))
    return np.c_[size / 2 + size / 3 * r * np.cos(t), size / 2 - size / 3 * r * np.sin(t)]


def cubic_periodic(P):
    Q = np.vstack([P, P[:1]])
    u = np.r_[0.0, np.cumsum(np.hypot(*np.diff(Q, axis=0).T))]
    return CubicSpline(u, Q, bc_type="periodic")


class _SpiroCP(ctypes.Structure):
    _fields_ = [("x", ctypes.c_double), ("y", ctypes.c_double), ("ty", ctypes.c_char)]


def load_spiro():
    name = ctypes.util.find_library("spiro") or "libspiro.so.1"
    try:
        lib = ctypes.CDLL(name)
    except OSError:
        return None
    lib.run_spiro.restype = ctypes.c_void_p
    lib.run_spiro.argtypes = [ctypes.POINTER(_SpiroCP), ctypes.c_int]
    lib.free_spiro.argtypes = [ctypes.c_void_p]

    dtype = np.dtype([("x", "<f8"), ("y", "<f8"), ("ty", "S1")], align=True)
    assert dtype.itemsize == ctypes.sizeof(_SpiroCP)

    def fit(P):
        n = len(P)
        cps = np.empty(n, dtype)
        cps["x"], cps["y"], cps["ty"] = P[:, 0], P[:, 1], b"c"
        seg = lib.run_spiro(cps.ctypes.data_as(ctypes.POINTER(_SpiroCP)), n)
        if not seg:
            raise RuntimeError("run_spiro failed")
        lib.free_spiro(seg)

    return fit


def lac_row(rng, shapes, repeat, n=30, alpha=-0.5):
    """One row: the G2 log-aesthetic spline (``lac_spline``, a genuine LAC
    solve at alpha = -0.5) against its anchor, the pure G2 QIC spline, on
    the same points, interleaved; medians of all repeats."""
    from attneave.stimuli.curves.lac.spline import lac_spline

    t_lac, t_qic, iters = [], [], []
    for _ in range(shapes):
        P = smooth_closed(rng, n)
        iters.append(lac_spline(P, alpha).iterations)
        for _ in range(max(10, repeat // 10)):
            t0 = time.perf_counter()
            lac_spline(P, alpha)
            t1 = time.perf_counter()
            qic_spline(P, robust=False)
            t_lac.append(t1 - t0)
            t_qic.append(time.perf_counter() - t1)
    lac, qic = 1e3 * np.median(t_lac), 1e3 * np.median(t_qic)
    print(f"lac (G2 log-aesthetic, alpha={alpha:g}) N={n}: {lac:.3f} ms vs pure QIC {qic:.3f} ms, "
          f"ratio {lac / qic:.1f}; Newton iterations <= {max(iters)}")


def real_rows(folder, every, repeat=3):
    """Rows on real outlines: every `every`-th MPEG-7 mask in `folder`
    reduced to N = 12 / 20 / 40 points (simple N-gons only), robust and pure
    QIC with the kernel and with the numpy path, interleaved fit by fit;
    medians of thread CPU time. Skipped where the folder or the kernel is
    missing."""
    from validate_spline import outlines

    lib = qic_kernel.LIB
    if lib is None or not Path(folder).is_dir():
        print(f"real outlines: skipped ({'no kernel' if lib is None else folder + ' not found'})")
        return
    shapes = [c for _, _, c in outlines(folder, every=every)]
    print(f"real outlines: {len(shapes)} from {folder}, CPU ms (kernel vs numpy path)")
    for n in (12, 20, 40):
        t = {key: [] for key in ("robust c", "robust np", "pure c", "pure np")}
        for c in shapes:
            P = c.resample(n).points
            if not shapely.is_simple(shapely.LinearRing(P)):
                continue
            for _ in range(repeat):
                for mode, robust in (("robust", True), ("pure", False)):
                    for path, use in (("c", lib), ("np", None)):
                        qic_kernel.LIB = use
                        try:
                            t0 = time.thread_time()
                            qic_spline(P, robust=robust)
                            t[f"{mode} {path}"].append(time.thread_time() - t0)
                        except InputError:
                            pass  # the pure spline may not converge: so on both paths
                        finally:
                            qic_kernel.LIB = lib
        med = {key: 1e3 * np.median(v) for key, v in t.items()}
        print(f"  N={n:>2}: robust {med['robust c']:.3f} vs {med['robust np']:.3f}, pure {med['pure c']:.3f} vs "
              f"{med['pure np']:.3f}; robust/pure {med['robust c'] / med['pure c']:.1f} "
              f"(numpy {med['robust np'] / med['pure np']:.1f})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=200, help="timed repeats per shape and method")
    ap.add_argument("--shapes", type=int, default=5, help="random shapes per N")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--outlines", default=str(Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "mpeg7"),
                    help="folder of MPEG-7 masks for the real-outline rows")
    ap.add_argument("--every", type=int, default=5, help="real outlines: every K-th mask")
    args = ap.parse_args()
    header("bench_spline: QIC spline (pure G2 and robust) vs scipy CubicSpline and libspiro")
    rng = np.random.default_rng(args.seed)
    spiro = load_spiro()
    print(f"libspiro: {'found' if spiro else 'not installed (apt-get install libspiro1)'}; "
          f"QIC solver: {qic_kernel.KERNEL} (ATTNEAVE_NUMPY_SPLINE=1 forces numpy)")
    print(f"{'N':>6} {'pure ms':>9} {'robust ms':>10} {'cubic ms':>9} {'spiro ms':>9} {'pure/spiro':>10} "
          f"{'robust/pure':>11} {'pure/cubic':>10} {'iters':>6} {'G2 err':>9} {'relaxed':>8}")
    for n in (30, 1000):
        reps = args.repeat if n <= 100 else max(20, args.repeat // 5)
        times = {"pure": [], "robust": [], "cubic": [], "spiro": []}
        iters, g2, relaxed = [], [], 0
        for _ in range(args.shapes):
            P = smooth_closed(rng, n)
            sp = qic_spline(P, robust=False)
            iters.append(sp.iterations)
            g2.append(sp.g2_error)
            relaxed += len(qic_spline(P).corners)
            cubic_periodic(P)
            if spiro:
                spiro(P)
            for _ in range(reps):
                t0 = time.perf_counter()
                qic_spline(P, robust=False)
                t1 = time.perf_counter()
                qic_spline(P)
                t2 = time.perf_counter()
                cubic_periodic(P)
                t3 = time.perf_counter()
                times["pure"].append(t1 - t0)
                times["robust"].append(t2 - t1)
                times["cubic"].append(t3 - t2)
                if spiro:
                    t4 = time.perf_counter()
                    spiro(P)
                    times["spiro"].append(time.perf_counter() - t4)
        med = {k: (1e3 * np.median(v) if v else float("nan")) for k, v in times.items()}
        print(f"{n:>6} {med['pure']:>9.3f} {med['robust']:>10.3f} {med['cubic']:>9.3f} {med['spiro']:>9.3f} "
              f"{med['pure'] / med['spiro']:>10.2f} {med['robust'] / med['pure']:>11.2f} "
              f"{med['pure'] / med['cubic']:>10.2f} {max(iters):>6} {max(g2):>9.1e} {relaxed:>8}")
    print("targets (issue 9): pure/spiro <= 2 at N = 30 and <= 1 at N = 1000; robust/pure <= 3")
    lac_row(rng, args.shapes, args.repeat)
    real_rows(args.outlines, args.every)


if __name__ == "__main__":
    main()
