"""Validate outline extraction on real photographs with ground-truth masks.

Data: a directory of ``NAME.jpg`` photos (or ``.jpeg``, ``.png``, ``.bmp``,
``.tif``) with ``NAME.mask.png`` masks of the same size (object > 127),
e.g. ``../shared/data/photos`` (Weizmann horses and GrabCut/GSC objects;
see its README). Photos without a mask, or whose mask is unreadable, of
another size or empty, are named on stderr and skipped. Groups are the
name's prefix before the first ``_`` (``weizmann``, ``gsc``), or its
leading letters when it has none (``horse001`` -> ``horse``).

Per photo and per mode:

* ``auto``: ``extract(photo, method='auto')``, no help;
* ``box``: one box per image, the mask's bounding box plus a 5 % margin on
  every side (as a person would draw it), ``extract(photo, boxes=[box])``;
* ``grabcut``: the anchor, plain ``cv2.grabCut`` with the same box and 5
  iterations on the raw photo (its mask taken as it is), its random start
  seeded (0) as attneave seeds its own: GrabCut's answer depends on it;
* ``model`` and ``model-box``: ``method='model'`` with the network given by
  ``--model-file`` (and ``--model-size``, ``--model-mean``,
  ``--model-std``), without and with the box;
* ``rembg`` and ``rembg-box``: ``method='rembg'``, rembg's network
  ``--rembg-model`` (default ``isnet-general-use``) with the weights rembg
  has, or those of ``--model-file``, without and with the box.

IoU: the extracted outline rendered with exact coverage
(``attneave.stimuli.render.coverage``) and thresholded at 0.5, against the mask;
the mean boundary distance (px) is the symmetric mean distance between the
two masks' boundary pixels. The verdict (``attneave.stimuli.extraction.verdict``)
of every outline is recorded: the share of outlines marked ``ok`` with IoU
>= 0.8 and the smallest IoU among them say whether ``ok`` can be trusted.

Prints per group and mode: n, median and mean IoU, share >= 0.8 and
< 0.5, mean boundary distance, ok share and its precision; then per
group, mode and half (``A``/``B``: alternate photos of each group in name
order, one half to tune on and the other to check) the median IoU, the ok
share, the ok precision (IoU >= 0.8) and the smallest IoU among ok. With
``--csv`` writes one row per photo and mode (the verdict's measures and
the half included), for ``benchmarks/calibrate_verdict.py``; it is
rewritten after every photo, so that a long run stopped early leaves the
photos measured so far.

With ``--holes`` the outlines' holes are traced too
(``extract(..., holes=True)``) and IoU counts the outline's inside less
its holes (the verdict then measures the object's own pixels).

Usage: python benchmarks/validate_photos.py [DATA_DIR] [--limit K] [--csv OUT.csv] [--modes auto,box,grabcut]
       [--workers N] [--progress] [--holes] [--model-file NET.onnx --model-size PX --model-mean M,M,M --model-std S,S,S]
       [--rembg-model NAME]
"""

from __future__ import annotations

import argparse
import itertools
import re
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import header  # noqa: E402

DEFAULT_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "photos"
#: The verdict's measures recorded per photo and mode.
MEASURES = ("frame", "fill", "contrast", "competing", "agreement", "colour_error", "edge_support", "box_contact",
            "box_gap", "uncertainty")
#: The modes of a learned network: method and whether the box is given.
LEARNED_MODES = {"model": ("model", False), "model-box": ("model", True), "rembg": ("rembg", False),
                 "rembg-box": ("rembg", True)}


def halves(names):
    """'A' or 'B' for each photo name: alternate photos of each group (:func:`group_of`) in name order."""
    seen = {}
    out = {}
    for n in sorted(names):
        group = group_of(n)
        out[n] = "AB"[seen.get(group, 0) % 2]
        seen[group] = seen.get(group, 0) + 1
    return out


