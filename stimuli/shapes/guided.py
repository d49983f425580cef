"""Information-guided stimuli: where does a contour's information lie?

Surprisal (:func:`stimuli.information.surprisal`) is computed at `n` equally
spaced points of the contour, and three kinds of stimuli are built from it:

* :func:`attneave_cat` -- Attneave's (1954) cat: the `k` most informative
  points joined by straight lines, in contour order.
* :func:`fragments` -- a given fraction of the contour's length kept as
  `m` equal fragments centred on surprisal peaks, and the same length in
  the same number of fragments centred on surprisal troughs (minima). The
  two sets have exactly the same total visible length and fragment count by
  construction; each set's fragments are at least `min_gap` pixels apart
  along the contour, so they cannot merge.
* :func:`dots` -- dots at the `k` most (or least) informative points.

Choosing the points. Candidates are the local maxima of surprisal (for
troughs: its local minima), ranked by value, then every other sample point
ranked by value (so that a contour with too few extrema can still yield `m`
places); ties, as on the straight sides of a polygon where surprisal is
constant, are broken by the mean surprisal over the fragment's span and then
by position. Surprisal is quantised to 1e-9 of its range before ranking so
that round-off on straight sides does not decide. A candidate is taken when
it is at least the required arc distance from every point already taken
(greedy non-maximum suppression), until `m` (or `k`) are taken.

Points are ``(x, y)`` in image pixels (y down). Fragment polylines follow the
contour itself (its own vertices, including corners, between the two ends),
so their length is exactly the arc length kept.

References
----------
.. [1] Attneave, F. (1954). Some informational aspects of visual perception.
       Psychological Review 61(3), 183-193.
.. [2] Feldman, J., & Singh, M. (2005). Information along contours and
       object boundaries. Psychological Review 112(1), 243-252.
"""

from __future__ import annotations

import math

import numpy as np

from stimuli.geometry.contour import Contour
from stimuli.errors import InputError
from stimuli.geometry.information import find_peaks, surprisal

__all__ = [
    "information",
    "rank_candidates",
    "select_separated",
    "arc_polyline",
    "attneave_cat",
    "fragments",
    "dots",
]


def information(contour, n=256, model="paper", A=0.25, b=None, prominence=None):
    """Surprisal of `contour` at `n` equally spaced points (see :func:`stimuli.information.surprisal`)."""
    if not isinstance(contour, Contour):
        contour = Contour(contour)
    if not contour.closed:
        raise InputError("contour: information-guided stimuli need a closed contour")
    return surprisal(contour, n=int(n), model=model, A=A, b=b, prominence=prominence)


def _quantise(u):
    """u rounded to 1e-9 of its range (same units), so equal-looking values are equal."""
    lo, hi = float(np.min(u)), float(np.max(u))
    if hi - lo <= 1e-12 * max(1.0, abs(hi)):
        return np.full_like(u, lo)
    step = (hi - lo) * 1e-9
    return lo + np.round((u - lo) / step) * step


def _window_mean(u, half):
    """Circular mean of u over i-half..i+half."""
    if half <= 0:
        return u.astype(float)
    k = np.ones(2 * half + 1) / (2 * half + 1)
    ext = np.concatenate([u[-half:], u, u[:half]])
    return np.convolve(ext, k, mode="valid")


def rank_candidates(u, which="peaks", span=0, prominence=None):
    """Sample indices in the order they are considered as centres.

    Parameters
    ----------
    u : (n,) array
        Surprisal at equally spaced points of a closed contour.
    which : {'peaks', 'troughs'}
        Most or least informative first.
    span : int
        Half-width in samples of the window whose mean breaks ties.
    prominence : float, optional
        Prominence for the local extrema (see :func:`find_peaks`).

    Returns
    -------
    order : (n,) int array
        The local extrema first (best first), then every other point.
    n_extrema : int
        How many of `order` are local extrema.
    """
    u = np.asarray(u, dtype=float)
    sign = 1.0 if which == "peaks" else -1.0
    if which not in ("peaks", "troughs"):
        raise InputError(f"which: expected 'peaks' or 'troughs', got {which!r}")
    q = sign * _quantise(u)
    wm = sign * _window_mean(u, int(span))
    idx = np.arange(len(u))
    # descending by quantised value, then window mean, then index
    by_value = np.lexsort((idx, -wm, -q))
    ext, _ = find_peaks(q, closed=True, prominence=None if prominence is None else float(prominence))
    is_ext = np.zeros(len(u), bool)
    is_ext[ext] = True
    order = np.concatenate([by_value[is_ext[by_value]], by_value[~is_ext[by_value]]])
    return order, int(is_ext.sum())


def select_separated(order, s, L, count, separation):
    """The first `count` of `order` at least `separation` apart (circular arc length).

    Parameters
    ----------
    order : sequence of int
        Candidate sample indices, best first.
    s : (n,) array
        Arc length of each sample.
    L : float
        Perimeter.
    count : int
    separation : float
        Minimum arc distance between chosen samples (px).

    Returns
    -------
    list of int, in the order chosen (may be shorter than `count`).
    """
    chosen = []
    pos = []
    for i in order:
        si = s[i]
        if pos:
            d = np.abs(np.asarray(pos) - si)
            d = np.minimum(d, L - d)
            if d.min() < separation - 1e-9:
                continue
        chosen.append(int(i))
        pos.append(si)
        if len(chosen) == count:
            break
    return chosen


