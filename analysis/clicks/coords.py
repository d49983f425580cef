"""Click coordinates: parsing them and converting them to image pixels.

Split from :mod:`attneave.analysis.clicks.read` (which re-exports every name
here): that module reads the files, this one understands the numbers.

Coordinate systems
------------------
Analysis works in image pixels with OpenCV's convention: ``(x, y)`` with
x = column, y = row, y down, and pixel centres at integer coordinates, so the
image of width W covers x in [-0.5, W - 0.5] and its centre is at
``((W - 1) / 2, (H - 1) / 2)``.

``image`` (default)
    Clicks are in pixels of the image as it was shown, origin at the top-left,
    y down, pixel centres at integers. When it was shown magnified by
    ``scale`` (shown width = ``scale * W``), the shown pixel edge coordinate
    ``x + 0.5`` is divided by ``scale``::

        x_image = (x + 0.5) / scale - 0.5

``centered``
    PsychoPy's ``'pix'`` units with the image drawn at the centre of the
    window: origin at the image centre, y up, one unit per screen pixel. The
    image centre lies at ``(W / 2, H / 2)`` in edge coordinates, which is
    ``((W - 1) / 2, (H - 1) / 2)`` with pixel centres at integers, so::

        x_image = (W - 1) / 2 + X / scale
        y_image = (H - 1) / 2 - Y / scale

    A click at the window centre maps to the image centre; one at
    ``(-W/2, +H/2) * scale`` (the top-left corner of the drawn image) maps to
    ``(-0.5, -0.5)``, the outer corner of the top-left pixel.

``pix``
    The same as ``centered``, under PsychoPy's name.

``height`` and ``norm``
    PsychoPy's window units, with the image drawn at the window centre, y up.
    They need the window size ``(Ww, Hw)`` in pixels (``--window-size``):
    ``height`` has 1 unit = the window height, so ``X = Xh * Hw``,
    ``Y = Yh * Hw`` pixels; ``norm`` runs from -1 to 1 over each window axis,
    so ``X = Xn * Ww / 2``, ``Y = Yn * Hw / 2``. Then as ``centered``; the
    scale of an image drawn ``size`` units high (``height`` units) is
    ``size * Hw / H``.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import parse_number

__all__ = [
    "COORDS",
    "WINDOW_UNITS",
    "MAX_COORDINATE",
    "SCALE_RANGE",
    "MISSING_TOKENS",
    "parse_coordinates",
    "to_image_coords",
    "from_image_coords",
    "parse_window_size",
    "window_units_to_pixels",
]

COORDS = ("image", "centered", "pix", "height", "norm")
#: Largest |coordinate| of a click; a larger one is excluded (reason coordinate_out_of_range).
MAX_COORDINATE = 1e12
#: Bounds of --scale (shown size / image size).
SCALE_RANGE = (1e-6, 1e6)
#: Units relative to the window, which need the window's size in pixels.
WINDOW_UNITS = ("height", "norm")
# spellings of "no value" that spreadsheets and R/pandas write
MISSING_TOKENS = frozenset({"", "nan", "na", "n/a", "null", "none", "<na>"})


def parse_coordinates(values):
    """Parse a text column of coordinates.

    Parameters
    ----------
    values : sequence of str
        Numbers as text; a one-element list (``'[0.109]'``, as PsychoPy
        writes) is its number, an empty list ``'[]'`` is missing.

    Returns
    -------
    numbers : (M,) ndarray of float
        NaN where the value is missing or not a finite number.
    problem : (M,) ndarray of object
        ``''`` for a good value, ``'missing_coordinate'`` for an empty or
        NA-like value (see `MISSING_TOKENS`) or an empty list,
        ``'coordinate_list'`` for a list of several values (that
        :func:`attneave.analysis.clicks.read.read_clicks` could not pair with the other coordinate's),
        ``'non_numeric_coordinate'`` for text or an infinite value,
        ``'coordinate_out_of_range'`` beyond +-:data:`MAX_COORDINATE`.

    Examples
    --------
    >>> v, p = parse_coordinates(["1.5", "[0.25]", "[]", "[1, 2]", "abc"])
    >>> v.tolist()[:2], p.tolist()
    ([1.5, 0.25], ['', '', 'missing_coordinate', 'coordinate_list', 'non_numeric_coordinate'])
    """
    import pandas as pd

    s = pd.Series(values, dtype=object)
    num = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float, copy=True)
    problem = np.full(len(s), "", dtype=object)
    bad = ~np.isfinite(num)
    if bad.any():
        # only the rows that failed are looked at as text (few, usually)
        idx = np.flatnonzero(bad)
        raw = s.iloc[idx].astype(str).str.strip()
        items = raw.str.extract(r"^\[\s*([^,\]]*?)\s*\]$")[0]  # the element of a one-element list
        one = items.notna().to_numpy() & (items.fillna("") != "").to_numpy()
        if one.any():
            num[idx[one]] = pd.to_numeric(items[one], errors="coerce").to_numpy(dtype=float)
        still = ~np.isfinite(num[idx])
        missing = (s.iloc[idx].isna().to_numpy() | raw.str.lower().isin(MISSING_TOKENS).to_numpy()
                   | raw.str.fullmatch(r"\[\s*\]").to_numpy(dtype=bool))
        listed = raw.str.fullmatch(r"\[.*,.*\]").to_numpy(dtype=bool)
        problem[idx[still & missing]] = "missing_coordinate"
        problem[idx[still & ~missing & listed]] = "coordinate_list"
        problem[idx[still & ~missing & ~listed]] = "non_numeric_coordinate"
        num[idx[still]] = np.nan
    # no screen or image has a coordinate near 1e12; beyond it squares and sums lose meaning
    far = np.abs(num) > MAX_COORDINATE
    if far.any():
        problem[far] = "coordinate_out_of_range"
        num[far] = np.nan
    return num, problem


def parse_window_size(spec):
    """Parse ``--window-size W,H`` (pixels) -> ``(W, H)`` floats.

    Examples
    --------
    >>> parse_window_size("1920,1080")
    (1920.0, 1080.0)
    """
    if spec is None:
        return None
    parts = spec if isinstance(spec, (tuple, list)) else str(spec).replace("x", ",").split(",")
    if len(parts) != 2:
        raise InputError(f"--window-size: expected W,H in pixels (e.g. 1920,1080), got {spec!r}")
    w, h = (parse_number(v, "--window-size", gt=0, le=1e6) for v in parts)
    return w, h


def _check(coords, scale, window):
    if coords not in COORDS:
        raise InputError(f"--coords must be one of {', '.join(COORDS)}, got {coords!r}")
    if not (np.isfinite(scale) and SCALE_RANGE[0] <= scale <= SCALE_RANGE[1]):
        raise InputError(f"--scale must be a positive number from {SCALE_RANGE[0]:g} to {SCALE_RANGE[1]:g}, "
                         f"got {scale!r}")
    if coords in WINDOW_UNITS and window is None:
        raise InputError(f"--coords {coords} needs --window-size W,H (the window's size in pixels)")


def _window_factors(coords, window):
    """Screen pixels per unit of `coords` along x and y (y up)."""
    w, h = parse_window_size(window)
    return (h, h) if coords == "height" else (w / 2.0, h / 2.0)


def to_image_coords(x, y, width, height, coords="image", scale=1.0, window=None):
    """Convert click coordinates to image pixels (y down, pixel centres at integers).

    Parameters
    ----------
    x, y : array_like
        Click coordinates in the system `coords`.
    width, height : array_like
        Image size in pixels (per click, or scalars).
    coords : {'image', 'centered', 'pix', 'height', 'norm'}
        See the module docstring.
    scale : float
        Shown size / image size (> 0).
    window : (float, float), optional
        Window size ``(W, H)`` in pixels; needed for 'height' and 'norm'.

    Returns
    -------
    (x_image, y_image) : tuple of ndarray
        In image pixels (x = column, y = row, y down).

    Examples
    --------
    >>> [float(v) for v in to_image_coords(0.0, 0.0, 512, 512, "centered")]
    [255.5, 255.5]
    >>> [float(v) for v in to_image_coords(-256.0, 256.0, 512, 512, "centered")]
    [-0.5, -0.5]
    >>> [float(v) for v in to_image_coords(-0.25, 0.25, 512, 512, "height", window=(1920, 1024))]
    [-0.5, -0.5]
    """
    _check(coords, scale, window)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) / scale - 0.5, (y + 0.5) / scale - 0.5
    if coords in WINDOW_UNITS:
        fx, fy = _window_factors(coords, window)
        x, y = x * fx, y * fy
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    return cx + x / scale, cy - y / scale


def from_image_coords(x, y, width, height, coords="image", scale=1.0, window=None):
    """Inverse of :func:`to_image_coords`: image pixels to `coords`.

    Examples
    --------
    >>> [float(v) for v in from_image_coords(255.5, 255.5, 512, 512, "centered")]
    [0.0, 0.0]
    """
    _check(coords, scale, window)
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if coords == "image":
        if scale == 1.0:
            return x.copy(), y.copy()
        return (x + 0.5) * scale - 0.5, (y + 0.5) * scale - 0.5
    cx = (np.asarray(width, dtype=float) - 1.0) / 2.0
    cy = (np.asarray(height, dtype=float) - 1.0) / 2.0
    xs, ys = (x - cx) * scale, (cy - y) * scale
    if coords in WINDOW_UNITS:
        fx, fy = _window_factors(coords, window)
        xs, ys = xs / fx, ys / fy
    return xs, ys


def window_units_to_pixels(clicks, coords, window):
    """Clicks in PsychoPy's 'height' or 'norm' units -> 'centered' screen pixels.

    The analysis maps 'centered' pixels; this converts the other two window
    units to them (see the module docstring), keeping the values as written
    in columns ``x_<coords>`` and ``y_<coords>``.

    Parameters
    ----------
    clicks : pandas.DataFrame
        From :func:`attneave.analysis.clicks.read.read_clicks`.
    coords : {'height', 'norm'}
    window : str or (float, float)
        Window size ``W,H`` in pixels.

    Returns
    -------
    pandas.DataFrame
        A copy, x and y in pixels from the window centre, y up.
    """
    _check(coords, 1.0, window)
    fx, fy = _window_factors(coords, window)
    x, px = parse_coordinates(clicks["x"].to_numpy())
    y, py = parse_coordinates(clicks["y"].to_numpy())
    out = clicks.copy()
    keep = {c: f"input_{c}" for c in (f"x_{coords}", f"y_{coords}") if c in out.columns}
    out = out.rename(columns=keep)
    out.insert(out.columns.get_loc("y") + 1, f"x_{coords}", clicks["x"].to_numpy())
    out.insert(out.columns.get_loc(f"x_{coords}") + 1, f"y_{coords}", clicks["y"].to_numpy())
    # a value that is not a number stays as written, so that its reason is the same
    out["x"] = np.where(px == "", x * fx, clicks["x"].to_numpy(dtype=object))
    out["y"] = np.where(py == "", y * fy, clicks["y"].to_numpy(dtype=object))
    return out
