"""Group and items tests of per-unit mean z, calibrated by Monte Carlo.

Each participant's effect is the mean of z over that participant's clicks.
It is the score statistic of the model at beta = 0 divided by the number of
clicks (so it is the locally most powerful per-participant statistic); under
the null of clicks uniform along the contour it has expectation exactly 0,
since z has mean 0 over the points; and it stays finite with any number of
clicks, where a per-participant ML beta does not (it is infinite when all of
a participant's few clicks fall on the highest-z points). The effects are
compared across participants by their one-sample t statistic. This two-stage
"summary statistics" approach treats participants as a random effect (Holmes
& Friston 1998); the same test across stimuli (each stimulus's mean z) is the
items analysis that treats stimuli as random (Clark 1973). The crossed mixed
model of :mod:`attneave.analysis.models.mixed` combines both.

The t statistic is not referred to the t distribution: on stimuli whose
surprisal is spiky (polygons: z up to ~10 at a few corners) a participant's
mean z over few clicks is strongly right-skewed, and the t-test is then too
liberal (false-positive rates of 0.10-0.40 at alpha = 0.05 were measured
with 1-10 clicks per participant on the Attneave polygon set). A signed-rank
test would be no better: it assumes effects symmetric around 0. Instead the
statistic is calibrated by Monte Carlo under the exact null of uniform
clicking with the observed design (:func:`mean_z_test`): each click keeps its
stimulus and participant and its point is redrawn uniformly among the
stimulus's n points, R times; ``p = (1 + #{null >= t}) / (1 + R)``,
one-sided, since the hypothesis is that clicks favour high surprisal. This is
an exact test of uniform clicking for every design (its size is at most
alpha up to the resolution 1/(1+R)). The t statistic, Cohen's d_z and the t
interval of the mean are kept as descriptive values.

References
----------
.. [1] Holmes, A. P., & Friston, K. J. (1998). Generalisability, random
       effects and population inference. NeuroImage 7, S754.
.. [2] Clark, H. H. (1973). The language-as-fixed-effect fallacy. Journal of
       Verbal Learning and Verbal Behavior 12, 335-359.
"""

from __future__ import annotations

import threading

import numpy as np
import scipy.stats

from attneave.analysis.threads import ordered_map

__all__ = ["group_test", "t_statistic", "mean_z_nulls", "mean_z_null", "mean_z_test",
           "monte_carlo_p"]


