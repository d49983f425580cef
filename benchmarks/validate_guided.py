"""Validate scale-free surprisal and information-guided stimuli on real silhouettes (MPEG-7).

For every silhouette (``extract(path)``, its largest object's outline):

* scale: surprisal at n = 128 of the outline scaled x0.25 and x4 about its
  centroid against x1, in the default unit (``'sample'``) and in ``'px'``;
* Attneave's cat (every surprisal peak, n = 256): how often the best-ranked
  separated points alone (the choice before untangling, the anchor) cross
  themselves, and whether ``attneave_cat`` ever does;
* peak fragments (4 fragments, 30 % of the perimeter, n = 256): the height
  ``(u - min u) / range`` of the weakest peak centre chosen by value with a
  fallback to any point (the choice before prominence, the anchor) against
  ``fragments`` with its default ``min_contrast`` (how many shapes it
  refuses, and the contrast of the others).

Usage: python benchmarks/validate_guided.py [DATA_DIR] [--limit K]
       DATA_DIR defaults to ../shared/data/mpeg7 relative to the repository.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from attneave.stimuli import Contour, InputError
from attneave.stimuli.extraction import extract
from attneave.stimuli.geometry.information import surprisal
from attneave.stimuli.shapes import guided
from attneave.stimuli.shapes.selection import rank_candidates, select_separated

from _machine import header

DEFAULT_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7"


def by_value_choice(res, L, ell, gap, m):
    """Peak centres as chosen before prominence: maxima by value, then any point by value."""
    half = max(0, int(round(0.5 * ell / res.params["ds"])))
    order, _ = rank_candidates(res.surprisal, "peaks", span=half)
    return select_separated(order, res.s, L, m, ell + gap)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DIR))
    ap.add_argument("--limit", type=int, default=None)
    args = ap.parse_args()
    header("validate_guided: scale-free surprisal, simple cats, fragment contrast (MPEG-7)")
    files = sorted(Path(args.data).glob("*.png"))[: args.limit]
    t0 = time.perf_counter()
    scale = {"sample": 0.0, "px": 0.0}
    old_cross = new_cross = untangled = refused = 0
    old_weakest, contrast = [], []
    for f in files:
        c = extract(str(f)).contours[0]
        ctr = c.centroid
        for unit in scale:
            u = [surprisal(Contour(ctr + s * (c.points - ctr)), n=128, length_unit=unit).surprisal
                 for s in (0.25, 1.0, 4.0)]
            scale[unit] = max(scale[unit], float(np.abs(u[0] - u[1]).max()), float(np.abs(u[2] - u[1]).max()))
        res = surprisal(c, n=256)
        order, n_ext = rank_candidates(res.surprisal, "peaks", span=1, prominence=1e-3 * np.ptp(res.surprisal))
        sep = 2 * res.params["ds"]
        k = max(3, len(select_separated(order[:n_ext], res.s, c.perimeter, n_ext, sep)))
        old = np.sort(select_separated(order, res.s, c.perimeter, k, sep))
        old_cross += not Contour(res.contour.points[old], orient=False).is_simple()
        pts, p = guided.attneave_cat(c, n=256)
        new_cross += not Contour(pts, orient=False).is_simple()
        untangled += bool(p["passed_over"])
        L, gap, m = c.perimeter, 6.0, 4
        ell = 0.3 * L / m
        u, lo, span = res.surprisal, res.surprisal.min(), np.ptp(res.surprisal)
        old_weakest.append(min((u[i] - lo) / span for i in by_value_choice(res, L, ell, gap, m)))
        try:
            contrast.append(guided.fragments(c, fraction=0.3, n_fragments=m, n=256, min_gap=gap)["params"]["contrast"])
        except InputError:
            refused += 1
    n = len(files)
    print(f"{n} silhouettes in {time.perf_counter() - t0:.0f} s")
    print(f"scale x0.25 / x4 against x1, max |du| (nats): sample {scale['sample']:.2e}, px {scale['px']:.3g}")
    print(f"cat, every peak: best-ranked points alone cross themselves on {old_cross}/{n}; "
          f"attneave_cat on {new_cross}/{n} (untangled {untangled})")
    weak = np.asarray(old_weakest)
    print(f"peak fragments by value: weakest centre below 5 % of the range on {int((weak < 0.05).sum())}/{n}, "
          f"below 20 % on {int((weak < 0.2).sum())}/{n}; median {statistics.median(weak):.3f}")
    print(f"fragments(min_contrast=0.2): refused {refused}/{n}; contrast of the others "
          f"min {min(contrast):.3f}, median {statistics.median(contrast):.3f}")


if __name__ == "__main__":
    main()
