"""The one set of argument validators of the library, its configs and its commands.

Every public function checks an argument once, where it enters, with one of
these functions; the pydantic schemas of the configs
(:mod:`attneave.stimuli.batch.params`, :mod:`attneave.stimuli.batch.config`,
:mod:`attneave.analysis.experiment.options`) call the same functions, and the
commands pass their parsed flags to the library, so one value is refused in
the same words wherever it comes from. Each raises
:class:`~attneave.stimuli.errors.InputError` (a ``ValueError``) with one line
that names the parameter.

The rule for numbers, decided once
----------------------------------
A number is a Python ``int`` or ``float`` or a numpy integer or floating
scalar (or any other `numbers.Real`), finite unless said otherwise. **Strings
and booleans are not numbers**, even when ``float()`` would take them
(``"50"``, ``True``): ``radial_frequency(r0="50")`` is refused like
``surprisal(c, b="1")``, as numpy-minded libraries refuse text where a
number belongs. Text becomes a number only where it is read: a command's flag
(argparse's ``type=float``), a CSV cell, or a YAML scalar written unquoted
(``r0: 50`` is a number, ``r0: "50"`` a string and refused). An integer may
be given as an integral float (``10.0``); ``3.7`` is refused. A flag is a
Python or numpy bool (not ``'no'``, which would be true). None, complex
numbers and arrays are refused where one number belongs.

How a message names an argument
-------------------------------
By the caller's name for it: the Python parameter (``spacing``), or, when
``attneave`` runs a command (inside :func:`cli_names`), its flag
(``--spacing``): a check names ``arg("spacing")``.

Points are ``(x, y)`` floats in image pixels (x = column, y = row, y down);
:data:`MAX_COORDINATE` and :data:`MIN_EXTENT` bound every contour, spline and
point file the same way (:func:`check_scale`).
"""

from __future__ import annotations

import numbers

import numpy as np

from attneave.stimuli.argnames import arg, cli_names  # noqa: F401  (part of this module's face)
from attneave.stimuli.errors import InputError

__all__ = ["check_points", "as_points", "as_number", "parse_number", "as_int", "check_flag", "check_values", "check_scale",
           "check_area", "count_distinct_upto3", "as_rng", "MAX_COORDINATE", "MIN_EXTENT", "MIN_RELATIVE_EXTENT",
           "MIN_AREA_RATIO", "arg", "cli_names"]

#: Largest |coordinate| (px) a contour may have: squares and products of coordinates
#: (lengths, areas) stay far from overflow, and no image is a million times larger.
MAX_COORDINATE = 1e12
#: Smallest extent (px, the larger side of the bounding box) of a contour: squared
#: segment lengths of smaller ones underflow towards 0 and their geometry is rounding.
MIN_EXTENT = 1e-6
#: The extent must also be this fraction of the largest |coordinate|: a shape drawn far from
#: the origin is resolved by doubles to eps / 1e-10 ~ 2e-6 of its size, no worse.
MIN_RELATIVE_EXTENT = 1e-10
#: A closed contour must enclose more than this fraction of its perimeter squared
#: (a circle encloses 1/(4 pi) = 0.08): below it, it is a line retracing itself and has
#: no inside, so convex and concave (the sign of its curvature) are undefined.
MIN_AREA_RATIO = 1e-12


# ------------------------------------------------------------------ points
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
    if raw.dtype.kind in "bSUV":  # booleans and text are not coordinates (the rule for numbers)
        raise InputError(f"{what}: expected an (N, 2) array of (x, y) numbers, got {raw.dtype} values")
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


# ------------------------------------------------------------------ scalars
def _scalar(value, name, kind):
    """Refuse what ``float()`` or ``int()`` would take but is no number here: strings, bools,
    None, arrays and complex values (the rule of the module docstring)."""
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None or np.ndim(value) != 0:
        raise InputError(f"{name}: must be {kind}, got {value!r}")
    if np.iscomplexobj(value):
        raise InputError(f"{name}: must be {kind}, got complex {value!r}")