def ok_figures(g):
    """(ok share, ok precision (IoU >= 0.8), smallest IoU among ok) of a table's rows, '-' where undefined."""
    ok = g[g.status == "ok"]
    if not len(ok):
        return f"{0:.2f}", "-", "-"
    return f"{len(ok) / len(g):.2f}", f"{(ok.iou >= 0.8).mean():.2f}", f"{ok.iou.min():.2f}"


def iou(a, b):
    return float(np.count_nonzero(a & b) / max(np.count_nonzero(a | b), 1))


def boundary_distance(a, b):
    """Symmetric mean distance (px) between the boundary pixels of two masks."""
    import cv2

    def edge(m):
        m8 = m.astype(np.uint8)
        return m8.astype(bool) & ~cv2.erode(m8, np.ones((3, 3), np.uint8)).astype(bool)

    ea, eb = edge(a), edge(b)
    if not ea.any() or not eb.any():
        return float("nan")
    da = cv2.distanceTransform((~eb).astype(np.uint8), cv2.DIST_L2, 5)
    db = cv2.distanceTransform((~ea).astype(np.uint8), cv2.DIST_L2, 5)
    return float(0.5 * (da[ea].mean() + db[eb].mean()))


def plain_grabcut(rgb, box, iterations=5, seed=0):
    """Plain cv2.grabCut from the box; `seed` fixes its random start (k-means of the colour models),
    which otherwise depends on what ran before in the thread."""
    import cv2

    cv2.setRNGSeed(seed)
    gc = np.zeros(rgb.shape[:2], np.uint8)
    bgd, fgd = np.zeros((1, 65)), np.zeros((1, 65))
    try:
        cv2.grabCut(np.ascontiguousarray(rgb[:, :, ::-1]), gc, box, bgd, fgd, iterations, cv2.GC_INIT_WITH_RECT)
    except cv2.error:
        return np.zeros(rgb.shape[:2], bool)
    return (gc == cv2.GC_FGD) | (gc == cv2.GC_PR_FGD)


#: Photo formats read from the data directory (any case); each photo's mask is ``STEM.mask.png``.
PHOTO_SUFFIXES = (".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff")


def photos_to_measure(program, data, limit=None):
    """:func:`photo_pairs` of directory `data` (the first `limit`), or None after one line on stderr
    when `data` is no directory or holds no pair."""
    data = Path(data)
    if not data.is_dir():
        print(f"{program}: {data}: not a directory", file=sys.stderr)
        return None
    photos = photo_pairs(data, report=sys.stderr)[:limit]
    if not photos:
        print(f"{program}: no NAME.jpg + NAME.mask.png pairs in {data}", file=sys.stderr)
        return None
    return photos


def photo_pairs(data, report=None):
    """The photos of a directory that have a mask beside them (``NAME.jpg`` + ``NAME.mask.png``), by name.

    Photos in any of :data:`PHOTO_SUFFIXES`; the masks themselves are not
    photos. Photos without a mask are skipped and, with `report` (a file),
    counted there with the first few names, never dropped silently."""
    data = Path(data)
    photos = sorted(p for p in data.iterdir() if p.is_file() and p.suffix.lower() in PHOTO_SUFFIXES
                    and not p.name.lower().endswith(".mask.png"))
    paired = [p for p in photos if (data / f"{p.stem}.mask.png").is_file()]
    lone = [p.name for p in photos if p not in paired]
    if lone and report is not None:
        print(f"validate_photos: {len(lone)} photo(s) without a STEM.mask.png skipped: {', '.join(lone[:5])}"
              + (" ..." if len(lone) > 5 else ""), file=report)
    return paired


def group_of(name):
    """A photo's group: its name's prefix before the first '_' (``weizmann_horse001`` -> ``weizmann``), or
    its leading letters when it has no '_' (``horse001`` -> ``horse``)."""
    stem = Path(name).stem
    if "_" in stem:
        return stem.split("_")[0]
    letters = re.match(r"[^\W\d_]*", stem).group(0)
    return letters or stem


