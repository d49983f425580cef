"""One job of a batch: plan the recipe calls, make one and write its files.

A *job* is one recipe call: condition ``c``, grid cell ``k``, repeat ``r``.
Its id prefix is ``<name>_<kkk>_<rrr>`` (zero-padded to at least 3 digits)
and its seed comes from :func:`attneave.stimuli.batch.config.stimulus_seed`, never
from the order in which workers pick jobs up. A recipe call may return
several items (e.g. ``base``/``concave``/``convex``); item ``s`` gets the
id ``<prefix>_<s>``, or ``<prefix>`` when its suffix is empty.

A job writes its images and contours first (each atomically) and then
appends its manifest rows as one JSON line to a journal of its own process
and thread, ``.rows/<host>-<pid>-<thread>.jsonl`` (one file per writer, so
lines never interleave; a line cut short by a kill is ignored). One journal
per writer rather than one file per job saves two file-system operations
per job, which on this kind of disk cost more than making the stimulus.
"""

from __future__ import annotations

import json
import os
import re
import socket
import threading
from pathlib import Path

from attneave.stimuli.batch.config import record_paths, stimulus_seed
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import atomic_write
from attneave.stimuli.stimulus_set import encode_json, to_jsonable

__all__ = ["ROWS_DIR", "JobError", "plan_jobs", "run_job", "journal_path"]

ROWS_DIR = ".rows"
_SUFFIX_RE = re.compile(r"[A-Za-z0-9_.-]*")


def plan_jobs(batch):
    """List the recipe calls of a resolved batch, in a fixed order.

    Parameters
    ----------
    batch : ResolvedBatch

    Returns
    -------
    list of dict
        Picklable job descriptions: ``key`` (the id prefix), ``condition``,
        ``index``, ``cell``, ``rep``, ``seed``, ``recipe``, ``params`` (the
        validated parameter model the recipe gets), ``style`` (a validated
        Style), ``canvas`` (a Canvas), ``output``, ``path_map`` and
        ``degrees`` (the lengths given in degrees, or ``{}``).
    """
    jobs = []
    for cond in batch.conditions:
        wk = max(3, len(str(len(cond.cells) - 1)))
        wr = max(3, len(str(cond.repeats - 1)))
        for k, params in enumerate(cond.models):
            for r in range(cond.repeats):
                jobs.append({
                    "key": f"{cond.name}_{k:0{wk}d}_{r:0{wr}d}",
                    "condition": cond.name,
                    "index": cond.index,
                    "cell": k,
                    "rep": r,
                    "seed": stimulus_seed(batch.seed, cond.index, k, r),
                    "recipe": cond.recipe,
                    "params": params,
                    "style": cond.style_model,
                    "canvas": cond.canvas_model,
                    "output": batch.output,
                    "path_map": cond.path_map,
                    "degrees": cond.degrees[k] if cond.degrees else {},
                })
    return jobs


def run_job(job, out_dir):
    """Make one recipe call and write its files; return its manifest rows.

    Errors name the condition, the call and its seed: an InputError (bad
    input met by the recipe, a figure that would render blank) keeps its
    type; any other exception but an OSError (the disk) is a bug, raised
    again as a :class:`JobError` with the same words.

    The job's parameters, style and canvas were validated when the config
    was read; they are used as they are.

    Parameters
    ----------
    job : dict
        One entry of :func:`plan_jobs`.
    out_dir : str or Path
        The stimulus-set directory (``images/``, ``contours/`` and ``.rows/``
        must exist).

    Returns
    -------
    list of dict
        Manifest rows (all values strings), one per item the recipe returned.
    """
    where = f"condition {job['condition']!r}, call {job['key']} (seed {job['seed']})"
    try:
        return _run_job(job, out_dir)
    except InputError as exc:
        # the recipe names the parameter or file; say which condition and call met it
        raise InputError(f"{where}: {exc}") from None
    except (OSError, MemoryError):
        raise
    except Exception as exc:
        raise JobError(f"{where}: {type(exc).__name__}: {' '.join(str(exc).split())}") from exc


class JobError(RuntimeError):
    """An unexpected error (a bug, not the input) in one recipe call; the message names the call."""


