"""Stimulus recipes: named, validated ways to make the items of one stimulus.

A recipe is ``RECIPES[name] = (ParamsModel, fn)``. ``ParamsModel`` is a
pydantic model (unknown keys and out-of-range values are errors that name
the key); ``fn(params, rng, canvas)`` draws everything it needs from the
`numpy.random.Generator` `rng` and returns a list of :class:`Item`: the
contour placed on the canvas in image pixels, what the image shows, and
every resolved parameter. :func:`draw_item` renders an item with a
:class:`Style` (exact area coverage, :mod:`stimuli.render.core`), and
:func:`item_svg` writes it as SVG in the same pixel coordinates.

Recipes
-------
``attneave_polygon``, ``attneave_curved``
    Attneave & Arnoult (1956) Method 1 polygons; ``version`` 'polygon',
    'curved' (smoothed through the same vertices) or 'both' (two items,
    ``polygon`` and ``curved``, placed with one transform so they overlay).
    The two names differ only in the default ``version``.
``radial_frequency``, ``fourier``, ``superformula``, ``blob``
    See :mod:`stimuli.shapes.generators`.
``from_csv``, ``from_image``
    A contour from a CSV file (columns x, y) or the largest object of a
    photograph (:func:`stimuli.extract.extract_contours`).
``deformation``
    Barenholtz et al. (2003): items ``base``, ``concave``, ``convex`` (the
    last two with parent ``base``); see :mod:`stimuli.shapes.deformations`.
``guided``
    Information-guided items from one base shape: ``base``, ``cat``,
    ``peaks``, ``troughs``, ``dots``, ``dots_troughs`` (``kinds`` chooses);
    see :mod:`stimuli.shapes.guided`.

Placement
---------
Every shape is made in its generator's own units and then placed on the
canvas: ``placement='fit'`` (default) scales it uniformly so that its
bounding box fills the canvas less ``margin`` on the tighter side and
centres the box on the image centre ``((width - 1) / 2, (height - 1) / 2)``
(:func:`stimuli.render.fit_to_image`); ``placement='native'`` keeps the
generator's units as pixels (e.g. an RF pattern's ``r0`` in px) and puts
the generator's centre (the polar origin, the grid centre) on the image
centre. Deformation displacements and fragment gaps are in pixels of the
placed shape. Points are ``(x, y)`` in image pixels, y down, pixel centres
at integers.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Any, Callable, Literal, Optional, Union

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationInfo, field_validator, model_validator

from stimuli.shapes import deformations
from stimuli.shapes import generators
from stimuli.shapes import guided
from stimuli.geometry.contour import Contour
from stimuli.errors import InputError

__all__ = [
    "Canvas",
    "Item",
    "Style",
    "RECIPES",
    "SHAPES",
    "draw_item",
    "item_svg",
    "make",
    "place",
]


# --------------------------------------------------------------------------- canvas, item, style


@dataclass(frozen=True)
class Canvas:
    """The image a stimulus is drawn on.

    Attributes
    ----------
    width, height : int
        Image size in pixels.
    margin : float
        Pixels between the shape's bounding box and the image edge (for
        ``placement='fit'``).
    """

    width: int = 512
    height: int = 512
    margin: float = 32.0

    def __post_init__(self):
        for name in ("width", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, np.integer)) and v > 0):
                raise InputError(f"canvas.{name}: must be a positive integer, got {v!r}")
        if not (np.isfinite(self.margin) and 0 <= self.margin and 2 * self.margin < min(self.width, self.height)):
            raise InputError(
                f"canvas.margin: must be >= 0 and less than half the smaller side, got {self.margin!r}"
            )

    @property
    def size(self):
        """``(width, height)``."""
        return (int(self.width), int(self.height))

    @property
    def centre(self):
        """The image centre ``((width - 1) / 2, (height - 1) / 2)`` in pixel coordinates."""
        return np.array([(self.width - 1) / 2.0, (self.height - 1) / 2.0])


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
    """

    suffix: str
    condition: str
    parent_suffix: Optional[str]
    contour: Contour
    draw: dict
    params: dict = field(default_factory=dict)


def _check_colour(v):
    if isinstance(v, (list, tuple)):
        if len(v) != 3:
            raise ValueError(f"a colour is a grey level or an [r, g, b] triple, got {len(v)} values")
        for c in v:
            if not 0 <= c <= 1:
                raise ValueError(f"colour values must be in [0, 1], got {c}")
        return tuple(float(c) for c in v)
    return v


