"""Which stimulus a click belongs to, and how many clicks analysis had to leave out.

Experiment software rarely writes the stimulus id of a set: PsychoPy's
conditions files and jsPsych's ``stimulus`` field hold the image file
(``rf_003.png``, ``images/rf_003.png``, ``C:\\exp\\stimuli\\rf_003.png``).
:func:`match_stimulus_ids` finds the stimulus such a value names, so that
those files are analysed as they are. :func:`exclusion_report` says, on
stderr and in the outputs, when a large share of the clicks was excluded
(a forgotten ``--scale`` or wrong ``--coords`` excludes most of them, and a
p-value from the few left would mislead).
"""

from __future__ import annotations

from pathlib import Path

from attneave.analysis.clicks.read import SOURCE
from attneave.stimuli.tables import shorten

__all__ = ["WARN_FRACTION", "match_stimulus_ids", "resolve_stimulus_ids", "exclusion_report"]

#: Share of excluded clicks above which analysis warns.
WARN_FRACTION = 0.2
# hints for the commonest causes of a reason
_HINTS = {
    "outside_image": "check --coords, --scale and --window-size",
    "far_from_contour": "check --coords, --scale and --window-size, or --tolerance",
    "unknown_stimulus": "stimulus values must name a stimulus id, image file name or image path of the set",
    "non_numeric_coordinate": "check the decimal mark (--decimal) and separator (--sep)",
    "repeated_header": "header lines inside the file, as when files are joined together; not clicks",
    "malformed_row": "rows whose field count differs from the header's; see row_error in clicks.csv",
    "coordinate_list": "x and y lists of different lengths",
    "off_drawn_part": "clicks in the gaps of stimuli that showed only fragments, dots or a polygon",
}


def _parts(path):
    """Path components of a value written on Windows or POSIX (``\\`` and ``/`` both separate)."""
    return [p for p in str(path).replace("\\", "/").split("/") if p not in ("", ".")]


def match_stimulus_ids(values, stimset):
    """The stimulus id each value names: by id, image path or image file name.

    Parameters
    ----------
    values : sequence of str
        Stimulus values as written in a click file.
    stimset : StimulusSet
        The set; its manifest's ``image`` column (paths relative to the set)
        gives the image of each stimulus.

    Returns
    -------
    ids : (M,) ndarray of object
        The matched id, or the value itself (stripped) when nothing matches.
    how : (M,) ndarray of object
        ``'id'``, ``'image'`` (the value is a path whose trailing components
        equal the end of exactly one stimulus's image path; the longest such
        match wins, so ``a/rf.png`` and ``b/rf.png`` are told apart by their
        folder), ``'file_stem'`` (the value's file name without extension is
        an id, for sets without images), ``'case'`` (one of these, found
        only when letter case is ignored and then by exactly one stimulus: a
        path typed on Windows, ``C:\\Exp\\RF_003.PNG``, names the file
        ``rf_003.png`` there) or ``''`` (no match, or a file name shared by
        several images with nothing to tell them apart).

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set
    >>> th = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    >>> d = tempfile.mkdtemp()
    >>> _ = write_stimulus_set(d, {"rf_003": np.c_[50 + 20 * np.cos(th), 50 + 20 * np.sin(th)]}, size=(100, 100))
    >>> ids, how = match_stimulus_ids(["rf_003", "rf_003.png", "C:\\\\exp\\\\rf_003.png", "other.png", "RF_003"],
    ...                               read_stimulus_set(d))
    >>> ids.tolist(), how.tolist()
    (['rf_003', 'rf_003', 'rf_003', 'other.png', 'rf_003'], ['id', 'image', 'image', '', 'case'])
    """
    import pandas as pd

    ids = list(stimset.ids)
    known = set(ids)
    images = {}  # file name -> [(path components, id)]
    mani = stimset.manifest
    if mani is not None and "image" in mani.columns:
        for sid, img in zip(ids, mani["image"].astype(str)):
            parts = _parts(img.strip())
            if parts:
                images.setdefault(parts[-1], []).append((parts, sid))
    # the same tables with letter case folded, for values that match nothing as written; an id that
    # differs from another only by case is left out (it would name either)
    folded = {}
    for sid in ids:
        folded.setdefault(sid.casefold(), []).append(sid)
    folded_ids = {k: v[0] for k, v in folded.items() if len(v) == 1}
    folded_images = {}
    for name, entries in images.items():
        folded_images.setdefault(name.casefold(), []).extend(([q.casefold() for q in parts], sid)
                                                             for parts, sid in entries)
    vals = pd.Series(values, dtype=object).fillna("").astype(str).str.strip()
    table = {}
    for v in pd.unique(vals):  # few distinct values: a dictionary lookup per click
        table[v] = _match_one(v, known, images)
        if table[v][1] == "":
            sid, how = _match_one(v.casefold(), folded_ids, folded_images)
            if how:
                table[v] = (folded_ids.get(sid, sid) if how != "image" else sid), "case"
    out = vals.map(lambda v: table[v][0]).to_numpy(dtype=object)
    how = vals.map(lambda v: table[v][1]).to_numpy(dtype=object)
    return out, how


