"""File helpers: atomic writes and reading point tables.

Every file the project writes goes through :func:`atomic_write`, so that an
interrupted run never leaves a half-written file under its final name.
"""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
from pathlib import Path

import numpy as np

from stimuli.errors import InputError

__all__ = ["atomic_write", "write_table", "read_text_csv", "read_table", "read_points", "as_points", "as_number"]


# Temporary files are named .attneave-tmp-<pid>-<random>-<final name>: no user file is named
# so, and cleanup (which deletes only names of this form) never touches a user's file.
TEMP_PREFIX = ".attneave-tmp-"
_TEMP_RE = re.compile(r"^\.attneave-tmp-[0-9]+-[A-Za-z0-9_]+-")


def is_temporary(name):
    """True for the name of a temporary file made by :func:`atomic_write`.

    Examples
    --------
    >>> is_temporary(".attneave-tmp-4242-k3j_x9a1-a.png"), is_temporary(".a.png.tmp")
    (True, False)
    """
    return bool(_TEMP_RE.match(name))


__all__ += ["TEMP_PREFIX", "is_temporary"]


@contextlib.contextmanager
def atomic_write(path, mode="w", fsync=False, **kwargs):
    """Open a temporary file beside `path` and move it into place on success.

    The rename is atomic, so a killed process (even ``kill -9``) leaves either
    the old file or the complete new one under `path`, never a partial one.

    Parameters
    ----------
    path : str or Path
        Final file name. Its directory must exist.
    mode : {'w', 'wb'}
        Text or binary.
    fsync : bool
        Also flush the data to disk before the rename. Only a power cut needs
        this, and it costs milliseconds per file, so it is off by default and
        kept for the files that mark a batch complete.
    **kwargs
        Passed to :func:`open` (e.g. ``newline=''``).

    Yields
    ------
    file
        The open temporary file. On an exception it is removed and `path` is
        left untouched.

    Raises
    ------
    InputError
        `path` is a directory, or its directory is missing or not writable.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a directory; expected a file name to write")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f"{TEMP_PREFIX}{os.getpid()}-", suffix=f"-{path.name[:80]}",
                                   dir=path.parent)
    except OSError as exc:
        # a missing or read-only directory is the user's input, not a crash
        raise InputError(f"{path}: cannot write there ({exc.strerror or exc})") from None
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            if fsync:
                fh.flush()
                os.fsync(fh.fileno())
        # mkstemp makes the file private (0600); give it the mode a plain open() would
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _read_umask():
    # os.umask can only be read by setting it; do it once, at import, not in threads
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _read_umask()


def write_table(table, path, float_format="%.10g"):
    """Write a mapping of columns or a DataFrame to CSV, atomically.

    Floats are written with 10 significant digits by default, enough for
    sub-micro-pixel coordinates, and deterministic so that the same input
    gives byte-identical files.
    """
    import pandas as pd

    df = table if isinstance(table, pd.DataFrame) else pd.DataFrame(table)
    with atomic_write(path, "w", newline="") as fh:
        df.to_csv(fh, index=False, float_format=float_format, lineterminator="\n")


_NEWLINE = r"\r\n|\r|\n"


def read_text_csv(path, what="a CSV file", empty="expected a header"):
    """Read a CSV file as text, with the physical line of each row.

    Every value is a ``str`` as written (leading spaces skipped). Unlike a bare
    :func:`pandas.read_csv`, a data row with more fields than the header is
    never read shifted (pandas would take its first field as an index):
    empty extra fields (a delimiter at the end of every row, as some
    exporters write) are ignored, and a non-empty one is an error naming the
    line. Blank lines are not rows; a row of empty fields is.

    Parameters
    ----------
    path : Path
    what : str
        What the file should be (for messages).
    empty : str
        What an empty file lacks (for messages).

    Returns
    -------
    df : pandas.DataFrame
        Columns as in the header (stripped), one row per non-blank record.
    lines : (M,) ndarray of int
        Line of the file on which each row starts (the header is line 1).

    Raises
    ------
    InputError
        Missing, a directory, empty, not UTF-8 text, not parseable, or a row
        with values beyond the header.
    """
    import warnings

    import pandas as pd

    path = Path(path)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", pd.errors.ParserWarning)
            # index_col=False: never take a first field as the index; blank lines
            # are kept as rows here so that row i + 2 is a line number
            df = pd.read_csv(path, dtype=str, keep_default_na=False, skipinitialspace=True, index_col=False,
                             skip_blank_lines=False)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected {what}") from None
    except OSError as exc:  # no permission, ...
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except pd.errors.EmptyDataError:
        raise InputError(f"{path}: empty file ({empty})") from None
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable CSV file ({str(exc).splitlines()[0]})") from None
    if any(issubclass(w.category, pd.errors.ParserWarning) for w in caught):
        _check_extra_fields(path)
    df.columns = [str(c).strip() for c in df.columns]
    # a row starts one line after the previous one ends; quoted values may hold line breaks
    breaks = np.zeros(len(df), np.int64)
    for c in df.columns:
        col = df[c]
        if len(col) and col.str.contains(r"[\r\n]", regex=True).any():
            breaks += col.str.count(_NEWLINE).to_numpy(dtype=np.int64)
    lines = 2 + np.arange(len(df), dtype=np.int64) + np.concatenate(([0], np.cumsum(breaks)[:-1]))[: len(df)]
    empty_row = (df == "").all(axis=1).to_numpy() if len(df.columns) else np.ones(len(df), bool)
    if empty_row.any():
        blank = _blank_lines(path)
        drop = empty_row & np.isin(lines, blank)
        if drop.any():
            df = df.loc[~drop].reset_index(drop=True)
            lines = lines[~drop]
    return df, lines


def _blank_lines(path):
    """Numbers (from 1) of the lines of `path` that hold only white space."""
    import re

    text = Path(path).read_text(encoding="utf-8-sig", errors="replace")
    return np.array([i + 1 for i, ln in enumerate(re.split(_NEWLINE, text)) if not ln.strip()], dtype=np.int64)


def _check_extra_fields(path):
    """Raise for the first row with non-empty values beyond the header's columns."""
    import csv

    with open(path, newline="", encoding="utf-8-sig", errors="replace") as fh:
        reader = csv.reader(fh, skipinitialspace=True)
        n = len(next(reader, []))
        for row in reader:
            if len(row) > n and any(v.strip() for v in row[n:]):
                extra = ", ".join(repr(v) for v in row[n:])
                raise InputError(f"{path}: line {reader.line_num}: {len(row)} fields but the header has {n} "
                                 f"(extra value(s) {extra}); add a column name to the header or remove them")


