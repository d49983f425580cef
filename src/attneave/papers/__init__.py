"""The seed paper's figures, each reproduced by a function of the library.

Modelled on stimupy's ``papers`` layer: :mod:`attneave.papers.ziatdinov`
has one function per figure of Ziatdinov's paper (Figs. 1-6, the Fig. 10
analogue from :mod:`attneave.papers.companions`, and two companions), each
returning the figure's data, a :class:`attneave.papers.base.FigureData`
(arrays, the caption's parameters, the caption, any reading decision),
listed by name in :data:`attneave.papers.ziatdinov.FIGURES`.
:mod:`attneave.papers.draw` draws them (matplotlib) and writes them all with
a note, ``figures.md`` (``attneave figures``);
:mod:`attneave.papers.spline_plots` holds plotting helpers for splines and
the Fig. 10 analogue's 30 points.

Examples
--------
>>> from attneave.papers.ziatdinov import fig4
>>> fd = fig4()
>>> [p.title.split(",")[0] for p in fd.panels[:2]]
['(a) clothoid k(s) = (2 pi/n) s', '(b) the same symbols read k = 2 pi/(n s): a logarithmic spiral']
"""
