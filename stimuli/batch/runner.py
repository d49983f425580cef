"""Run a batch config: plan recipe calls, run them in parallel, write a stimulus set.

The output directory (see DESIGN.md, "Files") ends up holding exactly::

    manifest.csv            one row per stimulus, sorted by stimulus_id
    config.yaml             the resolved config and the package version
    images/<id>.png         (and images/<id>.svg when output.svg is true)
    contours/<id>.csv       columns x, y in image pixels (y down)

and nothing else of ours, byte for byte the same for the same config whatever
the number of workers, the scheduler, or interruptions on the way.

How that is kept
----------------
* A *job* is one recipe call: condition ``c``, grid cell ``k``, repeat ``r``.
  Its id prefix is ``<name>_<kkk>_<rrr>`` (zero-padded to at least 3 digits)
  and its seed comes from :func:`stimuli.config.stimulus_seed`, never from the
  order in which workers pick jobs up. A recipe call may return several items
  (e.g. ``base``/``concave``/``convex``); item ``s`` gets the id
  ``<prefix>_<s>``, or ``<prefix>`` when its suffix is empty.
* Every file is written atomically (temporary name, then rename). A job writes
  its images and contours first and then appends its manifest rows as one
  JSON line to a journal of its own process and thread,
  ``.rows/<host>-<pid>-<thread>.jsonl`` (one file per writer, so lines never
  interleave; a line cut short by a kill is ignored); a job is complete when
  its line is there and every file it names exists. One journal per writer
  rather than one file per job saves two file-system operations per job,
  which on this kind of disk cost more than making the stimulus.
* Before any stimulus, a marker ``.attneave-batch`` holding the SHA-256 of the
  resolved config is written. A rerun into the same directory with the same
  config skips complete jobs and makes the rest; a directory made by another
  config is refused unless ``force=True`` (which deletes the earlier batch's
  files first). At the end the parent writes ``manifest.csv`` and
  ``config.yaml`` (after flushing everything to disk once, so that a manifest
  that survives a power cut lists only files that survived it) and removes
  ``.rows/``, the marker and any temporary file an interrupted write left
  behind.
* A config that does not validate writes nothing. An error inside a recipe
  call (e.g. an unreadable image) stops the batch; a directory that this run
  created is then removed again.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import re
import shutil
import socket
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from stimuli.batch.config import ResolvedBatch, load_config, manifest_json, stimulus_seed
from stimuli.errors import InputError
from stimuli.io import atomic_write

__all__ = ["BatchResult", "plan_jobs", "run_batch", "run_job", "MANIFEST_COLUMNS"]

MARKER = ".attneave-batch"
ROWS_DIR = ".rows"
MANIFEST_COLUMNS = (
    "stimulus_id", "image", "contour", "svg", "width", "height", "generator", "seed", "params",
    "condition", "parent_id", "batch_condition", "cell", "rep", "style",
)
_OURS = ("images", "contours", "manifest.csv", "config.yaml", MARKER, ROWS_DIR)
_SUFFIX_RE = re.compile(r"[A-Za-z0-9_.-]*")
_TMP_RE = re.compile(r"^\..+\.tmp(\.[A-Za-z0-9]+)?$")
# Test hook: seconds each job sleeps, so that a test can kill a batch mid-way.
_DELAY_ENV = "ATTNEAVE_BATCH_JOB_DELAY"


@dataclass
class BatchResult:
    """What :func:`run_batch` did.

    Attributes
    ----------
    directory : Path
    n_stimuli : int
        Rows in the manifest.
    n_jobs : int
        Recipe calls in the batch.
    n_run : int
        Recipe calls made by this run (the others were complete already).
    seconds : float
        Wall time of this run (not written to any file).
    """

    directory: Path
    n_stimuli: int
    n_jobs: int
    n_run: int
    seconds: float


# --------------------------------------------------------------------------- planning


def plan_jobs(batch):
    """List the recipe calls of a resolved batch, in a fixed order.

    Parameters
    ----------
    batch : ResolvedBatch

    Returns
    -------
    list of dict
        Plain, picklable job descriptions: ``key`` (the id prefix),
        ``condition``, ``index``, ``cell``, ``rep``, ``seed``, ``recipe``,
        ``params`` (as the recipe gets them), ``style``, ``canvas``,
        ``output`` and ``path_map``.
    """
    jobs = []
    for cond in batch.conditions:
        wk = max(3, len(str(len(cond.cells) - 1)))
        wr = max(3, len(str(cond.repeats - 1)))
        for k, params in enumerate(cond.cells):
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
                    "style": cond.style,
                    "canvas": cond.canvas,
                    "output": batch.output,
                    "path_map": cond.path_map,
                })
    return jobs


# --------------------------------------------------------------------------- one job


def run_job(job, out_dir):
    """Make one recipe call and write its files; return its manifest rows.

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
    import numpy as np

    from stimuli.batch import recipes
    from stimuli.batch.config import _jsonable, _unmap_paths
    from stimuli.render import write_png

    delay = os.environ.get(_DELAY_ENV)
    if delay:
        time.sleep(float(delay))

    out = Path(out_dir)
    model, fn = recipes.RECIPES[job["recipe"]]
    params = model.model_validate(job["params"])
    canvas = recipes.Canvas(**job["canvas"])
    style = recipes.Style.model_validate(job["style"])
    rng = np.random.default_rng(job["seed"])
    items = fn(params, rng, canvas)

    key = job["key"]
    suffixes = [it.suffix for it in items]
    if len(set(suffixes)) != len(suffixes) or not all(_SUFFIX_RE.fullmatch(s) for s in suffixes):
        raise RuntimeError(f"recipe {job['recipe']!r} returned bad or repeated item suffixes {suffixes!r}")

    def sid(suffix):
        return f"{key}_{suffix}" if suffix else key

    style_json = manifest_json(job["style"])
    svg = bool(job["output"].get("svg"))
    rows = []
    for it in items:
        stim = sid(it.suffix)
        image = f"images/{stim}.png"
        contour = f"contours/{stim}.csv"
        write_png(out / image, recipes.draw_item(it, style, canvas), job["output"]["png_bit_depth"])
        row = {"stimulus_id": stim, "image": image, "contour": contour}
        if svg:
            row["svg"] = f"images/{stim}.svg"
            text = recipes.item_svg(it, style, canvas)
            with atomic_write(out / row["svg"], "w", encoding="utf-8", newline="\n") as fh:
                fh.write(text)
        it.contour.to_csv(out / contour)
        if it.parent_suffix is not None and it.parent_suffix not in suffixes:
            raise RuntimeError(f"recipe {job['recipe']!r}: item {it.suffix!r} names a parent "
                               f"{it.parent_suffix!r} it did not return")
        row.update({
            "width": str(canvas.width),
            "height": str(canvas.height),
            "generator": job["recipe"],
            "seed": str(job["seed"]),
            "params": manifest_json(_unmap_paths(_jsonable(it.params), job["path_map"])),
            "condition": it.condition or job["condition"],
            "parent_id": sid(it.parent_suffix) if it.parent_suffix is not None else "",
            "batch_condition": job["condition"],
            "cell": str(job["cell"]),
            "rep": str(job["rep"]),
            "style": style_json,
        })
        rows.append(row)
    line = json.dumps({"job": key, "rows": rows}, sort_keys=True) + "\n"
    with open(_journal(out), "a", encoding="utf-8") as fh:
        fh.write(line)  # one write of one line, after the job's files are in place
    return rows


