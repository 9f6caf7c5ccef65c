"""User-written YAML files (worlds, missions, events): strict reading and one-line errors.

The specs ask that a bad file be rejected "with a message that names the file, the entry and
the field". This module does the two generic halves of that for any pydantic schema:

- :func:`read_yaml` turns a path into data or an ``InputError`` (missing, a directory, not
  text, not YAML, empty), refusing a key repeated in one mapping, which plain PyYAML would
  silently resolve to the last one, hiding a typo such as two ``x:`` in one pot;
- :func:`error_lines` turns a pydantic ``ValidationError`` into one line per problem, e.g.
  ``pots[3] (id P04): field 'flower': must be one of red, white, pink, none (got 'blue')``.
  Entries are found from the schema itself: a ``list[Model]`` field gives ``name[i]`` (with
  the item's ``id`` when it has one), a ``dict[key, Model]`` field ``name[key]``.
"""
from __future__ import annotations

import re
import typing
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError

from hw.errors import InputError


class StrictEntry(BaseModel):
    """Base of every entry of a user-written file: strict, because the file is a contract.

    ``extra='forbid'`` rejects unknown keys (a typo would otherwise be silently ignored);
    ``strict`` refuses ``x: '1.0'`` and ``tag: true`` instead of coercing them; NaN and
    infinity are never a position.
    """

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, use_attribute_docstrings=True)


class _UniqueKeyLoader(yaml.SafeLoader):
    """A safe loader that refuses a key repeated in one mapping."""


def _construct_unique_mapping(loader: _UniqueKeyLoader, node: yaml.MappingNode, deep: bool = False):
    loader.flatten_mapping(node)
    seen: set[Any] = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        try:
            duplicate = key in seen
        except TypeError:  # unhashable key: let the base constructor report it
            break
        if duplicate:
            raise yaml.constructor.ConstructorError(
                "while constructing a mapping", node.start_mark, f"found duplicate key {key!r}", key_node.start_mark)
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_unique_mapping)


def read_yaml(path: str | Path, kind: str) -> Any:
    """Parsed YAML of ``path``; ``kind`` ('world file', 'mission file') names it in messages."""
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{source}: {kind} not found") from None
    except IsADirectoryError:
        raise InputError(f"{source}: is a directory, not a {kind}") from None
    except UnicodeDecodeError:
        raise InputError(f"{source}: not a YAML {kind} (not UTF-8 text)") from None
    except OSError as exc:
        raise InputError(f"{source}: cannot read the {kind}: {exc.strerror or exc}") from None
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as exc:
        raise InputError(f"{source}: not valid YAML: {_yaml_reason(exc)}") from None
    if data is None:
        raise InputError(f"{source}: the {kind} is empty")
    return data


def _yaml_reason(exc: yaml.YAMLError) -> str:
    """``line L, column C: problem`` from a PyYAML error, on one line."""
    mark = getattr(exc, "problem_mark", None)
    problem = getattr(exc, "problem", None) or str(exc)
    where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
    return where + " ".join(str(problem).split())


# --- pydantic errors -> one line each ---------------------------------------------------------

_TYPES = {
    "float_type": "must be a number", "float_parsing": "must be a number",
    "int_type": "must be an integer", "int_parsing": "must be an integer",
    "int_from_float": "must be an integer", "string_type": "must be text",
    "bool_type": "must be true or false", "bool_parsing": "must be true or false",
    "list_type": "must be a list", "dict_type": "must be a mapping",
    "model_type": "must be a mapping", "model_attributes_type": "must be a mapping",
    "finite_number": "must be a finite number",
}
_BOUNDS = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}


def _field_shape(model: type[BaseModel], name: Any) -> tuple[str, type[BaseModel] | None]:
    """How field ``name`` of ``model`` holds entries: ('list'|'map'|'model'|'value', entry model)."""
    field = model.model_fields.get(name) if isinstance(name, str) else None
    if field is None:
        return "value", None
    ann = field.annotation
    origin, args = typing.get_origin(ann), typing.get_args(ann)
    if origin is list and args and _is_model(args[0]):
        return "list", args[0]
    if origin is dict and len(args) == 2 and _is_model(args[1]):
        return "map", args[1]
    if _is_model(ann):
        return "model", ann
    return "value", None


