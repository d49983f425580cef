"""The seed paper's figures, each reproduced by a function of the library.

:mod:`attneave.papers.ziatdinov` holds Figs. 1-6 and the curve families;
:mod:`attneave.papers.spline_plots` the spline figures (the Fig. 10
analogue). ``attneave figures`` writes them all.
"""
