"""Validate contour extraction on real silhouettes (MPEG-7 CE-Shape-1, part B).

For every image the default extraction (``extract(path)``: Otsu, polarity
from the border, largest object, sub-pixel contour) is compared with the
object's own pixels (the largest 8-connected object, holes filled, since the
contour is the outer boundary):

* area ratio: contour area / object pixel count;
* IoU: the contour re-rendered with exact coverage
  (``attneave.stimuli.render.coverage``) and thresholded at 0.5, against the object
  mask; and the soft IoU ``sum(min(cov, mask)) / sum(max(cov, mask))``;
* failures (with their reasons), contours that cross themselves, and time
  per image (extract alone, and
  extract + describe: curvature at 1 % of the perimeter and surprisal at
  n = 100).

The anchor for the area is the pixel count itself (the mask is what the
contour must reproduce). Prints a summary table and the worst images.

Usage: python benchmarks/validate_extract.py [DATA_DIR] [--method otsu] [--limit K]
       DATA_DIR defaults to ../shared/data/mpeg7 relative to the repository.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

DEFAULT_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "mpeg7"


def object_mask(ex):
    """The chosen object's pixels with holes filled."""
    import scipy.ndimage as ndi

    return ndi.binary_fill_holes(ex.mask)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DIR), help=f"directory of images (default {DEFAULT_DIR})")
    ap.add_argument("--method", default="otsu")
    ap.add_argument("--limit", type=int, default=None, help="only the first K images (sorted by name)")
    args = ap.parse_args(argv)

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.extraction import IMAGE_SUFFIXES, describe, extract, read_image
    from attneave.stimuli.render import coverage

    data = Path(args.data)
    files = sorted(p for p in data.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES) if data.is_dir() else []
    if not files:
        print(f"validate_extract: no images in {data}", file=sys.stderr)
        return 2
    if args.limit:
        files = files[: args.limit]

    # warm up: first-call imports are not per-image costs
    try:
        describe(extract(read_image(files[0]), method=args.method).contour)
    except InputError:
        pass
    rows, failures = [], []
    for f in files:
        img = read_image(f)  # reading is not timed
        t0 = time.perf_counter()
        try:
            ex = extract(img, method=args.method, name=f.name)
        except InputError as exc:
            failures.append((f.name, str(exc)))
            continue
        t1 = time.perf_counter()
        describe(ex.contour)
        t2 = time.perf_counter()
        m = object_mask(ex)
        cov = coverage(ex.contour, m.shape)
        r = cov >= 0.5
        iou = np.count_nonzero(r & m) / np.count_nonzero(r | m)
        soft = np.minimum(cov, m).sum() / np.maximum(cov, m).sum()
        touches = bool(m[0].any() or m[-1].any() or m[:, 0].any() or m[:, -1].any())
        rows.append(dict(
            image=f.name, pixels=int(m.sum()), area_ratio=ex.contour.area / m.sum(), iou=iou, soft_iou=soft,
            n_points=ex.contour.n, subpixel=ex.params["subpixel"], objects_found=ex.params["n_objects_found"],
            touches_border=touches, t_extract=t1 - t0, t_total=t2 - t0, megapixels=m.size / 1e6,
            simple=ex.contour.is_simple(),
        ))

    def q(v, p):
        return float(np.percentile(v, p))

    ar = np.array([r["area_ratio"] for r in rows])
    io = np.array([r["iou"] for r in rows])
    so = np.array([r["soft_iou"] for r in rows])
    te = np.array([r["t_extract"] for r in rows]) * 1e3
    tt = np.array([r["t_total"] for r in rows]) * 1e3
    mp = np.array([r["megapixels"] for r in rows])
    print(f"data: {data} ({len(files)} images), method {args.method}")
    print(f"processed {len(rows)}, failed {len(failures)}; "
          f"{sum(r['touches_border'] for r in rows)} objects touch the border; "
          f"{sum(r['objects_found'] > 1 for r in rows)} images have more than one object (largest taken); "
          f"{sum(not r['simple'] for r in rows)} contours cross themselves; "
          f"sub-pixel path: {', '.join(f'{k} {v}' for k, v in zip(*np.unique([r['subpixel'] for r in rows], return_counts=True)))}")
    print(f"{'measure':34s} {'min':>9s} {'p5':>9s} {'median':>9s} {'p95':>9s} {'max':>9s}")
    for name, v, fmt in [("area ratio (contour / pixels)", ar, "{:9.5f}"), ("IoU (re-rendered >= 0.5 vs mask)", io, "{:9.5f}"),
                         ("soft IoU (coverage vs mask)", so, "{:9.5f}"), ("time extract (ms)", te, "{:9.1f}"),
                         ("time extract + describe (ms)", tt, "{:9.1f}"), ("image size (Mpx)", mp, "{:9.3f}")]:
        print(f"{name:34s} " + " ".join(fmt.format(q(v, p)) for p in (0, 5, 50, 95, 100)))
    print(f"mean time per image: extract {te.mean():.1f} ms, extract + describe {tt.mean():.1f} ms "
          f"({statistics.fmean(tt / mp):.1f} ms per megapixel)")
    worst = sorted(rows, key=lambda r: r["iou"])[:5]
    print("lowest IoU: " + "; ".join(f"{r['image']} IoU {r['iou']:.4f} area ratio {r['area_ratio']:.4f}" for r in worst))
    for name, reason in failures:
        print(f"FAILED {name}: {reason}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
