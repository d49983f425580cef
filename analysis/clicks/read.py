"""Reading click files and converting their coordinates to image pixels.

A click file is a CSV with one row per selected point and at least the
columns ``participant``, ``stimulus_id``, ``x``, ``y`` (other names through a
mapping such as ``participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y``).
Every other column is kept and passed through to the output untouched: the
file is read as text, so values such as ``"007"`` or ``"1e3"`` come back as
they were written.

Coordinates are parsed and converted to image pixels by
:mod:`attneave.analysis.clicks.coords`; its names are also importable from here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.analysis.clicks.coords import (
    COORDS,
    MAX_COORDINATE,
    MISSING_TOKENS,
    SCALE_RANGE,
    WINDOW_UNITS,
    from_image_coords,
    parse_coordinates,
    parse_window_size,
    to_image_coords,
    window_units_to_pixels,
)
from attneave.stimuli.errors import InputError
from attneave.stimuli.tables import describe_columns, plausible_header, restore_cell

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
#: ``row_error`` of a line that repeats the header (files joined together); excluded as repeated_header.
REPEATED_HEADER = "the header line again (files joined together?): not a click"


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


def read_clicks(path, columns=None, sep=None, decimal=None, trial_type=None):
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

    jsPsych's data (CSV or JSON; a column ``trial_type``) and the data file
    of the attneave PsychoPy Builder export (``mouse.x``, ``mouse.y`` and the
    conditions' ``size_w, size_h, width_px, height_px``) are recognised and
    turned into one row per click in image pixels; rows that are no trial of
    the task are set aside and counted in ``attrs["set_aside"]``
    (:mod:`attneave.analysis.clicks.layouts`).

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
    trial_type : str, optional
        jsPsych: the ``trial_type`` whose rows hold the clicks (default
        ``attneave-points``, or the only type whose rows hold clicks).

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
    from attneave.analysis.clicks import layouts

    if _is_json(path):
        df, lines = layouts.read_json_records(path)
        row_error = np.full(len(df), "", dtype=object)
    else:
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
    df.insert(0, "line", lines)
    df["row_error"] = row_error
    set_aside, builder = {}, False
    if "trial_type" in df.columns:
        df, set_aside = layouts.jspsych_clicks(df, path, mapping, trial_type)
    elif trial_type is not None:
        raise InputError(f"--trial-type: {path} has no column trial_type (it is for jsPsych's data)")
    elif all(c in df.columns for c in layouts.BUILDER_COLUMNS) and not {"x", "y"} & set(df.columns):
        (df, set_aside), builder = layouts.builder_rows(df), True
    missing = [c for c in CANONICAL if c not in df.columns]
    if missing:
        own = [c for c in df.columns if c not in ("line", "row_error")]
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}; {describe_columns(own)} "
                         f"(map other names with --columns NAME=COLUMN,...{_suggest(missing, own)})")
    if len(df) == 0:
        aside = f" ({_aside_text(set_aside)} set aside)" if set_aside else " (only a header)"
        raise InputError(f"{path}: no click rows{aside}")
    for c in ("participant", "stimulus_id"):
        df[c] = df[c].str.strip()
    if decimal is None:
        decimal = sniff_decimal(df["x"].head(500).tolist() + df["y"].head(500).tolist())
    if decimal == ",":
        for c in ("x", "y"):
            df[c] = to_decimal_point(df[c].tolist())
    if not (df["row_error"] != "").any():
        df = df.drop(columns="row_error")
    df = _unpack_lists(df)
    if builder:
        df = layouts.builder_to_image_px(df)
    df.attrs["set_aside"] = dict(set_aside)
    # x, y of a Builder file are image pixels already: analyze refuses --coords/--scale on them
    df.attrs["layout"] = "psychopy-builder" if builder else ("jspsych" if "trial_type" in df.columns else "")
    return df


def _is_json(path):
    """The file begins like JSON (``[`` or ``{``); one that cannot be opened is left to the CSV reader's message."""
    import os
    import stat

    from attneave.analysis.clicks.layouts import looks_like_json

    try:
        if not stat.S_ISREG(os.stat(path).st_mode):  # a FIFO would block open(); the CSV reader refuses it
            return False
        with open(path, "rb") as fh:
            return looks_like_json(fh.read(4096))
    except OSError:
        return False


def _aside_text(set_aside):
    """``'3 rows of trial_type survey-text, 2 practice trials'``."""
    return ", ".join(f"{n} {'rows of ' if k.startswith('trial_type') else ''}{k}" for k, n in set_aside.items())


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
