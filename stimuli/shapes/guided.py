"""Information-guided stimuli: where does a contour's information lie?

Surprisal (:func:`attneave.stimuli.geometry.information.surprisal`) is computed at `n` equally
spaced points of the contour, and three kinds of stimuli are built from it:

* :func:`attneave_cat` -- Attneave's (1954) cat: the `k` most informative
  points joined by straight lines, in contour order, chosen so that the
  polygon never crosses itself.
* :func:`fragments` -- a given fraction of the contour's length kept as
  `m` equal fragments centred on prominent surprisal peaks, and the same
  length in the same number of fragments centred on surprisal troughs
  (minima). The two sets have exactly the same total visible length and
  fragment count by construction; each set's fragments are at least
  `min_gap` pixels apart along the contour, so they cannot merge. A shape
  whose peaks do not stand out from its troughs by `min_contrast` of the
  surprisal's range is refused.
* :func:`dots` -- dots at the `k` most (or least) informative points.

Choosing the points. Peak fragments are centred on local maxima of
surprisal whose prominence (height above the higher of the two lowest
points that separate them from a higher maximum, as in
:func:`scipy.signal.find_peaks`) is at least `min_contrast` of the range,
most prominent first; nothing else is a peak. For troughs, the cat and the
dots, candidates are the local extrema of surprisal, ranked by value, then
every other sample point ranked by value (so that a contour with too few
extrema can still yield `m` places); ties, as on the straight sides of a
polygon where surprisal is constant, are broken by the mean surprisal over
the fragment's span and then by position. Surprisal is quantised to 1e-9 of
its range before ranking so that round-off on straight sides does not
decide. A candidate is taken when it is at least the required arc distance
from every point already taken (greedy non-maximum suppression), until `m`
(or `k`) are taken.

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

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.geometry.information import surprisal
from attneave.stimuli.shapes._limits import MAX_POINTS
from attneave.stimuli.shapes.selection import rank_by_prominence, rank_candidates, select_separated
from attneave.stimuli.validate import as_int, as_number

__all__ = [
    "information",
    "rank_candidates",
    "rank_by_prominence",
    "select_separated",
    "arc_polyline",
    "attneave_cat",
    "fragments",
    "dots",
]


def _closed(contour):
    """A closed `Contour` from a Contour or an (N, 2) array of ``(x, y)`` points
    (image pixels, y down; an array is taken as closed and oriented
    counter-clockwise on the screen)."""
    if not isinstance(contour, Contour):
        try:
            contour = Contour(contour, True)
        except InputError as exc:
            raise InputError(f"contour: {exc}") from None
    if not contour.closed:
        raise InputError("contour: information-guided stimuli need a closed contour")
    return contour


def information(contour, n=256, model="paper", A=0.25, b=None, prominence=None):
    """Surprisal of `contour` at `n` equally spaced points.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed, points ``(x, y)`` in image pixels (y down); an array is taken
        as a closed contour.
    n : int
        Number of samples, in [3, 1e6].
    model, A, b, prominence
        Passed to :func:`attneave.stimuli.geometry.information.surprisal`.

    Returns
    -------
    SurprisalResult
        As :func:`attneave.stimuli.geometry.information.surprisal` returns it.

    Raises
    ------
    InputError
        An open contour, bad points or a bad parameter, naming it.
    """
    contour = _closed(contour)
    n = as_int(n, "n", lo=3, hi=MAX_POINTS)
    return surprisal(contour, n=n, model=model, A=A, b=b, prominence=prominence)


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


def _points_at_samples(contour, res, idx):
    """Sample points (on the contour) for sample indices, with their t."""
    t = res.t[idx]
    return contour.point_at(t), t


def attneave_cat(contour, k=None, n=256, model="paper", A=0.25, b=None, min_separation=None, prominence=None):
    """Attneave's cat: the most informative points joined by straight lines.

    The polygon never crosses itself. Where it would (as on a deep, narrow
    notch whose walls are closer than `min_separation`, or whose bottom
    bends), the worst-ranked end of a crossing edge is dropped until none is
    left, then the places freed are refilled with the next-ranked points that
    keep the polygon simple.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed (image pixels, y down); an array is taken as a closed contour.
    k : int, optional
        Number of points (an integer >= 3). Local maxima of surprisal (curvature
        extrema, the points Attneave's cat joins) come first, best first,
        then the other points. Default: every local maximum whose
        prominence is at least `prominence` (default 0.1% of the range of
        surprisal) and that keeps the polygon simple, and at least 3.
    n : int
        Surprisal sampling (points along the contour).
    model, A, b, prominence
        Passed to :func:`attneave.stimuli.geometry.information.surprisal`.
    min_separation : float, optional
        Minimum arc distance between chosen points, px (>= 0; default two
        sample spacings, so that one corner falling between two samples
        gives one point).

    Returns
    -------
    points : (k, 2) array
        The chosen points in contour order (image pixels); the polygon
        through them, a simple polygon, is the stimulus.
    params : dict
        ``k, n, model, A, b, ds, min_separation, indices, t, surprisal,
        height`` (``(u - min u) / range``), ``n_extrema``, ``passed_over`` (sample indices left out because the
        polygon would cross itself), ``simple`` (always true) and the
        surprisal parameters.

    Raises
    ------
    InputError
        A bad parameter, naming it, or fewer than `k` points can be placed.
    """
    import shapely

    contour = _closed(contour)
    k, min_separation = _check_k(k, 3, min_separation)
    res = information(contour, n=n, model=model, A=A, b=b, prominence=prominence)
    at, _ = _points_at_samples(contour, res, np.arange(res.params["n"]))

    def simple(indices):
        ring = at[np.sort(indices)]
        return len(ring) < 3 or bool(shapely.is_simple(shapely.LineString(np.vstack([ring, ring[:1]]))))

    k_asked = k
    k, sep, chosen, n_ext, order = _choose(contour, k, "peaks", 3, min_separation, prominence, res)
    rank = np.empty(len(order), int)
    rank[order] = np.arange(len(order))
    kept, dropped = _untangle(chosen, rank, at)
    # refill the places freed: with every extremum that fits when k was not given (then other
    # points up to 3), with any point, best first, up to k when it was
    L = contour.perimeter
    if k_asked is None:
        chosen = select_separated(order[:n_ext], res.s, L, k, sep, accept=simple, chosen=kept)
        if len(chosen) < 3:
            chosen = select_separated(order, res.s, L, 3, sep, accept=simple, chosen=chosen)
    else:
        chosen = select_separated(order, res.s, L, k, sep, accept=simple, chosen=kept)
    need = 3 if k_asked is None else k
    if len(chosen) < need:
        raise InputError(f"k: only {len(chosen)} points {sep:g} px apart keep the polygon simple on this contour, "
                         f"asked for {need}")
    idx = np.sort(np.asarray(chosen))
    pts, t = _points_at_samples(contour, res, idx)
    if not simple(list(idx)):  # the choice above makes this impossible
        raise InputError("attneave_cat: the polygon crosses itself")
    params = dict(
        k=len(idx),
        min_separation=sep,
        indices=[int(i) for i in idx],
        rank=[int(chosen.index(int(i))) for i in idx],
        t=[float(x) for x in t],
        surprisal=[float(res.surprisal[i]) for i in idx],
        height=_heights(res.surprisal, idx),
        n_extrema=n_ext,
        passed_over=sorted(int(i) for i in set(dropped) - set(chosen)),
        simple=True,
        **_surprisal_params(res),
    )
    return pts, params


def _untangle(chosen, rank, at):
    """Drop the worst-ranked end of a crossing edge until the polygon is simple.

    `chosen` are sample indices, `rank` the rank of every sample (0 best),
    `at` the sample points. Returns the kept and the dropped indices.
    """
    import shapely

    kept, dropped = [int(i) for i in chosen], []
    while len(kept) > 3:
        idx = np.sort(kept)
        ring = Contour(at[idx], orient=False)
        hits = ring.self_intersections()
        if len(hits) == 0:
            break
        q = np.vstack([ring.points, ring.points[:1]])
        edges = shapely.linestrings(np.stack([q[:-1], q[1:]], axis=1))
        near = shapely.distance(edges[:, None], shapely.points(hits)[None, :]).min(axis=1) < 1e-6
        ends = {int(idx[j]) for j in np.nonzero(near)[0]} | {int(idx[(j + 1) % len(idx)]) for j in np.nonzero(near)[0]}
        worst = max(ends, key=lambda i: rank[i])
        kept.remove(worst)
        dropped.append(worst)
    return kept, dropped


def _check_k(k, k_min, min_separation):
    """Validated `k` (None or an integer >= k_min) and `min_separation` (None or a number >= 0)."""
    if k is not None:
        k = as_int(k, "k", lo=k_min, hi=MAX_POINTS)
    if min_separation is not None:
        min_separation = as_number(min_separation, "min_separation", ge=0)
    return k, min_separation


def _extremum_prominence(res, prominence):
    # u grows with the square of the turn, so a 5%-of-range threshold keeps only the
    # sharpest corners; Attneave's points are every curvature extremum, ranked. Never below
    # resampling noise: a circle has no extrema (its ripple of 1e-10 gave 64)
    from attneave.stimuli.geometry.information import noise_prominence

    own = 1e-3 * float(np.ptp(res.surprisal)) if prominence is None else prominence
    return max(own, noise_prominence(res.params))


def _choose(contour, k, which, k_min, min_separation, prominence, res):
    """The `k` best-ranked samples at least `min_separation` apart (k=None: every extremum).

    Returns ``k, separation, chosen, n_extrema, order`` (the ranking).
    """
    L = contour.perimeter
    sep = 2 * res.params["ds"] if min_separation is None else float(min_separation)
    order, n_ext = rank_candidates(res.surprisal, which, span=1, prominence=_extremum_prominence(res, prominence))
    if k is None:
        # every extremum that keeps its distance from the better ones, and no fewer than k_min
        k = max(k_min, len(select_separated(order[:n_ext], res.s, L, n_ext, sep)))
    k = int(k)
    chosen = select_separated(order, res.s, L, k, sep)
    if len(chosen) < k:
        raise InputError(f"k: only {len(chosen)} points are {sep:g} px apart on this contour, asked for {k}")
    return k, sep, chosen, n_ext, order


def _heights(u, idx):
    """``(u - min u) / range`` at `idx`: where between the least and most informative point (0 on a circle)."""
    lo, span = float(np.min(u)), float(np.ptp(u))
    return [float((u[i] - lo) / span) if span > 0 else 0.0 for i in idx]


def _surprisal_params(res):
    p = res.params
    return dict(n=p["n"], model=p["model"], A=p["A"], b=p["b"], ds=p["ds"], units=p["units"], prominence=p["prominence"],
                length_unit=p["length_unit"])


#: Default smallest peak-trough contrast of :func:`fragments`, a fraction of the surprisal's range.
MIN_CONTRAST = 0.2


def fragments(contour, fraction=0.3, n_fragments=4, n=256, model="paper", A=0.25, b=None, min_gap=8.0,
              prominence=None, min_contrast=MIN_CONTRAST):
    """Fragments on surprisal peaks versus troughs, of equal length and number.

    Each set has `n_fragments` pieces of the contour, each of arc length
    ``fraction * L / n_fragments`` (L the perimeter). Peak pieces are
    centred on local maxima of surprisal whose prominence is at least
    `min_contrast` of the surprisal's range, the most prominent first;
    trough pieces on the best-ranked troughs (lowest surprisal). Centres of
    the same set are at least ``length + min_gap`` apart along the contour,
    so the pieces are disjoint with gaps of at least `min_gap` px between
    them. Both sets therefore show exactly ``fraction * L`` of contour in
    exactly `n_fragments` pieces.

    The peak-trough contrast is ``(min u(peak centres) - max u(trough
    centres)) / (max u - min u)``: every peak piece sits at least that
    fraction of the range above every trough piece. Below `min_contrast`
    the shape is refused: its "peaks" would not be more informative than
    its "troughs" in any useful sense.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed (image pixels, y down); an array is taken as a closed contour.
    fraction : float
        Fraction of the perimeter shown, in (0, 1).
    n_fragments : int
        Pieces per set (an integer >= 1).
    n : int
        Surprisal sampling.
    model, A, b, prominence
        Passed to :func:`attneave.stimuli.geometry.information.surprisal` (`prominence` also
        finds the troughs' local minima).
    min_gap : float
        Minimum gap in px along the contour between pieces of one set (>= 0).
    min_contrast : float
        Smallest prominence of a peak and smallest peak-trough contrast, as
        a fraction of the surprisal's range, in [0, 1) (default
        :data:`MIN_CONTRAST`, 0.2).

    Returns
    -------
    dict
        ``'peaks'`` and ``'troughs'``: lists of (M, 2) polylines (image
        pixels), in contour order; ``'params'``: ``fraction, n_fragments,
        fragment_length, visible_length, min_gap, min_contrast, contrast,
        surprisal_range, peaks_t, troughs_t`` (centres' arc positions),
        ``peaks_surprisal, troughs_surprisal``, ``peaks_height,
        troughs_height`` (``(u - min u) / range`` at the centres),
        ``peaks_prominence`` (fractions of the range), ``peaks_extrema,
        troughs_extrema`` (how many centres are true local extrema) and the
        surprisal parameters.

    Raises
    ------
    InputError
        A bad parameter, naming it; when the pieces and gaps cannot fit (``fraction * L + m * min_gap >
        L``), fewer than `n_fragments` prominent peaks or troughs can be
        placed, or the contrast is below `min_contrast`.
    """
    contour = _closed(contour)
    fraction = as_number(fraction, "fraction", gt=0, lt=1)
    m = as_int(n_fragments, "n_fragments", lo=1, hi=MAX_POINTS)
    min_gap = as_number(min_gap, "min_gap", ge=0)
    min_contrast = as_number(min_contrast, "min_contrast", ge=0, lt=1)
    L = contour.perimeter
    ell = fraction * L / m
    if fraction * L + m * min_gap > L:
        raise InputError(
            f"fraction: {m} fragments of {ell:.3g} px with gaps of {min_gap:g} px do not fit on a "
            f"{L:.4g} px contour; lower fraction, n_fragments or min_gap"
        )
    res = information(contour, n=n, model=model, A=A, b=b, prominence=prominence)
    u = res.surprisal
    lo, span = float(np.min(u)), float(np.ptp(u))
    if span <= 1e-12 * max(1.0, abs(lo)):
        raise InputError("min_contrast: the surprisal is constant along this contour; it has no peaks")
    half = max(0, int(round(0.5 * ell / res.params["ds"])))
    out = {}
    params = dict(fraction=fraction, n_fragments=m, fragment_length=ell, visible_length=m * ell, min_gap=min_gap,
                  min_contrast=min_contrast, surprisal_range=span)
    peak_order, peak_prom = rank_by_prominence(u, min_contrast)
    trough_order, n_trough_ext = rank_candidates(u, "troughs", span=half, prominence=prominence)
    for which, order, n_ext, what in (("peaks", peak_order, len(peak_order),
                                       f"on peaks of prominence >= {min_contrast:g} of the surprisal range"),
                                      ("troughs", trough_order, n_trough_ext, "on troughs")):
        ext_set = set(int(i) for i in order[:n_ext])
        chosen = select_separated(order, res.s, L, m, ell + min_gap)
        if len(chosen) < m:
            raise InputError(
                f"n_fragments: only {len(chosen)} fragments of {ell:.3g} px {what} fit {min_gap:g} px apart on "
                f"this contour, asked for {m}"
            )
        idx = np.sort(np.asarray(chosen))
        centres = res.s[idx]
        out[which] = [arc_polyline(contour, c - ell / 2, c + ell / 2) for c in centres]
        params[f"{which}_t"] = [float(x) for x in res.t[idx]]
        params[f"{which}_surprisal"] = [float(u[i]) for i in idx]
        params[f"{which}_height"] = _heights(u, idx)
        params[f"{which}_indices"] = [int(i) for i in idx]
        params[f"{which}_extrema"] = int(sum(int(i) in ext_set for i in idx))
        if which == "peaks":
            prom = dict(zip(peak_order.tolist(), peak_prom.tolist()))
            params["peaks_prominence"] = [float(prom[int(i)]) for i in idx]
    contrast = min(params["peaks_height"]) - max(params["troughs_height"])
    params["contrast"] = float(contrast)
    if contrast < min_contrast:
        raise InputError(
            f"min_contrast: the peak fragments sit only {contrast:.3g} of the surprisal range above the trough "
            f"fragments, below min_contrast = {min_contrast:g}"
        )
    params.update(_surprisal_params(res))
    out["params"] = params
    return out


def dots(contour, k=None, which="peaks", n=256, model="paper", A=0.25, b=None, min_separation=None, prominence=None):
    """Dots at the `k` most (``'peaks'``) or least (``'troughs'``) informative points.

    Parameters
    ----------
    contour : Contour or (N, 2) array
        Closed (image pixels, y down); an array is taken as a closed contour.
    k : int, optional
        Number of dots (an integer >= 1). Default: every local extremum of
        the chosen kind that keeps `min_separation`.
    which : {'peaks', 'troughs'}
        Most or least informative points.
    n : int
        Surprisal sampling (points along the contour).
    model, A, b, prominence
        Passed to :func:`attneave.stimuli.geometry.information.surprisal`.
    min_separation : float, optional
        Minimum arc distance between dots, px (>= 0; default two sample
        spacings).

    Returns
    -------
    points : (k, 2) array
        In contour order (image pixels, y down).
    params : dict
        ``k, which, indices, t, surprisal, height`` (``(u - min u) /
        range`` at each dot), ``n_extrema`` and the surprisal parameters.

    Raises
    ------
    InputError
        A bad parameter, naming it, or fewer than `k` dots can be placed.
    """
    contour = _closed(contour)
    k, min_separation = _check_k(k, 1, min_separation)
    res = information(contour, n=n, model=model, A=A, b=b, prominence=prominence)
    k, sep, chosen, n_ext, _ = _choose(contour, k, which, 1, min_separation, prominence, res)
    idx = np.sort(np.asarray(chosen))
    pts, t = _points_at_samples(contour, res, idx)
    params = dict(
        k=k,
        which=which,
        min_separation=sep,
        indices=[int(i) for i in idx],
        t=[float(x) for x in t],
        surprisal=[float(res.surprisal[i]) for i in idx],
        height=_heights(res.surprisal, idx),
        n_extrema=n_ext,
        **_surprisal_params(res),
    )
    return pts, params
