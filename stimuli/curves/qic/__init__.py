"""The QIC spline: clothoid segments through points, G2 wherever that adds
no information the points do not carry (the seed paper's proposal).

``spline`` (the driver, :func:`qic_spline`), ``newton`` (the G2 solve),
``rule`` (the robust rule: which nodes give up G2) and ``measures`` (its
measures), ``lac`` (the robust rule's log-aesthetic form), ``result``
(:class:`QICSpline`), ``kernel`` (the compiled solve, ``qic_solve.c`` and
``clothoid_moments.c``, if it was built).
"""
