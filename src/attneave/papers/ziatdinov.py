"""The figures of Ziatdinov's paper on the quantity of information function.

This module reproduces the figures of the seed paper [1]_ that the project
can compute: Figs. 1-4 (eq. 5 along given curvatures), Figs. 5-6 (eq. 7's
curvature) and, from :mod:`attneave.papers.companions`, an analogue of
Fig. 10 and two companion figures. Each figure is a function returning a
:class:`attneave.papers.base.FigureData` (the arrays of every line, the
caption's parameters, the caption and any reading decision), without
drawing; :func:`attneave.papers.draw.draw` draws one and
:func:`attneave.papers.draw.make_figures` writes them all (``attneave
figures``). :data:`FIGURES` lists them by name, as stimupy's ``papers``
modules do for stimuli.

Readings of the captions
------------------------
Eq. 5 is ``u(k) = -ln A' - b ds^2 cos(k ds - 2 pi/n)``. The captions of
Figs. 1-4 give "s = 100, n = 10, A' = 1/4", with s the length L (the
paper's footnote 1 renames L to s), so ``ds = L/n = 10`` in the paper's own
units of length. Two captions need a decision:

* Fig. 2: the text says that "the amplitudes of (5) increase with an arc
  length (Fig. 2)", which holds with ``ds = s/n`` (the arc length so far
  over n, as the paper takes for eq. 7), not with the caption's constant
  ``ds = 10``. :func:`fig2` draws both, side by side, with their ranges.
* Fig. 4: the caption prints "kappa = 2 pi/ns" and calls the curve a
  clothoid. Read ``(2 pi/n) s`` it is a clothoid (curvature linear in arc
  length); read ``2 pi/(n s)`` it is a logarithmic spiral. :func:`fig4`
  draws the clothoid reading first and the other beside it, labelled.

References
----------
.. [1] Ziatdinov, R. Visual perception, quantity of information function and
       the concept of the quantity of information continuous splines.
       Eqs. 4-7, Figs. 1-6 and 10.

Examples
--------
>>> fd = FIGURES["fig4"]()
>>> fd.params["kappa"]
'(2*pi/n)*s'
>>> sorted(FIGURES)[:3]
['curve_families', 'eq7_constant_u', 'fig1']
"""

from __future__ import annotations

import numpy as np

from attneave.papers.base import B_COLORS, C_COLORS, EQ7, PAPER, Band, FigureData, Line, Mark, Panel
from attneave.papers.companions import curve_families, fig10

__all__ = ["fig1", "fig2", "fig3", "fig4", "fig5", "fig6", "eq7_constant_u", "eq7_arc_lengths", "FIGURES", "CAPTIONS"]

#: The paper's captions, as printed (LaTeX as in the paper's text).
CAPTIONS = {
    "fig1": r"The quantity of information function (5) with $\kappa \in [-1; 1], s = 100, n = 10, A' = 1/4$ "
            r"and $b = \{1/2, 1, 2\}$ for black, blue and red lines, respectively.",
    "fig2": r"The quantity of information function (5) for an MC-curve with given curvature "
            r"$\kappa(s) = \exp(s), s \in [0; 3], s = 100, n = 10, A' = 1/4$ and $b = \{1/2, 1, 2\}$ "
            r"for black, blue and red lines, respectively.",
    "fig3": r"The quantity of information function (5) for a curve with given curvature "
            r"$\kappa(s) = (1 - s)^{-1}$, $s \in [0; 2], s = 100, n = 10, A' = 1/4$ and "
            r"$b = \{1/2, 1, 2\}$ for black, blue and red lines, respectively.",
    "fig4": r"The quantity of information function (5) for an MC-curve (clothoid) with given curvature "
            r"$\kappa = 2\pi/ns$, $s \in [0; 3], s = 100, n = 10, A' = 1/4$ and $b = \{1/2, 1, 2\}$ "
            r"for black, blue and red lines, respectively.",
    "fig5": r"Curvature function (7) for $C = 0, 1 \times 10^{-2}, 2 \times 10^{-2}, 3 \times 10^{-2}$ "
            r"(for red, green, yellow and blue, respectively) and $n = 10, s \in [0; 5]$.",
    "fig6": r"Curvature function (7) for $C = 0, -1 \times 10^{-2}, -2 \times 10^{-2}, -3 \times 10^{-2}$ "
            r"(for red, green, yellow and blue, respectively) and $n = 10, s \in [0; 5]$.",
}

_U_LABEL = "quantity of information u (nats)"


