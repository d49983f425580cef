"""Shape sizes in degrees of visual angle: ``r0_deg: 2`` in a batch config means ``r0`` in pixels.

Every recipe parameter that is a length in pixels (marked on its field:
:data:`~attneave.stimuli.batch.params.SIZE_PX`,
:data:`~attneave.stimuli.batch.params.PLACED_PX`, listed by
:func:`~attneave.stimuli.batch.params.length_fields`) may be given instead in
degrees with the suffix ``_deg``, also inside a deformation's or guided
set's ``base.params``. It is turned into pixels at the condition's canvas
scale (``px_per_deg``, given or computed from the viewing distance and
screen) before the parameters are validated, so the recipe gets pixels and
the usual bounds apply.

A *size* (``r0``, a superformula's ``scale``) only sets the shape's size
on the image when the shape is placed ``native``: ``placement: fit`` would
rescale it to fill the canvas. A size given in degrees therefore places its
shape ``native`` (the default becomes ``native``; an explicit ``fit`` is
refused), so that ``r0_deg: 2`` at 40 px/deg is a mean radius of 80 px on the
image. A *placed* length (a deformation's ``displacement``, a guided set's
``min_gap``) is measured on the placed shape whatever the placement.

Refused, naming the key: a length given both ways (``r0`` and ``r0_deg``), a
``_deg`` key without a display scale on the canvas, a ``_deg`` key of a
parameter that is not a length (``frequency_deg``) or of no parameter.
"""

from __future__ import annotations

import math

from attneave.stimuli.batch.params import SHAPES, BaseShape, length_fields

__all__ = ["DegreeError", "to_pixels", "written_params", "written_loc", "manifest_record", "SUFFIX"]

SUFFIX = "_deg"


class DegreeError(ValueError):
    """A bad ``_deg`` key; ``loc`` is its key path inside the recipe parameters."""

    def __init__(self, loc, message):
        super().__init__(message)
        self.loc = tuple(loc)


def to_pixels(params, model, px_per_deg):
    """Recipe parameters with their lengths in degrees turned into pixels (`params` is not changed).

    Parameters
    ----------
    params : dict
        One grid cell's recipe parameters as written (JSON values).
    model : type of RecipeParams
        The recipe's parameter model.
    px_per_deg : float or None
        The canvas's scale; None when the canvas gives none.

    Returns
    -------
    params : dict
        With each ``<name>_deg`` replaced by ``<name>`` in pixels (and
        ``placement: native`` where a size was given in degrees).
    degrees : dict
        ``{dotted px key: (dotted key as written, degrees)}``, e.g.
        ``{'base.params.r0': ('base.params.r0_deg', 2.0)}``; empty when no
        degrees were given.

    Raises
    ------
    DegreeError
        See the module docstring; ``loc`` names the ``_deg`` key.

    Examples
    --------
    >>> from attneave.stimuli.batch.params import RadialFrequencyParams
    >>> to_pixels({"r0_deg": 2, "frequency": 5}, RadialFrequencyParams, 40.0)
    ({'frequency': 5, 'r0': 80.0, 'placement': 'native'}, {'r0': ('r0_deg', 2)})
    """
    degrees = {}
    out = _convert(params, model, px_per_deg, (), degrees)
    return out, degrees


