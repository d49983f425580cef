"""Stimulus recipes: named, validated ways to make the items of one stimulus.

A recipe is ``RECIPES[name] = (ParamsModel, fn)``. ``ParamsModel`` is a
pydantic model (unknown keys and out-of-range values are errors that name
the key); ``fn(params, rng, canvas)`` draws everything it needs from the
`numpy.random.Generator` `rng` and returns a list of :class:`Item`: the
contour placed on the canvas in image pixels, what the image shows, and
every resolved parameter. The parameter models live in
:mod:`attneave.stimuli.batch.params`, placement on the canvas in
:mod:`attneave.stimuli.batch.placement`, drawing in :mod:`attneave.stimuli.batch.drawing`.

Recipes
-------
``attneave_polygon``, ``attneave_curved``
    Attneave & Arnoult (1956) Method 1 polygons; ``version`` 'polygon',
    'curved' (smoothed through the same vertices) or 'both' (two items,
    ``polygon`` and ``curved``, placed with one transform so they overlay).
    The two names differ only in the default ``version``.
``radial_frequency``, ``fourier``, ``superformula``, ``blob``
    See :mod:`attneave.stimuli.shapes.generators`.
``from_csv``, ``from_image``
    A contour from a CSV file (columns x, y) or the largest object of a
    photograph (:func:`attneave.stimuli.extraction.outlines.extract_contours`).
``deformation``
    Barenholtz et al. (2003): items ``base``, ``concave``, ``convex`` (the
    last two with parent ``base``); see :mod:`attneave.stimuli.shapes.deformations`.
``guided``
    Information-guided items from one base shape: ``base``, ``cat``,
    ``peaks``, ``troughs``, ``dots``, ``dots_troughs`` (``kinds`` chooses);
    see :mod:`attneave.stimuli.shapes.guided`.

Placement
---------
See :mod:`attneave.stimuli.batch.placement` (``placement='fit'`` or ``'native'``).
Deformation displacements and fragment gaps are in pixels of the placed
shape. A batch config may give any length in degrees (``r0_deg``,
``displacement_deg``): :mod:`attneave.stimuli.batch.degrees`. Points are ``(x, y)`` in image pixels, y down, pixel centres at
integers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Literal, Optional

from pydantic import BaseModel, Field, field_validator, model_validator

from attneave.stimuli.batch.drawing import draw_item, item_svg
from attneave.stimuli.batch.params import PLACED_PX, SHAPES, BaseShape, DeformationParams, Style, check_base_draw
from attneave.stimuli.batch.params import RecipeParams as _Params
from attneave.stimuli.batch.placement import Canvas, place
from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.shapes import deformations, generators, guided
from attneave.stimuli.validate import as_rng

# Canvas, Style, place, draw_item and item_svg are kept here too: callers make, place and draw in one place
__all__ = ["Canvas", "Item", "Style", "RECIPES", "SHAPES", "draw_item", "item_svg", "make", "place"]


@dataclass
class Item:
    """One stimulus made by a recipe.

    Attributes
    ----------
    suffix : str
        ``""`` for a lone stimulus, else unique within the recipe call
        (``base``, ``concave``, ...); ``[A-Za-z0-9_.-]*``.
    condition : str
        ``base``, ``concave``, ``peaks``, ... or ``""`` if none.
    parent_suffix : str or None
        Suffix of the item this one derives from, in the same call.
    contour : Contour
        The full closed contour in image pixels of the canvas (y down,
        counter-clockwise on the screen).
    draw : dict
        What the image shows: ``{"mode": "silhouette"}``, ``{"mode":
        "outline"}``, ``{"mode": "fragments", "polylines": [...]}``,
        ``{"mode": "dots", "points": array}``, ``{"mode": "polygon",
        "points": array}``; an optional ``"width"`` (outline, fragments,
        polygon) or ``"radius"`` (dots) overrides the style's.
    params : dict
        Every resolved parameter (JSON-serialisable).
    warnings : list of str
        Why this stimulus may be poor (e.g. the outline taken from an image
        is ``suspect``), one line each; empty for a clean one. ``generate``
        prints them and writes them to the manifest's ``warning`` column.
    """

    suffix: str
    condition: str
    parent_suffix: Optional[str]
    contour: Contour
    draw: dict
    params: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)



GUIDED_KINDS = ("base", "cat", "peaks", "troughs", "dots", "dots_troughs")


class GuidedParams(_Params):
    """Information-guided items from one base shape; see :mod:`attneave.stimuli.shapes.guided`."""

    base: BaseShape = Field(default_factory=BaseShape)
    kinds: list[Literal[GUIDED_KINDS]] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["base", "cat", "peaks", "troughs", "dots"], min_length=1)
    n: int = Field(256, ge=8, le=1_000_000, description="surprisal sampling: points along the contour")
    model: Literal["paper", "vonmises"] = "paper"
    A: float = Field(0.25, gt=0, allow_inf_nan=False)
    b: Optional[float] = Field(None, ge=0, allow_inf_nan=False)
    prominence: Optional[float] = Field(None, ge=0, allow_inf_nan=False)
    k: Optional[int] = Field(None, ge=3, le=100_000,
                             description="points of the cat and dots (default: every surprisal peak)")
    min_separation: Optional[float] = Field(None, ge=0, allow_inf_nan=False, json_schema_extra=PLACED_PX,
                                            description="px between cat/dot points")
    fraction: float = Field(0.3, gt=0, lt=1, description="fraction of the perimeter shown as fragments")
    n_fragments: int = Field(4, ge=1, le=100_000)
    min_gap: float = Field(8.0, ge=0, allow_inf_nan=False, json_schema_extra=PLACED_PX,
                           description="px between fragments of one set")
    min_contrast: float = Field(guided.MIN_CONTRAST, ge=0, lt=1,
                                description="smallest peak prominence and peak-trough contrast (fraction of the "
                                            "surprisal range); a base shape below it is drawn again")
    base_draw: Literal["silhouette", "outline"] = "outline"
    max_tries: int = Field(100, ge=1, le=100_000, description="base shapes drawn before giving up")

    @field_validator("kinds")
    @classmethod
    def _unique(cls, v):
        if len(set(v)) != len(v):
            raise ValueError("each kind at most once")
        return v

    @model_validator(mode="after")
    def _check_draw(self):
        check_base_draw(self.base, self.base_draw, "base_draw")
        return self


# --------------------------------------------------------------------------- shapes and placement


def _shape(name, p, rng):
    """(contours, gparams): one contour, or two for Attneave 'both' (polygon, curved)."""
    if name in ("attneave_polygon", "attneave_curved"):
        common = dict(n_points=p.n_points, grid=p.grid, min_angle=p.min_angle, max_angle=p.max_angle,
                      max_tries=p.max_tries)
        if p.version == "polygon":
            c, g = generators.attneave_polygon(rng, **common)
            return [c], dict(g, version="polygon")
        poly, curved, g = generators.attneave_curved(rng, method=p.smooth_method,
                                                     samples_per_edge=p.samples_per_edge, **common)
        g = dict(g, version=p.version, vertices=poly.points.tolist())
        return ([poly, curved] if p.version == "both" else [curved]), g
    if name == "radial_frequency":
        c, g = generators.radial_frequency(rng, r0=p.r0, frequency=p.frequency, amplitude=p.amplitude,
                                           phase=p.phase, n=p.n)
    elif name == "fourier":
        c, g = generators.fourier_shape(rng, kind=p.kind, r0=p.r0, amplitude=p.amplitude, falloff=p.falloff,
                                        harmonics=p.harmonics, n=p.n, max_tries=p.max_tries)
    elif name == "superformula":
        c, g = generators.superformula(m=p.m, n1=p.n1, n2=p.n2, n3=p.n3, a=p.a, b=p.b, scale=p.scale, n=p.n)
    elif name == "blob":
        c, g = generators.blob(rng, r0=p.r0, sigma=p.sigma, width=p.width, n=p.n)
    elif name == "from_csv":
        c, g = generators.contour_from_csv(p.path, resample=p.resample)
        g = dict(g, path=p.path)
    elif name == "from_image":
        c, g = _from_image(p)
    else:  # pragma: no cover - SHAPES and this switch are kept together
        raise InputError(f"unknown shape generator {name!r}")
    return [c], g


def _from_image(p):
    """The largest object's outline and the extraction's verdict (``ok`` or ``suspect``, with its reasons)."""
    # lazily: these pull in OpenCV and scikit-image
    from attneave.stimuli.extraction.imageio import open_image
    from attneave.stimuli.extraction.outlines import extract
    from attneave.stimuli.extraction.verdict import judge

    f = open_image(p.path)  # the decoder's complaints are collected, not printed
    ex = extract(f.image, method=p.method, threshold=p.threshold, polarity=p.polarity, objects="largest",
                 name=p.path)
    if not ex.contours:
        raise InputError(f"{p.path}: no object found in the image")
    verdict = judge(f.image, ex, f.warnings)
    c = ex.contours[0]
    n_read = c.n
    if p.resample is not None:
        c = c.resample(n=p.resample)
    if not c.is_simple():
        raise InputError(f"{p.path}: the extracted contour crosses itself")
    x0, y0, x1, y1 = c.bbox
    return c, dict(path=p.path, method=p.method, threshold=p.threshold, polarity=p.polarity,
                   n_points=int(n_read), n=int(c.n),
                   centre=[(x0 + x1) / 2.0, (y0 + y1) / 2.0],
                   extraction=dict(status=verdict.status, reasons=list(verdict.reasons)))


def _shape_warnings(shape_params):
    """The warnings a shape's parameters carry: a ``suspect`` outline taken from an image."""
    ex = (shape_params.get("shape") or {}).get("extraction") or {}
    if ex.get("status") == "suspect":
        return [f"outline from {shape_params['shape'].get('path')} is suspect: {'; '.join(ex.get('reasons') or [])}"]
    return []