def arc_polyline(contour, s0, s1):
    """The part of a closed contour from arc length `s0` to `s1` (s1 > s0).

    Returns
    -------
    (M, 2) array
        The point at `s0`, the contour's own vertices strictly between, and
        the point at `s1` (image pixels). Its length is ``s1 - s0`` when
        ``s1 - s0 <= perimeter``.
    """
    p = contour.points
    L = contour.perimeter
    s = contour.arclength()
    if not s1 > s0:
        raise InputError("arc_polyline: s1 must exceed s0")
    shift = math.floor(s0 / L) * L
    a, b = s0 - shift, s1 - shift
    # two laps of vertices so that a piece across the first point is one run
    ss = np.concatenate([s, s + L, [2 * L]])
    pp = np.vstack([p, p, p[:1]])
    inner = (ss > a) & (ss < b)
    ends = np.column_stack([np.interp([a, b], ss, pp[:, 0]), np.interp([a, b], ss, pp[:, 1])])
    return np.vstack([ends[:1], pp[inner], ends[1:]])


def _polyline_length(q):
    return float(np.hypot(*np.diff(q, axis=0).T).sum())


def _points_at_samples(contour, res, idx):
    """Sample points (on the contour) for sample indices, with their t."""
    t = res.t[idx]
    return contour.point_at(t), t


def attneave_cat(contour, k=None, n=256, model="paper", A=0.25, b=None, min_separation=None, prominence=None):
    """Attneave's cat: the most informative points joined by straight lines.

    Parameters
    ----------
    contour : Contour
        Closed (image pixels, y down).
    k : int, optional
        Number of points (>= 3). Local maxima of surprisal (curvature
        extrema, the points Attneave's cat joins) come first, best first,
        then the other points. Default: every local maximum whose
        prominence is at least `prominence` (default 0.1% of the range of
        surprisal), and at least 3.
    n : int
        Surprisal sampling (points along the contour).
    model, A, b, prominence
        Passed to :func:`stimuli.information.surprisal`.
    min_separation : float, optional
        Minimum arc distance between chosen points, px (default two sample
        spacings, so that one corner falling between two samples gives one
        point).

    Returns
    -------
    points : (k, 2) array
        The chosen points in contour order (image pixels); the polygon
        through them is the stimulus.
    params : dict
        ``k, n, model, A, b, ds, min_separation, indices, t, surprisal,
        n_extrema, simple`` (whether the polygon through the points is
        simple) and the surprisal parameters.
    """
    res, k, sep, chosen, n_ext = _choose(contour, k, "peaks", 3, n, model, A, b, min_separation, prominence)
    idx = np.sort(np.asarray(chosen))
    pts, t = _points_at_samples(contour, res, idx)
    import shapely

    simple = bool(shapely.is_simple(shapely.LineString(np.vstack([pts, pts[:1]]))))
    params = dict(
        k=k,
        min_separation=sep,
        indices=[int(i) for i in idx],
        rank=[int(chosen.index(int(i))) for i in idx],
        t=[float(x) for x in t],
        surprisal=[float(res.surprisal[i]) for i in idx],
        n_extrema=n_ext,
        simple=simple,
        **_surprisal_params(res),
    )
    return pts, params


def _choose(contour, k, which, k_min, n, model, A, b, min_separation, prominence):
    """The `k` best-ranked samples at least `min_separation` apart (k=None: every extremum)."""
    if k is not None and int(k) < k_min:
        raise InputError(f"k: must be >= {k_min}, got {k}")
    res = information(contour, n=n, model=model, A=A, b=b, prominence=prominence)
    L = contour.perimeter
    sep = 2 * res.params["ds"] if min_separation is None else float(min_separation)
    if prominence is None:
        # u grows with the square of the turn, so a 5%-of-range threshold keeps only the
        # sharpest corners; Attneave's points are every curvature extremum, ranked
        prominence = 1e-3 * float(np.ptp(res.surprisal))
    order, n_ext = rank_candidates(res.surprisal, which, span=1, prominence=prominence)
    if k is None:
        # every extremum that keeps its distance from the better ones, and no fewer than k_min
        k = max(k_min, len(select_separated(order[:n_ext], res.s, L, n_ext, sep)))
    k = int(k)
    chosen = select_separated(order, res.s, L, k, sep)
    if len(chosen) < k:
        raise InputError(f"k: only {len(chosen)} points are {sep:g} px apart on this contour, asked for {k}")
    return res, k, sep, chosen, n_ext


def _surprisal_params(res):
    p = res.params
    return dict(n=p["n"], model=p["model"], A=p["A"], b=p["b"], ds=p["ds"], units=p["units"], prominence=p["prominence"])