def _convert(node, model, ppd, loc, degrees):
    if not isinstance(node, dict):
        return node  # the model reports the wrong type
    out = dict(node)
    lengths = length_fields(model)
    sizes = []
    for key in [k for k in node if isinstance(k, str) and k.endswith(SUFFIX)]:
        name, where = key[: -len(SUFFIX)], loc + (key,)
        if name not in lengths:
            have = (", ".join(f"{k}{SUFFIX}" for k in lengths) or "none; its size is set by the canvas "
                    "(width_deg, margin_deg) with placement: fit")
            what = (f"{name} is not a length, so it has no form in degrees" if name in model.model_fields
                    else "unknown parameter")
            raise DegreeError(where, f"{what} (lengths this takes in degrees: {have})")
        if name in node:
            raise DegreeError(where, f"{name} is given too; give {name} (px) or {key} (degrees), not both")
        if ppd is None:
            raise DegreeError(where, "a length in degrees needs the display's scale: add px_per_deg (or "
                                     "viewing_distance_cm, screen_width_cm and screen_width_px) to the canvas")
        deg = node[key]
        if isinstance(deg, bool) or not isinstance(deg, (int, float)) or not math.isfinite(deg):
            raise DegreeError(where, f"expected a finite number of degrees, got {deg!r}")
        del out[key]
        out[name] = deg * ppd
        degrees[".".join(str(p) for p in loc + (name,))] = (".".join(str(p) for p in where), deg)
        if lengths[name] == "size":
            sizes.append(key)
    if sizes and "placement" in model.model_fields:
        if out.get("placement", "native") != "native":
            raise DegreeError(loc + (sizes[0],), f"a size in degrees is kept only with placement: native, but "
                                                 f"placement is {out['placement']!r} (fit rescales the shape to "
                                                 f"fill the canvas less its margin); drop placement, or give the "
                                                 f"size by the canvas (width_deg, margin_deg)")
        out["placement"] = "native"
    # a deformation's or guided set's base shape: its params are the generator's
    for fname, field in model.model_fields.items():
        base = out.get(fname)
        if field.annotation is BaseShape and isinstance(base, dict):
            gen = base.get("generator", BaseShape.model_fields["generator"].default)
            if isinstance(gen, str) and gen in SHAPES and "params" in base:
                base = dict(base, params=_convert(base["params"], SHAPES[gen], ppd, loc + (fname, "params"),
                                                  degrees))
                out[fname] = base
    return out


def written_params(params, degrees, grid_keys):
    """A condition's fixed params for the resolved config, with the lengths given in degrees written in degrees.

    The resolved config must run again to the same stimuli: writing both
    ``r0`` and ``r0_deg`` would be refused, and a grid axis ``r0_deg`` leaves
    no ``r0`` in the fixed params.

    Parameters
    ----------
    params : dict
        The fixed params (grid keys removed) in pixels; changed in place.
    degrees : dict
        One cell's degrees, as :func:`to_pixels` gives them.
    grid_keys : iterable of str
        The condition's grid keys (dotted).

    Examples
    --------
    >>> written_params({"r0": 80.0, "n": 64}, {"r0": ("r0_deg", 2)}, [])
    {'r0_deg': 2, 'n': 64}
    """
    grid_keys = list(grid_keys)
    for px_key, (deg_key, deg) in degrees.items():
        *parents, name = px_key.split(".")
        node = params
        for p in parents:
            node = node.get(p) if isinstance(node, dict) else None
        if not isinstance(node, dict) or name not in node:
            continue  # under a grid key: the grid writes it
        on_grid = any(deg_key == k or deg_key.startswith(k + ".") for k in grid_keys)
        items = [(k, v) for k, v in node.items()]
        node.clear()
        for k, v in items:  # the degrees where the pixels were, so the file reads in the config's order
            if k != name:
                node[k] = v
            elif not on_grid:
                node[deg_key.rsplit(".", 1)[-1]] = deg
    return params


def written_loc(loc, degrees, px_per_deg):
    """A validation error's key path inside the parameters, moved to the ``_deg`` key the value came from.

    Returns
    -------
    loc : tuple
    note : str
        ``' (= r0_deg -2 x 40 px/deg)'`` when the value was given in degrees, else ``''``.

    Examples
    --------
    >>> written_loc(("r0",), {"r0": ("r0_deg", -2)}, 40.0)
    (('r0_deg',), ' (= r0_deg -2 x 40 px/deg)')
    """
    dotted = ".".join(str(p) for p in loc)
    if dotted in degrees:
        deg_key, deg = degrees[dotted]
        return tuple(deg_key.split(".")), f" (= {deg_key.rsplit('.', 1)[-1]} {deg!r} x {px_per_deg:.6g} px/deg)"
    return tuple(loc), ""


def manifest_record(degrees, px_per_deg):
    """What the manifest records of one cell's degrees: the scale, each value given and its pixels.

    Examples
    --------
    >>> manifest_record({"base.params.r0": ("base.params.r0_deg", 2)}, 40.0)
    {'px_per_deg': 40.0, 'base.params.r0_deg': 2, 'base.params.r0': 80.0}
    """
    if not degrees:
        return {}
    out = {"px_per_deg": float(px_per_deg)}
    for px_key, (deg_key, deg) in degrees.items():
        out[deg_key] = deg
        out[px_key] = deg * px_per_deg
    return out
