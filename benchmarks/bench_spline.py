"""Benchmark: QIC spline fit against scipy's periodic cubic spline (and libspiro).

For N = 30 and N = 1000 points on random smooth closed curves (radial Fourier
shapes, seeded), each of these is timed on the same points, interleaved
repeat by repeat so that machine load hits all alike:

- project: ``stimuli.splines.qic_spline(points)`` (closed G2 clothoid spline,
  tolerance as shipped: every curvature jump below 1e-12 of max |k|);
- anchor: ``scipy.interpolate.CubicSpline(u, points, bc_type='periodic')``
  with the chord-length parameter ``u`` computed from the points inside the
  timed call (the same work the QIC fit does on its input);
- libspiro, when the C library is installed (Debian package ``libspiro1``):
  ``run_spiro`` + ``free_spiro`` through ctypes on the same points, all of
  type 'c' (G2 curve points), i.e. Raph Levien's G2 spiro spline solve.

Median times (ms), the ratios QIC / CubicSpline and QIC / libspiro, and the
QIC's iterations and G2 error are printed. Targets from issue 4: at most 3x
CubicSpline at N = 30 and at most 10x at N = 1000.

Usage::

    python benchmarks/bench_spline.py [--repeat 200] [--shapes 5] [--seed 0]
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import time

import numpy as np
from scipy.interpolate import CubicSpline

from stimuli.curves.splines import qic_spline


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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=200, help="timed repeats per shape and method")
    ap.add_argument("--shapes", type=int, default=5, help="random shapes per N")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    spiro = load_spiro()
    print(f"libspiro: {'found' if spiro else 'not installed (apt-get install libspiro1)'}")
    print(f"{'N':>6} {'QIC ms':>9} {'Cubic ms':>9} {'ratio':>7} {'spiro ms':>9} {'QIC/spiro':>9} {'iters':>6} {'G2 err':>9}")
    for n in (30, 1000):
        reps = args.repeat if n <= 100 else max(20, args.repeat // 5)
        times = {"qic": [], "cubic": [], "spiro": []}
        iters, g2 = [], []
        for _ in range(args.shapes):
            P = smooth_closed(rng, n)
            sp = qic_spline(P)
            iters.append(sp.iterations)
            g2.append(sp.g2_error)
            cubic_periodic(P)
            if spiro:
                spiro(P)
            for _ in range(reps):
                t0 = time.perf_counter()
                qic_spline(P)
                t1 = time.perf_counter()
                cubic_periodic(P)
                t2 = time.perf_counter()
                times["qic"].append(t1 - t0)
                times["cubic"].append(t2 - t1)
                if spiro:
                    t3 = time.perf_counter()
                    spiro(P)
                    times["spiro"].append(time.perf_counter() - t3)
        q = 1e3 * np.median(times["qic"])
        c = 1e3 * np.median(times["cubic"])
        s = 1e3 * np.median(times["spiro"]) if spiro else float("nan")
        print(f"{n:>6} {q:>9.3f} {c:>9.3f} {q / c:>7.2f} {s:>9.3f} {q / s:>9.2f} {max(iters):>6} {max(g2):>9.1e}")
    print("ratio = QIC / CubicSpline (targets: <= 3 at N = 30, <= 10 at N = 1000)")


if __name__ == "__main__":
    main()
