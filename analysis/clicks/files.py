"""Several click files read as one table.

The browser experiment and the PsychoPy script write one CSV per
participant (``attneave_P01.csv``, ...), so ``attneave analyze`` takes
them all at once: each is read by :func:`attneave.analysis.clicks.read.read_clicks` on
its own (its own separator and decimal mark, its own line numbers) and the
rows are stacked, with a column ``source_file`` naming the file each came
from. Nothing is merged silently: the same file given twice, or two files
holding the same bytes (a download and the copy that was POSTed), are
refused, and a participant id found in several files is reported (its
clicks are pooled, as for one participant's two sessions).
"""

from __future__ import annotations

import hashlib
from collections import Counter
from pathlib import Path

import numpy as np

from attneave.analysis.clicks.read import SOURCE, blank_rows, read_clicks, repeated_header_rows
from attneave.stimuli.errors import InputError

__all__ = ["SOURCE", "read_click_files", "participants_in_several_files", "repeated_rows"]


def _digest(path):
    """SHA-256 of a file's bytes, or None when it cannot be read (read_clicks then names the problem)."""
    try:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest()
    except OSError:
        return None


def read_click_files(paths, columns=None, sep=None, decimal=None, trial_type=None):
    """Read one or several click files into one table.

    Parameters
    ----------
    paths : str, Path or sequence of them
        Click files (CSV), e.g. one per participant.
    columns, sep, decimal, trial_type
        As for :func:`attneave.analysis.clicks.read.read_clicks`, applied to every file
        (the separator and decimal mark are found per file when not given).

    Returns
    -------
    pandas.DataFrame
        One file: exactly :func:`~attneave.analysis.clicks.read.read_clicks`'s table.
        Several: their rows in the order of `paths`, with a column
        :data:`SOURCE` (the path as given) after ``line`` (each file's own
        line numbers); a column a file lacks (another file's extra columns)
        is empty text on its rows. A file's own column named ``source_file``
        is kept as ``input_source_file``. ``attrs["set_aside"]`` sums the
        files' rows set aside (no clicks of the task; see
        :mod:`attneave.analysis.clicks.layouts`).

    Raises
    ------
    InputError
        A file that read_clicks refuses (the message names it), the same
        file given twice, or two files with identical contents.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "P01.csv").write_text("participant,stimulus_id,x,y\\nP01,rf_003,12.5,40\\n")
    >>> _ = (d / "P02.csv").write_text("participant;stimulus_id;x;y\\nP02;rf_003;30,5;41\\n")
    >>> t = read_click_files([d / "P01.csv", d / "P02.csv"])
    >>> t[["line", "participant", "x"]].values.tolist()
    [[2, 'P01', '12.5'], [2, 'P02', '30.5']]
    >>> [pathlib.Path(v).name for v in t["source_file"]]
    ['P01.csv', 'P02.csv']
    """
    import pandas as pd

    if isinstance(paths, (str, Path)):
        paths = [paths]
    paths = list(paths)
    if not paths:
        raise InputError("no click file given")
    if len(paths) == 1:
        return read_clicks(paths[0], columns=columns, sep=sep, decimal=decimal, trial_type=trial_type)
    seen, contents = {}, {}
    for p in paths:
        key = Path(p).resolve()
        if key in seen:
            raise InputError(f"{p}: given twice (as {seen[key]} too); give each click file once")
        seen[key] = p
        digest = _digest(p)
        if digest is not None and digest in contents:
            raise InputError(f"{p}: the same contents as {contents[digest]} (a file saved twice?); its clicks "
                             f"would count twice: give it once")
        if digest is not None:
            contents[digest] = p
    tables, set_aside, layouts = [], Counter(), set()
    for p in paths:
        t = read_clicks(p, columns=columns, sep=sep, decimal=decimal, trial_type=trial_type)
        set_aside.update(t.attrs.get("set_aside", {}))
        layouts.add(t.attrs.get("layout", ""))
        if SOURCE in t.columns:
            t = t.rename(columns={SOURCE: f"input_{SOURCE}"})
        t.insert(1, SOURCE, str(p))
        tables.append(t)
    out = pd.concat(tables, ignore_index=True, sort=False)
    for c in out.columns:
        if c == "list_index":  # -1: a row that held no list (read_clicks's convention)
            out[c] = out[c].fillna(-1).astype("Int64")
        elif c != "line" and out[c].isna().any():
            out[c] = out[c].astype(object).where(out[c].notna(), "")
    out.attrs["set_aside"] = dict(set_aside)
    out.attrs["layout"] = ",".join(sorted(v for v in layouts if v))
    return out