def _ds():
    return PAPER["L"] / PAPER["n"]


def _u(turn, ds, b):
    """Eq. 5 at turning angle ``turn = k ds`` with the caption's A' and n."""
    from attneave.stimuli.geometry.information import surprisal_paper

    return surprisal_paper(turning_angle=turn, ds=ds, n=PAPER["n"], A=PAPER["A"], b=b, closed=True)


def _level():
    return Mark("y", float(-np.log(PAPER["A"])))


def _s_by_phase(s_of_phase, phase_lo, phase_hi, step=0.05):
    """Arc lengths at which the turn ``k ds`` is sampled every `step` radians.

    Where the turn grows without bound u oscillates without bound in s;
    sampling equally in turn resolves every oscillation that is drawn.
    """
    m = int(np.ceil(abs(phase_hi - phase_lo) / step)) + 1
    return s_of_phase(np.linspace(phase_lo, phase_hi, m))


def _params(**extra):
    return dict(A=PAPER["A"], L=PAPER["L"], n=PAPER["n"], b=PAPER["b"], **extra)


def _subtitle(ds="ds = 10"):
    return f"eq. 5, A' = 1/4, L = {PAPER['L']:g}, n = {PAPER['n']}, {ds}"


# --------------------------------------------------------------------------- Figs. 1-4 (eq. 5)


def fig1(num=4001):
    """Fig. 1: eq. 5 over curvature, ``kappa in [-1, 1]``.

    Caption: "The quantity of information function (5) with kappa in
    [-1; 1], s = 100, n = 10, A' = 1/4 and b = {1/2, 1, 2} for black, blue
    and red lines", read with ``ds = s/n = 10``.

    Parameters
    ----------
    num : int
        Number of curvatures, equally spaced on [-1, 1].

    Returns
    -------
    FigureData
        One panel: u(kappa) for each b, the level ``-ln A'`` and the
        curvature ``2 pi/(n ds)`` of the minima.
    """
    ds = _ds()
    k = np.linspace(-1.0, 1.0, num)
    lines = tuple(Line(k, _u(k * ds, ds, b), f"b = {b:g}", col, zorder=3 - j)
                  for j, (b, col) in enumerate(zip(PAPER["b"], B_COLORS)))
    kmin = 2 * np.pi / PAPER["n"] / ds
    panel = Panel(lines, xlabel="curvature k (1/length)", ylabel=_U_LABEL,
                  marks=(_level(), Mark("x", kmin, color="0.5", style=":", width=0.8)))
    return FigureData(
        "fig1", "fig1_u_vs_curvature.png", f"Fig. 1: u over curvature ({_subtitle()})", (panel,),
        caption=CAPTIONS["fig1"], params=_params(ds=ds, kappa=(-1.0, 1.0)),
        description=(
            "Fig. 1. Eq. 5 over curvature k in [-1, 1] (A' = 1/4, L = 100, n = 10, ds = 10; b = 1/2, 1, 2 "
            "in black, blue, red). u is periodic in k with period 2*pi/ds; its minima sit where the "
            "turn k*ds equals the mean turn 2*pi/n (k = 2*pi/(n ds) = 0.0628, dotted line), i.e. where "
            "the tangent turns slightly inward; the amplitude is b*ds^2."))


