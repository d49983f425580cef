"""Parameter schemas of the batch recipes: what a config may say, checked once.

Each recipe of :mod:`attneave.stimuli.batch.recipes` takes one pydantic model of this
module (unknown keys and out-of-range values are errors that name the key).
The config validates every grid cell with it when the file is read
(:mod:`attneave.stimuli.batch.config`); the validated models are what the workers
get, so nothing is parsed twice. :class:`Style` says how items are drawn.
"""

from __future__ import annotations

import typing
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationInfo,
    field_serializer,
    field_validator,
    model_validator,
)

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number

__all__ = [
    "Style", "RecipeParams", "ShapeParams", "AttneavePolygonParams", "AttneaveCurvedParams",
    "RadialFrequencyParams", "FourierParams", "SuperformulaParams", "BlobParams", "FromCsvParams",
    "FromImageParams", "SHAPES", "BaseShape", "DeformationParams", "LibraryNumbers", "SIZE_PX", "PLACED_PX",
    "length_fields",
]

# The one table of which parameters are lengths is this metadata, on the fields themselves: a config
# may give each of them in degrees as ``<name>_deg`` (:mod:`attneave.stimuli.batch.degrees`), and no
# other parameter. Two kinds, because placement treats them differently:
#: A length that sets the shape's size in the generator's own units (an RF pattern's ``r0``): pixels
#: when the shape is placed ``native``; ``placement: fit`` rescales the shape to the canvas instead.
SIZE_PX = {"unit": "px", "length": "size"}
#: A length measured on the shape once placed on the canvas (a deformation's ``displacement``): pixels
#: whatever the placement.
PLACED_PX = {"unit": "px", "length": "placed"}


def length_fields(model):
    """The parameters of `model` that are lengths in pixels: ``{name: 'size' or 'placed'}``.

    Read from the fields' metadata (:data:`SIZE_PX`, :data:`PLACED_PX`).

    Examples
    --------
    >>> length_fields(RadialFrequencyParams)
    {'r0': 'size'}
    >>> length_fields(DeformationParams)
    {'displacement': 'placed', 'width': 'placed'}
    """
    return {name: f.json_schema_extra["length"] for name, f in model.model_fields.items()
            if isinstance(f.json_schema_extra, dict) and "length" in f.json_schema_extra}


def _number_check(tp):
    """:func:`~attneave.stimuli.validate.as_number` or :func:`~attneave.stimuli.validate.as_int` for a
    field of type float or int (optional, or a list of them), with whether it is a list; else None."""
    if typing.get_origin(tp) is Annotated:
        tp = typing.get_args(tp)[0]
    if tp is float:
        return as_number, False
    if tp is int:
        return as_int, False
    if typing.get_origin(tp) is Union:
        found = [_number_check(a) for a in typing.get_args(tp) if a is not type(None)]
        return found[0] if len(found) == 1 else None
    if typing.get_origin(tp) is list and typing.get_args(tp):
        inner = _number_check(typing.get_args(tp)[0])
        return None if inner is None or inner[1] else (inner[0], True)
    return None


class LibraryNumbers(BaseModel):
    """A config schema whose numbers follow the library's rule (:mod:`attneave.stimuli.validate`).

    Every float or int field (optional, or a list of them) is first checked by
    the function that checks the same argument of the Python API, so that a
    quoted ``r0: "50"`` or ``n: true`` is refused in the API's words (pydantic
    alone would take them as 50 and 1); the field's own bounds follow.
    """

    @field_validator("*", mode="before")
    @classmethod
    def _library_rule(cls, v, info: ValidationInfo):
        field = cls.model_fields.get(info.field_name)
        found = None if field is None or v is None else _number_check(field.annotation)
        if found is None:
            return v
        check, many = found
        items = v if many and isinstance(v, (list, tuple)) else [v]
        for item in items:
            try:
                check(item, info.field_name)
            except InputError as exc:
                # the key is named by the config's error line (file, line, key path)
                raise ValueError(str(exc).removeprefix(f"{info.field_name}: ")) from None
        return v


