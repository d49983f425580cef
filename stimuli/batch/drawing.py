"""Drawing a recipe item: a float image with exact area coverage, or SVG.

:func:`draw_item` renders an :class:`~attneave.stimuli.batch.recipes.Item` with a
:class:`~attneave.stimuli.batch.params.Style` through :mod:`attneave.stimuli.render`;
:func:`item_svg` writes the same drawing as SVG in the same pixel
coordinates (x = column, y = row, y down, pixel centres at integers).
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.batch.params import Style
from attneave.stimuli.errors import InputError

__all__ = ["draw_item", "drawn_bbox", "item_svg", "render_item"]


def render_item(item, style, canvas):
    """The :mod:`attneave.stimuli.render` result dict of an item: its image and the geometry drawn.

    Parameters
    ----------
    item : Item
    style : Style (or a mapping of its fields)
    canvas : Canvas

    Returns
    -------
    dict
        What the ``render_*`` function returned (``img``, ``kind``, the
        rings, strokes or dot centres in image pixels, ...); its image is
        :func:`draw_item`'s and its SVG (:func:`attneave.stimuli.render.svg_text`)
        :func:`item_svg`'s.
    """
    from attneave.stimuli import render

    if not isinstance(style, Style):
        style = Style.model_validate(style)
    size = canvas.size
    colours = dict(figure=style.figure, ground=style.ground)
    d = item.draw
    mode = d.get("mode")
    width = float(d.get("width") or style.line_width)
    if mode == "silhouette":
        return render.render_silhouette(item.contour.points, size=size, **colours)
    if mode == "outline":
        return render.render_outline(item.contour.points, width, size=size, closed=True, join=style.join, **colours)
    if mode == "fragments":
        return render.render_fragments([np.asarray(q, float) for q in d["polylines"]], width, size=size,
                                       cap=style.cap, join=style.join, **colours)
    if mode == "dots":
        radius = float(d.get("radius") or style.dot_radius)
        return render.render_dots(np.asarray(d["points"], float), radius, size=size, **colours)
    if mode == "polygon":
        pts = np.asarray(d["points"], float)
        if style.polygon_fill:
            return render.render_silhouette(pts, size=size, **colours)
        return render.render_outline(pts, width, size=size, closed=True, join=style.join, **colours)
    raise InputError(f"item {item.suffix!r}: unknown draw mode {mode!r}")


def draw_item(item, style, canvas):
    """Render an item: a float image in [0, 1] with exact area coverage.

    Parameters
    ----------
    item : Item
    style : Style (or a mapping of its fields)
    canvas : Canvas

    Returns
    -------
    ndarray
        ``(height, width)`` for grey colours, ``(height, width, 3)`` for RGB;
        pixel ``(i, j)`` is the square centred on ``(x, y) = (j, i)``.
    """
    return render_item(item, style, canvas)["img"]


def item_svg(item, style, canvas):
    """The item as a complete, deterministic SVG document (same pixel coordinates)."""
    from attneave.stimuli.render import svg_text

    return svg_text(render_item(item, style, canvas))


def drawn_bbox(result):
    """Bounding box ``(x0, y0, x1, y1)`` of what a render result paints, in image pixels.

    The painted region, not the contour: a stroke reaches half its width
    (and its joins and caps) beyond the line, a dot its radius beyond its
    centre. Pixel centres are at integers, so the image itself spans
    ``[-0.5, width - 0.5] x [-0.5, height - 0.5]``.

    Parameters
    ----------
    result : dict
        What :func:`render_item` returned.

    Returns
    -------
    tuple of float, or None
        None when nothing is painted.
    """
    kind = result["kind"]
    if kind == "dots":
        c = np.asarray(result["centers"], float).reshape(-1, 2)
        if not len(c):
            return None
        r = float(result["radius"])
        lo, hi = c.min(axis=0) - r, c.max(axis=0) + r
    else:
        rings = result["rings"] if kind == "silhouette" else result["stroke_rings"]
        if not len(rings):
            return None
        pts = np.vstack([np.asarray(q, float).reshape(-1, 2) for q in rings])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

