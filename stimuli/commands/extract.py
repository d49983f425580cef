"""``attneave extract``: contours, curvature and surprisal of objects in images.

For every input image ``DIR/STEM.*`` is written (STEM = the file name
without its extension):

* ``STEM.contour.csv``: the sub-pixel outer contour, columns ``x, y`` in the
  image's pixels (x = column, y = row, y down, pixel centres at integers),
  closed (first point not repeated), counter-clockwise on the screen;
* ``STEM.surprisal.csv``: the columns of ``attneave surprisal`` (``i, s, t,
  x, y, turning_angle, curvature, surprisal, peak``) at n equally spaced
  points of the contour smoothed at sigma;
* ``STEM.overlay.png``: the image with the contour coloured by surprisal
  (dark blue low, red high) and the peaks circled;
* ``STEM.silhouette.png``: the contour rendered black on white with exact
  coverage at the image's size (by :mod:`stimuli.render.core`);
* ``STEM.holes.csv`` with ``--holes``: columns ``hole, x, y``.

With ``--objects all`` every object of at least ``--min-area`` pixels gets
its own ``STEM.K.contour.csv``, ``STEM.K.surprisal.csv``,
``STEM.K.silhouette.png`` (and ``STEM.K.holes.csv``), K = 0 for the largest,
1 for the next...; the overlay ``STEM.overlay.png`` shows them all.

``DIR/summary.csv`` has one row per input: ``image, status, reason,
n_points, perimeter, area`` (of the largest object), then ``n_objects,
method, polarity, level, sigma, n``. A file that cannot be used (unreadable,
no object, everything object) gets ``status = failed`` and the reason; the
others are still processed, and the exit status is then 1. Outputs that
an earlier run wrote for an input that now fails (``STEM.contour.csv``, ...)
are removed so that the directory agrees with ``summary.csv``; per-object
``STEM.K.*`` files are left alone (an input named ``STEM.K.png`` writes the
same names). Every file is written under a temporary name and renamed.
"""

from __future__ import annotations

import math

OUTPUT_KINDS = ("contour.csv", "surprisal.csv", "holes.csv", "overlay.png", "silhouette.png")
SUMMARY_COLUMNS = (
    "image", "status", "reason", "n_points", "perimeter", "area",
    "n_objects", "method", "polarity", "level", "sigma", "n",
)


def add_parser(sub):
    p = sub.add_parser(
        "extract",
        help="contours, curvature and surprisal of objects in photos and silhouettes",
        description=(
            "Extract the sub-pixel outer contour of the object in each image (PNG, JPEG, TIFF, BMP; "
            "grey, RGB, RGBA; 8 or 16 bit) and write, per input STEM: STEM.contour.csv (x, y in image "
            "pixels, y down), STEM.surprisal.csv (the columns of 'attneave surprisal'), "
            "STEM.overlay.png (the image with the contour coloured by surprisal, peaks circled), "
            "STEM.silhouette.png (black on white, exact coverage, the image's size); and "
            "summary.csv (image, status, reason, n_points, perimeter, area, ...). With --objects all "
            "the per-object files are STEM.0.*, STEM.1.*, ... (largest first). A file that fails is "
            "listed with status 'failed' and its reason; the exit status is then 1."
        ),
    )
    p.add_argument("images", nargs="+", metavar="IMAGE", help="image files (PNG, JPEG, TIFF, BMP)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory (created if needed)")
    p.add_argument(
        "--method", choices=("otsu", "threshold", "mask", "alpha", "grabcut"), default="otsu",
        help="otsu: one object on a plain background (default); threshold: a known edge grey level "
        "(--threshold); mask: a binary silhouette of either polarity; alpha: the alpha channel of a "
        "cut-out; grabcut: cluttered backgrounds (slow; --rect)",
    )
    p.add_argument("--threshold", type=float, default=None, metavar="V",
                   help="edge level in the image's units (method threshold) or alpha level (method alpha)")
    p.add_argument("--polarity", choices=("auto", "dark", "light"), default="auto",
                   help="which class is the object (default: the one touching the border less)")
    p.add_argument("--objects", choices=("largest", "all"), default="largest",
                   help="the largest object (default) or all of at least --min-area px (STEM.0, STEM.1, ...)")
    p.add_argument("--min-area", type=float, default=None, metavar="PX",
                   help="smallest object in pixels (default max(9, 1e-4 * image pixels))")
    p.add_argument("--holes", action="store_true", help="also trace holes: STEM.holes.csv, and cut them from the silhouette")
    p.add_argument("--rect", type=int, nargs=4, default=None, metavar=("X", "Y", "W", "H"),
                   help="grabcut initial rectangle (default: the image inset by 5%%)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-n", type=int, default=None, help="number of equally spaced surprisal points (default 100)")
    g.add_argument("--spacing", type=float, default=None, metavar="PX", help="spacing in pixels instead of -n")
    p.add_argument("--sigma", type=float, default=None, metavar="PX",
                   help="smoothing/curvature scale in px of arc length (default 1%% of the perimeter, >= 1 px)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--A", type=float, default=0.25, help="A' of the paper's form (default 0.25)")
    p.add_argument("--b", type=float, default=None, help="concentration b (default 1 paper, 4 vonmises)")
    p.add_argument("--bits", action="store_true", help="surprisal in bits instead of nats")
    p.add_argument("--workers", type=int, default=1, metavar="N", help="processes to use (default 1)")
    return p


