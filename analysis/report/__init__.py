"""The outputs of an analysis.

``outputs`` (every file of an analysis, written atomically), ``tables``
(per-stimulus and per-participant tables), ``summary`` (summary.json),
``html`` (report.html, a methods-and-results section), ``plots`` and
``figure_files`` (figures as PNG), ``choice_table`` (the long-format choice
data and an R script fitting the same models).
"""