Unit = Annotated[float, Field(ge=0, le=1)]
Colour = Annotated[Union[Unit, tuple[Unit, Unit, Unit]], BeforeValidator(_check_colour)]


class Style(BaseModel):
    """How items are drawn; shared by a whole condition.

    Attributes
    ----------
    figure, ground : float or [r, g, b]
        Grey levels (or RGB) in [0, 1] of the shape and of the background.
    line_width : float
        Stroke width in px of outlines, fragments and outlined polygons.
    dot_radius : float
        Radius in px of dots.
    polygon_fill : bool
        Attneave's cat (mode ``polygon``) filled (True) or outlined (False).
    join : {'round', 'mitre', 'bevel'}
        Stroke joins.
    cap : {'flat', 'round', 'square'}
        Ends of fragments. 'flat' (default) makes the visible length equal
        the fragment length; 'round' and 'square' add ``line_width / 2`` at
        each end.
    """

    model_config = ConfigDict(extra="forbid")

    figure: Colour = 0.0
    ground: Colour = 1.0
    line_width: float = Field(3.0, gt=0, le=1000)
    dot_radius: float = Field(4.0, gt=0, le=1000)
    polygon_fill: bool = False
    join: Literal["round", "mitre", "bevel"] = "round"
    cap: Literal["flat", "round", "square"] = "flat"


# --------------------------------------------------------------------------- params models


class _Params(BaseModel):
    model_config = ConfigDict(extra="forbid")


class _ShapeParams(_Params):
    placement: Literal["fit", "native"] = Field("fit", description="'fit' scales to the canvas, 'native' keeps units as px")
    draw: Literal["silhouette", "outline"] = Field("silhouette", description="filled shape or its outline")


PosInt = Annotated[int, Field(ge=1)]
NonNeg = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


def _one_or_list(item_type):
    """Before-validator: a lone value becomes a one-element list.

    The lone value is checked here against `item_type` so that its error is
    reported at the key itself (``amplitude: must be >= 0``), not at an
    index the user never wrote.
    """
    from pydantic import TypeAdapter

    adapter = TypeAdapter(item_type)

    def convert(v):
        if v is None or isinstance(v, (list, tuple)):
            return v
        adapter.validate_python(v)
        return [v]

    return BeforeValidator(convert)


class AttneavePolygonParams(_ShapeParams):
    """Attneave & Arnoult (1956) Method 1; see :func:`stimuli.generators.attneave_polygon`."""

    n_points: int = Field(12, ge=3, le=1000, description="number of vertices")
    grid: int = Field(100, ge=2, le=100_000, description="side of the lattice the points are drawn from")
    min_angle: float = Field(10.0, ge=0, lt=180, description="smallest angle between sides at a vertex (deg)")
    max_angle: float = Field(170.0, gt=0, le=180, description="largest angle between sides at a vertex (deg)")
    max_tries: int = Field(1000, ge=1, le=1_000_000)
    version: Literal["polygon", "curved", "both"] = "polygon"
    smooth_method: Literal["cubic", "bspline", "qic"] = "cubic"
    samples_per_edge: int = Field(32, ge=2, le=10_000)

    @model_validator(mode="after")
    def _check(self):
        if not self.min_angle < self.max_angle:
            raise ValueError(f"min_angle ({self.min_angle:g}) must be < max_angle ({self.max_angle:g})")
        if self.n_points > self.grid * self.grid:
            raise ValueError(f"n_points ({self.n_points}) exceeds the {self.grid}x{self.grid} grid")
        return self


class AttneaveCurvedParams(AttneavePolygonParams):
    """As ``attneave_polygon`` with ``version='curved'`` by default."""

    version: Literal["polygon", "curved", "both"] = "curved"


class RadialFrequencyParams(_ShapeParams):
    """Radial-frequency pattern; see :func:`stimuli.generators.radial_frequency`."""

    r0: float = Field(100.0, gt=0, allow_inf_nan=False, description="mean radius (px when placement is native)")
    frequency: Annotated[list[PosInt], _one_or_list(PosInt), Field(min_length=1)] = Field(
        default_factory=lambda: [5], description="radial frequencies (one or a list)")
    amplitude: Annotated[list[NonNeg], _one_or_list(NonNeg), Field(min_length=1)] = Field(
        default_factory=lambda: [0.1], description="amplitudes, one per frequency")
    phase: Annotated[Optional[list[Finite]], _one_or_list(Finite)] = Field(
        None, description="phases in radians, one per frequency; null draws them")
    n: int = Field(1024, ge=8, le=1_000_000)

    @model_validator(mode="after")
    def _check(self):
        if len(self.amplitude) != len(self.frequency):
            raise ValueError(f"give one amplitude per frequency ({len(self.frequency)}), got {len(self.amplitude)}")
        if self.phase is not None and len(self.phase) != len(self.frequency):
            raise ValueError(f"give one phase per frequency ({len(self.frequency)}), got {len(self.phase)}")
        if sum(self.amplitude) >= 1:
            raise ValueError(f"the amplitudes must sum to < 1 so the radius stays positive, got {sum(self.amplitude):g}")
        return self


