"""Argument checks of the geometry package's public functions.

One rule per kind of argument, each raising :class:`~attneave.stimuli.errors.InputError`
(a ``ValueError``) whose one-line message names the argument. They run once,
where a value enters a public function; inner loops take checked values.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down).
"""

from __future__ import annotations

import numbers

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number, check_points  # noqa: F401  (check_points re-exported)

__all__ = ["check_points", "check_flag", "check_real", "check_int", "check_values", "check_scale", "check_area",
           "count_distinct_upto3", "MAX_COORDINATE", "MIN_EXTENT", "MIN_RELATIVE_EXTENT", "MIN_AREA_RATIO"]

# ------------------------------------------------------------------ the rules of a Contour
#: Largest |coordinate| (px) a contour may have: squares and products of coordinates
#: (lengths, areas) stay far from overflow, and no image is a million times larger.
MAX_COORDINATE = 1e12
#: Smallest extent (px, the larger side of the bounding box) of a contour: squared
#: segment lengths of smaller ones underflow towards 0 and their geometry is rounding.
MIN_EXTENT = 1e-6
#: the extent must also be this fraction of the largest |coordinate|: a shape drawn far from
# the origin is resolved by doubles to eps / 1e-10 ~ 2e-6 of its size, no worse
MIN_RELATIVE_EXTENT = 1e-10
#: A closed contour must enclose more than this fraction of its perimeter squared
#: (a circle encloses 1/(4 pi) = 0.08): below it, it is a line retracing itself and has
#: no inside, so convex and concave (the sign of its curvature) are undefined.
MIN_AREA_RATIO = 1e-12


def check_flag(value, name):
    """A ``bool`` (Python or numpy); a string such as ``'no'`` is refused, not taken as True."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InputError(f"{name}: must be True or False, got {value!r}")


def _scalar(value, name, kind):
    """Refuse what ``float()`` or ``int()`` would take but is no number here: strings, bools,
    None, arrays, complex values (the conversion and its bounds are :mod:`attneave.stimuli.validate`'s)."""
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None or np.ndim(value) != 0:
        raise InputError(f"{name}: must be {kind}, got {value!r}")
    if np.iscomplexobj(value):
        raise InputError(f"{name}: must be {kind}, got complex {value!r}")


def check_real(value, name, gt=None, ge=None):
    """One finite real number (not a string, bool or array), optionally bounded below.

    :func:`attneave.stimuli.validate.as_number` (its messages), after refusing what
    ``float()`` would take but is no number here (``'1'``, ``True``).
    """
    _scalar(value, name, "a number")
    return as_number(value, name, gt=gt, ge=ge)


def check_int(value, name, lo=None, hi=None):
    """One integer (an integral float such as ``10.0`` too; not 3.7, a string, bool or array).

    :func:`attneave.stimuli.validate.as_int` (its messages), after the same refusals as :func:`check_real`.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        _scalar(value, name, "an integer")
    return as_int(value, name, lo=lo, hi=hi)


def check_values(values, name, nan_ends=False):
    """A real float array with finite values; NaN allowed at the two ends if `nan_ends`
    (an open curve's end points have no turning angle)."""
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected an array of numbers") from None
    if raw.dtype.kind == "c":
        raise InputError(f"{name}: must be real numbers, got complex values")
    if raw.dtype.kind in "bSUV":  # booleans, strings and bytes are not numbers
        raise InputError(f"{name}: expected numbers, got {raw.dtype} values")
    try:
        a = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected an array of numbers") from None
    with np.errstate(over="ignore", invalid="ignore"):
        total = a.sum()
    if a.size and not np.isfinite(total):
        bad = ~np.isfinite(a)
        if nan_ends and a.ndim == 1 and len(a):
            bad[[0, -1]] &= ~np.isnan(a[[0, -1]])
        if bad.any():
            i = int(np.flatnonzero(bad.ravel())[0])
            raise InputError(f"{name}: values must be finite, got {a.ravel()[i]} at index {i}")
    return a


# ------------------------------------------------------------------ a Contour's shape
def _bounds(p):
    x, y = p[:, 0], p[:, 1]
    return float(x.min()), float(y.min()), float(x.max()), float(y.max())


def check_scale(p, where):
    """Refuse coordinates whose geometry would overflow or be only rounding noise."""
    if not len(p):
        return
    x0, y0, x1, y1 = _bounds(p)
    big = max(-x0, -y0, x1, y1)
    if big > MAX_COORDINATE:
        row = int(np.argmax(np.abs(p).max(axis=1)))
        raise InputError(f"{where}point {row}: coordinates must lie within +-{MAX_COORDINATE:g} px, "
                         f"got {p[row].tolist()}; rescale the contour")
    # the larger side of the bounding box (that of all-equal points is 0, caught below as too few points)
    extent = max(x1 - x0, y1 - y0)
    if 0 < extent < max(MIN_EXTENT, MIN_RELATIVE_EXTENT * big):
        raise InputError(f"{where}the contour spans only {extent:.3g} px (at coordinates up to {big:.3g}); "
                         f"a contour must span at least {MIN_EXTENT:g} px and 1e-10 of its distance from "
                         "the origin: rescale it")


def check_area(area, perimeter, p, where):
    """Refuse a closed contour that encloses no area (points on a line, or a path retracing itself).

    `area` is the (net) shoelace area about the first point; the tolerance
    adds to :data:`MIN_AREA_RATIO` times the perimeter squared the area that
    rounding the coordinates (eps times the largest, per point) can make or
    hide: of order that error times the perimeter. A net area within it is
    also that of a figure eight whose lobes cancel, which is accepted: then
    the area of the faces the curve bounds (by GEOS, lobes added) decides.
    """
    x0, y0, x1, y1 = _bounds(p)
    big = max(-x0, -y0, x1, y1)
    tol = MIN_AREA_RATIO * perimeter**2 + 4 * np.finfo(float).eps * big * perimeter
    if area <= tol:
        import shapely

        area = float(shapely.make_valid(shapely.Polygon(p)).area)
    if area <= tol:
        raise InputError(f"{where}the closed contour encloses no area ({area:.3g} px^2 for a perimeter of "
                         f"{perimeter:.6g} px: its points lie on one line or retrace themselves), so it has no "
                         "inside and convex and concave are undefined; treat it as an open curve (closed=False, or "
                         "--open on the command line)")


def count_distinct_upto3(z):
    """min(3, number of distinct points), points as complex numbers; O(N), no sort."""
    if len(z) == 0:
        return 0
    other = z != z[0]
    if not other.any():
        return 1
    second = z[np.argmax(other)]
    return 3 if np.any(other & (z != second)) else 2
