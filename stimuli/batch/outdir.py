"""The output directory of a batch: its lock, its state, what a rerun keeps.

While a batch runs, its directory holds, besides the stimulus files:

``.attneave.lock``
    Held with :func:`fcntl.flock` by the one ``generate`` writing there (it
    holds that process's pid), so that a second run on the same directory
    is refused instead of mixing files.
``.attneave-batch``
    The marker: the SHA-256 of the resolved config whose batch is in progress.
``.rows/``
    The journals of finished jobs (see :mod:`attneave.stimuli.batch.job`).

A directory may hold the user's own files too. Nothing here deletes a file
that a batch did not write: ``--force`` removes the files listed in the
earlier batch's manifest and journals, and cleanup removes only temporaries
named by :func:`attneave.stimuli.io.atomic_write` (``.attneave-tmp-<pid>-...``).
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
from pathlib import Path

from attneave.stimuli.batch.job import ROWS_DIR
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import is_temporary
from attneave.stimuli.stimulus_set import FILE_COLUMNS, read_manifest_rows

__all__ = ["MARKER", "LOCK", "locked", "inspect", "remove_previous", "remove_temporaries", "completed"]

MARKER = ".attneave-batch"
LOCK = ".attneave.lock"
_OURS = ("images", "contours", "manifest.csv", "config.yaml", MARKER, ROWS_DIR)
_HELD = set()  # descriptors of the locks this process holds


def _close_held_in_child():
    # a forked child (a worker) shares the lock's open file description and would keep the
    # directory locked after the parent died; it closes its copy (the parent keeps the lock)
    for fd in _HELD:
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_close_held_in_child)


@contextlib.contextmanager
def locked(out):
    """Hold the directory's lock for the duration of the block.

    Raises
    ------
    InputError
        Another process holds it: the message names the directory and that
        process's pid.
    """
    import fcntl

    path = Path(out) / LOCK
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:  # a read-only or foreign directory is the user's input
            raise InputError(f"{out}: cannot write there ({exc.strerror or exc})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "unknown"
            os.close(fd)
            raise InputError(f"{out}: another attneave generate (pid {holder}) is writing there; "
                             f"wait for it to finish or choose another directory") from None
        except OSError as exc:
            os.close(fd)
            raise InputError(f"{out}: cannot lock {LOCK} there ({exc.strerror or exc})") from None
        # the holder before us may have removed the file after we opened it: lock the file
        # that is there now, or two runs would each hold a lock on a different file
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    _HELD.add(fd)
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)  # while still held, so that no one locks a file about to vanish
        _HELD.discard(fd)
        os.close(fd)


def inspect(out, batch):
    """'fresh' | 'partial' | 'complete' | 'other' | 'unknown' (see :func:`attneave.stimuli.batch.run_batch`)."""
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


def check_inside(out):
    """Refuse an ``images/``, ``contours/`` or journal directory that is a link leading outside `out`.

    The set's files would be written elsewhere, and the set read back would be
    refused (:func:`attneave.stimuli.stimulus_set.inside`): say so before writing anything.

    Raises
    ------
    InputError
        Naming the directory and where it leads.
    """
    root = Path(os.path.realpath(out))
    for sub in ("images", "contours", ROWS_DIR):
        full = Path(os.path.realpath(out / sub))
        if full.parent != root:
            raise InputError(f"{out / sub}: leads outside the output directory (to {full}); the set's files must "
                             "be inside it: remove the link or choose another directory")


def remove_previous(out):
    """Delete an earlier batch: the files its manifest and journals list, then its own files.

    Files that no manifest or journal of ours lists stay, wherever they are
    (``images/`` and ``contours/`` are removed only when left empty).
    """
    listed = set()
    for rows in [read_manifest_rows(out / "manifest.csv")] + [rows for _, rows in _journal_rows(out)]:
        listed |= {row[col] for row in rows for col in FILE_COLUMNS if row.get(col)}
    root = Path(os.path.realpath(out))
    for rel in sorted(listed):
        p = Path(os.path.realpath(out / rel))
        if root in p.parents and p.parent.name in ("images", "contours"):  # never outside ours
            with contextlib.suppress(FileNotFoundError, IsADirectoryError):
                p.unlink()
    for name in ("manifest.csv", "config.yaml", MARKER):
        with contextlib.suppress(FileNotFoundError):
            (out / name).unlink()
    shutil.rmtree(out / ROWS_DIR, ignore_errors=True)
    remove_temporaries(out)
    for sub in ("images", "contours"):
        with contextlib.suppress(OSError):
            (out / sub).rmdir()  # only if empty


def remove_temporaries(out):
    """Delete the temporary files that an interrupted atomic write left behind."""
    for d in (out, out / "images", out / "contours"):
        if not d.is_dir():
            continue
        for entry in os.scandir(d):
            if is_temporary(entry.name) and entry.is_file(follow_symlinks=False):
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(entry.path)


def _journal_rows(out):
    """(job key, rows) of every complete line of the journals in ``out/.rows``."""
    rows_dir = out / ROWS_DIR
    if not rows_dir.is_dir():
        return
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
            if isinstance(rows, list) and all(isinstance(r, dict) for r in rows):
                yield key, rows


def completed(out, jobs):
    """{job key: rows} of jobs whose rows and files all exist already."""
    keys = {j["key"] for j in jobs}
    found = {key: rows for key, rows in _journal_rows(out) if key in keys}
    by_triple = {(j["condition"], j["cell"], j["rep"]): j["key"] for j in jobs}
    grouped = {}
    for row in read_manifest_rows(out / "manifest.csv"):
        key = by_triple.get((row.get("batch_condition"), _int(row.get("cell")), _int(row.get("rep"))))
        if key is not None:
            grouped.setdefault(key, []).append(row)
    for key, rows in grouped.items():
        found.setdefault(key, rows)
    return {key: rows for key, rows in found.items()
            if rows and all(_nonempty(out / row[col]) for row in rows for col in FILE_COLUMNS if row.get(col))}


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
