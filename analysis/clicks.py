"""Reading click files and converting their coordinates to image pixels.

A click file is a CSV with one row per selected point and at least the
columns ``participant``, ``stimulus_id``, ``x``, ``y`` (other names through a
mapping such as ``participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y``).
Every other column is kept and passed through to the output untouched: the
file is read as text, so values such as ``"007"`` or ``"1e3"`` come back as
they were written.

Coordinate systems
------------------
Analysis works in image pixels with OpenCV's convention: ``(x, y)`` with
x = column, y = row, y down, and pixel centres at integer coordinates, so the
image of width W covers x in [-0.5, W - 0.5] and its centre is at
``((W - 1) / 2, (H - 1) / 2)``.

``image`` (default)
    Clicks are in pixels of the image as it was shown, origin at the top-left,
    y down, pixel centres at integers. When it was shown magnified by
    ``scale`` (shown width = ``scale * W``), the shown pixel edge coordinate
    ``x + 0.5`` is divided by ``scale``::

        x_image = (x + 0.5) / scale - 0.5

``centered``
    PsychoPy's ``'pix'`` units with the image drawn at the centre of the
    window: origin at the image centre, y up, one unit per screen pixel. The
    image centre lies at ``(W / 2, H / 2)`` in edge coordinates, which is
    ``((W - 1) / 2, (H - 1) / 2)`` with pixel centres at integers, so::

        x_image = (W - 1) / 2 + X / scale
        y_image = (H - 1) / 2 - Y / scale

    A click at the window centre maps to the image centre; one at
    ``(-W/2, +H/2) * scale`` (the top-left corner of the drawn image) maps to
    ``(-0.5, -0.5)``, the outer corner of the top-left pixel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from stimuli.errors import InputError
from stimuli.io import read_text_csv

__all__ = [
    "CANONICAL",
    "COORDS",
    "MISSING_TOKENS",
    "parse_columns",
    "read_clicks",
    "read_text_csv",
    "parse_coordinates",
    "to_image_coords",
    "from_image_coords",
]

CANONICAL = ("participant", "stimulus_id", "x", "y")
COORDS = ("image", "centered")
# spellings of "no value" that spreadsheets and R/pandas write
MISSING_TOKENS = frozenset({"", "nan", "na", "n/a", "null", "none", "<na>"})


def parse_columns(spec):
    """Parse a column mapping ``participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y``.

    Parameters
    ----------
    spec : str or dict or None
        ``NAME=COLUMN`` pairs separated by commas, where NAME is one of
        ``participant, stimulus_id, x, y`` and COLUMN the header in the file.

    Returns
    -------
    dict of str -> str
        Canonical name -> column name in the file (only the names given).

    Raises
    ------
    InputError
        A malformed pair, an unknown NAME, or a NAME given twice.
    """
    if spec is None or spec == "":
        return {}
    if isinstance(spec, dict):
        pairs = list(spec.items())
    else:
        pairs = []
        for part in str(spec).split(","):
            if not part.strip():
                continue
            if "=" not in part:
                raise InputError(f"--columns: expected NAME=COLUMN pairs separated by commas, got {part.strip()!r}")
            k, v = part.split("=", 1)
            pairs.append((k.strip(), v.strip()))
    out = {}
    for k, v in pairs:
        if k not in CANONICAL:
            raise InputError(f"--columns: unknown name {k!r}; expected one of {', '.join(CANONICAL)}")
        if not v:
            raise InputError(f"--columns: empty column name for {k!r}")
        if k in out:
            raise InputError(f"--columns: {k!r} given twice")
        out[k] = v
    return out


def read_clicks(path, columns=None):
    """Read a click file as text, with canonical column names.

    Parameters
    ----------
    path : str or Path
        CSV file with a header.
    columns : str or dict, optional
        Mapping of canonical names to the file's names (see
        :func:`parse_columns`).

    Returns
    -------
    pandas.DataFrame
        One row per data row of the file, all values as text (``str``),
        columns renamed to ``participant, stimulus_id, x, y`` where mapped,
        other columns unchanged. A column of the file that already bears a
        canonical name which the mapping gives to another column, or the name
        ``line``, is kept as ``input_<name>``. A first column ``line`` holds
        the line number in the file (the header is line 1).

    Raises
    ------
    InputError
        The file is missing, unreadable, empty, has no data rows, or lacks a
        required column (the message names the file, the missing columns and
        the columns found).
    """
    path = Path(path)
    mapping = parse_columns(columns)
    df, lines = read_text_csv(path, what="a CSV click file",
                              empty=f"expected a header with {', '.join(CANONICAL)}")
    header = _header(path)
    seen = set()
    for c in header:
        if c in seen:
            raise InputError(f"{path}: column {c!r} appears twice in the header")
        seen.add(c)
    df.columns = [str(c).strip() for c in df.columns]
    absent = [f"{v} (for {k})" for k, v in mapping.items() if v not in df.columns]
    if absent:
        raise InputError(f"{path}: --columns names column(s) not in the file: {', '.join(absent)}; found {', '.join(df.columns)}")
    rename = {}
    for k, v in mapping.items():
        if v != k and k in df.columns and k not in mapping.values():
            rename[k] = f"input_{k}"
        rename[v] = k
    df = df.rename(columns=rename)
    missing = [c for c in CANONICAL if c not in df.columns]
    if missing:
        hint = " (map other names with --columns NAME=COLUMN,...)"
        raise InputError(
            f"{path}: missing column(s) {', '.join(missing)}; found {', '.join(df.columns) or 'none'}{hint}"
        )
    if len(df) == 0:
        raise InputError(f"{path}: no click rows (only a header)")
    for c in ("participant", "stimulus_id"):
        df[c] = df[c].str.strip()
    if "line" in df.columns:
        df = df.rename(columns={"line": "input_line"})
    df.insert(0, "line", lines)
    return df




def _header(path):
    """Header names as written (pandas renames duplicates to 'x.1')."""
    import csv

    with open(path, newline="", encoding="utf-8", errors="replace") as fh:
        row = next(csv.reader(fh), [])
    return [c.strip() for c in row]


def parse_coordinates(values):
    """Parse a text column of coordinates.

    Parameters
    ----------
    values : sequence of str

    Returns
    -------
    numbers : (M,) ndarray of float
        NaN where the value is missing or not a finite number.
    problem : (M,) ndarray of object
        ``''`` for a good value, ``'missing_coordinate'`` for an empty or
        NA-like value (see `MISSING_TOKENS`), ``'non_numeric_coordinate'`` for
        text or an infinite value.
    """
    import pandas as pd

    s = pd.Series(values, dtype=object)
    num = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float, copy=True)
    problem = np.full(len(s), "", dtype=object)
    bad = ~np.isfinite(num)
    if bad.any():
        # only the rows that failed are looked at as text (few, usually)
        idx = np.flatnonzero(bad)
        raw = s.iloc[idx]
        missing = raw.isna().to_numpy() | raw.astype(str).str.strip().str.lower().isin(MISSING_TOKENS).to_numpy()
        problem[idx[missing]] = "missing_coordinate"
        problem[idx[~missing]] = "non_numeric_coordinate"
        num[idx] = np.nan
    return num, problem


def _check(coords, scale):
    if coords not in COORDS:
        raise InputError(f"--coords must be one of {', '.join(COORDS)}, got {coords!r}")
    if not (np.isfinite(scale) and scale > 0):
        raise InputError(f"--scale must be a positive number, got {scale!r}")


def to_image_coords(x, y, width, height, coords="image", scale=1.0):
    """Convert click coordinates to image pixels (y down, pixel centres at integers).

    Parameters
    ----------
    x, y : array_like
        Click coordinates in the system `coords`.
    width, height : array_like
        Image size in pixels (per click, or scalars).
    coords : {'image', 'centered'}
        See the module docstring.
    scale : float
        Shown size / image size (> 0).

    Returns
    -------
    (x_image, y_image) : tuple of ndarray
        In image pixels (x = column, y = row, y down).

    Examples
    --------
    >>> [float(v) for v in to_image_coords(0.0, 0.0, 512, 512, "centered")]
    [255.5, 255.5]
    >>> [float(v) for v in to_image_coords(-256.0, 256.0, 512, 512, "centered")]
    [-0.5, -0.5]
    """
    _check(coords, scale)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) / scale - 0.5, (y + 0.5) / scale - 0.5
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    return cx + x / scale, cy - y / scale


def from_image_coords(x, y, width, height, coords="image", scale=1.0):
    """Inverse of :func:`to_image_coords`: image pixels to `coords`.

    Examples
    --------
    >>> [float(v) for v in from_image_coords(255.5, 255.5, 512, 512, "centered")]
    [0.0, 0.0]
    """
    _check(coords, scale)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) * scale - 0.5, (y + 0.5) * scale - 0.5
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    return (x - cx) * scale, (cy - y) * scale
