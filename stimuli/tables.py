"""Tables as CSV files: one parser (the csv module) behind every reader, a
writer that gives byte-identical files for the same input, and messages
that name a file's columns without echoing its contents.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down).
"""

from __future__ import annotations

import csv
import io
import math
import re
from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import MAX_TEXT_BYTES, atomic_write, check_regular_file

__all__ = [
    "write_table",
    "neutralise_cell",
    "restore_cell",
    "FORMULA_STARTS",
    "describe_columns",
    "plausible_header",
    "shorten",
    "read_text_csv",
    "read_table",
    "read_points",
]


#: First characters that make a spreadsheet (Excel, LibreOffice, Google Sheets) evaluate a cell
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")
_PLAIN_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def neutralise_cell(value):
    """A text cell that a spreadsheet would evaluate, made inert by a leading ``'``.

    OWASP's rule against CSV (formula) injection [1]_: a text beginning with
    ``=``, ``+``, ``-``, ``@``, tab or carriage return gets a ``'`` before
    it, which spreadsheets read as "text" and do not show. A number
    (``-3.5``, ``+1e3``) is left as it is, and so is anything that is not a
    ``str``. :func:`restore_cell` undoes it.

    References
    ----------
    .. [1] OWASP, "CSV Injection", https://owasp.org/www-community/attacks/CSV_Injection

    Examples
    --------
    >>> neutralise_cell("=1+2"), neutralise_cell("@SUM(A1)"), neutralise_cell("-3.5"), neutralise_cell("P01")
    ("'=1+2", "'@SUM(A1)", '-3.5', 'P01')
    """
    if isinstance(value, str) and value[:1] in FORMULA_STARTS and value and not _PLAIN_NUMBER.fullmatch(value):
        return "'" + value
    return value


def restore_cell(value):
    """`value` without the ``'`` that :func:`neutralise_cell` put before it.

    Exactly one leading ``'`` is removed, and only when what follows begins
    with one of :data:`FORMULA_STARTS`; any other text is returned as it is.

    Examples
    --------
    >>> restore_cell("'=1+2"), restore_cell("'quoted'"), restore_cell("''=x")
    ('=1+2', "'quoted'", "''=x")
    """
    if isinstance(value, str) and value[:1] == "'" and value[1:2] and value[1:2] in FORMULA_STARTS:
        return value[1:]
    return value


def _neutralise_frame(table):
    """A copy of DataFrame `table` whose text cells and column names are neutralised (numbers untouched)."""
    from pandas.api.types import is_object_dtype, is_string_dtype

    text = [c for c in table.columns if is_object_dtype(table[c].dtype) or is_string_dtype(table[c].dtype)]
    names = [neutralise_cell(c) for c in table.columns]
    if not text and names == list(table.columns):
        return table
    out = table.copy(deep=False)
    for c in text:
        col = out[c]
        # only the cells that begin like a formula go through neutralise_cell (a vectorised test first:
        # a per-cell Python call on every text cell made the tables of a large study slow to write)
        hit = _text_test(col, lambda t: t.str[:1].isin(FORMULA_STARTS), lambda v: v[:1] in FORMULA_STARTS)
        if hit.any():
            fixed = col[hit].map(neutralise_cell)
            if not fixed.equals(col[hit]):
                out[c] = col.where(~hit, fixed).astype(col.dtype)
    out.columns = names
    return out


def _text_test(col, vectorised, per_cell):
    """Boolean Series: `per_cell` of each str cell of `col` (False elsewhere), by `vectorised` where pandas can."""
    strings = col.map(type) == str if col.dtype == object else col.notna()
    try:
        result = vectorised(col.where(strings, ""))
    except (AttributeError, TypeError):  # a column pandas' .str refuses
        result = col.map(lambda v: isinstance(v, str) and per_cell(v))
    return result.fillna(False).astype(bool) & strings


def _has_carriage_return(frame):
    """True when a text cell of DataFrame `frame` holds a carriage return."""
    from pandas.api.types import is_object_dtype, is_string_dtype

    return any(_text_test(frame[c], lambda t: t.str.contains("\r", regex=False), lambda v: "\r" in v).any()
               for c in frame.columns if is_object_dtype(frame[c].dtype) or is_string_dtype(frame[c].dtype))


def write_table(table, path, float_format="%.10g"):
    """Write a mapping of columns or a DataFrame to CSV, atomically.

    Floats are written with 10 significant digits by default, enough for
    sub-micro-pixel coordinates, and deterministic so that the same input
    gives byte-identical files. NaN and None are written as empty fields.
    A mapping of columns is written with the csv module (no pandas import:
    commands that write one table start faster); a DataFrame with its own
    ``to_csv``, with the same formatting.

    A text cell (or column name) that a spreadsheet would evaluate as a
    formula, such as a participant id ``=HYPERLINK(...)`` from an untrusted
    file, is written with a leading ``'`` (:func:`neutralise_cell`);
    numbers, and numeric columns, are written as they are.
    """
    import csv

    if hasattr(table, "to_csv"):
        table = _neutralise_frame(table)
        quoting = csv.QUOTE_NONNUMERIC if _has_carriage_return(table) else csv.QUOTE_MINIMAL
        with atomic_write(path, "w", newline="") as fh:
            table.to_csv(fh, index=False, float_format=float_format, lineterminator="\n", quoting=quoting)
        return
    names = [neutralise_cell(str(n)) for n in table]
    columns = [_format_column(table[name], float_format) for name in table]
    # the csv module quotes a field holding the line terminator ('\n') but not a lone '\r', which
    # every reader takes for a line end: a table holding one is written with its text quoted
    quoting = csv.QUOTE_ALL if any("\r" in v for col in columns for v in col) else csv.QUOTE_MINIMAL
    with atomic_write(path, "w", newline="") as fh:
        writer = csv.writer(fh, lineterminator="\n", quoting=quoting)
        writer.writerow(names)
        writer.writerows(zip(*columns))


