"""A scene file's validation error as one line: the file, the key path (``material[0].nu``), what is wrong and
the allowed range, read from the pydantic model's JSON schema, so a range is stated where it is declared."""
from __future__ import annotations

import functools

from pydantic import ValidationError


@functools.cache
def _json_schema(model) -> dict:
    return model.model_json_schema()


def _schema_at(model, loc: tuple) -> dict:
    """The JSON schema node of the key at ``loc`` of ``model`` (through $ref, optional values and list items)."""
    root = _json_schema(model)

    def resolve(node):
        while True:
            if "$ref" in node:
                node = root["$defs"][node["$ref"].rsplit("/", 1)[-1]]
            elif "anyOf" in node:
                node = next((n for n in node["anyOf"] if n.get("type") != "null"), {})
            elif "allOf" in node:
                node = node["allOf"][0]
            else:
                return node

    node = resolve(root)
    for part in loc:
        node = resolve(node.get("items", {}) if isinstance(part, int) else node.get("properties", {}).get(part, {}))
    return node


def _key_path(loc: tuple) -> str:
    """('material', 0, 'nu') -> material[0].nu"""
    text = ""
    for part in loc:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text


def _allowed_range(node: dict) -> str:
    bounds = [(f"> {node['exclusiveMinimum']:g}" if "exclusiveMinimum" in node else
               f">= {node['minimum']:g}" if "minimum" in node else ""),
              (f"< {node['exclusiveMaximum']:g}" if "exclusiveMaximum" in node else
               f"<= {node['maximum']:g}" if "maximum" in node else "")]
    return " and ".join(b for b in bounds if b)


def _got(value) -> str:
    return f"{value:g}" if isinstance(value, (int, float)) and not isinstance(value, bool) else repr(value)


def _message(error: dict, model) -> tuple[tuple, str]:
    """(key location, text after the key) of one pydantic error."""
    loc, kind, value = tuple(error["loc"]), error["type"], error.get("input")
    if kind == "extra_forbidden":
        allowed = ", ".join(_schema_at(model, loc[:-1]).get("properties", {}))
        return loc, f"unknown {'section' if len(loc) == 1 else 'key'} (allowed: {allowed})"
    if kind == "missing":
        required = _schema_at(model, loc[:-1]).get("required", [])
        return loc, f"missing (need {', '.join(required)})" if required else "missing"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        return loc, f"out of range: need {_allowed_range(_schema_at(model, loc))}, got {_got(value)}"
    if kind == "literal_error":
        return loc, f"must be one of {', '.join(map(str, _schema_at(model, loc).get('enum', [])))}, got {value!r}"
    if kind == "value_error":
        text = str(error["ctx"]["error"])
        if not loc and ": " in text:    # a rule of the whole file names its key first
            key, text = text.split(": ", 1)
            return (key,), text
        return loc, text
    what = {"float_type": "a number", "int_type": "an integer", "int_from_float": "an integer",
            "bool_type": "true or false", "string_type": "a string", "tuple_type": "a list",
            "model_type": "a table", "model_attributes_type": "a table", "dict_type": "a table"}.get(kind)
    if what is not None:
        return loc, f"must be {what}, got {_got(value)} ({type(value).__name__})"
    if kind == "finite_number":
        return loc, f"must be finite, got {value}"
    if kind in ("too_short", "string_too_short"):
        return loc, f"must not be empty, got {value!r}"
    return loc, error["msg"]


def one_line(exc: ValidationError, source: str, model) -> str:
    """The first error of validating scene ``source`` against the pydantic ``model`` as one line: the file, the
    key path, what is wrong and the allowed range (read from the model's JSON schema)."""
    loc, text = _message(exc.errors()[0], model)
    key = _key_path(loc)
    return f"scene {source}: {key}: {text}" if key else f"scene {source}: {text}"