def _journal(out):
    host = re.sub(r"[^A-Za-z0-9_.-]", "_", socket.gethostname())
    return out / ROWS_DIR / f"{host}-{os.getpid()}-{threading.get_ident()}.jsonl"


def _run_chunk(chunk, out_dir):
    return [(job["key"], run_job(job, out_dir)) for job in chunk]


def _init_worker():
    # one process per core: keep libraries from starting thread pools of their own
    with contextlib.suppress(Exception):
        import cv2

        cv2.setNumThreads(1)


# --------------------------------------------------------------------------- the batch


def run_batch(config, out_dir, workers=1, scheduler=None, resume=False, force=False, progress=None):
    """Generate the stimulus set of a batch config.

    Parameters
    ----------
    config : str, Path or ResolvedBatch
        The YAML config file, or an already resolved one.
    out_dir : str or Path
        The stimulus-set directory. Created if needed.
    workers : int
        Local worker processes (1 runs in this process). Ignored with
        `scheduler`.
    scheduler : str or dask.distributed.Client, optional
        Run the jobs on a Dask distributed scheduler at this address (the
        workers must see `out_dir` at the same path). Needs the ``dask``
        extra: ``pip install 'attneave[dask]'``.
    resume : bool
        Insist that `out_dir` holds an earlier run of the same config (an
        error otherwise). Without it, such a directory is completed anyway.
    force : bool
        Delete an earlier batch's files in `out_dir` (``images/``,
        ``contours/``, ``manifest.csv``, ``config.yaml``) and start afresh.
        Other files in `out_dir` are left alone.
    progress : bool or None
        Show a tqdm progress bar on stderr; None shows it when stderr is a
        terminal.

    Returns
    -------
    BatchResult

    Raises
    ------
    InputError
        A config that does not validate (nothing is written), a directory
        that holds another batch (without `force`), nothing to resume (with
        `resume`), bad worker or scheduler settings, or bad input met by a
        recipe.
    """
    t0 = time.perf_counter()
    batch = config if isinstance(config, ResolvedBatch) else load_config(config)
    if resume and force:
        raise InputError("--resume and --force contradict each other; give one")
    if scheduler is None and (not isinstance(workers, int) or workers < 1):
        raise InputError(f"--workers must be a positive integer, got {workers!r}")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")

    state = _inspect(out, batch)
    if state in ("other", "unknown") and not force:
        what = ("was made by another config (or another attneave version)" if state == "other"
                else "holds images/, contours/ or a manifest not made by this config")
        raise InputError(f"{out}: {what}; use --force to replace that batch, or choose another directory")
    if resume and state not in ("partial", "complete"):
        raise InputError(f"{out}: nothing to resume (no batch of this config there)")
    jobs = plan_jobs(batch)

    created = not out.exists()
    if force and not created:
        _remove_ours(out)
        state = "fresh"
    try:
        for sub in ("images", "contours", ROWS_DIR):
            (out / sub).mkdir(parents=True, exist_ok=True)
        if not (out / MARKER).exists():
            with atomic_write(out / MARKER, "w", encoding="utf-8") as fh:
                fh.write(f"attneave batch in progress\nconfig_sha256: {batch.sha256}\n")
    except OSError as exc:
        raise InputError(f"{out}: cannot write there ({exc.strerror or exc})") from None

    done = _completed(out, jobs, batch)
    pending = [j for j in jobs if j["key"] not in done]
    try:
        results = dict(done)
        if pending:
            for key, rows in _execute(pending, out, workers, scheduler, progress, len(jobs), len(done)):
                results[key] = rows
    except InputError:
        if created:
            shutil.rmtree(out, ignore_errors=True)
        raise

    rows = [row for job in jobs for row in results[job["key"]]]
    ids = {}
    for job in jobs:
        for row in results[job["key"]]:
            if row["stimulus_id"] in ids:
                raise InputError(
                    f"{batch.source}: stimulus id {row['stimulus_id']!r} made by both {ids[row['stimulus_id']]}"
                    f" and {job['key']}; rename a condition"
                )
            ids[row["stimulus_id"]] = job["key"]
    rows.sort(key=lambda r: r["stimulus_id"])
    # the stimulus files are renamed into place but not flushed one by one (that
    # costs ms per file); flush them all once, so that a manifest that survives a
    # power cut lists only files that survived it too
    if hasattr(os, "sync"):
        os.sync()
    _write_manifest(out / "manifest.csv", rows, bool(batch.output.get("svg")))
    with atomic_write(out / "config.yaml", "w", fsync=True, encoding="utf-8", newline="\n") as fh:
        fh.write(batch.text)
    shutil.rmtree(out / ROWS_DIR, ignore_errors=True)
    _remove_temporaries(out)
    with contextlib.suppress(FileNotFoundError):
        os.unlink(out / MARKER)
    return BatchResult(directory=out, n_stimuli=len(rows), n_jobs=len(jobs), n_run=len(pending),
                       seconds=time.perf_counter() - t0)


