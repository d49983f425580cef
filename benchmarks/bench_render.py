"""Benchmark: exact-coverage silhouette rendering + PNG against OpenCV and matplotlib.

For each of ``--n`` random 500-vertex polygons (default 1000) a filled
512 x 512 image is made and written as an 8-bit PNG, several ways,
interleaved image by image so that machine load hits all alike:

- project+imwrite: ``attneave.stimuli.render.render_silhouette(..., dtype='uint8')``
  then ``cv2.imwrite`` (the target's numerator);
- opencv: ``cv2.fillPoly(img, pts, 0, cv2.LINE_AA, shift=4)`` then
  ``cv2.imwrite`` (OpenCV's default PNG settings; the anchor);
- project: the renderer with ``attneave.stimuli.render.write_png`` (atomic write:
  temporary file, then rename), and opencv+write_png, the anchor through the
  same writer;
- matplotlib: a 512 x 512 px figure (made once, no axes) with a filled
  ``Polygon`` patch, ``fig.savefig`` (the patch is swapped per image);
- the split: the renderer alone, fillPoly alone, and ``cv2.imwrite`` alone
  of each method's image.

Why the ratio differs between machines and stacks
-------------------------------------------------
With R the renderer, F fillPoly and W the PNG encoder (``cv2.imwrite``),
the target ratio is ``(R + W) / (F + W)``. F is small (under 0.1 ms for a
blob, 0.25 ms for a spiky star), so the ratio runs from about 1 where the
encoder dominates to R / F (about 1.5 for both kinds) where it is free. W is
zlib's deflate inside OpenCV's libpng, the same for both images to within
a few per cent, and it depends on the build (zlib or zlib-ng, compression
defaults, CPU): on this project's 2-core AMD EPYC with the OpenCV 5.0 wheels
it is 0.6 ms per blob and 1.1 ms per spiky image (thread CPU time, about 8
and 11 million instructions). A stack whose encoder is three times faster
shows a ratio nearer R / F. The wall clock of ``imwrite`` also holds the
file system's latency, which on this machine swung between 0.1 and 3.5 ms
per file with the other users' disk traffic: wall-clock ratios measured
while the disk was slow (1.1-1.3 here) look far better than the CPU-time
ratio, which is why ``cv2.imencode`` (the encoder in memory) is timed too
and the CPU-time ratio is the one to judge by. The renderer's own path is
printed (``attneave.stimuli.render.KERNEL``): the compiled kernel, or the numpy path
(``ATTNEAVE_NUMPY_RENDER=1``, or no C compiler at install), whose hundred
small numpy calls slow more than the encoder when other work has evicted
the caches, which callgrind's counts do not see (numpy path: blob 11.8 M
instructions against 10.1 M, ratio 1.17, spiky 22.3 M against 16.0 M,
ratio 1.39, while CPU time gave 1.74 and 1.82 at load 8-11). The cold
caches are also why the kernel paints 8-bit images band by band of rows
in a 128 KB buffer instead of over the shape's whole box (1.3 MB of
deposits, which evicted the encoder's tables and then ran cold itself),
and why one plain float64 ring goes to it in one ctypes call (a dozen
small Python calls took as long as the kernel with cold caches). Measured
with the kernel (``--n 1000``, three runs, load 1.1-1.3, CPU medians):
1.14 / 1.05 / 1.06 (blob) and 1.12 / 1.10 / 1.11 (spiky), renderer 0.10 /
0.34 ms per image, fillPoly 0.065 / 0.227 ms, imwrite 0.52 / 1.00 ms;
callgrind (``--instructions 20``): render step 2.28 / 4.49 M instructions,
fillPoly step 2.18 / 4.48 M (polygon generation included in both),
project+imwrite against opencv 10.13 / 10.03 M (1.01) and 16.04 / 16.02 M
(1.00); before the bands, 1.39 / 1.35 / 1.36 and 1.25 / 1.28 / 1.23
(load 1.1-1.6). So the split is printed, with the ratio the measured R and
F would give at half and a quarter of the measured W.

Each method is timed both by wall clock and by the CPU time of the calling
thread (``time.thread_time``): on a loaded machine the wall clock of a
sub-millisecond call mostly measures when the scheduler lets it run, the
CPU time does not (OpenCV's PNG encoder and fillPoly run in the calling
thread). Medians over all images, never a best run.

``--instructions K`` also counts the instructions per image of each step
under ``valgrind --tool=callgrind`` (K images against 0 in a fresh process
each; independent of load, not of the CPU's instruction set).

Two polygon families (``--kind``): ``blob`` (smooth random radial-Fourier
shapes, the usual stimulus) and ``spiky`` (star polygons with independent
random radii, a stress case with a boundary twelve times longer). The
boundary offset of each method (mean coverage minus exact area, per pixel
of perimeter) shows what the speed buys. Files go to a temporary directory
that is removed at the end.

Usage::

    python benchmarks/bench_render.py [--n 1000] [--kind blob|spiky|both] [--seed 0]
                                      [--instructions 20]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

from _machine import header

SIZE = 512
TARGET = 1.3


def blob(rng, n=500, size=SIZE):
    """Smooth random radial-Fourier shape with `n` vertices, fitted to the image."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.ones(n)
    for k in range(2, 9):
        r += rng.normal(0, 0.35 / k**1.5) * np.cos(k * t + rng.uniform(0, 2 * np.pi))
    r = np.clip(r, 0.2, None)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    return _fit(pts, size)