def _check_args(args):
    from stimuli.errors import InputError

    if args.threshold is not None and not math.isfinite(args.threshold):
        raise InputError(f"--threshold must be a finite number, got {args.threshold}")
    if args.method == "threshold" and args.threshold is None:
        raise InputError("--method threshold needs --threshold V (the edge grey level in the image's units)")
    if args.n is not None and args.n < 3:
        raise InputError(f"-n must be >= 3, got {args.n}")
    if args.spacing is not None and not args.spacing > 0:
        raise InputError(f"--spacing must be > 0, got {args.spacing}")
    if args.sigma is not None and not args.sigma > 0:
        raise InputError(f"--sigma must be > 0, got {args.sigma}")
    if args.min_area is not None and not args.min_area >= 0:
        raise InputError(f"--min-area must be >= 0, got {args.min_area}")
    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if not args.A > 0:
        raise InputError(f"--A must be > 0, got {args.A}")
    if args.b is not None and not args.b >= 0:
        raise InputError(f"--b must be >= 0, got {args.b}")


def _stems(images, objects="largest"):
    from pathlib import Path

    from stimuli.errors import InputError

    seen = {}
    for img in images:
        stem = Path(img).stem
        if not stem or stem in (".", ".."):
            raise InputError(f"{img}: cannot name outputs after this file")
        if stem in seen:
            raise InputError(f"{seen[stem]} and {img} share the name {stem!r}; their outputs would collide")
        seen[stem] = img
    if objects == "all":
        # STEM.K.* of one image would be the outputs of an image named STEM.K
        for stem, img in seen.items():
            base, _, k = stem.rpartition(".")
            if k.isdigit() and base in seen:
                raise InputError(f"{seen[base]} and {img}: with --objects all, object {k} of {seen[base]} and "
                                 f"{img} would write the same files ({stem}.*)")
    return [Path(i).stem for i in images]


def _options(args):
    return dict(
        method=args.method, threshold=args.threshold, polarity=args.polarity, objects=args.objects,
        min_area=args.min_area, holes=args.holes, rect=args.rect, n=args.n, spacing=args.spacing,
        sigma=args.sigma, model=args.model, A=args.A, b=args.b, bits=args.bits,
    )


