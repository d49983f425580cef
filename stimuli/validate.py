"""Validators for the Python API's arguments: points, numbers, integers and
random generators, each checked where it enters, with an `InputError` that
names the parameter.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down).
"""

from __future__ import annotations


import numpy as np

from stimuli.errors import InputError

__all__ = ["as_points", "as_number", "as_int", "as_rng"]


def as_points(obj, what="points", min_points=1):
    """Check and convert an (N, 2) array of ``(x, y)`` points (or anything with
    a ``.points`` attribute, such as a `Contour`).

    Raises
    ------
    InputError
        One line naming `what` and, for a non-finite value, the row.
    """
    pts = getattr(obj, "points", obj)
    try:
        pts = np.array(pts, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) numbers") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) points, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        row = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InputError(f"{what}: row {row}: coordinates must be finite, got {pts[row].tolist()}")
    if len(pts) < min_points:
        raise InputError(f"{what}: need at least {min_points} point(s), got {len(pts)}")
    return pts


def as_number(value, name, gt=None, ge=None, lt=None, le=None):
    """Check and convert one finite number, optionally bounded.

    Raises
    ------
    InputError
        One line naming `name`: not a number, not finite, or out of bounds.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number, got {value!r}") from None
    if not np.isfinite(v):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    if gt is not None and not v > gt:
        raise InputError(f"{name}: must be > {gt}, got {value!r}")
    if ge is not None and not v >= ge:
        raise InputError(f"{name}: must be >= {ge}, got {value!r}")
    if lt is not None and not v < lt:
        raise InputError(f"{name}: must be < {lt}, got {value!r}")
    if le is not None and not v <= le:
        raise InputError(f"{name}: must be <= {le}, got {value!r}")
    return v


def as_int(value, name, lo=None, hi=None):
    """Check that `value` is an integer (in [lo, hi] where given); return it as int.

    Raises
    ------
    InputError
        Naming `name`, for a non-integer or out-of-range value.

    Examples
    --------
    >>> as_int(12.0, "n_points", lo=3)
    12
    """
    try:
        v = int(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be an integer, got {value!r}") from None
    if v != value:
        raise InputError(f"{name}: must be an integer, got {value!r}")
    if lo is not None and v < lo:
        raise InputError(f"{name}: must be >= {lo}, got {value!r}")
    if hi is not None and v > hi:
        raise InputError(f"{name}: must be <= {hi}, got {value!r}")
    return v


def as_rng(rng, name="rng"):
    """A `numpy.random.Generator` from what a user passes as `rng`.

    A `Generator` is used as it is (its state advances); a non-negative
    integer seed (or a `numpy.random.SeedSequence`) gives
    ``numpy.random.default_rng(seed)``, so the same seed gives the same
    stimulus. Anything else, including None (fresh entropy would make the
    result irreproducible), a bool, a float, a negative integer or a legacy
    `numpy.random.RandomState`, is refused.

    Raises
    ------
    InputError
        Naming `name` and what was expected.

    Examples
    --------
    >>> as_rng(7).integers(100) == np.random.default_rng(7).integers(100)
    np.True_
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, (bool, np.bool_)):
        if rng < 0:
            raise InputError(f"{name}: a seed must be a non-negative integer, got {rng!r}")
        return np.random.default_rng(int(rng))
    if isinstance(rng, np.random.SeedSequence):
        return np.random.default_rng(rng)
    got = type(rng).__name__ + (f" {rng!r}"[:60] if isinstance(rng, (bool, float, str, np.generic)) else "")
    raise InputError(f"{name}: expected an integer seed >= 0 or a numpy.random.Generator, got {got}")
