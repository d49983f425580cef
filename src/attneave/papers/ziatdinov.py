"""The seed paper's figures 1-6 (and companions), drawn from the library's own functions.

:func:`make_figures` writes every figure listed in :data:`FIGURE_MAKERS` into a
directory, then a note (``figures.md``) saying what each shows.

Adding a figure
---------------
Write a function ``maker(outdir: pathlib.Path) -> list[tuple[Path, str]]``
that saves its PNG(s) with :func:`save_png` and returns, for each file, the
path and a one-paragraph description for the note; then append it to
:data:`FIGURE_MAKERS` (the QIC-spline Fig. 10 analogue goes there).

Parameters of the paper's figures
----------------------------------
Eq. 5, ``u(k) = -ln A' - b ds^2 cos(k ds - 2 pi/n)``, with ``A' = 1/4``,
``L = 100``, ``n = 10`` (so ``ds = L/n = 10``) and ``b`` in ``{1/2, 1, 2}``
(black, blue, red as in the paper), evaluated with
:func:`stimuli.information.surprisal_paper` on the turning angle
``a = k ds``; ds is in the paper's literal units of length (``length_unit``
'px'). Fig. 2 alone takes ``ds = s/n``, as the paper does for eq. 7: its
text says that the amplitudes of eq. 5 grow with arc length along an
MC-curve, which holds only then (with ``ds = L/n`` the amplitude is the
constant ``b ds^2``). Eq. 7 with ``n = 10`` and ``C`` in ``{0, +-0.01,
+-0.02, +-0.03}`` on ``s`` in ``(0, 5]`` where it is defined.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.analysis.report.figure_files import pyplot, save_png  # noqa: F401  (save_png: part of this module's face)

__all__ = ["make_figures", "save_png", "fig2_curve", "FIGURE_MAKERS", "PAPER", "NOTE_NAME"]

#: Parameters of the paper's Figs. 1-4 (eq. 5).
PAPER = dict(A=0.25, L=100.0, n=10, b=(0.5, 1.0, 2.0))
#: Eq. 7's constants in Figs. 5 and 6.
EQ7_C_POS = (0.0, 0.01, 0.02, 0.03)
EQ7_C_NEG = (0.0, -0.01, -0.02, -0.03)
EQ7_N = 10
EQ7_S_END = 5.0
NOTE_NAME = "figures.md"

_B_COLORS = ("black", "tab:blue", "tab:red")  # the paper's colours for b = 1/2, 1, 2
_C_COLORS = ("tab:red", "tab:green", "gold", "tab:blue")  # the paper's colours in Figs. 5-6


_plt = pyplot  # the module's own short name for it


def _ds():
    return PAPER["L"] / PAPER["n"]


def _u(k, b):
    """Eq. 5 along curvature `k` with the paper's A', L, n."""
    from attneave.stimuli.geometry.information import surprisal_paper

    ds = _ds()
    return surprisal_paper(turning_angle=np.asarray(k) * ds, ds=ds, n=PAPER["n"], A=PAPER["A"], b=b, closed=True)


def _u_axes(ax, xlabel):
    ax.set_xlabel(xlabel)
    ax.set_ylabel("quantity of information u (nats)")
    ax.axhline(-np.log(PAPER["A"]), color="0.7", lw=0.6, zorder=0)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8, frameon=False)
    ax.figure.tight_layout()


def _subtitle():
    return f"eq. 5, A' = 1/4, L = {PAPER['L']:g}, n = {PAPER['n']}, ds = {_ds():g}"


def _s_by_phase(s_of_phase, phase_lo, phase_hi, step=0.05):
    """Arc lengths at which the phase ``k ds`` is sampled every `step` radians.

    Near a curvature singularity u oscillates without bound in s; sampling
    equally in phase resolves every oscillation that is drawn.
    """
    m = int(np.ceil(abs(phase_hi - phase_lo) / step)) + 1
    return s_of_phase(np.linspace(phase_lo, phase_hi, m))


# --------------------------------------------------------------------------- Figs. 1-4 (eq. 5)


def fig1(outdir):
    """Fig. 1: eq. 5 as a function of curvature, k in [-1, 1]."""
    plt = _plt()
    k = np.linspace(-1.0, 1.0, 4001)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for j, (b, col) in enumerate(zip(PAPER["b"], _B_COLORS)):
        ax.plot(k, _u(k, b), color=col, lw=1, zorder=3 - j, label=f"b = {b:g}")
    kmin = 2 * np.pi / PAPER["n"] / _ds()
    ax.axvline(kmin, color="0.5", ls=":", lw=0.8)
    ax.set_title(f"Fig. 1: u over curvature ({_subtitle()})", fontsize=9)
    _u_axes(ax, "curvature k (1/length)")
    path = save_png(fig, Path(outdir) / "fig1_u_vs_curvature.png")
    return [(path, (
        "Fig. 1. Eq. 5 over curvature k in [-1, 1] (A' = 1/4, L = 100, n = 10, ds = 10; b = 1/2, 1, 2 "
        "in black, blue, red). u is periodic in k with period 2*pi/ds; its minima sit where the "
        "turn k*ds equals the mean turn 2*pi/n (k = 2*pi/(n ds) = 0.0628, dotted line), i.e. where "
        "the tangent turns slightly inward; the amplitude is b*ds^2."
    ))]


def fig2_curve(b, s_end=3.0, num=20001):
    """The data of Fig. 2: eq. 5 along ``k(s) = exp(s)`` with ``ds = s/n``.

    Parameters
    ----------
    b : float
        Concentration ``b`` of eq. 5.
    s_end : float
        Arc length at the end (the paper's 3).
    num : int
        Number of arc lengths, equally spaced on ``[0, s_end]``.

    Returns
    -------
    s, u : ndarray
        Arc length and ``u = -ln A' - b (s/n)^2 cos(exp(s) s/n - 2 pi/n)``
        with the paper's ``A' = 1/4``, ``n = 10``; its amplitude about
        ``-ln A'`` is at most ``b (s/n)^2``, growing with s.

    Examples
    --------
    >>> s, u = fig2_curve(1.0, num=4)
    >>> bool(abs(u[0] + np.log(0.25)) < 1e-12)  # no amplitude at s = 0
    True
    """
    from attneave.stimuli.geometry.information import surprisal_paper

    s = np.linspace(0.0, s_end, num)
    ds = s / PAPER["n"]
    return s, surprisal_paper(turning_angle=np.exp(s) * ds, ds=ds, n=PAPER["n"], A=PAPER["A"], b=b, closed=True)


def fig2(outdir):
    """Fig. 2: eq. 5 along k = exp(s), s in [0, 3], with ds = s/n (its amplitude grows with s)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for j, (b, col) in enumerate(zip(PAPER["b"], _B_COLORS)):
        s, u = fig2_curve(b)
        ax.plot(s, u, color=col, lw=1, zorder=3 - j, label=f"b = {b:g}")
        env = b * (s / PAPER["n"]) ** 2
        ax.plot(s, -np.log(PAPER["A"]) + env, color=col, lw=0.5, ls=":", zorder=1)
        ax.plot(s, -np.log(PAPER["A"]) - env, color=col, lw=0.5, ls=":", zorder=1)
    ax.set_title(f"Fig. 2: u along k(s) = exp(s) (eq. 5, A' = 1/4, n = {PAPER['n']}, ds = s/n; "
                 "dotted: -ln A' +- b (s/n)^2)", fontsize=9)
    _u_axes(ax, "arc length s")
    path = save_png(fig, Path(outdir) / "fig2_u_exp_curvature.png")
    return [(path, (
        "Fig. 2. Eq. 5 along an MC-curve (monotone curvature) with k(s) = exp(s), s in [0, 3], A' = 1/4, "
        "n = 10, b = 1/2, 1, 2 (black, blue, red), with ds = s/n, the arc length so far over n, as the "
        "paper takes for eq. 7. The paper's text says that the amplitudes of eq. 5 grow with arc length "
        "here; that holds with ds = s/n, whose amplitude b (s/n)^2 (dotted envelope) grows from 0 to "
        "0.09 b, and not with the caption's ds = L/n = 10, whose amplitude is the constant b ds^2 = 100 b. "
        "We follow the text. The turn k ds = exp(s) s/n grows from 0 to 6 rad; u touches its upper "
        "envelope where the turn is 2 pi/n + pi (s = 2.65)."
    ))]


def fig3(outdir, delta=0.01):
    """Fig. 3: eq. 5 along k = 1/(1 - s), s in [0, 2], with the cusp at s = 1."""
    plt = _plt()
    ds = _ds()
    # phase = k*ds = ds/(1 - s)  <=>  s = 1 - ds/phase
    left = _s_by_phase(lambda ph: 1 - ds / ph, ds, ds / delta)
    right = _s_by_phase(lambda ph: 1 - ds / ph, -ds / delta, -ds)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for j, (b, col) in enumerate(zip(PAPER["b"], _B_COLORS)):
        for side, s in enumerate((left, right)):
            ax.plot(s, _u(1 / (1 - s), b), color=col, lw=0.5, zorder=3 - j,
                    label=f"b = {b:g}" if side == 0 else None)
    lo = -np.log(PAPER["A"]) - max(PAPER["b"]) * ds * ds
    hi = -np.log(PAPER["A"]) + max(PAPER["b"]) * ds * ds
    ax.fill_between([1 - delta, 1 + delta], lo, hi, color="0.6", lw=0, zorder=5,
                    label=f"|s - 1| < {delta:g}: unbounded oscillation")
    ax.axvline(1.0, color="k", ls="--", lw=0.8, zorder=6, label="cusp s = 1 (k -> +-inf, u undefined, eq. 6)")
    ax.set_title(f"Fig. 3: u along k(s) = 1/(1 - s) ({_subtitle()})", fontsize=9)
    _u_axes(ax, "arc length s")
    path = save_png(fig, Path(outdir) / "fig3_u_cusp.png")
    return [(path, (
        "Fig. 3. Eq. 5 along k(s) = 1/(1 - s), s in [0, 2]: a cusp at s = 1 where k -> +inf from the "
        "left and -inf from the right, so u has no limit there (the paper's eq. 6). The two sides "
        f"are drawn separately (never across the cusp, dashed line), sampled every 0.05 rad of turn "
        f"up to |s - 1| = {delta:g}; inside that band (grey) u oscillates without bound between "
        "-ln A' -+ b*ds^2."
    ))]


def fig4(outdir, delta=0.01):
    """Fig. 4: eq. 5 along k = 2*pi/(n*s), s in (0, 3]."""
    plt = _plt()
    n, ds = PAPER["n"], _ds()
    # phase = k*ds = 2*pi*ds/(n*s)  <=>  s = 2*pi*ds/(n*phase)
    c = 2 * np.pi * ds / n
    s = _s_by_phase(lambda ph: c / ph, c / delta, c / 3.0)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for j, (b, col) in enumerate(zip(PAPER["b"], _B_COLORS)):
        ax.plot(s, _u(2 * np.pi / (n * s), b), color=col, lw=0.5, zorder=3 - j, label=f"b = {b:g}")
    lo = -np.log(PAPER["A"]) - max(PAPER["b"]) * ds * ds
    hi = -np.log(PAPER["A"]) + max(PAPER["b"]) * ds * ds
    ax.fill_between([0, delta], lo, hi, color="0.6", lw=0, zorder=5, label=f"s < {delta:g}: unbounded oscillation")
    ax.set_xlim(0, 3)
    ax.set_title(f"Fig. 4: u along k(s) = 2 pi/(n s) ({_subtitle()})", fontsize=9)
    _u_axes(ax, "arc length s")
    path = save_png(fig, Path(outdir) / "fig4_u_log_spiral.png")
    return [(path, (
        "Fig. 4. Eq. 5 along k(s) = 2*pi/(n*s), s in (0, 3]. The paper calls this curve a clothoid; "
        "rho = n*s/(2*pi) is proportional to s, so it is a logarithmic spiral (pseudospiral m = 1). "
        "The turn k*ds = 2*pi/s grows without bound as s -> 0, so u oscillates ever faster there "
        f"(grey band, s < {delta:g}, not drawn); for s > 1 it is below one period."
    ))]


# --------------------------------------------------------------------------- Figs. 5-6 (eq. 7)


def _eq7_s(C, n=EQ7_N, s_end=EQ7_S_END, num=2001):
    from attneave.stimuli.curves.constant_info import constant_info_domain

    s_min = constant_info_domain(C, n)
    if s_min == 0:
        # C = 0: k = (pi/s)(n/2 + 2) is defined on all of (0, s_end]; start where it fits the plot
        s_min = s_end / 500
    # cluster points near the domain start, where k has a square-root slope
    t = np.linspace(0.0, 1.0, num)
    return s_min + (s_end - s_min) * t * t


def _eq7_figure(outdir, Cs, number, name):
    from attneave.stimuli.curves.constant_info import constant_info_curvature, constant_info_domain

    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ymax = 50.0
    for C, col in zip(Cs, _C_COLORS):
        s = _eq7_s(C)
        k = constant_info_curvature(s, C, EQ7_N)
        ax.plot(s, k, color=col, lw=1.2, label=f"C = {C:g}")
        s_min = constant_info_domain(C, EQ7_N)
        if s_min > 0:
            ax.plot([s_min], [k[0]], "o", color=col, ms=4)
    ax.set_xlim(0, EQ7_S_END)
    ax.set_ylim(0, ymax)
    ax.set_xlabel("arc length s")
    ax.set_ylabel("curvature k(s)")
    sign = "C >= 0" if min(Cs) >= 0 else "C <= 0"
    ax.set_title(f"Fig. {number}: eq. 7 curvature, n = {EQ7_N}, {sign} (dots: start of domain s = sqrt(|C|) n)",
                 fontsize=9)
    ax.legend(loc="upper right", fontsize=8)
    return save_png(fig, Path(outdir) / name)


def fig5(outdir):
    """Fig. 5: eq. 7's curvature for C = 0, 0.01, 0.02, 0.03."""
    path = _eq7_figure(outdir, EQ7_C_POS, 5, "fig5_eq7_curvature_pos.png")
    return [(path, (
        "Fig. 5. Eq. 7's curvature k(s) = (1/s)(n arccos(C n^2/s^2) + 2 pi), n = 10, for C = 0, 0.01, "
        "0.02, 0.03 (red, green, yellow, blue), drawn only where defined, s >= sqrt(|C|) n (dots: "
        "1, 1.41, 1.73); y clipped at 50. For C > 0 the curvature starts at 2 pi/s_min, rises and "
        "then falls, so it is not monotone. For C = 0, k = (pi/s)(n/2 + 2): a logarithmic spiral."
    ))]


def fig6(outdir):
    """Fig. 6: eq. 7's curvature for C = 0, -0.01, -0.02, -0.03."""
    path = _eq7_figure(outdir, EQ7_C_NEG, 6, "fig6_eq7_curvature_neg.png")
    return [(path, (
        "Fig. 6. As Fig. 5 for C = 0, -0.01, -0.02, -0.03. For C <= 0 the curvature decreases "
        "strictly from (n pi + 2 pi)/s_min, so these are MC-curves (monotone curvature)."
    ))]


# --------------------------------------------------------------------------- companions


def fig_eq7_u(outdir):
    """Eq. 5 along eq. 7's curvature with ds = s/n: constant u = -ln A' - b C."""
    from attneave.stimuli.curves.constant_info import constant_info_curvature
    from attneave.stimuli.geometry.information import surprisal_paper

    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5))
    b, n = 1.0, EQ7_N
    for Cs, ls in ((EQ7_C_POS, "-"), (EQ7_C_NEG[1:], "--")):
        for C, col in zip(Cs, _C_COLORS if ls == "-" else _C_COLORS[1:]):
            s = _eq7_s(C, num=400)
            k = constant_info_curvature(s, C, n)
            u = surprisal_paper(turning_angle=k * s / n, ds=s / n, n=n, A=PAPER["A"], b=b, closed=True)
            ax.plot(s, u, ls, color=col, lw=1.2, label=f"C = {C:g}: u = {-np.log(PAPER['A']) - b * C:.4f}")
    ax.set_xlim(0, EQ7_S_END)
    ax.set_xlabel("arc length s")
    ax.set_ylabel("u (nats), eq. 5 with ds = s/n")
    ax.set_title("Eq. 5 along eq. 7's curvature: constant u = -ln A' - b C (A' = 1/4, b = 1, n = 10)",
                 fontsize=9)
    ax.legend(fontsize=7, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.13), frameon=False)
    fig.tight_layout()
    path = save_png(fig, Path(outdir) / "fig_eq7_constant_u.png")
    return [(path, (
        "Companion to Figs. 5-6: eq. 5 evaluated along eq. 7's curvature with ds = s/n (A' = 1/4, "
        "b = 1, n = 10). Since k ds - 2 pi/n = arccos(C n^2/s^2), u = -ln A' - b (s/n)^2 (C n^2/s^2) "
        "= -ln A' - b C: a constant for each C (solid C >= 0, dashed C < 0)."
    ))]


