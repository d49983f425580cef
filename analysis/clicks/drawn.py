"""What participants saw of each contour: fragments, dots or a polygon instead of the whole outline.

Information-guided stimuli (:mod:`attneave.stimuli.shapes.guided`, recipe
``guided`` of ``attneave generate``) show only part of their contour, while
the set's contour file holds the whole closed contour (the base shape). The
manifest says what was drawn: ``params.draw`` is ``'fragments'``, ``'dots'``
or ``'polygon'`` (Attneave's cat), and ``params.guided`` gives where, as arc
positions on that contour:

* fragments: ``which`` (``'peaks'`` or ``'troughs'``), the centres
  ``<which>_t`` and ``fragment_length`` (px of arc length), so fragment i
  is the arc from ``t_i * L - length / 2`` to ``t_i * L + length / 2``;
* dots: the dot centres ``t`` on the contour, with the style's
  ``dot_radius`` (px);
* polygon: the corners ``t``, joined by straight lines.

:func:`drawn_parts` rebuilds that geometry from the manifest and the contour,
and :func:`distance_to_drawn` measures how far a click lies from it.

Decision (how the analysis treats such stimuli)
-----------------------------------------------
A click farther than the click tolerance (the one that decides
``far_from_contour``) from everything that was drawn -- in a gap between
fragments, between dots, or away from the cat's edges -- is excluded with
the reason ``off_drawn_part`` and counted on its own in ``summary.json``
(``exclusions.off_drawn_part``) and in report.html; the figures mark it.
Clicks near a drawn part are mapped to the whole contour as any click is.

The choice set is *not* restricted to the drawn points: every model keeps
the n equally spaced points of the whole contour. Restricting it would make
the choice set differ per stimulus in every model (pooled, joint, mixed,
Monte Carlo nulls, effect size), which they do not support. The
consequence is stated in the report: on a stimulus showing only its
surprisal peaks, clicks on what was drawn are clicks on high-surprisal
points by construction, so the test against uniform clicking over the
whole contour is not evidence that people seek information there; with
such designs compare conditions (peaks against troughs of one base shape,
same visible length) rather than each against uniform clicking.

A manifest without these columns (hand-made sets, ``outline`` stimuli) means
the whole contour was drawn: nothing changes for those stimuli.

Examples
--------
>>> import numpy as np
>>> from attneave.stimuli.geometry.contour import Contour
>>> square = Contour(np.array([[0, 0], [0, 100], [100, 100], [100, 0]], float))
>>> d = DrawnParts("dots", points=square.point_at([0.0, 0.5]), radius=4.0)
>>> distance_to_drawn(d, np.array([[0.0, 0.0], [50.0, 0.0]])).round(1)
array([ 0., 46.])
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

__all__ = ["MODES", "DrawnParts", "drawn_parts", "distance_to_drawn", "describe", "drawn_summary"]

#: Ways a stimulus may have been drawn other than as its whole outline.
MODES = ("fragments", "dots", "polygon")


@dataclass
class DrawnParts:
    """What was shown of one contour.

    Attributes
    ----------
    mode : {'fragments', 'dots', 'polygon'}
    polylines : list of (M, 2) ndarray
        Fragments (open) or the polygon (closed, first point repeated), in
        image pixels.
    points : (k, 2) ndarray
        Dot centres or polygon corners.
    radius : float
        Dot radius in px (0 for lines).
    spans : list of (float, float)
        Fragments as arc positions ``(t0, t1)`` on the contour (t0 may be
        negative or t1 above 1 where a fragment crosses the first point).
    t : (k,) ndarray
        Arc positions of the dots, corners or fragment centres.
    """

    mode: str
    polylines: list = field(default_factory=list)
    points: np.ndarray = None
    radius: float = 0.0
    spans: list = field(default_factory=list)
    t: np.ndarray = None


def _json(cell):
    try:
        v = json.loads(str(cell))
    except (TypeError, ValueError):
        return {}
    return v if isinstance(v, dict) else {}


def _number(v):
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v if np.isfinite(v) else None


def _positions(values):
    if not isinstance(values, list):
        return None
    t = [_number(v) for v in values]
    return None if not t or any(v is None for v in t) else np.asarray(t, float)


def parts_of(contour, params, style):
    """The drawn geometry of one stimulus from its manifest ``params`` and ``style`` (dicts), or None.

    None means the whole contour was drawn (or the manifest does not say
    otherwise in a form this function reads).
    """
    from attneave.stimuli.shapes.guided import arc_polyline

    mode, g = params.get("draw"), params.get("guided")
    if mode not in MODES or not isinstance(g, dict):
        return None
    L = contour.perimeter
    if mode == "fragments":
        which = g.get("which")
        t, ell = _positions(g.get(f"{which}_t")), _number(g.get("fragment_length"))
        if t is None or ell is None or ell <= 0:
            return None
        spans = [(c - ell / (2 * L), c + ell / (2 * L)) for c in t]
        lines = [arc_polyline(contour, a * L, b * L) for a, b in spans]
        return DrawnParts(mode, lines, contour.point_at(t), _half_width(style), spans, t)
    t = _positions(g.get("t"))
    if t is None:
        return None
    pts = contour.point_at(t)
    if mode == "dots":
        return DrawnParts(mode, [], pts, float(_number(style.get("dot_radius")) or 0.0), t=t)
    return DrawnParts(mode, [np.vstack([pts, pts[:1]])], pts, _half_width(style), t=t)


def _half_width(style):
    return float(_number(style.get("line_width")) or 0.0) / 2


def drawn_parts(stimset):
    """What was drawn of each stimulus whose manifest says it was not the whole outline.

    Parameters
    ----------
    stimset : StimulusSet

    Returns
    -------
    dict of str -> DrawnParts
        Only stimuli drawn as fragments, dots or a polygon; the others are
        absent (their whole contour was drawn).
    """
    m = getattr(stimset, "manifest", None)
    if m is None or "params" not in getattr(m, "columns", ()):
        return {}
    styles = m["style"] if "style" in m.columns else [""] * len(m)
    out = {}
    for sid, params, style in zip(stimset.ids, m["params"], styles):
        p = _json(params)
        if p.get("draw") in MODES and sid in stimset.contours:
            d = parts_of(stimset.contours[sid], p, _json(style))
            if d is not None:
                out[sid] = d
    return out


#: Spacing (px) of the points that stand for a drawn line when distances are measured.
STEP = 0.2


def _dense(polylines, step=STEP):
    """The polylines as points at most `step` px apart, both ends of every segment included."""
    out = []
    for line in polylines:
        a, b = line[:-1], line[1:]
        k = np.maximum(1, np.ceil(np.hypot(*(b - a).T) / step)).astype(int)
        f = np.concatenate([np.arange(m) / m for m in k])
        i = np.repeat(np.arange(len(a)), k)
        out += [a[i] + f[:, None] * (b - a)[i], line[-1:]]
    return np.vstack(out)


def distance_to_drawn(parts, xy, upto=None):
    """Distance (px) from each click `xy` (M, 2) to the nearest drawn part's edge (0 on it).

    A dot counts from its rim, a line from its centre line less half its
    width. Lines are measured through points :data:`STEP` px apart along
    them (a k-d tree), so a distance is at most 0.1 px too long. With
    `upto`, distances beyond it are not searched for and come back as inf
    (fast on clicks far from everything).
    """
    from scipy.spatial import cKDTree

    xy = np.asarray(xy, float).reshape(-1, 2)
    pts = parts.points if parts.mode == "dots" else _dense([p for p in parts.polylines if len(p) >= 2])
    bound = np.inf if upto is None else float(upto) + parts.radius + STEP
    d = cKDTree(pts).query(xy, distance_upper_bound=bound)[0]
    return np.maximum(d - parts.radius, 0.0)


def describe(parts):
    """'4 fragments', '9 dots', 'a polygon of 9 corners' (for captions)."""
    k = len(parts.points) if parts.points is not None else 0
    if parts.mode == "fragments":
        return f"{len(parts.polylines)} fragment{'s' if len(parts.polylines) != 1 else ''}"
    if parts.mode == "dots":
        return f"{k} dot{'s' if k != 1 else ''}"
    return f"a polygon of {k} corners"


def drawn_summary(predictions, mapped):
    """The ``drawn_parts`` block of summary.json: which stimuli showed part of their contour, and the decision.

    Returns None when every stimulus was drawn whole. Otherwise ``n_stimuli``,
    ``by_mode`` (e.g. ``{"fragments": 2, "dots": 1}``), ``off_drawn_part``
    (clicks excluded for lying far from every drawn part) and
    ``choice_set`` (``'whole contour'``, with the reason in ``note``).
    """
    shown = {k: pr.drawn for k, pr in predictions.items() if getattr(pr, "drawn", None) is not None}
    if not shown:
        return None
    modes = {}
    for d in shown.values():
        modes[d.mode] = modes.get(d.mode, 0) + 1
    return dict(n_stimuli=len(shown), by_mode=dict(sorted(modes.items())),
                off_drawn_part=int((mapped["reason"] == "off_drawn_part").sum()), choice_set="whole contour",
                note="clicks far from every drawn part are excluded (off_drawn_part); the choice set stays the n "
                     "points of the whole contour, so on partial stimuli compare conditions (peaks against "
                     "troughs), not each against uniform clicking; see attneave.analysis.clicks.drawn")