def _validated(model, params):
    return params if isinstance(params, model) else model.model_validate(params)


def _shape_params(gname, gparams, pl):
    return {"shape": dict(generator=gname, **gparams), "placement": pl}


def _draw(mode):
    return {"mode": mode}


# --------------------------------------------------------------------------- recipe functions


def _lone_shape(name):
    model = SHAPES[name]

    def fn(params, rng, canvas):
        p = _validated(model, params)
        contours, g = _shape(name, p, rng)
        placed, pl = place(contours, g["centre"], canvas, p.placement)
        base = _shape_params(name, g, pl)
        if len(placed) == 2:  # Attneave 'both'
            return [
                Item("polygon", "polygon", None, placed[0], _draw(p.draw), dict(base, version="polygon")),
                Item("curved", "curved", "polygon", placed[1], _draw(p.draw), dict(base, version="curved")),
            ]
        return [Item("", "", None, placed[0], _draw(p.draw), base, _shape_warnings(base))]

    fn.__name__ = f"{name}_recipe"
    fn.__doc__ = f"Recipe {name!r}: one item (two for Attneave version 'both'); params {model.__name__}."
    return fn


def _base(p, rng, canvas):
    """The placed base contour of a deformation / guided set, with its params."""
    bp = SHAPES[p.base.generator].model_validate(p.base.params)
    contours, g = _shape(p.base.generator, bp, rng)
    placed, pl = place(contours, g["centre"], canvas, bp.placement)
    return placed[0], _shape_params(p.base.generator, g, pl)