def fig_curves(outdir):
    """Gallery of the paper's curve families (y-up coordinates)."""
    from attneave.stimuli import curves

    plt = _plt()
    fig, axes = plt.subplots(2, 3, figsize=(11, 8))
    panels = []

    ax = axes[0, 0]
    for c_, col in ((1.0, "k"), (-1.0, "tab:red")):
        cl = curves.clothoid(0.0, c_, -3.0, 3.0, 801)
        ax.plot(cl.x, cl.y, color=col, lw=1, label=f"k = {c_:g} s, s in [-3, 3]")
    panels.append((ax, "clothoid, k = k0 + c s"))

    ax = axes[0, 1]
    for m, rng, col in ((1.0, (0.05, 6.0), "k"), (-1.0, (0.0, 2.0), "tab:blue"), (0.5, (0.001, 4.0), "tab:red")):
        ps = curves.pseudospiral(0.2, m, *rng, 1601)
        ax.plot(ps.x, ps.y, color=col, lw=0.8, label=f"m = {m:g}, s in [{rng[0]:g}, {rng[1]:g}]")
    panels.append((ax, "pseudospirals rho = 0.2 s^m (eq. 8)"))

    ax = axes[0, 2]
    lam = 1.0
    for alpha, col in zip((-1.0, 0.0, 1.0, 2.0), ("k", "tab:blue", "tab:red", "tab:green")):
        # the arc on which the curvature falls from 10 to 0.2
        k = np.array([10.0, 0.2])
        s_rng = -np.log(k) / lam if alpha == 0 else (k ** (-alpha) - 1) / (lam * alpha)
        lac = curves.log_aesthetic(alpha, lam, *s_rng, 1601)
        ax.plot(lac.x, lac.y, color=col, lw=0.8, label=f"alpha = {alpha:g}")
    panels.append((ax, "LAC (eq. 9), lam = 1, k from 10 to 0.2"))

    ax = axes[1, 0]
    for (a, b, c), col in (((1.0, 1.0, 2.0), "k"), ((2.0, 1.0, 3.0), "tab:blue"), ((0.5, 1.0, 1.5), "tab:red")):
        sp = curves.superspiral(a, b, c, 4 * np.pi, 801)
        ax.plot(sp.x, sp.y, color=col, lw=0.8, label=f"(a, b, c) = ({a:g}, {b:g}, {c:g})")
    panels.append((ax, "superspirals, theta in [0, 4 pi] (eq. 10)"))

    ax = axes[1, 1]
    for C, col in zip((0.0, 0.03, -0.03), ("tab:red", "tab:blue", "tab:green")):
        s0 = max(curves.constant_info_domain(C, EQ7_N), 1.0)
        ci = curves.constant_info(C, EQ7_N, s0, EQ7_S_END, 1601)
        ax.plot(ci.x, ci.y, color=col, lw=0.8, label=f"C = {C:g}, s in [{s0:.3g}, 5]")
    panels.append((ax, "constant-information curves (eq. 7), n = 10"))

    ax = axes[1, 2]
    for C, col in zip((0.0, 0.03, -0.03), ("tab:red", "tab:blue", "tab:green")):
        s0 = max(curves.constant_info_domain(C, EQ7_N), 1.0)
        ci = curves.constant_info(C, EQ7_N, s0, EQ7_S_END, 801)
        ax.plot(ci.s, ci.curvature, color=col, lw=1, label=f"C = {C:g}")
    ax.set_xlabel("arc length s")
    ax.set_ylabel("curvature")
    ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    ax.set_title("their curvature", fontsize=9)

    for ax, title in panels:
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (y up)")
        ax.set_ylabel("y")
        ax.set_title(title, fontsize=9)
        ax.plot([0], [0], "o", color="0.3", ms=3, zorder=5)
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    fig.tight_layout()
    path = save_png(fig, Path(outdir) / "fig_curves.png")
    return [(path, (
        "The curve families of sections 2.2 and 3 from `attneave.stimuli.curves.natural` (y-up coordinates, each "
        "starting at the origin, grey dot, heading along +x): clothoids, pseudospirals (m = 1 "
        "logarithmic spiral, m = -1 Cornu spiral, m = 1/2 involute of a circle), log-aesthetic "
        "curves (alpha = -1 clothoid, 0 Nielsen's spiral, 1 logarithmic spiral, 2 involute), "
        "superspirals, and eq. 7's constant-information curves with their curvature."
    ))]


