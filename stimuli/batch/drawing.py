"""Drawing a recipe item: a float image with exact area coverage, or SVG.

:func:`draw_item` renders an :class:`~stimuli.batch.recipes.Item` with a
:class:`~stimuli.batch.params.Style` through :mod:`stimuli.render`;
:func:`item_svg` writes the same drawing as SVG in the same pixel
coordinates (x = column, y = row, y down, pixel centres at integers).
"""

from __future__ import annotations

import numpy as np

from stimuli.batch.params import Style
from stimuli.errors import InputError

__all__ = ["draw_item", "item_svg"]


def _render(item, style, canvas):
    """The :mod:`stimuli.render` result dict of an item."""
    from stimuli import render

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
    return _render(item, style, canvas)["img"]


def item_svg(item, style, canvas):
    """The item as a complete, deterministic SVG document (same pixel coordinates)."""
    from stimuli.render import svg_text

    return svg_text(_render(item, style, canvas))