def deformation_recipe(params, rng, canvas):
    """Recipe ``deformation``: items ``base``, ``concave``, ``convex``.

    A base shape is drawn and placed; :func:`attneave.stimuli.shapes.deformations.deform`
    then looks for a place on it (in an order drawn from `rng`). If there is
    none, another base shape is drawn, up to ``max_tries``.
    """
    p = _validated(DeformationParams, params)
    last = None
    for tries in range(1, p.max_tries + 1):
        contour, bparams = _base(p, rng, canvas)
        if p.resample is not None:
            contour = contour.resample(n=p.resample)
            if not contour.is_simple():
                last = "the resampled base crosses itself"
                continue
        try:
            dfm = deformations.deform(contour, rng, mode=p.mode, displacement=p.displacement, position=p.position,
                                      width=p.width, min_turn=p.min_turn)
        except InputError as exc:
            last = str(exc)
            continue
        dparams = dict(dfm.params, base_tries=tries, resample=p.resample)
        common = dict(bparams, deformation=dparams)
        draw = _draw(p.draw)
        warn = _shape_warnings(bparams)
        return [
            Item("base", "base", None, dfm.base, dict(draw), dict(common, condition="base"), list(warn)),
            Item("concave", "concave", "base", dfm.concave, dict(draw), dict(common, condition="concave"), list(warn)),
            Item("convex", "convex", "base", dfm.convex, dict(draw), dict(common, condition="convex"), list(warn)),
        ]
    raise InputError(f"deformation: no valid {p.mode} change on {p.max_tries} base shapes; last: {last}")




