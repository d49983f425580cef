"""Exact discs: the coverage of pixels by circles, to floating point.

Points are ``(x, y)`` in image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).

Each circle is cut where it crosses a grid line (and at its four extreme
points); the polygon through those cuts is rasterised exactly by
:mod:`attneave.stimuli.render.raster`, and each cut arc adds its circular segment
``R^2/2 (d - sin d)`` to the one pixel that contains it.
"""

from __future__ import annotations

import math

import numpy as np

from attneave.stimuli.render.raster import accumulate, box_coverage, dense_coverage, ring_stream
from attneave.stimuli.render.rings import resolve_shape
from attneave.stimuli.validate import as_number, as_points


def _disc_terms(centers, radius, h, w):
    """Chord polygons and circular-segment corrections of exact discs.

    Each circle is cut where it crosses a grid line (and at its four extreme
    points); the polygon through the cuts is rasterised exactly, and each
    arc's circular segment ``R^2/2 (d - sin d)`` lies in the one pixel that
    holds the arc, so it is added there. Returns (rings, extra) with rings in
    image coordinates and extra = (row, col, area).
    """
    rings, rows, cols, areas = [], [], [], []
    r = float(radius)
    quad = np.array([r, 0.0, -r, 0.0]), np.array([0.0, r, 0.0, -r])
    for cx, cy in centers + 0.5:
        # Only grid lines of the image (edges included) need cuts: an arc
        # outside the image spans the same columns as its chord (arcs are
        # monotone between the extreme points) and its segment is dropped.
        gx = np.arange(max(math.floor(cx - r) + 1, 0), min(math.ceil(cx + r), w + 1), dtype=float)
        gy = np.arange(max(math.floor(cy - r) + 1, 0), min(math.ceil(cy + r), h + 1), dtype=float)
        hx = np.sqrt(np.maximum(r * r - (gx - cx) ** 2, 0.0))
        hy = np.sqrt(np.maximum(r * r - (gy - cy) ** 2, 0.0))
        px = np.concatenate([gx, gx, cx + hy, cx - hy, cx + quad[0]])
        py = np.concatenate([cy + hx, cy - hx, gy, gy, cy + quad[1]])
        ang = np.arctan2(py - cy, px - cx)
        order = np.argsort(ang, kind="stable")
        ang, px, py = ang[order], px[order], py[order]
        d = np.diff(np.append(ang, ang[0] + 2.0 * np.pi))
        keep = d > 0.0
        ang, px, py, d = ang[keep], px[keep], py[keep], d[keep]
        # increasing angle with y down: positive shoelace, +1 inside
        rings.append(np.column_stack([px - 0.5, py - 0.5]))
        mid = ang + 0.5 * d
        rows.append(np.floor(cy + r * np.sin(mid)).astype(np.intp))
        cols.append(np.floor(cx + r * np.cos(mid)).astype(np.intp))
        areas.append(0.5 * r * r * (d - np.sin(d)))
    row, col, area = (np.concatenate(v) for v in (rows, cols, areas))
    inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
    return rings, (row[inside], col[inside], area[inside])


def disc_accumulation(centers, radius, h, w, dtype=np.float64):
    """:func:`accumulate` of exact discs (chord polygons plus circular segments)."""
    rings, extra = _disc_terms(centers, radius, h, w)
    p, bridge, _ = ring_stream(rings, oriented=True)
    return accumulate(p, bridge, h, w, extra, dtype)


def disc_coverage(centers, radius, shape):
    """Exact area coverage of pixels by discs.

    Parameters
    ----------
    centers : (M, 2) array
        Disc centres ``(x, y)`` in image pixels (y down, pixel centres at
        integer coordinates).
    radius : float
        Disc radius in pixels (> 0).
    shape : (int, int)
        Image ``(height, width)``.

    Returns
    -------
    cov : (height, width) float64 array
        Exact covered fraction of each pixel (to floating point), clipped to
        [0, 1]. Where discs overlap the winding integrals add and are
        clipped at 1, exact except in pixels crossed by two circles.

    Examples
    --------
    A disc of diameter 1 inscribed in pixel (3, 3) covers pi/4 of it:

    >>> cov = disc_coverage([(3.0, 3.0)], 0.5, (7, 7))
    >>> bool(np.isclose(cov[3, 3], np.pi / 4)), float(cov.sum() - cov[3, 3])
    (True, 0.0)
    """
    h, w = resolve_shape(shape=shape)
    centers = as_points(centers, "centers")
    radius = as_number(radius, "radius", gt=0)
    return dense_coverage(box_coverage(disc_accumulation(centers, radius, h, w)), h, w)