class FourierParams(_ShapeParams):
    """Random Fourier shape; see :func:`stimuli.generators.fourier_shape`."""

    kind: Literal["radial", "elliptic"] = "radial"
    r0: float = Field(100.0, gt=0, allow_inf_nan=False)
    amplitude: float = Field(0.1, ge=0, allow_inf_nan=False)
    falloff: float = Field(1.5, ge=0, allow_inf_nan=False)
    harmonics: int = Field(8, ge=2, le=1000)
    n: int = Field(1024, ge=8, le=1_000_000)
    max_tries: int = Field(100, ge=1, le=1_000_000)

    @model_validator(mode="after")
    def _check(self):
        if self.n < 4 * self.harmonics:
            raise ValueError(f"n ({self.n}) must be at least 4 * harmonics ({4 * self.harmonics})")
        return self


class SuperformulaParams(_ShapeParams):
    """Gielis' superformula; see :func:`stimuli.generators.superformula`."""

    m: float = Field(5.0, ge=0, allow_inf_nan=False)
    n1: float = Field(2.0, gt=0, allow_inf_nan=False)
    n2: float = Field(7.0, gt=0, allow_inf_nan=False)
    n3: float = Field(7.0, gt=0, allow_inf_nan=False)
    a: float = Field(1.0, gt=0, allow_inf_nan=False)
    b: float = Field(1.0, gt=0, allow_inf_nan=False)
    scale: float = Field(100.0, gt=0, allow_inf_nan=False)
    n: int = Field(1024, ge=8, le=1_000_000)


class BlobParams(_ShapeParams):
    """Smooth random blob; see :func:`stimuli.generators.blob`."""

    r0: float = Field(100.0, gt=0, allow_inf_nan=False)
    sigma: float = Field(0.2, ge=0, allow_inf_nan=False, description="RMS of the log-radius")
    width: float = Field(0.6, gt=0, allow_inf_nan=False, description="correlation width in radians")
    n: int = Field(1024, ge=8, le=1_000_000)


class FromCsvParams(_ShapeParams):
    """A contour from a CSV file with columns x, y; rescaled and centred."""

    path: str = Field(min_length=1)
    resample: Optional[int] = Field(None, ge=3, le=1_000_000)


class FromImageParams(_ShapeParams):
    """The largest object of an image, via :func:`stimuli.extract.extract_contours`."""

    path: str = Field(min_length=1)
    method: Literal["otsu", "threshold", "mask", "alpha", "grabcut"] = "otsu"
    threshold: Optional[float] = Field(None, allow_inf_nan=False,
                                       description="grey level for method 'threshold' (image units)")
    polarity: Literal["auto", "dark", "light"] = "auto"
    resample: Optional[int] = Field(None, ge=3, le=1_000_000)

    @model_validator(mode="after")
    def _threshold_given(self):
        if (self.method == "threshold") != (self.threshold is not None):
            raise ValueError("threshold: give a value with method 'threshold' and only then")
        return self


SHAPES: dict[str, type[_ShapeParams]] = {
    "attneave_polygon": AttneavePolygonParams,
    "attneave_curved": AttneaveCurvedParams,
    "radial_frequency": RadialFrequencyParams,
    "fourier": FourierParams,
    "superformula": SuperformulaParams,
    "blob": BlobParams,
    "from_csv": FromCsvParams,
    "from_image": FromImageParams,
}


class BaseShape(_Params):
    """The shape a deformation or guided set starts from: a generator and its params."""

    generator: Literal[tuple(SHAPES)] = "attneave_polygon"  # type: ignore[valid-type]
    params: dict[str, Any] = Field(default_factory=dict)

    @field_validator("params")
    @classmethod
    def _valid_params(cls, v, info: ValidationInfo):
        gen = info.data.get("generator")
        if gen is None:
            return v
        model = SHAPES[gen].model_validate(v)
        if getattr(model, "version", None) == "both":
            raise ValueError("version 'both' makes two shapes; a base shape needs 'polygon' or 'curved'")
        return model.model_dump(mode="json")


