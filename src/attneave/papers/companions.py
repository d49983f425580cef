"""Figures beside the seed paper's Figs. 1-6: its curve families and a Fig. 10 analogue.

:func:`curve_families` draws the curves of the paper's sections 2.2 and 3
from :mod:`attneave.stimuli.curves`; :func:`fig10` redoes the paper's Fig. 10
("A duck which 'turns into' a Pterosaur with the increase of the polynomial
degree (from left to right n=3, 4 and 5)") on 30 points of a real bird
outline, adding the QIC spline. Both return a
:class:`attneave.papers.base.FigureData` and are listed in
:data:`attneave.papers.ziatdinov.FIGURES`.

Examples
--------
>>> fd = fig10()
>>> fd.params["interior_extrema"]["qic-g2"]
0
"""

from __future__ import annotations

import numpy as np

from attneave.papers.base import EQ7, FigureData, Line, Mark, Panel

__all__ = ["curve_families", "fig10", "FIG10_METHODS", "FIG10_SAMPLES"]

#: Splines of the Fig. 10 analogue: (method of :func:`fit_spline`, title).
FIG10_METHODS = (("poly3", "cubic (periodic)"), ("poly4", "quartic (periodic)"),
                 ("poly5", "quintic (periodic)"), ("qic-g2", "QIC spline (G2 clothoids)"))
#: Samples per segment of each spline.
FIG10_SAMPLES = 64
_FAMILY_COLORS = ("black", "tab:blue", "tab:red", "tab:green")


def _origin():
    return Line(np.zeros(1), np.zeros(1), None, "0.3", "", marker="o", size=3, zorder=5)


def _shape_panel(lines, title):
    return Panel(tuple(lines) + (_origin(),), title, "x (y up)", "y", equal=True, columns=2)


def curve_families():
    """Gallery of the paper's curve families (y-up coordinates).

    Clothoids, pseudospirals (eq. 8), log-aesthetic curves (eq. 9),
    superspirals (eq. 10) and eq. 7's constant-information curves with
    their curvature, each starting at the origin heading along +x.

    Returns
    -------
    FigureData
        Six panels (2 x 3); the last plots curvature over arc length.
    """
    from attneave.stimuli import curves

    panels = []
    cl = [curves.clothoid(0.0, c, -3.0, 3.0, 801) for c in (1.0, -1.0)]
    panels.append(_shape_panel([Line(c.x, c.y, f"k = {v:g} s, s in [-3, 3]", col)
                                for c, v, col in zip(cl, (1, -1), ("black", "tab:red"))],
                               "clothoid, k = k0 + c s"))
    lines = []
    for m, rng, col in ((1.0, (0.05, 6.0), "black"), (-1.0, (0.0, 2.0), "tab:blue"), (0.5, (0.001, 4.0), "tab:red")):
        ps = curves.pseudospiral(0.2, m, *rng, 1601)
        lines.append(Line(ps.x, ps.y, f"m = {m:g}, s in [{rng[0]:g}, {rng[1]:g}]", col, width=0.8))
    panels.append(_shape_panel(lines, "pseudospirals rho = 0.2 s^m (eq. 8)"))
    lines, lam, k = [], 1.0, np.array([10.0, 0.2])
    for alpha, col in zip((-1.0, 0.0, 1.0, 2.0), _FAMILY_COLORS):
        # the arc on which the curvature falls from 10 to 0.2
        s_rng = -np.log(k) / lam if alpha == 0 else (k ** (-alpha) - 1) / (lam * alpha)
        lac = curves.log_aesthetic(alpha, lam, *s_rng, 1601)
        lines.append(Line(lac.x, lac.y, f"alpha = {alpha:g}", col, width=0.8))
    panels.append(_shape_panel(lines, "LAC (eq. 9), lam = 1, k from 10 to 0.2"))
    lines = []
    for (a, b, c), col in zip(((1.0, 1.0, 2.0), (2.0, 1.0, 3.0), (0.5, 1.0, 1.5)), _FAMILY_COLORS):
        sp = curves.superspiral(a, b, c, 4 * np.pi, 801)
        lines.append(Line(sp.x, sp.y, f"(a, b, c) = ({a:g}, {b:g}, {c:g})", col, width=0.8))
    panels.append(_shape_panel(lines, "superspirals, theta in [0, 4 pi] (eq. 10)"))
    shapes, kappas = [], []
    for C, col in zip((0.0, 0.03, -0.03), ("tab:red", "tab:blue", "tab:green")):
        s0 = max(curves.constant_info_domain(C, EQ7["n"]), 1.0)
        ci = curves.constant_info(C, EQ7["n"], s0, EQ7["s_end"], 1601)
        shapes.append(Line(ci.x, ci.y, f"C = {C:g}, s in [{s0:.3g}, 5]", col, width=0.8))
        ci = curves.constant_info(C, EQ7["n"], s0, EQ7["s_end"], 801)
        kappas.append(Line(ci.s, ci.curvature, f"C = {C:g}", col))
    panels.append(_shape_panel(shapes, "constant-information curves (eq. 7), n = 10"))
    panels.append(Panel(tuple(kappas), "their curvature", "arc length s", "curvature", columns=2))
    return FigureData(
        "curve_families", "fig_curves.png", "", tuple(panels), grid=(2, 3), size=(11.0, 8.0),
        params=dict(n=EQ7["n"], lac_lam=lam),
        description=(
            "The curve families of sections 2.2 and 3 from `attneave.stimuli.curves` (y-up coordinates, "
            "each starting at the origin, grey dot, heading along +x): clothoids, pseudospirals (m = 1 "
            "logarithmic spiral, m = -1 Cornu spiral, m = 1/2 involute of a circle), log-aesthetic "
            "curves (alpha = -1 clothoid, 0 Nielsen's spiral, 1 logarithmic spiral, 2 involute), "
            "superspirals, and eq. 7's constant-information curves with their curvature."))


