"""Size limits shared by the shape generators (see :mod:`attneave.stimuli.shapes.generators`)."""

#: Most points a generator makes (``n``; vertices times samples per edge for
#: the smoothed polygons): the bound of the ``attneave surprisal`` command,
#: far beyond any stimulus (a 1000 px wide shape sampled every 0.01 px).
MAX_POINTS = 1_000_000
#: Most terms ``n * harmonics`` a harmonic sum may take: a few seconds of work.
MAX_TERMS = 100_000_000
#: Largest side of the Attneave lattice (``grid``); its cells are numbered in int64.
MAX_GRID = 1_000_000