class DeformationParams(_Params):
    """Barenholtz et al. (2003) matched concave/convex changes; see :mod:`stimuli.shapes.deformations`."""

    base: BaseShape = Field(default_factory=BaseShape)
    mode: Literal["edge", "vertex", "bump"] = "edge"
    displacement: float = Field(10.0, gt=0, allow_inf_nan=False, description="px the moved point travels")
    position: float = Field(0.5, gt=0, lt=1, description="where on the side the new vertex goes (edge mode)")
    width: Optional[float] = Field(None, gt=0, allow_inf_nan=False, description="bump half-width in px; null: automatic")
    min_turn: float = Field(0.0, ge=0, lt=180, description="minimum |turning angle| at the moved vertex (deg)")
    resample: Optional[int] = Field(None, ge=8, le=1_000_000, description="resample the placed base first (bump mode)")
    draw: Literal["silhouette", "outline"] = "silhouette"
    max_tries: int = Field(100, ge=1, le=100_000, description="base shapes drawn before giving up")


GUIDED_KINDS = ("base", "cat", "peaks", "troughs", "dots", "dots_troughs")


class GuidedParams(_Params):
    """Information-guided items from one base shape; see :mod:`stimuli.shapes.guided`."""

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
    min_separation: Optional[float] = Field(None, ge=0, allow_inf_nan=False, description="px between cat/dot points")
    fraction: float = Field(0.3, gt=0, lt=1, description="fraction of the perimeter shown as fragments")
    n_fragments: int = Field(4, ge=1, le=100_000)
    min_gap: float = Field(8.0, ge=0, allow_inf_nan=False, description="px between fragments of one set")
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
    from stimuli.extraction.core import extract_contours  # lazily: it pulls in OpenCV and scikit-image

    found = extract_contours(p.path, method=p.method, threshold=p.threshold, polarity=p.polarity,
                             objects="largest")
    if not found:
        raise InputError(f"{p.path}: no object found in the image")
    c = found[0]
    n_read = c.n
    if p.resample is not None:
        c = c.resample(n=p.resample)
    if not c.is_simple():
        raise InputError(f"{p.path}: the extracted contour crosses itself")
    x0, y0, x1, y1 = c.bbox
    return c, dict(path=p.path, method=p.method, threshold=p.threshold, polarity=p.polarity,
                   n_points=int(n_read), n=int(c.n),
                   centre=[(x0 + x1) / 2.0, (y0 + y1) / 2.0])


def place(contours, centre, canvas, placement="fit"):
    """Place contours (one transform for all) on the canvas.

    Parameters
    ----------
    contours : list of Contour
        In the generator's units (y down).
    centre : (2,) array_like
        The generator's centre (used by ``'native'``).
    canvas : Canvas
    placement : {'fit', 'native'}
        See the module docstring.

    Returns
    -------
    placed : list of Contour
        In image pixels: ``points * scale + offset``.
    params : dict
        ``placement, scale, offset``.
    """
    if placement == "fit":
        from stimuli.render.core import fit_to_image

        allp = np.vstack([c.points for c in contours])
        f = fit_to_image(allp, size=canvas.size, margin=canvas.margin)
        scale, offset = float(f["scale"]), np.asarray(f["offset"], float)
    elif placement == "native":
        scale, offset = 1.0, canvas.centre - np.asarray(centre, float)
    else:
        raise InputError(f"placement: expected 'fit' or 'native', got {placement!r}")
    placed = [c.transformed(scale, offset) for c in contours]
    if placement == "native":
        # a shape cut off by the image edge is not the stimulus the contour file describes
        lo = np.min([c.points.min(axis=0) for c in placed], axis=0)
        hi = np.max([c.points.max(axis=0) for c in placed], axis=0)
        if lo[0] < -0.5 or lo[1] < -0.5 or hi[0] > canvas.width - 0.5 or hi[1] > canvas.height - 0.5:
            raise InputError(
                f"placement: native: the shape spans x {lo[0]:.1f}..{hi[0]:.1f}, y {lo[1]:.1f}..{hi[1]:.1f} px, "
                f"outside the {canvas.width}x{canvas.height} canvas; make it smaller, the canvas larger, "
                f"or use placement: fit")
    return placed, dict(placement=placement, scale=scale, offset=[float(offset[0]), float(offset[1])])


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
        return [Item("", "", None, placed[0], _draw(p.draw), base)]

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

    A base shape is drawn and placed; :func:`stimuli.deformations.deform`
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
        return [
            Item("base", "base", None, dfm.base, dict(draw), dict(common, condition="base")),
            Item("concave", "concave", "base", dfm.concave, dict(draw), dict(common, condition="concave")),
            Item("convex", "convex", "base", dfm.convex, dict(draw), dict(common, condition="convex")),
        ]
    raise InputError(f"deformation: no valid {p.mode} change on {p.max_tries} base shapes; last: {last}")


