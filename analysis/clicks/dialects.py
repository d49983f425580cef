"""Reading click files as the tools of the lab write them: separators, decimal commas, bad rows.

A contour file or a manifest is written by a program and read strictly
(:func:`attneave.stimuli.tables.read_text_csv`). A click file comes from an experiment
run in PsychoPy, jsPsych, a spreadsheet or a script, often saved by a
spreadsheet with a European locale, so it is read tolerantly:

* the separator is found from the header line (``,``, ``;``, tab or ``|``:
  the one that splits it into the most fields; ties go to the comma), unless
  it is given (``--sep``);
* decimal commas (``12,5``) in the coordinate columns are recognised when
  such values occur there and no value with a decimal point does (or when
  ``--decimal ,`` is given), and are converted to ``12.5``;
* a row whose field count differs from the header's (a hand edit, a field
  with an unquoted separator, a quote left open) is not a reason to refuse
  the file: it is kept, with its fields as far as they go, and flagged so
  that analysis excludes it with reason ``malformed_row``. Empty fields after
  the last column (PsychoPy ends every line with a separator) are not extra
  fields.
* The text is UTF-8 (with or without a byte-order mark) or UTF-16 with a
  byte-order mark (Excel's "Unicode text").
"""

from __future__ import annotations

import codecs
import csv
import io
import re

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import MAX_TEXT_BYTES, check_regular_file

__all__ = ["SEPARATORS", "read_tolerant_csv", "repeated_header", "sniff_separator", "sniff_decimal",
           "to_decimal_point"]

#: Separators recognised in a header line, by name for messages.
SEPARATORS = {",": "','", ";": "';'", "\t": "tab", "|": "'|'"}
_COMMA_NUMBER = re.compile(r"^\s*[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?\s*$")
_POINT_NUMBER = re.compile(r"^\s*[+-]?(\d+\.\d*|\.\d+)([eE][+-]?\d+)?\s*$")
# rows looked at to decide on decimal commas
_SNIFF_ROWS = 500


def _separator(sep):
    """A separator as given on the command line (``;``, ``tab``, ``\\t``) -> one character."""
    if sep is None:
        return None
    s = {"tab": "\t", "\\t": "\t", "semicolon": ";", "comma": ",", "pipe": "|"}.get(str(sep).lower(), str(sep))
    if len(s) != 1 or s in "\"\r\n" or s.isalnum() or s == ".":
        raise InputError(f"--sep: expected one separator character such as ',', ';', '|' or 'tab', got {sep!r}")
    return s


def sniff_separator(header):
    """The separator that splits a header line into the most fields.

    Parameters
    ----------
    header : str
        The first line of the file.

    Returns
    -------
    str
        One of :data:`SEPARATORS`; ``','`` when none splits the line.

    Examples
    --------
    >>> sniff_separator("participant;stimulus_id;x;y")
    ';'
    >>> sniff_separator('"rt","stimulus","response"')
    ','
    """
    best, count = ",", 1
    for sep in SEPARATORS:
        try:
            fields = next(csv.reader([header], delimiter=sep), [])
        except csv.Error:  # a field beyond csv's size limit with this separator: not it
            continue
        while fields and not fields[-1].strip():
            fields.pop()
        if len(fields) > count:
            best, count = sep, len(fields)
    return best


def sniff_decimal(values):
    """``','`` when text numbers use decimal commas, else ``'.'``.

    Decimal commas are recognised when some values look like ``12,5`` and none
    like ``12.5``; integers say nothing either way.

    Examples
    --------
    >>> sniff_decimal(["12,5", "3", "-0,25"]), sniff_decimal(["12.5", "3"]), sniff_decimal(["1,5", "2.5"])
    (',', '.', '.')
    """
    comma = point = False
    for v in values[:_SNIFF_ROWS]:
        comma = comma or bool(_COMMA_NUMBER.match(v))
        point = point or bool(_POINT_NUMBER.match(v))
    return "," if comma and not point else "."


def to_decimal_point(values):
    """Text numbers with a decimal comma -> with a decimal point; other values unchanged.

    Examples
    --------
    >>> to_decimal_point(["12,5", "abc", "", "3"])
    ['12.5', 'abc', '', '3']
    """
    import pandas as pd

    s = pd.Series(values, dtype=object)
    new = s.str.replace(",", ".", regex=False)
    # keep a value as written unless the change made it a number ('[1,2]', '1.234,5' stay)
    number = pd.to_numeric(new, errors="coerce").notna().to_numpy() & (new != s).to_numpy(dtype=bool)
    return s.where(~number, new).tolist()


