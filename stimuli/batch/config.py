"""Batch configs: read, validate and resolve the YAML file of ``attneave generate``.

A batch config is a YAML mapping::

    seed: 1                      # required; every stimulus seed derives from it
    canvas: {width: 256, height: 256, margin: 24}   # px (defaults 512, 512, 32)
    output: {png_bit_depth: 8, svg: false}          # 8 or 16; SVG beside each PNG
    style: {figure: 0.0, ground: 1.0, line_width: 3.0}  # defaults for every condition
    conditions:
      - name: rf                 # [A-Za-z0-9][A-Za-z0-9_.-]*, unique
        recipe: radial_frequency # a key of attneave.stimuli.batch.recipes.RECIPES
        params:                  # fixed recipe parameters (lengths in px, or r0_deg: degrees.py)
          r0: 80                 # (a list here is a list-valued parameter)
        grid:                    # grid axes: each value is a list; the cells are
          frequency: [3, 5]      # the product of the lists, first key slowest
          amplitude: [0.05, 0.1]
        repeats: 3               # stimuli per cell, each with its own seed
        style: {figure: 0.2}     # overrides the top-level style
        canvas: {width: 128}     # overrides the top-level canvas

A grid key may be a dotted path into a nested parameter, e.g.
``base.params.n_points: [6, 12]`` for a recipe whose ``base`` parameter is a
mapping. A key may be in ``params`` or in ``grid``, not both.

Every value is checked before anything is written: unknown keys, wrong types,
values out of range, and every grid cell's recipe parameters (with the
recipe's own pydantic model). The first problem is reported on one line that
names the file, the YAML line and the key path, e.g.::

    cfg.yaml:14: conditions[2].grid.amplitude[1]: must be > 0, got -0.1

A batch makes at most ``MAX_JOBS`` (100,000) recipe calls; the grid is
counted (the product of its list lengths times the repeats) before it is
expanded, so a grid of a million cells is refused at once, naming the
condition. The file itself is bounded too (:mod:`attneave.stimuli.batch.config_file`:
size, nesting, aliases).

Parameters named ``path`` or ending in ``_path`` are file names; relative ones
are taken relative to the config file's directory, and they are recorded as
written so that output files do not depend on where the config lives.

Seeds: the stimulus of condition ``c`` (index in the list), grid cell ``k``
and repeat ``r`` gets the integer seed
``SeedSequence(seed, spawn_key=(c, k, r)).generate_state(1, uint64)[0]``
and is drawn with ``numpy.random.default_rng(that_seed)``; the seed is written
to the manifest, so any stimulus can be remade from its row alone. No seed
depends on worker order or on the number of workers.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Optional

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from attneave.stimuli.batch.config_file import parse_yaml, read_text, resolved_text, yaml_line
from attneave.stimuli.batch.degrees import DegreeError, manifest_record, to_pixels, written_loc, written_params
from attneave.stimuli.batch.errors import describe, loc_str, suggest
from attneave.stimuli.batch.params import Style
from attneave.stimuli.batch.placement import Canvas, canvas_base, canvas_in_pixels
from attneave.stimuli.errors import InputError
from attneave.stimuli.stimulus_set import to_jsonable

__all__ = [
    "BatchConfig",
    "CanvasConfig",
    "ConditionConfig",
    "OutputConfig",
    "ResolvedBatch",
    "ResolvedCondition",
    "load_config",
    "resolve_config",
    "stimulus_seed",
]

NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.-]*$"
#: Smallest figure area (px, each side, inside the margins): a smaller image shows no usable shape.
MIN_FIGURE_PX = 8
MAX_JOBS = 100_000  # recipe calls per batch: planning and validating them takes seconds, not minutes

_STRICT = ConfigDict(extra="forbid", strict=True)


class CanvasConfig(BaseModel):
    """Image size and margin in pixels, or in degrees at a scale (:func:`~attneave.stimuli.batch.placement.canvas_in_pixels`)."""

    model_config = _STRICT

    width: int = Field(512, ge=MIN_FIGURE_PX, le=16384)
    height: int = Field(512, ge=MIN_FIGURE_PX, le=16384)
    margin: float = Field(32.0, ge=0, allow_inf_nan=False)
    width_deg: Optional[float] = Field(None, gt=0, le=180, allow_inf_nan=False)
    height_deg: Optional[float] = Field(None, gt=0, le=180, allow_inf_nan=False)
    margin_deg: Optional[float] = Field(None, ge=0, le=90, allow_inf_nan=False)
    px_per_deg: Optional[float] = Field(None, gt=0, allow_inf_nan=False)
    viewing_distance_cm: Optional[float] = Field(None, gt=0, allow_inf_nan=False)
    screen_width_cm: Optional[float] = Field(None, gt=0, allow_inf_nan=False)
    screen_width_px: Optional[int] = Field(None, gt=0)

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, values):
        return canvas_in_pixels(values)

    @field_validator("margin")
    @classmethod
    def _margin_fits(cls, margin, info):
        w, h = info.data.get("width"), info.data.get("height")
        if w is not None and h is not None and min(w, h) - 2 * margin < MIN_FIGURE_PX:
            raise ValueError(f"must be <= {(min(w, h) - MIN_FIGURE_PX) / 2:g} (the figure needs at least "
                             f"{MIN_FIGURE_PX} px between the margins of the {w}x{h} image), got {margin:g}")
        return margin


class OutputConfig(BaseModel):
    """What each stimulus is written as."""

    model_config = _STRICT

    png_bit_depth: Literal[8, 16] = 8
    svg: bool = False


class ConditionConfig(BaseModel):
    """One condition: a recipe, its fixed parameters, its grid axes, repeats."""

    model_config = _STRICT

    name: str = Field(pattern=NAME_PATTERN, max_length=80)
    recipe: str
    params: dict[str, Any] = Field(default_factory=dict)
    grid: dict[str, list[Any]] = Field(default_factory=dict)
    repeats: int = Field(1, ge=1, le=100_000)
    style: dict[str, Any] = Field(default_factory=dict)
    canvas: dict[str, Any] = Field(default_factory=dict)

    @field_validator("grid")
    @classmethod
    def _grid_lists_not_empty(cls, grid):
        for key, values in grid.items():
            if not values:
                raise ValueError(f"grid axis {key!r} is an empty list")
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*", key):
                raise ValueError(f"grid key {key!r} is not a parameter name or dotted path")
        return grid


class BatchConfig(BaseModel):
    """The whole batch config as written (before recipe parameters are checked)."""

    model_config = _STRICT

    attneave_version: Optional[str] = None  # written to config.yaml; ignored when read back
    seed: int = Field(ge=0, lt=2**63)
    canvas: CanvasConfig = Field(default_factory=CanvasConfig)
    output: OutputConfig = Field(default_factory=OutputConfig)
    style: dict[str, Any] = Field(default_factory=dict)
    conditions: list[ConditionConfig] = Field(min_length=1)


@dataclass
class ResolvedCondition:
    """A condition with every grid cell's parameters checked.

    Attributes
    ----------
    index, name, recipe, repeats
        As in the config (``index`` is the position in ``conditions``).
    cells : list of dict
        Per grid cell, the recipe parameters as the recipe gets them (JSON
        values; file paths absolute).
    recorded_cells : list of dict
        The same with file paths as written in the config; these go to files.
    axes : dict
        The grid as written (key -> list of values).
    style, canvas : dict
        Fully resolved (defaults and top-level values filled in).
    path_map : dict
        Absolute path -> path as written, to undo the path resolution in
        whatever the recipe records.
    models : list of RecipeParams
        Per grid cell, the validated parameter model: what the recipe gets
        (validated here once, never again on the way).
    style_model : Style
    canvas_model : Canvas
        The validated style and canvas, as the recipes and drawing get them.
    degrees : list of dict
        Per grid cell, the lengths given in degrees, their pixels and the
        scale (:func:`~attneave.stimuli.batch.degrees.manifest_record`); empty
        dicts when none were.
    """

    index: int
    name: str
    recipe: str
    repeats: int
    cells: list
    recorded_cells: list
    axes: dict
    params: dict
    style: dict
    canvas: dict
    path_map: dict = field(default_factory=dict)
    models: list = field(default_factory=list)
    style_model: Any = None
    canvas_model: Any = None
    degrees: list = field(default_factory=list)

    @property
    def n_jobs(self):
        return len(self.cells) * self.repeats


@dataclass
class ResolvedBatch:
    """A validated batch: what to make, and the text of its resolved config."""

    source: str
    seed: int
    output: dict
    conditions: list
    text: str  # the resolved config.yaml, byte for byte

    @property
    def sha256(self):
        return hashlib.sha256(self.text.encode("utf-8")).hexdigest()

    @property
    def n_jobs(self):
        return sum(c.n_jobs for c in self.conditions)


def stimulus_seed(config_seed, condition_index, cell, rep):
    """The integer seed of one recipe call; see the module docstring.

    Examples
    --------
    >>> s = stimulus_seed(1, 0, 0, 0)
    >>> s == stimulus_seed(1, 0, 0, 0) and s != stimulus_seed(1, 0, 0, 1)
    True
    """
    ss = np.random.SeedSequence(int(config_seed), spawn_key=(int(condition_index), int(cell), int(rep)))
    return int(ss.generate_state(1, np.uint64)[0])


# --------------------------------------------------------------------------- loading


def load_config(path):
    """Read, validate and resolve a batch config file.

    Parameters
    ----------
    path : str or Path
        The YAML file.

    Returns
    -------
    ResolvedBatch

    Raises
    ------
    InputError
        One line: ``FILE:LINE: key.path: what was expected`` (or the YAML
        syntax error with its line).
    """
    path = Path(path)
    text = read_text(path)
    root, data = parse_yaml(text, path)
    if data is None:
        raise InputError(f"{path}: the config is empty")
    if not isinstance(data, dict):
        raise InputError(f"{path}: the config must be a mapping of keys, got a {type(data).__name__}")
    return resolve_config(data, source=path, base_dir=path.parent, yaml_root=root)


def resolve_config(data, source="<config>", base_dir=".", yaml_root=None):
    """Validate a config mapping (as `yaml.safe_load` gives it) and resolve it.

    Parameters
    ----------
    data : dict
        The config.
    source : str or Path
        Name used in error messages.
    base_dir : str or Path
        Directory that relative file paths in recipe parameters are relative to.
    yaml_root : yaml.Node, optional
        The composed YAML document, to give line numbers in errors.

    Returns
    -------
    ResolvedBatch
    """
    src = str(source)
    base_dir = Path(os.path.abspath(base_dir))

    def fail(loc, msg):
        line = yaml_line(yaml_root, loc)
        where = f"{src}:{line}" if line else src
        raise InputError(f"{where}: {loc_str(loc)}: {msg}")

    def check(model, value, loc_prefix, strict=None):
        try:
            return model.model_validate(value, strict=strict)
        except ValidationError as exc:
            loc, msg = describe(exc, value, model)
            fail(tuple(loc_prefix) + tuple(loc), msg)

    cfg = check(BatchConfig, data, ())
    registry = _recipes()

    top_style = check(Style, cfg.style, ("style",)).model_dump(mode="json", by_alias=True)
    top_canvas = cfg.canvas.model_dump(mode="json", exclude_none=True)  # degrees only where given

    conditions = []
    n_jobs = 0
    for ci, cond in enumerate(cfg.conditions):
        loc0 = ("conditions", ci)
        if any(c.name == cond.name for c in cfg.conditions[:ci]):
            fail(loc0 + ("name",), f"condition name {cond.name!r} is used twice")
        if cond.recipe not in registry:
            fail(loc0 + ("recipe",), f"unknown recipe {cond.recipe!r}{suggest(cond.recipe, registry)}"
                 f" (expected one of: {', '.join(sorted(registry))})")
        params_model = registry[cond.recipe][0]

        # canvas and style: condition values override top-level ones, key by key
        canvas = _check_override(CanvasConfig, canvas_base(top_canvas, cond.canvas), cond.canvas,
                                 loc0 + ("canvas",), ("canvas",), fail, strict=True)
        style = _check_override(Style, top_style, cond.style, loc0 + ("style",), ("style",), fail)
        canvas_model = Canvas(canvas.width, canvas.height, canvas.margin)

        for key in cond.grid:
            if _has_path(cond.params, key.split(".")):
                fail(loc0 + ("grid", key), f"{key!r} is also in params; give it in one place only")

        # count before expanding: a grid of a million cells must be refused at once
        keys = list(cond.grid)
        n_cells = math.prod(len(cond.grid[key]) for key in keys)
        n_jobs += n_cells * cond.repeats
        if n_jobs > MAX_JOBS:
            fail(loc0 + ("grid",), f"condition {cond.name!r} makes {n_cells} grid cell(s) x {cond.repeats} "
                                   f"repeat(s), which brings the batch to {n_jobs} recipe calls; the limit is "
                                   f"{MAX_JOBS} per batch (split it into several configs)")

        cells, recorded, models, path_map, degrees = [], [], [], {}, []
        for combo in itertools.product(*(range(len(cond.grid[k])) for k in keys)):
            written = copy.deepcopy(cond.params)
            origin = {}  # dotted key -> loc of the value in the YAML
            for key, j in zip(keys, combo):
                _set_path(written, key.split("."), copy.deepcopy(cond.grid[key][j]))
                origin[key] = loc0 + ("grid", key, j)
            call, pmap = _resolve_paths(written, base_dir, lambda p: _value_loc(p, origin, loc0), fail)
            path_map.update(pmap)
            try:  # lengths given in degrees (r0_deg) become pixels at this condition's scale
                call, degs = to_pixels(call, params_model, canvas.px_per_deg)
            except DegreeError as exc:
                fail(_value_loc(exc.loc, origin, loc0), str(exc))
            try:
                model = params_model.model_validate(call)
            except ValidationError as exc:
                loc, msg = describe(exc, call, params_model)
                loc, note = written_loc(loc, degs, canvas.px_per_deg)
                fail(_value_loc(loc, origin, loc0), msg + note)
            degrees.append(manifest_record(degs, canvas.px_per_deg))
            dumped = to_jsonable(model.model_dump(mode="json", by_alias=True))
            models.append(model)
            cells.append(dumped)
            recorded.append(record_paths(dumped, pmap))

        params = copy.deepcopy(recorded[0])
        for key in keys:
            _del_path(params, key.split("."))
        written_params(params, degs, keys)  # lengths given in degrees stay in degrees (the same in every cell)
        conditions.append(
            ResolvedCondition(
                index=ci, name=cond.name, recipe=cond.recipe, repeats=cond.repeats, cells=cells,
                recorded_cells=recorded, axes=copy.deepcopy(cond.grid), params=params,
                style=style.model_dump(mode="json", by_alias=True), canvas=canvas.model_dump(mode="json", exclude_none=True),
                path_map=path_map, models=models, style_model=style, canvas_model=canvas_model, degrees=degrees,
            )
        )

    output = cfg.output.model_dump(mode="json")
    text = resolved_text(cfg.seed, output, top_canvas, top_style, conditions)
    return ResolvedBatch(source=src, seed=cfg.seed, output=output, conditions=conditions, text=text)


# --------------------------------------------------------------------------- helpers


def _recipes():
    # imported when a config is resolved, not when this module is: recipes pull in the generators
    from attneave.stimuli.batch.recipes import RECIPES

    return RECIPES


def _check_override(model, base, override, loc_override, loc_base, fail, strict=None):
    """Validate `base` updated by `override`; blame the override when it is involved."""
    merged = {**base, **override}
    try:
        return model.model_validate(merged, strict=strict)
    except ValidationError as exc:
        loc, msg = describe(exc, merged, model)
        # `base` alone is valid (checked before), so the override is what broke it
        fail((loc_override if override else loc_base) + tuple(loc), msg)


def _value_loc(loc, origin, loc0):
    """Map a loc inside the recipe parameters to where the value is written."""
    dotted = ".".join(str(p) for p in loc)
    best = None
    for key in origin:
        if dotted == key or dotted.startswith(key + "."):
            if best is None or len(key) > len(best):
                best = key
    if best is not None:
        rest = tuple(loc)[len(best.split(".")):]
        return origin[best] + rest
    return loc0 + ("params",) + tuple(loc)


def _resolve_paths(params, base_dir, loc_of, fail):
    """Make relative file parameters absolute; return (params, {abs: as written})."""
    out = copy.deepcopy(params)
    pmap = {}

    def walk(node, loc):
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        for k, v in list(items):
            if isinstance(v, (dict, list)):
                walk(v, loc + (k,))
            elif isinstance(k, str) and (k == "path" or k.endswith("_path")) and isinstance(v, str):
                p = Path(v).expanduser()
                absolute = p if p.is_absolute() else base_dir / p
                absolute = Path(os.path.normpath(absolute))
                if not absolute.exists():
                    fail(loc_of(loc + (k,)), f"no such file {v!r} (relative paths are relative to the "
                                             f"config file's directory)")
                node[k] = str(absolute)
                pmap[str(absolute)] = v
                pmap[str(absolute.resolve())] = v

    walk(out, ())
    return out, pmap


def record_paths(obj, path_map):
    """`obj` with the absolute file paths of `path_map` put back as written in the config.

    Examples
    --------
    >>> record_paths({"path": "/abs/shapes/a.csv", "n": 3}, {"/abs/shapes/a.csv": "shapes/a.csv"})
    {'path': 'shapes/a.csv', 'n': 3}
    """
    pmap = path_map
    if not pmap:
        return obj
    if isinstance(obj, dict):
        return {k: record_paths(v, pmap) for k, v in obj.items()}
    if isinstance(obj, list):
        return [record_paths(v, pmap) for v in obj]
    if isinstance(obj, str) and obj in pmap:
        return pmap[obj]
    return obj


def _has_path(d, keys):
    for k in keys:
        if not isinstance(d, dict) or k not in d:
            return False
        d = d[k]
    return True


def _set_path(d, keys, value):
    for k in keys[:-1]:
        if not isinstance(d.get(k), dict):
            d[k] = {}
        d = d[k]
    d[keys[-1]] = value


def _del_path(d, keys):
    for k in keys[:-1]:
        if not isinstance(d, dict) or k not in d:
            return
        d = d[k]
    if isinstance(d, dict):
        d.pop(keys[-1], None)
