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

``pix``
    The same as ``centered``, under PsychoPy's name.

``height`` and ``norm``
    PsychoPy's window units, with the image drawn at the window centre, y up.
    They need the window size ``(Ww, Hw)`` in pixels (``--window-size``):
    ``height`` has 1 unit = the window height, so ``X = Xh * Hw``,
    ``Y = Yh * Hw`` pixels; ``norm`` runs from -1 to 1 over each window axis,
    so ``X = Xn * Ww / 2``, ``Y = Yn * Hw / 2``. Then as ``centered``; the
    scale of an image drawn ``size`` units high (``height`` units) is
    ``size * Hw / H``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.tables import describe_columns, plausible_header, restore_cell
from attneave.stimuli.validate import parse_number

__all__ = [
    "CANONICAL",
    "COORDS",
    "WINDOW_UNITS",
    "MAX_COORDINATE",
    "SCALE_RANGE",
    "MISSING_TOKENS",
    "parse_columns",
    "read_clicks",
    "malformed_rows",
    "repeated_header_rows",
    "blank_rows",
    "REPEATED_HEADER",
    "SOURCE",
    "READER_COLUMNS",
    "parse_coordinates",
    "to_image_coords",
    "from_image_coords",
    "parse_window_size",
    "window_units_to_pixels",
]

CANONICAL = ("participant", "stimulus_id", "x", "y")
COORDS = ("image", "centered", "pix", "height", "norm")
#: Largest |coordinate| of a click; a larger one is excluded (reason coordinate_out_of_range).
MAX_COORDINATE = 1e12
#: Bounds of --scale (shown size / image size).
SCALE_RANGE = (1e-6, 1e6)
#: Units relative to the window, which need the window's size in pixels.
WINDOW_UNITS = ("height", "norm")
#: ``row_error`` of a line that repeats the header (files joined together); excluded as repeated_header.
REPEATED_HEADER = "the header line again (files joined together?): not a click"
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


def read_clicks(path, columns=None, sep=None, decimal=None):
    """Read a click file as text, with canonical column names.

    The file is read tolerantly (:mod:`attneave.analysis.clicks.dialects`): the separator
    (``,``, ``;``, tab, ``|``) and decimal commas in x and y are recognised,
    and a row with the wrong number of fields is kept and flagged (analysis
    excludes it with reason ``malformed_row``) rather than refusing the file.

    Coordinates written as lists, as PsychoPy Builder's mouse component
    saves them (``[0.109]``; ``[0.1, 0.3]`` and ``[0.2, 0.4]`` for two
    clicks), are unpacked: a one-element list is its number; x and y lists of
    the same length k > 1 become k rows, one per click, that share the line
    number and differ in a column ``list_index`` (0 .. k-1; -1 on rows that
    held no list), and every other column holding a list of k values in that
    row (e.g. ``mouse.time``) is split alongside. An empty list ``[]`` is a
    missing coordinate; lists of unequal lengths are left as written and
    excluded with reason ``coordinate_list``.

    A cell written as ``'=...``, ``'+...``, ``'-...``, ``'@...`` (a leading
    ``'`` that CSV writers put before a text a spreadsheet would evaluate as
    a formula; :func:`attneave.stimuli.tables.neutralise_cell`) is read
    without that ``'``, so ids come back as they were.

    Several files joined into one (``cat P01.csv P02.csv``) repeat the header
    line: such a line is kept, with ``row_error`` saying so, and analysis
    excludes it with reason ``repeated_header``.

    Parameters
    ----------
    path : str or Path
        CSV file with a header.
    columns : str or dict, optional
        Mapping of canonical names to the file's names (see
        :func:`parse_columns`).
    sep : str, optional
        Field separator (``','``, ``';'``, ``'tab'``, ``'|'``); default: found
        from the header.
    decimal : {'.', ','}, optional
        Decimal mark of x and y; default: ``','`` when x or y values look like
        ``12,5`` and none like ``12.5``. Decimal commas are converted to points
        in the x, y columns; other columns pass through as written.

    Returns
    -------
    pandas.DataFrame
        One row per data row of the file (more for unpacked lists), all values
        as text (``str``), columns renamed to ``participant, stimulus_id, x,
        y`` where mapped, other columns unchanged. A column of the file that
        already bears a canonical name which the mapping gives to another
        column, or one of the names added here, is kept as ``input_<name>``.
        A first column ``line`` holds the line number in the file (the header
        is line 1); a column ``row_error`` (only when some row is malformed)
        says what is wrong with a row; ``list_index`` as above.

    Raises
    ------
    InputError
        The file is missing, not a regular file, too large, not text, empty,
        has no data rows, or lacks a required column (the message names the
        file and the missing columns, and the columns found when the first
        line looks like a CSV header).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "clicks.csv"
    >>> _ = f.write_text("participant;stimulus_id;x;y\\nP1;rf_003;12,5;40\\n")
    >>> read_clicks(f)[["participant", "x", "y"]].values.tolist()
    [['P1', '12.5', '40']]
    """
    from attneave.analysis.clicks.dialects import read_tolerant_csv, repeated_header, sniff_decimal, to_decimal_point

    path = Path(path)
    mapping = parse_columns(columns)
    if decimal not in (None, ".", ","):
        raise InputError(f"--decimal: expected '.' or ',', got {decimal!r}")
    df, lines, row_error, _ = read_tolerant_csv(path, sep=sep, what="a CSV click file",
                                                empty=f"expected a header with {', '.join(CANONICAL)}")
    # the ' that a CSV writer (ours, the experiment page's, PsychoPy's) put before a cell a spreadsheet
    # would run as a formula is no part of the value: '=P01 is the participant =P01
    df = df.map(restore_cell)
    df.columns = [restore_cell(c) for c in df.columns]
    # files joined one after another (cat P01.csv P02.csv) repeat the header: such a line is no click;
    # it is kept and flagged (analysis excludes it as repeated_header), not mistaken for a click with
    # non-numeric coordinates
    row_error = np.where(repeated_header(df), REPEATED_HEADER, np.asarray(row_error, dtype=object))
    absent = [f"{v} (for {k})" for k, v in mapping.items() if v not in df.columns]
    if absent:
        raise InputError(f"{path}: --columns names column(s) not in the file: {', '.join(absent)}; "
                         f"{describe_columns(df.columns)}")
    rename = {c: f"input_{c}" for c in _ADDED if c in df.columns}
    for k, v in mapping.items():
        if v != k and k in df.columns and k not in mapping.values():
            rename[k] = f"input_{k}"
        rename[v] = k
    df = df.rename(columns=rename)
    missing = [c for c in CANONICAL if c not in df.columns]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}; {describe_columns(df.columns)} "
                         f"(map other names with --columns NAME=COLUMN,...{_suggest(missing, df.columns)})")
    if len(df) == 0:
        raise InputError(f"{path}: no click rows (only a header)")
    for c in ("participant", "stimulus_id"):
        df[c] = df[c].str.strip()
    if decimal is None:
        decimal = sniff_decimal(df["x"].head(500).tolist() + df["y"].head(500).tolist())
    if decimal == ",":
        for c in ("x", "y"):
            df[c] = to_decimal_point(df[c].tolist())
    df.insert(0, "line", lines)
    if any(row_error):
        df["row_error"] = row_error
    return _unpack_lists(df)


