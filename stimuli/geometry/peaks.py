"""Peaks of a sampled function and their topographic prominence, in numpy.

The definitions are those of :func:`scipy.signal.find_peaks` and
:func:`scipy.signal.peak_prominences`: a peak is a sample (or the middle of a
plateau) higher than both neighbours; its prominence is its height above the
higher of the two lowest points reached when walking left and right from it
until the signal rises above the peak (or the ends are reached). Importing
:mod:`scipy.signal` costs about a second, more than any command that only
needs peaks spends on its work, so they are computed here from the sequence
of alternating maxima and minima: between two extrema the signal is
monotone, so only the extrema matter, and the walk to the nearest higher
maximum is a query on a sparse table of maxima (binary lifting), the lowest
point on the way a range-minimum query on a sparse table of minima.

References
----------
.. [1] SciPy, ``scipy.signal.peak_prominences``, definition of prominence.
.. [2] M. A. Bender and M. Farach-Colton, "The LCA problem revisited",
       LATIN 2000 (sparse tables for range queries).
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_number, check_flag, check_values

__all__ = ["find_peaks", "peaks_and_prominences", "circular_peaks_and_prominences", "ROUNDOFF"]

#: Relative round-off (about 4500 eps): values whose range is at most this fraction of
#: their magnitude are resolved to a few thousand units in the last place, so their
#: "peaks" would be rounding; they are flat, and no peak is less prominent than that.
#: (The 'perimeter' length unit at n of several hundred reaches it: see LENGTH_UNITS.)
ROUNDOFF = 1e-12


def _runs(x):
    """Start index and value of every run of equal values in `x`."""
    starts = np.flatnonzero(np.concatenate(([True], x[1:] != x[:-1])))
    return starts, x[starts]


def _sparse_table(a, op):
    """Levels ``t[l][i] = op(a[i : i + 2**l])`` for every l with 2**l <= len(a)."""
    table = [a]
    step = 1
    while 2 * step <= len(a):
        prev = table[-1]
        table.append(op(prev[:-step], prev[step:]))
        step *= 2
    return table


def _range_min(table, lo, hi):
    """min(a[lo:hi]) for arrays of half-open ranges with lo < hi."""
    length = hi - lo
    level = np.floor(np.log2(length)).astype(int)
    out = np.empty(len(lo))
    for lev in np.unique(level):
        m = level == lev
        t = table[lev]
        out[m] = np.minimum(t[lo[m]], t[hi[m] - (1 << lev)])
    return out


def _nearest_higher(table, heights, start, direction):
    """Index of the nearest entry of the table's array higher than `heights`.

    Walks from `start` (exclusive) to the left (``direction=-1``) or right
    (``+1``) by binary lifting over the table of maxima; returns -1 (left)
    or ``len`` (right) where no higher entry exists.
    """
    n = len(table[0])
    pos = start.copy()
    for lev in range(len(table) - 1, -1, -1):
        step = 1 << lev
        t = table[lev]
        if direction < 0:
            ok = pos - step >= 0
            idx = np.where(ok, pos - step, 0)
            move = ok & (t[idx] <= heights)
            pos = np.where(move, pos - step, pos)
        else:
            ok = pos + 1 + step <= n
            idx = np.where(ok, pos + 1, 0)
            move = ok & (t[idx] <= heights)
            pos = np.where(move, pos + step, pos)
    return pos - 1 if direction < 0 else pos + 1


def _extrema(x):
    """Plateau-aware maxima (as scipy) and the minima between them.

    Returns the index of every maximum (middle of its plateau, rounded
    down), its height, and ``lows``: ``lows[i]`` is the lowest value between
    maximum i - 1 and maximum i (``lows[0]`` before the first maximum,
    ``lows[-1]`` after the last; +inf where that stretch is empty).
    """
    starts, vals = _runs(x)
    ends = np.append(starts[1:], len(x)) - 1
    k = np.arange(1, len(vals) - 1)
    is_max = (vals[k] > vals[k - 1]) & (vals[k] > vals[k + 1])
    kmax = k[is_max]
    idx = (starts[kmax] + ends[kmax]) // 2
    # lowest run value in each stretch between consecutive maxima
    cut = np.concatenate(([0], kmax, [len(vals)]))
    seg_vals = np.concatenate((vals, [np.inf]))
    # reduceat over [cut[i], cut[i+1]) excludes no maximum's own run from the
    # stretch after it, which is harmless: a maximum is above its neighbours
    lows = np.minimum.reduceat(seg_vals, np.minimum(cut, len(vals)))[: len(cut) - 1]
    return idx, vals[kmax], lows


def peaks_and_prominences(x):
    """Peaks of a 1-D signal and their prominences (scipy's definitions).

    Parameters
    ----------
    x : (N,) array_like of float
        Finite values. The first and last samples are never peaks.

    Returns
    -------
    peaks : (K,) ndarray of int
        Indices of the peaks in increasing order (a plateau's middle sample,
        rounded down).
    prominences : (K,) ndarray
        Their prominences.

    Examples
    --------
    >>> p, prom = peaks_and_prominences([0.0, 2.0, 1.0, 3.0, 0.0])
    >>> p.tolist(), prom.tolist()
    ([1, 3], [1.0, 3.0])
    """
    x = np.asarray(x, dtype=float)
    idx, h, lows = _extrema(x)
    if len(idx) == 0:
        return idx, np.empty(0)
    q = np.arange(len(h))
    hmax = _sparse_table(h, np.maximum)
    tmin = _sparse_table(lows, np.minimum)
    left = _nearest_higher(hmax, h, q, -1)  # -1: none, walk to the start
    right = _nearest_higher(hmax, h, q, +1)  # len(h): none, walk to the end
    # minima crossed on the way: lows[left+1 .. q] and lows[q+1 .. right]
    left_min = _range_min(tmin, left + 1, q + 1)
    right_min = _range_min(tmin, q + 1, right + 1)
    return idx, h - np.maximum(left_min, right_min)


def circular_peaks_and_prominences(x):
    """Peaks and prominences of a periodic signal.

    The same as :func:`peaks_and_prominences` applied to three copies of `x`
    end to end, keeping the peaks of the middle copy (so that a peak can sit
    at index 0 and walks wrap around); a highest peak's prominence is its
    height above the global minimum.

    Parameters
    ----------
    x : (N,) array_like of float
        Finite values, one period.

    Returns
    -------
    peaks : (K,) ndarray of int
        Indices in [0, N), increasing.
    prominences : (K,) ndarray

    Examples
    --------
    >>> p, prom = circular_peaks_and_prominences([3.0, 0.0, 1.0, 0.5, 0.0])
    >>> p.tolist(), prom.tolist()
    ([0, 2], [3.0, 1.0])
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    top = x.max()
    is_top = x == top
    if is_top.all():
        return np.empty(0, int), np.empty(0)
    # start one period at the first sample of a highest plateau, end it with
    # that sample again: every other peak then has a higher point on both sides
    g = int(np.flatnonzero(is_top & ~np.roll(is_top, 1))[0])
    y = np.concatenate((x[g:], x[:g], x[g : g + 1]))
    # a plateau of the highest value at the start: pad so that it is a peak
    below = x.min() - 1.0
    idx, prom = peaks_and_prominences(np.concatenate(([below], y[:-1], [below])))
    idx = idx - 1
    highest = y[idx] == top
    prom[highest] = top - x.min()
    # the rest: walks bounded by the highest value at both ends of y
    rest, rprom = peaks_and_prominences(y)
    keep = y[rest] < top
    peaks = np.concatenate((idx[highest], rest[keep]))
    proms = np.concatenate((prom[highest], rprom[keep]))
    peaks = (peaks + g) % n
    order = np.argsort(peaks, kind="stable")
    return peaks[order], proms[order]


def find_peaks(u, closed=True, prominence=None, floor=0.0):
    """Local maxima of surprisal, ranked from the highest.

    Parameters
    ----------
    u : (N,) array_like
        Values along the contour (NaN allowed at the ends of an open curve).
    closed : bool
        Treat `u` as circular, so a peak can sit at the first point.
    prominence : float, optional
        Minimum prominence (as :func:`scipy.signal.find_peaks` defines it;
        computed by :mod:`attneave.stimuli.geometry.peaks`); default 5%
        of the range of `u`. A constant `u` (a circle) has no peaks.
    floor : float, optional
        Noise floor: a peak's prominence must exceed it, whatever
        `prominence` says, and a `u` whose range is at most `floor` is flat
        (no peaks). Default 0; :func:`surprisal` passes
        :func:`noise_prominence`, the surprisal of resampling noise. The
        floor is never below :data:`ROUNDOFF` (1e-12) times the largest
        ``|u|``: differences at round-off are no peaks.

    Returns
    -------
    peaks : (K,) ndarray of int
        Indices of the peaks, highest value first.
    prominences : (K,) ndarray
        Their prominences, in the same order.

    Raises
    ------
    InputError
        `u` not a 1-D array of finite numbers (NaN allowed only at the two
        ends of an open curve), a `prominence` or `floor` that is not a
        finite number >= 0, or `closed` not a bool.

    Examples
    --------
    >>> find_peaks([0.0, 2.0, 1.0, 3.0, 0.0])[0].tolist()
    [3, 1]
    >>> find_peaks(0.5 + 1e-14 * np.sin(np.arange(64.0)))[0].size  # round-off: flat
    0
    """
    closed = check_flag(closed, "closed")
    if prominence is not None:
        # max(nan, floor) is nan, which silently finds no peaks at all
        prominence = as_number(prominence, "prominence", ge=0)
    floor = as_number(floor, "floor", ge=0)
    u = check_values(u, "u", nan_ends=not closed)
    if u.ndim != 1:
        raise InputError(f"u: expected a 1-D array of values along the contour, got shape {u.shape}")
    finite = np.isfinite(u)
    if not finite.any():
        return np.empty(0, int), np.empty(0)
    lo, hi = np.nanmin(u), np.nanmax(u)
    noise = max(floor, ROUNDOFF * max(abs(lo), abs(hi)))
    if hi - lo <= noise:
        return np.empty(0, int), np.empty(0)
    if prominence is None:
        prominence = 0.05 * (hi - lo)
    v = np.where(finite, u, lo - 1.0)
    if closed:
        idx, prom = circular_peaks_and_prominences(v)
    else:
        # pad so that a maximum at an end point counts as a peak
        idx, prom = peaks_and_prominences(np.concatenate(([lo - 1.0], v, [lo - 1.0])))
        idx = idx - 1
    big = (prom >= prominence) & (prom > noise)
    idx, prom = idx[big], prom[big]
    order = np.lexsort((idx, -v[idx]))
    return idx[order], prom[order]
