"""Simulated observers and power analysis.

A simulated observer clicks on a stimulus by the choice model of
:mod:`attneave.analysis.models.choice`: point j of the stimulus's n equally spaced points is
chosen with probability ``exp(beta_p * z_j) / sum_i exp(beta_p * z_i)``, z
being the standardised surprisal; the click is then placed uniformly on that
point's arc (``t = (j + U(-1/2, 1/2)) / n``, so it maps back to point j) on
the contour as read, and displaced by isotropic Gaussian noise of sd
``noise`` pixels (the observer's motor and aiming error). ``beta_p`` is the
group's ``beta`` plus, optionally, a participant's own deviation with sd
``beta_sd``.

Randomness comes only from :class:`numpy.random.Generator`: participant p
draws from the p-th child of ``numpy.random.SeedSequence(seed)``, so the
clicks of the first participants do not change when more are simulated.
"""

from __future__ import annotations

import numpy as np

from attneave.analysis.argnames import arg
from attneave.analysis.clicks.read import from_image_coords
from attneave.analysis.models.group import mean_z_null, mean_z_test, monte_carlo_p, t_statistic
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number

__all__ = ["simulate", "simulate_indices", "power", "seed_sequence"]


def _count(name, value, minimum=1):
    """A whole number >= `minimum` (:func:`attneave.stimuli.validate.as_int`'s rule), as int."""
    try:
        return as_int(value, arg(name), lo=minimum)
    except InputError:
        raise InputError(f"{arg(name)} must be a whole number >= {minimum}, got {value!r}") from None


def _real(name, value, expected):
    """A finite float (:func:`attneave.stimuli.validate.as_number`'s rule: a bool or text is not
    one); `expected` completes the message."""
    try:
        return as_number(value, arg(name))
    except InputError:
        raise InputError(f"{arg(name)} must be {expected}, got {value!r}") from None


#: Largest |beta| and beta sd (as ``attneave simulate``'s): exp(beta * z) at |z| ~ 10 stays finite,
#: and 50 already puts every click on the most surprising point.
MAX_BETA = 50.0


def _check(participants, clicks, noise, beta, beta_sd):
    """Refuse bad arguments; return (participants, clicks) as ints (10.0 is 10)."""
    participants = _count("participants", participants)
    clicks = _count("clicks", clicks)
    if not _real("noise", noise, "a number of pixels >= 0") >= 0:
        raise InputError(f"{arg('noise')} must be a number of pixels >= 0, got {noise!r}")
    if not abs(_real("beta", beta, "a finite number")) <= MAX_BETA:
        raise InputError(f"{arg('beta')} must be from {-MAX_BETA:g} to {MAX_BETA:g}, got {beta!r}")
    if not 0 <= _real("beta_sd", beta_sd, "a finite number >= 0") <= MAX_BETA:
        raise InputError(f"{arg('beta_sd')} must be from 0 to {MAX_BETA:g}, got {beta_sd!r}")
    return participants, clicks


def _prediction_ids(predictions):
    from attneave.analysis.clicks.mapping import check_predictions

    return check_predictions(predictions)


def seed_sequence(seed):
    """The :class:`numpy.random.SeedSequence` of a `seed` argument, and the seed to record.

    Parameters
    ----------
    seed : int, numpy.random.Generator, numpy.random.SeedSequence or None
        A whole number >= 0; a Generator, from which one integer is drawn
        (so the generator advances, and a second call gives other draws);
        None for fresh entropy from the operating system. The recorded seed
        of a Generator or None is the integer actually used, so that passing
        it back reproduces the result.

    Returns
    -------
    (SeedSequence, int or str)
        The sequence, and the seed to record (the entropy as text for a
        SeedSequence given).

    Raises
    ------
    InputError
        Anything else (a negative number, a float, text, a bool, a
        RandomState), naming `seed`.

    Examples
    --------
    >>> ss, used = seed_sequence(7)
    >>> used, ss.entropy
    (7, 7)
    >>> _, a = seed_sequence(np.random.default_rng(0)); _, b = seed_sequence(np.random.default_rng(0))
    >>> a == b
    True
    """
    if isinstance(seed, np.random.SeedSequence):
        return seed, str(seed.entropy)
    if seed is None:
        ss = np.random.SeedSequence()
        return ss, int(ss.entropy)
    if isinstance(seed, np.random.Generator):
        used = int(seed.integers(0, 2**63 - 1))
        return np.random.SeedSequence(used), used
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"{arg('seed')} must be a whole number >= 0, a numpy.random.Generator or None, "
                         f"got {seed!r}")
    return np.random.SeedSequence(int(seed)), int(seed)