def _inspect(out, batch):
    """'fresh' | 'partial' | 'complete' | 'other' | 'unknown' (see run_batch)."""
    if not out.exists():
        return "fresh"
    marker = out / MARKER
    if marker.exists():
        text = marker.read_text(encoding="utf-8", errors="replace")
        return "partial" if f"config_sha256: {batch.sha256}" in text else "other"
    cfg = out / "config.yaml"
    if cfg.exists():
        return "complete" if cfg.read_bytes() == batch.text.encode("utf-8") else "other"
    if any((out / name).exists() for name in _OURS):
        return "unknown"
    return "fresh"


def _remove_ours(out):
    for name in _OURS:
        p = out / name
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        elif p.exists() or p.is_symlink():
            p.unlink()
    _remove_temporaries(out)


def _remove_temporaries(out):
    """Delete temporary files that an interrupted atomic write left behind."""
    for d in (out, out / "images", out / "contours"):
        if not d.is_dir():
            continue
        for entry in os.scandir(d):
            if entry.is_file(follow_symlinks=False) and _TMP_RE.match(entry.name):
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(entry.path)


def _completed(out, jobs, batch):
    """{job key: rows} of jobs whose rows and files all exist already."""
    keys = {j["key"] for j in jobs}
    found = {}
    rows_dir = out / ROWS_DIR
    if rows_dir.is_dir():
        for entry in os.scandir(rows_dir):
            if not entry.name.endswith(".jsonl"):
                continue
            try:
                with open(entry.path, encoding="utf-8", errors="replace") as fh:
                    lines = fh.read().splitlines()
            except OSError:
                continue
            for line in lines:
                try:
                    data = json.loads(line)
                    key, rows = data["job"], data["rows"]
                except (ValueError, KeyError, TypeError):
                    continue  # a line cut short by a kill: that job is simply made again
                if key in keys:
                    found[key] = rows
    manifest = out / "manifest.csv"
    if manifest.exists():
        by_triple = {(j["condition"], j["cell"], j["rep"]): j["key"] for j in jobs}
        grouped = {}
        try:
            with open(manifest, encoding="utf-8", newline="") as fh:
                for row in csv.DictReader(fh):
                    key = by_triple.get((row.get("batch_condition"), _int(row.get("cell")), _int(row.get("rep"))))
                    if key is not None:
                        grouped.setdefault(key, []).append({k: v for k, v in row.items() if k in MANIFEST_COLUMNS})
        except (OSError, csv.Error, UnicodeDecodeError):
            grouped = {}
        for key, rows in grouped.items():
            found.setdefault(key, rows)
    complete = {}
    for key, rows in found.items():
        if key in keys and rows and all(
            _nonempty(out / row[col]) for row in rows for col in ("image", "contour", "svg") if row.get(col)
        ):
            complete[key] = rows
    return complete