def run(args):
    from concurrent.futures import ProcessPoolExecutor
    from pathlib import Path

    from tqdm import tqdm

    from stimuli.errors import InputError
    from stimuli.io import write_table

    _check_args(args)
    stems = _stems(args.images, args.objects)
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")
    out.mkdir(parents=True, exist_ok=True)
    opts = _options(args)
    tasks = [(str(img), stem, str(out), opts) for img, stem in zip(args.images, stems)]
    rows = [None] * len(tasks)
    bar = tqdm(total=len(tasks), desc="extract", unit="image", disable=None)
    try:
        if args.workers == 1 or len(tasks) == 1:
            for i, task in enumerate(tasks):
                rows[i] = process_one(*task)
                bar.update()
        else:
            with ProcessPoolExecutor(max_workers=min(args.workers, len(tasks))) as pool:
                futures = {pool.submit(process_one, *task): i for i, task in enumerate(tasks)}
                from concurrent.futures import as_completed

                for fut in as_completed(futures):
                    rows[futures[fut]] = fut.result()
                    bar.update()
    finally:
        bar.close()
    write_table(_summary_frame(rows), out / "summary.csv")
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        import sys

        for r in failed:
            print(f"attneave extract: {r['image']}: failed: {r['reason']}", file=sys.stderr)
        return 1
    return 0


def _summary_frame(rows):
    """Summary table with numeric columns typed (empty cells for failed files)."""
    import numpy as np
    import pandas as pd

    df = pd.DataFrame([{c: r[c] for c in SUMMARY_COLUMNS} for r in rows], columns=list(SUMMARY_COLUMNS))
    for c in ("n_points", "perimeter", "area", "n_objects", "level", "sigma", "n"):
        df[c] = pd.to_numeric(df[c].replace("", np.nan), errors="coerce")
        if c in ("n_points", "n_objects", "n"):
            df[c] = df[c].astype("Int64")
    return df


def _remove_stale(outdir, stem, keep):
    """Remove this stem's outputs of an earlier run that this run did not write.

    Only names that no other input can produce are touched: ``STEM.KIND``
    (one object per image) and ``STEM.overlay.png``. Per-object files
    ``STEM.K.KIND`` of an earlier ``--objects all`` run are left alone,
    since an input named ``STEM.K.png`` writes the same names.
    """
    for kind in OUTPUT_KINDS:
        f = outdir / f"{stem}.{kind}"
        if f.name not in keep and f.is_file():
            f.unlink()


def process_one(image, stem, outdir, opts):
    """Extract, analyse and write the outputs of one image; return its summary row.

    Never raises for a bad image: the row then has ``status='failed'`` and
    the reason (an unexpected exception is reported as an internal error).
    """
    from pathlib import Path

    import numpy as np

    from stimuli.errors import InputError

    outdir = Path(outdir)
    row = {c: "" for c in SUMMARY_COLUMNS}
    row.update(image=image, method=opts["method"])
    try:
        files, info = _analyse(image, stem, opts)
        for name, writer in files.items():
            writer(outdir / name)
        _remove_stale(outdir, stem, set(files))
        row.update(info, status="ok")
    except InputError as exc:
        msg = str(exc)
        if msg.startswith(image + ": "):
            msg = msg[len(image) + 2 :]
        row.update(status="failed", reason=msg)
        _remove_stale(outdir, stem, set())
    except Exception as exc:  # noqa: BLE001 - one bad file must not stop a batch
        row.update(status="failed", reason=f"internal error: {type(exc).__name__}: {exc}")
        _remove_stale(outdir, stem, set())
    for k, v in row.items():
        if isinstance(v, (np.floating, np.integer)):
            row[k] = v.item()
    return row


