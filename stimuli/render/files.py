"""Image files: quantisation to 8 or 16 bits, PNG (atomic writes) and SVG in
the same coordinates as the contour files.

The SVG written by :func:`write_svg` places its shapes in a group with
``transform="translate(0.5 0.5)"``, because in SVG the centre of pixel ``j``
is at user unit ``j + 0.5``. Rasterised at one user unit per pixel it
matches the PNG.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import atomic_write
from attneave.stimuli.render.paint import colours, plain_colour
from attneave.stimuli.render.rings import as_rings, resolve_shape

# ---------------------------------------------------------------------------
# Output


def _check_unit(img, name="image"):
    a = np.asarray(img, dtype=float)
    if a.size:
        lo, hi = a.min(), a.max()  # NaN propagates into both
        if np.isnan(lo) or np.isnan(hi):
            raise InputError(f"{name}: contains NaN values")
        if lo < -1e-9 or hi > 1.0 + 1e-9:
            raise InputError(f"{name}: float values must lie in [0, 1], got [{lo:g}, {hi:g}]")
    return a


def _check_image_shape(img, name="image"):
    """Refuse what is not a (height, width) grey, (height, width, 3) RGB or (height, width, 4) RGBA image."""
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] not in (3, 4)) or img.size == 0:
        raise InputError(f"{name}: expected a (height, width), (height, width, 3) or (height, width, 4) image "
                         f"with at least one pixel, got shape {img.shape}")


def _quantise(img, top, dtype):
    a = _check_unit(img)
    m = np.multiply(a, float(top), out=np.empty(a.shape))
    np.rint(m, out=m)  # -0.0 and top + 3e-7 round into range after the check
    return m.astype(dtype)


def to_uint8(img):
    """Quantise an image to 8 bits: ``rint(255 * img)`` for floats in [0, 1].

    uint8 input is returned unchanged, uint16 input is rescaled
    (``rint(v / 257)``).

    Parameters
    ----------
    img : array_like
        A (height, width) grey, (height, width, 3) RGB or (height, width, 4)
        RGBA image: floats in [0, 1], uint8 or uint16.

    Returns
    -------
    uint8 array of the same shape

    Raises
    ------
    InputError
        Another shape or an empty image; float values outside [0, 1] or not
        finite; other dtypes.

    Examples
    --------
    >>> to_uint8(np.array([[0.0, 0.5, 1.0]])).tolist()
    [[0, 128, 255]]
    """
    img = np.asarray(img)
    _check_image_shape(img)
    if img.dtype == np.uint8:
        return img
    if img.dtype == np.uint16:
        return np.rint(img / 257.0).astype(np.uint8)
    if not np.issubdtype(img.dtype, np.floating):
        raise InputError(f"image: expected floats in [0, 1], uint8 or uint16, got {img.dtype}")
    return _quantise(img, 255, np.uint8)


def to_uint16(img):
    """Quantise an image to 16 bits: ``rint(65535 * img)`` for floats in [0, 1].

    uint16 input is returned unchanged, uint8 input is rescaled exactly
    (``v * 257``, so that 255 becomes 65535).

    Parameters
    ----------
    img : array_like
        A (height, width) grey, (height, width, 3) RGB or (height, width, 4)
        RGBA image: floats in [0, 1], uint8 or uint16.

    Returns
    -------
    uint16 array of the same shape

    Raises
    ------
    InputError
        Another shape or an empty image; float values outside [0, 1] or not
        finite; other dtypes.
    """
    img = np.asarray(img)
    _check_image_shape(img)
    if img.dtype == np.uint16:
        return img
    if img.dtype == np.uint8:
        return img.astype(np.uint16) * np.uint16(257)
    if not np.issubdtype(img.dtype, np.floating):
        raise InputError(f"image: expected floats in [0, 1], uint8 or uint16, got {img.dtype}")
    return _quantise(img, 65535, np.uint16)


def _image_of(image):
    return image["img"] if isinstance(image, dict) else image


def _parent_exists(path):
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"{path}: output directory {path.parent} does not exist")
    return path


def write_png(path, image, bit_depth=8):
    """Write an image as PNG, atomically (temporary name, then rename).

    Parameters
    ----------
    path : str or Path
        Output file; its directory must exist.
    image : array or dict
        (height, width) grey or (height, width, 3) RGB image: floats in
        [0, 1], uint8 or uint16; or a result dict of a ``render_*`` function.
    bit_depth : {8, 16}
        Bits per channel written.

    Returns
    -------
    Path
        The file written. The bytes depend only on the pixels (OpenCV's PNG
        encoder with default settings writes no time stamp).

    Raises
    ------
    InputError
        Bad image, bit depth or output directory.
    """
    import cv2

    img = np.asarray(_image_of(image))
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] != 3) or img.size == 0:
        raise InputError(f"{path}: image must be (height, width) or (height, width, 3), got shape {img.shape}")
    if bit_depth == 8:
        img = to_uint8(img)
    elif bit_depth == 16:
        img = to_uint16(img)
    else:
        raise InputError(f"{path}: bit_depth must be 8 or 16, got {bit_depth!r}")
    if img.ndim == 3:
        img = np.ascontiguousarray(img[..., ::-1])  # OpenCV wants BGR
    ok, buf = cv2.imencode(".png", img)
    if not ok:  # pragma: no cover - OpenCV failure
        raise InputError(f"{path}: OpenCV could not encode the image as PNG")
    path = _parent_exists(path)
    with atomic_write(path, "wb") as fh:
        fh.write(buf.tobytes())
    return path


def _num(v):
    s = f"{float(v):.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _hex(c):
    c = (c,) * 3 if np.ndim(c) == 0 else tuple(c)
    return "#" + "".join(f"{int(np.rint(255.0 * v)):02x}" for v in c)


def _path_data(lines, closed):
    out = []
    for p in lines:
        coords = " ".join(f"{_num(x)} {_num(y)}" for x, y in p[1:])
        out.append(f"M {_num(p[0, 0])} {_num(p[0, 1])} L {coords}" + (" Z" if closed else ""))
    return " ".join(out)


def svg_text(result):
    """The SVG document (a str) of a ``render_*`` result.

    Shapes are drawn inside ``<g transform="translate(0.5 0.5)">`` so that
    the numbers in the file are the same ``(x, y)`` image-pixel coordinates
    as the contour files (pixel centres at integers), while SVG puts the
    centre of pixel ``j`` at user unit ``j + 0.5``. The document is
    ``width x height`` user units (one per pixel) with a ground rectangle.
    Silhouettes use ``fill-rule="evenodd"``; outlines and fragments are
    strokes with the same width, joins and caps, except that with mitre
    joins the exact stroke region is written as a filled path (SVG bevels a
    mitre beyond the limit where shapely squares it off); dots are circles.
    Colours are 8-bit hex. Checked with librsvg: the SVG rasterised at one
    unit per pixel matches the PNG with no shift (mean difference under 0.2
    grey levels; librsvg flattens arcs a little inside the true circle). Numbers have at most 6 decimals; no time stamps, so the
    same result always gives the same text.

    Parameters
    ----------
    result : dict
        What a ``render_*`` function returned (its ``kind``, ``size``,
        colours and geometry are used).

    Returns
    -------
    str

    Raises
    ------
    InputError
        Not such a dict, or an unknown ``kind``.
    """
    if not isinstance(result, dict):
        raise InputError(f"result: expected the dict a render_* function returns, got {type(result).__name__}; "
                         "write_svg also takes rings")
    kind = result.get("kind")
    w, h = result["size"]
    fig, gnd = _hex(result["figure"]), _hex(result["ground"])
    if kind == "silhouette":
        body = f'<path d="{_path_data(result["rings"], True)}" fill="{fig}" fill-rule="evenodd"/>'
    elif kind in ("outline", "fragments") and result["join"] == "mitre":
        # SVG bevels a mitre past the limit where GEOS squares it off, so
        # the exact stroke region is written as a filled path instead.
        rings = result["stroke_rings"]
        body = f'<path d="{_path_data(rings, True)}" fill="{fig}" fill-rule="evenodd"/>' if rings else ""
    elif kind in ("outline", "fragments"):
        closed = kind == "outline" and result["closed"]
        lines = [result["points"]] if kind == "outline" else result["polylines"]
        join = {"mitre": "miter"}.get(result["join"], result["join"])
        cap = {"flat": "butt"}.get(result["cap"], result["cap"])
        body = (
            f'<path d="{_path_data(lines, closed)}" fill="none" stroke="{fig}" '
            f'stroke-width="{_num(result["width"])}" stroke-linejoin="{join}" '
            f'stroke-linecap="{cap}" stroke-miterlimit="{_num(result["mitre_limit"])}"/>'
        )
    elif kind == "dots":
        r = _num(result["radius"])
        body = "\n".join(
            f'<circle cx="{_num(x)}" cy="{_num(y)}" r="{r}" fill="{fig}"/>' for x, y in result["centers"]
        )
    else:
        raise InputError(f"result: expected the dict of a render_* function, got kind {kind!r}")
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" '
        f'viewBox="0 0 {w} {h}">\n'
        "<!-- attneave: (x, y) in image pixels, pixel centres at integers, y down; "
        "translate(0.5 0.5) maps them to SVG user units -->\n"
        f'<rect x="0" y="0" width="{w}" height="{h}" fill="{gnd}"/>\n'
        f'<g transform="translate(0.5 0.5)">\n{body}\n</g>\n</svg>\n'
    )


def write_svg(path, result, size=None, *, figure=0.0, ground=1.0):
    """Write a plain SVG in the image's pixel coordinate system, atomically.

    Parameters
    ----------
    path : str or Path
        Output file; its directory must exist.
    result : dict or rings
        The dict returned by a ``render_*`` function (then `size`, `figure`
        and `ground` come from it), or rings of a silhouette as accepted by
        :func:`render_silhouette` (then `size` is required).
    size : int or (int, int), optional
        Image ``(width, height)`` for rings.
    figure, ground : float or RGB triple in [0, 1], optional
        Colours for rings.

    Returns
    -------
    Path
        The file written; see :func:`svg_text` for its content.
    """
    if not isinstance(result, dict):
        h, w = resolve_shape(size)
        f, g = colours(figure, ground)
        rings, _ = as_rings(result, "rings")
        result = {"kind": "silhouette", "size": (w, h), "figure": plain_colour(f), "ground": plain_colour(g), "rings": rings}
    text = svg_text(result)
    path = _parent_exists(path)
    with atomic_write(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return path