def group_test(values, level=0.95, alternative="two-sided"):
    """One-sample t-test of per-unit effects (e.g. per participant) against 0.

    Valid when the effects are close to normal; for per-unit mean z, whose
    distribution under the null can be far from normal (few clicks on stimuli
    with spiky surprisal), use :func:`mean_z_test`, which calibrates the same
    statistic by Monte Carlo.

    Parameters
    ----------
    values : array_like
        One effect per participant (NaN ignored).
    level : float
        Confidence level of the (two-sided) interval of the mean.
    alternative : {'two-sided', 'greater', 'less'}
        Alternative hypothesis of the p-value.

    Returns
    -------
    dict
        ``test`` ('one-sample t-test'), ``statistic`` (t), ``df``,
        ``p_value``, ``alternative``, ``effect_size`` (Cohen's d_z = mean /
        sd), ``mean``, ``sd``, ``ci_low``, ``ci_high`` (of the mean), ``n``.
        NaN where there are too few values or no spread.
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = len(v)
    out = dict(test="one-sample t-test", statistic=np.nan, df=n - 1 if n >= 2 else None, p_value=np.nan,
               alternative=alternative, effect_size=np.nan, effect_size_name="cohen_dz",
               mean=float(v.mean()) if n else np.nan, sd=np.nan, ci_low=np.nan, ci_high=np.nan, n=n)
    if n >= 2:
        sd = float(v.std(ddof=1))
        out["sd"] = sd
        # a spread at rounding level is no spread: the t statistic would be noise
        if sd > 1e-12 * max(1.0, abs(float(v.mean()))):
            res = scipy.stats.ttest_1samp(v, 0.0, alternative=alternative)
            out["statistic"] = float(res.statistic)
            out["p_value"] = float(res.pvalue)
            out["effect_size"] = float(v.mean() / sd)
            half = scipy.stats.t.ppf(0.5 + level / 2, n - 1) * sd / np.sqrt(n)
            out["ci_low"], out["ci_high"] = float(v.mean() - half), float(v.mean() + half)
    return out


def t_statistic(v, axis=0):
    """One-sample t statistic against 0 along `axis`, defined for every sample.

    ``mean * sqrt(k) / sd`` (sd with ddof = 1) for k >= 2 values; where the
    values do not spread (sd at rounding level, as in :func:`group_test`) it
    is ``+inf`` for a positive mean, ``-inf`` for a negative one and 0 for
    all zeros, so that a Monte Carlo null can rank every replicate. NaN for
    k < 2.

    Examples
    --------
    >>> float(t_statistic([1.0, 2.0, 3.0]))
    3.4641016151377544
    >>> float(t_statistic([-0.1] * 4 + [-0.1 * (1 + 1e-14)]))  # equal but for rounding: no spread
    -inf
    """
    v = np.asarray(v, dtype=float)
    k = v.shape[axis]
    if k < 2:
        return np.full(np.delete(v.shape, axis), np.nan) if v.ndim > 1 else np.float64(np.nan)
    m = v.mean(axis=axis)
    sd = v.std(axis=axis, ddof=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = m * np.sqrt(k) / sd
    # a spread at rounding level is no spread: its t (e.g. -2e11) would be noise
    spread = sd > 1e-12 * np.maximum(1.0, np.abs(m))
    return np.where(spread, t, np.where(m > 0, np.inf, np.where(m < 0, -np.inf, 0.0)))


#: Sum the cells of a complete design as a grid (off only to test that it changes nothing).
_GRID = True


def _cycles(cell_row, k):
    """Whether the cells cycle through all k units in turn (each participant once on each stimulus:
    a complete design), so that a unit's cells are one column of a (blocks, k) grid."""
    return bool(k and len(cell_row) % k == 0
                and np.array_equal(cell_row.reshape(-1, k), np.broadcast_to(np.arange(k), (len(cell_row) // k, k))))


def _index_dtype(n):
    # numpy draws bounded 16-bit integers from buffered random bits, faster than 32- or 64-bit ones
    return np.uint16 if n <= 65536 else np.int64


def mean_z_nulls(Z, stimulus, units, replicates=1999, rng=None, observed_z=None, max_elements=1 << 22,
                 progress=None):
    """t statistics of per-unit mean z under uniform clicking, for several groupings of one design.

    Each click keeps its stimulus and units; its contour point is redrawn
    uniformly among the stimulus's n points (``p = 1/n``, the choice model at
    beta = 0), and for each grouping (e.g. participants, and stimuli for the
    items analysis) the statistic is recomputed exactly as for the data: each
    informative unit's mean z over all its clicks, then :func:`t_statistic`
    across those units. One set of draws serves every grouping: each
    grouping's null is exact; the nulls of two groupings are correlated.

    The draws are made for all replicates at once, in chunks of at most
    `max_elements` (clicks x replicates) values. The clicks on non-constant
    stimuli (the only ones whose z can vary) are ordered by cell (the clicks
    sharing stimulus and every unit), so that each cell's sum in every
    replicate is one :func:`numpy.add.reduceat` (skipped when every cell
    holds one click, as in a design where each participant clicks once per
    stimulus). A grouping whose units follow that order (stimuli, the first
    key) sums its cells with one more ``reduceat``; one whose units cycle
    within each stimulus (a complete design: every participant once on every
    stimulus) sums them as the columns of a grid; another adds them with
    :func:`numpy.bincount` per replicate (measured on 1,000,000 clicks:
    2-4 x faster than the sparse product it replaced, which copied each
    chunk into the other memory order; the grid's sums, in the same order,
    3 x faster again).

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus : (U,) array_like of int
        Stimulus of each used click.
    units : dict of str -> ((U,) array_like of int, int or None)
        For each grouping, the unit of each click and the number of units.
    replicates : int
        Null replicates R.
    rng : numpy.random.Generator, optional
    observed_z : (U,) array_like, optional
        z at the observed clicks; its statistic is computed by the same code
        (same summation order), so that ties with replicates are exact.
    progress : callable, optional
        Called with the fraction of replicates done after each chunk.

    Returns
    -------
    dict of str -> (null (R,) ndarray, observed float, informative (n_units,) bool ndarray)
    """
    Z = np.asarray(Z, dtype=float)
    rng = np.random.default_rng() if rng is None else rng
    stimulus = np.asarray(stimulus, dtype=np.int64)
    S, n = Z.shape
    live = np.flatnonzero(np.any(Z != 0, axis=1)[stimulus])
    keys = [stimulus[live]] + [np.asarray(u, dtype=np.int64)[live] for u, _ in units.values()]
    order = np.lexsort(keys[::-1])
    sel = live[order]
    sk = np.stack([k[order] for k in keys])
    starts = (np.flatnonzero(np.r_[True, np.any(sk[:, 1:] != sk[:, :-1], axis=0)]) if len(sel)
              else np.empty(0, np.int64))
    groupings = {}
    for g, (name, (unit, n_units)) in enumerate(units.items()):
        unit = np.asarray(unit, dtype=np.int64)
        if n_units is None:
            n_units = int(unit.max()) + 1 if len(unit) else 0
        informative = np.bincount(unit[live], minlength=n_units) > 0
        counts = np.bincount(unit, minlength=n_units).astype(float)[informative]
        row = np.cumsum(informative) - 1
        cell_row = row[sk[g + 1, starts]]
        # every informative unit has a cell; where the cells come unit by unit, each unit's
        # cells are one run (its start is where cell_row changes)
        runs = (np.flatnonzero(np.r_[True, cell_row[1:] != cell_row[:-1]])
                if len(cell_row) and np.all(cell_row[1:] >= cell_row[:-1]) else None)
        grid = _GRID and runs is None and _cycles(cell_row, len(counts))
        groupings[name] = (informative, counts, cell_row, runs, grid)
    singletons = len(starts) == len(sel)

    def unit_means(cells, counts, cell_row, runs, grid):  # (replicates, cells) -> (replicates, units)
        if runs is not None:
            return np.add.reduceat(cells, runs, axis=1) / counts
        if grid:  # the same sums in the same order as bincount's, 3 x faster
            return cells.reshape(len(cells), -1, len(counts)).sum(axis=1) / counts
        return np.stack([np.bincount(cell_row, weights=r, minlength=len(counts)) for r in cells]) / counts

    def stats(zc):  # zc (replicates, clicks) -> {name: t of each replicate}
        if zc.shape[1] == 0:
            return {k: np.full(len(zc), np.nan) for k in groupings}
        cells = zc if singletons else np.add.reduceat(zc, starts, axis=1)
        return {k: t_statistic(unit_means(cells, *g[1:]), axis=1) for k, g in groupings.items()}

    observed = dict.fromkeys(groupings, np.nan)
    if observed_z is not None:
        observed = {k: float(v[0]) for k, v in stats(np.asarray(observed_z, dtype=float)[sel][None, :]).items()}
    R = int(replicates)
    nulls = {k: np.empty(R) for k in groupings}
    step = max(1, int(max_elements // max(len(sel), 1)))
    # row offsets as intp: np.take converts narrower indices first (measured: 2.3 x slower)
    base = (stimulus[sel] * n).astype(np.intp)
    flat = Z.ravel()
    buffers = threading.local()  # each thread's index and gather arrays, reused from chunk to chunk
    spans = [(a, min(R, a + step)) for a in range(0, R, step)]
    # each chunk draws from a generator of its own, seeded from `rng`: the nulls are the same
    # whatever the number of threads that ran the chunks
    seeds = rng.integers(0, 2**63, size=len(spans)) if spans else []

    def chunk(i):
        a, b = spans[i]
        draws = np.random.default_rng(int(seeds[i])).integers(0, n, size=(b - a, len(sel)), dtype=_index_dtype(n))
        if getattr(buffers, "idx", None) is None or len(buffers.idx) < b - a:
            buffers.idx = np.empty(draws.shape, np.intp)
            buffers.z = np.empty(draws.shape)
        idx, zc = buffers.idx[:b - a], buffers.z[:b - a]
        # small integers plus the row offsets in one pass into a buffer that is already mapped
        np.add(draws, base, out=idx)
        return stats(np.take(flat, idx, out=zc, mode="clip"))  # "raise" with out= buffers the whole gather

    for i, result in enumerate(ordered_map(chunk, len(spans))):
        a, b = spans[i]
        for k, v in result.items():
            nulls[k][a:b] = v
        if progress is not None:
            progress(b / R)
    return {k: (nulls[k], observed[k], groupings[k][0]) for k in groupings}


def monte_carlo_p(null, observed):
    """One-sided Monte Carlo p-value ``(1 + #{null >= observed}) / (1 + R)`` (NaN without replicates).

    Examples
    --------
    >>> monte_carlo_p(np.array([0.0, 1.0, 2.0, 3.0]), 2.0)
    0.6
    """
    R = len(null)
    if R == 0 or np.isnan(observed):
        return np.nan
    # rounding must not break a tie between the data and a replicate
    tol = 1e-9 * max(1.0, abs(observed)) if np.isfinite(observed) else 0.0
    return float((1 + np.count_nonzero(null >= observed - tol)) / (1 + R))


def mean_z_null(Z, stimulus, unit, n_units=None, replicates=1999, rng=None, observed_z=None):
    """t statistics of per-unit mean z under uniform clicking, for one grouping (see :func:`mean_z_nulls`).

    Returns
    -------
    null : (R,) ndarray
    observed : float
        NaN if `observed_z` is not given.
    informative : (n_units,) ndarray of bool
    """
    return mean_z_nulls(Z, stimulus, {"unit": (unit, n_units)}, replicates, rng, observed_z)["unit"]


def mean_z_test(Z, stimulus, unit, z, n_units=None, replicates=1999, rng=None, level=0.95, null=None):
    """Test whether clicks favour high z: per-unit mean z across units, calibrated by Monte Carlo.

    The statistic is the one-sample t of the units' mean z (0 under uniform
    clicking). Its null distribution is simulated under the exact null of
    uniform clicking with the observed design (:func:`mean_z_null`), because
    with few clicks per unit on stimuli whose z is spiky (polygons) the mean
    z is strongly right-skewed and the t distribution makes the test too
    liberal. The p-value is one-sided (the hypothesis is that clicks favour
    high surprisal): ``(1 + #{null >= t}) / (1 + R)``, which never falls
    below ``1 / (1 + R)``.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus, unit : (U,) array_like of int
        Stimulus and unit (participant, or stimulus for the items analysis)
        of each used click.
    z : (U,) array_like
        z at each used click (``Z[stimulus, point]``).
    replicates : int
        Monte Carlo replicates R (0: only the parametric values).
    rng : numpy.random.Generator, optional
    null : tuple, optional
        This grouping's entry of :func:`mean_z_nulls` when it has been
        drawn already (with `z` as `observed_z`).

    Returns
    -------
    dict
        ``test``, ``statistic`` (t), ``p_value`` (Monte Carlo), ``alternative``
        ('greater'), ``simulations`` (R), ``p_value_parametric`` (one-sided
        t distribution, descriptive), ``df``, ``effect_size`` (Cohen's d_z),
        ``mean``, ``sd``, ``ci_low``, ``ci_high`` (t interval of the mean,
        descriptive), ``n`` (informative units).
    """
    z = np.asarray(z, dtype=float)
    stimulus = np.asarray(stimulus, dtype=np.int64)
    unit = np.asarray(unit, dtype=np.int64)
    if n_units is None:
        n_units = int(unit.max()) + 1 if len(unit) else 0
    R = int(replicates)
    if null is None:
        null = mean_z_null(Z, stimulus, unit, n_units, R, rng, observed_z=z)
    null, obs, informative = null
    R = len(null)
    sums = np.bincount(unit, weights=z, minlength=n_units)
    cnt = np.bincount(unit, minlength=n_units)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = np.where(informative, sums / cnt, np.nan)
    out = group_test(v, level=level, alternative="greater")
    out["p_value_parametric"] = out.pop("p_value")
    out["statistic"] = obs
    p = monte_carlo_p(null, obs)
    out.update(test=f"one-sample t statistic of mean z across units, Monte Carlo null under uniform clicking "
                    f"(R = {R})", p_value=p, simulations=R, alternative="greater")
    return out
