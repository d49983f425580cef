"""What a reproduced figure is: its data, apart from any drawing.

Every figure function of :mod:`attneave.papers.ziatdinov` returns a
:class:`FigureData`: the arrays of every line it plots (in :class:`Line`,
grouped by axes in :class:`Panel`), the parameters read from the paper's
caption, the caption itself, and a note on any reading decision. Nothing
here imports matplotlib; :func:`attneave.papers.draw.draw` turns a
:class:`FigureData` into a picture. This follows the ``papers`` layer of
stimupy [1]_, where each stimulus of a paper is a function returning data.

:func:`fingerprint` condenses a figure's arrays into a few numbers per array,
so that a test can notice an accidental change to any plotted curve.

References
----------
.. [1] Schmittwilken, L., Maertens, M. & Vincent, J. (2023). stimupy: A
       Python package for creating stimuli in vision science. Journal of
       Open Source Software 8(86), 5321 (module ``stimupy.papers``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Line", "Mark", "Band", "Panel", "FigureData", "fingerprint", "PAPER", "EQ7", "B_COLORS", "C_COLORS"]

#: Eq. 5's parameters in the captions of Figs. 1-4: "s = 100, n = 10, A' = 1/4
#: and b = {1/2, 1, 2} for black, blue and red lines" (the caption's s = 100
#: is the length L, so ds = L/n = 10).
PAPER = dict(A=0.25, L=100.0, n=10, b=(0.5, 1.0, 2.0))
#: Eq. 7's constants in the captions of Figs. 5-6: "n = 10, s in [0; 5]",
#: C = 0, +-1e-2, +-2e-2, +-3e-2.
EQ7 = dict(n=10, s_end=5.0, C_pos=(0.0, 0.01, 0.02, 0.03), C_neg=(0.0, -0.01, -0.02, -0.03))
#: The captions' colours for b = 1/2, 1, 2 (Figs. 1-4).
B_COLORS = ("black", "tab:blue", "tab:red")
#: The captions' colours for the four values of C (Figs. 5-6): red, green, yellow, blue.
C_COLORS = ("tab:red", "tab:green", "gold", "tab:blue")


@dataclass(frozen=True)
class Line:
    """One plotted line (or set of markers).

    Attributes
    ----------
    x, y : ndarray
        Coordinates; NaN breaks the line (used between spline segments).
    label : str or None
        Legend entry.
    color, style, width, marker, size, zorder
        Matplotlib's ``color``, ``linestyle`` (``''`` for markers only),
        ``linewidth``, ``marker``, ``markersize`` and ``zorder``;
        ``face`` is the marker face colour (None: same as `color`).
    """

    x: np.ndarray
    y: np.ndarray
    label: str | None = None
    color: str = "black"
    style: str = "-"
    width: float = 1.0
    marker: str = ""
    size: float = 3.0
    face: str | None = None
    zorder: float = 2.0


@dataclass(frozen=True)
class Mark:
    """A horizontal (``axis='y'``) or vertical (``axis='x'``) reference line at `at`."""

    axis: str
    at: float
    label: str | None = None
    color: str = "0.7"
    style: str = "-"
    width: float = 0.6
    zorder: float = 0.0


@dataclass(frozen=True)
class Band:
    """A shaded range ``x0 <= x <= x1`` over the whole height of the axes."""

    x0: float
    x1: float
    label: str | None = None
    color: str = "0.6"


@dataclass(frozen=True)
class Panel:
    """One axes: its lines, reference marks, bands and limits.

    `legend` is a matplotlib ``loc`` string, ``'below'`` (centred under the
    axes, in `columns` columns) or None; `text` is written at the top left inside the axes.
    `equal` asks for equal scales on x and y, `y_down` for image
    coordinates, `ticks` False hides the tick labels.
    """

    lines: tuple
    title: str = ""
    xlabel: str = ""
    ylabel: str = ""
    marks: tuple = ()
    bands: tuple = ()
    xlim: tuple | None = None
    ylim: tuple | None = None
    legend: str | None = "below"
    columns: int = 3
    text: str | None = None
    equal: bool = False
    y_down: bool = False
    ticks: bool = True


@dataclass(frozen=True)
class FigureData:
    """A figure of the paper as data.

    Attributes
    ----------
    name : str
        Key in :data:`attneave.papers.ziatdinov.FIGURES`.
    filename : str
        PNG file name written by ``attneave figures``.
    title : str
        Title over the whole figure.
    panels : tuple of Panel
        The axes, row by row in a grid of `grid` = (rows, columns).
    caption : str
        The paper's caption, as printed ('' for a companion figure).
    params : dict
        Parameters used (those of the caption, and any chosen here).
    reading : str
        The reading decision where the caption is ambiguous or wrong ('' if none).
    description : str
        What the figure shows: the paragraph of ``figures.md``.
    """

    name: str
    filename: str
    title: str
    panels: tuple
    caption: str = ""
    params: dict = field(default_factory=dict)
    reading: str = ""
    description: str = ""
    grid: tuple = (1, 1)
    size: tuple = (7.0, 4.8)

    def arrays(self):
        """Every plotted array, by a stable name.

        Returns
        -------
        dict of str to ndarray
            ``'p<panel>/<line>:<label>/x'`` and ``.../y`` for every line, in
            plotting order.
        """
        out = {}
        for i, panel in enumerate(self.panels):
            for j, line in enumerate(panel.lines):
                key = f"p{i}/{j}:{line.label or ''}"
                out[f"{key}/x"] = np.asarray(line.x, dtype=float)
                out[f"{key}/y"] = np.asarray(line.y, dtype=float)
        return out


def fingerprint(fig_data, digits=15):
    """A few numbers per plotted array of a figure, to notice changes.

    Compared at a tolerance of 1e-9 times the array's largest magnitude
    (its square for the sum of squares), a change of one point by more
    than that shows in the sums, while the rounding of libm and of numpy's
    summation (about 1e-16 of it per term) does not.

    Parameters
    ----------
    fig_data : FigureData
        The figure.
    digits : int
        Significant digits kept (15: the sums of 20 000 points must keep
        their last 1e-9 of the largest point).

    Returns
    -------
    dict of str to list
        For each array of :meth:`FigureData.arrays`: ``[size, NaN count,
        sum, sum of squares, sum of abs, first, last, min, max]``, NaNs
        left out of the sums and extremes and the first/last taken among the
        finite values. Plain floats, ready for JSON.

    Examples
    --------
    >>> fd = FigureData("f", "f.png", "t", (Panel((Line(np.array([0.0, 1, 2]), np.array([1.0, np.nan, 3])),)),))
    >>> fingerprint(fd)["p0/0:/y"]
    [3, 1, 4.0, 10.0, 4.0, 1.0, 3.0, 1.0, 3.0]
    """
    def r(v):
        return float(f"{float(v):.{digits}g}")

    out = {}
    for key, a in fig_data.arrays().items():
        a = a.ravel()
        f = a[np.isfinite(a)]
        if f.size == 0:
            out[key] = [int(a.size), int(a.size - f.size)]
            continue
        out[key] = [int(a.size), int(a.size - f.size), r(f.sum()), r((f * f).sum()), r(np.abs(f).sum()),
                    r(f[0]), r(f[-1]), r(f.min()), r(f.max())]
    return out
