"""Ranking and choosing places on a contour by their surprisal.

The building blocks of :mod:`attneave.stimuli.shapes.guided`: rank the equally spaced
samples of a closed contour as candidate centres (by value, with ties broken
by a window mean, or by prominence), then take the best ones that keep a
given arc distance from each other (greedy non-maximum suppression),
optionally under a further condition on the chosen set.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.information import find_peaks

__all__ = ["rank_candidates", "rank_by_prominence", "select_separated", "quantise"]


def quantise(u):
    """`u` rounded to steps of 1e-9 of its range, so that values equal up to round-off are equal.

    Parameters
    ----------
    u : (n,) array

    Returns
    -------
    (n,) array
        In the units of `u`; a constant `u` (range below 1e-12 of its
        values) becomes exactly constant.

    Examples
    --------
    >>> q = quantise(np.array([0.0, 1.0, 1.0 + 1e-13]))
    >>> bool(q[1] == q[2])
    True
    """
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
    q = sign * quantise(u)
    wm = sign * _window_mean(u, int(span))
    idx = np.arange(len(u))
    # descending by quantised value, then window mean, then index
    by_value = np.lexsort((idx, -wm, -q))
    ext, _ = find_peaks(q, closed=True, prominence=None if prominence is None else float(prominence))
    is_ext = np.zeros(len(u), bool)
    is_ext[ext] = True
    order = np.concatenate([by_value[is_ext[by_value]], by_value[~is_ext[by_value]]])
    return order, int(is_ext.sum())


def rank_by_prominence(u, min_prominence=0.0):
    """Local maxima of a closed contour's surprisal, most prominent first.

    Parameters
    ----------
    u : (n,) array
        Surprisal at equally spaced points of a closed contour.
    min_prominence : float
        Smallest prominence kept, as a fraction of the range of `u` (in
        [0, 1)).

    Returns
    -------
    order : (K,) int array
        Indices of the maxima, by prominence, then value, then index.
    prominence : (K,) array
        Their prominences as fractions of the range of `u` (the global
        maximum's is 1 on a closed contour).

    Examples
    --------
    The maximum 0.45 at index 5 rises only 0.05 above the dip that parts it
    from the higher 0.5, so it is not kept at 10% of the range:

    >>> u = np.array([0.0, 1.0, 0.0, 0.5, 0.4, 0.45, 0.0, 0.2])
    >>> order, prom = rank_by_prominence(u, 0.1)
    >>> order.tolist(), prom.round(2).tolist()
    ([1, 3, 7], [1.0, 0.5, 0.2])
    """
    u = np.asarray(u, dtype=float)
    q = quantise(u)
    span = float(np.ptp(q))
    if span == 0:
        return np.empty(0, int), np.empty(0)
    idx, prom = find_peaks(q, closed=True, prominence=float(min_prominence) * span)
    order = np.lexsort((idx, -q[idx], -prom))
    return idx[order], prom[order] / span


def select_separated(order, s, L, count, separation, accept=None, chosen=()):
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
    accept : callable, optional
        ``accept(indices) -> bool``, a further condition on the chosen set
        with the candidate added (e.g. that the cat's polygon is simple). A
        candidate it refuses is skipped for the next one and tried again,
        best first, after every later choice, since a larger set may admit
        it.
    chosen : sequence of int
        Indices already chosen; the result starts with them.

    Returns
    -------
    list of int, in the order chosen (may be shorter than `count`).
    """
    s = np.asarray(s, dtype=float)
    pending = np.asarray(order, dtype=int)
    chosen = [int(i) for i in chosen]
    for i in chosen:
        d = np.abs(s[pending] - s[i])
        pending = pending[(np.minimum(d, L - d) >= separation - 1e-9) & (pending != i)]
    while len(chosen) < count and len(pending):
        if accept is None:
            j = 0
        else:
            j = next((j for j, i in enumerate(pending) if accept(chosen + [int(i)])), None)
            if j is None:
                break
        i = int(pending[j])
        chosen.append(i)
        # candidates too close to the new point can never be taken: drop them now
        d = np.abs(s[pending] - s[i])
        keep = np.minimum(d, L - d) >= separation - 1e-9
        keep[j] = False
        pending = pending[keep]
    return chosen
