"""Argument checks shared by the curve families and splines, and their arc-length grid.

Each check returns the value in the type the code needs or raises
:class:`~attneave.stimuli.errors.InputError` with one line naming the parameter.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number, check_flag

__all__ = ["MAX_ARC", "MAX_RATE", "MAX_POINTS", "check_flag", "check_count", "check_samples", "check_tolerance",
           "arc_grid"]

#: Largest |arc length| of a curve, in its own units: far beyond any figure,
#: and small enough that curvature x arc length cannot overflow.
MAX_ARC = 1e6
#: Largest |curvature parameter| (k0, c) of the clothoid.
MAX_RATE = 1e12
#: Most points a curve family or a spline's samples may have. Each point
#: carries five float64 columns (s, x, y, theta, curvature) and costs up to
#: ~15 us to evaluate (superspiral quadrature), so the bound is ten times below
#: :meth:`attneave.stimuli.geometry.Contour.resample`'s 1e8 plain points: 10**7 points
#: are about 0.4 GB and seconds to minutes of work; the command line allows
#: 1e6 rows.
MAX_POINTS = 10**7


def check_count(value, name, lo=2, hi=MAX_POINTS):
    """A whole number in ``[lo, hi]`` (:func:`attneave.stimuli.validate.as_int`'s rule:
    integral floats accepted, bools and strings refused), as int; an InputError naming
    `name` and the range otherwise."""
    if isinstance(value, np.generic):
        value = value.item()  # messages print plain numbers, never np.int64(...)
    span = f"in [{lo}, {hi:.0e}]" if hi >= 10**6 else f"in [{lo}, {hi}]"
    if hi >= 2**62:
        span = ""
    try:
        return as_int(value, name, lo=lo, hi=hi)
    except InputError:
        raise InputError(f"{name}: must be an integer {span}".rstrip() + f", got {value!r}") from None


def check_samples(samples, segments):
    """Samples per segment of a spline's ``sample``: an integer >= 2 with at
    most :data:`MAX_POINTS` points in all (`segments` segments)."""
    samples = as_int(samples, "samples (per segment)", lo=2)
    if samples * max(int(segments), 1) > MAX_POINTS:
        raise InputError(
            f"samples: {samples} per segment x {segments} segments = {samples * segments} points; "
            f"at most {MAX_POINTS:.0e} in all"
        )
    return samples


def check_tolerance(value, name, allow_zero=False):
    """A finite tolerance, > 0 (>= 0 with `allow_zero`)."""
    return as_number(value, name, ge=0.0) if allow_zero else as_number(value, name, gt=0.0)


def _arc_number(value, name):
    """A finite arc length within +-MAX_ARC; messages print plain numbers
    (never ``np.float64(...)``)."""
    if isinstance(value, np.generic):
        value = value.item()
    v = as_number(value, name)
    if abs(v) > MAX_ARC:
        raise InputError(f"{name}: arc lengths must lie within +-{MAX_ARC:g}, got {v:g}")
    return v


def arc_grid(s_start, s_end, num, s=None):
    """The output arc lengths: `num` equally spaced in [s_start, s_end], or `s`.

    Arc lengths must lie within +-:data:`MAX_ARC`; at most :data:`MAX_POINTS`
    of them.
    """
    if s is not None:
        try:
            s = np.asarray(s, dtype=float)
        except (TypeError, ValueError):
            raise InputError("s must be a 1-D array of at least 2 finite arc lengths") from None
        if s.ndim != 1 or len(s) < 2 or not np.all(np.isfinite(s)):
            raise InputError("s must be a 1-D array of at least 2 finite arc lengths")
        if len(s) > MAX_POINTS:
            raise InputError(f"s: at most {MAX_POINTS:.0e} arc lengths, got {len(s)}")
        if np.max(np.abs(s)) > MAX_ARC:
            raise InputError(f"s: arc lengths must lie within +-{MAX_ARC:g}")
        if np.any(np.diff(s) <= 0):
            raise InputError("s must be strictly increasing")
        return s
    s_start = _arc_number(s_start, "s_start")
    s_end = _arc_number(s_end, "s_end")
    if not s_end > s_start:
        raise InputError(f"s_end must be greater than s_start, got s_start={s_start:g}, s_end={s_end:g}")
    num = check_count(num, "num (points)")
    return np.linspace(s_start, s_end, num)
