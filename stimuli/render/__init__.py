"""Rendering contours to images with exact area-coverage antialiasing.

Modules: ``rings`` (shapes as oriented rings), ``raster`` (the exact
rasteriser: coverage of rings), ``kernel`` (its optional compiled
inner loops; ``KERNEL`` says whether they run), ``discs`` (exact discs), ``workspace``
(its scratch buffers), ``paint`` (silhouettes and dots
as images), ``strokes`` (outlines and fragments), ``placement`` (fitting
points to an image), ``files`` (8/16-bit quantisation, PNG, SVG).

Points are ``(x, y)`` in image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).
"""

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "KERNEL": ".kernel",
    "coverage": ".raster",
    "disc_coverage": ".discs",
    "render_silhouette": ".paint",
    "render_dots": ".paint",
    "render_outline": ".strokes",
    "render_fragments": ".strokes",
    "fit_to_image": ".placement",
    "to_uint8": ".files",
    "to_uint16": ".files",
    "write_png": ".files",
    "svg_text": ".files",
    "write_svg": ".files",
})