def _analyse(image, stem, opts):
    """Everything in memory first; return ({file name: writer}, summary values)."""
    import numpy as np

    from stimuli.extraction.core import describe, extract, read_image
    from stimuli.render import render_silhouette

    img = read_image(image)
    ex = extract(
        img, method=opts["method"], threshold=opts["threshold"], polarity=opts["polarity"],
        objects=opts["objects"], min_area=opts["min_area"], holes=opts["holes"], rect=opts["rect"], name=image,
    )
    h, w = ex.mask.shape
    infos = [
        describe(c, n=opts["n"], spacing=opts["spacing"], sigma=opts["sigma"], model=opts["model"],
                 A=opts["A"], b=opts["b"], bits=opts["bits"])
        for c in ex.contours
    ]
    files = {}
    prefixes = [f"{stem}.{k}" for k in range(len(ex.contours))] if opts["objects"] == "all" else [stem]
    for pre, c, holes, info in zip(prefixes, ex.contours, ex.holes, infos):
        files[f"{pre}.contour.csv"] = c.to_csv
        files[f"{pre}.surprisal.csv"] = _table_writer(info.surprisal.table())
        sil = render_silhouette([c, *holes] if holes else c, shape=(h, w), figure=0.0, ground=1.0, dtype="uint8")
        files[f"{pre}.silhouette.png"] = _png_writer(sil["img"])
        if opts["holes"]:
            hole_ids = np.concatenate([np.full(len(hc), k) for k, hc in enumerate(holes)]) if holes else []
            pts = np.concatenate([hc.points for hc in holes]) if holes else np.empty((0, 2))
            files[f"{pre}.holes.csv"] = _table_writer({"hole": np.asarray(hole_ids, int), "x": pts[:, 0], "y": pts[:, 1]},
                                                      float_format="%.10g")
    files[f"{stem}.overlay.png"] = _png_writer(overlay(img, ex.contours, infos, ex.holes))
    c0, i0 = ex.contours[0], infos[0]
    summary = dict(
        reason="", n_points=c0.n, perimeter=c0.perimeter, area=c0.area, n_objects=len(ex.contours),
        polarity=ex.params["polarity"], level=ex.params.get("level"), sigma=i0.sigma, n=i0.params["n"],
    )
    return files, summary


def _table_writer(table, float_format="%.17g"):
    from stimuli.io import write_table

    return lambda path: write_table(table, path, float_format=float_format)


def _png_writer(img):
    from stimuli.render import write_png

    return lambda path: write_png(path, img)


def overlay(image, contours, infos, holes=None):
    """The image (as 8-bit RGB) with each contour coloured by surprisal and its peaks circled.

    Parameters
    ----------
    image : ndarray
        As read by :func:`stimuli.extract.read_image`.
    contours : list of Contour
        ``(x, y)`` image pixels (y down, pixel centres at integers).
    infos : list of stimuli.extract.ContourInfo
        Their surprisal (from :func:`stimuli.extract.describe`).
    holes : list of list of Contour, optional
        Drawn as black lines on a white halo (no surprisal).

    Returns
    -------
    (H, W, 3) uint8 ndarray, RGB
        Surprisal is mapped with the turbo colour map over each contour's
        own range (dark blue lowest, dark red highest; with one contour a
        colour bar in the top-left corner gives the values), on a thin white
        halo; peaks are white circles with a black rim.
    """
    import cv2
    import numpy as np

    rgb = _display_rgb(image)
    h, w = rgb.shape[:2]
    lw = max(2, int(round(min(h, w) / 200)))
    rad = max(3, int(round(min(h, w) / 100)))
    def colour_range(group):
        u = np.concatenate([i.surprisal.surprisal for i in group])
        lo, hi = float(np.min(u)), float(np.max(u))
        # a nearly constant surprisal (a circle) is shown as constant: the
        # scale spans at least the step from the mean turn to twice it (the
        # default peak prominence is 5 % of that)
        floor = max((i.params.get("prominence") or 0.0) for i in group) / 0.05
        span = max(hi - lo, floor)
        return lo, (span if span > 0 else 1.0)

    # objects of different sizes have different spacings (and the paper's
    # surprisal scales with spacing^2): each object gets its own scale
    ranges = [colour_range([i]) for i in infos]
    lut = cv2.applyColorMap(np.arange(256, dtype=np.uint8)[:, None], cv2.COLORMAP_TURBO)[:, 0, ::-1]
    shift = 4  # sub-pixel drawing: coordinates in 1/16 px
    scale = 1 << shift
    for c, info, (lo, span) in zip(contours, infos, ranges):
        res = info.surprisal
        u = res.surprisal
        # colour each stretch of the contour by the surprisal at its arc position
        t = c.t()
        tu = np.append(res.t, 1.0)
        uu = np.append(u, u[0])
        val = np.interp(t, tu, uu)
        idx = np.clip(((val - lo) / span * 255).round().astype(int), 0, 255)
        p = np.round(np.vstack([c.points, c.points[:1]]) * scale).astype(np.int32)
        # draw runs of equal colour as polylines (fast even for long contours)
        # a white halo keeps the dark end of the colour map visible on dark images
        cv2.polylines(rgb, [p.reshape(-1, 1, 2)], True, (255, 255, 255), lw + 2, cv2.LINE_AA, shift)
        brk = np.flatnonzero(np.diff(idx)) + 1
        starts = np.concatenate([[0], brk])
        ends = np.concatenate([brk, [len(idx)]])
        for a, b in zip(starts, ends):
            col = tuple(int(v) for v in lut[idx[a]])
            cv2.polylines(rgb, [p[a : b + 1].reshape(-1, 1, 2)], False, col, lw, cv2.LINE_AA, shift)
        for k in res.peaks:
            x, y = res.contour.points[k]
            centre = (int(round(x * scale)), int(round(y * scale)))
            cv2.circle(rgb, centre, (rad + lw) * scale, (0, 0, 0), lw + 1, cv2.LINE_AA, shift)
            cv2.circle(rgb, centre, rad * scale, (255, 255, 255), lw, cv2.LINE_AA, shift)
    for hole in (h for hl in (holes or []) for h in hl):
        p = np.round(hole.points * scale).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(rgb, [p], True, (255, 255, 255), lw + 2, cv2.LINE_AA, shift)
        cv2.polylines(rgb, [p], True, (0, 0, 0), max(1, lw - 1), cv2.LINE_AA, shift)
    units = infos[0].params.get("units", "nats")
    if len(infos) == 1:
        lo, span = ranges[0]
        _legend(rgb, lut, f"{lo:.4g}", f"{lo + span:.4g} {units}")
    else:
        _legend(rgb, lut, "low", f"high {units} (per object)")
    return rgb