def spiky(rng, n=500, size=SIZE):
    """Star polygon with independent random radii (long, jagged boundary)."""
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.4, 1.0, n)
    return _fit(np.column_stack([r * np.cos(t), r * np.sin(t)]), size)


def _fit(pts, size):
    from attneave.stimuli.render import fit_to_image

    return fit_to_image(pts, size, margin=0.08 * size)["points"]


def shoelace(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def perimeter(p):
    return float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))


def polygons(kind, n, seed):
    rng = np.random.default_rng(seed)
    make = {"blob": blob, "spiky": spiky}[kind]
    return [make(rng, 500, SIZE) for _ in range(n)]


def steps():
    """The timed steps: name -> fn(points, path, image) returning an image or None."""
    import cv2

    from attneave.stimuli.render import render_silhouette, write_png

    def render(p):
        return render_silhouette(p, size=SIZE, dtype="uint8")["img"]

    def fill(p):
        img = np.full((SIZE, SIZE), 255, np.uint8)
        cv2.fillPoly(img, [np.round(p * 16).astype(np.int32)], 0, cv2.LINE_AA, shift=4)
        return img

    def imwrite(path, img):
        if not cv2.imwrite(path, img):
            raise OSError(f"cv2.imwrite failed: {path}")
        return img

    def atomic(path, img):
        write_png(path, img)
        return img

    return {
        "project+imwrite": lambda p, path, im: imwrite(path, render(p)),
        "opencv": lambda p, path, im: imwrite(path, fill(p)),
        "project": lambda p, path, im: atomic(path, render(p)),
        "opencv+write_png": lambda p, path, im: atomic(path, fill(p)),
        "render only": lambda p, path, im: render(p),
        "fillPoly only": lambda p, path, im: fill(p),
        "imwrite(project)": lambda p, path, im: imwrite(path, im["render only"]),
        "imwrite(opencv)": lambda p, path, im: imwrite(path, im["fillPoly only"]),
        "imencode(project)": lambda p, path, im: cv2.imencode(".png", im["render only"])[1],
    }


