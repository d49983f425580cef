"""The per-image pipeline of ``attneave extract``: extract, describe, write, summarise.

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
  coverage at the image's size (by :mod:`attneave.stimuli.render`);
* ``STEM.holes.csv`` with ``holes``: columns ``hole, x, y``.

With ``objects='all'`` every object of at least ``min_area`` pixels gets
its own ``STEM.K.contour.csv``, ``STEM.K.surprisal.csv``,
``STEM.K.silhouette.png`` (and ``STEM.K.holes.csv``), K = 0 for the largest,
1 for the next...; the overlay ``STEM.overlay.png`` shows them all.

``DIR/summary.csv`` has one row per input (:data:`SUMMARY_COLUMNS`) with
its verdict (:mod:`attneave.stimuli.extraction.verdict`): ``status`` ``ok``,
``suspect`` (the outline was written, but ``reason`` names why it may be
wrong: frame contact, low contrast, fill, competing regions, disagreeing
hypotheses, decoder warnings; the overlay says so too) or ``failed`` (no
outline: unreadable, too large, no object, everything object), and the
measures behind it (``frame``, ``fill``, ``contrast``, ``agreement``; for
photographs ``colour_error``, ``edge_support``, ``box_contact``), and
``resolved``, the method ``auto`` chose. Reasons are always one line. A
failed file does not stop the others.
Outputs that an earlier run wrote for an input and this run did not
(``STEM.contour.csv`` after a switch to ``objects='all'``, or for an input
that now fails) are removed so that the directory agrees with
``summary.csv``. Per-object ``STEM.K.*`` files are removed only when the
earlier run's ``summary.csv`` in the directory shows that run wrote them
for this input (``objects='all'``, at least K + 1 objects); otherwise they
may be the outputs of an input named ``STEM.K.png`` and are left, and
:func:`extract_images` returns their names in ``summary.attrs['left']``
(the command says so on stderr). Every file is written under a
temporary name and renamed.

``summary.csv`` is written last: a directory without it is the output of a
run that was stopped (a signal, ``kill -9``, a power cut); running the same
command again completes it, processing only the images without a complete
record (:mod:`attneave.stimuli.extraction.corpus`), with files
byte-identical to those of an uninterrupted run (the earlier summary is
removed when a run starts, so a stopped rerun never leaves an old summary
beside new files).

Option mistakes are refused before any image is processed (one line, an
:class:`~attneave.stimuli.errors.InputError`): an option for another method
(``threshold`` without method threshold or alpha, ``rect`` without
grabcut, ``boxes`` without auto, photo, model or rembg, ``scribbles`` without
auto or photo, ``model_*`` without model (``model_file`` also with rembg),
``rembg_model`` without rembg), a ``rect`` outside an image, a model file
that does not load, a rembg network that is not installed or whose weights
are not on this machine, an output directory that cannot be made or
whose outputs would overwrite an input.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction.segment import OPTION_METHODS
from attneave.stimuli.extraction.verdict import PHOTO_MEASURES

__all__ = ["OUTPUT_KINDS", "SUMMARY_COLUMNS", "OPTION_METHODS", "output_stems", "check_options", "extract_images",
           "process_one", "summary_frame"]

OUTPUT_KINDS = ("contour.csv", "surprisal.csv", "holes.csv", "overlay.png", "silhouette.png")
SUMMARY_COLUMNS = (
    "image", "status", "reason", "n_points", "perimeter", "area",
    "n_objects", "method", "polarity", "level", "sigma", "n",
    "resolved", "frame", "fill", "contrast", "agreement", "thickness", *PHOTO_MEASURES,
)
#: Options of :func:`extract_images` and their defaults.
DEFAULTS = dict(
    method="auto", threshold=None, polarity="auto", objects="largest", min_area=None, holes=False, rect=None,
    n=None, spacing=None, sigma=None, model="paper", A=0.25, b=None, bits=False, boxes=None, scribbles=None,
    model_file=None, model_size=None, model_mean=None, model_std=None, rembg_model=None, max_pixels=None,
)
# OPTION_METHODS: the methods each method-specific option applies to (any other method refuses
# it), the same rule as the Python API's (:func:`attneave.stimuli.extraction.segment.check_method_options`)


def output_stems(images, objects="largest"):
    """The output name (file stem) of every image; raises if two would collide.

    Parameters
    ----------
    images : list of str or Path
    objects : {'largest', 'all'}
        With 'all', ``STEM.K`` of one image must not be another image's stem.

    Returns
    -------
    list of str

    Raises
    ------
    InputError
        Two inputs whose outputs would have the same names.
    """
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


def extract_images(images, output, workers=1, progress=None, stages=None, scheduler=None, as_frame=True,
                   **options):
    """Extract, describe and write the outputs of every image; write ``summary.csv``.

    Parameters
    ----------
    images : list of str or Path
        Image files (PNG, JPEG, TIFF, BMP).
    output : str or Path
        Output directory, created if needed.
    workers : int
        Processes to use (default 1); the files written do not depend on it.
    scheduler : str or dask.distributed.Client, optional
        Distribute the images over Dask workers (``tcp://host:8786``); they
        must see the images and `output` at the same paths. The files are
        byte-identical to those of ``workers=1``.
    progress : bool or None
        Show a progress bar on stderr (None: only on a terminal).
    stages : attneave.stimuli.progress.Stages, optional
        Told of every finished image (its lines reach a log as well).
    as_frame : bool
        Return the summary as a DataFrame (True, default; read back from
        ``summary.csv``) or a :class:`attneave.stimuli.extraction.corpus.CorpusResult`
        (counts and the first failures: memory does not grow with the
        number of images).
    **options
        Any of :data:`DEFAULTS` (the parameters of
        :func:`attneave.stimuli.extraction.extract` and :func:`attneave.stimuli.extraction.describe`).

    Returns
    -------
    pandas.DataFrame or CorpusResult
        The summary, one row per input in input order (as written to
        ``summary.csv``).

        ``summary.attrs['left']`` lists the per-object files of an earlier
        run that were left (see the module notes).

    Raises
    ------
    InputError
        Colliding output names, an output directory that cannot be made or
        whose outputs would overwrite an input, an unknown option, an
        option for another method (:func:`check_options`), a model file
        that does not load.
    """
    from tqdm import tqdm

    from attneave.stimuli.io import make_output_dir
    unknown = set(options) - set(DEFAULTS)
    if unknown:
        raise InputError(f"unknown extraction option(s): {', '.join(sorted(unknown))}")
    opts = {**DEFAULTS, **options}
    stems = output_stems(images, opts["objects"])
    check_options(opts, images)
    inputs = [str(i) for i in images]
    if opts["boxes"] is not None and not isinstance(opts["boxes"], dict):
        from attneave.stimuli.extraction.figure_ground.assists import read_boxes

        inputs.append(str(opts["boxes"]))
        opts["boxes"] = read_boxes(opts["boxes"], [str(i) for i in images], opts["objects"])
    if opts["scribbles"] is not None and not isinstance(opts["scribbles"], dict):
        from attneave.stimuli.extraction.figure_ground.assists import scribble_files

        opts["scribbles"] = scribble_files(opts["scribbles"], [str(i) for i in images])
    inputs += [str(f) for f in (opts["scribbles"] or {}).values()]
    if opts["method"] == "model":
        from attneave.stimuli.extraction.figure_ground.model import load_model

        load_model(opts["model_file"])  # a file that is no usable network is refused before any image
        inputs.append(str(opts["model_file"]))
    if opts["method"] == "rembg":
        from attneave.stimuli.extraction.figure_ground.learned import load_network

        load_network(opts["rembg_model"], opts["model_file"])  # rembg missing, weights absent: before any image
        if opts["model_file"]:
            inputs.append(str(opts["model_file"]))
    out = make_output_dir(output)
    _check_spares_inputs(out, stems, inputs)
    ours = _earlier_objects(out, stems)
    # summary.csv is written last and marks a complete directory: the earlier run's goes first,
    # so that a run stopped midway leaves a directory without one (rerun to complete it), not an
    # old summary beside new files
    (out / "summary.csv").unlink(missing_ok=True)
    from attneave.stimuli.extraction.corpus import run_corpus

    bar = tqdm(total=len(stems), desc="extract", unit="image", disable=None if progress is None else not progress)
    try:
        result = run_corpus([str(i) for i in images], stems, out, opts, ours, workers=workers, scheduler=scheduler,
                            stages=stages, bar=bar, process_one=process_one, summary_frame=summary_frame,
                            output_kinds=OUTPUT_KINDS)
    finally:
        bar.close()
    # per-object names left by an earlier run, unless an input of this run writes them
    stem_set = set(stems)
    result.left = sorted(f for f in result.left if _prefix(f) not in stem_set)
    if not as_frame:
        return result
    import pandas as pd

    summary = summary_frame(pd.read_csv(out / "summary.csv", dtype=str, keep_default_na=False).to_dict("records"))
    summary.attrs["left"] = result.left
    return summary


def _prefix(name):
    """``STEM.K`` of an output file name ``STEM.K.KIND``."""
    kind = next(k for k in OUTPUT_KINDS if name.endswith("." + k))
    return name[: -len(kind) - 1]


def check_options(opts, images=()):
    """Refuse options that do not apply to the method, or a rectangle outside an image (one line).

    Parameters
    ----------
    opts : dict
        The options of :func:`extract_images` (:data:`DEFAULTS` filled in).
    images : list of str or Path
        The inputs; a ``rect`` must fit in each one whose header gives its size.

    Raises
    ------
    InputError
        ``--OPTION applies to --method A or B only, not --method M``, or the
        rectangle and the image it does not fit.
    """
    from attneave.stimuli.extraction.figure_ground.grabcut import check_box
    from attneave.stimuli.extraction.imageio import header_size
    from attneave.stimuli.extraction.segment import check_method_options

    method = opts["method"]
    if method == "model" and not opts["model_file"]:
        raise InputError("--method model needs --model-file FILE.onnx")
    check_method_options(method, {k: opts.get(k) for k in OPTION_METHODS}, cli=True)
    if opts["rect"] is not None:
        rect = opts["rect"]
        try:
            x, y, w, h = (float(v) for v in rect)
        except (TypeError, ValueError):
            raise InputError(f"--rect must be four numbers X Y W H, got {rect!r}") from None
        if not (all(np.isfinite([x, y, w, h])) and x >= 0 and y >= 0 and w >= 2 and h >= 2):
            raise InputError(f"--rect {' '.join(f'{v:g}' for v in (x, y, w, h))}: expected X Y >= 0 and a width and "
                             "height W H of at least 2 px (the rectangle around the object, image pixels)")
        for img in images:
            size = header_size(img)
            if size is not None:
                check_box(rect, (size[1], size[0]), f"{img}: --rect", what="the rectangle")


def _check_spares_inputs(out, stems, inputs):
    """Refuse a run whose outputs in `out` would overwrite one of its inputs (one line)."""
    from attneave.stimuli.io import check_output_spares_inputs

    # a set, not one regular expression of every stem: that grows to megabytes over 100,000 images
    stem_set = set(stems)

    def ours(name):
        kind = next((k for k in OUTPUT_KINDS if name.endswith("." + k)), None)
        if kind is None:
            return False
        pre = name[: -len(kind) - 1]
        base, _, k = pre.rpartition(".")
        return pre in stem_set or (k.isdigit() and k.isascii() and base in stem_set)

    check_output_spares_inputs(out / "summary.csv", inputs)
    where = out.resolve()
    for item in inputs:
        p = Path(item)
        if p.resolve().parent == where and ours(p.name):
            check_output_spares_inputs(out / p.name, [item])


def _earlier_objects(out, stems):
    """Per stem, how many per-object files ``STEM.K.*`` the earlier run in `out` provably wrote.

    Its ``summary.csv`` must list an input of this stem with an outline
    (ok or suspect) and ``n_objects`` N, no input named ``STEM.K``, and
    ``STEM.contour.csv`` must be absent (a run with ``objects='all'``
    removes it; one with ``objects='largest'`` writes it): then that run
    wrote ``STEM.0.*`` to ``STEM.{N-1}.*``. Anything unreadable is no proof.
    """
    import csv

    try:
        with open(out / "summary.csv", newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except (OSError, UnicodeDecodeError, csv.Error):
        return {}
    earlier_stems = {Path(str(r.get("image") or "")).stem for r in rows}
    proof = {}
    for r in rows:
        stem = Path(str(r.get("image") or "")).stem
        if stem not in stems or r.get("status") not in ("ok", "suspect"):
            continue
        try:
            n = int(float(r.get("n_objects") or "nan"))
        except ValueError:
            continue
        if (out / f"{stem}.contour.csv").exists():
            continue
        n = next((k for k in range(n) if f"{stem}.{k}" in earlier_stems or f"{stem}.{k}" in stems), n)
        proof[stem] = max(proof.get(stem, 0), n)
    return proof


def summary_frame(rows):
    """Summary table with numeric columns typed (empty cells for failed files)."""
    import pandas as pd

    df = pd.DataFrame([{c: r[c] for c in SUMMARY_COLUMNS} for r in rows], columns=list(SUMMARY_COLUMNS))
    for c in ("n_points", "perimeter", "area", "n_objects", "level", "sigma", "n", "frame", "fill", "contrast",
              "agreement", "thickness", *PHOTO_MEASURES):
        df[c] = pd.to_numeric(df[c].replace("", np.nan), errors="coerce")
        if c in ("n_points", "n_objects", "n"):
            df[c] = df[c].astype("Int64")
    return df


def _remove_stale(outdir, stem, keep, earlier=0, names=None):
    """Remove this stem's outputs of an earlier run that this run did not write; list those left.

    ``STEM.KIND`` (one object per image, and ``STEM.overlay.png``) only
    this stem can produce: removed. Per-object files ``STEM.K.KIND`` are
    removed for ``K < earlier``, the objects the earlier run provably wrote
    for this stem (:func:`_earlier_objects`); others may be the outputs of
    an input named ``STEM.K.png`` and are left, and returned unless
    ``STEM.K.overlay.png`` shows that they are (no per-object overlay is
    written). `names`: the candidates ``STEM.K.*`` in `outdir` when the run
    started (default: list `outdir`, which costs its size for every image).

    Returns
    -------
    list of str
        The names of the per-object files left.
    """
    import re

    for kind in OUTPUT_KINDS:
        f = outdir / f"{stem}.{kind}"
        if f.name not in keep and f.is_file():
            f.unlink()
    # --objects all writes no per-object overlay: STEM.K.overlay.png is an input STEM.K's
    kinds = "|".join(re.escape(k) for k in OUTPUT_KINDS if k != "overlay.png")
    per_object = re.compile(rf"{re.escape(stem)}\.(\d+)\.(?:{kinds})")
    left = []
    if names is None:
        try:
            names = sorted(f.name for f in outdir.iterdir())
        except OSError:
            return left
    for name in names:
        m = per_object.fullmatch(name)
        if not m or name in keep or not (outdir / name).is_file():
            continue
        k = m.group(1)
        if int(k) < earlier and k == str(int(k)):
            (outdir / name).unlink()
        elif not (outdir / f"{stem}.{k}.overlay.png").exists():
            left.append(name)
    return left


def process_one(image, stem, outdir, opts):
    """Extract, analyse and write the outputs of one image; return its summary row.

    Never raises for a bad image: the row then has ``status='failed'`` and
    the reason (an unexpected exception is reported as an internal error).
    """
    outdir = Path(outdir)
    row = {c: "" for c in SUMMARY_COLUMNS}
    row.update(image=image, method=opts["method"])
    earlier = opts.get("_earlier", 0)
    written, done = set(), []
    try:
        files, info = _analyse(image, stem, opts)
        for name, writer in files.items():
            writer(outdir / name)
            done.append(name)
        written = set(files)
        row.update(info)
    except InputError as exc:
        msg = str(exc)
        if msg.startswith(image + ": "):
            msg = msg[len(image) + 2 :]
        row.update(status="failed", reason=msg)
    except Exception as exc:  # noqa: BLE001 - one bad file must not stop a batch
        row.update(status="failed", reason=f"internal error: {type(exc).__name__}: {exc}")
    if not written:  # a failed file has no outputs: not even those it wrote before failing
        for name in done:
            (outdir / name).unlink(missing_ok=True)
    row["_left"] = _remove_stale(outdir, stem, written, earlier, opts.get("_names"))
    row["_files"] = sorted(written)
    # a reason is one line of a CSV cell, whatever a library put in its message
    row["reason"] = " ".join(str(row["reason"]).split())[:500]
    for k, v in row.items():
        if isinstance(v, (np.floating, np.integer)):
            row[k] = v.item()
    return row


def _analyse(image, stem, opts):
    """Everything in memory first; return ({file name: writer}, summary values)."""
    from attneave.stimuli.extraction.imageio import MAX_PIXELS, open_image
    from attneave.stimuli.extraction.outlines import extract
    from attneave.stimuli.extraction.overlays import overlay
    from attneave.stimuli.extraction.scalespace import describe
    from attneave.stimuli.extraction.verdict import judge
    from attneave.stimuli.render import render_silhouette

    f = open_image(image, opts["max_pixels"] or MAX_PIXELS)
    img = f.image
    scribbles = None
    if opts["scribbles"] and image in opts["scribbles"]:
        from attneave.stimuli.extraction.figure_ground.photo import read_scribbles

        scribbles = read_scribbles(opts["scribbles"][image], img.shape[:2])
    model = None
    if opts["method"] == "model":
        model = {k: v for k, v in (("model_file", opts["model_file"]), ("size", opts["model_size"]),
                                   ("mean", opts["model_mean"]), ("std", opts["model_std"])) if v is not None}
    if opts["method"] == "rembg":
        model = {"network": opts["rembg_model"], "model_file": opts["model_file"]}
    ex = extract(
        img, method=opts["method"], threshold=opts["threshold"], polarity=opts["polarity"],
        objects=opts["objects"], min_area=opts["min_area"], holes=opts["holes"], rect=opts["rect"], name=image,
        boxes=(opts["boxes"] or {}).get(image), scribbles=scribbles, model=model,
    )
    verdict = judge(img, ex, f.warnings)
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
    files[f"{stem}.overlay.png"] = _png_writer(overlay(img, ex.contours, infos, ex.holes, verdict=verdict))
    c0, i0 = ex.contours[0], infos[0]
    m = verdict.measures
    summary = dict(
        status=verdict.status, reason=verdict.reason, n_points=c0.n, perimeter=c0.perimeter, area=c0.area,
        n_objects=len(ex.contours), polarity=ex.params["polarity"], level=ex.params.get("level"), sigma=i0.sigma,
        n=i0.params["n"], resolved=ex.params.get("resolved", ex.params["method"]), frame=m["frame"],
        fill=m["fill"], contrast=m["contrast"], agreement=m["agreement"], thickness=m["thickness"],
        **{k: "" if m[k] is None else m[k] for k in PHOTO_MEASURES},
    )
    return files, summary


def _table_writer(table, float_format="%.17g"):
    from attneave.stimuli.tables import write_table

    return lambda path: write_table(table, path, float_format=float_format)


def _png_writer(img):
    from attneave.stimuli.render import write_png

    return lambda path: write_png(path, img)
