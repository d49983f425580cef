"""Stimulus shapes: generators (Attneave polygons, radial-frequency and
Fourier shapes, superformula, blobs), deformations matched in size, and
information-guided stimuli (fragments, Attneave's cat, dots).

Modules: ``generators`` (and ``attneave``, the Attneave & Arnoult polygons),
``deformations``, ``guided`` (and ``selection``, its ranking of places).
Generators take `rng`, a `numpy.random.Generator` or an integer seed, and
return ``(contour, params)``. Points are ``(x, y)`` (x = column, y = row,
y down). Names below are imported on first use, so ``import attneave.stimuli.shapes``
is cheap.
"""

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "attneave_polygon": ".attneave",
    "attneave_curved": ".attneave",
    "smooth_closed": ".attneave",
    "radial_frequency": ".generators",
    "fourier_shape": ".generators",
    "superformula": ".generators",
    "blob": ".generators",
    "contour_from_csv": ".generators",
    "check_sampling": ".generators",
    "MAX_POINTS": "._limits",
    "Deformation": ".deformations",
    "deform": ".deformations",
    "deform_at": ".deformations",
    "insert_vertex": ".deformations",
    "move_vertex": ".deformations",
    "attneave_cat": ".guided",
    "fragments": ".guided",
    "dots": ".guided",
    "information": ".guided",
})