def _suggest(missing, columns):
    """'; e.g. x=mouse.x,y=mouse.y' for PsychoPy-like names of a plausible header ('' if none)."""
    if not plausible_header(columns):
        return ""
    pairs = []
    for k in missing:
        if k in ("x", "y"):
            found = [c for c in columns if c.lower().endswith((f".{k}", f"_{k}"))]
            if len(found) == 1:
                pairs.append(f"{k}={found[0][:30]}")
    return f"; e.g. {','.join(pairs)}" if pairs else ""


# columns read_clicks adds; a file's own columns of these names are kept as input_<name>
_ADDED = ("line", "row_error", "list_index")
#: The column naming each row's file when several files are read (:mod:`attneave.analysis.clicks.files`).
SOURCE = "source_file"
#: Every column the readers add to a file's own.
READER_COLUMNS = _ADDED + (SOURCE,)


def blank_rows(table, rows):
    """Which of the rows at indices `rows` have every field of the file empty (a row of separators
    only, ``;;;;``), as a bool array over `rows`; the columns the readers add are not the file's."""
    data = table.iloc[rows][[c for c in table.columns if c not in READER_COLUMNS]].astype(str)
    return (data.apply(lambda c: c.str.strip()) == "").all(axis=1).to_numpy()


def _list_items(value):
    """``'[a, b]'`` -> ``['a', 'b']``; None when `value` is not written as a list."""
    v = value.strip()
    if len(v) < 2 or v[0] != "[" or v[-1] != "]":
        return None
    inner = v[1:-1].strip()
    return [t.strip().strip("'\"") for t in inner.split(",")] if inner else []