def _check_colour(v):
    # one message for every wrong colour, rather than one per member of the union below
    def level(c):
        return isinstance(c, (int, float)) and not isinstance(c, bool) and 0 <= c <= 1

    if isinstance(v, (list, tuple)):
        if len(v) != 3 or not all(level(c) for c in v):
            raise ValueError(f"must be a grey level in [0, 1] or an [r, g, b] triple of them, got {list(v)!r}")
        return tuple(float(c) for c in v)
    if not level(v):
        raise ValueError(f"must be a grey level in [0, 1] or an [r, g, b] triple of them, got {v!r}")
    return v


Unit = Annotated[float, Field(ge=0, le=1)]
Colour = Annotated[Union[Unit, tuple[Unit, Unit, Unit]], BeforeValidator(_check_colour)]


class Style(LibraryNumbers):
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


class RecipeParams(LibraryNumbers):
    """Base of every recipe's parameters: unknown keys are errors."""

    model_config = ConfigDict(extra="forbid")


class ShapeParams(RecipeParams):
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


def _check_sampling(n, cycles, what, param):
    """The generators' rule (:func:`attneave.stimuli.shapes.generators.check_sampling`), when the config is read:
    at least 4 of the `n` points per cycle, or the shape aliases."""
    if n < 4 * cycles:
        raise ValueError(f"n: {n} points alias {what} {cycles:g} (at least 4 points per cycle are needed, "
                         f"n >= {4 * cycles:g}); raise n or lower {param}")


class AttneavePolygonParams(ShapeParams):
    """Attneave & Arnoult (1956) Method 1; see :func:`attneave.stimuli.shapes.generators.attneave_polygon`."""

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


class RadialFrequencyParams(ShapeParams):
    """Radial-frequency pattern; see :func:`attneave.stimuli.shapes.generators.radial_frequency`."""

    r0: float = Field(100.0, gt=0, allow_inf_nan=False, json_schema_extra=SIZE_PX,
                      description="mean radius (px when placement is native)")
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
        _check_sampling(self.n, max(self.frequency), "radial frequency", "frequency")
        return self


class FourierParams(ShapeParams):
    """Random Fourier shape; see :func:`attneave.stimuli.shapes.generators.fourier_shape`."""

    kind: Literal["radial", "elliptic"] = "radial"
    r0: float = Field(100.0, gt=0, allow_inf_nan=False, json_schema_extra=SIZE_PX)
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


class SuperformulaParams(ShapeParams):
    """Gielis' superformula; see :func:`attneave.stimuli.shapes.generators.superformula`."""

    m: float = Field(5.0, ge=0, allow_inf_nan=False)
    n1: float = Field(2.0, gt=0, allow_inf_nan=False)
    n2: float = Field(7.0, gt=0, allow_inf_nan=False)
    n3: float = Field(7.0, gt=0, allow_inf_nan=False)
    a: float = Field(1.0, gt=0, allow_inf_nan=False)
    b: float = Field(1.0, gt=0, allow_inf_nan=False)
    scale: float = Field(100.0, gt=0, allow_inf_nan=False, json_schema_extra=SIZE_PX)
    n: int = Field(1024, ge=8, le=1_000_000)

    @model_validator(mode="after")
    def _check(self):
        _check_sampling(self.n, self.m, "superformula m", "m")
        # the generator's closure rule, here so that the config is refused with its file and line
        # rather than when the recipe runs
        import numpy as np

        from attneave.stimuli.shapes.generators import superformula_radius

        probe = np.array([0.0, 1e-3, 2 * np.pi, 2 * np.pi + 1e-3])
        with np.errstate(all="ignore"):
            rp = superformula_radius(probe, self.m, self.n1, self.n2, self.n3, self.a, self.b)
        if np.isfinite(rp).all() and not np.allclose(rp[[0, 1]], rp[[2, 3]], rtol=1e-9, atol=0):
            raise ValueError(f"m: the superformula with m={self.m:g} does not close after one turn; use an even "
                             "integer m, or an odd integer with a == b and n2 == n3")
        return self


class BlobParams(ShapeParams):
    """Smooth random blob; see :func:`attneave.stimuli.shapes.generators.blob`."""

    r0: float = Field(100.0, gt=0, allow_inf_nan=False, json_schema_extra=SIZE_PX)
    # the generator's bound (attneave.stimuli.shapes.generators.MAX_BLOB_SIGMA), checked when the config is read
    sigma: float = Field(0.2, ge=0, le=3.0, allow_inf_nan=False, description="RMS of the log-radius")
    width: float = Field(0.6, gt=0, allow_inf_nan=False, description="correlation width in radians")
    n: int = Field(1024, ge=8, le=1_000_000)


