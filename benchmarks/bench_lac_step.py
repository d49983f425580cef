"""Benchmark: the robust QIC spline's log-aesthetic step against the same step at an earlier commit.

The step (:func:`attneave.stimuli.curves.qic.lac.prefer_log_aesthetic`: the cubic
reference, the log-aesthetic form's Newton solve where the clothoid fit
strays, and the comparison) is timed on real outlines (every K-th MPEG-7
mask, reduced to N points, simple N-gons only) for the fits that pass its
screen (a segment turning by more than 45 degrees), on the working tree's
code and on the code of `--before` (the LAC modules read from git into a
temporary package), interleaved fit by fit (the order alternating repeat
by repeat) so that machine load hits both alike. Thread CPU time; per N the
median over curves of each curve's median, for every curve that passes the
screen and for those where the form is solved, and the ratio. The machine
and its load average are printed first and last.

Measured, issue 9's speed round of the step (this script, every 2nd mask,
3 repeats; AMD EPYC, 2 shared cpus, load average 1.05 -> 1.03; before:
commit fec89cc), median per curve, ms:

=====  ============================  ============================
N      every curve screened           curves whose form is solved
=====  ============================  ============================
12     6.67 -> 3.27 (2.04 x), 166     6.80 -> 3.34 (2.03 x), 136
20     7.76 -> 3.81 (2.04 x), 168     8.17 -> 4.01 (2.04 x), 126
40     10.41 -> 5.32 (1.96 x), 170    11.72 -> 5.87 (2.00 x), 107
80     16.60 -> 7.88 (2.11 x), 173    18.12 -> 8.54 (2.12 x), 106
=====  ============================  ============================

(the median of the per-curve ratios: 1.98 / 1.98 / 1.97 / 2.05 screened,
2.00 / 2.02 / 1.99 / 2.13 solved; another run at load 1.5-1.7 gave 1.95-2.08).
The fits are the same: all 1368 robust fits of the 350 outlines at N = 12 /
20 / 40 / 80 make the same choice with the same corners, and the curves (and
the 957 log-aesthetic forms solved on the way) agree to 3.7e-14 (angles in
radians, curvatures and lengths in mean chords); ``validate_spline.py
--halves --methods qic cubic`` prints the same tables.

Usage::

    python benchmarks/bench_lac_step.py [--before fec89cc] [--every 4] [--repeat 2] [--n 12 20 40 80]
"""

from __future__ import annotations

import argparse
import importlib
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import shapely

sys.path.insert(0, str(Path(__file__).resolve().parent))
from attneave.stimuli.curves.qic import lac as qic_lac
from attneave.stimuli.curves.qic.spline import qic_spline  # noqa: E402

from _machine import header  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
MODULES = ("lac_quadrature", "lac_arc", "lac_newton", "lac_result", "qic_lac")


def load_before(ref, folder):
    """The step's modules at commit `ref`, as package ``lacref`` in `folder`
    (their imports of each other rewritten); returns its qic_lac."""
    pkg = Path(folder) / "lacref"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    for name in MODULES:
        try:
            text = subprocess.run(["git", "show", f"{ref}:stimuli/curves/{name}.py"], cwd=ROOT, check=True,
                                  capture_output=True, text=True).stdout
        except subprocess.CalledProcessError:
            continue  # not at that commit
        for other in MODULES:
            text = text.replace(f"attneave.stimuli.curves.{other}", f"lacref.{other}")
        (pkg / f"{name}.py").write_text(text)
    sys.path.insert(0, str(folder))
    return importlib.import_module("lacref.qic_lac")


def cases(folder, every, sizes):
    """(N, fit, polygon_simple, turn, solved) of every fit that passes the step's screen."""
    from validate_spline import outlines

    out = []
    for _, _, c in outlines(folder, every=every):
        for n in sizes:
            P = c.resample(n).points
            if not shapely.is_simple(shapely.LinearRing(P)):
                continue
            sp = qic_spline(P, log_aesthetic=False)
            turn = sp.max_segment_turn
            if turn <= qic_lac.SCREEN_TURN:
                continue
            simple = (lambda P=P: shapely.is_simple(shapely.LinearRing(P)))
            solved = []
            form = qic_lac.log_aesthetic_form
            qic_lac.log_aesthetic_form = lambda *a, **k: solved.append(1) or form(*a, **k)
            try:
                qic_lac.prefer_log_aesthetic(sp, simple, max_turn=turn)
            finally:
                qic_lac.log_aesthetic_form = form
            out.append((n, sp, simple, turn, bool(solved)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="fec89cc", help="git commit whose step is the anchor")
    ap.add_argument("--data", default=str(ROOT / ".." / "shared" / "data" / "mpeg7"))
    ap.add_argument("--every", type=int, default=4, help="every K-th mask")
    ap.add_argument("--repeat", type=int, default=2, help="timed repeats per fit and code")
    ap.add_argument("--n", type=int, nargs="+", default=[12, 20, 40, 80])
    args = ap.parse_args()
    header(f"bench_lac_step: the log-aesthetic step, working tree vs {args.before}")
    with tempfile.TemporaryDirectory() as tmp:
        before = load_before(args.before, tmp)
        todo = cases(args.data, args.every, args.n)
        print(f"{len(todo)} fits pass the screen; {sum(c[4] for c in todo)} solve the form")
        times = {}
        for rep in range(args.repeat):
            for i, (n, sp, simple, turn, _) in enumerate(todo):
                codes = (("before", before), ("after", qic_lac))
                for label, mod in codes if rep % 2 == 0 else codes[::-1]:
                    t0 = time.thread_time()
                    mod.prefer_log_aesthetic(sp, simple, max_turn=turn)
                    times.setdefault((i, label), []).append(time.thread_time() - t0)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    for n in args.n:
        for label, keep in (("screen", lambda c: True), ("solved", lambda c: c[4])):
            rows = [i for i, c in enumerate(todo) if c[0] == n and keep(c)]
            if not rows:
                continue
            b = 1e3 * np.array([np.median(times[(i, "before")]) for i in rows])
            a = 1e3 * np.array([np.median(times[(i, "after")]) for i in rows])
            print(f"N={n:>2} {label} ({len(rows):>3} curves): before {np.median(b):.3f} ms, after {np.median(a):.3f} ms, "
                  f"ratio of medians {np.median(b) / np.median(a):.2f}, median per-curve ratio {np.median(b / a):.2f}")


if __name__ == "__main__":
    main()