def participants_in_several_files(clicks):
    """A warning naming participant ids found in more than one file ('' if none).

    Parameters
    ----------
    clicks : pandas.DataFrame
        :func:`read_click_files`'s table (without a :data:`SOURCE` column
        there is one file and nothing to report).
    """
    if SOURCE not in clicks.columns or "participant" not in clicks.columns:
        return ""
    part = clicks["participant"].astype(str).str.strip()
    keep = (part != "").to_numpy() & ~repeated_header_rows(clicks)  # a repeated header names no one
    files = clicks.loc[keep, SOURCE].groupby(part[keep]).nunique()
    shared = files[files > 1]
    if shared.empty:
        return ""
    names = ", ".join(f"{k} ({v} files)" for k, v in list(shared.items())[:5])
    more = f" and {len(shared) - 5} more" if len(shared) > 5 else ""
    return (f"participant id(s) found in several click files, whose clicks are pooled as one participant's: "
            f"{names}{more}; if they are different people, give them different ids")


#: Words in a column name that make it an index or a time stamp: rows that differ there are different clicks.
INDEX_WORDS = frozenset({"trial", "click", "index", "idx", "number", "order", "seq", "sequence", "rep", "time",
                         "timestamp", "rt", "onset", "ms"})


def _index_columns(cols):
    """The columns whose names say they number or time the clicks (``trial``, ``click``, ``rt_ms``...)."""
    import re

    return [c for c in cols if set(re.split(r"[^a-z0-9]+", str(c).lower())) & INDEX_WORDS]


def repeated_rows(clicks):
    """A warning counting rows that look like copies of earlier rows ('' if none).

    With a column that numbers or times the clicks (:data:`INDEX_WORDS`:
    ``trial``, ``click``, ``timestamp``, ``rt_ms``...), as the browser page
    and the PsychoPy script write, a row equal to an earlier one in every
    column (but ``line``) is a copy: two real clicks differ there. Without
    such a column, a participant who clicks one point twice writes the same
    row twice; so a repeat is only reported when it is part of a block: at
    least two consecutive rows repeating consecutive earlier rows, as a file
    (or part of one) added twice gives. The rows are still analysed (nothing
    is dropped on a guess), and the warning says so. Repeated header lines
    and rows of separators only are not counted.
    """
    import pandas as pd

    from attneave.analysis.clicks.read import READER_COLUMNS

    cols = [c for c in clicks.columns if c not in READER_COLUMNS]
    if not cols or len(clicks) < 2:
        return ""
    dup = clicks[cols].duplicated().to_numpy() & ~repeated_header_rows(clicks)
    rows = np.flatnonzero(dup)
    if len(rows):  # rows of separators only are equal too, and no clicks (empty_row)
        dup[rows] = ~blank_rows(clicks, rows)
    if dup.any() and not _index_columns(cols):
        # the first row each row repeats; a row counts when a neighbour repeats the neighbour of its twin
        h = pd.util.hash_pandas_object(clicks[cols].astype(str), index=False).to_numpy()
        twin = pd.Series(np.arange(len(h))).groupby(h).transform("min").to_numpy()
        nxt = np.zeros(len(h), bool)
        nxt[:-1] = dup[:-1] & dup[1:] & (twin[1:] == twin[:-1] + 1)
        dup &= nxt | np.r_[False, nxt[:-1]]
    k = int(dup.sum())
    if k == 0:
        return ""
    first = clicks.loc[dup].iloc[0]
    where = (f"{Path(first[SOURCE]).name}:" if SOURCE in clicks.columns else "line ") + str(int(first["line"]))
    return (f"{k} row(s) repeat an earlier row in every column (first at {where}): a file or part of one added "
            f"twice? They are analysed as clicks; remove them if they are copies")