def fig2(num=20001, step=0.05):
    """Fig. 2: eq. 5 along the MC-curve ``kappa(s) = exp(s)``, ``s in [0, 3]``.

    Caption: "... for an MC-curve with given curvature kappa(s) = exp(s),
    s in [0; 3], s = 100, n = 10, A' = 1/4 and b = {1/2, 1, 2} ...". The text
    says "the amplitudes of (5) increase with an arc length (Fig. 2)",
    which holds only with ``ds = s/n``; the caption's s = 100 gives the
    constant ``ds = 10``, whose amplitude ``b ds^2 = 100 b`` does not grow.

    Parameters
    ----------
    num : int
        Arc lengths of the text's reading, equally spaced on [0, 3].
    step : float
        Turn (radians) between samples of the caption's reading, whose
        turn ``10 exp(s)`` runs from 10 to 201 rad.

    Returns
    -------
    FigureData
        Panel 0, the text's reading ``ds = s/n`` (u and its envelope
        ``-ln A' +- b (s/n)^2``, dotted); panel 1, the caption's literal
        ``ds = 10``. ``params['u_range']`` holds the range of u for each b
        under each reading.

    Examples
    --------
    >>> fd = fig2()
    >>> round(fd.params["u_range"]["text ds = s/n"][2.0], 3), round(fd.params["u_range"]["caption ds = 10"][2.0])
    (0.256, 400)
    """
    n, level, ds = PAPER["n"], -np.log(PAPER["A"]), _ds()
    s = np.linspace(0.0, 3.0, num)
    s_lit = _s_by_phase(lambda turn: np.log(turn / ds), ds, ds * np.exp(3.0), step)
    text, literal, ranges = [], [], {"text ds = s/n": {}, "caption ds = 10": {}}
    for j, (b, col) in enumerate(zip(PAPER["b"], B_COLORS)):
        u = _u(np.exp(s) * s / n, s / n, b)
        env = b * (s / n) ** 2
        text += [Line(s, u, f"b = {b:g}", col, zorder=3 - j),
                 Line(s, level + env, None, col, ":", 0.5, zorder=1),
                 Line(s, level - env, None, col, ":", 0.5, zorder=1)]
        u_lit = _u(np.exp(s_lit) * ds, ds, b)
        literal.append(Line(s_lit, u_lit, f"b = {b:g}", col, width=0.3, zorder=3 - j))
        ranges["text ds = s/n"][b] = float(np.ptp(u))
        ranges["caption ds = 10"][b] = float(np.ptp(u_lit))
    r_text, r_lit = ranges["text ds = s/n"][2.0], ranges["caption ds = 10"][2.0]
    panels = (
        Panel(tuple(text), f"(a) the text's reading, ds = s/n: u spans {r_text:.2f} for b = 2",
              "arc length s", _U_LABEL, marks=(_level(),)),
        Panel(tuple(literal), f"(b) the caption read literally, ds = L/n = 10: u spans {r_lit:.0f} for b = 2",
              "arc length s", _U_LABEL, marks=(_level(),)),
    )
    return FigureData(
        "fig2", "fig2_u_exp_curvature.png",
        "Fig. 2: u along k(s) = exp(s) (eq. 5, A' = 1/4, n = 10); (a) as the text reads it, "
        "(b) the caption's ds = 10 for comparison", panels,
        caption=CAPTIONS["fig2"], params=_params(kappa="exp(s)", s=(0.0, 3.0), ds="s/n", u_range=ranges),
        grid=(1, 2), size=(13.0, 4.8),
        reading=(
            "The caption's s = 100 gives ds = L/n = 10; the text says the amplitudes of eq. 5 grow with "
            "arc length along this curve, which holds only with ds = s/n (the arc length so far over n, "
            "as the paper takes for eq. 7). Panel (a) follows the text; panel (b) is the caption "
            "read literally, for comparison."),
        description=(
            "Fig. 2. Eq. 5 along an MC-curve (monotone curvature) with k(s) = exp(s), s in [0, 3], A' = 1/4, "
            "n = 10, b = 1/2, 1, 2 (black, blue, red). (a) With ds = s/n, the arc length so far over n, as "
            "the paper takes for eq. 7: the amplitude b (s/n)^2 (dotted envelope) grows from 0 to 0.09 b, "
            "as the paper's text says of this figure, and u spans "
            f"{r_text:.3f} for b = 2. We follow the text. The turn k ds = exp(s) s/n grows from 0 to 6 rad; "
            "u touches its upper envelope where the turn is 2 pi/n + pi (s = 2.65). (b) The caption's "
            f"s = 100 read literally, ds = L/n = 10: the amplitude is the constant b ds^2 = 100 b (u spans "
            f"{r_lit:.1f} for b = 2, {r_lit / r_text:.0f} times (a)) and the turn 10 exp(s) runs from 10 "
            "to 201 rad, so u oscillates about 30 times over [0, 3] (sampled every 0.05 rad of turn)."))


