"""A portable effect size: the share of clicks at the top points of a prediction.

beta, the weight of standardised surprisal in the choice model, has no scale
that carries across stimulus sets: z at a polygon's corners reaches 8-10, so
beta = 1.5 puts nearly every click on one corner there while it is a modest
effect on smooth shapes. The share of clicks that fall on the top 10% of a
stimulus's points by the prediction means the same on any set:

``top_share``
    Share of the used clicks (on stimuli whose prediction is not constant)
    that fall on the top `fraction` of their stimulus's points.
``chance_share``
    The same share under uniform clicking: `fraction` exactly, because
    points tied at the threshold count fractionally (:func:`top_weights`).
``lift``
    ``top_share / chance_share``: how many times more often than chance
    people click the predicted points (1 = no effect).

:func:`beta_for_top_share` solves the other way, for the beta at which the
choice model gives a wanted share on a stimulus set, so that simulations and
power analyses can be stated in these units.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["TOP_FRACTION", "top_weights", "top_share", "expected_top_share", "beta_for_top_share",
           "resolve_effect"]

#: The share of points counted as "top" by default.
TOP_FRACTION = 0.1


def top_weights(Z, fraction=TOP_FRACTION):
    """Membership of each point in the top `fraction` of its stimulus's points.

    Points above the threshold count 1, points below 0, and the points tied at
    the threshold share what is left, so that every row sums to exactly
    ``fraction * n`` (a constant prediction gives every point `fraction`).

    Parameters
    ----------
    Z : (S, n) array_like
        Predictions (raw or standardised: only their order matters).
    fraction : float
        In (0, 1].

    Returns
    -------
    (S, n) ndarray

    Examples
    --------
    >>> top_weights([[0.0, 1.0, 2.0, 3.0, 4.0]], 0.2).tolist()
    [[0.0, 0.0, 0.0, 0.0, 1.0]]
    >>> top_weights([[0.0, 2.0, 2.0, 1.0]], 0.25).tolist()  # two points tied for the top one
    [[0.0, 0.5, 0.5, 0.0]]
    """
    Z = np.atleast_2d(np.asarray(Z, dtype=float))
    if not 0 < fraction <= 1:
        raise InputError(f"fraction must be in (0, 1], got {fraction!r}")
    S, n = Z.shape
    k = fraction * n
    # values equal to 9 digits of the row's range are ties (rounding noise on straight edges)
    span = np.ptp(Z, axis=1, keepdims=True)
    q = np.round((Z - Z.min(axis=1, keepdims=True)) / np.where(span > 0, span, 1.0), 9)
    srt = -np.sort(-q, axis=1)
    thr = srt[:, min(n - 1, max(0, int(np.ceil(k)) - 1))][:, None]
    above = q > thr
    tied = q == thr
    rest = k - above.sum(axis=1, keepdims=True)
    return np.where(above, 1.0, np.where(tied, rest / np.maximum(tied.sum(axis=1, keepdims=True), 1), 0.0))


def top_share(W, sidx, j, fraction=TOP_FRACTION):
    """Share of clicks on the top points, its chance level and the lift.

    Parameters
    ----------
    W : (S, n) array_like
        :func:`top_weights` of each stimulus.
    sidx, j : (U,) array_like of int
        Stimulus and point of each click (clicks on stimuli with a constant
        prediction should be left out: they carry no information).
    fraction : float
        The fraction `W` was made with (the chance share).

    Returns
    -------
    dict
        ``top_share``, ``chance_share``, ``lift``, ``fraction``,
        ``n_clicks`` (NaN values without clicks).
    """
    W = np.asarray(W, dtype=float)
    U = len(sidx)
    share = float(W[sidx, j].mean()) if U else np.nan
    return dict(top_share=share, chance_share=float(fraction), lift=share / fraction if U else np.nan,
                fraction=float(fraction), n_clicks=int(U))


def expected_top_share(Z, beta, fraction=TOP_FRACTION, weights=None):
    """Share of clicks on the top points expected under the choice model with `beta`.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    beta : float
    weights : (S,) array_like, optional
        Clicks per stimulus (default equal).
    """
    Z = np.asarray(Z, dtype=float)
    W = top_weights(Z, fraction)
    x = beta * Z
    p = np.exp(x - x.max(axis=1, keepdims=True))
    p /= p.sum(axis=1, keepdims=True)
    per = (p * W).sum(axis=1)
    w = np.ones(len(Z)) if weights is None else np.asarray(weights, dtype=float)
    return float(per @ w / w.sum())


def beta_for_top_share(Z, target, fraction=TOP_FRACTION, bound=50.0, name="--top-share", per=1.0):
    """The beta at which the choice model puts a share `target` of clicks on the top points.

    The expected share rises with beta (its derivative is the covariance of
    the top membership with z under the model, which is >= 0), so the root
    is unique; it is found with :func:`scipy.optimize.brentq`.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions of the stimulus set (each stimulus weighted
        equally, as in :func:`attneave.analysis.simulate.observers.simulate`).
    target : float
        Wanted share, in ``[fraction, largest reachable)``.
    fraction : float
        Share of points counted as top.
    name, per : str, float
        How the caller gave the target (the flag, and the factor from its
        value to the share: ``fraction`` for a lift), for the error message.

    Returns
    -------
    float

    Raises
    ------
    InputError
        If `target` is below chance or beyond what any beta reaches on this set.

    Examples
    --------
    >>> Z = np.array([[1.0, -1.0] + [0.0] * 8])  # one point of ten on top
    >>> b = beta_for_top_share(Z, 0.4)
    >>> round(expected_top_share(Z, b), 9)
    0.4
    """
    import scipy.optimize

    lo = expected_top_share(Z, 0.0, fraction)
    hi = expected_top_share(Z, bound, fraction)
    if not (np.isfinite(target) and lo - 1e-12 <= target < hi):
        raise InputError(f"{name} must be in [{lo / per:.3g}, {hi / per:.3g}) on this stimulus set (chance share "
                         f"{lo:.3g}; the largest share any beta <= {bound:g} reaches is {hi:.3g}), got {target / per:g}")
    if target <= lo:
        return 0.0
    return float(scipy.optimize.brentq(lambda b: expected_top_share(Z, b, fraction) - target, 0.0, bound,
                                       xtol=1e-12))


def resolve_effect(Z, beta=None, lift=None, top_share=None, fraction=TOP_FRACTION):
    """The effect given in any of its units: beta, lift or top share (exactly one).

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions of the stimulus set.
    beta, lift, top_share : float, optional
        Exactly one of them.

    Returns
    -------
    dict
        ``beta`` (solved by :func:`beta_for_top_share` when the effect is a
        lift or a share), ``top_share`` (expected under the model with that
        beta), ``chance_share``, ``lift``, ``fraction``, ``given`` (which unit
        was given).
    """
    given = {k: v for k, v in dict(beta=beta, lift=lift, top_share=top_share).items() if v is not None}
    if len(given) != 1:
        raise InputError("give the effect as exactly one of --beta, --lift, --top-share"
                         + (f" (got {', '.join('--' + k.replace('_', '-') for k in given)})" if given else ""))
    (unit, value), = given.items()
    if not np.isfinite(value):
        raise InputError(f"--{unit.replace('_', '-')} must be a finite number, got {value!r}")
    if unit == "beta":
        b = float(value)
    else:
        per = fraction if unit == "lift" else 1.0
        b = beta_for_top_share(Z, value * per, fraction, name=f"--{unit.replace('_', '-')}", per=per)
    share = expected_top_share(Z, b, fraction)
    return dict(beta=b, top_share=share, chance_share=float(fraction), lift=share / fraction,
                fraction=float(fraction), given=unit)