def _by_segment(curve, values):
    """`values` with NaN between segments, so that a line is not drawn across a join."""
    from attneave.stimuli.curves.metrics import segment_slices

    parts = []
    for sl in segment_slices(curve.segment):
        parts += [values[sl], [np.nan]]
    return np.concatenate(parts[:-1])


def fig10(samples=FIG10_SAMPLES):
    """Analogue of the paper's Fig. 10 on 30 points of a bird outline.

    Caption: "A duck which 'turns into' a Pterosaur with the increase of
    the polynomial degree (from left to right n=3, 4 and 5)". The paper's
    30 points are not published; these are 30 points of MPEG-7
    ``bird-1.png`` (:func:`attneave.papers.spline_plots.load_bird30`),
    interpolated by periodic polynomial splines of degree 3, 4, 5 and by
    the QIC spline.

    Parameters
    ----------
    samples : int
        Samples per segment.

    Returns
    -------
    FigureData
        Top row: each spline (y down), its points and its curvature extrema
        between the points; bottom row: curvature along arc length.
        ``params['interior_extrema']`` counts the extrema per method.
    """
    from attneave.papers.spline_plots import load_bird30
    from attneave.stimuli.curves.metrics import curve_metrics, extrema_indices, segment_slices
    from attneave.stimuli.curves.splines import fit_spline

    P = load_bird30()
    curves = [fit_spline(P, method).sample(samples) for method, _ in FIG10_METHODS]
    counts = {m: int(curve_metrics(c)["interior_extrema"]) for (m, _), c in zip(FIG10_METHODS, curves)}
    lim = 1.5 * float(np.abs(curves[-1].curvature).max())
    top, bottom = [], []
    for (method, title), c in zip(FIG10_METHODS, curves):
        e = extrema_indices(c.curvature, c.segment, 1e-9)
        dots = dict(style="", marker="o", size=3, zorder=4)
        top.append(Panel((
            Line(c.x, c.y, None, "black"),
            Line(P[:, 0], P[:, 1], None, "tab:blue", "", marker="o", size=3, face="white", zorder=3),
            Line(c.x[e], c.y[e], None, "tab:red", **dots),
        ), f"{title}\n{counts[method]} curvature extrema between the points", legend=None, equal=True,
            y_down=True, ticks=False))
        kmax = float(np.abs(c.curvature).max())
        starts = c.s[[sl.start for sl in segment_slices(c.segment)]]
        bottom.append(Panel((
            Line(_by_segment(c, c.s), _by_segment(c, c.curvature), None, "black"),
            Line(c.s[e], c.curvature[e], None, "tab:red", **dots),
        ), "", "arc length s (px)", "curvature (1/px)", ylim=(-lim, lim), legend=None,
            marks=tuple(Mark("x", float(v), color="0.85", width=0.5) for v in starts) + (Mark("y", 0.0, color="0.6", width=0.5),),
            text=f"max |k| = {kmax:.3g} (clipped)" if kmax > lim else None))
    return FigureData(
        "fig10", "fig10_bird_splines.png",
        "Fig. 10 analogue: a bird outline through 30 points (MPEG-7 bird-1); "
        "red dots: curvature extrema between the points", tuple(top + bottom), grid=(2, 4), size=(16.0, 7.0),
        caption="A duck which \"turns into\" a Pterosaur with the increase of the polynomial degree (from left "
                "to right n=3, 4 and 5).",
        params=dict(points=30, samples_per_segment=samples, methods=[m for m, _ in FIG10_METHODS],
                    interior_extrema=counts),
        reading="The paper's 30 points (given by Miura and Suzuki) are not published; 30 points of a real "
                "bird silhouette stand in for them, and the QIC spline is added on the right.",
        description=(
            "Analogue of the paper's Fig. 10 (the duck that turns into a pterosaur). Thirty points on "
            "the outline of a real silhouette (MPEG-7 CE-Shape-1 `bird-1.png`: outer contour smoothed "
            "by a Gaussian of 1/150 of the perimeter, 30 points equally spaced in arc length from the "
            "beak tip; shipped as `stimuli/data/bird30.csv`) interpolated by "
            "periodic polynomial splines of degree 3, 4 and 5 with chord-length parameters and by the "
            "QIC spline (G2 spline of clothoid segments). Top: the curves (blue circles: the points; "
            "red dots: curvature extrema strictly between points). Bottom: curvature along arc length "
            f"(grey lines: the points; {samples} samples per segment). Curvature extrema added "
            "between the points: " + ", ".join(f"{t.split(' (')[0]} {counts[m]}" for m, t in FIG10_METHODS)
            + ". The QIC spline adds none by construction: curvature is linear in arc length on "
            "every segment and continuous at the points."))
