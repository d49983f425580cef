"""Shape generators: random polygons, radial-frequency patterns, Fourier shapes, ...

Every generator takes its randomness from `rng`: a `numpy.random.Generator`
(used as it is) or a non-negative integer seed (``numpy.random.default_rng(seed)``);
None and other objects are refused (:func:`attneave.stimuli.validate.as_rng`). Each returns ``(contour, params)``: a closed, simple `Contour` and a dict of
every resolved parameter (JSON-serialisable), as stimupy returns its
parameters with its images.

Coordinates are ``(x, y)`` floats with y pointing DOWN, as in image pixels,
but in the generator's own units and around its own centre
(``params["centre"]``): grid cells for the Attneave polygons, pixels of
radius for the polar shapes (which are centred on ``(0, 0)``). Polar angles
run counter-clockwise *as seen on the screen*: a polar point is
``(r cos(theta), -r sin(theta))``. :mod:`attneave.stimuli.batch.recipes` places a shape on an
image canvas.

Simplicity: every contour is checked with `Contour.is_simple`. Polar shapes
whose radius stays positive are star-shaped about the centre and so simple by
construction; generators whose output can cross itself (Attneave polygons
and their curved versions, elliptic Fourier shapes) draw again from the same
`Generator` until they get a simple curve, up to ``max_tries`` draws, so the
result is still a deterministic function of the seed. The number of draws
used is recorded as ``params["tries"]``.

Sampling. A periodic shape sampled at `n` points is refused when `n` gives
fewer than 4 points per cycle of its fastest component (:func:`check_sampling`):
below that the samples alias (an RF pattern of frequency 8 at 16 points is a
perfect circle). `n` is at most :data:`MAX_POINTS`, and a harmonic sum at most
:data:`MAX_TERMS` terms (points times harmonics).
"""

from __future__ import annotations

import math

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.shapes._limits import MAX_POINTS, MAX_TERMS
from attneave.stimuli.shapes.attneave import SMOOTH_METHODS, attneave_curved, attneave_polygon, smooth_closed
from attneave.stimuli.shapes.from_csv import contour_from_csv  # re-exported: this module is its public home
from attneave.stimuli.validate import as_int, as_number, as_rng

__all__ = [
    "attneave_polygon",
    "attneave_curved",
    "smooth_closed",
    "radial_frequency",
    "radial_frequency_radius",
    "fourier_shape",
    "superformula",
    "superformula_radius",
    "blob",
    "contour_from_csv",
    "SMOOTH_METHODS",
    "MAX_POINTS",
    "MAX_TERMS",
    "check_sampling",
]

#: Rows of the (n, harmonics) cosine and sine tables computed at once.
_BLOCK_TERMS = 1 << 20

# --------------------------------------------------------------------------- helpers


def _polar(r, theta):
    """Polar to (x, y) with y down and theta counter-clockwise on the screen."""
    return np.column_stack([r * np.cos(theta), -r * np.sin(theta)])


def _mv(m, v):
    """Matrix times vector by a plain numpy sum: the same bits whatever BLAS
    and thread count (files must be byte-identical across workers)."""
    return (m * v[None, :]).sum(axis=1)


def _angles(n):
    return 2.0 * np.pi * np.arange(n) / n


def _check_n(n, name="n"):
    return as_int(n, name, lo=8, hi=MAX_POINTS)


def check_sampling(n, cycles, what, param):
    """Refuse a sampling that aliases: fewer than 4 of `n` points per cycle.

    Parameters
    ----------
    n : int
        Points per revolution.
    cycles : float
        Cycles per revolution of the fastest component (a radial frequency,
        the highest harmonic, the superformula's `m`).
    what, param : str
        The component, and the parameter to lower, for the message.

    Raises
    ------
    InputError
        Naming `n` when ``n < 4 * cycles``.

    Examples
    --------
    >>> check_sampling(16, 8, "radial frequency 8", "frequency")
    Traceback (most recent call last):
    ...
    attneave.stimuli.errors.InputError: n: 16 points alias radial frequency 8 (at least 4 points per cycle are needed, n >= 32); raise n or lower frequency
    """
    need = 4.0 * float(cycles)
    if n < need:
        raise InputError(f"n: {n} points alias {what} (at least 4 points per cycle are needed, n >= {math.ceil(need)}); "
                         f"raise n or lower {param}")