def _cdf_rows(Z, beta):
    """Stacked cumulative choice probabilities: row s lives in (s, s+1]."""
    x = beta * Z
    w = np.exp(x - x.max(axis=1, keepdims=True))
    cdf = np.cumsum(w, axis=1)
    cdf /= cdf[:, -1:]
    cdf[:, -1] = 1.0
    return (cdf + np.arange(len(Z))[:, None]).ravel()


def _draw(rng, Z, beta, clicks):
    """Point indices (S, clicks) for one observer, by inverse CDF in one search."""
    S, n = Z.shape
    flat = _cdf_rows(Z, beta)
    u = rng.random((S, clicks)) + np.arange(S)[:, None]
    j = np.searchsorted(flat, u, side="right") - (np.arange(S) * n)[:, None]
    return np.clip(j, 0, n - 1)


def simulate_indices(Z, participants, clicks, beta, seed, beta_sd=0.0):
    """Chosen point indices for simulated observers (no geometry, no noise).

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised surprisal of each stimulus at its n points.
    participants, clicks : int
        Observers, and clicks per observer per stimulus.
    beta : float
        Weight of z in the choice model.
    seed : int, numpy.random.Generator, numpy.random.SeedSequence or None
        See :func:`seed_sequence`.
    beta_sd : float
        Between-observer sd of beta.

    Returns
    -------
    j : (P, S, K) ndarray of int
    betas : (P,) ndarray
        Each observer's beta.
    rngs : list of numpy.random.Generator
        Each observer's generator, after the draws (for further draws).
    """
    participants, clicks = _check(participants, clicks, 0.0, beta, beta_sd)
    Z = np.asarray(Z, dtype=float)
    ss, _ = seed_sequence(seed)
    rngs = [np.random.Generator(np.random.PCG64(c)) for c in ss.spawn(participants)]
    betas = np.empty(participants)
    out = np.empty((participants, Z.shape[0], clicks), dtype=np.int64)
    for p, rng in enumerate(rngs):
        betas[p] = beta + (beta_sd * rng.standard_normal() if beta_sd > 0 else 0.0)
        out[p] = _draw(rng, Z, betas[p], clicks)
    return out, betas, rngs


