"""The one translator of pydantic validation errors into one plain line.

It reads pydantic's structured errors (:meth:`pydantic.ValidationError.errors`:
``loc``, ``type``, ``msg``, ``ctx``, ``input``), never its message texts or
the names it gives union members. The key path is the part of ``loc`` that
the user wrote: a step of ``loc`` that is not a key (or index) of the input
(pydantic puts union members such as ``'float'`` there) is left out.
"""

from __future__ import annotations

import difflib
import typing

from pydantic import BaseModel

__all__ = ["describe", "loc_str", "suggest"]

# what a value of the wrong type should have been, by pydantic error type
_EXPECTED = {
    "int_type": "an integer", "int_parsing": "an integer", "int_from_float": "an integer",
    "float_type": "a number", "float_parsing": "a number", "finite_number": "a finite number",
    "bool_type": "true or false", "bool_parsing": "true or false", "string_type": "a string",
    "dict_type": "a mapping of keys", "model_type": "a mapping of keys",
    "model_attributes_type": "a mapping of keys", "list_type": "a list", "tuple_type": "a list",
}
_BOUNDS = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<=",
           "multiple_of": "a multiple of"}


def describe(exc, data=None, model=None):
    """The first problem of a validation error as ``(loc, message)``.

    Parameters
    ----------
    exc : pydantic.ValidationError
    data : object, optional
        The input that was validated; steps of ``loc`` not found in it are
        pydantic's own (union members) and are dropped.
    model : type of BaseModel, optional
        The model validated, to list the keys it knows after an unknown key.

    Returns
    -------
    loc : tuple
        The key path as written (str keys, int indices).
    message : str
        Plain words: ``must be >= 0, got -0.1``; ``unknown key (did you mean
        'sigma'?) ...``; ``(and N more problems)`` when there are others.

    Examples
    --------
    >>> from pydantic import BaseModel, Field, ValidationError
    >>> class P(BaseModel):
    ...     sigma: float = Field(0.2, ge=0)
    >>> try:
    ...     P.model_validate({"sigma": -1})
    ... except ValidationError as exc:
    ...     describe(exc, {"sigma": -1}, P)
    (('sigma',), 'must be >= 0.0, got -1')
    """
    errors = exc.errors(include_url=False)
    # an unknown key (a typo) usually explains a missing one: report it first
    first = min(errors, key=lambda e: e["type"] != "extra_forbidden")
    loc = _written(first, data)
    # a value that fits no member of a union gives one error per member, all at one written loc
    same = [e for e in errors if _written(e, data) == loc]
    constraint = [e for e in same if e["type"] not in _EXPECTED and e["type"] != "literal_error"]
    if len(same) > 1 and first["type"] != "extra_forbidden":
        if constraint:
            first = constraint[0]  # it had the type of one member but broke that member's constraint
            msg = _message(first, model, loc)
        else:
            wanted = dict.fromkeys(_EXPECTED.get(e["type"], "another value") for e in same)
            msg = f"must be {' or '.join(wanted)}, got {_got(first)}"
    else:
        msg = _message(first, model, loc)
    others = len({_written(e, data) for e in errors} - {loc})
    if others:
        msg += f" (and {others} more problem{'s' if others > 1 else ''})"
    return loc, msg


def loc_str(loc):
    """``conditions[2].grid.amplitude[1]`` from ``('conditions', 2, 'grid', 'amplitude', 1)``.

    Examples
    --------
    >>> loc_str(("conditions", 2, "grid", "amplitude", 1))
    'conditions[2].grid.amplitude[1]'
    """
    out = ""
    for p in loc:
        out += f"[{p}]" if isinstance(p, int) else ("." if out else "") + str(p)
    return out or "(top level)"


def suggest(word, choices):
    """`` (did you mean 'x'?)`` for the closest of `choices`, or ``''``."""
    close = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _written(err, data):
    """The steps of the error's loc that exist in `data` (plus a missing key at the end)."""
    raw = tuple(err["loc"])
    if data is None:
        return raw
    loc, node = [], data
    for i, p in enumerate(raw):
        if isinstance(node, dict) and p in node:
            node = node[p]
        elif isinstance(node, (list, tuple)) and isinstance(p, int) and 0 <= p < len(node):
            node = node[p]
        elif err["type"] == "missing" and i == len(raw) - 1 and isinstance(node, dict):
            pass  # the key that should have been there
        else:
            continue  # a step of pydantic's own
        loc.append(p)
    return tuple(loc)


def _got(e):
    v = e.get("input")
    if isinstance(v, (dict, list)) and len(repr(v)) > 60:
        return f"a {type(v).__name__}"
    return repr(v)


def _message(e, model, loc):
    t, ctx = e["type"], e.get("ctx") or {}
    if t == "extra_forbidden":
        fields = _fields_at(model, loc[:-1])
        hint = suggest(loc[-1], fields) if fields and loc else ""
        return f"unknown key{hint}" + (f" (expected one of: {', '.join(fields)})" if fields else "")
    if t == "missing":
        return "required key is missing"
    if t in _BOUNDS:
        return f"must be {_BOUNDS[t]} {next(iter(ctx.values()), '?')}, got {_got(e)}"
    if t in _EXPECTED:
        return f"must be {_EXPECTED[t]}, got {_got(e)}"
    if t == "literal_error":
        return f"must be {ctx.get('expected', 'one of the allowed values')}, got {_got(e)}"
    if t == "string_pattern_mismatch":
        return f"must match {ctx.get('pattern')}, got {_got(e)}"
    if t in ("too_short", "too_long"):
        n = ctx.get("min_length") if t == "too_short" else ctx.get("max_length")
        return f"must have at {'least' if t == 'too_short' else 'most'} {n} item(s), got {ctx.get('actual_length')}"
    if t == "string_too_long":
        return f"must be at most {ctx.get('max_length')} characters long"
    if t in ("value_error", "assertion_error"):
        # our own validators' words, as raised
        return str(ctx.get("error", e["msg"]))
    msg = e["msg"]
    return f"{msg[:1].lower()}{msg[1:]}, got {_got(e)}"


def _fields_at(model, loc):
    """Field names of the pydantic model reached by following `loc` from `model`."""
    tp = model
    for p in loc:
        if isinstance(tp, type) and issubclass(tp, BaseModel):
            f = tp.model_fields.get(p) if isinstance(p, str) else None
            tp = f.annotation if f is not None else None
        elif typing.get_origin(tp) in (list, dict) and typing.get_args(tp):
            tp = typing.get_args(tp)[-1]  # the item type of list[X] / dict[K, X]
        else:
            return []
    return list(tp.model_fields) if isinstance(tp, type) and issubclass(tp, BaseModel) else []
