"""Benchmark: exact-coverage silhouette rendering + PNG against OpenCV and matplotlib.

For each of ``--n`` random 500-vertex polygons (default 1000) a filled
512 x 512 image is made and written as an 8-bit PNG, three ways, interleaved
image by image so that machine load hits all three alike:

- project: ``stimuli.render.render_silhouette(..., dtype='uint8')`` and
  ``stimuli.render.write_png`` (atomic write: temporary file, then rename);
  also timed with a plain ``cv2.imwrite`` of the same image, so that the
  renderer is compared with the anchor through the very same writer;
- anchor: ``cv2.fillPoly(img, pts, 0, cv2.LINE_AA, shift=4)`` then
  ``cv2.imwrite`` (OpenCV's default PNG settings, same as ours); also timed
  with ``write_png``, so that the cost of the atomic write can be told
  apart from the cost of rendering;
- matplotlib: a 512 x 512 px figure (made once, no axes) with a filled
  ``Polygon`` patch, ``fig.savefig`` (the patch is swapped per image).

Two polygon families (``--kind``): ``blob`` (smooth random radial-Fourier
shapes, the usual stimulus) and ``spiky`` (star polygons with independent
random radii, a stress case with a much longer boundary). Per-image medians
(ms) and ratios are printed, with the boundary offset of each method (mean
coverage minus exact area, per pixel of perimeter) to show what the speed
buys. Files go to a temporary directory that is removed at the end.

Usage::

    python benchmarks/bench_render.py [--n 1000] [--kind blob|spiky|both] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
import time

import numpy as np


def blob(rng, n=500, size=512):
    """Smooth random radial-Fourier shape with `n` vertices, fitted to the image."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.ones(n)
    for k in range(2, 9):
        r += rng.normal(0, 0.35 / k**1.5) * np.cos(k * t + rng.uniform(0, 2 * np.pi))
    r = np.clip(r, 0.2, None)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    return _fit(pts, size)


def spiky(rng, n=500, size=512):
    """Star polygon with independent random radii (long, jagged boundary)."""
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.4, 1.0, n)
    return _fit(np.column_stack([r * np.cos(t), r * np.sin(t)]), size)


def _fit(pts, size):
    from stimuli.render import fit_to_image

    return fit_to_image(pts, size, margin=0.08 * size)["points"]


def shoelace(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def perimeter(p):
    return float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))


def run(kind, n, seed, tmp):
    import cv2
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    from stimuli.render import render_silhouette, write_png

    size = 512
    make = {"blob": blob, "spiky": spiky}[kind]
    rng = np.random.default_rng(seed)
    polys = [make(rng, 500, size) for _ in range(n)]

    fig = plt.figure(figsize=(size / 100, size / 100), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    ax.set_xlim(-0.5, size - 0.5)
    ax.set_ylim(size - 0.5, -0.5)

    def ours(p, path):
        img = render_silhouette(p, size=size, dtype="uint8")["img"]
        write_png(path, img)
        return img

    def ours_imwrite(p, path):
        img = render_silhouette(p, size=size, dtype="uint8")["img"]
        cv2.imwrite(path, img)
        return img

    def opencv(p, path):
        img = np.full((size, size), 255, np.uint8)
        cv2.fillPoly(img, [np.round(p * 16).astype(np.int32)], 0, cv2.LINE_AA, shift=4)
        cv2.imwrite(path, img)
        return img

    def opencv_write_png(p, path):
        img = np.full((size, size), 255, np.uint8)
        cv2.fillPoly(img, [np.round(p * 16).astype(np.int32)], 0, cv2.LINE_AA, shift=4)
        write_png(path, img)
        return img

    def mpl(p, path):
        patch = Polygon(p, closed=True, facecolor="black", edgecolor="none", antialiased=True)
        ax.add_patch(patch)
        fig.savefig(path, dpi=100, facecolor="white")
        patch.remove()
        return None

    methods = {
        "project": ours,
        "project+imwrite": ours_imwrite,
        "opencv": opencv,
        "opencv+write_png": opencv_write_png,
        "matplotlib": mpl,
    }
    times = {m: [] for m in methods}
    offsets = {m: [] for m in methods}
    names = list(methods)
    for i, p in enumerate(polys):
        order = names[i % len(names):] + names[: i % len(names)]
        for m in order:
            path = os.path.join(tmp, f"{m}_{i % 8}.png")
            t0 = time.perf_counter()
            img = methods[m](p, path)
            times[m].append(time.perf_counter() - t0)
            if i < 50:
                if img is None:
                    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
                cov = 1.0 - img.astype(float) / 255.0
                offsets[m].append((cov.sum() - shoelace(p)) / perimeter(p))
    plt.close(fig)

    med = {m: 1e3 * float(np.median(v)) for m, v in times.items()}
    print(f"\n{kind}: {n} polygons x 500 vertices, 512x512, 8-bit PNG; "
          f"mean perimeter {np.mean([perimeter(p) for p in polys]):.0f} px")
    print(f"{'method':<18}{'median ms':>10}{'offset px':>11}")
    for m in names:
        print(f"{m:<18}{med[m]:>10.3f}{np.mean(offsets[m]):>+11.4f}")
    print("(offset: mean over the first 50 images of (coverage sum - area) / perimeter)")
    print("targets: renderer at most 1.5x OpenCV, at least 5x faster than matplotlib, both")
    print("through the same PNG writer (cv2.imwrite, default settings):")
    print(f"  project+imwrite / opencv            = {med['project+imwrite'] / med['opencv']:.2f}  (target <= 1.5)")
    print(f"  matplotlib / project+imwrite        = {med['matplotlib'] / med['project+imwrite']:.1f}x (target >= 5)")
    print("with the project's atomic writer (write_png: temporary file, then rename):")
    print(f"  project / opencv+write_png          = {med['project'] / med['opencv+write_png']:.2f}")
    print(f"  project / opencv (raw imwrite)      = {med['project'] / med['opencv']:.2f}")
    print(f"  matplotlib / project                = {med['matplotlib'] / med['project']:.1f}x")
    return med


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="images per method (default 1000)")
    ap.add_argument("--kind", choices=["blob", "spiky", "both"], default="both")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    tmp = tempfile.mkdtemp(prefix="bench_render_")
    try:
        for kind in (["blob", "spiky"] if args.kind == "both" else [args.kind]):
            run(kind, args.n, args.seed, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
