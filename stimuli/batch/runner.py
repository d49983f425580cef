"""Run a batch config: plan recipe calls, run them, write a stimulus set.

The output directory (see docs/design.md, "Files", and :mod:`attneave.stimuli.stimulus_set`)
ends up holding exactly::

    manifest.csv            one row per stimulus, sorted by stimulus_id
    config.yaml             the resolved config and the package version
    images/<id>.png         (and images/<id>.svg when output.svg is true)
    contours/<id>.csv       columns x, y in image pixels (y down)

and nothing else of ours (files of the user's own are left alone), byte for
byte the same for the same config whatever the number of workers, the
scheduler, or interruptions on the way.

How that is kept
----------------
* Jobs (one recipe call each) have ids and seeds that do not depend on the
  order in which they run, and each writes its files atomically and then
  journals its manifest rows (:mod:`attneave.stimuli.batch.job`).
* One ``generate`` at a time writes a directory: it holds a lock there
  (:func:`attneave.stimuli.batch.outdir.locked`); a second is refused.
* Before any stimulus, a marker ``.attneave-batch`` holding the SHA-256 of the
  resolved config is written. A rerun into the same directory with the same
  config skips complete jobs and makes the rest; a directory made by another
  config is refused unless ``force=True`` (which deletes the files the
  earlier batch listed, and only those). At the end the parent writes
  ``manifest.csv`` and ``config.yaml`` (after flushing everything to disk
  once, so that a manifest that survives a power cut lists only files that
  survived it) and removes ``.rows/``, the marker, the lock and the
  temporary files an interrupted write left behind.
* A config that does not validate writes nothing. An error inside a recipe
  call (e.g. an unreadable image, or a bug: :class:`BatchError`) stops the
  batch; a directory that this run created is then removed again, and one
  that existed keeps its complete stimuli (the message says which). A full
  disk (an ``OSError``) stops it too but keeps what is complete: the rerun
  completes it.
* A stimulus that may be poor (an outline taken from an image that the
  extraction's verdict calls ``suspect``) is made, and its reasons are
  written to the manifest's ``warning`` column and returned in
  :attr:`BatchResult.warnings`.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

from attneave.stimuli.batch import outdir
from attneave.stimuli.batch.config import ResolvedBatch, load_config
from attneave.stimuli.batch.execution import execute
from attneave.stimuli.batch.job import ROWS_DIR, plan_jobs
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import DISK_ERRORS, atomic_write, check_output_spares_inputs, make_output_dir
from attneave.stimuli.stimulus_set import write_manifest

__all__ = ["BatchError", "BatchResult", "run_batch", "identical_repeats", "DISK_ERRORS"]

# errors of the disk rather than of the input: the batch stops, keeps what is complete, exit 1


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
    warnings : list of (str, str)
        ``(stimulus_id, warning)`` of every stimulus that may be poor (its
        manifest ``warning`` column), in manifest order.
    notes : list of str
        Warnings about whole conditions: repeats that came out identical
        (:func:`identical_repeats`).
    """

    directory: Path
    n_stimuli: int
    n_jobs: int
    n_run: int
    seconds: float
    warnings: list = field(default_factory=list)
    notes: list = field(default_factory=list)


def identical_repeats(out, rows):
    """One warning per condition whose repeats all gave the same contours.

    A generator that draws no random numbers with the given parameters (a
    superformula, ``from_csv``, ``from_image``, a radial-frequency pattern
    of amplitude 0, a guided set on such a base) makes every repeat of a
    cell the same stimulus: the set holds copies that an analysis would
    count as different stimuli. Repeats are compared by their contour files'
    bytes (the same shape is written byte for byte the same).

    Parameters
    ----------
    out : Path
        The set's directory.
    rows : list of dict
        Its manifest rows (``batch_condition``, ``cell``, ``rep``,
        ``stimulus_id``, ``contour``).

    Returns
    -------
    list of str
    """
    import hashlib
    from collections import defaultdict

    cells = defaultdict(lambda: defaultdict(list))
    for row in rows:
        cells[(row["batch_condition"], row["cell"])][row["rep"]].append(row)
    alike = defaultdict(list)  # condition -> (cells whose repeats are identical, repeats)
    for (cond, cell), reps in cells.items():
        if len(reps) < 2:
            continue
        made = set()
        for rs in reps.values():
            files = sorted(rs, key=lambda r: r["stimulus_id"])
            made.add(tuple(hashlib.sha256((Path(out) / r["contour"]).read_bytes()).hexdigest() for r in files))
        if len(made) == 1:
            alike[cond].append(len(reps))
    return [f"condition {cond!r}: its {n[0]} repeats are identical in {len(n)} of its cells (the generator draws no "
            f"random numbers with these parameters): copies, not new stimuli; use repeats: 1"
            for cond, n in alike.items()]


