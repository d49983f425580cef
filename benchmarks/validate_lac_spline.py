"""Validation: the G2 log-aesthetic spline (``--method lac``) through real
outlines reduced to N points, for several alphas, against scipy's periodic
``CubicSpline``.

The outlines, the reduction and the measures are those of
``validate_spline.py`` (its ``outlines`` and ``measure``); only the spline's
alpha is set here. Per N and alpha: shapes whose N-gon is simple, fits that
raise (by exception class), shapes whose curve crosses itself, shapes with a
segment turning by more than pi, shapes with an interior curvature extremum,
the largest relative curvature jump at a node (on the samples), the p90
over shapes of the largest distance to the dense outline divided by the
perimeter as a ratio to the cubic's, and the median fit time.

Usage::

    python benchmarks/validate_lac_spline.py [--alphas -1 -0.5 -2] [--n 12 20 40 80] [--every 1]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import shapely
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
import validate_spline as vs  # noqa: E402

from attneave.stimuli.curves.lac.spline import lac_spline  # noqa: E402
from attneave.stimuli.curves.splines import fit_spline  # noqa: E402
from attneave.stimuli.errors import InputError  # noqa: E402

from _machine import header  # noqa: E402


def with_alpha(alpha):
    """``fit_spline`` with the G2 LAC spline's alpha set (``vs.measure`` fits by method name)."""
    def fit(P, method, closed=True, **kwargs):
        if method == "lac":
            kwargs["alpha"] = alpha
        return fit_spline(P, method, closed=closed, **kwargs)
    return fit


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "mpeg7"))
    ap.add_argument("--alphas", type=float, nargs="+", default=[-1.0, -0.5, -2.0])
    ap.add_argument("--n", type=int, nargs="+", default=[12, 20, 40, 80])
    ap.add_argument("--every", type=int, default=1, help="every K-th file only")
    args = ap.parse_args(argv)
    header("validate_lac_spline: G2 log-aesthetic splines through real outlines reduced to N points")
    shapes = [(c, cKDTree(c.resample(spacing=0.25).points), c.perimeter)
              for _, _, c in vs.outlines(args.data, None, args.every)]
    print(f"{len(shapes)} outlines from {args.data}")
    for n in args.n:
        polys = [(c.resample(n).points, tree, per) for c, tree, per in shapes]
        polys = [p for p in polys if shapely.is_simple(shapely.LinearRing(p[0]))]
        vs.fit_spline = fit_spline
        ref = np.percentile([r["dist"] for r in (vs.measure(P, t, per, "cubic") for P, t, per in polys) if r], 90)
        for alpha in args.alphas:
            vs.fit_spline = with_alpha(alpha)
            rows = [vs.measure(P, t, per, "lac") for P, t, per in polys]
            ok = [r for r in rows if r]
            errors = {}
            for (P, _, _), r in zip(polys, rows):
                if r is None:
                    try:
                        lac_spline(P, alpha)
                    except InputError as exc:
                        errors[type(exc).__name__] = errors.get(type(exc).__name__, 0) + 1
            p90 = np.percentile([r["dist"] for r in ok], 90) if ok else float("nan")
            print(f"N={n} alpha={alpha:g} shapes={len(polys)} fail={len(polys) - len(ok)} {errors} "
                  f"cross={100.0 * sum(r['crosses'] for r in ok) / max(len(polys), 1):.1f}% "
                  f"turn>pi={sum(r['turn'] > np.pi for r in ok)} extrema={sum(r['extrema'] > 0 for r in ok)} "
                  f"g2={max((r['g2'] for r in ok), default=0.0):.1e} p90/cubic={p90 / ref:.2f} "
                  f"median_ms={1e3 * np.median([r['seconds'] for r in ok]) if ok else float('nan'):.1f}", flush=True)


if __name__ == "__main__":
    main()