def simulate(predictions, participants, clicks, beta, seed, noise=0.0, beta_sd=0.0, coords="image", scale=1.0):
    """Clicks of simulated observers on every stimulus of a set.

    Parameters
    ----------
    predictions : dict of str -> StimulusPrediction
        From :func:`attneave.analysis.clicks.mapping.predict` (it fixes n and the model).
    participants : int
        Number of observers.
    clicks : int
        Clicks per observer per stimulus.
    beta : float
        Weight of standardised surprisal (0: clicks uniform along the contour).
    seed : int, numpy.random.Generator or None
        Seed of the :class:`numpy.random.SeedSequence` (a whole number >=
        0), a Generator to draw it from, or None for fresh entropy; the seed
        used is recorded in ``params['seed']`` (see :func:`seed_sequence`).
    noise : float
        sd in pixels of isotropic Gaussian displacement of each click.
    beta_sd : float
        Between-observer sd of beta.
    coords : {'image', 'centered'}, scale : float
        Coordinate system of the written x, y (see :mod:`analysis.clicks`).

    Returns
    -------
    clicks : pandas.DataFrame
        Columns ``participant, stimulus_id, trial, x, y, true_t, true_point,
        participant_beta``; x, y in `coords` (image pixels, y down, by
        default). Rows by participant, then stimulus (set order), then trial.
    params : dict
        Every resolved parameter, and ``outside_share``: the share of the
        clicks that the noise put outside their image.

    Raises
    ------
    InputError
        A count that is no whole number >= 1 (a bool is not one), a `beta`,
        `noise` or `beta_sd` that is no finite number (or negative), a bad
        `seed`, an empty set; naming the parameter.

    Examples
    --------
    >>> import numpy as np
    >>> from attneave.stimuli.stimulus_set import StimulusSet
    >>> from attneave.analysis.clicks.mapping import predict
    >>> from attneave.stimuli import Contour
    >>> th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    >>> c = Contour(np.c_[100 + 60 * np.cos(th), 100 + 30 * np.sin(th)])
    >>> s = StimulusSet(".", None, ["e"], {"e": c}, {"e": (200, 200)})
    >>> df, params = simulate(predict(s, n=50), participants=2, clicks=3, beta=1.0, seed=1)
    >>> len(df), params["n"]
    (6, 50)
    """
    import pandas as pd

    participants, clicks = _check(participants, clicks, noise, beta, beta_sd)
    ss, used_seed = seed_sequence(seed)
    ids = _prediction_ids(predictions)
    if not ids:
        raise InputError("the stimulus set is empty")
    first = predictions[ids[0]]
    n = first.n
    Z = np.stack([predictions[s].z["surprisal"] for s in ids])
    j, betas, rngs = simulate_indices(Z, participants, clicks, beta, ss, beta_sd)
    P, S, K = j.shape
    offset = np.empty((P, S, K))
    disp = np.zeros((P, S, K, 2))
    for p, rng in enumerate(rngs):
        offset[p] = rng.random((S, K)) - 0.5
        if noise > 0:
            disp[p] = noise * rng.standard_normal((S, K, 2))
    t = np.mod((j + offset) / n, 1.0)
    xy = np.empty((P, S, K, 2))
    outside = 0
    for s, sid in enumerate(ids):
        pr = predictions[sid]
        pts = pr.contour.point_at(t[:, s, :].ravel()).reshape(P, K, 2)
        xi, yi = pts[..., 0] + disp[:, s, :, 0], pts[..., 1] + disp[:, s, :, 1]
        # the image covers pixel centres 0 .. width-1, i.e. [-0.5, width - 0.5] (docs/design.md, Coordinates)
        outside += int(((xi < -0.5) | (xi > pr.width - 0.5) | (yi < -0.5) | (yi > pr.height - 0.5)).sum())
        x, y = from_image_coords(xi, yi, pr.width, pr.height, coords, scale)
        xy[:, s, :, 0], xy[:, s, :, 1] = x, y
    width = max(3, len(str(P)))
    df = pd.DataFrame(
        {
            "participant": np.repeat([f"P{p + 1:0{width}d}" for p in range(P)], S * K),
            "stimulus_id": np.tile(np.repeat(ids, K), P),
            "trial": np.tile(np.arange(1, K + 1), P * S),
            "x": xy[..., 0].ravel(),
            "y": xy[..., 1].ravel(),
            "true_t": t.ravel(),
            "true_point": j.ravel(),
            "participant_beta": np.repeat(betas, S * K),
        }
    )
    params = dict(
        participants=int(P), clicks=int(K), stimuli=int(S), beta=float(beta), beta_sd=float(beta_sd),
        noise=float(noise), seed=used_seed,
        n=int(n), model=first.result.params["model"], coords=coords, scale=float(scale),
        outside_share=outside / max(P * S * K, 1),
    )
    return df, params


