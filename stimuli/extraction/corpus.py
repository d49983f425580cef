"""``attneave extract`` over many images: local workers or Dask, resumable, summary streamed.

Every image is processed by :func:`attneave.stimuli.extraction.pipeline.process_one`
and then leaves a *record* in ``DIR/.extract-progress/``: ``STEM.row.csv``
(its ``summary.csv`` row, with the header) and, written last, atomically,
``STEM.done.json`` (a fingerprint of the image and the options, the files
written, status and reason). A record is the proof that the image's outputs
are complete: a rerun of the same command after an interruption (``kill
-9``, a power cut, a lost Dask worker) skips every image whose record
matches its fingerprint and whose files are all present, and processes the
rest. When all images are done ``summary.csv`` is made by concatenating the
rows in input order (never more than one row in memory), and the records
are removed: the directory is byte-identical to that of an uninterrupted
run with any number of workers or a Dask scheduler, because each image's
files depend on that image and the options only.

The fingerprint holds the image's path, size and modification time, and
the options that apply to it (its boxes and scribble file among them): an
image changed since, or a rerun with other options, is processed again.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["PROGRESS_DIR", "CorpusResult", "run_corpus"]

#: Subdirectory of the per-image records of a run not yet finished.
PROGRESS_DIR = ".extract-progress"


@dataclass
class CorpusResult:
    """What a run wrote: counts by status, the first failures, the per-object files left.

    Attributes
    ----------
    n : int
        Images.
    counts : dict
        ``{'ok': k, 'suspect': k, 'failed': k}``.
    failed : list of (str, str)
        The first ten failed images and their reasons (all are in ``summary.csv``).
    left : list of str
        Per-object files of an earlier run that were left (see :mod:`attneave.stimuli.extraction.pipeline`).
    resumed : int
        Images whose complete outputs an interrupted run had left.
    """

    n: int = 0
    counts: dict = field(default_factory=lambda: {"ok": 0, "suspect": 0, "failed": 0})
    failed: list = field(default_factory=list)
    left: list = field(default_factory=list)
    resumed: int = 0


def _fingerprint(image, opts):
    """A digest of the image file (path, size, mtime) and of the options that apply to it."""
    import hashlib

    def stat(p):
        try:
            st = os.stat(p)
            return [str(p), st.st_size, st.st_mtime_ns]
        except OSError:
            return [str(p), None, None]

    own = {k: v for k, v in opts.items() if k not in ("boxes", "scribbles", "_earlier")}
    if own.get("model_file"):
        own["model_file"] = stat(own["model_file"])
    boxes = (opts.get("boxes") or {}).get(image)
    scribble = (opts.get("scribbles") or {}).get(image)
    blob = json.dumps([stat(image), own, boxes, stat(scribble) if scribble else None], sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()


def _complete(rec_dir, out, stem, key):
    """The record of `stem` if it matches `key` and its files are all there, else None."""
    try:
        with open(rec_dir / f"{stem}.done.json", encoding="utf-8") as fh:
            rec = json.load(fh)
    except (OSError, ValueError):
        return None
    if rec.get("key") != key or not (rec_dir / f"{stem}.row.csv").is_file():
        return None
    if not all((out / name).is_file() for name in rec.get("files", ())):
        return None
    return rec


def _run_chunk(chunk, outdir, opts, process_one, summary_frame):
    """Process the images of `chunk` (``(index, image, stem, earlier, key)``); write each one's record last.

    Returns ``[(index, status, reason, left), ...]``.
    """
    from attneave.stimuli.io import atomic_write
    from attneave.stimuli.tables import write_table

    out = Path(outdir)
    rec_dir = out / PROGRESS_DIR
    done = []
    for index, image, stem, earlier, key, names in chunk:
        (rec_dir / f"{stem}.done.json").unlink(missing_ok=True)
        row = process_one(image, stem, outdir, {**opts, "_earlier": earlier, "_names": names})
        left = row.pop("_left", [])
        files = row.pop("_files", [])
        write_table(summary_frame([row]), rec_dir / f"{stem}.row.csv")
        rec = {"key": key, "files": files, "status": row["status"], "reason": row["reason"], "left": left}
        with atomic_write(rec_dir / f"{stem}.done.json", "w") as fh:
            json.dump(rec, fh)
        done.append((index, row["status"], row["reason"], left))
    return done


def _chunk_opts(opts, images):
    """`opts` with the per-image boxes and scribbles of `images` only (a chunk carries what it needs)."""
    sub = dict(opts)
    for k in ("boxes", "scribbles"):
        if opts.get(k):
            sub[k] = {i: opts[k][i] for i in images if i in opts[k]}
    return sub


def run_corpus(images, stems, out, opts, earlier, workers=1, scheduler=None, stages=None, bar=None, *,
               process_one, summary_frame, output_kinds):
    """Process every image not already done, then write ``summary.csv`` and remove the records.

    Parameters
    ----------
    images, stems : list of str
        Inputs and their output stems (checked by the caller).
    out : Path
        The output directory (made and checked by the caller).
    opts : dict
        The options, filled in.
    earlier : dict
        Per stem, the per-object files an earlier run provably wrote.
    workers : int
        Local worker processes.
    scheduler : str or dask.distributed.Client, optional
        Run on Dask (the workers must see `out` and the images at the same paths).
    stages : attneave.stimuli.progress.Stages, optional
        Told of every finished image.
    bar : tqdm, optional
        Updated for every finished image.
    process_one, summary_frame, output_kinds
        Those of :mod:`attneave.stimuli.extraction.pipeline` (passed in: it imports this module).

    Returns
    -------
    CorpusResult
    """
    from attneave.stimuli.dispatch import chunk_size, run_chunks
    from attneave.stimuli.io import remove_stale_temporaries

    rec_dir = out / PROGRESS_DIR
    rec_dir.mkdir(exist_ok=True)
    remove_stale_temporaries(rec_dir)
    result = CorpusResult(n=len(images))
    per_object = _per_object_names(out, stems, output_kinds)
    todo = []
    for i, (image, stem) in enumerate(zip(images, stems)):
        key = _fingerprint(image, opts)
        if _complete(rec_dir, out, stem, key) is None:
            todo.append((i, image, stem, earlier.get(stem, 0), key, per_object.get(stem, [])))
    result.resumed = len(images) - len(todo)
    if result.resumed:
        if stages is not None:
            stages.stage(f"resuming: {result.resumed} of {len(images)} image(s) already done")
            stages.advance(result.resumed)
        if bar is not None:
            bar.update(result.resumed)
    # one image per chunk in this process (a record after each); a few per chunk elsewhere, fewer
    # round trips; the files do not depend on it
    size = 1 if scheduler is None and workers <= 1 else chunk_size(len(todo), 8 if scheduler is not None else workers)
    chunks = ((todo[k:k + size], _chunk_opts(opts, [t[1] for t in todo[k:k + size]]))
              for k in range(0, len(todo), size))
    for done in run_chunks(_run_packed, chunks, workers=min(workers, max(1, len(todo))), scheduler=scheduler,
                           outdir=str(out.resolve()), process_one=process_one, summary_frame=summary_frame):
        if stages is not None:
            stages.advance(len(done))
        if bar is not None:
            bar.update(len(done))
    del todo
    _write_summary(out, rec_dir, stems, images, result)
    return result


def _per_object_names(out, stems, output_kinds):
    """Per stem, the names ``STEM.K.KIND`` in `out` now (one listing for the run, not one per image)."""
    import re

    kinds = "|".join(re.escape(k) for k in output_kinds)
    pattern = re.compile(rf"(.+)\.\d+\.(?:{kinds})")
    stem_set, found = set(stems), {}
    with os.scandir(out) as it:
        for entry in it:
            m = pattern.fullmatch(entry.name)
            if m and m.group(1) in stem_set:
                found.setdefault(m.group(1), []).append(entry.name)
    return {k: sorted(v) for k, v in found.items()}


def _run_packed(packed, outdir, process_one, summary_frame):
    chunk, opts = packed
    return _run_chunk(chunk, outdir, opts, process_one, summary_frame)


def _write_summary(out, rec_dir, stems, images, result):
    """Concatenate the rows in input order into ``summary.csv`` (atomically), tally, remove the records."""
    import shutil

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import atomic_write

    with atomic_write(out / "summary.csv", "w", newline="") as fh:
        for k, (image, stem) in enumerate(zip(images, stems)):
            try:
                with open(rec_dir / f"{stem}.done.json", encoding="utf-8") as f:
                    rec = json.load(f)
                with open(rec_dir / f"{stem}.row.csv", encoding="utf-8", newline="") as f:
                    header = f.readline()
                    row = f.read()
            except (OSError, ValueError) as exc:
                # another process removed a record midway (two runs in one directory)
                raise InputError(f"{out}: the record of {image} vanished before the summary was written "
                                 f"({exc}); is another run writing there? run again to complete it") from None
            if k == 0:
                fh.write(header)
            fh.write(row)
            status = rec["status"]
            result.counts[status] = result.counts.get(status, 0) + 1
            if status == "failed" and len(result.failed) < 10:
                result.failed.append((image, rec["reason"]))
            result.left.extend(rec.get("left", ()))
    shutil.rmtree(rec_dir, ignore_errors=True)
