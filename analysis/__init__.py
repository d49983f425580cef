"""attneave.analysis: participants' point selections against predicted information.

Reads click files, maps clicks onto contours, fits and tests the surprisal
model, simulates observers, writes reports; and holds the command line.
``analysis`` may import :mod:`stimuli`; :mod:`stimuli` never imports ``analysis``.
"""
