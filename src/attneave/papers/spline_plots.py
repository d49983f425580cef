"""Plots for splines: curvature along arc length, and the Fig. 10 analogue
(a bird outline through 30 points: polynomial splines of degree 3, 4, 5
beside the QIC spline, with the curvature extrema each adds between the
points).

The 30 points ship as package data (``stimuli/data/bird30.csv``, columns
``x, y`` in image pixels, y down, counter-clockwise on the screen), so the
figure needs no image data; :func:`bird_points_from_silhouette` is the rule
that made them from ``bird-1.png`` of the MPEG-7 CE-Shape-1 set (part B).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = [
    "bird_points_from_silhouette",
    "load_bird30",
    "plot_curvature",
    "plot_spline",
    "fig10_analogue",
    "fig10_maker",
    "FIG10_NAME",
]

FIG10_NAME = "fig10_bird_splines.png"
FIG10_METHODS = (("poly3", "cubic (periodic)"), ("poly4", "quartic (periodic)"),
                 ("poly5", "quintic (periodic)"), ("qic-g2", "QIC spline (G2 clothoids)"))
FIG10_SAMPLES = 64


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
    clockwise on the screen)."""
    from importlib.resources import files

    from attneave.stimuli.tables import read_points

    return read_points(files("stimuli") / "data" / "bird30.csv")


def plot_curvature(ax, curve, color="k", mark_extrema=True, label=None, rtol=1e-9):
    """Curvature along arc length, segment by segment, with the points
    (segment joins) as vertical ticks and interior extrema as red dots.

    Parameters
    ----------
    ax : matplotlib Axes
    curve : stimuli.curve_metrics.SampledCurve
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


def _fig10(outdir):
    from attneave.analysis.report.figure_files import pyplot, save_png
    from attneave.stimuli.curves.metrics import curve_metrics
    from attneave.stimuli.curves.splines import fit_spline

    plt = pyplot()
    P = load_bird30()
    curves, counts = [], []
    for method, _ in FIG10_METHODS:
        c = fit_spline(P, method).sample(FIG10_SAMPLES)
        curves.append(c)
        counts.append(curve_metrics(c)["interior_extrema"])
    qk = np.abs(curves[-1].curvature).max()
    fig, axes = plt.subplots(2, 4, figsize=(16, 7), gridspec_kw={"height_ratios": [1.3, 1]})
    for j, ((method, title), c, n) in enumerate(zip(FIG10_METHODS, curves, counts)):
        plot_spline(axes[0, j], c, P)
        axes[0, j].set_title(f"{title}\n{n} curvature extrema between the points", fontsize=10)
        plot_curvature(axes[1, j], c)
        lim = 1.5 * qk
        axes[1, j].set_ylim(-lim, lim)
        clipped = np.abs(c.curvature).max() > lim
        if clipped:
            axes[1, j].text(0.02, 0.95, f"max |k| = {np.abs(c.curvature).max():.3g} (clipped)",
                            transform=axes[1, j].transAxes, fontsize=8, va="top")
    fig.suptitle("Fig. 10 analogue: a bird outline through 30 points (MPEG-7 bird-1); "
                 "red dots: curvature extrema between the points", fontsize=11)
    fig.tight_layout()
    path = save_png(fig, Path(outdir) / FIG10_NAME)
    text = (
        "Analogue of the paper's Fig. 10 (the duck that turns into a pterosaur). Thirty points on "
        "the outline of a real silhouette (MPEG-7 CE-Shape-1 `bird-1.png`: outer contour smoothed "
        "by a Gaussian of 1/150 of the perimeter, 30 points equally spaced in arc length from the "
        "beak tip; shipped as `stimuli/data/bird30.csv`) interpolated by "
        "periodic polynomial splines of degree 3, 4 and 5 with chord-length parameters and by the "
        "QIC spline (G2 spline of clothoid segments). Top: the curves (blue circles: the points; "
        "red dots: curvature extrema strictly between points). Bottom: curvature along arc length "
        f"(grey lines: the points; {FIG10_SAMPLES} samples per segment). Curvature extrema added "
        "between the points: " + ", ".join(f"{t.split(' (')[0]} {n}" for (_, t), n in zip(FIG10_METHODS, counts))
        + ". The QIC spline adds none by construction: curvature is linear in arc length on "
        "every segment and continuous at the points."
    )
    return [(path, text)], counts


def fig10_maker(outdir):
    """Figure maker for :data:`attneave.papers.ziatdinov.FIGURE_MAKERS`:
    ``[(path, description)]``."""
    return _fig10(outdir)[0]


def fig10_analogue(outdir):
    """Write the Fig. 10 analogue PNG into `outdir`; return ``[path]``."""
    return [p for p, _ in _fig10(outdir)[0]]