def fig3(delta=0.01, step=0.05):
    """Fig. 3: eq. 5 along ``kappa(s) = 1/(1 - s)``, ``s in [0, 2]``, with its cusp at s = 1.

    Caption: "... for a curve with given curvature kappa(s) = (1 - s)^-1,
    s in [0; 2], s = 100, n = 10, A' = 1/4 and b = {1/2, 1, 2} ...", read
    with ``ds = 10``.

    Parameters
    ----------
    delta : float
        Half-width of the band about the cusp left undrawn (u oscillates
        without bound there: eq. 6).
    step : float
        Turn (radians) between samples.

    Returns
    -------
    FigureData
        One panel: u left and right of the cusp as separate lines.
    """
    ds = _ds()
    # turn = k ds = ds/(1 - s)  <=>  s = 1 - ds/turn
    left = _s_by_phase(lambda t: 1 - ds / t, ds, ds / delta, step)
    right = _s_by_phase(lambda t: 1 - ds / t, -ds / delta, -ds, step)
    lines = []
    for j, (b, col) in enumerate(zip(PAPER["b"], B_COLORS)):
        for side, s in enumerate((left, right)):
            lines.append(Line(s, _u(ds / (1 - s), ds, b), f"b = {b:g}" if side == 0 else None, col, width=0.5,
                              zorder=3 - j))
    panel = Panel(tuple(lines), xlabel="arc length s", ylabel=_U_LABEL,
                  marks=(_level(), Mark("x", 1.0, "cusp s = 1 (k -> +-inf, u undefined, eq. 6)", "black", "--",
                                        0.8, 6)),
                  bands=(Band(1 - delta, 1 + delta, f"|s - 1| < {delta:g}: unbounded oscillation"),))
    return FigureData(
        "fig3", "fig3_u_cusp.png", f"Fig. 3: u along k(s) = 1/(1 - s) ({_subtitle()})", (panel,),
        caption=CAPTIONS["fig3"], params=_params(ds=ds, kappa="1/(1 - s)", s=(0.0, 2.0), delta=delta),
        description=(
            "Fig. 3. Eq. 5 along k(s) = 1/(1 - s), s in [0, 2]: a cusp at s = 1 where k -> +inf from the "
            "left and -inf from the right, so u has no limit there (the paper's eq. 6). The two sides "
            "are drawn separately (never across the cusp, dashed line), sampled every 0.05 rad of turn "
            f"up to |s - 1| = {delta:g}; inside that band (grey) u oscillates without bound between "
            "-ln A' -+ b*ds^2."))


def fig4(num=3001, delta=0.01, step=0.05):
    """Fig. 4: eq. 5 along the caption's clothoid ``kappa(s) = (2 pi/n) s``, ``s in [0, 3]``.

    Caption: "... for an MC-curve (clothoid) with given curvature
    kappa = 2 pi/ns, s in [0; 3], s = 100, n = 10, A' = 1/4 and
    b = {1/2, 1, 2} ...". A clothoid's curvature is linear in arc length,
    which "2 pi/ns" is when read ``(2 pi/n) s``: that reading is drawn
    first. Read ``2 pi/(n s)`` the curvature is inversely proportional to
    s, a logarithmic spiral, not a clothoid: drawn beside it, labelled.
    Both with ``ds = 10``.

    Parameters
    ----------
    num : int
        Arc lengths of the clothoid reading, equally spaced on [0, 3].
    delta : float
        Arc length below which the spiral reading is not drawn (its turn
        ``2 pi/s`` grows without bound as s -> 0).
    step : float
        Turn (radians) between samples of the spiral reading.

    Returns
    -------
    FigureData
        Panels 0 and 2: u and kappa(s) of the clothoid reading; panels 1
        and 3: the same for ``2 pi/(n s)``.
    """
    n, ds = PAPER["n"], _ds()
    s = np.linspace(0.0, 3.0, num)
    k_clo = (2 * np.pi / n) * s
    c = 2 * np.pi * ds / n  # spiral reading: turn = c/s  <=>  s = c/turn
    s_sp = _s_by_phase(lambda t: c / t, c / delta, c / 3.0, step)
    k_sp = 2 * np.pi / (n * s_sp)
    clo, sp = [], []
    for j, (b, col) in enumerate(zip(PAPER["b"], B_COLORS)):
        clo.append(Line(s, _u(k_clo * ds, ds, b), f"b = {b:g}", col, zorder=3 - j))
        sp.append(Line(s_sp, _u(k_sp * ds, ds, b), f"b = {b:g}", col, width=0.5, zorder=3 - j))
    band = Band(0.0, delta, f"s < {delta:g}: unbounded oscillation")
    k_top = 2 * np.pi / n * 3.0
    panels = (
        Panel(tuple(clo), "(a) clothoid k(s) = (2 pi/n) s, as the caption names the curve",
              "arc length s", _U_LABEL, marks=(_level(),), xlim=(0.0, 3.0)),
        Panel(tuple(sp), "(b) the same symbols read k = 2 pi/(n s): a logarithmic spiral",
              "arc length s", _U_LABEL, marks=(_level(),), bands=(band,), xlim=(0.0, 3.0)),
        Panel((Line(s, k_clo, "k(s) = (2 pi/n) s", "black"),), "(a) curvature: linear in s (clothoid)",
              "arc length s", "curvature k", xlim=(0.0, 3.0), ylim=(0.0, 1.2 * k_top), legend="upper left"),
        Panel((Line(s_sp, k_sp, "k(s) = 2 pi/(n s)", "black"),), "(b) curvature: 1/s (logarithmic spiral)",
              "arc length s", "curvature k", xlim=(0.0, 3.0), ylim=(0.0, 1.2 * k_top), legend="upper right",
              bands=(Band(0.0, delta),)),
    )
    return FigureData(
        "fig4", "fig4_u_clothoid.png",
        f"Fig. 4: u along the caption's clothoid k = (2 pi/n) s (a), and k = 2 pi/(n s) (b) ({_subtitle()})",
        panels, caption=CAPTIONS["fig4"],
        params=_params(ds=ds, kappa="(2*pi/n)*s", kappa_other_reading="2*pi/(n*s)", s=(0.0, 3.0), delta=delta),
        grid=(2, 2), size=(13.0, 8.5),
        reading=(
            "The caption prints kappa = 2 pi/ns and calls the curve a clothoid. A clothoid's curvature is "
            "linear in arc length: kappa = (2 pi/n) s. Read 2 pi/(n s), the radius of curvature n s/(2 pi) is "
            "proportional to s, which makes a logarithmic spiral (pseudospiral m = 1), not a clothoid. "
            "Panel (a) follows the caption's word; panel (b) shows the other reading of the same symbols."),
        description=(
            "Fig. 4. (a) Eq. 5 along the clothoid k(s) = (2 pi/n) s, s in [0, 3] (A' = 1/4, L = 100, n = 10, "
            "ds = 10; b = 1/2, 1, 2 in black, blue, red): the reading of the caption's 'kappa = 2 pi/ns' that "
            "makes the curve the clothoid the caption names (curvature linear in s, panel below). The turn "
            "k ds = 2 pi s grows by one full turn per unit of arc length, so u runs through one period of "
            "amplitude b ds^2 per unit of s, lowest where 2 pi s = 2 pi/n (s = 0.1, 1.1, 2.1). (b) The same "
            "symbols read k = 2 pi/(n s), for comparison: a logarithmic spiral (curvature proportional to "
            "1/s), whose turn 2 pi/s grows without bound as s -> 0, so u oscillates ever faster there "
            f"(grey band, s < {delta:g}, not drawn); for s > 1 it is below one period."))


