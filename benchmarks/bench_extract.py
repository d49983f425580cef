"""Benchmark: contour extraction from a 1-megapixel photo-like image.

Measured in the same run, median of repeated timings (reading the file is
excluded; the image is an array in memory):

* full pipeline: ``extract`` (Otsu, polarity, largest object, sub-pixel
  contour) + ``describe`` (smoothing, curvature at 1 % of the perimeter,
  surprisal at n = 100 points)
  against its anchor ``skimage.measure.find_contours`` alone on the same
  image at the same level (sub-pixel iso-contours of the whole image, no
  segmentation, no object choice, no curvature);
* fast path: ``extract`` alone (everything up to the sub-pixel contour)
  against its anchor raw ``cv2.findContours`` on the Otsu mask
  (``cv2.threshold(..., THRESH_OTSU)`` + ``findContours``: pixel contours,
  no sub-pixel step).

Target: the full pipeline at most 2x ``find_contours`` alone.

Usage: python benchmarks/bench_extract.py [--repeats 7] [--size 1000]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np


def photo_like(size=1000, seed=0):
    """A smooth textured object on a gradient background, antialiased (uint8, RGB)."""
    from stimuli.render import coverage

    rng = np.random.default_rng(seed)
    h = w = size
    th = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    r = 0.3 * size * (1 + 0.12 * np.cos(3 * th + 0.4) + 0.06 * np.sin(5 * th + 1.0) + 0.03 * np.cos(7 * th))
    ring = np.c_[0.52 * w + r * np.cos(th), 0.48 * h + r * np.sin(th)]
    cov = coverage(ring, (h, w))
    yy, xx = np.mgrid[:h, :w] / size
    background = 70 + 60 * xx + 25 * yy
    # low-frequency texture on the object: a blurred noise field
    import cv2

    tex = cv2.GaussianBlur(rng.normal(0, 1, (h, w)), (0, 0), size / 60)
    tex *= 18 / tex.std()
    obj = 205 + tex - 20 * yy
    grey = background * (1 - cov) + obj * cov + rng.normal(0, 6, (h, w))
    rgb = np.stack([grey * 1.02, grey, grey * 0.95], axis=-1)
    return np.clip(np.round(rgb), 0, 255).astype(np.uint8)


def median_time(fn, repeats):
    times = []
    out = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--size", type=int, default=1000, help="image side in px (default 1000: 1 megapixel)")
    args = ap.parse_args(argv)

    import cv2
    from skimage.measure import find_contours

    from stimuli.extract import describe, extract

    img = photo_like(args.size)
    grey = img[:, :, :3].astype(np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
    grey8 = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
    ex = extract(img)
    level = ex.params["level"]

    def full():
        e = extract(img)
        return e, describe(e.contour)

    def fast():
        return extract(img)

    def anchor_fc():
        return find_contours(grey, level)

    def anchor_cv():
        _, m = cv2.threshold(grey8, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
        return cv2.findContours(m, cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)[0]

    # warm up (imports, caches), then interleave nothing: each measured as a block
    for f in (full, fast, anchor_fc, anchor_cv):
        f()
    t_full, (e, info) = median_time(full, args.repeats)
    t_fc, fc = median_time(anchor_fc, args.repeats)
    t_fast, _ = median_time(fast, args.repeats)
    t_cv, cvc = median_time(anchor_cv, args.repeats)

    h, w = img.shape[:2]
    print(f"image: {w}x{h} RGB uint8 ({w * h / 1e6:.2f} Mpx), photo-like (textured object, gradient, noise)")
    print(f"extracted: {len(e.contour)} points, perimeter {e.contour.perimeter:.1f} px, area {e.contour.area:.0f} px^2, "
          f"level {level:.2f}, polarity {e.params['polarity']}, sigma {info.sigma:.2f} px, n {info.params['n']}")
    print(f"find_contours found {len(fc)} iso-contours; cv2.findContours found {len(cvc)} contours")
    print(f"{'what':58s} {'median ms':>10s}")
    print(f"{'full pipeline (extract + describe)':58s} {t_full * 1e3:10.1f}")
    print(f"{'anchor: skimage.measure.find_contours alone':58s} {t_fc * 1e3:10.1f}")
    print(f"{'ratio full / find_contours (target <= 2)':58s} {t_full / t_fc:10.2f}")
    print(f"{'fast path (extract: Otsu, object, sub-pixel contour)':58s} {t_fast * 1e3:10.1f}")
    print(f"{'anchor: cv2.threshold(Otsu) + cv2.findContours':58s} {t_cv * 1e3:10.1f}")
    print(f"{'ratio fast / cv2.findContours':58s} {t_fast / t_cv:10.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