def read_table(path, required=(), numeric=()):
    """Read a CSV file, checking that it has the columns it needs.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    required : sequence of str
        Columns that must be present.
    numeric : sequence of str
        Columns whose every value must be a finite number.

    Returns
    -------
    pandas.DataFrame
        With `numeric` columns converted to float.

    Raises
    ------
    InputError
        One line naming the file and, where it applies, the column and the
        line number (the header is line 1).
    """
    import pandas as pd

    path = Path(path)
    df, lines = read_text_csv(path)
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise InputError(
            f"{path}: missing column(s) {', '.join(missing)}; found {', '.join(df.columns) or 'none'}"
        )
    for col in numeric:
        values = pd.to_numeric(df[col], errors="coerce")
        bad = ~np.isfinite(values.to_numpy(dtype=float))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"{path}: line {lines[i]}: column {col!r} must be a finite number, got {df[col].iloc[i]!r}"
            )
        df[col] = values.astype(float)
    return df


def read_points(path, columns=("x", "y")):
    """Read an (N, 2) array of points from a CSV file with columns `x`, `y`.

    Points are ``(x, y)`` in image pixels (x = column, y = row, y down).
    """
    df = read_table(path, required=columns, numeric=columns)
    if len(df) == 0:
        raise InputError(f"{path}: no rows")
    return df[list(columns)].to_numpy(dtype=float)


def as_points(obj, what="points", min_points=1):
    """Check and convert an (N, 2) array of ``(x, y)`` points (or anything with
    a ``.points`` attribute, such as a `Contour`).

    Raises
    ------
    InputError
        One line naming `what` and, for a non-finite value, the row.
    """
    pts = getattr(obj, "points", obj)
    try:
        pts = np.array(pts, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) numbers") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) points, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        row = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InputError(f"{what}: row {row}: coordinates must be finite, got {pts[row].tolist()}")
    if len(pts) < min_points:
        raise InputError(f"{what}: need at least {min_points} point(s), got {len(pts)}")
    return pts


def as_number(value, name, gt=None, ge=None, lt=None, le=None):
    """Check and convert one finite number, optionally bounded.

    Raises
    ------
    InputError
        One line naming `name`: not a number, not finite, or out of bounds.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number, got {value!r}") from None
    if not np.isfinite(v):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    if gt is not None and not v > gt:
        raise InputError(f"{name}: must be > {gt}, got {value!r}")
    if ge is not None and not v >= ge:
        raise InputError(f"{name}: must be >= {ge}, got {value!r}")
    if lt is not None and not v < lt:
        raise InputError(f"{name}: must be < {lt}, got {value!r}")
    if le is not None and not v <= le:
        raise InputError(f"{name}: must be <= {le}, got {value!r}")
    return v
