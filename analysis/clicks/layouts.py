"""Click files of jsPsych and of PsychoPy Builder: finding the clicks among their rows.

:func:`attneave.analysis.clicks.read.read_clicks` reads every file as a table
of text; this module recognises two layouts in it and turns them into one row
per click with ``x, y`` in image pixels. Rows that hold no click of the task
(instructions, surveys, practice) are *set aside*: removed from the table,
not excluded clicks, and counted in the table's ``attrs["set_aside"]``
(``{what: rows}``), which ``attneave analyze`` reports in ``summary.json``
(``rows_set_aside``) and on stderr.

jsPsych
-------
A file of ``jsPsych.data.get().csv()`` or ``.json()`` [1]_ (a column
``trial_type``) has one row per trial of every plugin. The clicks are a
column whose cells are lists of objects ``{"x": .., "y": .., "rt": ..}`` (a
JSON text in a CSV cell), as the attneave plugin ``attneave-points`` records
them in image pixels in ``clicks``; ``--columns x=COLUMN`` names another
column. The trial type is ``trial_type`` (``--trial-type``), by default
``attneave-points`` or else the only type whose rows hold clicks; rows of
every other type are set aside. Each object becomes a row: its ``x`` and
``y``, its other keys as ``<column>.<key>`` (``clicks.rt``), ``list_index``
its place in the list; the list's own column is not repeated on every
click. An empty list ``[]`` is one row with a missing coordinate (the trial
had no click), as in :func:`attneave.analysis.clicks.read.read_clicks`.

PsychoPy Builder
----------------
The data file (``*.csv``) of ``attneave experiment --psychopy``'s Builder
experiment: ``mouse.x``, ``mouse.y`` and ``mouse.time`` hold lists (``[0.1,
0.2]``) in the window's units, and every row carries the conditions' columns,
among them ``size_w, size_h`` (the image's size in those units) and
``width_px, height_px`` (in pixels). With the image at the window centre and y
up, a click ``(X, Y)`` is, in image pixels (pixel centres at integers, y
down)::

    x = (X / size_w + 0.5) * width_px - 0.5
    y = (0.5 - Y / size_h) * height_px - 0.5

The values as written are kept in ``mouse.x`` and ``mouse.y``. Rows without
an image and without clicks (the routines outside the loop: instructions,
the end) and practice rows (``practice`` 1) are set aside. The stimulus is
the file name of ``image`` without its extension (the export copies each
image to ``images/<id>.<ext>``): PsychoPy's ``importConditions`` reads a
``stimulus_id`` such as ``007`` as the number 7, which would name no
stimulus; the column as written is kept as ``input_stimulus_id``.

References
----------
.. [1] de Leeuw, J. R. (2015). jsPsych: A JavaScript library for creating
       behavioral experiments in a Web browser. Behavior Research Methods,
       47(1), 1-12.
"""

from __future__ import annotations

import json
from collections import Counter

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import MAX_TEXT_BYTES, check_regular_file

__all__ = ["ATTNEAVE_TRIAL_TYPE", "BUILDER_COLUMNS", "looks_like_json", "read_json_records", "jspsych_clicks",
           "builder_rows", "builder_to_image_px"]

#: The trial_type of the attneave jsPsych plugin.
ATTNEAVE_TRIAL_TYPE = "attneave-points"
#: Columns that mark the data file of the attneave Builder export.
BUILDER_COLUMNS = ("mouse.x", "mouse.y", "size_w", "size_h", "width_px", "height_px")


def looks_like_json(raw):
    """True when a file's bytes begin (after a byte-order mark and white space) with ``[`` or ``{``."""
    head = raw[:4096].lstrip(b"\xef\xbb\xbf").lstrip()
    return head[:1] in (b"[", b"{")


