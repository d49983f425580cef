"""Plots for splines (curvature along arc length, a spline with its
points) and the 30 points of the Fig. 10 analogue
(:func:`attneave.papers.companions.fig10`): a bird outline.

The 30 points ship as package data (``stimuli/data/bird30.csv``, columns
``x, y`` in image pixels, y down, counter-clockwise on the screen), so the
figure needs no image data; :func:`bird_points_from_silhouette` is the rule
that made them from ``bird-1.png`` of the MPEG-7 CE-Shape-1 set (part B).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "bird_points_from_silhouette",
    "load_bird30",
    "plot_curvature",
    "plot_spline",
]

def bird_points_from_silhouette(path, n=30, smooth=1 / 150):
    """Reduce a silhouette's outer contour to `n` points.

    The rule behind ``stimuli/data/bird30.csv`` (made from MPEG-7
    ``bird-1.png`` with the defaults): the object's outer contour
    (:func:`attneave.stimuli.extraction.extract`, method 'threshold' at grey level
    127, light object, holes filled), smoothed along its arc by a periodic
    Gaussian of standard deviation ``smooth`` times the perimeter
    (:func:`attneave.stimuli.extraction.smooth`; it removes the toes and feather tips
    that 30 points cannot carry); then `n` points equally spaced in arc
    length (:meth:`Contour.resample`) starting at its leftmost point (the
    beak tip), counter-clockwise on the screen. (The shipped file was made
    by the same rule with an earlier tracer, skimage's ``find_contours`` on
    the filled mask; the two differ by less than 0.6 px.)

    Returns
    -------
    ndarray, shape (n, 2)
        ``(x, y)`` in image pixels (x = column, y = row, y down).
    """
    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction import smooth as smooth_contour
    from attneave.stimuli.geometry.contour import Contour

    outline = extract(path, method="threshold", threshold=127, polarity="light").contour
    c = smooth_contour(outline, sigma=smooth * outline.perimeter)
    start = int(np.argmin(c.points[:, 0]))
    c = Contour(np.roll(c.points, -start, axis=0), orient=False)
    return c.resample(n).points


def load_bird30():
    """The shipped 30-point bird outline (image pixels, y down, counter-
    clockwise on the screen).

    Examples
    --------
    >>> load_bird30().shape
    (30, 2)
    """
    from importlib.resources import files

    from attneave.stimuli.tables import read_points

    return read_points(files("attneave.stimuli") / "data" / "bird30.csv")


def plot_curvature(ax, curve, color="k", mark_extrema=True, label=None, rtol=1e-9):
    """Curvature along arc length, segment by segment, with the points
    (segment joins) as vertical ticks and interior extrema as red dots.

    Parameters
    ----------
    ax : matplotlib Axes
    curve : attneave.stimuli.curves.metrics.SampledCurve
    """
    from attneave.stimuli.curves.metrics import extrema_indices, segment_slices

    for i, sl in enumerate(segment_slices(curve.segment)):
        ax.plot(curve.s[sl], curve.curvature[sl], color=color, lw=1.0, label=label if i == 0 else None)
    starts = [sl.start for sl in segment_slices(curve.segment)]
    for s0 in curve.s[starts]:
        ax.axvline(s0, color="0.85", lw=0.5, zorder=0)
    ax.axhline(0, color="0.6", lw=0.5, zorder=0)
    if mark_extrema:
        e = extrema_indices(curve.curvature, curve.segment, rtol)
        ax.plot(curve.s[e], curve.curvature[e], "o", color="tab:red", ms=3, zorder=3)
    ax.set_xlabel("arc length s (px)")
    ax.set_ylabel("curvature (1/px)")
    return ax


def plot_spline(ax, curve, points, color="k", mark_extrema=True, rtol=1e-9):
    """The curve in image coordinates (y down), its points and its interior
    curvature extrema (red)."""
    from attneave.stimuli.curves.metrics import extrema_indices

    ax.plot(curve.x, curve.y, color=color, lw=1.0)
    ax.plot(points[:, 0], points[:, 1], "o", ms=3, mfc="white", mec="tab:blue", zorder=3)
    if mark_extrema:
        e = extrema_indices(curve.curvature, curve.segment, rtol)
        ax.plot(curve.x[e], curve.y[e], "o", color="tab:red", ms=3, zorder=4)
    ax.set_aspect("equal")
    if not ax.yaxis_inverted():
        ax.invert_yaxis()
    ax.set_xticks([])
    ax.set_yticks([])
    return ax
