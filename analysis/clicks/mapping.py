"""Mapping clicks to contours: predictions per stimulus and the nearest contour point per click.

For each stimulus the contour is resampled at ``n`` equally spaced points
from its first point (:func:`stimuli.information.surprisal`); curvature and
surprisal are known there. A click is projected onto the contour itself (the
polyline of the file, not the resampled one) to get its arc position ``t``
and its distance; its curvature, surprisal and z are those of the nearest of
the n points, ``j = round(n * t) mod n`` -- the point whose arc of length
``1/n`` contains the click, which is the unit of the choice model in
:mod:`attneave.analysis.models.choice`.

Exclusion
---------
No row is dropped. A row is excluded, with the first reason that applies,
in this order:

``repeated_header``
    The row repeats the file's header line (several files joined into one;
    see :func:`attneave.analysis.clicks.read.read_clicks`): no click.
``empty_row``
    Every field of the row is empty (a spreadsheet's row of separators
    only, ``;;;;``): no click.
``malformed_row``
    The row's field count differs from the header's (see
    :func:`attneave.analysis.clicks.read.read_clicks`; ``row_error`` says how).
``missing_coordinate``
    x or y empty or NA-like.
``non_numeric_coordinate``
    x or y text that is not a number, or infinite.
``coordinate_list``
    x or y a list of several values that could not be paired (x and y lists
    of different lengths).
``coordinate_out_of_range``
    x or y beyond +-1e12 (:data:`attneave.analysis.clicks.read.MAX_COORDINATE`).
``unknown_stimulus``
    The stimulus id is not in the stimulus set (or is empty).
``missing_participant``
    The participant is empty.
``outside_image``
    The click (in image pixels) lies outside the image,
    ``[-0.5, W - 0.5] x [-0.5, H - 0.5]``.
``far_from_contour``
    The click lies farther from the contour than the tolerance: by default
    5% of the image diagonal (36 px on a 512 x 512 image), or a fixed number
    of pixels (``tolerance``). People aim at the contour; a click that far
    away is a slip or a click on something else.
``off_drawn_part``
    The stimulus showed only part of its contour (fragments, dots or
    Attneave's cat; see :mod:`attneave.analysis.clicks.drawn`) and the click
    lies farther than the tolerance from everything that was drawn (in a gap
    between fragments, say). The choice set stays the whole contour's n
    points; that module's docstring gives the reasons.

Excluded rows that have coordinates and a known stimulus still get their
mapping (t, distance, ...), so one can see where they were.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field

import numpy as np

from attneave.analysis.argnames import arg
from attneave.analysis.clicks.read import (
    blank_rows,
    malformed_rows,
    parse_coordinates,
    repeated_header_rows,
    to_image_coords,
)
from attneave.analysis.models.choice import point_index, standardize
from attneave.analysis.models.circular import midrank_percentile
from attneave.analysis.models.predictors import RIVALS, rival_values
from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.information import MODELS, surprisal

__all__ = [
    "REASONS",
    "DEFAULT_TOLERANCE_FRACTION",
    "PREDICTORS",
    "StimulusPrediction",
    "check_clicks",
    "check_predictions",
    "predict",
    "map_clicks",
]

REASONS = (
    "repeated_header",
    "empty_row",
    "malformed_row",
    "missing_coordinate",
    "non_numeric_coordinate",
    "coordinate_list",
    "coordinate_out_of_range",
    "unknown_stimulus",
    "missing_participant",
    "outside_image",
    "far_from_contour",
    "off_drawn_part",
)
#: Reasons of rows that are no clicks (not counted in the share of excluded clicks that is reported).
NOT_CLICKS = ("repeated_header", "empty_row")
DEFAULT_TOLERANCE_FRACTION = 0.05
#: Predictors known for every stimulus: the tested surprisal and its rivals (:mod:`attneave.analysis.models.predictors`).
PREDICTORS = ("surprisal",) + RIVALS
# turning angles below this (radians) count as straight, neither concave nor convex
_FLAT = 1e-9


@dataclass
class StimulusPrediction:
    """What the information model predicts along one stimulus's contour.

    Attributes
    ----------
    stimulus_id : str
    contour : Contour
        The contour as read (image pixels, y down, counter-clockwise on screen).
    width, height : int
        Image size in pixels.
    result : SurprisalResult
        Surprisal at the n resampled points, with every resolved parameter.
    predictors : dict of str -> (n,) ndarray
        Raw values of each predictor in :data:`PREDICTORS` at the n points,
        and under ``'surprisal'`` those of the model under test.
    z : dict of str -> (n,) ndarray
        The same, standardised over the n points.
    sign : (n,) ndarray of int
        +1 convex, -1 concave, 0 straight, at each point.
    drawn : DrawnParts or None
        What was shown when it was not the whole contour
        (:func:`attneave.analysis.clicks.drawn.drawn_parts`).
    """

    stimulus_id: str
    contour: object
    width: int
    height: int
    result: object
    predictors: dict = field(default_factory=dict)
    z: dict = field(default_factory=dict)
    sign: np.ndarray = None
    drawn: object = None

    @property
    def n(self):
        return len(self.result.s)

    @property
    def perimeter(self):
        return float(self.result.params["length"])

    @property
    def peak_t(self):
        """Arc positions of the predicted surprisal peaks."""
        return np.asarray(self.result.peaks, dtype=float) / self.n


#: Stimuli per chunk of a parallel :func:`predict`: a few ms each, so a chunk is a few 100 ms of work.
PREDICT_CHUNK = 64


def predict(stimset, n=100, model="paper", A=0.25, b=None, prominence=None, length_unit=None, workers=1,
            progress=None):
    """Predictions for every stimulus of a set.

    Parameters
    ----------
    stimset : StimulusSet
    n : int
        Number of equally spaced points per contour (recorded; peak values
        and z depend on it).
    model : {'paper', 'vonmises'}
        The form of the surprisal model (both give the same standardised z).
    A, b, prominence
        Passed to :func:`attneave.stimuli.geometry.information.surprisal` for `model`.
    length_unit : str, optional
        Passed to :func:`attneave.stimuli.geometry.information.surprisal` when given
        (its default otherwise); the resolved unit is in each result's
        ``params["length_unit"]``.
    workers : int
        Local processes (forked, :func:`attneave.stimuli.dispatch.run_chunks`).
        Each stimulus is predicted on its own, so the result is the same for
        any number of workers. A stimulus takes a few ms (most of it the
        medial axis of :mod:`attneave.analysis.models.predictors`): 20,000
        take about a minute on one core.
    progress : callable, optional
        Called with the number of stimuli done after each chunk of
        :data:`PREDICT_CHUNK`.

    Returns
    -------
    dict of str -> StimulusPrediction

    Raises
    ------
    InputError
        `stimset` not a StimulusSet, `n` not a whole number >= 3, an
        unknown `model`, `A` or `b` not a finite number, `workers` not a
        whole number >= 1 (naming the
        parameter; the flag when ``attneave`` called it).

    Notes
    -----
    After standardisation the paper's form and the von Mises form give the
    same z: both are a constant minus a positive multiple of
    ``cos(a - 2*pi/n)``. So the other form is no rival and is not computed;
    the rivals that differ are those of :mod:`attneave.analysis.models.predictors`.
    """
    if not isinstance(model, str) or model not in MODELS:
        raise InputError(f"{arg('model')} must be one of {', '.join(MODELS)}, got {model!r}")
    if isinstance(n, (bool, np.bool_)) or not (isinstance(n, (int, np.integer)) and n >= 3):
        raise InputError(f"{arg('n')} must be a whole number >= 3, got {n!r}")
    if not (hasattr(stimset, "ids") and hasattr(stimset, "contours") and hasattr(stimset, "sizes")):
        raise InputError(f"stimset: expected a StimulusSet (attneave.stimuli.stimulus_set.read_stimulus_set), got "
                         f"{type(stimset).__name__}")
    A = _number("A", A)
    b = None if b is None else _number("b", b)
    # passed only when given, so that the library's default stays the default
    unit = {} if length_unit is None else {"length_unit": length_unit}
    if unit and "length_unit" not in inspect.signature(surprisal).parameters:
        raise InputError(f"{arg('length_unit')} is not supported by this version of "
                         "attneave.stimuli.geometry.information.surprisal")
    from attneave.analysis.clicks.drawn import drawn_parts

    if isinstance(workers, (bool, np.bool_)) or not (isinstance(workers, (int, np.integer)) and workers >= 1):
        raise InputError(f"{arg('workers')} must be a whole number >= 1, got {workers!r}")
    shown = drawn_parts(stimset)
    ids = list(stimset.ids)
    chunks = ([(sid, stimset.contours[sid]) for sid in ids[i:i + PREDICT_CHUNK]]
              for i in range(0, len(ids), PREDICT_CHUNK))
    options = dict(n=n, model=model, A=A, b=b, prominence=prominence, **unit)
    if workers > 1 and len(ids) > PREDICT_CHUNK:
        from attneave.stimuli.dispatch import run_chunks

        done = run_chunks(_predict_chunk, chunks, workers=int(workers), options=options)
    else:
        done = (_predict_chunk(chunk, options) for chunk in chunks)
    made = {}
    for part in done:
        made.update(part)
        if progress is not None:
            progress(len(part))
    out = {}
    for sid in ids:  # the set's order, whatever order the chunks finished in
        c, (r, raw, sign) = stimset.contours[sid], made[sid]
        w, h = stimset.sizes[sid]
        out[sid] = StimulusPrediction(
            sid, c, w, h, r, raw, {k: standardize(v) for k, v in raw.items()}, sign, shown.get(sid)
        )
    return out


def _predict_chunk(chunk, options):
    """``{sid: (surprisal result, raw predictor values, turn signs)}`` for ``[(sid, contour), ...]``."""
    out = {}
    for sid, c in chunk:
        r = surprisal(c, **options)
        raw = {"surprisal": np.asarray(r.surprisal, dtype=float), **rival_values(r, c)}
        a = np.asarray(r.turning_angle, dtype=float)
        out[sid] = (r, raw, np.where(a > _FLAT, 1, np.where(a < -_FLAT, -1, 0)))
    return out


def check_predictions(predictions):
    """The stimulus ids of a :func:`predict` output; anything else is refused (one line).

    Raises
    ------
    InputError
        `predictions` is not a dict of :class:`StimulusPrediction`.
    """
    if not isinstance(predictions, dict) or not all(isinstance(v, StimulusPrediction) for v in predictions.values()):
        raise InputError(f"predictions: expected the dict of attneave.analysis.clicks.mapping.predict(stimset, ...), got "
                         f"{type(predictions).__name__}")
    return list(predictions)


def check_clicks(clicks):
    """Refuse clicks that are no DataFrame with columns ``participant, stimulus_id, x, y`` (one line)."""
    import pandas as pd

    if not isinstance(clicks, pd.DataFrame):
        raise InputError(f"clicks: expected a pandas.DataFrame with columns participant, stimulus_id, x, y "
                         f"(e.g. from attneave.analysis.clicks.read.read_clicks), got {type(clicks).__name__}")
    missing = [c for c in ("participant", "stimulus_id", "x", "y") if c not in clicks.columns]
    if missing:
        raise InputError(f"clicks: missing column(s) {', '.join(missing)}; expected participant, stimulus_id, x, y "
                         "(rename others, e.g. with read_clicks(columns=...))")


def _number(name, value):
    """A finite number (not a bool or text), for the model's parameters; their ranges are the model's."""
    if not isinstance(value, (bool, np.bool_, str, bytes)):
        try:
            v = float(value)
        except (TypeError, ValueError):
            v = None
        if v is not None and np.isfinite(v):
            return v
    raise InputError(f"{arg(name)} must be a finite number, got {value!r}")


def _empty_rows(df, px, py):
    """Rows whose every field is empty (only x and y missing are checked first: few rows are)."""
    rows = np.flatnonzero((px == "missing_coordinate") & (py == "missing_coordinate"))
    out = np.zeros(len(df), bool)
    if len(rows):
        out[rows] = blank_rows(df, rows)
    return out


def map_clicks(clicks, predictions, coords="image", scale=1.0, tolerance=None):
    """Map every click to its stimulus's contour and flag the ones to exclude.

    Parameters
    ----------
    clicks : pandas.DataFrame
        With columns ``participant, stimulus_id, x, y`` (text or numbers),
        as from :func:`attneave.analysis.clicks.read.read_clicks`; other columns are kept.
    predictions : dict of str -> StimulusPrediction
        From :func:`predict`.
    coords : {'image', 'centered'}
        Coordinate system of x, y (see :mod:`analysis.clicks`).
    scale : float
        Shown size / image size.
    tolerance : float, optional
        Largest distance (px) from the contour for a click to be used.
        Default: 5% of the image diagonal of its stimulus.

    Raises
    ------
    InputError
        `clicks` not a DataFrame or missing one of the four columns, a bad
        `tolerance`, `coords` or `scale`.

    Returns
    -------
    pandas.DataFrame
        The input columns, with ``participant`` and ``stimulus_id`` as text
        stripped of surrounding spaces (an input column whose name the mapping uses is
        kept as ``input_<name>``) followed by: ``x_image, y_image`` (image
        pixels, y down), ``nearest_x, nearest_y``, ``distance`` (px), ``t``
        (arc position in [0, 1) from the contour's first point,
        counter-clockwise on screen), ``point`` (index of the nearest of the n
        points), ``curvature`` (1/px, positive convex), ``surprisal``, ``z``,
        ``surprisal_percentile`` (0-100, among the stimulus's n points),
        ``concave`` (1/0), ``excluded`` (bool) and ``reason`` ('' if used).
    """
    import pandas as pd

    if tolerance is not None and not _number("tolerance", tolerance) > 0:
        raise InputError(f"{arg('tolerance')} must be a positive number of pixels, got {tolerance!r}")
    check_clicks(clicks)
    check_predictions(predictions)
    new_cols = (
        "x_image", "y_image", "nearest_x", "nearest_y", "distance", "t", "point", "curvature",
        "surprisal", "z", "surprisal_percentile", "concave", "excluded", "reason",
    )
    df = clicks.copy()
    df = df.rename(columns={c: f"input_{c}" for c in new_cols if c in df.columns})
    N = len(df)
    x, px = _parse(df["x"])
    y, py = _parse(df["y"])
    reason = np.where(px != "", px, py).astype(object)
    reason[malformed_rows(df)] = "malformed_row"
    reason[_empty_rows(df, px, py)] = "empty_row"
    reason[repeated_header_rows(df)] = "repeated_header"
    sid = _ids(df["stimulus_id"])
    part = _ids(df["participant"])
    df["stimulus_id"], df["participant"] = sid, part
    known = pd.Series(sid).isin(list(predictions)).to_numpy()
    reason[(reason == "") & ~known] = "unknown_stimulus"
    reason[(reason == "") & (part == "")] = "missing_participant"

    cols = {c: np.full(N, np.nan) for c in new_cols if c not in ("excluded", "reason")}
    cols["point"] = np.full(N, -1, dtype=np.int64)
    cols["concave"] = np.zeros(N, dtype=np.int64)
    coords_ok = (px == "") & (py == "") & known
    ok_idx = np.flatnonzero(coords_ok)
    groups = pd.Series(ok_idx).groupby(sid[ok_idx]).indices if len(ok_idx) else {}

    # one thread: two were slower (1,000,000 clicks on 5,000 stimuli: 4.3 s against 3.1 s), the
    # projections being many small numpy calls that hold the GIL between them
    for s, rel in groups.items():
        rows = ok_idx[rel]
        pr = predictions[s]
        xi, yi = to_image_coords(x[rows], y[rows], pr.width, pr.height, coords, scale)
        outside = (xi < -0.5) | (xi > pr.width - 0.5) | (yi < -0.5) | (yi > pr.height - 0.5)
        nearest, t, dist = pr.contour.project(np.column_stack([xi, yi]))
        j = point_index(t, pr.n)
        tol = tolerance if tolerance is not None else DEFAULT_TOLERANCE_FRACTION * np.hypot(pr.width, pr.height)
        u = pr.predictors["surprisal"]
        cols["x_image"][rows], cols["y_image"][rows] = xi, yi
        cols["nearest_x"][rows], cols["nearest_y"][rows] = nearest[:, 0], nearest[:, 1]
        cols["distance"][rows] = dist
        cols["t"][rows] = t
        cols["point"][rows] = j
        cols["curvature"][rows] = pr.result.curvature[j]
        cols["surprisal"][rows] = u[j]
        cols["z"][rows] = pr.z["surprisal"][j]
        # ranked by z, not by the raw surprisal: z is exactly 0 where the prediction is constant
        # (a circle), whose raw values differ only by rounding and would be ranked as if they
        # differed; elsewhere z is an increasing function of u, so the ranks are the same
        zs = pr.z["surprisal"]
        cols["surprisal_percentile"][rows] = midrank_percentile(zs[j], zs)
        cols["concave"][rows] = (pr.sign[j] < 0).astype(np.int64)
        r = reason[rows]
        r[(r == "") & outside] = "outside_image"
        r[(r == "") & (dist > tol)] = "far_from_contour"
        if pr.drawn is not None:
            from attneave.analysis.clicks.drawn import distance_to_drawn

            r[(r == "") & (distance_to_drawn(pr.drawn, np.column_stack([xi, yi]), upto=tol) > tol)] = "off_drawn_part"
        reason[rows] = r
    for k, v in cols.items():
        df[k] = v
    df["excluded"] = reason != ""
    df["reason"] = reason.astype(str)
    return df


def _ids(col):
    """Identifiers as stripped text ('' for missing)."""
    v = col.astype(object).where(col.notna(), "").astype(str).to_numpy(dtype=str)
    strip = getattr(getattr(np, "strings", None), "strip", np.char.strip)  # a ufunc in numpy >= 2
    return strip(v).astype(object)


def _parse(col):
    """Coordinates from a text or numeric column -> (values, problem)."""
    import pandas as pd

    if pd.api.types.is_numeric_dtype(col):
        v = col.to_numpy(dtype=float).copy()
        problem = np.full(len(v), "", dtype=object)
        problem[np.isnan(v)] = "missing_coordinate"
        problem[np.isinf(v)] = "non_numeric_coordinate"
        v[~np.isfinite(v)] = np.nan
        return v, problem
    return parse_coordinates(col.to_numpy())