def map_tasks(fn, tasks, workers=1, chunksize=1):
    """``fn(*task)`` for every task, in order, in `workers` processes (in this one when 1)."""
    if workers > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(workers) as pool:
            yield from pool.map(fn, *zip(*tasks), chunksize=chunksize)
    else:
        for task in tasks:
            yield fn(*task)


def _progress(args, got):
    if args.progress and got:
        print(f"{got[0]['image']}: " + ", ".join(f"{r['mode']} {r['iou']:.3f} {r['status']}" for r in got),
              file=sys.stderr, flush=True)


def measure_photo(path, modes, holes=False, model=None, seed=0, rembg=None):
    """Rows (one per mode) of IoU, distance, verdict and time for one photo and its mask.

    With `holes`, the outline's holes are traced too and the object is the
    outline's inside less its holes' insides. `model` holds the network's
    options (``model_file``, ``size``, ``mean``, ``std``) for the model modes, `rembg` the rembg network's
    (``network``, ``model_file``) for the rembg modes.
    `seed` seeds every GrabCut's random start, attneave's and the anchor's."""
    import importlib

    import cv2

    importlib.import_module("attneave.stimuli.extraction.figure_ground.grabcut").SEED = seed

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.extraction import extract, read_image
    from attneave.stimuli.extraction.figure_ground.photo import box_around
    from attneave.stimuli.extraction.verdict import judge
    from attneave.stimuli.render import coverage

    p = Path(path)
    rgb = read_image(p)
    truth = cv2.imread(str(p.with_name(f"{p.stem}.mask.png")), cv2.IMREAD_GRAYSCALE)
    if truth is None or truth.shape != rgb.shape[:2] or not (truth > 127).any():
        why = ("unreadable" if truth is None else f"{truth.shape[1]}x{truth.shape[0]}, the photo "
               f"{rgb.shape[1]}x{rgb.shape[0]}" if truth.shape != rgb.shape[:2] else "empty")
        print(f"validate_photos: {p.stem}.mask.png: {why}; photo skipped", file=sys.stderr)
        return []
    truth = truth > 127
    box = box_around(truth, 0.05)
    group = group_of(p.name)
    rows = []
    for mode in modes:
        t0 = time.perf_counter()
        row = dict(image=p.name, group=group, mode=mode, status="", reason="")
        if mode == "grabcut":
            pred = plain_grabcut(rgb, box, seed=seed)
        else:
            try:
                method, boxed = LEARNED_MODES.get(mode, ("auto", mode == "box"))
                ex = extract(rgb, method=method, boxes=[box] if boxed else None, holes=holes, name=p.name,
                             model={"model": model, "rembg": rembg}.get(method))
            except InputError as exc:
                row.update(status="failed", reason=str(exc), iou=0.0, seconds=time.perf_counter() - t0)
                rows.append(row)
                continue
            pred = coverage(ex.contour, truth.shape) >= 0.5
            for hole in ex.holes[0] if holes else ():
                pred &= coverage(hole, truth.shape) < 0.5
            v = judge(rgb, ex)
            row.update(status=v.status, reason=v.reason, resolved=ex.params.get("resolved"),
                       **{k: v.measures.get(k, ex.params.get(k)) for k in MEASURES})
        row.update(iou=iou(pred, truth), distance=boundary_distance(pred, truth), seconds=time.perf_counter() - t0)
        rows.append(row)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DIR))
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--csv", default=None, help="write one row per photo and mode here")
    ap.add_argument("--modes", default="auto,box,grabcut")
    ap.add_argument("--progress", action="store_true", help="one line per photo on stderr")
    ap.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    ap.add_argument("--holes", action="store_true",
                    help="trace the outlines' holes too; the object is the outline less its holes")
    ap.add_argument("--model-file", default=None, help="ONNX network for the modes model and model-box")
    ap.add_argument("--model-size", type=int, default=None, help="the network's input size (px)")
    ap.add_argument("--model-mean", default=None, help="per-channel mean, R,G,B on [0, 1] values")
    ap.add_argument("--model-std", default=None, help="per-channel std, R,G,B")
    ap.add_argument("--rembg-model", default=None, help="rembg network for the modes rembg and rembg-box "
                    "(default isnet-general-use; its weights from --model-file when given)")
    args = ap.parse_args(argv)

    import pandas as pd

    header("validate_photos: outlines from photographs against ground-truth masks")
    photos = photos_to_measure("validate_photos", args.data, args.limit or None)
    if photos is None:
        return 2
    modes = args.modes.split(",")
    model = {k: v for k, v in (("model_file", args.model_file), ("size", args.model_size),
                               ("mean", args.model_mean and [float(v) for v in args.model_mean.split(",")]),
                               ("std", args.model_std and [float(v) for v in args.model_std.split(",")]))
             if v is not None}
    if any(m.startswith("model") for m in modes) and "model_file" not in model:
        print("validate_photos: the modes model and model-box need --model-file", file=sys.stderr)
        return 2
    rembg = {"network": args.rembg_model, "model_file": args.model_file}
    rows = []
    t_start = time.perf_counter()
    # the groups in turn (a run stopped early has measured some photos of each), in name order within each
    by_group = {}
    for p in photos:
        by_group.setdefault(group_of(p.name), []).append(p)
    order = [p for batch in itertools.zip_longest(*by_group.values()) for p in batch if p is not None]
    tasks = [(str(p), modes, args.holes, model, 0, rembg) for p in order]
    for got in map_tasks(measure_photo, tasks, args.workers):
        rows += got
        _progress(args, got)
        if args.csv and rows:
            _write_csv(rows, args.csv)
    if not rows:
        print(f"validate_photos: no photo in {args.data} could be measured", file=sys.stderr)
        return 2
    df = pd.DataFrame(rows)
    df["half"] = df.image.map(halves(df.image.unique()))
    print(f"{df.image.nunique()} of {len(photos)} photos measured, {time.perf_counter() - t_start:.0f} s in all")
    print(f"{'group':10s} {'mode':9s} {'n':>3s} {'medIoU':>7s} {'meanIoU':>7s} {'>=0.8':>6s} {'<0.5':>6s} "
          f"{'dist px':>7s} {'ok':>5s} {'ok>=0.8':>7s} {'ok min':>6s}")
    for (group, mode), g in df.groupby(["group", "mode"], sort=True):
        okshare, prec, okmin = ok_figures(g) if mode != "grabcut" else ("-", "-", "-")
        print(f"{group:10s} {mode:9s} {len(g):3d} {g.iou.median():7.3f} {g.iou.mean():7.3f} "
              f"{(g.iou >= 0.8).mean():6.2f} {(g.iou < 0.5).mean():6.2f} {g.distance.median():7.2f} "
              f"{okshare:>5s} {prec:>7s} {okmin:>6s}")
    print(f"\nper half\n{'group':10s} {'mode':9s} {'half':4s} {'n':>3s} {'medIoU':>7s} {'ok':>5s} {'ok>=0.8':>7s} "
          f"{'ok min':>6s}")
    for (group, mode, half), g in df.groupby(["group", "mode", "half"], sort=True):
        okshare, prec, okmin = ok_figures(g) if mode != "grabcut" else ("-", "-", "-")
        print(f"{group:10s} {mode:9s} {half:4s} {len(g):3d} {g.iou.median():7.3f} {okshare:>5s} {prec:>7s} {okmin:>6s}")
    if args.csv:
        _write_csv(rows, args.csv)
    return 0


def _write_csv(rows, path):
    """The rows so far, with their halves, written atomically (a run stopped early keeps what it measured)."""
    import os

    import pandas as pd

    df = pd.DataFrame(rows)
    df["half"] = df.image.map(halves(df.image.unique()))
    tmp = f"{path}.part"
    df.to_csv(tmp, index=False)
    os.replace(tmp, path)


if __name__ == "__main__":
    sys.exit(main())
