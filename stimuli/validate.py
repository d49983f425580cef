"""Validators for the Python API's arguments: points, numbers, integers and
random generators, each checked where it enters, with an `InputError` that
names the parameter.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down).
"""

from __future__ import annotations


import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["check_points", "as_points", "as_number", "as_int", "as_rng"]


def check_points(points, what="points", min_points=1):
    """An (N, 2) float array of finite ``(x, y)``, N >= `min_points`.

    Accepts anything with a ``.points`` attribute (a `Contour`). Returns the
    input itself when it already is a float64 array (no copy: callers that
    keep or freeze the array must copy it).

    Raises
    ------
    InputError
        Naming `what`: not numbers, complex numbers, a shape other than
        (N, 2), a non-finite coordinate (with its row), or too few points.
    """
    pts = getattr(points, "points", points)
    try:
        raw = np.asarray(pts)
    except (TypeError, ValueError):  # ragged rows
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) numbers") from None
    if raw.dtype.kind == "c":
        raise InputError(f"{what}: coordinates must be real numbers, got complex values")
    try:
        p = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) numbers") from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) points, got shape {p.shape}")
    # a sum is finite only if every term is (an overflowing sum is checked term by term)
    with np.errstate(over="ignore", invalid="ignore"):
        total = p.sum()
    if len(p) and not np.isfinite(total) and not np.isfinite(p).all():
        row = int(np.flatnonzero(~np.isfinite(p).all(axis=1))[0])
        raise InputError(f"{what}: row {row}: coordinates must be finite, got {p[row].tolist()}")
    if len(p) < min_points:
        raise InputError(f"{what}: need at least {min_points} point(s), got {len(p)}")
    return p


def as_points(obj, what="points", min_points=1):
    """Check and copy an (N, 2) array of ``(x, y)`` points (or anything with
    a ``.points`` attribute, such as a `Contour`): :func:`check_points`, copied.

    Raises
    ------
    InputError
        One line naming `what` and, for a non-finite value, the row.
    """
    return np.array(check_points(obj, what, min_points), dtype=float)


def as_number(value, name, gt=None, ge=None, lt=None, le=None):
    """Check and convert one finite number, optionally bounded.

    Raises
    ------
    InputError
        One line naming `name`: not a number, not finite, or out of bounds.
    """
    try:
        v = float(value)
    except OverflowError:  # an integer beyond the float range
        raise InputError(f"{name}: must be a finite number, got {value!r}") from None
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
    except (TypeError, ValueError, OverflowError):  # OverflowError: an infinite float
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