def _unpack_lists(df):
    """Coordinates written as lists -> numbers, one row per click (see :func:`read_clicks`)."""
    import pandas as pd

    x, y = df["x"].to_numpy(dtype=object), df["y"].to_numpy(dtype=object)
    is_list = (df["x"].str.contains("[", regex=False).to_numpy(dtype=bool)
               | df["y"].str.contains("[", regex=False).to_numpy(dtype=bool))
    if not is_list.any():
        return df
    counts = np.ones(len(df), np.int64)
    new_x, new_y = {}, {}
    for i in np.flatnonzero(is_list):
        lx, ly = _list_items(x[i]), _list_items(y[i])
        if lx is None or ly is None or len(lx) != len(ly):
            continue  # left as written: parse_coordinates names the problem
        if len(lx) == 0:
            new_x[i], new_y[i] = [""], [""]
        else:
            new_x[i], new_y[i] = lx, ly
            counts[i] = len(lx)
    if not new_x:
        return df
    out = df.loc[df.index.repeat(counts)].reset_index(drop=True)
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    index = np.full(len(out), -1, np.int64)
    cols = {c: np.array(out[c], dtype=object) for c in out.columns if c != "line"}
    for i, lx in new_x.items():
        k, lo = len(lx), first[i]
        cols["x"][lo : lo + k], cols["y"][lo : lo + k] = lx, new_y[i]
        if k > 1:
            index[lo : lo + k] = np.arange(k)
            for c, v in cols.items():  # a list of k values beside k clicks belongs to them (mouse.time, ...)
                items = _list_items(str(v[lo])) if c not in ("x", "y") else None
                if items is not None and len(items) == k:
                    v[lo : lo + k] = items
    for c, v in cols.items():
        out[c] = v
    if (counts > 1).any():
        out["list_index"] = pd.array(index)
    return out


def parse_coordinates(values):
    """Parse a text column of coordinates.

    Parameters
    ----------
    values : sequence of str
        Numbers as text; a one-element list (``'[0.109]'``, as PsychoPy
        writes) is its number, an empty list ``'[]'`` is missing.

    Returns
    -------
    numbers : (M,) ndarray of float
        NaN where the value is missing or not a finite number.
    problem : (M,) ndarray of object
        ``''`` for a good value, ``'missing_coordinate'`` for an empty or
        NA-like value (see `MISSING_TOKENS`) or an empty list,
        ``'coordinate_list'`` for a list of several values (that
        :func:`read_clicks` could not pair with the other coordinate's),
        ``'non_numeric_coordinate'`` for text or an infinite value,
        ``'coordinate_out_of_range'`` beyond +-:data:`MAX_COORDINATE`.

    Examples
    --------
    >>> v, p = parse_coordinates(["1.5", "[0.25]", "[]", "[1, 2]", "abc"])
    >>> v.tolist()[:2], p.tolist()
    ([1.5, 0.25], ['', '', 'missing_coordinate', 'coordinate_list', 'non_numeric_coordinate'])
    """
    import pandas as pd

    s = pd.Series(values, dtype=object)
    num = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float, copy=True)
    problem = np.full(len(s), "", dtype=object)
    bad = ~np.isfinite(num)
    if bad.any():
        # only the rows that failed are looked at as text (few, usually)
        idx = np.flatnonzero(bad)
        raw = s.iloc[idx].astype(str).str.strip()
        items = raw.str.extract(r"^\[\s*([^,\]]*?)\s*\]$")[0]  # the element of a one-element list
        one = items.notna().to_numpy() & (items.fillna("") != "").to_numpy()
        if one.any():
            num[idx[one]] = pd.to_numeric(items[one], errors="coerce").to_numpy(dtype=float)
        still = ~np.isfinite(num[idx])
        missing = (s.iloc[idx].isna().to_numpy() | raw.str.lower().isin(MISSING_TOKENS).to_numpy()
                   | raw.str.fullmatch(r"\[\s*\]").to_numpy(dtype=bool))
        listed = raw.str.fullmatch(r"\[.*,.*\]").to_numpy(dtype=bool)
        problem[idx[still & missing]] = "missing_coordinate"
        problem[idx[still & ~missing & listed]] = "coordinate_list"
        problem[idx[still & ~missing & ~listed]] = "non_numeric_coordinate"
        num[idx[still]] = np.nan
    # no screen or image has a coordinate near 1e12; beyond it squares and sums lose meaning
    far = np.abs(num) > MAX_COORDINATE
    if far.any():
        problem[far] = "coordinate_out_of_range"
        num[far] = np.nan
    return num, problem


def malformed_rows(clicks):
    """Rows that :func:`read_clicks` found malformed (wrong field count), as a bool array.

    Frames built otherwise (e.g. simulated clicks) have no malformed rows.
    A repeated header line is not counted here (:func:`repeated_header_rows`).
    """
    if "row_error" not in clicks.columns:
        return np.zeros(len(clicks), bool)
    err = clicks["row_error"].astype(str)
    return ((err != "") & (err != REPEATED_HEADER)).to_numpy()


def repeated_header_rows(clicks):
    """Rows that :func:`read_clicks` found to repeat the file's header line, as a bool array."""
    if "row_error" not in clicks.columns:
        return np.zeros(len(clicks), bool)
    return (clicks["row_error"].astype(str) == REPEATED_HEADER).to_numpy()