def run_batch(config, out_dir, workers=1, scheduler=None, resume=False, force=False, progress=None, stages=None):
    """Generate the stimulus set of a batch config.

    Parameters
    ----------
    config : str, Path or ResolvedBatch
        The YAML config file, or an already resolved one.
    out_dir : str or Path
        The stimulus-set directory. Created if needed.
    workers : int
        Local worker processes (1 runs in this process); no more processes
        than jobs are started. Ignored with `scheduler`.
    scheduler : str or dask.distributed.Client, optional
        Run the jobs on a Dask distributed scheduler at this address (the
        workers must see `out_dir` at the same path). Needs the ``dask``
        extra: ``pip install 'attneave[dask]'``.
    resume : bool
        Insist that `out_dir` holds an earlier run of the same config (an
        error otherwise). Without it, such a directory is completed anyway.
    force : bool
        Delete an earlier batch's files in `out_dir` (those its manifest or
        journals list, its ``manifest.csv`` and ``config.yaml``) and start
        afresh. Other files in `out_dir` are left alone.
    progress : bool or None
        Show a tqdm progress bar on stderr; None shows it when stderr is a
        terminal.
    stages : attneave.stimuli.progress.Stages, optional
        Told of every finished recipe call (its lines reach a log as well).

    Returns
    -------
    BatchResult

    Raises
    ------
    InputError
        A config that does not validate (nothing is written), a directory
        that holds another batch (without `force`) or that another run is
        writing, nothing to resume (with `resume`), bad worker or scheduler
        settings, or bad input met by a recipe.
    OSError
        The disk is full (or failing) or the directory became unwritable;
        what was complete is kept, and the rerun completes the set.
    """
    t0 = time.perf_counter()
    batch = config if isinstance(config, ResolvedBatch) else load_config(config)
    if resume and force:
        raise InputError("--resume and --force contradict each other; give one")
    if scheduler is None and (not isinstance(workers, int) or workers < 1):
        raise InputError(f"--workers must be a positive integer, got {workers!r}")
    if str(out_dir) == "":
        raise InputError("-o: empty output path; name a directory")
    out = Path(out_dir)
    _check_spares_inputs(batch, out, force)
    created = not out.exists()
    make_output_dir(out)
    held = False
    try:
        with outdir.locked(out):
            held = True
            rows, n_jobs, n_run = _run_locked(batch, out, workers, scheduler, resume, force, progress, stages)
    except InputError:
        if created and held:  # only this run wrote there
            shutil.rmtree(out, ignore_errors=True)
        raise
    except Exception as exc:
        if isinstance(exc, OSError) and exc.errno in DISK_ERRORS:
            raise  # the disk: what is complete is kept, the rerun completes it
        # a bug, not the input: never leave a half-written directory without saying so
        if created and held:
            shutil.rmtree(out, ignore_errors=True)
            fate = f"nothing was written ({out} was removed)"
        else:
            fate = (f"{out} keeps the stimuli completed so far; once the cause is fixed, rerun the same command "
                    "(or with --resume) to complete the set, or use --force to start again")
        raise BatchError(f"{exc}; {fate}") from exc
    warnings = [(row["stimulus_id"], row["warning"]) for row in rows if row.get("warning")]
    return BatchResult(directory=out, n_stimuli=len(rows), n_jobs=n_jobs, n_run=n_run,
                       seconds=time.perf_counter() - t0, warnings=warnings, notes=identical_repeats(out, rows))


class BatchError(RuntimeError):
    """An unexpected error (a bug) stopped a batch; the message says what became of the directory."""


