"""The information model: surprisal of turning angles along a contour.

Two forms are provided.

* The paper's form (Ziatdinov, eq. 4-5), written exactly as published:
  ``u = -ln A' - b * ds**2 * cos(a)`` for an open curve (eq. 4) and
  ``u = -ln A' - b * ds**2 * cos(a - 2*pi/n)`` for a closed one (eq. 5),
  where ``a = k * ds`` is the turning angle, ``ds = L / n`` and ``n`` the
  number of equally spaced points. It is not a normalised log-density (the
  ``ds**2`` factor is the paper's); its shape, not its level, is what matters.
* The von Mises form of Feldman & Singh (2005): turning angles follow
  ``p(a) = exp(b*cos(a - mu)) / (2*pi*I0(b))`` with ``mu = 2*pi/n`` on a
  closed contour (its mean turn) and 0 on an open one; ``u = -ln p(a)``.

Both are computed from the discrete turning angle rather than from curvature,
so a corner (where curvature is infinite, the paper's eq. 6) has a finite,
high surprisal. In both, a concave turn carries more information than a convex
turn of the same size, because the mean turn ``2*pi/n`` is convex.

The unit of length
------------------
Turning angles do not depend on the size of a shape, but the paper's factor
``ds**2`` does: with ds in pixels the same shape drawn twice as large has four
times the contrast and, on its straight parts, values far below zero. So ``ds``
enters eq. 4-5 in an explicit ``length_unit`` (:data:`LENGTH_UNITS`), recorded
in every result:

* ``'sample'`` (default): lengths in units of the sample spacing, so
  ``ds = 1`` and eq. 5 is eq. 3 of the paper (Feldman & Singh's kernel)
  applied to the turning angle, ``u = -ln A' - b*cos(a - 2*pi/n)``: ``b`` is
  the concentration of turning angles and u lies in
  ``[-ln A' - b, -ln A' + b]`` whatever the size of the shape.
* ``'perimeter'``: lengths in perimeters, ``ds = 1/n`` on a closed contour
  and ``ds = 1/(n-1)`` on an open one (its n points, both ends included,
  span n - 1 intervals: ``ds = L/(n-1)`` in pixels); scale-free too, but
  the shape-dependent part shrinks to ``b/n**2`` (1e-4 nats at n = 100).
* ``'radius'``: lengths in radii of the circle of equal area (closed only),
  ``ds = L/(n*R)``, ``2*pi/n`` on a circle; scale-free, larger for
  elongated shapes.
* ``'px'``: the paper's literal pixels (or a curve's own units), to reproduce
  its figures; values then scale with the square of the drawing size.

A negative value. ``u = -ln(A' * exp(b*ds**2*cos(a - mu)))`` is negative
where the paper's unnormalised density of turning angles exceeds 1 per
radian, i.e. where ``b*ds**2*cos(a - mu) > -ln A'``. ``A'`` is a free
constant, not the normaliser, so the level of u is arbitrary and only
differences between points carry meaning. With ``'sample'`` and the default
``A' = 1/4``, ``b = 1`` it cannot happen (u >= ln 4 - 1 = 0.386 nats); with
``b > ln(1/A')`` it happens at turns close to the mean turn (the least
informative points); with ``'px'`` it happens on every nearly straight part
of a shape a few pixels across or more, and means no more than that.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.geometry.peaks import (  # re-exported: part of this module's API
    ROUNDOFF,
    find_peaks,
)
from attneave.stimuli.geometry.polyline import unchecked_turning_angles
from attneave.stimuli.geometry.surprisal_result import SurprisalResult  # re-exported: part of this module's API
from attneave.stimuli.validate import (
    as_int,
    as_number,
    check_flag,
    check_points,
    check_values,
)

__all__ = [
    "surprisal_paper",
    "surprisal_vonmises",
    "surprisal",
    "surprisal_from_points",
    "find_peaks",
    "noise_prominence",
    "length_scale",
    "SurprisalResult",
    "MODELS",
    "LENGTH_UNITS",
    "DEFAULT_LENGTH_UNIT",
    "NOISE_TURN",
    "ROUNDOFF",
]

MODELS = ("paper", "vonmises")
#: Units of length in which ``ds`` enters eq. 4-5 (see the module docstring).
LENGTH_UNITS = ("sample", "perimeter", "radius", "px")
#: Scale-free: one shape at any size has the same surprisal.
DEFAULT_LENGTH_UNIT = "sample"
_LN2 = np.log(2.0)
#: Turning-angle noise as a fraction of the mean turn ``2*pi/n``: a surprisal peak must
#: stand out by more than a turn this far from the mean turn makes (see
#: :func:`noise_prominence`). Resampling a circle drawn as a polygon of V vertices moves
#: its turning angles off the mean turn by up to about 0.17 * n / V of it (the samples
#: fall at varying places between the vertices): below 1 % for V >= 17 n, so a circle
#: drawn finely enough for its sampling has no peaks; an ellipse of axis ratio 1.02
#: already turns 3 % away from the mean and keeps its peaks at any n.
NOISE_TURN = 0.01


def _check_params(n, A=None, b=None):
    """Checked ``n, A, b`` (an integer n >= 1, finite A > 0, finite b >= 0); None stays None."""
    n = as_int(n, "n", lo=1)
    # infinite A or b would give -inf or NaN surprisal in every row
    A = None if A is None else as_number(A, "A", gt=0)
    b = None if b is None else as_number(b, "b", ge=0)
    return n, A, b


def noise_prominence(params):
    """Smallest surprisal prominence that is not resampling noise, for a result's parameters.

    The surprisal difference that a turn :data:`NOISE_TURN` (1 %) of the mean
    turn ``2*pi/n`` away from it makes: ``amp * (1 - cos(NOISE_TURN * 2*pi/n))``,
    where ``amp`` is the amplitude of the cosine term (``b * ds**2`` in the
    length unit for the paper's form, ``b`` for the von Mises form; divided
    by ln 2 in bits).
    :func:`surprisal` never reports a peak of smaller prominence, so that a
    circle (whatever its size, n or length unit) has none; callers that find
    peaks of the same surprisal themselves can pass it as `floor` to
    :func:`find_peaks`.

    Parameters
    ----------
    params : dict
        ``SurprisalResult.params`` (keys ``model``, ``n``, ``b``,
        ``ds_in_unit``, ``bits``).

    Returns
    -------
    float

    Examples
    --------
    >>> float(noise_prominence(dict(model="paper", n=100, b=1.0, ds_in_unit=1.0, bits=False)))  # doctest: +ELLIPSIS
    1.97...e-07
    """
    amp = float(params["b"]) * (float(params["ds_in_unit"]) ** 2 if params["model"] == "paper" else 1.0)
    amp = amp / _LN2 if params["bits"] else amp
    d = NOISE_TURN * 2 * np.pi / float(params["n"])
    return amp * 2 * np.sin(d / 2) ** 2  # 1 - cos(d), without cancellation


def length_scale(length_unit, spacing, length, area=None):
    """Pixels per unit of length, for ``ds`` in eq. 4-5.

    Parameters
    ----------
    length_unit : {'sample', 'perimeter', 'radius', 'px'}
        See :data:`LENGTH_UNITS` and the module docstring.
    spacing : float
        Sample spacing ``ds`` in pixels.
    length : float
        Length of the contour in pixels.
    area : float, optional
        Enclosed area in px^2; needed for ``'radius'`` only.

    Returns
    -------
    float
        The length of one unit in pixels: `spacing`, `length`,
        ``sqrt(area/pi)`` or 1. ``ds`` in the unit is ``spacing / scale``.

    Raises
    ------
    InputError
        An unknown unit, or ``'radius'`` without a positive area.

    Examples
    --------
    >>> length_scale("perimeter", spacing=2.0, length=200.0)
    200.0
    >>> length_scale("radius", spacing=2.0, length=200.0, area=100 * np.pi)
    10.0
    """
    if length_unit == "sample":
        return float(spacing)
    if length_unit == "perimeter":
        return float(length)
    if length_unit == "px":
        return 1.0
    if length_unit == "radius":
        if area is None or not area > 0:
            raise InputError("length_unit 'radius' needs a closed contour with a positive area")
        return float(np.sqrt(area / np.pi))
    raise InputError(f"unknown length_unit {length_unit!r}; expected one of {', '.join(LENGTH_UNITS)}")


def surprisal_paper(turning_angle, ds, n, A=0.25, b=1.0, closed=True, bits=False):
    """Surprisal in the paper's curvature form (Ziatdinov, eq. 4 and 5).

    Parameters
    ----------
    turning_angle : array_like
        Turning angle ``a = k * ds`` at each point, in radians (left turns on
        the screen positive, so convex points of a counter-clockwise closed
        contour are positive).
    ds : float
        Spacing between points, ``L / n``, in the unit of length chosen (see
        :func:`length_scale`): 1 in units of the spacing (``'sample'``),
        ``1/n`` in perimeters (``1/(n-1)`` on an open curve, whose spacing
        is ``L/(n-1)``), ``L/n`` in pixels (the paper's literal reading,
        whose values scale with the square of the drawing size).
    n : int
        Number of equally spaced points on the contour.
    A : float
        The constant ``A'`` (default 1/4 as in the paper's figures).
    b : float
        The concentration ``b`` (default 1).
    closed : bool
        Eq. 5 (closed, mean turn ``2*pi/n``) or eq. 4 (open, mean turn 0).
    bits : bool
        Return bits instead of nats.

    Returns
    -------
    ndarray
        ``-ln A' - b * ds**2 * cos(a - 2*pi/n)`` (closed) or
        ``-ln A' - b * ds**2 * cos(a)`` (open).

    Raises
    ------
    InputError
        Non-finite turning angles (NaN is allowed at the two ends of an open
        curve's 1-D array, which have none, and gives NaN there), `ds` not
        finite numbers >= 0, `n` not an integer >= 1, `A` or `b` out of
        range, `closed` or `bits` not a bool.

    References
    ----------
    .. [1] Ziatdinov, R. Visual perception, quantity of information function
           and the concept of the quantity of information continuous splines.
           Eq. 4-5.

    Examples
    --------
    >>> round(float(surprisal_paper(0.0, ds=10, n=10, A=0.25, b=1, closed=False)), 6)  # -ln(1/4) - 100
    -98.613706
    """
    n, A, b = _check_params(n, A, b)
    closed, bits = check_flag(closed, "closed"), check_flag(bits, "bits")
    a = check_values(turning_angle, "turning_angle", nan_ends=not closed)
    ds = check_values(ds, "ds")
    if (ds < 0).any():
        raise InputError(f"ds: must be >= 0, got {ds.min()}")
    return _paper(a, ds, n, A, b, closed, bits)


def _paper(a, ds, n, A, b, closed, bits):
    """:func:`surprisal_paper` of checked arguments."""
    mu = 2 * np.pi / n if closed else 0.0
    u = -np.log(A) - b * ds * ds * np.cos(a - mu)
    return u / _LN2 if bits else u


def surprisal_vonmises(turning_angle, n, b=4.0, closed=True, bits=False):
    """Surprisal of turning angles under a normalised von Mises law.

    Parameters
    ----------
    turning_angle : array_like
        Turning angles in radians (left turns on the screen positive).
    n : int
        Number of equally spaced points (sets the mean turn of a closed
        contour, ``mu = 2*pi/n``).
    b : float
        Concentration of the von Mises law (default 4).
    closed : bool
        ``mu = 2*pi/n`` when closed, 0 when open.
    bits : bool
        Return bits instead of nats.

    Returns
    -------
    ndarray
        ``-ln p(a) = ln(2*pi*I0(b)) - b*cos(a - mu)``.

    Raises
    ------
    InputError
        As :func:`surprisal_paper` (`b` must be a finite number >= 0).

    References
    ----------
    .. [1] Feldman, J., & Singh, M. (2005). Information along contours and
           object boundaries. Psychological Review 112(1), 243-252.
    """
    n, _, b = _check_params(n, None, b)
    if b is None:
        raise InputError("b: must be a number (the concentration, default 4), got None")
    closed, bits = check_flag(closed, "closed"), check_flag(bits, "bits")
    a = check_values(turning_angle, "turning_angle", nan_ends=not closed)
    return _vonmises(a, n, b, closed, bits)


def _vonmises(a, n, b, closed, bits):
    """:func:`surprisal_vonmises` of checked arguments."""
    mu = 2 * np.pi / n if closed else 0.0
    log_norm = np.log(2 * np.pi) + _log_i0(b)
    u = log_norm - b * np.cos(a - mu)
    return u / _LN2 if bits else u


def _log_i0(b):
    """ln I0(b), finite for any concentration b >= 0.

    numpy's ``i0`` (Cephes, about 1e-15 relative) overflows above b ~ 700;
    there the asymptotic series ``b - ln(2 pi b)/2 + ln(1 + 1/(8b) + 9/(128
    b^2) + 225/(3072 b^3))`` is exact to 1e-12 (Abramowitz & Stegun 9.7.1).
    Used instead of scipy.special.i0e, whose import alone costs a command
    more than its work.
    """
    if b < 700.0:
        return float(np.log(np.i0(b)))
    t = 1.0 / (8.0 * b)
    return float(b - 0.5 * np.log(2 * np.pi * b) + np.log1p(t + 4.5 * t * t + 37.5 * t**3))


def surprisal(contour, n=None, spacing=None, model="paper", A=0.25, b=None, bits=False, prominence=None,
              length_unit=DEFAULT_LENGTH_UNIT):
    """Surprisal at `n` equally spaced points of a contour.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Points in image pixels (y down). Arrays are taken as closed contours.
    n : int, optional
        Number of equally spaced points (default 100 when `spacing` is not
        given). Peak values depend on it; it is recorded in the result.
    spacing : float, optional
        Spacing in pixels instead of `n`.
    model : {'paper', 'vonmises'}
        Eq. 4/5 of the paper or the normalised von Mises form.
    A : float
        ``A'`` of the paper's form (default 1/4).
    b : float, optional
        Concentration; default 1 for 'paper' (as in the paper's figures) and
        4 for 'vonmises'.
    bits : bool
        Bits instead of nats.
    prominence : float, optional
        Peak prominence threshold (see :func:`find_peaks`). Whatever it is,
        a peak must stand out by more than :func:`noise_prominence` (what a
        turn 1 % of the mean turn away from it makes), so that a circle drawn
        as a fine polygon has no peaks.
    length_unit : {'sample', 'perimeter', 'radius', 'px'}
        Unit of ``ds`` in eq. 4-5 (the 'paper' model only; the von Mises form
        has no ``ds``). The default, ``'sample'`` (ds = 1), and
        ``'perimeter'`` (ds = 1/n closed, 1/(n-1) open) and ``'radius'`` give the same values for
        a shape at any size; ``'px'`` is the paper's literal pixels. Recorded
        in ``params['length_unit']``; see the module docstring for what a
        negative value means.

    Returns
    -------
    SurprisalResult

    Raises
    ------
    InputError
        Unknown `model` or `length_unit`, a parameter out of range or of the
        wrong type (a non-integer `n`, a string for a number or for `bits`),
        or a contour the :class:`Contour` rules refuse.

    Examples
    --------
    >>> import numpy as np
    >>> th = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    >>> r = surprisal(np.c_[50 * np.cos(th), 50 * np.sin(th)], n=64)
    >>> bool(np.ptp(r.surprisal) < 1e-9), len(r.peaks)
    (True, 0)
    >>> big = surprisal(np.c_[200 * np.cos(th), 100 * np.sin(th)], n=64)
    >>> small = surprisal(np.c_[2 * np.cos(th), np.sin(th)], n=64)
    >>> bool(np.allclose(big.surprisal, small.surprisal, rtol=0, atol=1e-9)), big.params["length_unit"]
    (True, 'sample')
    """
    if not isinstance(model, str) or model not in MODELS:
        raise InputError(f"unknown model {model!r}; expected one of {', '.join(MODELS)}")
    if not isinstance(length_unit, str) or length_unit not in LENGTH_UNITS:
        raise InputError(f"unknown length_unit {length_unit!r}; expected one of {', '.join(LENGTH_UNITS)}")
    bits = check_flag(bits, "bits")
    if prominence is not None:
        prominence = as_number(prominence, "prominence", ge=0)
    b = None if b is None else as_number(b, "b", ge=0)
    b = (1.0 if model == "paper" else 4.0) if b is None else b
    A = as_number(A, "A", gt=0)
    c = contour if isinstance(contour, Contour) else Contour(contour)
    if n is None and spacing is None:
        n = 100
    r = c.resample(n=n, spacing=spacing)
    n = r.n
    L = c.perimeter
    if c.closed:
        ds = L / n
        s = np.arange(n) * ds
    else:
        ds = L / (n - 1)
        s = np.arange(n) * ds
    a = r.turning_angles()
    k = a / ds
    unit = length_scale(length_unit, ds, L, c.area if c.closed and length_unit == "radius" else None)
    if model == "paper":
        u = _paper(a, ds / unit, n, A, b, c.closed, bits)
    else:
        u = _vonmises(a, n, b, c.closed, bits)
    inner = u if c.closed else u[1:-1]  # an open curve's ends have no turning angle (NaN)
    if not np.isfinite(inner).all():
        raise InputError(f"b: the surprisal overflows: b*ds^2 = {b:.3g} * {ds / unit:.3g}^2 in length_unit "
                         f"{length_unit!r}; use a smaller b, another length_unit or a rescaled contour")
    floor = noise_prominence({"model": model, "n": n, "b": b, "ds_in_unit": ds / unit, "bits": bits})
    peaks, _ = find_peaks(u, closed=c.closed, prominence=prominence, floor=floor)
    params = dict(
        model=model,
        n=int(n),
        ds=float(ds),
        length=float(L),
        length_unit=length_unit,
        unit_px=unit,
        ds_in_unit=float(ds / unit),
        A=float(A) if model == "paper" else None,
        b=float(b),
        closed=c.closed,
        bits=bool(bits),
        units="bits" if bits else "nats",
        prominence=None if prominence is None else float(prominence),
    )
    return SurprisalResult(r, s, s / L, a, k, u, peaks, params)


def surprisal_from_points(points, model="paper", A=0.25, b=None, closed=True, bits=False,
                          length_unit=DEFAULT_LENGTH_UNIT):
    """Surprisal at the given points as they are (no resampling).

    The fast path for large, already equally spaced contours: one pass of
    turning angles and a cosine. ``n`` is the number of points and ``ds`` the
    mean spacing.

    Parameters
    ----------
    points : (N, 2) array_like
        ``(x, y)`` in image pixels, counter-clockwise on the screen if closed.
    model, A, b, closed, bits, length_unit
        As in :func:`surprisal`.

    Returns
    -------
    (N,) ndarray

    Raises
    ------
    InputError
        `points` not an (N, 2) array of finite numbers with N >= 3, or a
        parameter out of range or of the wrong type (see :func:`surprisal`).
    """
    if not isinstance(length_unit, str) or length_unit not in LENGTH_UNITS:
        raise InputError(f"unknown length_unit {length_unit!r}; expected one of {', '.join(LENGTH_UNITS)}")
    if not isinstance(model, str) or model not in MODELS:
        raise InputError(f"unknown model {model!r}; expected one of {', '.join(MODELS)}")
    closed, bits = check_flag(closed, "closed"), check_flag(bits, "bits")
    b = None if b is None else as_number(b, "b", ge=0)
    A = as_number(A, "A", gt=0)
    p = check_points(points, "points", min_points=3)
    n = len(p)
    a = unchecked_turning_angles(p, closed)
    if model == "paper":
        d = np.diff(p, axis=0)
        L = np.hypot(d[:, 0], d[:, 1]).sum()
        if closed:
            L += float(np.hypot(*(p[0] - p[-1])))
        if not L > 0:
            raise InputError("points: all points are equal; the curve has no length")
        ds = L / n if closed else L / (n - 1)
        # the area is only computed when the unit needs it (a pass over every point)
        area = Contour(p, closed, orient=False).area if length_unit == "radius" and closed else None
        ds = ds / length_scale(length_unit, ds, L, area)
        return _paper(a, ds, n, A, 1.0 if b is None else b, closed, bits)
    return _vonmises(a, n, 4.0 if b is None else b, closed, bits)