def _decode(path, raw):
    """File bytes -> text: UTF-16 with a byte-order mark, else UTF-8 (optional BOM)."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        encoding = "utf-16"
    else:
        encoding = "utf-8-sig"
    try:
        return raw.decode(encoding)
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise InputError(f"{path}: line {line}: not {encoding.upper().replace('-SIG', '')} text (byte "
                         f"0x{raw[exc.start]:02x}); save the file as UTF-8 (a spreadsheet's 'CSV UTF-8')") from None


def read_tolerant_csv(path, sep=None, what="a CSV file", empty="expected a header"):
    """Read a CSV file as text, keeping rows whose field count is wrong.

    Parameters
    ----------
    path : str or Path
        The file (a regular file of at most :data:`attneave.stimuli.io.MAX_TEXT_BYTES`).
    sep : str, optional
        Field separator (``','``, ``';'``, ``'tab'``, ...); default: found
        from the header line (:func:`sniff_separator`).
    what, empty : str
        What the file should be and what an empty file lacks (for messages).

    Returns
    -------
    df : pandas.DataFrame
        Columns named as in the header (stripped; an empty name in the middle
        becomes ``Unnamed: i``, empty names at the end are dropped), one row
        per non-blank record, every value a ``str`` as written (leading spaces
        skipped). A malformed row holds its first fields, padded with ``''``.
    lines : (M,) ndarray of int
        Line of the file on which each row starts (the header is line 1).
    row_error : (M,) ndarray of str
        ``''``, or what is wrong with the row (e.g. ``'5 fields, the header
        has 4'``).
    sep : str
        The separator used.

    Raises
    ------
    InputError
        Not a regular file, too large, not text, empty, a header naming a
        column twice, or an invalid `sep`.
    """
    import pandas as pd

    path = check_regular_file(path, what, max_bytes=MAX_TEXT_BYTES)
    sep = _separator(sep)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    text = _decode(path, raw)
    if not text.strip():
        raise InputError(f"{path}: empty file ({empty})")
    if sep is None:
        sep = sniff_separator(text.splitlines()[0])
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=sep, skipinitialspace=True)
    try:
        header = next(reader)
    except csv.Error as exc:
        raise InputError(f"{path}: line 1: not a readable CSV header ({exc})") from None
    names = [c.strip() for c in header]
    while names and not names[-1]:
        names.pop()
    names = [c or f"Unnamed: {i}" for i, c in enumerate(names)]
    seen = set()
    for c in names:
        if c in seen:
            raise InputError(f"{path}: column {c[:30]!r} appears twice in the header")
        seen.add(c)
    n = len(names)
    fast = _read_fast(raw, sep, names, header) if n else None
    if fast is not None:
        return (*fast, sep)
    physical = io.StringIO(text, newline="").readlines()  # the lines as csv counts them
    rows, lines, errors = [], [], []
    done = reader.line_num  # physical lines consumed (the header's)
    while True:
        more, ends = _parse_rows(path, physical[done:], sep, n, done)
        i = _open_quote(physical, sep, n, *more, ends)
        for part, got in zip((rows, lines, errors), more):
            part.extend(got[:i])
        if i == len(ends):
            break
        # a quote left open swallows the lines after it into one field (up to the next quote,
        # or to the end of the file): its own line is a malformed row, and the lines after it
        # are read again as the rows they are
        line = more[1][i]
        fields = next(csv.reader([physical[line - 1].rstrip("\r\n")], delimiter=sep, skipinitialspace=True,
                                 quoting=csv.QUOTE_NONE))
        rows.append(_fit(fields, n)[0])
        lines.append(line)
        errors.append(f"a quote opened on line {line} is never closed")
        done = line
    df = pd.DataFrame(rows, columns=names, dtype=object) if rows else pd.DataFrame(columns=names, dtype=object)
    return df, np.asarray(lines, dtype=np.int64), np.asarray(errors, dtype=object), sep


def _parse_rows(path, physical, sep, n, offset):
    """``((rows, lines, errors), last lines)`` of the CSV records in `physical`, the lines after line `offset`."""
    reader = csv.reader(iter(physical), delimiter=sep, skipinitialspace=True)
    rows, lines, errors, ends = [], [], [], []
    prev = 0
    try:
        for row in reader:
            start, prev = prev + 1, reader.line_num
            if not row or (len(row) == 1 and not row[0].strip()):
                continue  # a blank line is not a row
            row, err = _fit(row, n)
            rows.append(row)
            lines.append(offset + start)
            errors.append(err)
            ends.append(offset + prev)
    except csv.Error as exc:  # a NUL byte, a field beyond csv's size limit
        raise InputError(f"{path}: line {offset + reader.line_num}: not readable as CSV ({exc})") from None
    return (rows, lines, errors), ends


def _open_quote(physical, sep, n, rows, lines, errors, ends):
    """Index of the first row that a stray quote made span several lines, or ``len(rows)``.

    Such a row is malformed (its field count is wrong); or it is the last and
    its lines hold an odd number of quotes (the quote runs to the end of the
    file); or its first line and another of its lines are each a whole record
    by themselves (a quote that the next stray quote closed, swallowing the
    rows between). A field that legitimately holds a line break (a typed
    answer) leaves its first line short of fields.
    """
    def whole(line):
        fields = next(csv.reader([physical[line - 1].rstrip("\r\n")], delimiter=sep, quoting=csv.QUOTE_NONE), [])
        return _fit(fields, n)[1] == ""

    for i, (start, end) in enumerate(zip(lines, ends)):
        if end > start and (errors[i] or (i == len(rows) - 1 and "".join(physical[start - 1 : end]).count('"') % 2)
                            or (whole(start) and any(whole(k) for k in range(start + 1, end + 1)))):
            return i
    return len(rows)


def _fit(row, n):
    """A row's fields fitted to `n` columns, and what was wrong with it ('' if nothing)."""
    if len(row) > n and not any(v.strip() for v in row[n:]):
        row = row[:n]  # empty fields after the last column
    if len(row) == n:
        return row, ""
    return (row + [""] * n)[:n], f"{len(row)} field{'s' if len(row) != 1 else ''}, the header has {n}"


def _read_fast(raw, sep, names, header):
    """The common case at the speed of pandas' C parser, or None for the general reader.

    Without quotes in the file, the separators on each line give its field
    count exactly, so the rows with a wrong count are found with numpy; they
    are blanked to a row of empty fields for pandas and then filled from their
    own line, parsed alone. Quotes, a lone CR, UTF-16, a header ending with
    empty names, or more than 1% of bad rows go to the general reader.
    """
    import pandas as pd

    if raw.startswith(codecs.BOM_UTF8):
        raw = raw[len(codecs.BOM_UTF8):]
    n = len(names)
    if (raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)) or b'"' in raw or len(header) != n
            or raw.count(b"\r") != raw.count(b"\r\n")):
        return None
    buf = np.frombuffer(raw, np.uint8)
    nl = np.flatnonzero(buf == 10)
    starts = np.concatenate(([0], nl + 1))
    ends = np.append(nl, len(buf))
    if starts[-1] == len(buf):  # the file ends with a line break
        starts, ends = starts[:-1], ends[:-1]
    ends = ends - ((ends > starts) & (buf[np.maximum(ends - 1, 0)] == 13))  # CRLF
    length = ends - starts
    counts = np.bincount(np.searchsorted(nl, np.flatnonzero(buf == ord(sep))), minlength=len(starts))[: len(starts)]
    blank = length == 0
    bad = ~blank & (counts != n - 1)
    bad[0] = False
    idx = np.flatnonzero(bad)
    if len(idx) > max(100, 0.01 * len(starts)) or (length[idx] < n - 1).any():
        return None
    data = bytearray(raw) if len(idx) else raw
    for i in idx:  # a row of n empty fields in place of the bad line, same length
        data[starts[i] : ends[i]] = sep.encode() * (n - 1) + b" " * int(length[i] - (n - 1))
    df = pd.read_csv(io.BytesIO(bytes(data)), sep=sep, dtype=str, keep_default_na=False, skipinitialspace=True,
                     index_col=False, skip_blank_lines=True, encoding="utf-8", quoting=csv.QUOTE_NONE)
    keep = np.flatnonzero(~blank)[1:]
    if len(df) != len(keep) or len(df.columns) != n:
        return None  # not the file this reasoning assumed: let the general reader decide
    df.columns = names
    errors = np.full(len(df), "", dtype=object)
    white = np.zeros(len(df), bool)
    for r, i in zip(np.searchsorted(keep, idx), idx):
        line = raw[starts[i] : ends[i]].decode("utf-8")
        if not line.strip():
            white[r] = True  # white space only: a blank line, not a row
            continue
        fields, errors[r] = _fit(next(csv.reader([line], delimiter=sep, skipinitialspace=True)), n)
        df.iloc[r] = fields
    if white.any():
        df, keep, errors = df.loc[~white].reset_index(drop=True), keep[~white], errors[~white]
    return df, keep + 1, errors


def repeated_header(df):
    """Rows whose every field is the header's name of its column (stripped; a byte-order mark ignored).

    Such a line is the header of a file that was appended to another, as
    ``cat`` or a copy and paste of several participants' files writes it.
    """
    names = list(df.columns)
    out = np.zeros(len(df), bool)
    if not names or not len(df):
        return out

    def same(values, name):
        v = values.str.strip().str.lstrip("\ufeff").str.strip()
        # an empty name in the header was read as 'Unnamed: i'
        return ((v == name) | ((v == "") & name.startswith("Unnamed: "))).to_numpy(dtype=bool)

    idx = np.flatnonzero(same(df[names[0]], names[0]))  # candidates by the first column, then the others
    for name in names[1:]:
        if not len(idx):
            break
        idx = idx[same(df[name].iloc[idx], name)]
    out[idx] = True
    return out