class FromCsvParams(ShapeParams):
    """A contour from a CSV file with columns x, y; rescaled and centred."""

    path: str = Field(min_length=1)
    resample: Optional[int] = Field(None, ge=3, le=1_000_000)


class FromImageParams(ShapeParams):
    """The largest object of an image, via :func:`attneave.stimuli.extraction.outlines.extract_contours`."""

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


SHAPES: dict[str, type[ShapeParams]] = {
    "attneave_polygon": AttneavePolygonParams,
    "attneave_curved": AttneaveCurvedParams,
    "radial_frequency": RadialFrequencyParams,
    "fourier": FourierParams,
    "superformula": SuperformulaParams,
    "blob": BlobParams,
    "from_csv": FromCsvParams,
    "from_image": FromImageParams,
}


class BaseShape(RecipeParams):
    """The shape a deformation or guided set starts from: a generator and its params.

    ``params`` is validated here, once, into the generator's own model (a
    :class:`ShapeParams`), which the recipe then uses as it is.
    """

    generator: Literal[tuple(SHAPES)] = "attneave_polygon"  # type: ignore[valid-type]
    params: Any = Field(default_factory=dict, validate_default=True)

    @field_validator("params")
    @classmethod
    def _valid_params(cls, v, info: ValidationInfo):
        gen = info.data.get("generator")
        if gen is None:  # the generator's own error is reported
            return v
        model = SHAPES[gen]
        if not isinstance(v, model):
            if not isinstance(v, dict):
                raise ValueError(f"must be a mapping of {gen} parameters, got {v!r}")
            v = model.model_validate(v)
        if getattr(v, "version", None) == "both":
            raise ValueError("version 'both' makes two shapes; a base shape needs 'polygon' or 'curved'")
        return v

    @field_serializer("params")
    def _dump_params(self, v, info):
        # a base shape's own `draw` is never used (the recipe's draw / base_draw is), so the
        # resolved config does not write it: read back, it would contradict the recipe's
        if isinstance(v, BaseModel):
            return v.model_dump(mode=info.mode, by_alias=info.by_alias, exclude={"draw"})
        return v


def check_base_draw(base, used, key):
    """Refuse a base shape's ``draw`` that differs from how the recipe draws it.

    The deformation and guided recipes draw their base with their own
    ``draw`` / ``base_draw``; a ``draw`` given inside ``base.params`` would
    otherwise be accepted and silently ignored.
    """
    p = base.params
    # 'silhouette', the default, is let through: resolved configs written before this check hold it
    # beside base_draw: outline, and must run again as they are
    default = ShapeParams.model_fields["draw"].default
    if isinstance(p, ShapeParams) and "draw" in p.model_fields_set and p.draw != used and p.draw != default:
        raise ValueError(f"base.params.draw: {p.draw!r} is not used here: this recipe draws its base as "
                         f"{key} says ({used!r}); set {key}: {p.draw} instead")


class DeformationParams(RecipeParams):
    """Barenholtz et al. (2003) matched concave/convex changes; see :mod:`attneave.stimuli.shapes.deformations`."""

    base: BaseShape = Field(default_factory=BaseShape)
    mode: Literal["edge", "vertex", "bump"] = "edge"
    displacement: float = Field(10.0, gt=0, allow_inf_nan=False, json_schema_extra=PLACED_PX,
                                description="px the moved point travels")
    position: float = Field(0.5, gt=0, lt=1, description="where on the side the new vertex goes (edge mode)")
    width: Optional[float] = Field(None, gt=0, allow_inf_nan=False, json_schema_extra=PLACED_PX,
                                   description="bump half-width in px; null: automatic")
    min_turn: float = Field(0.0, ge=0, lt=180, description="minimum |turning angle| at the moved vertex (deg)")
    resample: Optional[int] = Field(None, ge=8, le=1_000_000, description="resample the placed base first (bump mode)")
    draw: Literal["silhouette", "outline"] = "silhouette"
    max_tries: int = Field(100, ge=1, le=100_000, description="base shapes drawn before giving up")

    @model_validator(mode="after")
    def _check_draw(self):
        check_base_draw(self.base, self.draw, "draw")
        return self

