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
model of :mod:`analysis.mixed` combines both.

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

import numpy as np
import scipy.stats

__all__ = ["group_test", "t_statistic", "mean_z_null", "mean_z_test"]


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
    values do not spread (sd = 0) it is ``+inf`` for a positive mean,
    ``-inf`` for a negative one and 0 for all zeros, so that a Monte Carlo
    null can rank every replicate. NaN for k < 2.
    """
    v = np.asarray(v, dtype=float)
    k = v.shape[axis]
    if k < 2:
        return np.full(np.delete(v.shape, axis), np.nan) if v.ndim > 1 else np.float64(np.nan)
    m = v.mean(axis=axis)
    sd = v.std(axis=axis, ddof=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = m * np.sqrt(k) / sd
    return np.where(sd > 0, t, np.where(m > 0, np.inf, np.where(m < 0, -np.inf, 0.0)))


def _unit_means(Z, stimulus, unit, n_units):
    """The design of the mean-z statistic.

    Returns the informative units (at least one click on a stimulus whose
    prediction is not constant), the clicks on non-constant stimuli (the only
    ones whose z can differ from 0), their unit's row among the informative
    units as a sparse indicator, and each informative unit's number of clicks
    (all its clicks, including those with z = 0 by construction).
    """
    import scipy.sparse

    Z = np.asarray(Z, dtype=float)
    stimulus = np.asarray(stimulus, dtype=np.int64)
    unit = np.asarray(unit, dtype=np.int64)
    if n_units is None:
        n_units = int(unit.max()) + 1 if len(unit) else 0
    varies = np.any(Z != 0, axis=1)
    live = varies[stimulus]
    informative = np.bincount(unit[live], minlength=n_units) > 0
    counts = np.bincount(unit, minlength=n_units).astype(float)[informative]
    row = np.cumsum(informative) - 1
    k = int(informative.sum())
    sel = np.flatnonzero(live)
    ind = scipy.sparse.csr_matrix((np.ones(len(sel)), (row[unit[sel]], np.arange(len(sel)))), shape=(k, len(sel)))
    return informative, sel, ind, counts


def mean_z_null(Z, stimulus, unit, n_units=None, replicates=1999, rng=None, observed_z=None,
                max_elements=1 << 22):
    """t statistics of per-unit mean z under uniform clicking, for a fixed design.

    Each click keeps its stimulus and unit (participant or stimulus); its
    contour point is redrawn uniformly among the stimulus's n points
    (``p = 1/n``, the choice model at beta = 0), and the statistic is
    recomputed exactly as for the data: each informative unit's mean z over
    all its clicks, then :func:`t_statistic` across those units. The draws
    are made for all replicates at once, in chunks of at most `max_elements`
    (clicks x replicates) values.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    stimulus, unit : (U,) array_like of int
        Stimulus and unit of each used click.
    n_units : int, optional
    replicates : int
        Null replicates R.
    rng : numpy.random.Generator, optional
    observed_z : (U,) array_like, optional
        z at the observed clicks; its statistic is computed by the same code
        (same summation order), so that ties with replicates are exact.

    Returns
    -------
    null : (R,) ndarray
    observed : float
        NaN if `observed_z` is not given.
    informative : (n_units,) ndarray of bool
    """
    Z = np.asarray(Z, dtype=float)
    rng = np.random.default_rng() if rng is None else rng
    informative, sel, ind, counts = _unit_means(Z, stimulus, unit, n_units)
    S, n = Z.shape
    base = (np.asarray(stimulus, dtype=np.int64)[sel] * n)[:, None]
    flat = Z.ravel()
    R = int(replicates)

    def stat(zc):  # zc (clicks, columns) -> t of each column
        return t_statistic(np.asarray(ind @ zc) / counts[:, None], axis=0)

    observed = np.nan
    if observed_z is not None:
        observed = float(stat(np.asarray(observed_z, dtype=float)[sel][:, None])[0])
    null = np.empty(R)
    step = max(1, int(max_elements // max(len(sel), 1)))
    for a in range(0, R, step):
        b = min(R, a + step)
        idx = rng.integers(0, n, size=(len(sel), b - a), dtype=np.int32 if n < 2**31 else np.int64)
        null[a:b] = stat(flat[base + idx])
    return null, observed, informative


def mean_z_test(Z, stimulus, unit, z, n_units=None, replicates=1999, rng=None, level=0.95):
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
    null, obs, informative = mean_z_null(Z, stimulus, unit, n_units, R, rng, observed_z=z)
    sums = np.bincount(unit, weights=z, minlength=n_units)
    cnt = np.bincount(unit, minlength=n_units)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = np.where(informative, sums / cnt, np.nan)
    out = group_test(v, level=level, alternative="greater")
    out["p_value_parametric"] = out.pop("p_value")
    out["statistic"] = obs
    if R > 0 and not np.isnan(obs):
        # rounding must not break a tie between the data and a replicate
        tol = 1e-9 * max(1.0, abs(obs)) if np.isfinite(obs) else 0.0
        p = (1 + np.count_nonzero(null >= obs - tol)) / (1 + R)
    else:
        p = np.nan
    out.update(test=f"one-sample t statistic of mean z across units, Monte Carlo null under uniform clicking "
                    f"(R = {R})", p_value=p, simulations=R, alternative="greater")
    return out