def as_number(value, name, gt=None, ge=None, lt=None, le=None):
    """Check one finite real number, optionally bounded; return it as a float.

    Strings and booleans are refused (see the module docstring).

    Raises
    ------
    InputError
        One line naming `name`: not a number, not finite, or out of bounds.

    Examples
    --------
    >>> as_number(np.float32(2.5), "r0", gt=0)
    2.5
    >>> as_number("50", "r0")
    Traceback (most recent call last):
        ...
    attneave.stimuli.errors.InputError: r0: must be a number, got '50'
    """
    _scalar(value, name, "a number")
    try:
        v = float(value)
    except OverflowError:  # an integer beyond the float range
        raise InputError(f"{name}: must be a finite number, got {value!r}") from None
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number, got {value!r}") from None
    if not np.isfinite(v):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    for bound, ok, sign in ((gt, lambda b: v > b, ">"), (ge, lambda b: v >= b, ">="),
                            (lt, lambda b: v < b, "<"), (le, lambda b: v <= b, "<=")):
        if bound is not None and not ok(bound):
            raise InputError(f"{name}: must be {sign} {bound}, got {value!r}")
    return v


def parse_number(text, name, gt=None, ge=None, lt=None, le=None):
    """A number read from text (a flag's or a cell's), then :func:`as_number`'s checks.

    The one place where text becomes a number: for values that are read
    (``--window-size 1920,1080``), never for a Python argument.

    Raises
    ------
    InputError
        Naming `name`: not the text of a number, or :func:`as_number`'s refusals.

    Examples
    --------
    >>> parse_number(" 1920", "--window-size", gt=0)
    1920.0
    """
    if isinstance(text, (str, bytes)):
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{name}: must be a number, got {text!r}") from None
    else:
        value = text
    return as_number(value, name, gt=gt, ge=ge, lt=lt, le=le)


def as_int(value, name, lo=None, hi=None):
    """Check one integer (an integral float such as ``10.0`` too), in [lo, hi]
    where given; return it as an int.

    Strings, booleans and fractional values are refused.

    Raises
    ------
    InputError
        Naming `name`, for a non-integer or out-of-range value.

    Examples
    --------
    >>> as_int(12.0, "n_points", lo=3)
    12
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        _scalar(value, name, "an integer")
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


def check_flag(value, name):
    """A ``bool`` (Python or numpy); a string such as ``'no'`` is refused, not taken as True."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InputError(f"{name}: must be True or False, got {value!r}")


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


# ------------------------------------------------------------------ a contour's size and area
def _bounds(p):
    x, y = p[:, 0], p[:, 1]
    return float(x.min()), float(y.min()), float(x.max()), float(y.max())


def check_scale(p, where, labels=None):
    """Refuse coordinates whose geometry would overflow or be only rounding noise.

    Parameters
    ----------
    p : (N, 2) float array
        Finite points.
    where : str
        Prefix of the message (``''`` or ``'FILE: '``).
    labels : sequence of str, optional
        How to name each row in a message (``'line 7'`` for a file's
        points); default ``'point i'``.

    Raises
    ------
    InputError
        A coordinate beyond +-:data:`MAX_COORDINATE`, or an extent below
        :data:`MIN_EXTENT` or :data:`MIN_RELATIVE_EXTENT` of the largest
        coordinate.
    """
    if not len(p):
        return
    x0, y0, x1, y1 = _bounds(p)
    big = max(-x0, -y0, x1, y1)
    if big > MAX_COORDINATE:
        row = int(np.argmax(np.abs(p).max(axis=1)))
        label = f"point {row}" if labels is None else labels[row]
        raise InputError(f"{where}{label}: coordinates must lie within +-{MAX_COORDINATE:g} px, "
                         f"got {p[row].tolist()}; rescale the contour")
    # the larger side of the bounding box (that of all-equal points is 0, caught elsewhere as too few points)
    extent = max(x1 - x0, y1 - y0)
    if 0 < extent < max(MIN_EXTENT, MIN_RELATIVE_EXTENT * big):
        raise InputError(f"{where}the contour spans only {extent:.3g} px (at coordinates up to {big:.3g}); "
                         f"a contour must span at least {MIN_EXTENT:g} px and {MIN_RELATIVE_EXTENT:g} of its "
                         "distance from the origin: rescale it")


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


# ------------------------------------------------------------------ random generators
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