#: Fewest simulated experiments per design: with fewer, the Monte Carlo standard error of a
#: power near 0.5 exceeds 0.1 (sqrt(0.25 / 20) = 0.11) and the table estimates nothing.
MIN_SIMULATIONS = 20


def power(predictions, beta, participants=(5, 10, 20, 40), clicks=10, simulations=200, alpha=0.05, seed=0,
          noise=0.0, beta_sd=0.0, target=0.8, group_simulations=1999):
    """Power of the group test to detect `beta`, by simulation.

    For each simulated experiment the largest number of observers is drawn
    once and the smaller designs use its first observers (common random
    numbers, so the power curve is smooth in the number of participants).
    The test is the one `attneave analyze` reports: the one-sample t
    statistic across participants of each participant's mean z at the
    clicks, referred to its Monte Carlo null under uniform clicking with the
    same design (one-sided; see :func:`attneave.analysis.models.group.mean_z_test`); an
    experiment counts as a detection when ``p <= alpha``. The design (every
    participant clicks every stimulus `clicks` times) is the same in every
    experiment, so its null is simulated once per number of participants;
    an experiment in which click noise excluded clicks gets a null of its
    own design.

    Without noise a click maps back to the point it was drawn at, so the
    simulation works on point indices alone; with noise every click is
    placed, displaced, and mapped back to the contour as in `analyze`
    (clicks farther than the default tolerance are excluded, as there).

    Parameters
    ----------
    predictions : dict of str -> StimulusPrediction
    beta : float
        Effect to detect.
    participants : int or sequence of int
        Numbers of participants to evaluate (each at least 2; one number is
        a one-design table).
    clicks : int
        Clicks per participant per stimulus.
    simulations : int
        Simulated experiments per design, at least :data:`MIN_SIMULATIONS`.
    alpha : float
        Significance level; it must be at least ``1 / (group_simulations + 1)``,
        the smallest p the Monte Carlo null can give.
    seed : int, numpy.random.Generator or None
        As in :func:`simulate` (the seed used is recorded in ``info['seed']``).
    noise, beta_sd : float
        As in :func:`simulate`.
    target : float
        Power wanted, in (0, 1]; the smallest design reaching it is reported.
    group_simulations : int
        Monte Carlo replicates R of the null of the group test.

    Returns
    -------
    table : pandas.DataFrame
        ``participants, power, mc_se`` (Monte Carlo standard error),
        ``mean_effect`` (mean over experiments of the mean participant effect).
    info : dict
        Every parameter and ``required_participants`` (None if no design in
        `participants` reaches `target`).

    Raises
    ------
    InputError
        A bad count, number, `seed` or `predictions`, naming the parameter
        (the flag when ``attneave power`` called it).
    """
    import pandas as pd

    from attneave.analysis.clicks.mapping import map_clicks

    given = participants
    if np.ndim(participants) == 0 and not isinstance(participants, (str, bytes)):
        participants = [participants]  # one design
    try:
        items = list(participants)
        participants = sorted({_count("participants", p, 2) for p in items})
    except (TypeError, InputError):
        participants = None
    if not participants:
        raise InputError(f"{arg('participants')} needs whole numbers >= 2 (a t-test needs two), got {given!r}")
    try:
        simulations = _count("simulations", simulations, MIN_SIMULATIONS)
    except InputError:
        raise InputError(f"{arg('simulations')} must be a whole number >= {MIN_SIMULATIONS} (fewer experiments give "
                         f"no estimate of power: its Monte Carlo error would exceed 0.1), got {simulations!r}") from None
    if not 0 < _real("alpha", alpha, "in (0, 1)") < 1:
        raise InputError(f"{arg('alpha')} must be in (0, 1), got {alpha!r}")
    if not 0 < _real("target", target, "a power in (0, 1]") <= 1:
        raise InputError(f"{arg('target')} must be a power in (0, 1], got {target!r}")
    clicks = _check(participants[-1], clicks, noise, beta, beta_sd)[1]
    group_simulations = _count("group_simulations", group_simulations)
    ss, used_seed = seed_sequence(seed)
    R = int(group_simulations)
    if 1.0 / (R + 1) > alpha:
        # p = (1 + #{null >= t}) / (1 + R) is never below 1 / (1 + R): every design would show power 0
        need = int(np.ceil(1.0 / alpha - 1.0 - 1e-9))
        a, g = arg("alpha"), arg("group_simulations")
        raise InputError(f"{a} {alpha:g} is below the smallest p the Monte Carlo null can give, "
                         f"1/(R+1) = {1.0 / (R + 1):.3g} with {g} {R}: raise {g} "
                         f"to at least {need} (or {a} to at least {1.0 / (R + 1):.3g})")
    ids = _prediction_ids(predictions)
    Z = np.stack([predictions[s].z["surprisal"] for s in ids])
    Pmax = participants[-1]
    S = len(ids)
    sig = np.zeros((len(participants), simulations), bool)
    eff = np.zeros((len(participants), simulations))
    children = ss.spawn(simulations + 1)
    null_rng = np.random.default_rng(children[-1])  # the experiments' streams do not depend on it
    nulls = {}
    for P in participants:
        stim = np.tile(np.repeat(np.arange(S), clicks), P)
        unit = np.repeat(np.arange(P), S * clicks)
        nulls[P] = mean_z_null(Z, stim, unit, P, R, null_rng)

    def p_full_design(P, per_p):
        null, _, informative = nulls[P]
        return monte_carlo_p(null, t_statistic(per_p[:P][informative]))

    for r, child in enumerate(children[:simulations]):
        if noise == 0:
            j, _, _ = simulate_indices(Z, Pmax, clicks, beta, child, beta_sd)
            per_p = Z[np.arange(S)[None, :, None], j].mean(axis=(1, 2))
            pvals = [p_full_design(P, per_p) for P in participants]
        else:
            df, _ = simulate(predictions, Pmax, clicks, beta, child, noise=noise, beta_sd=beta_sd)
            m = map_clicks(df, predictions)
            keep = ~m["excluded"].to_numpy()
            pid = np.repeat(np.arange(Pmax), S * clicks)  # simulate writes rows participant by participant
            sid = np.tile(np.repeat(np.arange(S), clicks), Pmax)
            zc = m["z"].to_numpy(dtype=float)
            with np.errstate(invalid="ignore", divide="ignore"):
                per_p = (np.bincount(pid[keep], weights=zc[keep], minlength=Pmax)
                         / np.bincount(pid[keep], minlength=Pmax))
            pvals = []
            for P in participants:
                first = pid < P
                if keep[first].all():
                    pvals.append(p_full_design(P, per_p))
                else:  # exclusions changed the design: a null of its own
                    u = first & keep
                    pvals.append(mean_z_test(Z, sid[u], pid[u], zc[u], n_units=P, replicates=R,
                                             rng=null_rng)["p_value"])
        for i, P in enumerate(participants):
            sig[i, r] = np.isfinite(pvals[i]) and pvals[i] <= alpha
            eff[i, r] = np.nanmean(per_p[:P])
    pw = sig.mean(axis=1)
    table = pd.DataFrame(
        dict(participants=participants, power=pw, mc_se=np.sqrt(pw * (1 - pw) / simulations), mean_effect=eff.mean(axis=1))
    )
    reach = [p for p, w in zip(participants, pw) if w >= target]
    info = dict(
        beta=float(beta), beta_sd=float(beta_sd), clicks=int(clicks), stimuli=len(ids), simulations=int(simulations),
        alpha=float(alpha), seed=used_seed, noise=float(noise), target=float(target),
        n=int(predictions[ids[0]].n), model=predictions[ids[0]].result.params["model"],
        group_simulations=R,
        test=f"one-sample t statistic of per-participant mean z, Monte Carlo null under uniform clicking "
             f"(R = {R}), one-sided, detection when p <= alpha",
        required_participants=reach[0] if reach else None,
    )
    return table, info