def fragments(contour, fraction=0.3, n_fragments=4, n=256, model="paper", A=0.25, b=None, min_gap=8.0,
              prominence=None):
    """Fragments on surprisal peaks versus troughs, of equal length and number.

    Each set has `n_fragments` pieces of the contour, each of arc length
    ``fraction * L / n_fragments`` (L the perimeter) and centred on a chosen
    sample: the best-ranked peaks for ``'peaks'``, the best-ranked troughs
    (lowest surprisal) for ``'troughs'``. Centres of the same set are at least
    ``length + min_gap`` apart along the contour, so the pieces are disjoint
    with gaps of at least `min_gap` px between them. Both sets therefore show
    exactly ``fraction * L`` of contour in exactly `n_fragments` pieces.

    Parameters
    ----------
    contour : Contour
        Closed (image pixels, y down).
    fraction : float
        Fraction of the perimeter shown, in (0, 1).
    n_fragments : int
        Pieces per set (>= 1).
    n : int
        Surprisal sampling.
    model, A, b, prominence
        Passed to :func:`stimuli.information.surprisal`.
    min_gap : float
        Minimum gap in px along the contour between pieces of one set (>= 0).

    Returns
    -------
    dict
        ``'peaks'`` and ``'troughs'``: lists of (M, 2) polylines (image
        pixels), in contour order; ``'params'``: ``fraction, n_fragments,
        fragment_length, visible_length, min_gap, peaks_t, troughs_t``
        (centres' arc positions), ``peaks_surprisal, troughs_surprisal``,
        ``peaks_extrema, troughs_extrema`` (how many centres are true local
        extrema) and the surprisal parameters.

    Raises
    ------
    InputError
        When the pieces and gaps cannot fit (``fraction * L + m * min_gap >
        L``) or the greedy choice cannot place `n_fragments` of them.
    """
    fraction = float(fraction)
    if not 0 < fraction < 1:
        raise InputError(f"fraction: must be in (0, 1), got {fraction}")
    m = int(n_fragments)
    if m < 1:
        raise InputError(f"n_fragments: must be >= 1, got {n_fragments}")
    min_gap = float(min_gap)
    if not min_gap >= 0:
        raise InputError(f"min_gap: must be >= 0, got {min_gap}")
    L = contour.perimeter
    ell = fraction * L / m
    if fraction * L + m * min_gap > L:
        raise InputError(
            f"fraction: {m} fragments of {ell:.3g} px with gaps of {min_gap:g} px do not fit on a "
            f"{L:.4g} px contour; lower fraction, n_fragments or min_gap"
        )
    res = information(contour, n=n, model=model, A=A, b=b, prominence=prominence)
    span = max(0, int(round(0.5 * ell / res.params["ds"])))
    out = {}
    params = dict(fraction=fraction, n_fragments=m, fragment_length=ell, visible_length=m * ell, min_gap=min_gap)
    for which in ("peaks", "troughs"):
        order, n_ext = rank_candidates(res.surprisal, which, span=span, prominence=prominence)
        ext_set = set(int(i) for i in order[:n_ext])
        chosen = select_separated(order, res.s, L, m, ell + min_gap)
        if len(chosen) < m:
            raise InputError(
                f"n_fragments: only {len(chosen)} {which} fragments of {ell:.3g} px fit {min_gap:g} px apart on "
                f"this contour, asked for {m}"
            )
        idx = np.sort(np.asarray(chosen))
        centres = res.s[idx]
        out[which] = [arc_polyline(contour, c - ell / 2, c + ell / 2) for c in centres]
        params[f"{which}_t"] = [float(x) for x in res.t[idx]]
        params[f"{which}_surprisal"] = [float(res.surprisal[i]) for i in idx]
        params[f"{which}_indices"] = [int(i) for i in idx]
        params[f"{which}_extrema"] = int(sum(int(i) in ext_set for i in idx))
    params.update(_surprisal_params(res))
    out["params"] = params
    return out


def dots(contour, k=None, which="peaks", n=256, model="paper", A=0.25, b=None, min_separation=None, prominence=None):
    """Dots at the `k` most (``'peaks'``) or least (``'troughs'``) informative points.

    Parameters are as in :func:`attneave_cat`; `k` defaults to every local
    extremum of the chosen kind and `min_separation` to two sample spacings.

    Returns
    -------
    points : (k, 2) array
        In contour order (image pixels, y down).
    params : dict
        ``k, which, indices, t, surprisal, n_extrema`` and the surprisal
        parameters.
    """
    res, k, sep, chosen, n_ext = _choose(contour, k, which, 1, n, model, A, b, min_separation, prominence)
    idx = np.sort(np.asarray(chosen))
    pts, t = _points_at_samples(contour, res, idx)
    params = dict(
        k=k,
        which=which,
        min_separation=sep,
        indices=[int(i) for i in idx],
        t=[float(x) for x in t],
        surprisal=[float(res.surprisal[i]) for i in idx],
        n_extrema=n_ext,
        **_surprisal_params(res),
    )
    return pts, params