def _check_spares_inputs(batch, out, force):
    """Refuse an output directory whose batch files would overwrite or delete one of the batch's inputs.

    The inputs are the config file and the files its recipes read (``path``
    parameters). ``force`` deletes an earlier batch's files, so with it the
    directory may hold no input at all (:func:`attneave.stimuli.io.check_output_spares_inputs`);
    without it, no input may be one of the files the batch writes there
    (``config.yaml``, ``manifest.csv``, ``images/``, ``contours/``), except
    the set's own resolved ``config.yaml`` run again (it is written back
    byte for byte).
    """
    inputs = [batch.source] if Path(batch.source).is_file() else []
    inputs += sorted({p for c in batch.conditions for p in c.path_map if os.path.isabs(p)})
    if force:
        check_output_spares_inputs(out, inputs)
        return
    root = Path(os.path.realpath(out))
    ours = {root / "config.yaml", root / "manifest.csv"}
    for item in inputs:
        src = Path(os.path.realpath(item))
        if src == root / "config.yaml" and item == batch.source:
            with contextlib.suppress(OSError):
                if src.read_bytes() == batch.text.encode("utf-8"):
                    continue  # the set's resolved config, run again: written back as it is
        if src == root or src in ours or src.parent in (root / "images", root / "contours"):
            raise InputError(f"-o {out}: the batch would overwrite one of its inputs ({item}) there; "
                             "choose another output directory")


def _run_locked(batch, out, workers, scheduler, resume, force, progress, stages=None):
    """The batch, once this process holds the directory: (stimuli, jobs, jobs run)."""
    outdir.check_inside(out)
    state = outdir.inspect(out, batch)
    if state in ("other", "unknown") and not force:
        what = ("was made by another config (or another attneave version)" if state == "other"
                else "holds images/, contours/ or a manifest not made by this config")
        raise InputError(f"{out}: {what}; use --force to replace that batch, or choose another directory")
    if resume and state not in ("partial", "complete"):
        raise InputError(f"{out}: nothing to resume (no batch of this config there)")
    jobs = plan_jobs(batch)
    if force:
        outdir.remove_previous(out)
    try:
        for sub in ("images", "contours", ROWS_DIR):
            (out / sub).mkdir(parents=True, exist_ok=True)
        if not (out / outdir.MARKER).exists():
            with atomic_write(out / outdir.MARKER, "w", encoding="utf-8") as fh:
                fh.write(f"attneave batch in progress\nconfig_sha256: {batch.sha256}\n")
    except OSError as exc:
        if exc.errno in DISK_ERRORS:
            raise
        raise InputError(f"{out}: cannot write there ({exc.strerror or exc})") from None

    results = outdir.completed(out, jobs)
    pending = [j for j in jobs if j["key"] not in results]
    if pending:
        for key, rows in execute(pending, out, workers, scheduler, progress, len(jobs), len(results)):
            results[key] = rows
            if stages is not None:
                stages.advance()

    ids = {}
    for job in jobs:
        for row in results[job["key"]]:
            if row["stimulus_id"] in ids:
                raise InputError(
                    f"{batch.source}: stimulus id {row['stimulus_id']!r} made by both {ids[row['stimulus_id']]}"
                    f" and {job['key']}; rename a condition"
                )
            ids[row["stimulus_id"]] = job["key"]
    rows = sorted((row for job in jobs for row in results[job["key"]]), key=lambda r: r["stimulus_id"])
    # the stimulus files are renamed into place but not flushed one by one (that
    # costs ms per file); flush them all once, so that a manifest that survives a
    # power cut lists only files that survived it too
    if hasattr(os, "sync"):
        os.sync()
    write_manifest(out / "manifest.csv", rows)
    with atomic_write(out / "config.yaml", "w", fsync=True, encoding="utf-8", newline="\n") as fh:
        fh.write(batch.text)
    shutil.rmtree(out / ROWS_DIR, ignore_errors=True)
    outdir.remove_temporaries(out)
    with contextlib.suppress(FileNotFoundError):
        os.unlink(out / outdir.MARKER)
    return rows, len(jobs), len(pending)
