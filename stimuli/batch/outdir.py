"""The output directory of a batch: its state and what a rerun keeps.

While a batch runs, its directory holds, besides the stimulus files, the
marker ``.attneave-batch`` (the SHA-256 of the resolved config whose batch is
in progress) and ``.rows/``, the journals of finished jobs (see
:mod:`stimuli.batch.job`).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil

from stimuli.batch.job import ROWS_DIR
from stimuli.stimulus_set import FILE_COLUMNS, read_manifest_rows

__all__ = ["MARKER", "inspect", "remove_previous", "remove_temporaries", "completed"]

MARKER = ".attneave-batch"
_TMP_RE = re.compile(r"^\..+\.tmp(\.[A-Za-z0-9]+)?$")
_OURS = ("images", "contours", "manifest.csv", "config.yaml", MARKER, ROWS_DIR)


def inspect(out, batch):
    """'fresh' | 'partial' | 'complete' | 'other' | 'unknown' (see :func:`stimuli.batch.run_batch`)."""
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


def remove_previous(out):
    """Delete an earlier batch's files and folders (``images/``, ``contours/``, ...)."""
    for name in _OURS:
        p = out / name
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        elif p.exists() or p.is_symlink():
            p.unlink()
    remove_temporaries(out)


def remove_temporaries(out):
    """Delete the temporary files that an interrupted atomic write left behind."""
    for d in (out, out / "images", out / "contours"):
        if not d.is_dir():
            continue
        for entry in os.scandir(d):
            if entry.is_file(follow_symlinks=False) and _TMP_RE.match(entry.name):
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