def _run_job(job, out_dir):
    import numpy as np

    from attneave.stimuli.batch.drawing import render_item
    from attneave.stimuli.batch.recipes import RECIPES
    from attneave.stimuli.render import svg_text, write_png

    out = Path(out_dir)
    fn = RECIPES[job["recipe"]][1]
    canvas, style = job["canvas"], job["style"]
    items = fn(job["params"], np.random.default_rng(job["seed"]), canvas)

    key = job["key"]
    suffixes = [it.suffix for it in items]
    if len(set(suffixes)) != len(suffixes) or not all(_SUFFIX_RE.fullmatch(s) for s in suffixes):
        raise RuntimeError(f"recipe {job['recipe']!r} returned bad or repeated item suffixes {suffixes!r}")

    def sid(suffix):
        return f"{key}_{suffix}" if suffix else key

    style_json = encode_json(style.model_dump(mode="json", by_alias=True))
    svg = bool(job["output"].get("svg"))
    rows = []
    for it in items:
        stim = sid(it.suffix)
        image = f"images/{stim}.png"
        contour = f"contours/{stim}.csv"
        # one rendering gives the PNG, the SVG and the painted extent checked here
        drawn = render_item(it, style, canvas)
        img = drawn["img"]
        label = f"item {it.suffix!r}" if it.suffix else ""
        _check_visible(label, it, img, canvas)
        cut = _cut_off(drawn, canvas)
        if cut:
            it.warnings = list(it.warnings) + [cut]
        write_png(out / image, img, job["output"]["png_bit_depth"])
        row = {"stimulus_id": stim, "image": image, "contour": contour}
        if svg:
            row["svg"] = f"images/{stim}.svg"
            with atomic_write(out / row["svg"], "w", encoding="utf-8", newline="\n") as fh:
                fh.write(svg_text(drawn))
        it.contour.to_csv(out / contour)
        if it.parent_suffix is not None and it.parent_suffix not in suffixes:
            raise RuntimeError(f"recipe {job['recipe']!r}: item {it.suffix!r} names a parent "
                               f"{it.parent_suffix!r} it did not return")
        row.update({
            "width": str(canvas.width),
            "height": str(canvas.height),
            "generator": job["recipe"],
            "seed": str(job["seed"]),
            # what the image shows (silhouette, outline, fragments, ...): the row alone must say it
            # and the lengths given in degrees, with their pixels and the scale
            "params": encode_json(record_paths(to_jsonable({"draw": it.draw["mode"], **it.params, **(
                {"degrees": job["degrees"]} if job.get("degrees") else {})}), job["path_map"])),
            "condition": it.condition or job["condition"],
            "parent_id": sid(it.parent_suffix) if it.parent_suffix is not None else "",
            "batch_condition": job["condition"],
            "cell": str(job["cell"]),
            "rep": str(job["rep"]),
            "style": style_json,
        })
        if it.warnings:
            row["warning"] = _as_written(" | ".join(" ".join(str(w).split()) for w in it.warnings), job["path_map"])
        rows.append(row)
    line = json.dumps({"job": key, "rows": rows}, sort_keys=True) + "\n"
    with open(journal_path(out), "a", encoding="utf-8") as fh:
        fh.write(line)  # one write of one line, after the job's files are in place
    return rows


def _as_written(text, path_map):
    """`text` with absolute input paths put back as the config wrote them (files must not depend on
    where the config lives)."""
    for absolute in sorted(path_map, key=len, reverse=True):
        text = text.replace(absolute, path_map[absolute])
    return text


#: Smallest extent (px) of a figure on its canvas: below it the image shows a speck, not a shape.
MIN_FIGURE_EXTENT = 1.0


def _check_visible(label, item, img, canvas):
    """InputError when a stimulus would show no shape: a figure below 1 px, or an image of one colour."""
    label = f"{label}: " if label else ""
    x0, y0, x1, y1 = item.contour.bbox
    w, h = x1 - x0, y1 - y0
    if max(w, h) < MIN_FIGURE_EXTENT:
        raise InputError(f"{label}the figure is {w:.2g} x {h:.2g} px on the {canvas.width}x{canvas.height} "
                         f"canvas, below {MIN_FIGURE_EXTENT:g} px: its image would be blank; make it larger "
                         "(e.g. r0 or scale) or, for a size given in px, use placement: fit")
    if img.min() == img.max():
        raise InputError(f"{label}the image is blank (one colour everywhere): the figure lies outside the "
                         f"{canvas.width}x{canvas.height} canvas or is drawn in the ground's colour")


#: Slack (px) allowed beyond the image edge: round-off of a figure placed exactly at the edge (margin 0).
EDGE_TOLERANCE = 1e-6


def _cut_off(drawn, canvas):
    """Why the image cuts off part of what it paints (a warning), or "" when it does not.

    ``placement: fit`` puts the contour's bounding box inside the margins,
    but what is painted can reach beyond it: half a stroke's width (and its
    joins) around an outline, a dot's radius, a convex deformation made
    after placement. A cut-off figure is not the stimulus its contour file
    describes (its area, its outline), so it is flagged like any other poor
    stimulus: one line on stderr and the manifest's ``warning`` column.
    """
    from attneave.stimuli.batch.drawing import drawn_bbox

    box = drawn_bbox(drawn)
    if box is None:
        return ""
    x0, y0, x1, y1 = box
    w, h = canvas.width, canvas.height
    over = max(-0.5 - x0, -0.5 - y0, x1 - (w - 0.5), y1 - (h - 0.5))
    if not over > EDGE_TOLERANCE:
        return ""
    return (f"cut off by the canvas edge: the figure as drawn spans x {x0:.1f}..{x1:.1f}, y {y0:.1f}..{y1:.1f} px, "
            f"{over:.2f} px beyond the edge of the {w}x{h} image, so the image does not show the whole contour; "
            f"raise canvas.margin by more than {over:.2f} px (strokes, dots and deformations reach beyond the "
            f"contour's bounding box) or make the figure smaller")


def journal_path(out):
    """The journal of this process and thread in the set directory `out`."""
    host = re.sub(r"[^A-Za-z0-9_.-]", "_", socket.gethostname())
    return Path(out) / ROWS_DIR / f"{host}-{os.getpid()}-{threading.get_ident()}.jsonl"
