"""Rendering contours to images: the exact-coverage rasteriser, strokes,
fragments and dots, placement on a canvas, PNG and SVG files."""

from stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "coverage": ".core",
    "disc_coverage": ".core",
    "fit_to_image": ".core",
    "render_silhouette": ".core",
    "render_outline": ".core",
    "render_fragments": ".core",
    "render_dots": ".core",
    "to_uint8": ".core",
    "to_uint16": ".core",
    "write_png": ".core",
    "svg_text": ".core",
    "write_svg": ".core",
})