# --------------------------------------------------------------------------- Figs. 5-6 (eq. 7)


def eq7_arc_lengths(C, num=2001):
    """Arc lengths on eq. 7's domain ``[sqrt(|C|) n, 5]`` (n = 10), clustered at its start.

    Eq. 7's curvature has a square-root slope at the start of its domain,
    so the points are spaced quadratically from there. For C = 0 the
    domain is (0, 5]; it starts at 5/500.
    """
    from attneave.stimuli.curves.constant_info import constant_info_domain

    s_min = constant_info_domain(C, EQ7["n"])
    if s_min == 0:
        s_min = EQ7["s_end"] / 500
    t = np.linspace(0.0, 1.0, num)
    return s_min + (EQ7["s_end"] - s_min) * t * t


def _eq7_figure(Cs, number, filename, description):
    from attneave.stimuli.curves.constant_info import constant_info_curvature, constant_info_domain

    lines = []
    for C, col in zip(Cs, C_COLORS):
        s = eq7_arc_lengths(C)
        k = constant_info_curvature(s, C, EQ7["n"])
        lines.append(Line(s, k, f"C = {C:g}", col, width=1.2))
        if constant_info_domain(C, EQ7["n"]) > 0:
            lines.append(Line(s[:1], k[:1], None, col, "", marker="o", size=4))
    sign = "C >= 0" if min(Cs) >= 0 else "C <= 0"
    panel = Panel(tuple(lines), xlabel="arc length s", ylabel="curvature k(s)", xlim=(0.0, EQ7["s_end"]),
                  ylim=(0.0, 50.0), legend="upper right")
    return FigureData(
        f"fig{number}", filename,
        f"Fig. {number}: eq. 7 curvature, n = {EQ7['n']}, {sign} (dots: start of domain s = sqrt(|C|) n)",
        (panel,), caption=CAPTIONS[f"fig{number}"], params=dict(n=EQ7["n"], C=Cs, s=(0.0, EQ7["s_end"])),
        description=description, size=(7.0, 4.2))


