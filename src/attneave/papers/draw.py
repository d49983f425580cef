"""Drawing the paper's figures: a :class:`~attneave.papers.base.FigureData` to a picture.

:func:`draw` makes a matplotlib figure of one figure's data,
:func:`png_bytes` its PNG, and :func:`make_figures` writes every figure of
:data:`attneave.papers.ziatdinov.FIGURES` into a directory with a note,
``figures.md``, that says what each shows and how its caption was read
(``attneave figures``). The figures' data never need matplotlib; only this
module does.

Adding a figure
---------------
Write a function returning a :class:`~attneave.papers.base.FigureData` and
add it to :data:`attneave.papers.ziatdinov.FIGURES`; record its fingerprint
in the tests (``python tests/test_papers.py --update``).
"""

from __future__ import annotations

import io
from pathlib import Path

__all__ = ["draw", "png_bytes", "make_figures", "NOTE_NAME"]

NOTE_NAME = "figures.md"


def _panel(ax, panel):
    for line in panel.lines:
        ax.plot(line.x, line.y, color=line.color, ls=line.style or "none", lw=line.width, marker=line.marker or None,
                ms=line.size, mfc=line.face or line.color, mec=line.color, zorder=line.zorder, label=line.label)
    for m in panel.marks:
        place = ax.axvline if m.axis == "x" else ax.axhline
        place(m.at, color=m.color, ls=m.style, lw=m.width, zorder=m.zorder, label=m.label)
    for band in panel.bands:
        ax.axvspan(band.x0, band.x1, color=band.color, lw=0, zorder=5, label=band.label)
    if panel.xlim is not None:
        ax.set_xlim(*panel.xlim)
    if panel.ylim is not None:
        ax.set_ylim(*panel.ylim)
    if panel.equal:
        ax.set_aspect("equal", adjustable="datalim")
    if panel.y_down and not ax.yaxis_inverted():
        ax.invert_yaxis()
    if not panel.ticks:
        ax.set_xticks([])
        ax.set_yticks([])
    ax.set_xlabel(panel.xlabel)
    ax.set_ylabel(panel.ylabel)
    ax.set_title(panel.title, fontsize=9)
    if panel.text:
        ax.text(0.02, 0.95, panel.text, transform=ax.transAxes, fontsize=8, va="top")
    if panel.legend and ax.get_legend_handles_labels()[1]:
        if panel.legend == "below":
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=panel.columns,
                      fontsize=7 if panel.columns > 2 else 6, frameon=False)
        else:
            ax.legend(loc=panel.legend, fontsize=8)


def draw(fig_data):
    """Draw a figure's data with matplotlib (Agg backend).

    Parameters
    ----------
    fig_data : FigureData
        From a function of :data:`attneave.papers.ziatdinov.FIGURES`.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, its panels on ``fig_data.grid``; close it when done
        (:func:`png_bytes` does).

    Examples
    --------
    >>> from attneave.papers.ziatdinov import fig1
    >>> fig = draw(fig1())
    >>> len(fig.axes)
    1
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    from attneave.analysis.report.figure_files import pyplot

    plt = pyplot()
    rows, cols = fig_data.grid
    fig, axes = plt.subplots(rows, cols, figsize=fig_data.size, squeeze=False)
    for ax, panel in zip(axes.ravel(), fig_data.panels):
        _panel(ax, panel)
    if fig_data.title:
        if rows * cols == 1:
            axes[0, 0].set_title(fig_data.title, fontsize=9)
        else:
            fig.suptitle(fig_data.title, fontsize=11)
    fig.tight_layout()
    return fig


def png_bytes(fig_data):
    """The PNG of :func:`draw` (the matplotlib figure is closed)."""
    from attneave.analysis.report.figure_files import DPI, pyplot

    fig = draw(fig_data)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": None})
    finally:
        pyplot().close(fig)
    return buf.getvalue()


def _note(entries):
    lines = [
        "# Figures",
        "",
        "Reproductions of Figs. 1-6 of Ziatdinov, *Visual perception, quantity of information function "
        "and the concept of the quantity of information continuous splines*, written by "
        "`attneave figures` (data: `attneave.papers.ziatdinov`, one function per figure), with "
        "companions and a Fig. 10 analogue.",
        "",
    ]
    for path, fd in entries:
        lines += [f"## {path.name}", "", fd.description, ""]
        if fd.reading:
            lines += [f"Reading of the caption: {fd.reading}", ""]
        if fd.caption:
            lines += [f"The paper's caption: {fd.caption}", ""]
    return "\n".join(lines)


def make_figures(outdir, names=None):
    """Write the paper's figures as PNG files and a note describing them.

    Parameters
    ----------
    outdir : str or Path
        Output directory; created if missing (its parent must exist).
    names : sequence of str, optional
        Keys of :data:`attneave.papers.ziatdinov.FIGURES` to write, in order
        (default all).

    Returns
    -------
    list of Path
        Every file written: the PNGs in order, then ``figures.md``. Each is
        written atomically.

    Raises
    ------
    InputError
        If `outdir` exists and is not a directory, its parent is missing, or
        a name is not a figure.
    """
    from attneave.papers import ziatdinov
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import atomic_write

    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"{outdir}: exists and is not a directory")
    if not outdir.parent.is_dir():
        raise InputError(f"{outdir}: parent directory {outdir.parent} does not exist")
    figures = ziatdinov.FIGURES  # looked up now, so that a replaced registry is used
    names = list(figures) if names is None else list(names)
    unknown = [n for n in names if n not in figures]
    if unknown:
        raise InputError(f"figures: no figure named {', '.join(unknown)} (known: {', '.join(figures)})")
    outdir.mkdir(exist_ok=True)
    entries = []
    for name in names:
        fd = figures[name]()
        path = outdir / fd.filename
        data = png_bytes(fd)
        with atomic_write(path, "wb") as fh:
            fh.write(data)
        entries.append((path, fd))
    note = outdir / NOTE_NAME
    with atomic_write(note, "w") as fh:
        fh.write(_note(entries))
    return [p for p, _ in entries] + [note]