#: Figure makers run by :func:`make_figures`, in order. Each takes the output
#: directory and returns ``[(path, description), ...]``. Append new makers
#: here (e.g. the QIC-spline Fig. 10 analogue from ``attneave.stimuli.curves.splines``).
FIGURE_MAKERS = [fig1, fig2, fig3, fig4, fig5, fig6, fig_eq7_u, fig_curves]

from attneave.papers.spline_plots import fig10_maker  # noqa: E402  (QIC-spline Fig. 10 analogue; no circle)

FIGURE_MAKERS.append(fig10_maker)


def make_figures(outdir, makers=None):
    """Write the paper's figures and a note describing them.

    Parameters
    ----------
    outdir : str or Path
        Output directory; created if missing (its parent must exist).
    makers : sequence of callables, optional
        Figure makers to run (default :data:`FIGURE_MAKERS`).

    Returns
    -------
    list of Path
        Every file written: the PNGs in order, then ``figures.md``.

    Raises
    ------
    InputError
        If `outdir` exists and is not a directory, or its parent is missing.
    """
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import atomic_write

    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"{outdir}: exists and is not a directory")
    if not outdir.parent.is_dir():
        raise InputError(f"{outdir}: parent directory {outdir.parent} does not exist")
    outdir.mkdir(exist_ok=True)
    makers = FIGURE_MAKERS if makers is None else makers
    entries = []
    for maker in makers:
        entries.extend(maker(outdir))
    lines = [
        "# Figures",
        "",
        "Reproductions of Figs. 1-6 of Ziatdinov, *Visual perception, quantity of information function "
        "and the concept of the quantity of information continuous splines*, written by "
        "`attneave figures` (module `attneave.papers.ziatdinov`), with companions.",
        "",
    ]
    for path, text in entries:
        lines += [f"## {path.name}", "", text, ""]
    note = outdir / NOTE_NAME
    with atomic_write(note, "w") as fh:
        fh.write("\n".join(lines))
    return [p for p, _ in entries] + [note]