def _format_column(values, float_format):
    """The text of every value of a column, as pandas' ``to_csv`` writes it."""
    a = np.asarray(values)
    if a.ndim == 0:
        a = a.reshape(1)
    if a.dtype.kind == "f":
        return ["" if v != v else float_format % v for v in a.tolist()]
    if a.dtype.kind in "iub":
        return [str(v) for v in a.tolist()]
    return ["" if v is None or (isinstance(v, float) and v != v) else
            (float_format % v if isinstance(v, float) else
             neutralise_cell(v) if isinstance(v, str) else str(v)) for v in a.tolist()]


def shorten(text, limit=30):
    """`text` as ``repr``, cut to about `limit` characters (for messages that quote a file).

    Examples
    --------
    >>> shorten("x")
    "'x'"
    >>> shorten("a" * 40, limit=10)
    "'aaaaaaaaa...'"
    """
    text = str(text)
    return repr(text if len(text) <= limit else text[: limit - 1] + "...")


# a column name as people write them: words, digits, spaces and a little punctuation;
# anything else (':' of /etc/passwd, '$' of a password hash, binary) is not a header
_HEADER_NAME = re.compile(r"^[\w .()\[\]/%#+*'-]{1,64}$")
_OTHER_SEPARATORS = {";": "';'", "\t": "tab", "|": "'|'"}


def plausible_header(columns):
    """True when `columns` look like the column names of a CSV header.

    Names as people write them (words, digits, spaces and ``. ( ) [ ] / % #
    + * ' -``, at most 64 characters each); pandas' ``Unnamed: i`` for empty
    fields is ignored. The first line of a password file, a binary file or
    prose is not a header, and its text is not quoted in messages.

    Examples
    --------
    >>> plausible_header(["participant", "mouse.x", "rt (ms)"]), plausible_header(["root:x:0:0"])
    (True, False)
    """
    names = [str(c).strip() for c in columns if not re.fullmatch(r"Unnamed: \d+", str(c))]
    return bool(names) and all(_HEADER_NAME.match(c) for c in names if c)


def describe_columns(columns, limit=5):
    """Name the columns found in a file, for a message about missing columns.

    Quoting a file's first line in a message would echo the contents of any
    file a user (or an attacker) points the program at, so the names are
    given only when they look like a CSV header, and cut short: the first
    `limit` names, each to 30 characters.

    Parameters
    ----------
    columns : sequence of str
        Column names as read.
    limit : int
        How many names to quote at most.

    Returns
    -------
    str
        E.g. ``"found 'a', 'b' (2 columns)"``, ``"found no columns"`` or a
        sentence saying the first line is not a CSV header (naming the
        separator it seems to use, if it is ';', tab or '|').

    Examples
    --------
    >>> describe_columns(["participant", "x"])
    "found 'participant', 'x' (2 columns)"
    >>> describe_columns(["participant;stimulus_id;x;y"])
    "found 1 column whose name holds ';': the file seems to use ';' as separator; expected commas"
    >>> describe_columns(["root:x:0:0:root:/root:/bin/bash"])
    'the first line is not a CSV header with comma-separated column names'
    """
    # pandas names an empty header field 'Unnamed: 3' (a trailing comma, as PsychoPy writes)
    names = [str(c) for c in columns if not re.fullmatch(r"Unnamed: \d+", str(c))]
    if not names:
        return "found no columns"
    if len(names) == 1:
        for sep, name in _OTHER_SEPARATORS.items():
            if sep in names[0] and all(_HEADER_NAME.match(p.strip() or "_") for p in names[0].split(sep)):
                return (f"found 1 column whose name holds {name}: the file seems to use {name} as separator; "
                        "expected commas")
    if not plausible_header(names):
        return "the first line is not a CSV header with comma-separated column names"
    shown = ", ".join(shorten(c) for c in names[:limit]) + (", ..." if len(names) > limit else "")
    return f"found {shown} ({len(names)} column{'s' if len(names) != 1 else ''})"