def _match_one(value, known, images):
    if value in known:
        return value, "id"
    parts = _parts(value)
    if not parts:
        return value, ""
    best, best_len, tie = None, 0, False
    for ip, sid in images.get(parts[-1], ()):
        k = 0  # trailing components in common
        while k < min(len(ip), len(parts)) and ip[-1 - k] == parts[-1 - k]:
            k += 1
        if k > best_len:
            best, best_len, tie = sid, k, False
        elif k == best_len and sid != best:
            tie = True
    if best is not None and not tie:
        return best, "image"
    if best is None:
        stem = parts[-1].rsplit(".", 1)[0] if "." in parts[-1] else None
        if stem in known:
            return stem, "file_stem"
    return value, ""


def resolve_stimulus_ids(clicks, stimset):
    """Clicks with ``stimulus_id`` replaced by the id its value names (:func:`match_stimulus_ids`).

    When any value changes, the values as written are kept in a column
    ``stimulus_as_written`` placed after ``stimulus_id``.

    Returns
    -------
    pandas.DataFrame
        A copy of `clicks` (or `clicks` itself when every value is an id or
        matches nothing).
    """
    ids, how = match_stimulus_ids(clicks["stimulus_id"].to_numpy(dtype=object), stimset)
    changed = (how == "image") | (how == "file_stem") | (how == "case")
    if not changed.any():
        return clicks
    out = clicks.copy()
    if "stimulus_as_written" in out.columns:
        out = out.rename(columns={"stimulus_as_written": "input_stimulus_as_written"})
    out.insert(out.columns.get_loc("stimulus_id") + 1, "stimulus_as_written", clicks["stimulus_id"].to_numpy())
    out["stimulus_id"] = ids
    return out


def exclusion_report(table, threshold=WARN_FRACTION, examples=3):
    """A sentence about excluded clicks when more than `threshold` of them were excluded.

    Parameters
    ----------
    table : pandas.DataFrame
        The mapped clicks (columns ``reason``, ``excluded``, ``line`` and
        ``stimulus_id``, as in ``clicks.csv``).
    threshold : float
        Share of excluded rows above which to report.
    examples : int
        Values quoted for the commonest reasons (cut short).

    Returns
    -------
    str or None
        E.g. ``'92% of the clicks (920 of 1000) were excluded: outside_image
        900, far_from_contour 20 (check --coords, ...)'``; None when the share
        is at most `threshold`.

    Examples
    --------
    >>> import pandas as pd
    >>> t = pd.DataFrame(dict(reason=["outside_image"] * 3 + [""], excluded=[True] * 3 + [False],
    ...                       line=[2, 3, 4, 5], stimulus_id=["a"] * 4))
    >>> exclusion_report(t)
    '75% of the clicks (3 of 4) were excluded: outside_image 3 (check --coords, --scale and --window-size)'
    """
    from attneave.analysis.clicks.mapping import NOT_CLICKS

    # a repeated header or a row of separators only is no click: the share is of the clicks
    not_click = table["reason"].isin(NOT_CLICKS)
    if len(table) and not_click.all():
        counts = table["reason"].value_counts()
        return "no row is a click: " + ", ".join(f"{r} {int(c)}" for r, c in counts.items())
    table = table[~not_click]
    n = len(table)
    excluded = table["excluded"].to_numpy(dtype=bool)
    k = int(excluded.sum())
    if n == 0 or k <= threshold * n:
        return None
    counts = table.loc[excluded, "reason"].value_counts()
    parts = []
    for reason, count in counts.head(3).items():
        detail = [_HINTS[reason]] if reason in _HINTS else []
        if reason == "unknown_stimulus":
            vals = table.loc[table["reason"] == reason, "stimulus_id"].astype(str).unique()[:examples]
            detail.append("e.g. " + ", ".join(shorten(v) for v in vals))
        elif reason == "malformed_row":
            rows = table.loc[table["reason"] == reason].head(examples)
            if SOURCE in rows.columns:  # several files: each line with its file's name
                where = [f"{Path(f).name}:{int(v)}" for f, v in zip(rows[SOURCE], rows["line"])]
            else:
                where = [str(int(v)) for v in rows["line"]]
            detail.append("line(s) " + ", ".join(where))
        parts.append(f"{reason} {int(count)}" + (f" ({'; '.join(detail)})" if detail else ""))
    more = len(counts) - 3
    return (f"{100 * k / n:.0f}% of the clicks ({k} of {n}) were excluded: " + ", ".join(parts)
            + (f", and {more} other reason(s)" if more > 0 else ""))
