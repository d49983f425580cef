"""Log-aesthetic curves (the seed paper's eq. 9) and splines made of them.

``aesthetic`` (LAC and GLAC by their natural equation), ``gamma`` (the
closed form through incomplete gamma functions), ``g1`` (LAC segments in a
control triangle, the G1 LAC spline of Fig. 7), and the G2 LAC spline:
``spline`` (the driver), ``newton``, ``arc``, ``quadrature`` and ``result``.
"""