def parse_window_size(spec):
    """Parse ``--window-size W,H`` (pixels) -> ``(W, H)`` floats.

    Examples
    --------
    >>> parse_window_size("1920,1080")
    (1920.0, 1080.0)
    """
    if spec is None:
        return None
    parts = spec if isinstance(spec, (tuple, list)) else str(spec).replace("x", ",").split(",")
    if len(parts) != 2:
        raise InputError(f"--window-size: expected W,H in pixels (e.g. 1920,1080), got {spec!r}")
    w, h = (parse_number(v, "--window-size", gt=0, le=1e6) for v in parts)
    return w, h


def _check(coords, scale, window):
    if coords not in COORDS:
        raise InputError(f"--coords must be one of {', '.join(COORDS)}, got {coords!r}")
    if not (np.isfinite(scale) and SCALE_RANGE[0] <= scale <= SCALE_RANGE[1]):
        raise InputError(f"--scale must be a positive number from {SCALE_RANGE[0]:g} to {SCALE_RANGE[1]:g}, "
                         f"got {scale!r}")
    if coords in WINDOW_UNITS and window is None:
        raise InputError(f"--coords {coords} needs --window-size W,H (the window's size in pixels)")


def _window_factors(coords, window):
    """Screen pixels per unit of `coords` along x and y (y up)."""
    w, h = parse_window_size(window)
    return (h, h) if coords == "height" else (w / 2.0, h / 2.0)


def to_image_coords(x, y, width, height, coords="image", scale=1.0, window=None):
    """Convert click coordinates to image pixels (y down, pixel centres at integers).

    Parameters
    ----------
    x, y : array_like
        Click coordinates in the system `coords`.
    width, height : array_like
        Image size in pixels (per click, or scalars).
    coords : {'image', 'centered', 'pix', 'height', 'norm'}
        See the module docstring.
    scale : float
        Shown size / image size (> 0).
    window : (float, float), optional
        Window size ``(W, H)`` in pixels; needed for 'height' and 'norm'.

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
    >>> [float(v) for v in to_image_coords(-0.25, 0.25, 512, 512, "height", window=(1920, 1024))]
    [-0.5, -0.5]
    """
    _check(coords, scale, window)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) / scale - 0.5, (y + 0.5) / scale - 0.5
    if coords in WINDOW_UNITS:
        fx, fy = _window_factors(coords, window)
        x, y = x * fx, y * fy
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    return cx + x / scale, cy - y / scale


def from_image_coords(x, y, width, height, coords="image", scale=1.0, window=None):
    """Inverse of :func:`to_image_coords`: image pixels to `coords`.

    Examples
    --------
    >>> [float(v) for v in from_image_coords(255.5, 255.5, 512, 512, "centered")]
    [0.0, 0.0]
    """
    _check(coords, scale, window)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) * scale - 0.5, (y + 0.5) * scale - 0.5
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    xs, ys = (x - cx) * scale, (cy - y) * scale
    if coords in WINDOW_UNITS:
        fx, fy = _window_factors(coords, window)
        xs, ys = xs / fx, ys / fy
    return xs, ys


def window_units_to_pixels(clicks, coords, window):
    """Clicks in PsychoPy's 'height' or 'norm' units -> 'centered' screen pixels.

    The analysis maps 'centered' pixels; this converts the other two window
    units to them (see the module docstring), keeping the values as written
    in columns ``x_<coords>`` and ``y_<coords>``.

    Parameters
    ----------
    clicks : pandas.DataFrame
        From :func:`read_clicks`.
    coords : {'height', 'norm'}
    window : str or (float, float)
        Window size ``W,H`` in pixels.

    Returns
    -------
    pandas.DataFrame
        A copy, x and y in pixels from the window centre, y up.
    """
    _check(coords, 1.0, window)
    fx, fy = _window_factors(coords, window)
    x, px = parse_coordinates(clicks["x"].to_numpy())
    y, py = parse_coordinates(clicks["y"].to_numpy())
    out = clicks.copy()
    keep = {c: f"input_{c}" for c in (f"x_{coords}", f"y_{coords}") if c in out.columns}
    out = out.rename(columns=keep)
    out.insert(out.columns.get_loc("y") + 1, f"x_{coords}", clicks["x"].to_numpy())
    out.insert(out.columns.get_loc(f"x_{coords}") + 1, f"y_{coords}", clicks["y"].to_numpy())
    # a value that is not a number stays as written, so that its reason is the same
    out["x"] = np.where(px == "", x * fx, clicks["x"].to_numpy(dtype=object))
    out["y"] = np.where(py == "", y * fy, clicks["y"].to_numpy(dtype=object))
    return out
