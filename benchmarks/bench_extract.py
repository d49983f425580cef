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

Photographs: ``extract(method='photo')`` (what ``--method auto`` does with
a photograph: bilateral smoothing and five GrabCut hypotheses on at most
0.25 Mpx, the mask brought back to full size, sub-pixel outline) against
plain ``cv2.grabCut`` with 5 iterations from the 5 % inset box on the full
image, in ms per megapixel (target: at most 2x).

The image: a smooth three-to-seven-lobed object (exact-coverage
antialiasing) whose grey level is 205 with a low-frequency texture (SD 18)
and a vertical shading, on a background graded from 60 to 125, plus pixel
noise (SD 6), as RGB. Its true outline is known, so the accuracy of our
contour and of ``find_contours``' longest iso-contour (same level) are
printed too. ``--noise`` raises the pixel noise (more noise makes
``find_contours`` slower: it traces every noise blob).

Usage: python benchmarks/bench_extract.py [--repeats 9] [--size 1000] [--photo-repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import header  # noqa: E402


def photo_like(size=1000, seed=0, noise=6.0):
    """A smooth textured object on a gradient background, antialiased.

    Returns (uint8 RGB image, true outline as an (M, 2) ring in pixels).
    """
    from attneave.stimuli.render import coverage

    rng = np.random.default_rng(seed)
    h = w = size
    th = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    r = 0.3 * size * (1 + 0.12 * np.cos(3 * th + 0.4) + 0.06 * np.sin(5 * th + 1.0) + 0.03 * np.cos(7 * th))
    ring = np.c_[0.52 * w + r * np.cos(th), 0.48 * h + r * np.sin(th)]
    cov = coverage(ring, (h, w))
    yy, xx = np.mgrid[:h, :w] / size
    background = 60 + 45 * xx + 20 * yy
    # low-frequency texture on the object: a blurred noise field
    import cv2

    tex = cv2.GaussianBlur(rng.normal(0, 1, (h, w)), (0, 0), size / 60)
    tex *= 18 / tex.std()
    obj = 205 + tex - 20 * yy
    grey = background * (1 - cov) + obj * cov + rng.normal(0, noise, (h, w))
    rgb = np.stack([grey * 1.02, grey, grey * 0.95], axis=-1)
    return np.clip(np.round(rgb), 0, 255).astype(np.uint8), ring


def interleaved_medians(fns, repeats):
    """Median time of each function, the calls interleaved round by round so
    that load from other processes falls on all of them alike."""
    times = {k: [] for k in fns}
    out = {}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            out[k] = fn()
            times[k].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in times.items()}, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--size", type=int, default=1000, help="image side in px (default 1000: 1 megapixel)")
    ap.add_argument("--noise", type=float, default=6.0, help="pixel noise SD in grey levels (default 6)")
    ap.add_argument("--photo-repeats", type=int, default=5, help="rounds for the photo method against GrabCut")
    args = ap.parse_args(argv)
    header("bench_extract: contour extraction, and the photo method against plain GrabCut")

    import cv2
    from skimage.measure import find_contours

    from attneave.stimuli.extraction import describe, extract
    from attneave.stimuli.geometry.contour import Contour
    from attneave.stimuli.render import coverage

    img, ring = photo_like(args.size, noise=args.noise)
    grey = img[:, :, :3].astype(np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
    grey8 = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
    level = extract(img).params["level"]

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

    fns = dict(full=full, fc=anchor_fc, fast=fast, cv=anchor_cv)
    for f in fns.values():  # warm up (imports, caches)
        f()
    t, out = interleaved_medians(fns, args.repeats)
    t_full, t_fc, t_fast, t_cv = t["full"], t["fc"], t["fast"], t["cv"]
    e, info = out["full"]
    fc, cvc = out["fc"], out["cv"]
    truth = Contour(ring)
    _, _, dist = truth.project(e.contour.points)
    longest = max(fc, key=len)
    _, _, dist_fc = truth.project(longest[:, ::-1])

    h, w = img.shape[:2]
    print(f"image: {w}x{h} RGB uint8 ({w * h / 1e6:.2f} Mpx), photo-like (textured object, gradient, noise)")
    print(f"extracted: {len(e.contour)} points, perimeter {e.contour.perimeter:.1f} px, area {e.contour.area:.0f} px^2, "
          f"level {level:.2f}, polarity {e.params['polarity']}, sigma {info.sigma:.2f} px, n {info.params['n']}")
    print(f"accuracy against the true outline: RMS distance {np.sqrt(np.mean(dist ** 2)):.4f} px, "
          f"max {dist.max():.4f} px; area {e.contour.area / truth.area - 1:+.4%}, "
          f"perimeter {e.contour.perimeter / truth.perimeter - 1:+.4%}")
    print(f"find_contours' longest iso-contour at the same level: RMS distance "
          f"{np.sqrt(np.mean(dist_fc ** 2)):.4f} px, max {dist_fc.max():.4f} px")
    print(f"find_contours found {len(fc)} iso-contours (noise included); cv2.findContours found {len(cvc)} contours")
    print(f"medians of {args.repeats} interleaved rounds")
    print(f"{'what':58s} {'median ms':>10s}")
    print(f"{'full pipeline (extract + describe)':58s} {t_full * 1e3:10.1f}")
    print(f"{'anchor: skimage.measure.find_contours alone':58s} {t_fc * 1e3:10.1f}")
    print(f"{'ratio full / find_contours (target <= 2)':58s} {t_full / t_fc:10.2f}")
    print(f"{'fast path (extract: Otsu, object, sub-pixel contour)':58s} {t_fast * 1e3:10.1f}")
    print(f"{'anchor: cv2.threshold(Otsu) + cv2.findContours':58s} {t_cv * 1e3:10.1f}")
    print(f"{'ratio fast / cv2.findContours':58s} {t_fast / t_cv:10.2f}")

    # photographs: the automatic photo method against plain GrabCut (5 iterations, inset box)
    from attneave.stimuli.extraction.figure_ground.grabcut import inset_box

    bgr = np.ascontiguousarray(img[:, :, ::-1])

    def photo():
        return extract(img, method="photo")

    def plain():
        gc = np.zeros((h, w), np.uint8)
        cv2.grabCut(bgr, gc, inset_box(bgr.shape), np.zeros((1, 65)), np.zeros((1, 65)), 5, cv2.GC_INIT_WITH_RECT)
        return gc

    t, out = interleaved_medians(dict(photo=photo, plain=plain), args.photo_repeats)
    mpx = w * h / 1e6
    truth_mask = coverage(ring, (h, w)) >= 0.5
    got = coverage(out["photo"].contour, (h, w)) >= 0.5
    plain_mask = (out["plain"] == 1) | (out["plain"] == 3)
    iou = lambda a, b: (a & b).sum() / (a | b).sum()  # noqa: E731
    print(f"medians of {args.photo_repeats} interleaved rounds")
    print(f"{'photo method (auto on photographs), ms per Mpx':58s} {t['photo'] * 1e3 / mpx:10.1f}")
    print(f"{'anchor: plain cv2.grabCut, 5 iterations, ms per Mpx':58s} {t['plain'] * 1e3 / mpx:10.1f}")
    print(f"{'ratio photo / grabCut (target <= 2)':58s} {t['photo'] / t['plain']:10.2f}")
    print(f"IoU against the true object: photo method {iou(got, truth_mask):.4f}, plain GrabCut {iou(plain_mask, truth_mask):.4f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