def _legend(rgb, lut, low, high):
    """A small colour bar with its end values in the top-left corner."""
    import cv2
    import numpy as np

    h, w = rgb.shape[:2]
    font = cv2.FONT_HERSHEY_SIMPLEX
    fs = float(np.clip(min(h, w) / 900, 0.3, 1.0))
    (tw0, th), _ = cv2.getTextSize(low, font, fs, 1)
    (tw1, _), _ = cv2.getTextSize(high, font, fs, 1)
    bar = int(np.clip(w // 5, 30, 200))
    total = tw0 + bar + tw1 + 20
    if total > w or 2 * th + 8 > h:
        return  # too small an image for a legend
    x0, y0 = 4, 4
    cv2.rectangle(rgb, (x0, y0), (x0 + total, y0 + th + 10), (255, 255, 255), -1)
    cv2.putText(rgb, low, (x0 + 4, y0 + th + 4), font, fs, (0, 0, 0), 1, cv2.LINE_AA)
    bx = x0 + tw0 + 10
    cols = lut[np.linspace(0, 255, bar).round().astype(int)]
    rgb[y0 + 3 : y0 + th + 7, bx : bx + bar] = cols[None, :, :]
    cv2.putText(rgb, high, (bx + bar + 6, y0 + th + 4), font, fs, (0, 0, 0), 1, cv2.LINE_AA)


def _display_rgb(image):
    """8-bit RGB copy of an image for drawing on (alpha composited over white)."""
    import numpy as np

    img = np.asarray(image)
    if img.dtype == bool:
        img = img.astype(np.uint8) * 255
    f = img.astype(np.float64)
    if img.dtype == np.uint8:
        scale = 255.0
    elif img.dtype == np.uint16:
        scale = 65535.0
    else:
        lo, hi = float(f.min()), float(f.max())
        f = (f - lo) / (hi - lo if hi > lo else 1.0)
        scale = 1.0
    f = f / scale
    if f.ndim == 2:
        f = np.repeat(f[:, :, None], 3, axis=2)
    elif f.shape[2] == 1:
        f = np.repeat(f, 3, axis=2)
    elif f.shape[2] == 2:
        f = np.concatenate([np.repeat(f[:, :, :1], 3, axis=2), f[:, :, 1:]], axis=2)
    if f.shape[2] == 4:
        a = f[:, :, 3:4]
        f = f[:, :, :3] * a + (1.0 - a)
    return np.ascontiguousarray(np.clip(np.round(f[:, :, :3] * 255), 0, 255).astype(np.uint8))
