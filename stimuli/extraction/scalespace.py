"""The scale-space description of a closed contour: smoothing at the shape's own
scale, Gaussian-derivative curvature, surprisal and curvature extrema.

Points are ``(x, y)`` image pixels (x = column, y = row, y down).

References
----------
.. [1] Mokhtarian, F., & Mackworth, A. K. (1992). A theory of multiscale,
       curvature-based shape representation for planar curves. IEEE PAMI
       14(8), 789-805.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.geometry.polyline import gaussian_curvature
from attneave.stimuli.validate import as_number, check_flag

__all__ = ["SIGMA_FRACTION", "MIN_SIGMA", "MAX_SIGMA_FRACTION", "ContourInfo", "default_sigma", "smooth", "contour_curvature",
           "describe", "curvature_peaks", "fourier_smooth"]

#: Default curvature/smoothing scale as a fraction of the contour's perimeter.
SIGMA_FRACTION = 0.01
#: Smallest default smoothing scale, in pixels (pixel noise sets this floor).
MIN_SIGMA = 1.0
#: Largest smoothing scale given, as a fraction of the perimeter: beyond it
#: the periodic Gaussian shrinks the outline to a point (its first harmonic
#: by a factor under exp(-pi**2 / 2) = 0.007).
MAX_SIGMA_FRACTION = 0.5
#: Most points :func:`smooth` returns (a spacing that asks for more is refused).
MAX_SMOOTH_POINTS = 10_000_000

def fourier_smooth(q, sigma, length):
    """Equally spaced closed points `q` (perimeter `length`) smoothed by a periodic Gaussian of `sigma` px."""
    n = len(q)
    w = 2 * np.pi * np.fft.fftfreq(n, d=length / n)
    g = np.exp(-0.5 * (w * sigma) ** 2)
    z = np.fft.ifft(np.fft.fft(q[:, 0] + 1j * q[:, 1]) * g)
    return np.column_stack([z.real, z.imag])


def default_sigma(contour, fraction=SIGMA_FRACTION, minimum=MIN_SIGMA):
    """The default smoothing/curvature scale of a contour, in px of arc length.

    ``max(fraction * perimeter, minimum)``: 1 % of the perimeter, so the
    scale follows the shape (the same object photographed twice as large is
    smoothed at twice the pixel scale, i.e. identically), and never below
    1 px, the scale of pixel noise.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        ``(x, y)`` image pixels (y down).
    fraction : float
        Share of the perimeter, in ``(0, MAX_SIGMA_FRACTION]`` (default
        :data:`SIGMA_FRACTION`, 0.01).
    minimum : float
        Smallest scale in px, >= 0 (default :data:`MIN_SIGMA`, 1 px).

    Returns
    -------
    float
        The scale in px of arc length.

    Raises
    ------
    InputError
        `fraction` or `minimum` out of range or not a number; a bad contour.

    Examples
    --------
    >>> default_sigma([[0, 0], [100, 0], [100, 100], [0, 100]])
    4.0
    """
    fraction = as_number(fraction, "fraction", gt=0, le=MAX_SIGMA_FRACTION)
    minimum = as_number(minimum, "minimum", ge=0)
    c = contour if isinstance(contour, Contour) else Contour(contour)
    return float(max(fraction * c.perimeter, minimum))


def _resolve_sigma(c, sigma):
    if sigma is None:
        return default_sigma(c)
    sigma = as_number(sigma, "sigma", gt=0)
    if sigma > MAX_SIGMA_FRACTION * c.perimeter:
        raise InputError(f"sigma (--sigma) {sigma:g} px is over {MAX_SIGMA_FRACTION:g} times this outline's perimeter "
                         f"({c.perimeter:.4g} px): smoothing at that scale shrinks it to a point; give a smaller sigma")
    return sigma


def smooth(contour, sigma=None, spacing=None):
    """A closed contour smoothed along its arc by a periodic Gaussian.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    sigma : float, optional
        Scale in px of arc length; default :func:`default_sigma`.
    spacing : float, optional
        Spacing of the returned points in px (default: about 1 px, and at
        most ``sigma / 4``); > 0, and giving at most
        :data:`MAX_SMOOTH_POINTS` points.

    Returns
    -------
    Contour
        Equally spaced (in the input's arc length) points of the smoothed
        curve, starting at the smoothed first point, counter-clockwise on the
        screen. A circle of radius R shrinks by about ``sigma**2 / (2 R)``.

    Raises
    ------
    InputError
        An open or bad contour, `sigma` or `spacing` not a number > 0 (or
        `sigma` over half the perimeter, `spacing` asking for more than
        :data:`MAX_SMOOTH_POINTS` points).
    """
    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("smoothing is for closed contours")
    sigma = _resolve_sigma(c, sigma)
    if spacing is None:
        spacing = min(1.0, sigma / 4)
    else:
        spacing = as_number(spacing, "spacing", gt=0)
        if c.perimeter / spacing > MAX_SMOOTH_POINTS:
            raise InputError(f"spacing {spacing:g} px gives {c.perimeter / spacing:.3g} points on this outline "
                             f"(perimeter {c.perimeter:.4g} px); at most {MAX_SMOOTH_POINTS:,}")
    m = max(int(np.ceil(c.perimeter / spacing)), 16)
    q = c.resample(n=m).points
    return Contour(fourier_smooth(q, sigma, c.perimeter), orient=False, name=c.name)


def contour_curvature(contour, sigma=None):
    """Curvature (1/px, positive where convex) at a contour's own points.

    Gaussian-derivative curvature at scale `sigma` (default
    :func:`default_sigma`, 1 % of the perimeter), computed on the contour
    resampled at equal arc-length steps and read back at each point's arc
    position (``Contour.curvature(method='gaussian')``).

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        ``(x, y)`` image pixels (y down); closed unless a `Contour` says otherwise.
    sigma : float, optional
        Scale in px of arc length, > 0 and at most
        ``MAX_SIGMA_FRACTION * perimeter`` (default :func:`default_sigma`).

    Returns
    -------
    (N,) ndarray
        Curvature in 1/px at each point of `contour`, positive where the
        contour is convex.

    Raises
    ------
    InputError
        A bad contour, or `sigma` not a number in range.
    """
    c = contour if isinstance(contour, Contour) else Contour(contour)
    return c.curvature(method="gaussian", sigma=_resolve_sigma(c, sigma))


@dataclass
class ContourInfo:
    """Curvature and surprisal of an extracted contour, with its parameters.

    Attributes
    ----------
    contour : Contour
        The contour as given (e.g. extracted), image pixels, y down.
    smoothed : Contour
        It smoothed at `sigma` (about 1 px spacing).
    sigma : float
        The smoothing/curvature scale in px of arc length.
    surprisal : attneave.stimuli.geometry.information.SurprisalResult
        Surprisal at `n` equally spaced points of the smoothed contour
        (its ``table()`` has the columns of ``attneave surprisal``).
    curvature : ndarray
        Gaussian-derivative curvature at scale `sigma` at the same points
        (1/px, positive where convex).
    params : dict
        sigma, sigma_fraction (None if sigma was given), and the surprisal
        parameters (model, n, ds, length, A, b, ...).
    """

    contour: Contour
    smoothed: Contour
    sigma: float
    surprisal: object
    curvature: np.ndarray
    params: dict = field(default_factory=dict)


def describe(contour, n=None, spacing=None, sigma=None, model="paper", A=0.25, b=None, bits=False,
             prominence=None, length_unit=None):
    """Smooth a closed contour at its own scale, then curvature and surprisal.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    n, spacing : optional
        Sampling of the surprisal (default ``n=100``); see
        :func:`attneave.stimuli.geometry.information.surprisal`.
    sigma : float, optional
        Smoothing scale in px of arc length (default 1 % of the perimeter,
        at least 1 px).
    model, A, b, bits, length_unit
        As in :func:`attneave.stimuli.geometry.information.surprisal` (`length_unit`
        None: its default).
    prominence : float, optional
        Smallest prominence of a surprisal peak. Default: 5 % of the
        surprisal's range or of the surprisal step from the mean turn
        ``2 pi / n`` to twice it, whichever is larger, so that a circle's
        pixel noise yields no peaks (as :func:`curvature_peaks`).

    Returns
    -------
    ContourInfo
    """
    from attneave.stimuli.geometry.information import surprisal

    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("describe() is for closed contours")
    s = _resolve_sigma(c, sigma)
    q = c.resample(n=max(int(np.ceil(c.perimeter / min(1.0, s / 4))), 16)).points
    sm = Contour(fourier_smooth(q, s, c.perimeter), orient=False, name=c.name)
    unit = {} if length_unit is None else {"length_unit": length_unit}
    res = surprisal(sm, n=n, spacing=spacing, model=model, A=A, b=b, bits=bits, prominence=prominence, **unit)
    if prominence is None:
        res = _with_default_prominence(res, model, A, bits)
    # the Gaussian-derivative curvature of the same samples is the smoothed
    # curve's curvature; read it at the surprisal's arc positions
    k = gaussian_curvature(q, s)
    t_sm = sm.t()
    kk = np.interp(res.t, np.append(t_sm, 1.0), np.append(k, k[0]))
    params = dict(sigma=s, sigma_fraction=SIGMA_FRACTION if sigma is None else None, **res.params)
    return ContourInfo(c, sm, s, res, kk, params)


def _with_default_prominence(res, model, A, bits):
    """Peaks again with prominence 5 % of max(range of u, u(2 mu) - u(mu)), mu = 2 pi / n."""
    import dataclasses

    from attneave.stimuli.geometry.information import find_peaks, surprisal_paper, surprisal_vonmises

    n = res.params["n"]
    mu = 2 * np.pi / n
    if model == "paper":
        ref = surprisal_paper(np.array([mu, 2 * mu]), res.params["ds_in_unit"], n, A=A, b=res.params["b"], bits=bits)
    else:
        ref = surprisal_vonmises(np.array([mu, 2 * mu]), n, b=res.params["b"], bits=bits)
    prominence = 0.05 * max(float(np.ptp(res.surprisal)), float(abs(ref[1] - ref[0])))
    peaks, _ = find_peaks(res.surprisal, closed=True, prominence=prominence)
    return dataclasses.replace(res, peaks=peaks, params={**res.params, "prominence": prominence})


def curvature_peaks(contour, sigma=None, prominence=None, minima=False):
    """Curvature maxima (or minima) of a closed contour, located between samples.

    Parameters
    ----------
    contour : Contour or (N, 2) array_like
        Closed, ``(x, y)`` image pixels (y down).
    sigma : float, optional
        Curvature scale in px of arc length (default :func:`default_sigma`).
    prominence : float, optional
        Minimum prominence in 1/px. Default: 5 % of the curvature's range
        or of the mean curvature of a closed curve, ``2 pi / perimeter``,
        whichever is larger, so that a circle's pixel noise yields no
        extrema.
    minima : bool
        Find minima (the most concave places) instead of maxima.

    Returns
    -------
    dict
        ``t`` (arc positions in [0, 1) from the first point), ``s`` (px),
        ``points`` ((K, 2) ``(x, y)`` on the contour), ``curvature`` (1/px)
        and ``sigma``, ordered from the most extreme. Each extremum is the
        vertex of a parabola fitted to the curvature over +-sigma/2 around
        the best sample, so that its place is not limited by the sampling or
        by pixel noise on a flat maximum.
    """
    from attneave.stimuli.geometry.information import find_peaks

    minima = check_flag(minima, "minima")
    c = contour if isinstance(contour, Contour) else Contour(contour)
    if not c.closed:
        raise InputError("curvature_peaks() is for closed contours")
    s = _resolve_sigma(c, sigma)
    m = max(int(np.ceil(c.perimeter / min(1.0, s / 4))), 16)
    q = c.resample(n=m).points
    k = gaussian_curvature(q, s)
    sign = -1.0 if minima else 1.0
    if prominence is None:
        prominence = 0.05 * max(float(np.ptp(k)), 2 * np.pi / c.perimeter)
    idx, _ = find_peaks(sign * k, closed=True, prominence=prominence)
    ds = c.perimeter / m
    half = int(np.clip(round(s / ds), 2, m // 4))
    off = np.arange(-half, half + 1)
    pos = []
    for i in idx:
        y = sign * k[(i + off) % m]
        a2, a1, _a0 = np.polyfit(off.astype(float), y, 2)
        d = -a1 / (2 * a2) if a2 < 0 else 0.0
        pos.append(i + float(np.clip(d, -half, half)))
    pos = np.mod(np.asarray(pos, float), m)
    t = pos / m
    kv = np.interp(pos, np.arange(m + 1), np.append(k, k[0]))
    return dict(t=t, s=t * c.perimeter, points=c.point_at(t), curvature=kv, sigma=s, prominence=float(prominence))