def fig5():
    """Fig. 5: eq. 7's curvature for ``C = 0, 0.01, 0.02, 0.03``, ``n = 10``.

    Caption: "Curvature function (7) for C = 0, 1e-2, 2e-2, 3e-2 (for red,
    green, yellow and blue, respectively) and n = 10, s in [0; 5]". Eq. 7 is
    defined only for ``s >= sqrt(|C|) n``, where each line starts (dot).
    """
    return _eq7_figure(EQ7["C_pos"], 5, "fig5_eq7_curvature_pos.png", (
        "Fig. 5. Eq. 7's curvature k(s) = (1/s)(n arccos(C n^2/s^2) + 2 pi), n = 10, for C = 0, 0.01, "
        "0.02, 0.03 (red, green, yellow, blue), drawn only where defined, s >= sqrt(|C|) n (dots: "
        "1, 1.41, 1.73); y clipped at 50. For C > 0 the curvature starts at 2 pi/s_min, rises and "
        "then falls, so it is not monotone. For C = 0, k = (pi/s)(n/2 + 2): a logarithmic spiral."))


def fig6():
    """Fig. 6: eq. 7's curvature for ``C = 0, -0.01, -0.02, -0.03``, ``n = 10``.

    Caption: "Curvature function (7) for C = 0, -1e-2, -2e-2, -3e-2 (for red,
    green, yellow and blue, respectively) and n = 10, s in [0; 5]".
    """
    return _eq7_figure(EQ7["C_neg"], 6, "fig6_eq7_curvature_neg.png", (
        "Fig. 6. As Fig. 5 for C = 0, -0.01, -0.02, -0.03. For C <= 0 the curvature decreases "
        "strictly from (n pi + 2 pi)/s_min, so these are MC-curves (monotone curvature)."))


def eq7_constant_u(b=1.0, num=400):
    """Companion of Figs. 5-6: eq. 5 along eq. 7's curvature is constant.

    With ``ds = s/n``, ``k ds - 2 pi/n = arccos(C n^2/s^2)``, so eq. 5 gives
    ``u = -ln A' - b (s/n)^2 (C n^2/s^2) = -ln A' - b C`` for every s; this
    figure evaluates it with :func:`surprisal_paper` to show it.

    Returns
    -------
    FigureData
        One panel: u(s) for C = 0, +-0.01, +-0.02, +-0.03 (solid C >= 0,
        dashed C < 0), A' = 1/4, n = 10.
    """
    from attneave.stimuli.curves.constant_info import constant_info_curvature

    n, lines = EQ7["n"], []
    for Cs, style, colors in ((EQ7["C_pos"], "-", C_COLORS), (EQ7["C_neg"][1:], "--", C_COLORS[1:])):
        for C, col in zip(Cs, colors):
            s = eq7_arc_lengths(C, num)
            k = constant_info_curvature(s, C, n)
            lines.append(Line(s, _u(k * s / n, s / n, b), f"C = {C:g}: u = {-np.log(PAPER['A']) - b * C:.4f}",
                              col, style, 1.2))
    panel = Panel(tuple(lines), xlabel="arc length s", ylabel="u (nats), eq. 5 with ds = s/n",
                  xlim=(0.0, EQ7["s_end"]))
    return FigureData(
        "eq7_constant_u", "fig_eq7_constant_u.png",
        "Eq. 5 along eq. 7's curvature: constant u = -ln A' - b C (A' = 1/4, b = 1, n = 10)", (panel,),
        params=dict(A=PAPER["A"], b=b, n=n, ds="s/n", C=EQ7["C_pos"] + EQ7["C_neg"][1:]), size=(8.0, 5.0),
        description=(
            "Companion to Figs. 5-6: eq. 5 evaluated along eq. 7's curvature with ds = s/n (A' = 1/4, "
            "b = 1, n = 10). Since k ds - 2 pi/n = arccos(C n^2/s^2), u = -ln A' - b (s/n)^2 (C n^2/s^2) "
            "= -ln A' - b C: a constant for each C (solid C >= 0, dashed C < 0)."))


#: Every figure, by name, in the order ``attneave figures`` writes them:
#: the paper's Figs. 1-6, two companions, and the Fig. 10 analogue. Each
#: value is a function of no required argument returning a FigureData.
FIGURES = {
    "fig1": fig1,
    "fig2": fig2,
    "fig3": fig3,
    "fig4": fig4,
    "fig5": fig5,
    "fig6": fig6,
    "eq7_constant_u": eq7_constant_u,
    "curve_families": curve_families,
    "fig10": fig10,
}