def _nonempty(p):
    try:
        return p.is_file() and p.stat().st_size > 0
    except OSError:
        return False


def _int(v):
    try:
        return int(v)
    except (TypeError, ValueError):
        return None


def _write_manifest(path, rows, svg):
    cols = [c for c in MANIFEST_COLUMNS if svg or c != "svg"]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n", extrasaction="ignore")
    w.writeheader()
    for row in rows:
        w.writerow(row)
    with atomic_write(path, "w", fsync=True, encoding="utf-8", newline="") as fh:
        fh.write(buf.getvalue())


# --------------------------------------------------------------------------- execution


def _chunks(jobs, slots):
    size = max(1, min(16, math.ceil(len(jobs) / (4 * max(1, slots)))))
    return [jobs[i:i + size] for i in range(0, len(jobs), size)]


def _execute(jobs, out, workers, scheduler, progress, total, initial):
    """Yield (key, rows) for every job, as they finish."""
    from tqdm import tqdm

    bar = tqdm(total=total, initial=initial, desc="generate", unit="call", file=sys.stderr,
               disable=(None if progress is None else not progress), dynamic_ncols=True)
    try:
        if scheduler is not None:
            yield from _execute_dask(jobs, out, scheduler, bar)
        elif workers == 1 or len(jobs) == 1:
            for job in jobs:
                yield job["key"], run_job(job, out)
                bar.update(1)
        else:
            yield from _execute_pool(jobs, out, workers, bar)
    finally:
        bar.close()


def _execute_pool(jobs, out, workers, bar):
    import multiprocessing
    from concurrent.futures import FIRST_EXCEPTION, ProcessPoolExecutor, wait

    ctx = None
    if sys.platform.startswith("linux"):
        # fork: workers start at once with everything imported, and the caller's
        # __main__ is not re-run (spawn and forkserver would need an
        # ``if __name__ == "__main__"`` guard in every script that calls this)
        ctx = multiprocessing.get_context("fork")
    out_s = str(out.resolve())
    ex = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker)
    try:
        futures = {ex.submit(_run_chunk, chunk, out_s): len(chunk) for chunk in _chunks(jobs, workers)}
        pending = set(futures)
        while pending:
            finished, pending = wait(pending, return_when=FIRST_EXCEPTION)
            for fut in finished:
                yield from fut.result()
                bar.update(futures[fut])
    except BaseException:
        # an error or Ctrl-C: stop at once rather than finish the queued chunks; a
        # worker killed mid-write leaves at most a temporary file, which the rerun removes
        _terminate_workers(ex)  # before shutdown(), which forgets the processes
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True)


def _terminate_workers(ex):
    if hasattr(ex, "terminate_workers"):  # Python >= 3.14
        with contextlib.suppress(Exception):
            ex.terminate_workers()
            return
    for proc in list((getattr(ex, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            proc.terminate()


def _execute_dask(jobs, out, scheduler, bar):
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise InputError(
            "--scheduler needs dask.distributed; install it with: pip install 'attneave[dask]'"
        ) from None
    own = not isinstance(scheduler, Client)
    if own:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    else:
        client = scheduler
    try:
        slots = max(1, sum(client.nthreads().values()))
        chunks = _chunks(jobs, slots)
        futures = client.map(_run_chunk, chunks, out_dir=str(out.resolve()), pure=False)
        sizes = {f.key: len(c) for f, c in zip(futures, chunks)}
        try:
            for fut in as_completed(futures):
                yield from fut.result()
                bar.update(sizes[fut.key])
        except BaseException:
            client.cancel(futures)
            raise
    finally:
        if own:
            client.close()