_WARNED: set = set()  # messages of guided_recipe's repeat warning already shown


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
    not drawn again, and a ``UserWarning`` says once per process that
    repeats of these parameters give identical files.
    """
    import warnings

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
    if fixed:
        where = p.base.params.get("path", "")
        msg = (f"guided: base {p.base.generator} {where} draws no random numbers: every repeat of these "
               f"parameters gives identical files (use repeats: 1)")
        if msg not in _WARNED:  # once per distinct base in a process, whatever the warnings filters
            _WARNED.add(msg)
            warnings.warn(msg, UserWarning, stacklevel=2)
    parent = "base" if "base" in kinds else None
    common = dict(bparams, base_tries=tries, base_rejected=rejected, base_random=not fixed)
    items = []
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
        The generator (an int seeds ``numpy.random.default_rng``).
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
        Unknown recipe or invalid parameters (one line naming the key).

    Examples
    --------
    >>> [it] = make("radial_frequency", 1, frequency=5, amplitude=0.1)
    >>> it.contour.n, it.draw
    (1024, {'mode': 'silhouette'})
    """
    from pydantic import ValidationError

    if recipe not in RECIPES:
        raise InputError(f"recipe: unknown {recipe!r}; expected one of {', '.join(sorted(RECIPES))}")
    model, fn = RECIPES[recipe]
    try:
        p = model.model_validate(params)
    except ValidationError as exc:
        e = exc.errors(include_url=False)[0]
        loc = ".".join(str(x) for x in e["loc"])
        msg = e["msg"].removeprefix("Value error, ")
        raise InputError(f"{recipe}: {loc or 'params'}: {msg}") from None
    if not isinstance(rng, np.random.Generator):
        rng = np.random.default_rng(rng)
    return fn(p, rng, canvas if canvas is not None else Canvas())


# --------------------------------------------------------------------------- drawing


def _render(item, style, canvas):
    """The :mod:`stimuli.render.core` result dict of an item."""
    from stimuli import render

    if not isinstance(style, Style):
        style = Style.model_validate(style)
    size = canvas.size
    colours = dict(figure=style.figure, ground=style.ground)
    d = item.draw
    mode = d.get("mode")
    width = float(d.get("width") or style.line_width)
    if mode == "silhouette":
        return render.render_silhouette(item.contour.points, size=size, **colours)
    if mode == "outline":
        return render.render_outline(item.contour.points, width, size=size, closed=True, join=style.join, **colours)
    if mode == "fragments":
        return render.render_fragments([np.asarray(q, float) for q in d["polylines"]], width, size=size,
                                       cap=style.cap, join=style.join, **colours)
    if mode == "dots":
        radius = float(d.get("radius") or style.dot_radius)
        return render.render_dots(np.asarray(d["points"], float), radius, size=size, **colours)
    if mode == "polygon":
        pts = np.asarray(d["points"], float)
        if style.polygon_fill:
            return render.render_silhouette(pts, size=size, **colours)
        return render.render_outline(pts, width, size=size, closed=True, join=style.join, **colours)
    raise InputError(f"item {item.suffix!r}: unknown draw mode {mode!r}")


def draw_item(item, style, canvas):
    """Render an item: a float image in [0, 1] with exact area coverage.

    Parameters
    ----------
    item : Item
    style : Style (or a mapping of its fields)
    canvas : Canvas

    Returns
    -------
    ndarray
        ``(height, width)`` for grey colours, ``(height, width, 3)`` for RGB;
        pixel ``(i, j)`` is the square centred on ``(x, y) = (j, i)``.
    """
    return _render(item, style, canvas)["img"]


def item_svg(item, style, canvas):
    """The item as a complete, deterministic SVG document (same pixel coordinates)."""
    from stimuli.render.core import svg_text

    return svg_text(_render(item, style, canvas))