def _text(value):
    """A JSON value as the text a CSV cell would hold: nested values as JSON, null as ''."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    return json.dumps(value, ensure_ascii=False, allow_nan=True)


def read_json_records(path):
    """A JSON array of trial objects (jsPsych's ``.json()``) as a table of text.

    Returns
    -------
    df : pandas.DataFrame
        One row per object, columns the keys in the order first met, every
        value text (lists and objects as JSON).
    lines : (M,) ndarray of int
        The object's place in the array (1-based): a JSON file has no lines
        to count by.

    Raises
    ------
    InputError
        Not JSON, or not an array of objects.
    """
    import pandas as pd

    path = check_regular_file(path, "a JSON click file", max_bytes=MAX_TEXT_BYTES)
    try:
        data = json.loads(path.read_bytes().decode("utf-8-sig"))
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}: not valid JSON ({exc.msg})") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if isinstance(data, dict) and isinstance(data.get("trials"), list):
        data = data["trials"]
    if not isinstance(data, list) or not all(isinstance(r, dict) for r in data):
        raise InputError(f"{path}: expected a JSON array of trial objects (jsPsych's data.get().json()), "
                         f"got {type(data).__name__}")
    if not data:
        raise InputError(f"{path}: no trials (an empty JSON array)")
    columns = list(dict.fromkeys(k for r in data for k in r))
    rows = [[_text(r.get(c)) for c in columns] for r in data]
    return pd.DataFrame(rows, columns=[str(c) for c in columns], dtype=object), np.arange(1, len(data) + 1)


def _objects(cell):
    """A cell's list of objects, or None when it is not written as one."""
    v = str(cell).strip()
    if not v.startswith("["):
        return None
    try:
        items = json.loads(v)
    except ValueError:
        return None
    if isinstance(items, list) and all(isinstance(o, dict) for o in items):
        return items
    return None


def _clicks_column(df, mapping):
    """The column holding lists of {x, y} objects: the one mapped to x, or 'clicks', or the only such one."""
    holding = [c for c in df.columns if df[c].astype(str).str.match(r"\s*\[\s*\{").any()]
    if mapping.get("x") and "x" in holding and mapping.get("y") in (None, mapping["x"]):
        return "x"
    if "x" in df.columns and "y" in df.columns:
        return None  # coordinates in columns of their own
    for c in ("clicks", *holding):
        if c in holding:
            return c
    return None


def _choose_type(path, types, holds, trial_type):
    """The trial_type whose rows are the trials (see the module docstring)."""
    with_clicks = Counter(types[holds])
    if trial_type is not None:
        if trial_type not in set(types):
            raise InputError(f"--trial-type: {path} has no rows of trial_type {trial_type!r}; trial types there: "
                             f"{', '.join(repr(t) for t in dict.fromkeys(types))}")
        return trial_type
    if ATTNEAVE_TRIAL_TYPE in with_clicks:
        return ATTNEAVE_TRIAL_TYPE
    if len(with_clicks) == 1:
        return next(iter(with_clicks))
    several = ", ".join(f"{t!r} ({n} rows)" for t, n in with_clicks.most_common())
    raise InputError(f"{path}: clicks are recorded by several trial types: {several}; choose one with "
                     f"--trial-type NAME")


def jspsych_clicks(df, path, mapping, trial_type=None):
    """A jsPsych table (a column ``trial_type``) -> one row per click (see the module docstring).

    Parameters
    ----------
    df : pandas.DataFrame
        The file as text, columns renamed by the mapping, with ``line``.
    path : Path
    mapping : dict
        The ``--columns`` mapping (canonical name -> the file's column).
    trial_type : str, optional

    Returns
    -------
    df : pandas.DataFrame
    set_aside : collections.Counter
        ``'trial_type NAME'`` -> rows set aside.

    Raises
    ------
    InputError
        No click column and no x, y columns; lists of objects without
        ``x`` and ``y``; several trial types with clicks and no
        `trial_type`; an unknown `trial_type`.
    """
    import pandas as pd

    from attneave.stimuli.tables import describe_columns

    col = _clicks_column(df, mapping)
    types = df["trial_type"].astype(str).str.strip().to_numpy(dtype=object)
    if col is None:
        if "x" not in df.columns or "y" not in df.columns:
            raise InputError(
                f"{path}: no clicks found: a jsPsych file (column trial_type) holds them in a column whose cells "
                f"are lists of {{\"x\": .., \"y\": .., \"rt\": ..}} objects (the attneave-points plugin's "
                f"'clicks'; another column: --columns x=COLUMN) or in columns x and y; "
                f"{describe_columns(df.columns)}")
        holds = (df["x"].astype(str).str.strip() != "").to_numpy()
    else:
        holds = df[col].astype(str).str.lstrip().str.startswith("[").to_numpy()
    chosen = _choose_type(path, types, holds, trial_type)
    keep = types == chosen
    set_aside = Counter(f"trial_type {t}" for t in types[~keep])
    df = df.loc[keep].reset_index(drop=True)
    if col is None:
        return df, set_aside
    lists = [_objects(v) for v in df[col]]
    keys = Counter(k for items in lists if items for o in items for k in o)
    if keys and not (keys["x"] and keys["y"]):
        raise InputError(f"{path}: column {col!r} holds lists of objects with keys "
                         f"{', '.join(sorted(keys)[:8])}, not x and y (image pixels)")
    extra = [k for k in keys if k not in ("x", "y")]
    name = mapping["x"] if col == "x" else col  # the file's name of the column, for the keys' columns
    out = []
    for i, items in enumerate(lists):
        base = df.iloc[i].to_dict()
        del base[col]
        if items is None:  # not a list of objects (cut short, say): a malformed row, excluded as such
            why = f"column {name!r} is not a JSON list of {{x, y}} objects"
            out.append({**base, "x": "", "y": "", "list_index": -1, "row_error": base.get("row_error") or why})
            continue
        if not items:
            out.append({**base, "x": "", "y": "", "list_index": -1})
            continue
        for k, o in enumerate(items):
            row = {**base, "x": _text(o.get("x")), "y": _text(o.get("y")), "list_index": k}
            row.update({f"{name}.{key}": _text(o.get(key)) for key in extra})
            out.append(row)
    kept = [c for c in df.columns if c != col]
    columns = kept + [c for c in ("x", "y") if c not in kept] + [f"{name}.{key}" for key in extra] + ["list_index"]
    table = pd.DataFrame(out, columns=columns).fillna("")
    for c in table.columns:
        if c != "list_index":
            table[c] = table[c].astype(object)
    table["list_index"] = pd.array(table["list_index"].astype(int), dtype="Int64")
    if "line" in table.columns:
        table["line"] = table["line"].astype(np.int64)
    return table, set_aside


def builder_rows(df):
    """The trials of an attneave Builder data file, ``mouse.x/y`` as ``x, y`` (before lists are unpacked).

    Returns
    -------
    df : pandas.DataFrame
        The trial rows; ``x, y`` the lists as written (also kept as
        ``mouse.x, mouse.y``, and unpacked by read_clicks alongside),
        ``stimulus_id`` from ``image`` where it names a file.
    set_aside : collections.Counter
    """
    from pathlib import PurePosixPath

    x = df["mouse.x"].astype(str).str.strip()
    image = df["image"].astype(str).str.strip() if "image" in df.columns else x.where(False, "")
    outside = ((x == "") & (image == "")).to_numpy()
    practice = (df["practice"].astype(str).str.strip().isin(["1", "1.0"]).to_numpy()
                if "practice" in df.columns else np.zeros(len(df), bool))
    set_aside = Counter({"rows of routines outside the trials loop": int(outside.sum()),
                         "practice trials": int((practice & ~outside).sum())})
    df = df.loc[~outside & ~practice].reset_index(drop=True)
    df.insert(df.columns.get_loc("mouse.x"), "x", df["mouse.x"].to_numpy())
    df.insert(df.columns.get_loc("mouse.y"), "y", df["mouse.y"].to_numpy())
    if "image" in df.columns:
        named = df["image"].astype(str).str.strip()
        stems = named.map(lambda v: PurePosixPath(v.replace("\\", "/")).stem if v else "")
        if "stimulus_id" in df.columns:
            df.insert(df.columns.get_loc("stimulus_id") + 1, "input_stimulus_id", df["stimulus_id"].to_numpy())
        df["stimulus_id"] = np.where(stems != "", stems, df.get("stimulus_id", stems))
    return df, +set_aside


def builder_to_image_px(df):
    """``x, y`` (window units, unpacked) -> image pixels with each row's ``size_w, size_h, width_px, height_px``.

    A value that is not a number, or a row whose sizes are not positive
    numbers, stays as written, so that analysis names the reason.

    Examples
    --------
    >>> import pandas as pd
    >>> t = pd.DataFrame(dict(x=["-0.4", "0"], y=["0.3", "0"], size_w=["0.8"] * 2, size_h=["0.6"] * 2,
    ...                       width_px=["160"] * 2, height_px=["120"] * 2))
    >>> builder_to_image_px(t)[["x", "y"]].values.tolist()
    [['-0.5', '-0.5'], ['79.5', '59.5']]
    """
    import pandas as pd

    def num(c):
        return pd.to_numeric(df[c], errors="coerce").to_numpy(dtype=float)

    X, Y = num("x"), num("y")
    sw, sh, w, h = num("size_w"), num("size_h"), num("width_px"), num("height_px")
    ok = np.isfinite(X) & np.isfinite(Y) & (sw > 0) & (sh > 0) & (w > 0) & (h > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        xi = (X / sw + 0.5) * w - 0.5
        yi = (0.5 - Y / sh) * h - 0.5
    out = df.copy()
    # repr of a float is exact: the text parses back to the same number
    out["x"] = np.where(ok, [repr(float(v)) for v in xi], df["x"].to_numpy(dtype=object))
    out["y"] = np.where(ok, [repr(float(v)) for v in yi], df["y"].to_numpy(dtype=object))
    return out