def _is_model(t: Any) -> bool:
    return isinstance(t, type) and issubclass(t, BaseModel)


def _holder(model: type[BaseModel] | None, path: list[Any]) -> type[BaseModel] | None:
    """The model holding the last field of a nested path (``estop.speed`` -> the estop entry's),
    so an unknown key lists the keys allowed where it is; list indices keep the entry model."""
    for name in path:
        if isinstance(name, int) or model is None:
            continue
        field = model.model_fields.get(name)
        inner = [a for a in typing.get_args(field.annotation) or (field.annotation,) if _is_model(a)] if field else []
        model = inner[0] if inner else None
    return model


def error_lines(exc: ValidationError, data: dict[str, Any], root: type[BaseModel]) -> list[str]:
    """One ``<entry>: field '<name>': <what is wrong>`` line per error of ``exc``."""
    return [_format_error(err, data, root) for err in exc.errors()]


def _format_error(err: dict[str, Any], data: dict[str, Any], root: type[BaseModel]) -> str:
    loc = list(err["loc"])
    entry, rest, model = "top level", loc, root
    if loc:
        shape, entry_model = _field_shape(root, loc[0])
        if shape == "list" and len(loc) > 1 and isinstance(loc[1], int):
            entry, rest, model = f"{loc[0]}[{loc[1]}]", loc[2:], entry_model
            items = data.get(loc[0])
            item = items[loc[1]] if isinstance(items, list) and loc[1] < len(items) else None
            if isinstance(item, dict) and isinstance(item.get("id"), (str, int)):
                entry += f" (id {item['id']})"
        elif shape == "map" and len(loc) > 1:
            key = loc[1] if isinstance(loc[1], int) else repr(loc[1])
            entry, rest, model = f"{loc[0]}[{key}]", loc[2:], entry_model
        elif shape == "model" and len(loc) > 1:
            entry, rest, model = str(loc[0]), loc[1:], entry_model
    if rest == ["[key]"]:
        return f"{entry}: key {loc[1]!r}: must be an integer id"
    what = describe(err, _holder(model, rest[:-1]) if rest else root)
    if not rest:
        return f"{entry}: {what}"
    return f"{entry}: field '{'.'.join(str(p) for p in rest)}': {what}"


def describe(err: dict[str, Any], model: type[BaseModel] | None) -> str:
    kind, ctx, got = err["type"], err.get("ctx") or {}, err.get("input")
    if kind == "missing":
        return "missing required key"
    if kind == "extra_forbidden":
        allowed = ", ".join(model.model_fields) if model else ""
        return f"unknown key (allowed: {allowed})" if allowed else "unknown key"
    if kind == "too_short":
        n = ctx.get("min_length", 1)
        count = len(got) if isinstance(got, (list, dict)) else shown(got)
        return f"must have at least {n} {'entry' if n == 1 else 'entries'} (got {count})"
    if kind == "literal_error":
        options = ", ".join(re.findall(r"'([^']*)'", str(ctx.get("expected", ""))))
        return f"must be one of {options} (got {shown(got)})"
    if kind in _BOUNDS:
        bound = next(iter(ctx.values()))
        return f"must be {_BOUNDS[kind]} {bound:g} (got {shown(got)})"
    if kind == "value_error":
        return str(err["msg"]).removeprefix("Value error, ")
    if kind in _TYPES:
        return f"{_TYPES[kind]} (got {shown(got)})"
    return f"{str(err['msg'])[:1].lower()}{str(err['msg'])[1:]} (got {shown(got)})"


def shown(value: Any) -> str:
    """A short rendering of an offending value: scalars as written, containers by kind."""
    if value is None:
        return "nothing"
    if isinstance(value, bool):
        return str(value).lower()  # as YAML spells it
    if isinstance(value, (dict, list)):
        return kind_of(value)
    return repr(value)


def kind_of(value: Any) -> str:
    """A user-facing name for the type of a YAML value."""
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"text {value[:40]!r}"
    if isinstance(value, (int, float)):
        return f"a number ({value!r})"
    return type(value).__name__