def matplotlib_step():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Polygon

    fig = plt.figure(figsize=(SIZE / 100, SIZE / 100), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    ax.set_xlim(-0.5, SIZE - 0.5)
    ax.set_ylim(SIZE - 0.5, -0.5)

    def mpl(p, path, im):
        patch = Polygon(p, closed=True, facecolor="black", edgecolor="none", antialiased=True)
        ax.add_patch(patch)
        fig.savefig(path, dpi=100, facecolor="white")
        patch.remove()

    return mpl, lambda: plt.close(fig)


def run(kind, n, seed, tmp):
    import cv2

    polys = polygons(kind, n, seed)
    methods = steps()
    mpl, close = matplotlib_step()
    methods["matplotlib"] = mpl
    names = list(methods)
    # the imwrite-only steps need their image made first, so they are not rotated
    rotating = [m for m in names if not m.startswith(("imwrite(", "imencode("))]
    wall = {m: [] for m in names}
    cpu = {m: [] for m in names}
    offsets = {m: [] for m in names}
    for i, p in enumerate(polys):
        made = {}
        k = i % len(rotating)
        order = rotating[k:] + rotating[:k] + ["imwrite(project)", "imwrite(opencv)", "imencode(project)"]
        for m in order:
            path = os.path.join(tmp, f"{m.replace(' ', '_')}_{i % 8}.png")
            t0, c0 = time.perf_counter(), time.thread_time()
            img = methods[m](p, path, made)
            c1, t1 = time.thread_time(), time.perf_counter()
            wall[m].append(t1 - t0)
            cpu[m].append(c1 - c0)
            made[m] = img
            if i < 50 and m in ("project+imwrite", "opencv", "project", "opencv+write_png", "matplotlib"):
                if img is None:
                    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
                cov = 1.0 - img.astype(float) / 255.0
                offsets[m].append((cov.sum() - shoelace(p)) / perimeter(p))
    close()
    report(kind, polys, names, wall, cpu, offsets)


def report(kind, polys, names, wall, cpu, offsets):
    w = {m: 1e3 * float(np.median(v)) for m, v in wall.items()}
    c = {m: 1e3 * float(np.median(v)) for m, v in cpu.items()}
    print(f"\n{kind}: {len(polys)} polygons x 500 vertices, {SIZE}x{SIZE}, 8-bit PNG; "
          f"mean perimeter {np.mean([perimeter(p) for p in polys]):.0f} px; load average "
          f"{os.getloadavg()[0]:.2f}")
    print(f"{'step':<18}{'wall ms':>9}{'cpu ms':>9}{'offset px':>11}   (medians over images)")
    for m in names:
        off = f"{np.mean(offsets[m]):>+11.4f}" if offsets[m] else f"{'':>11}"
        print(f"{m:<18}{w[m]:>9.3f}{c[m]:>9.3f}{off}")
    print("(offset: mean over the first 50 images of (coverage sum - area) / perimeter)")
    for label, t in (("wall", w), ("cpu", c)):
        print(f"{label}: project+imwrite / opencv = {t['project+imwrite'] / t['opencv']:.2f} "
              f"(target <= {TARGET}); matplotlib / project+imwrite = "
              f"{t['matplotlib'] / t['project+imwrite']:.1f}x (target >= 5); "
              f"project / opencv+write_png = {t['project'] / t['opencv+write_png']:.2f}")
    r, f = c["render only"], c["fillPoly only"]
    wp, wo = c["imwrite(project)"], c["imwrite(opencv)"]
    print(f"split (cpu ms): render {r:.3f}, fillPoly {f:.3f}, imwrite {wp:.3f} (project's "
          f"image) / {wo:.3f} (OpenCV's); (R + W) / (F + W) = {(r + wp) / (f + wo):.2f}")
    print(f"  the encoder alone (cv2.imencode, in memory): {c['imencode(project)']:.3f} ms cpu, "
          f"{w['imencode(project)']:.3f} ms wall; imwrite waits {w['imwrite(project)'] - c['imwrite(project)']:.3f}"
          " ms (wall - cpu) for the file system, which flatters the wall-clock ratio")
    print("  with a faster PNG encoder: " + ", ".join(
        f"W x {s:g} -> {(r + s * wp) / (f + s * wo):.2f}" for s in (0.5, 0.25)))


def instructions(kind, n, seed):
    """Instructions per image of each step, by callgrind (n images minus 0)."""
    if shutil.which("valgrind") is None:
        print("\n--instructions: valgrind not found (apt-get install valgrind)")
        return
    print(f"\n{kind}: instructions per image (valgrind --tool=callgrind, {n} images "
          "minus none, in fresh processes)")
    counts = {}
    for step in ("render only", "fillPoly only", "project+imwrite", "opencv"):
        ir = []
        for k in (0, n):
            with tempfile.TemporaryDirectory() as d:
                cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={d}/cg.out",
                       sys.executable, os.path.abspath(__file__), "--kind", kind,
                       "--seed", str(seed), "--only", step, "--n", str(k)]
                res = subprocess.run(cmd, capture_output=True, text=True,
                                     env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
                found = re.search(r"Collected : (\d+)", res.stderr)
                if res.returncode or not found:
                    print(f"  {step}: callgrind failed: {res.stderr.strip().splitlines()[-1:]}")
                    return
                ir.append(int(found.group(1)))
        counts[step] = (ir[1] - ir[0]) / n
        print(f"  {step:<18}{counts[step] / 1e6:>9.2f} M instructions")
    print(f"  ratio project+imwrite / opencv = "
          f"{counts['project+imwrite'] / counts['opencv']:.2f}; render / fillPoly = "
          f"{counts['render only'] / counts['fillPoly only']:.1f}")


def only(kind, n, seed, step):
    """Run one step on n images (what --instructions runs under valgrind)."""
    polys = polygons(kind, max(n, 1), seed)[:n]
    fn = steps()[step]
    tmp = tempfile.mkdtemp(prefix="bench_render_")
    try:
        fn(polys[0] if polys else polygons(kind, 1, seed)[0], os.path.join(tmp, "w.png"), {})
        for p in polys:
            fn(p, os.path.join(tmp, "x.png"), {})
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000, help="images per method (default 1000)")
    ap.add_argument("--kind", choices=["blob", "spiky", "both"], default="both")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--instructions", type=int, default=0, metavar="K",
                    help="also count instructions per image under callgrind over K images")
    ap.add_argument("--only", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    kinds = ["blob", "spiky"] if args.kind == "both" else [args.kind]
    if args.only:
        only(kinds[0], args.n, args.seed, args.only)
        return
    header("bench_render: exact-coverage rendering + PNG vs cv2.fillPoly(LINE_AA) + imwrite")
    from attneave.stimuli.render import KERNEL

    print(f"renderer: attneave.stimuli.render.KERNEL = {KERNEL!r} (ATTNEAVE_NUMPY_RENDER=1 forces 'numpy')")
    tmp = tempfile.mkdtemp(prefix="bench_render_")
    try:
        for kind in kinds:
            run(kind, args.n, args.seed, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for kind in kinds if args.instructions else []:
        instructions(kind, args.instructions, args.seed)


if __name__ == "__main__":
    main()
