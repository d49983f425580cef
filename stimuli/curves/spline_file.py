"""A spline through the points of a CSV file: what ``attneave spline`` computes.

:func:`spline_of_file` reads the file once (points and their CSV lines),
refuses what cannot give a curve with messages that name the file and the CSV
line (too few points, repeated or doubling-back points, coordinates beyond the
bounds every contour has, :func:`attneave.stimuli.validate.check_scale`), fits
:func:`attneave.stimuli.curves.splines.fit_spline` in a frame where neither
curvature nor arc length overflows, and returns the sampled curve with its
notes, its problems (self-crossings, segments turning by more than pi) and a
summary.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from attneave.stimuli.curves.metrics import (
    curve_metrics,
    segment_slices,
    segment_turning,
    self_crossing_segments,
    self_intersections,
)
from attneave.stimuli.curves.splines import fit_spline
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import arg, as_int, as_number, check_flag, check_scale

__all__ = ["SplineFile", "spline_of_file"]

#: Methods that take a log-aesthetic slope `alpha`.
ALPHA_METHODS = ("lac-g1", "lac")


@dataclass
class SplineFile:
    """A spline fitted to a file's points, sampled.

    Attributes
    ----------
    table : dict of str -> ndarray
        Columns ``s, x, y, curvature, segment`` (image pixels, y down).
    notes : list of str
        What the user should know but that is no error: a dropped closing
        point, the nodes where the robust fit relaxed G2.
    problem : str or None
        The curve crosses itself or has segments turning by more than pi.
    summary : dict or None
        Method, n_points, closed, g2_error, corners, self_intersections and
        more (JSON-ready: non-finite values are None).
    """

    table: dict
    notes: list = field(default_factory=list)
    problem: str = None
    summary: dict = None


def spline_of_file(path, method="qic", closed=True, samples=32, alpha=None, max_rows=None, summary=True):
    """Fit a spline through the points of a CSV file of ``x, y`` and sample it.

    Parameters
    ----------
    path : str or Path
        CSV file with columns ``x, y`` (image pixels, y down). A closed
        curve's last point may repeat its first: it is then dropped, with a
        note.
    method : str
        A method of :func:`~attneave.stimuli.curves.splines.fit_spline`.
    closed : bool
    samples : int
        Samples per segment, both ends included (>= 2).
    alpha : float, optional
        Log-aesthetic slope of the methods ``lac-g1`` and ``lac`` (refused
        with the others).
    max_rows : int, optional
        Most rows the table may have (the command's bound on its output).
    summary : bool
        Compute the summary (its curve metrics cost a pass over the
        samples). Without it, the nodes where the robust fit relaxed G2 are
        named in a note instead.

    Returns
    -------
    SplineFile

    Raises
    ------
    InputError
        One line naming the file and the CSV line at fault, or the argument.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.csv"
    >>> _ = path.write_text("x,y\\n0,0\\n100,0\\n100,100\\n0,100\\n")
    >>> fit = spline_of_file(path, "cubic", samples=5)
    >>> len(fit.table["s"]), fit.problem, fit.notes
    (20, None, [])
    """
    from attneave.stimuli.tables import read_points

    closed = check_flag(closed, arg("closed"))
    samples = as_int(samples, arg("samples"), lo=2)
    if method == "cubic-natural" and closed:
        raise InputError(f"{arg('method')} cubic-natural: is for open curves (use --open)")
    if alpha is not None:
        if method not in ALPHA_METHODS:
            raise InputError(f"{arg('alpha')}: applies to the methods lac-g1 and lac only, not to "
                             f"{arg('method')} {method}")
        alpha = as_number(alpha, arg("alpha"))
    P, lines = read_points(path, with_lines=True)
    notes = []
    if closed and len(P) > 1 and (P[-1] == P[0]).all():
        # common in real data; the segment indices of the other points are unchanged
        notes.append(f"{path}: line {lines[-1]} repeats the first point (line {lines[0]}); dropped it (a closed "
                     "curve joins its last point to its first)")
        P, lines = P[:-1], lines[:-1]
    _check_points(P, lines, path, closed)
    n_seg = len(P) if closed else len(P) - 1
    if max_rows is not None and samples * n_seg > max_rows:
        raise InputError(f"{arg('samples')}: {samples} per segment x {n_seg} segments = {samples * n_seg} rows; "
                         f"at most {max_rows} rows")
    centre, span = _frame(P)
    kwargs = {"alpha": alpha} if alpha is not None else {}
    with warnings.catch_warnings():
        # an overflow would show as non-finite output, refused below with one line
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            sp = fit_spline((P - centre) / span, method, closed=closed, **kwargs)
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
        unit = sp.sample(samples)
        curve = _to_frame(unit, P, centre, span)
    table = curve.table()
    _check_table(table, path, method)
    crossings, crossing, looping = _problems(unit, closed)
    problem = None
    if crossing or looping:
        parts = []
        if crossing:
            parts.append(f"crosses itself ({crossings} crossings; segments {', '.join(map(str, crossing))})")
        if looping:
            parts.append(f"has segments turning by more than pi (segments {', '.join(map(str, looping))})")
        problem = f"{path}: the {method} curve " + " and ".join(parts)
    corners = list(getattr(sp, "corners", ()) or ())
    if corners and not summary:
        # the robust fit gave up curvature continuity at these nodes: the curve is right, but not G2 there
        kinds = list(getattr(sp, "corner_kinds", ()) or ())
        named = ", ".join(f"{c}" + (f" ({kinds[i]})" if i < len(kinds) else "") for i, c in enumerate(corners[:8]))
        more = f" and {len(corners) - 8} more" if len(corners) > 8 else ""
        notes.append(f"{path}: curvature is continuous except at {len(corners)} of {len(P)} points, where the "
                     f"robust fit relaxed it (G1: tangent kept; G0: a corner): point(s) {named}{more}, numbered "
                     "from 0; --summary lists them")
    info = _summary(method, samples, P, sp, unit, span, closed, crossings) if summary else None
    return SplineFile(table, notes, problem, info)


def _check_points(P, lines, path, closed):
    """One-line errors that name the file and the CSV lines of the rows at fault."""
    need = 3 if closed else 2
    if len(P) < need:
        raise InputError(
            f"{path}: a {'closed' if closed else 'open'} spline needs at least {need} points, got {len(P)}"
        )
    # the bounds of every contour (those of attneave surprisal): coordinates whose geometry
    # would overflow, or a span that is only rounding noise
    check_scale(P, f"{path}: ", labels=[f"line {k}" for k in lines])
    nxt = np.concatenate((P[1:], P[:1])) if closed else P[1:]
    same = (nxt == P[: len(nxt)]).all(axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % len(P)
        raise InputError(f"{path}: lines {lines[i]} and {lines[j]} are the same point; consecutive points must differ")
    # a polygon that turns back on itself (edges in and out antiparallel) makes every smooth
    # curve through it stop and reverse there: a cusp, where curvature is undefined (a closed
    # curve through collinear points always does this)
    inner = np.arange(len(P)) if closed else np.arange(1, len(P) - 1)
    if len(inner):
        with np.errstate(all="ignore"):  # huge coordinates: edges as unit vectors (half-differences)
            d_in = 0.5 * P - 0.5 * np.roll(P, 1, axis=0)
            d_out = 0.5 * np.roll(P, -1, axis=0) - 0.5 * P
            a, b = d_in[inner], d_out[inner]
            a = a / np.hypot(a[:, 0], a[:, 1])[:, None]
            b = b / np.hypot(b[:, 0], b[:, 1])[:, None]
            cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            dot = (a * b).sum(axis=1)
            back = (dot < 0) & (np.abs(cross) <= 1e-12)
        if back.any():
            i = int(inner[np.flatnonzero(back)[0]])
            what = " (all the points lie on one line)" if closed and _collinear(P) else ""
            raise InputError(
                f"{path}: line {lines[i]}: the points double back here (the polygon turns by 180 degrees)"
                f"{what}; a smooth curve through them has a cusp, where curvature is undefined"
            )


def _collinear(P):
    with np.errstate(all="ignore"):
        c = P - P.mean(axis=0)
        c = c / np.abs(c).max()
        sv = np.linalg.svd(c, compute_uv=False) if np.all(np.isfinite(c)) else np.ones(2)
    return bool(sv[-1] <= 1e-12 * sv[0])


def _frame(P):
    """Centre and scale of the frame the fit runs in. Points of ordinary size
    are fitted as they are (centre 0, scale 1); points spanning less than
    1e-4 px, or lying more than 1e8 spans from the origin, are moved to the
    origin and scaled by a power of two to a span of about 1, so that neither
    curvature nor arc length loses precision (the curve is the same)."""
    lo, hi = P.min(axis=0), P.max(axis=0)
    centre = 0.5 * lo + 0.5 * hi
    span = float(np.max(hi - lo))  # checked: within 2e12 px and at least 1e-6 px
    if 1e-4 <= span and float(np.max(np.abs(P))) <= 1e8 * span:
        return np.zeros(2), 1.0
    return centre, float(2.0 ** np.round(np.log2(span)))


def _to_frame(unit, P, centre, span):
    """The curve `unit` (fitted in the frame of :func:`_frame`) in image pixels.

    Every segment's samples start AND end on its input points exactly: the
    polynomial splines reach them to round-off only and the G1 log-aesthetic
    segments to ~1e-10 of the size, and a join that is off by that is a tiny
    zig-zag that crossing tests count.
    """
    sl = unit.segment
    first = np.r_[True, sl[1:] != sl[:-1]]
    last = np.r_[sl[1:] != sl[:-1], True]
    node0, node1 = sl[first], (sl[last] + 1) % len(P)
    Pu = (P - centre) / span
    unit.x[first], unit.y[first] = Pu[node0, 0], Pu[node0, 1]
    unit.x[last], unit.y[last] = Pu[node1, 0], Pu[node1, 1]
    curve = replace(unit, s=unit.s * span, x=centre[0] + unit.x * span, y=centre[1] + unit.y * span,
                    curvature=unit.curvature / span)
    # the nodes exactly as given, not to round-off of the change of frame
    curve.x[first], curve.y[first] = P[node0, 0], P[node0, 1]
    curve.x[last], curve.y[last] = P[node1, 0], P[node1, 1]
    return curve


def _check_table(table, path, method):
    """Never write blank or infinite cells: a cusp (zero speed) or an overflow is an error."""
    if np.any(np.isnan(table["curvature"])):
        k = int(np.flatnonzero(np.isnan(table["curvature"]))[0])
        raise InputError(
            f"{path}: the {method} curve stops and turns back (zero speed, a cusp) at "
            f"s={table['s'][k]:.6g} in segment {int(table['segment'][k])}, where curvature is undefined; "
            "nothing written (try --method qic)"
        )
    if not all(np.all(np.isfinite(v)) for k, v in table.items() if k != "curvature") or np.any(
        np.isinf(table["curvature"])
    ):
        raise InputError(f"{path}: the curve does not fit in float64 at this scale (non-finite values)")


def _summary(method, samples, P, sp, unit, span, closed, crossings):
    """The summary; `unit` is the curve fitted in the frame of :func:`_frame`."""
    m = curve_metrics(unit)
    with np.errstate(over="ignore"):  # an overflow is reported as null
        m["max_abs_curvature"] = float(np.float64(m["max_abs_curvature"]) / span)
        m["bending_energy"] = float(np.float64(m["bending_energy"]) / span)
        m["length"] = float(np.float64(m["length"]) * span)
    summary = {
        "method": method,
        "n_points": int(len(P)),
        "closed": closed,
        "g2_error": m["g2_error"],
        "interior_extrema": m["interior_extrema"],
        "loops": m["loops"],
        "corners": [int(c) for c in getattr(sp, "corners", ())],
        "corner_kinds": list(getattr(sp, "corner_kinds", ())),
        "self_intersections": int(crossings),
        "max_segment_turn": m["max_segment_turn"],
        "iterations": int(getattr(sp, "iterations", 0)),
        "seconds": float(sp.seconds),
        "samples_per_segment": int(samples),
        "max_abs_curvature": m["max_abs_curvature"],
        "bending_energy": m["bending_energy"],
        "length": m["length"],
        "extrema_per_segment": m["extrema_per_segment"],
    }
    if hasattr(sp, "closure_error"):
        summary["closure_error"] = float(sp.closure_error)
    if hasattr(sp, "alpha") or method in ("qic", "qic-g2"):
        # the segments' log-aesthetic slope: -1 for clothoids
        summary["alpha"] = float(getattr(sp, "alpha", -1.0))
    if hasattr(sp, "fallback_segments"):
        summary["fallback_segments"] = [int(i) for i in sp.fallback_segments]
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in summary.items()}


def _problems(curve, closed):
    """(crossing count, crossing segments, segments turning by more than pi)."""
    crossings = self_intersections(curve.x, curve.y, closed)
    crossing = self_crossing_segments(curve.x, curve.y, curve.segment, closed) if crossings else []
    turn = segment_turning(curve.s, curve.curvature, curve.segment, curve.theta)
    labels = [int(curve.segment[q.start]) for q in segment_slices(curve.segment)]
    looping = [labels[i] for i in np.flatnonzero(turn > np.pi)]
    return crossings, crossing, looping
