"""Batch configs: read, validate and resolve the YAML file of ``attneave generate``.

A batch config is a YAML mapping::

    seed: 1                      # required; every stimulus seed derives from it
    canvas: {width: 256, height: 256, margin: 24}   # px (defaults 512, 512, 32)
    output: {png_bit_depth: 8, svg: false}          # 8 or 16; SVG beside each PNG
    style: {figure: 0.0, ground: 1.0, line_width: 3.0}  # defaults for every condition
    conditions:
      - name: rf                 # [A-Za-z0-9][A-Za-z0-9_.-]*, unique
        recipe: radial_frequency # a key of stimuli.recipes.RECIPES
        params:                  # fixed recipe parameters, taken verbatim
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
import difflib
import hashlib
import itertools
import json
import os
import re
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Optional

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from stimuli.errors import InputError

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
MAX_JOBS = 1_000_000  # a guard against a grid that would take days to even list

_STRICT = ConfigDict(extra="forbid", strict=True)


class CanvasConfig(BaseModel):
    """Image size and margin, in pixels."""

    model_config = _STRICT

    width: int = Field(512, gt=0, le=16384)
    height: int = Field(512, gt=0, le=16384)
    margin: float = Field(32.0, ge=0)

    @field_validator("margin")
    @classmethod
    def _margin_fits(cls, margin, info):
        w, h = info.data.get("width"), info.data.get("height")
        if w is not None and h is not None and 2 * margin >= min(w, h):
            raise ValueError(f"must be < {min(w, h) / 2:g} (half the smaller side of the {w}x{h} image), "
                             f"got {margin:g}")
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
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read ({exc})") from None
    try:
        data = yaml.safe_load(text)
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark is not None else f"{path}"
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise InputError(f"{where}: invalid YAML: {problem}") from None
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
    recipes_mod = _recipes()
    src = str(source)
    base_dir = Path(os.path.abspath(base_dir))

    def fail(loc, msg):
        line = _yaml_line(yaml_root, loc)
        where = f"{src}:{line}" if line else src
        raise InputError(f"{where}: {_loc_str(loc)}: {msg}")

    def check(model, value, loc_prefix, strict=None):
        try:
            return model.model_validate(value, strict=strict)
        except ValidationError as exc:
            loc, msg = _first_error(exc, model)
            fail(tuple(loc_prefix) + tuple(loc), msg)

    cfg = check(BatchConfig, data, ())
    registry = recipes_mod.RECIPES
    Style = recipes_mod.Style

    top_style = check(Style, cfg.style, ("style",)).model_dump(mode="json", by_alias=True)
    top_canvas = cfg.canvas.model_dump(mode="json")

    conditions = []
    n_jobs = 0
    for ci, cond in enumerate(cfg.conditions):
        loc0 = ("conditions", ci)
        if any(c.name == cond.name for c in cfg.conditions[:ci]):
            fail(loc0 + ("name",), f"condition name {cond.name!r} is used twice")
        if cond.recipe not in registry:
            fail(loc0 + ("recipe",), f"unknown recipe {cond.recipe!r}{_suggest(cond.recipe, registry)}"
                 f" (expected one of: {', '.join(sorted(registry))})")
        params_model = registry[cond.recipe][0]

        # canvas and style: condition values override top-level ones, key by key
        canvas = _check_override(CanvasConfig, top_canvas, cond.canvas, loc0 + ("canvas",), ("canvas",),
                                 fail, strict=True)
        style = _check_override(Style, top_style, cond.style, loc0 + ("style",), ("style",), fail)

        for key in cond.grid:
            if _has_path(cond.params, key.split(".")):
                fail(loc0 + ("grid", key), f"{key!r} is also in params; give it in one place only")

        keys = list(cond.grid)
        n_cells = 1
        for key in keys:
            n_cells *= len(cond.grid[key])
        n_jobs += n_cells * cond.repeats
        if n_jobs > MAX_JOBS:
            fail(loc0 + ("grid",), f"the batch would have more than {MAX_JOBS} recipe calls")

        cells, recorded, path_map = [], [], {}
        for combo in itertools.product(*(range(len(cond.grid[k])) for k in keys)):
            written = copy.deepcopy(cond.params)
            origin = {}  # dotted key -> loc of the value in the YAML
            for key, j in zip(keys, combo):
                _set_path(written, key.split("."), copy.deepcopy(cond.grid[key][j]))
                origin[key] = loc0 + ("grid", key, j)
            call, pmap = _resolve_paths(written, base_dir, lambda p: _value_loc(p, origin, loc0), fail)
            path_map.update(pmap)
            try:
                model = params_model.model_validate(call)
            except ValidationError as exc:
                loc, msg = _first_error(exc, params_model)
                fail(_value_loc(tuple(loc), origin, loc0), msg)
            dumped = _jsonable(model.model_dump(mode="json", by_alias=True))
            cells.append(dumped)
            recorded.append(_unmap_paths(dumped, pmap))

        params = copy.deepcopy(recorded[0])
        for key in keys:
            _del_path(params, key.split("."))
        conditions.append(
            ResolvedCondition(
                index=ci, name=cond.name, recipe=cond.recipe, repeats=cond.repeats, cells=cells,
                recorded_cells=recorded, axes=copy.deepcopy(cond.grid), params=params,
                style=style, canvas=canvas, path_map=path_map,
            )
        )

    output = cfg.output.model_dump(mode="json")
    text = _resolved_text(cfg.seed, output, top_canvas, top_style, conditions)
    return ResolvedBatch(source=src, seed=cfg.seed, output=output, conditions=conditions, text=text)


# --------------------------------------------------------------------------- helpers


def _recipes():
    import importlib

    try:
        return importlib.import_module("stimuli.batch.recipes")
    except ImportError as exc:  # pragma: no cover - only while the package is incomplete
        raise InputError(f"the stimulus recipes are not available ({exc})") from None


def _version():
    from stimuli import __version__

    return __version__


def _check_override(model, base, override, loc_override, loc_base, fail, strict=None):
    """Validate `base` updated by `override`; blame the override when it is involved."""
    merged = {**base, **override}
    try:
        return model.model_validate(merged, strict=strict).model_dump(mode="json", by_alias=True)
    except ValidationError as exc:
        loc, msg = _first_error(exc, model)
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


def _unmap_paths(obj, pmap):
    if not pmap:
        return obj
    if isinstance(obj, dict):
        return {k: _unmap_paths(v, pmap) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_unmap_paths(v, pmap) for v in obj]
    if isinstance(obj, str) and obj in pmap:
        return pmap[obj]
    return obj


def _jsonable(obj):
    """Plain JSON types, so that dumps are the same whatever produced them."""
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj)
    if obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, Path):
        return str(obj)
    return str(obj)


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


def _resolved_text(seed, output, canvas, style, conditions):
    import yaml

    doc = {
        "attneave_version": _version(),
        "seed": seed,
        "canvas": canvas,
        "output": output,
        "style": style,
        "conditions": [
            {
                "name": c.name,
                "recipe": c.recipe,
                "params": c.params,
                "grid": c.axes,
                "repeats": c.repeats,
                "style": c.style,
                "canvas": c.canvas,
            }
            for c in conditions
        ],
    }
    header = (
        "# Resolved batch config written by `attneave generate` (defaults filled in).\n"
        "# Rerunning it gives the same files: attneave generate config.yaml -o DIR\n"
    )
    body = yaml.dump(_jsonable(doc), Dumper=_dumper(), sort_keys=False, default_flow_style=False,
                     allow_unicode=True, width=4096)
    return header + body


def _dumper():
    import yaml

    class Dumper(yaml.SafeDumper):
        """Safe dumper that writes lists of scalars on one line: ``[3, 5]``."""

    def represent_list(dumper, data):
        flow = all(not isinstance(v, (dict, list)) for v in data)
        return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flow)

    Dumper.add_representer(list, represent_list)
    return Dumper


def _loc_str(loc):
    out = ""
    for p in loc:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + str(p)
    return out or "(top level)"


def _suggest(word, choices):
    close = difflib.get_close_matches(str(word), list(choices), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _first_error(exc, model):
    """(loc, message) of the first pydantic error, in plain words."""
    errors = exc.errors(include_url=False)
    # an unknown key (a typo) usually explains a missing one: report it first
    e = min(errors, key=lambda err: err["type"] != "extra_forbidden")
    raw = tuple(e["loc"])
    loc = tuple(p for p in raw if not _is_union_tag(p))
    msg = _message(e, model, loc)
    tag_at = next((i for i, p in enumerate(raw) if isinstance(p, str) and _is_union_tag(p)), None)
    if tag_at is not None and e["type"] != "extra_forbidden":
        # a value that fits none of the members of a union: name the members
        members = [err for err in errors if tuple(err["loc"])[:tag_at] == raw[:tag_at]
                   and len(err["loc"]) > tag_at and _is_union_tag(str(err["loc"][tag_at]))]
        tags = list(dict.fromkeys(str(err["loc"][tag_at]) for err in members))
        whole = next((err for err in members if len(err["loc"]) == tag_at + 1), e)
        if len(tags) > 1:
            fitting = [err for err in members if not _is_type_mismatch(err)]
            if fitting:
                # the value has the type of one member but breaks its constraint: say which
                e = fitting[0]
                loc = tuple(p for p in e["loc"] if not _is_union_tag(p))
                msg = _message(e, model, loc)
            else:
                loc = tuple(p for p in raw[:tag_at] if not _is_union_tag(p))
                msg = f"must be {' or '.join(_plain_type(t) for t in tags)}, got {_got(whole)}"
            errors = [err for err in errors if err not in members] + [e]
    if len(errors) > 1:
        msg += f" (and {len(errors) - 1} more problem{'s' if len(errors) > 2 else ''})"
    return loc, msg


def _plain_type(tag):
    words = {"float": "a number", "int": "an integer", "str": "a string", "bool": "true or false"}
    if tag in words:
        return words[tag]
    m = re.fullmatch(r"tuple\[(.*)\]", tag)
    if m:
        parts = [x.strip().removeprefix("constrained-") for x in m.group(1).split(",")]
        if len(set(parts)) == 1 and parts[0] in words:
            return f"a list of {len(parts)} {'numbers' if parts[0] == 'float' else parts[0] + 's'}"
    m = re.fullmatch(r"constrained-(\w+)", tag)
    if m:
        return _plain_type(m.group(1))
    return tag


_TYPE_WORDS = {"int", "float", "str", "bool", "bytes", "list", "tuple", "dict", "set", "none", "decimal",
               "date", "datetime", "any"}
_TAG_PREFIXES = ("constrained-", "function-", "lax-", "strict-", "json-or-python", "nullable", "chain",
                 "default", "union", "tagged-union", "literal", "is-instance", "enum")


def _is_union_tag(p):
    # pydantic puts the union member ('float', 'constrained-float', 'tuple[float, float, float]')
    # into loc; these are not keys anyone wrote
    return isinstance(p, str) and (p in _TYPE_WORDS or "[" in p or p.startswith(_TAG_PREFIXES))


def _is_type_mismatch(err):
    t = err["type"]
    return t.endswith(("_type", "_parsing")) or t in ("is_instance_of", "literal_error", "union_tag_invalid")


def _got(e):
    v = e.get("input")
    if isinstance(v, (dict, list)) and len(repr(v)) > 60:
        return f"a {type(v).__name__}"
    return repr(v)


def _message(e, model, loc):
    t = e["type"]
    ctx = e.get("ctx") or {}
    if t == "extra_forbidden":
        key = loc[-1] if loc else "?"
        fields = _fields_at(model, loc[:-1])
        hint = _suggest(key, fields) if fields else ""
        expected = f" (expected one of: {', '.join(fields)})" if fields else ""
        return f"unknown key{hint}{expected}"
    if t == "missing":
        return "required key is missing"
    if t in ("greater_than", "greater_than_equal", "less_than", "less_than_equal", "multiple_of"):
        op = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<=",
              "multiple_of": "a multiple of"}[t]
        bound = next(iter(ctx.values())) if ctx else "?"
        return f"must be {op} {bound}, got {_got(e)}"
    if t in ("int_type", "int_parsing", "int_from_float"):
        return f"must be an integer, got {_got(e)}"
    if t in ("float_type", "float_parsing", "finite_number"):
        return f"must be a finite number, got {_got(e)}" if t == "finite_number" else \
            f"must be a number, got {_got(e)}"
    if t in ("bool_type", "bool_parsing"):
        return f"must be true or false, got {_got(e)}"
    if t in ("string_type",):
        return f"must be a string, got {_got(e)}"
    if t in ("dict_type", "model_type", "model_attributes_type"):
        return f"must be a mapping of keys, got {_got(e)}"
    if t in ("list_type", "tuple_type"):
        return f"must be a list, got {_got(e)}"
    if t == "literal_error":
        return f"must be {ctx.get('expected', 'one of the allowed values')}, got {_got(e)}"
    if t == "string_pattern_mismatch":
        return f"must match {ctx.get('pattern')}, got {_got(e)}"
    if t == "too_short":
        return f"must have at least {ctx.get('min_length')} item(s), got {ctx.get('actual_length')}"
    if t == "too_long":
        return f"must have at most {ctx.get('max_length')} item(s), got {ctx.get('actual_length')}"
    if t == "string_too_long":
        return f"must be at most {ctx.get('max_length')} characters long"
    msg = e["msg"]
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    msg = msg[:1].lower() + msg[1:]
    return msg if t in ("value_error", "assertion_error") else f"{msg}, got {_got(e)}"


def _fields_at(model, loc):
    """Field names of the pydantic model reached by following `loc` from `model`."""
    tp = model
    for p in loc:
        tp = _descend(tp, p)
        if tp is None:
            return []
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        return list(tp.model_fields)
    return []


def _descend(tp, p):
    tp = _unwrap(tp)
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        f = tp.model_fields.get(p) if isinstance(p, str) else None
        return f.annotation if f is not None else None
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin in (list, tuple) and isinstance(p, int) and args:
        return args[0] if origin is list or len(args) == 2 and args[1] is Ellipsis else (
            args[p] if p < len(args) else None)
    if origin is dict and len(args) == 2:
        return args[1]
    return None


def _unwrap(tp):
    # Optional[X] / Annotated[X, ...] -> X (first model-like member)
    origin = typing.get_origin(tp)
    if origin is typing.Annotated:
        return _unwrap(typing.get_args(tp)[0])
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        for a in typing.get_args(tp):
            if isinstance(a, type) and issubclass(a, BaseModel):
                return a
    return tp


def _yaml_line(root, loc):
    """1-based line of the YAML node at `loc` (or of its deepest existing parent)."""
    if root is None:
        return None
    import yaml

    node = root
    line = node.start_mark.line + 1
    for p in loc:
        if isinstance(node, yaml.MappingNode) and isinstance(p, str):
            for k, v in node.value:
                if getattr(k, "value", None) == p:
                    line = k.start_mark.line + 1
                    node = v
                    break
            else:
                return line
        elif isinstance(node, yaml.SequenceNode) and isinstance(p, int) and 0 <= p < len(node.value):
            node = node.value[p]
            line = node.start_mark.line + 1
        else:
            return line
    if not isinstance(node, (yaml.MappingNode, yaml.SequenceNode)):
        line = node.start_mark.line + 1
    return line


def manifest_json(obj):
    """Deterministic compact JSON used for the manifest's ``params``/``style`` columns."""
    return json.dumps(_jsonable(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)