def guided_recipe(params, rng, canvas):
    """Recipe ``guided``: information-guided items from one base shape.

    Items (as listed in ``kinds``): ``base`` (the whole contour), ``cat``
    (polygon through the `k` most informative points), ``peaks`` and
    ``troughs`` (fragments of equal total length and count), ``dots`` and
    ``dots_troughs`` (dots at the `k` most / least informative points).
    Derived items have parent ``base`` when it is made. If the fragments or
    points do not fit on a base shape, or its peak-trough contrast is below
    ``min_contrast``, another is drawn from the same stream, up to
    ``max_tries``; ``base_tries`` and ``base_rejected`` (the reasons) are
    recorded. A base that draws no random numbers (``from_csv``,
    ``from_image``) is the same on every call (``base_random`` false): it is
    not drawn again (:func:`attneave.stimuli.batch.runner.identical_repeats` warns
    when repeats of it are copies).
    """

    p = _validated(GuidedParams, params)
    kinds = list(p.kinds)
    info = dict(n=p.n, model=p.model, A=p.A, b=p.b, prominence=p.prominence)
    rejected = []
    for tries in range(1, p.max_tries + 1):
        state = rng.bit_generator.state
        contour, bparams = _base(p, rng, canvas)
        fixed = rng.bit_generator.state == state
        try:
            made = {}
            if "cat" in kinds:
                made["cat"] = guided.attneave_cat(contour, k=p.k, min_separation=p.min_separation, **info)
            if "peaks" in kinds or "troughs" in kinds:
                made["fragments"] = guided.fragments(contour, fraction=p.fraction, n_fragments=p.n_fragments,
                                                     min_gap=p.min_gap, min_contrast=p.min_contrast, **info)
            for kind, which in (("dots", "peaks"), ("dots_troughs", "troughs")):
                if kind in kinds:
                    made[kind] = guided.dots(contour, k=p.k, which=which, min_separation=p.min_separation, **info)
        except InputError as exc:
            rejected.append(str(exc))
            if fixed:  # the same base again would fail the same way
                raise InputError(f"guided: {p.base.generator} base: {exc}") from None
            continue
        break
    else:
        raise InputError(f"guided: the requested items do not fit on {p.max_tries} base shapes; last: {rejected[-1]}")
    # (a base without randomness makes identical repeats: the runner says so once per condition,
    # and only when there are repeats; see attneave.stimuli.batch.runner.identical_repeats)
    parent = "base" if "base" in kinds else None
    common = dict(bparams, base_tries=tries, base_rejected=rejected, base_random=not fixed)
    items = []
    warn = _shape_warnings(bparams)
    for kind in kinds:
        if kind == "base":
            items.append(Item("base", "base", None, contour, _draw(p.base_draw), dict(common, condition="base")))
        elif kind == "cat":
            pts, g = made["cat"]
            items.append(Item("cat", "cat", parent, contour, {"mode": "polygon", "points": pts},
                              dict(common, condition="cat", guided=g)))
        elif kind in ("peaks", "troughs"):
            fr = made["fragments"]
            g = dict(fr["params"], which=kind)
            items.append(Item(kind, kind, parent, contour, {"mode": "fragments", "polylines": fr[kind]},
                              dict(common, condition=kind, guided=g)))
        else:
            pts, g = made[kind]
            items.append(Item(kind, kind, parent, contour, {"mode": "dots", "points": pts},
                              dict(common, condition=kind, guided=g)))
    for it in items:
        it.warnings = list(warn)
    return items


RECIPES: dict[str, tuple[type[BaseModel], Callable]] = {
    **{name: (model, _lone_shape(name)) for name, model in SHAPES.items()},
    "deformation": (DeformationParams, deformation_recipe),
    "guided": (GuidedParams, guided_recipe),
}


def make(recipe, rng, canvas=None, **params):
    """Run a recipe by name: validate `params`, then call it.

    Parameters
    ----------
    recipe : str
        A key of `RECIPES`.
    rng : numpy.random.Generator or int
        The generator (a non-negative int seeds ``numpy.random.default_rng``;
        None, floats and other objects are refused: see
        :func:`attneave.stimuli.validate.as_rng`).
    canvas : Canvas, optional
        Default ``Canvas()`` (512 x 512, margin 32).
    **params
        The recipe's parameters.

    Returns
    -------
    list of Item

    Raises
    ------
    InputError
        Unknown recipe, invalid parameters (one line naming the key), a bad
        `rng` or a `canvas` that is not a :class:`Canvas`.

    Examples
    --------
    >>> [it] = make("radial_frequency", 1, frequency=5, amplitude=0.1)
    >>> it.contour.n, it.draw
    (1024, {'mode': 'silhouette'})
    """
    from pydantic import ValidationError

    from attneave.stimuli.batch.errors import describe, loc_str

    if recipe not in RECIPES:
        raise InputError(f"recipe: unknown {recipe!r}; expected one of {', '.join(sorted(RECIPES))}")
    model, fn = RECIPES[recipe]
    try:
        p = model.model_validate(params)
    except ValidationError as exc:
        loc, msg = describe(exc, params, model)
        raise InputError(f"{recipe}: {loc_str(loc) if loc else 'params'}: {msg}") from None
    rng = as_rng(rng)
    if canvas is None:
        canvas = Canvas()
    elif not isinstance(canvas, Canvas):
        raise InputError(f"canvas: expected a Canvas(width, height, margin), got {type(canvas).__name__}")
    return fn(p, rng, canvas)
