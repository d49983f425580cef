"""Surprisal of a 1,000,000-point closed contour against a bare numpy pass.

Anchor: headings by ``np.arctan2`` of ``np.diff``, turning angles by
``np.diff`` of the headings (wrapped), then ``np.cos`` -- the least any
implementation must do. Project, in the same process on the same array:

* ``surprisal_from_points`` -- the fast path on points as they are;
* ``Contour(points)`` + ``surprisal(contour, n=N)`` -- the full path:
  validation (finite, duplicates, orientation), equal-arc resampling,
  turning angles, curvature, eq. 5, circular peak finding.

Both project paths run with ``length_unit='px'`` (ds in pixels, as the
anchor computes it) and the fast path also with the default scale-free unit.
Prints the machine, medians of repeats and the ratios. Target (issue 2): at
most 3x.
Usage: python benchmarks/bench_surprisal.py [--n 1000000] [--repeats 7]
"""

import argparse

import numpy as np

from attneave.stimuli import Contour, surprisal
from attneave.stimuli.geometry.information import surprisal_from_points

from _machine import header, median_time


def bare_numpy(p, A=0.25, b=1.0):
    n = len(p)
    d = np.diff(p, axis=0, append=p[:1])
    heading = np.arctan2(d[:, 1], d[:, 0])
    turn = np.diff(heading, prepend=heading[-1:])
    turn = (turn + np.pi) % (2 * np.pi) - np.pi
    ds = np.hypot(d[:, 0], d[:, 1]).sum() / n
    return -np.log(A) - b * ds * ds * np.cos(turn - 2 * np.pi / n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    header("bench_surprisal: surprisal against a bare numpy pass")
    n = args.n
    th = 2 * np.pi * np.arange(n) / n
    # a wobbly closed contour, counter-clockwise on the screen (y down)
    r = 300 * (1 + 0.2 * np.sin(5 * th) + 0.05 * np.cos(17 * th))
    p = np.c_[512 + r * np.cos(th), 512 - r * np.sin(th)]

    # the two agree where they should: same turning angles up to the sign convention (y down)
    u_bare = bare_numpy(np.c_[p[:, 0], -p[:, 1]])
    u_fast = surprisal_from_points(p, length_unit="px")
    assert np.allclose(u_bare, u_fast, atol=1e-6 * np.abs(u_fast).max()), "fast path disagrees with anchor"

    t_bare = median_time(lambda: bare_numpy(p), args.repeats)
    t_fast = median_time(lambda: surprisal_from_points(p, length_unit="px"), args.repeats)
    t_default = median_time(lambda: surprisal_from_points(p), args.repeats)
    t_full = median_time(lambda: surprisal(Contour(p), n=n, length_unit="px"), max(3, args.repeats // 2))
    print(f"contour: {n:,} points, closed; median of {args.repeats} repeats")
    print(f"  bare numpy (arctan2, diff, cos)     {t_bare * 1e3:9.1f} ms   1.00x")
    print(f"  attneave surprisal_from_points      {t_fast * 1e3:9.1f} ms   {t_fast / t_bare:.2f}x")
    print(f"    same, default length unit         {t_default * 1e3:9.1f} ms   {t_default / t_bare:.2f}x")
    print(f"  attneave Contour + surprisal(n=N)   {t_full * 1e3:9.1f} ms   {t_full / t_bare:.2f}x")
    print("target: at most 2x the bare numpy pass (issue 13; issue 2 asked 3x)")


if __name__ == "__main__":
    main()