def _check_terms(n, k, param):
    if n * k > MAX_TERMS:
        raise InputError(f"{param}: {k} harmonics at {n} points is {n * k:.3g} terms, more than {MAX_TERMS:.0e}; "
                         f"lower {param} or n")


def _trig_sums(th, k, coefs):
    """``_mv(cos(outer(th, k)), a)`` or, for a name starting 's', the same with sin,
    for each ``name: a`` of `coefs` (a dict of the results).

    The tables are built a block of rows at a time, so memory stays bounded;
    each row's sum is the one a single table gives, bit for bit.
    """
    n = len(th)
    step = max(1, _BLOCK_TERMS // max(1, len(k)))
    out = {name: np.empty(n) for name in coefs}
    for i in range(0, n, step):
        arg = np.outer(th[i : i + step], k)
        tables = {"c": np.cos(arg), "s": np.sin(arg)}
        for name, a in coefs.items():
            out[name][i : i + step] = _mv(tables[name[0]], a)
    return out


# ------------------------------------------------------------ radial frequency


def _as_list(value, name):
    if value is None:
        return None
    if np.ndim(value) == 0:
        return [value]
    return list(value)


def radial_frequency_radius(theta, r0, frequencies, amplitudes, phases):
    """``r0 * (1 + sum_k A_k sin(w_k theta + phi_k))`` at angles `theta` (radians)."""
    theta = np.asarray(theta, dtype=float)
    s = np.zeros_like(theta)
    for w, a, ph in zip(frequencies, amplitudes, phases):
        s = s + a * np.sin(w * theta + ph)
    return r0 * (1.0 + s)


def radial_frequency(rng=None, r0=100.0, frequency=5, amplitude=0.1, phase=None, n=1024):
    """A radial-frequency (RF) pattern (Wilkinson, Wilson & Habak, 1998).

    ``r(theta) = r0 * (1 + sum_k A_k sin(w_k theta + phi_k))``, sampled at `n`
    equally spaced polar angles ``theta_j = 2 pi j / n``. The point at angle
    theta is ``(r cos(theta), -r sin(theta))``: theta runs counter-clockwise
    on the screen from the +x axis, and the pattern is centred on (0, 0).

    Parameters
    ----------
    rng : numpy.random.Generator or int, optional
        Draws the phases when `phase` is None (uniform in [0, 2 pi)); an
        integer is a seed. Needed only then.
    r0 : float
        Mean radius (> 0), in the output's units (pixels when placed natively).
    frequency : int or list of int
        Radial frequencies w_k (cycles per revolution, >= 1).
    amplitude : float or list of float
        Amplitudes A_k (>= 0), one per frequency; their sum must be < 1 so
        that the radius stays positive (the pattern is then star-shaped,
        hence simple).
    phase : float or list of float, optional
        Phases phi_k in radians; drawn from `rng` when None.
    n : int
        Number of points, in [8, :data:`MAX_POINTS`] and at least 4 per
        cycle of the highest frequency (fewer alias: see
        :func:`check_sampling`).

    Returns
    -------
    contour : Contour
    params : dict
        ``r0, frequency, amplitude, phase (lists), n, centre``.

    Raises
    ------
    InputError
        A bad parameter, naming it; `n` too small for the highest frequency.

    References
    ----------
    .. [1] Wilkinson, F., Wilson, H. R., & Habak, C. (1998). Detection and
           recognition of radial frequency patterns. Vision Research 38(22),
           3555-3568.

    Examples
    --------
    >>> c, p = radial_frequency(r0=100, frequency=3, amplitude=0.2, phase=0.0, n=360)
    >>> float(np.hypot(*c.points[0])), p["frequency"]
    (100.0, [3])
    """
    r0 = as_number(r0, "r0", gt=0)
    freqs = [as_int(f, f"frequency[{i}]", lo=1) for i, f in enumerate(_as_list(frequency, "frequency"))]
    amps = [as_number(a, f"amplitude[{i}]", ge=0) for i, a in enumerate(_as_list(amplitude, "amplitude"))]
    if len(freqs) == 0:
        raise InputError("frequency: give at least one radial frequency")
    if len(amps) != len(freqs):
        raise InputError(f"amplitude: give one amplitude per frequency ({len(freqs)}), got {len(amps)}")
    if sum(amps) >= 1:
        raise InputError(f"amplitude: the amplitudes must sum to < 1 so the radius stays positive, got {sum(amps):g}")
    n = _check_n(n)
    check_sampling(n, max(freqs), f"radial frequency {max(freqs)}", "frequency")
    _check_terms(n, len(freqs), "frequency")
    if phase is None:
        phases = [float(x) for x in as_rng(rng).uniform(0.0, 2 * np.pi, size=len(freqs))]
    else:
        phases = [as_number(x, f"phase[{i}]") for i, x in enumerate(_as_list(phase, "phase"))]
        if len(phases) != len(freqs):
            raise InputError(f"phase: give one phase per frequency ({len(freqs)}), got {len(phases)}")
    th = _angles(n)
    r = radial_frequency_radius(th, r0, freqs, amps, phases)
    c = Contour(_polar(r, th), simple=True)
    return c, dict(r0=r0, frequency=freqs, amplitude=amps, phase=phases, n=n, centre=[0.0, 0.0])


# ------------------------------------------------------------ Fourier shapes


def fourier_shape(rng, kind="radial", r0=100.0, amplitude=0.1, falloff=1.5, harmonics=8, n=1024, max_tries=100):
    """A random Fourier shape whose harmonic amplitudes fall off as a power law.

    Parameters
    ----------
    rng : numpy.random.Generator or int
        The generator, or an integer seed.
    kind : {'radial', 'elliptic'}
        ``'radial'``: ``r(theta) = r0 * (1 + sum_{k=2}^{K} a_k cos(k theta) +
        b_k sin(k theta))`` with ``a_k, b_k ~ N(0, (amplitude * k**-falloff)**2)``;
        draws whose radius dips below ``0.1 * r0`` are redrawn (the shape is
        then star-shaped, hence simple). ``'elliptic'``: the elliptic Fourier
        form (Kuhl & Giardina, 1982) ``x(t) = r0 cos t + sum_k (a_k cos kt +
        b_k sin kt)``, ``y(t) = -r0 sin t + sum_k (c_k cos kt + d_k sin kt)``
        with the four coefficients ``~ N(0, (r0 * amplitude * k**-falloff)**2)``;
        draws that cross themselves are redrawn.
    r0 : float
        Radius of the base circle (> 0).
    amplitude : float
        Standard deviation scale of the coefficients (>= 0).
    falloff : float
        Power-law exponent of the fall-off with harmonic number k (>= 0).
    harmonics : int
        Highest harmonic K (>= 2).
    n : int
        Number of points, equally spaced in theta (or t), in [8,
        :data:`MAX_POINTS`] and at least ``4 * harmonics`` (fewer alias);
        ``n * harmonics`` at most :data:`MAX_TERMS`.
    max_tries : int
        Draws before giving up.

    Returns
    -------
    contour : Contour
    params : dict
        The inputs, ``tries``, ``centre`` and the coefficients drawn:
        ``coefficients`` is a list of ``[k, a_k, b_k]`` (radial) or
        ``[k, a_k, b_k, c_k, d_k]`` (elliptic).

    References
    ----------
    .. [1] Zahn, C. T., & Roskies, R. Z. (1972). Fourier descriptors for plane
           closed curves. IEEE Transactions on Computers C-21(3), 269-281.
    .. [2] Kuhl, F. P., & Giardina, C. R. (1982). Elliptic Fourier features of
           a closed contour. Computer Graphics and Image Processing 18(3),
           236-258.
    """
    rng = as_rng(rng)
    if kind not in ("radial", "elliptic"):
        raise InputError(f"kind: expected 'radial' or 'elliptic', got {kind!r}")
    r0 = as_number(r0, "r0", gt=0)
    amplitude = as_number(amplitude, "amplitude", ge=0)
    falloff = as_number(falloff, "falloff", ge=0)
    K = as_int(harmonics, "harmonics", lo=2)
    n = _check_n(n)
    max_tries = as_int(max_tries, "max_tries", lo=1)
    check_sampling(n, K, f"harmonic {K}", "harmonics")
    _check_terms(n, K - 1, "harmonics")
    k = np.arange(2, K + 1)
    sd = amplitude * k.astype(float) ** -falloff
    th = _angles(n)
    for tries in range(1, max_tries + 1):
        if kind == "radial":
            a, b = rng.normal(size=(2, len(k))) * sd
            t = _trig_sums(th, k, {"ca": a, "sb": b})
            r = r0 * (1.0 + t["ca"] + t["sb"])
            if r.min() < 0.1 * r0:
                continue
            c = Contour(_polar(r, th))
            coef = np.column_stack([k, a, b])
        else:
            a, b, cc, d = rng.normal(size=(4, len(k))) * (r0 * sd)
            t = _trig_sums(th, k, {"ca": a, "sb": b, "cc": cc, "sd": d})
            x = r0 * np.cos(th) + t["ca"] + t["sb"]
            y = -r0 * np.sin(th) + t["cc"] + t["sd"]
            c = Contour(np.column_stack([x, y]))
            if not c.is_simple():
                continue
            coef = np.column_stack([k, a, b, cc, d])
        coefs = [[int(row[0])] + [float(v) for v in row[1:]] for row in coef]
        params = dict(kind=kind, r0=r0, amplitude=amplitude, falloff=falloff, harmonics=K, n=n,
                      max_tries=max_tries, tries=tries, coefficients=coefs, centre=[0.0, 0.0])
        return c, params
    raise InputError(f"fourier_shape: no simple {kind} shape in {max_tries} tries; lower the amplitude")


# ------------------------------------------------------------ superformula


def superformula_radius(phi, m, n1, n2, n3, a=1.0, b=1.0):
    """Gielis' superformula ``(|cos(m phi/4)/a|**n2 + |sin(m phi/4)/b|**n3) ** (-1/n1)``."""
    phi = np.asarray(phi, dtype=float)
    t = m * phi / 4.0
    return (np.abs(np.cos(t) / a) ** n2 + np.abs(np.sin(t) / b) ** n3) ** (-1.0 / n1)


def superformula(m=5, n1=2.0, n2=7.0, n3=7.0, a=1.0, b=1.0, scale=100.0, n=1024):
    """A closed curve from the superformula (Gielis, 2003).

    ``r(phi) = scale * (|cos(m phi / 4) / a|**n2 + |sin(m phi / 4) / b|**n3) ** (-1 / n1)``
    at `n` equally spaced angles, the point at phi being
    ``(r cos(phi), -r sin(phi))`` (counter-clockwise on the screen, centred on
    (0, 0)). With ``n1, n2, n3, a, b > 0`` the radius is finite and positive,
    so the curve is star-shaped and simple.

    Parameters
    ----------
    m : float
        Rotational symmetry (>= 0): m lobes per turn. The curve closes after
        one turn when m is an even integer, or an odd integer with ``a == b``
        and ``n2 == n3``.
    n1, n2, n3, a, b : float
        Shape exponents and axes (> 0).
    scale : float
        Multiplies the radius (> 0).
    n : int
        Number of points, in [8, :data:`MAX_POINTS`] and at least ``4 * m``
        (fewer alias: the lobes fall between the samples).

    Returns
    -------
    contour : Contour
    params : dict
        ``m, n1, n2, n3, a, b, scale, n, centre``.

    Raises
    ------
    InputError
        Parameters for which the curve does not close after one turn, or
        `n` too small for `m`.

    References
    ----------
    .. [1] Gielis, J. (2003). A generic geometric transformation that unifies
           a wide range of natural and abstract shapes. American Journal of
           Botany 90(3), 333-338.
    """
    m = as_number(m, "m", ge=0)
    n1, n2, n3, a, b = (as_number(v, name, gt=0) for v, name in zip((n1, n2, n3, a, b), ("n1", "n2", "n3", "a", "b")))
    scale = as_number(scale, "scale", gt=0)
    n = _check_n(n)
    check_sampling(n, m, f"{m:g} lobes (m)", "m")
    what = f"superformula(m={m:g}, n1={n1:g}, n2={n2:g}, n3={n3:g}, a={a:g}, b={b:g}, scale={scale:g})"
    # extreme exponents or axes overflow or underflow the float range: the radius is checked
    # below, so numpy's warnings would only repeat it (with a source line) before the error
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        # one turn closes only if r and its one-sided slopes agree at 0 and 2*pi
        probe = np.array([0.0, 1e-3, 2 * np.pi, 2 * np.pi + 1e-3])
        rp = superformula_radius(probe, m, n1, n2, n3, a, b)
        phi = _angles(n)
        r = scale * superformula_radius(phi, m, n1, n2, n3, a, b)
        pts = _polar(r, phi)
    bad = ~(np.isfinite(r) & (r > 0)) | ~np.isfinite(pts).all(axis=1)
    if bad.any():
        kind = "infinite or undefined" if not np.isfinite(r[bad]).all() else "zero"
        raise InputError(f"{what}: the radius is {kind} at {int(bad.sum())} of {n} angles (beyond the float "
                         "range); use exponents and axes nearer 1")
    if not np.allclose(rp[[0, 1]], rp[[2, 3]], rtol=1e-9, atol=0):
        raise InputError(
            f"m: the superformula with m={m:g} does not close after one turn; use an even integer m, "
            f"or an odd integer with a == b and n2 == n3"
        )
    try:
        c = Contour(pts, simple=True)
    except InputError as exc:
        raise InputError(f"{what}: {exc}") from None
    return c, dict(m=m, n1=n1, n2=n2, n3=n3, a=a, b=b, scale=scale, n=n, centre=[0.0, 0.0])


# ------------------------------------------------------------ smooth blobs


#: Largest RMS log-radius of :func:`blob`.
MAX_BLOB_SIGMA = 3.0


def blob(rng, r0=100.0, sigma=0.2, width=0.6, n=1024):
    """A smooth random blob: a circle whose log-radius is smoothed noise.

    ``log r(theta) = log r0 + g(theta)`` with g a periodic Gaussian random
    function of correlation width `width` (radians): harmonic k >= 2 gets a
    complex normal coefficient scaled by ``exp(-(k * width)**2 / 2)`` (the
    spectrum of white noise smoothed by a Gaussian of s.d. `width`), and g is
    scaled to root-mean-square `sigma`. Harmonics whose weight is below 1e-3
    are left out. The radius is positive, so the blob is star-shaped and
    simple.

    Parameters
    ----------
    rng : numpy.random.Generator or int
        The generator, or an integer seed.
    r0 : float
        Geometric-mean radius (> 0).
    sigma : float
        RMS of the log-radius, in [0, :data:`MAX_BLOB_SIGMA`] (0 gives a
        circle; 3 already lets the radius range over a factor of about 1e6).
    width : float
        Correlation width in radians (> 0); smaller is bumpier.
    n : int
        Number of points, equally spaced in theta, in [8, :data:`MAX_POINTS`];
        the harmonics used (up to ``n / 4``, so none aliases) times `n` at
        most :data:`MAX_TERMS`.

    Returns
    -------
    contour : Contour
    params : dict
        ``r0, sigma, width, n, centre, coefficients`` (``[k, re, im]`` as
        drawn, before the scaling to `sigma`).
    """
    rng = as_rng(rng)
    r0 = as_number(r0, "r0", gt=0)
    sigma = as_number(sigma, "sigma", ge=0, le=MAX_BLOB_SIGMA)
    width = as_number(width, "width", gt=0)
    n = _check_n(n)
    kmax = max(2, int(min(math.floor(math.sqrt(2 * math.log(1e3)) / width), n // 4)))
    _check_terms(n, kmax - 1, "width")
    k = np.arange(2, kmax + 1)
    z = rng.normal(size=(2, len(k)))
    coef = (z[0] + 1j * z[1]) * np.exp(-0.5 * (k * width) ** 2)
    th = _angles(n)
    t = _trig_sums(th, k, {"c": coef.real, "s": coef.imag})
    g = t["c"] - t["s"]
    rms = float(np.sqrt(np.mean(g**2)))
    g = g * (sigma / rms) if rms > 0 else g
    r = r0 * np.exp(g)
    c = Contour(_polar(r, th), simple=True)
    coefs = [[int(kk), float(a), float(b)] for kk, a, b in zip(k, z[0], z[1])]
    return c, dict(r0=r0, sigma=sigma, width=width, n=n, centre=[0.0, 0.0], coefficients=coefs)