def read_text_csv(path, what="a CSV file", empty="expected a header"):
    """Read a CSV file as text, with the physical line of each row.

    Every value is a ``str`` as written (leading spaces skipped). Unlike a bare
    :func:`pandas.read_csv`, a data row with more fields than the header is
    never read shifted (pandas would take its first field as an index):
    empty extra fields (a delimiter at the end of every row, as some
    exporters write) are ignored, and a non-empty one is an error naming the
    line. A row with fewer fields than the header is padded with empty
    values. Blank lines are not rows; a row of empty fields is.

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
        Missing, a directory or other non-regular file, larger than
        :data:`MAX_TEXT_BYTES`, empty, not UTF-8 text, not parseable, or a row
        with values beyond the header.
    """
    import pandas as pd

    header, rows, lines = _read_records(path, what, empty)
    df = pd.DataFrame(rows, columns=header, dtype=str) if rows else pd.DataFrame(columns=header, dtype=str)
    return df, np.asarray(lines, dtype=np.int64)


def _read_records(path, what, empty):
    """``(header, rows, lines)`` of a CSV file, read with the csv module.

    The one CSV parser behind :func:`read_text_csv` and :func:`read_points`
    (pandas only wraps its result), so that reading a contour file costs no
    pandas import.
    """
    path = check_regular_file(path, what, max_bytes=MAX_TEXT_BYTES)
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            text = fh.read()
        if '"' not in text:
            # no quoted field, so one record per physical line: line numbers are positions, and the
            # records come in one C-level pass (a contour file of 360 points in a quarter of the time)
            records = list(csv.reader(io.StringIO(text, newline=""), skipinitialspace=True, strict=True))
            numbered = [(i + 1, r) for i, r in enumerate(records) if r]
        else:
            numbered = _numbered_records(text)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected {what}") from None
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not a readable CSV file (not UTF-8 text: {exc.reason})") from None
    except csv.Error as exc:
        raise InputError(f"{path}: not a readable CSV file ({exc})") from None
    except OSError as exc:  # no permission, ...
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    header, rows, lines = None, [], []
    if numbered:
        header = [c.strip() for c in numbered[0][1]]
        n = len(header)
        rows = [r if len(r) == n else _fit_record(path, r, header, line) for line, r in numbered[1:]]
        lines = [line for line, _ in numbered[1:]]
    if header is None:
        raise InputError(f"{path}: empty file ({empty})")
    return header, rows, lines


def _numbered_records(text):
    """``[(first line, record), ...]`` of the non-blank records of CSV `text` (a quoted field may span lines)."""
    reader = csv.reader(io.StringIO(text, newline=""), skipinitialspace=True, strict=True)
    out, end = [], 0
    for record in reader:
        start, end = end + 1, reader.line_num
        if record:
            out.append((start, record))
    return out


def _fit_record(path, record, header, line):
    """A record cut or padded to the `header`'s fields; non-empty extras are an error."""
    n = len(header)
    if len(record) > n:
        if any(v.strip() for v in record[n:]):
            hint = describe_columns(header) if n == 1 else ""
            if "separator" in hint:  # 'x;y' as one column: say so, not 'add a column name'
                raise InputError(f"{path}: line 1: {hint}")
            extra = ", ".join(shorten(v) for v in record[n:][:3]) + (", ..." if len(record) - n > 3 else "")
            raise InputError(f"{path}: line {line}: {len(record)} fields but the header has {n} "
                             f"(extra value(s) {extra}); add a column name to the header or remove them")
        return record[:n]
    return record + [""] * (n - len(record))


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
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}; {describe_columns(df.columns)}")
    for col in numeric:
        values = pd.to_numeric(df[col], errors="coerce")
        bad = ~np.isfinite(values.to_numpy(dtype=float))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"{path}: line {lines[i]}: column {col!r} must be a finite number, got {shorten(df[col].iloc[i])}"
            )
        df[col] = values.astype(float)
    return df


def read_points(path, columns=("x", "y"), with_lines=False):
    """Read an (N, 2) array of points from a CSV file with columns `x`, `y`.

    Points are ``(x, y)`` in image pixels (x = column, y = row, y down).
    With `with_lines`, also the file line of each point (header = line 1;
    blank lines are no points and a quoted field may span lines, so point i
    is not always on line i + 2): messages name the lines a person sees.

    Raises
    ------
    InputError
        As :func:`read_table`: a missing column, a value that is not a finite
        number (naming its line), or no rows.
    """
    path = Path(path)
    header, rows, lines = _read_records(path, "a CSV file", "expected a header")
    missing = [c for c in columns if c not in header]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}; {describe_columns(header)}")
    if not rows:
        raise InputError(f"{path}: no rows")
    out = np.empty((len(rows), len(columns)))
    for j, name in enumerate(columns):
        c = header.index(name)
        try:  # the common case in one C-level pass (float() as below, so the same values)
            out[:, j] = np.fromiter(map(float, [row[c] for row in rows]), dtype=float, count=len(rows))
            if np.isfinite(out[:, j]).all():
                continue
        except ValueError:
            pass
        for i, row in enumerate(rows):  # find the first bad value, for the message
            try:
                v = float(row[c])
            except ValueError:
                v = math.nan
            if not math.isfinite(v):
                raise InputError(f"{path}: line {lines[i]}: column {name!r} must be a finite number, "
                                 f"got {shorten(row[c])}")
            out[i, j] = v
    return (out, np.asarray(lines, dtype=np.int64)) if with_lines else out


