"""Strict JSON reading, and the schema of simplified_model.json as a JSON Schema document.

:func:`load_json` reads a file with duplicate keys, NaN, Infinity, numbers beyond a float and
deep nesting refused, so a schema never sees them. :data:`MODEL_SCHEMA` validates a model
file against ``model_schema.json`` (JSON Schema draft 2020-12, shipped with the package) with
:class:`jsonschema.Draft202012Validator`; its :meth:`~Schema.check` raises an
:class:`~gd_analyze.errors.InputError` of one line naming the file and the key
(``robot.parameters``, ``choices.D11``, ``cost.additions``) of the most relevant fault
(:func:`jsonschema.exceptions.best_match`).

To add a key to the model file, add it to ``model_schema.json``.
"""

from __future__ import annotations

import functools
import json
import math
import os
from importlib import resources
from typing import Any

from ..errors import InputError, regular_file

__all__ = ["Schema", "load_json", "MODEL_SCHEMA", "MAX_DEPTH"]


def _is_int(checker, value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(checker, value) -> bool:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:                                 # an integer beyond a float
        return False


_TYPE_NAMES = {"object": "an object", "array": "a list", "string": "a string",
               "boolean": "true/false", "null": "null", "integer": "an integer",
               "number": "a number"}


def _kind(value) -> str:
    return {dict: "an object", list: "a list", str: "a string", bool: "true/false",
            type(None): "null", int: "an integer", float: "a number"}.get(type(value),
                                                                       type(value).__name__)


def _key(path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def _message(err) -> tuple[str, str]:
    """The (key, message) of one :class:`jsonschema.exceptions.ValidationError`, in the
    words of the tool."""
    key, value, schema, rule = _key(err.absolute_path), err.instance, err.schema, err.validator
    if rule == "type":
        types = schema["type"] if isinstance(schema["type"], list) else [schema["type"]]
        if isinstance(value, int) and not isinstance(value, bool) and "number" in types:
            return key, "number too large for a float"
        return key, f"expected {' or '.join(_TYPE_NAMES[t] for t in types)}, got {_kind(value)}"
    if rule in ("required", "dependentRequired"):       # a key missing, or missing beside one
        needed = err.validator_value if rule == "required" else [
            k for given, keys in err.validator_value.items() if given in value for k in keys]
        missing = next(k for k in needed if k not in value)
        return _key([*err.absolute_path, missing]), "missing key"
    if rule == "additionalProperties":
        unknown = min(set(value) - set(schema.get("properties", {})))
        known = ", ".join(schema.get("properties", {}))
        return _key([*err.absolute_path, unknown]), f"unknown key (known: {known})"
    if rule == "enum":
        choices = err.validator_value
        if all(isinstance(c, str) for c in choices):
            return key, f"expected one of {', '.join(choices)}, got {str(value)[:40]!r}"
        return key, f"expected {' or '.join(map(repr, choices))}, got {value!r}"[:200]
    if rule in ("minimum", "maximum", "exclusiveMinimum"):
        what = "an integer" if schema.get("type") == "integer" else "a number"
        lo = schema.get("exclusiveMinimum", schema.get("minimum", -math.inf))
        bracket = "(" if "exclusiveMinimum" in schema else "["
        return key, (f"expected {what} in {bracket}{lo:g}, {schema.get('maximum', math.inf):g}]"
                     f", got {value:g}")
    if rule == "maxLength":
        return key, f"string longer than {err.validator_value} characters"
    if rule == "maxItems":
        return key, f"more than {err.validator_value} items"
    if rule == "pattern":
        return key, f"malformed value {value[:40]!r}"
    return key, schema["description"] if rule == "not" else " ".join(err.message.split())[:200]


class Schema:
    """A JSON Schema (draft 2020-12) whose faults are one-line input errors.

    Parameters
    ----------
    document : dict
        The JSON Schema.
    """

    def __init__(self, document: dict) -> None:
        self.document = document

    @functools.cached_property
    def validator(self) -> Any:
        """The :class:`jsonschema.Draft202012Validator` of the document with JSON's own types
        (``1.0`` is not an integer, ``true`` not a number, and a number is one a float holds;
        the file's reader refuses NaN and Infinity already), made at the first check:
        jsonschema is imported only when a model file is read."""
        from jsonschema import Draft202012Validator, validators

        checker = Draft202012Validator.TYPE_CHECKER.redefine_many({"integer": _is_int,
                                                                   "number": _is_number})
        return validators.extend(Draft202012Validator, type_checker=checker)(self.document)

    def check(self, value: object, path: str | os.PathLike) -> None:
        """Validate a parsed JSON document.

        Parameters
        ----------
        value : object
            The parsed JSON document.
        path : str or os.PathLike
            The file, for the message.

        Raises
        ------
        InputError
            One line naming the file and the key of the most relevant fault
            (a key present with the wrong type first, the shallowest; else
            :func:`jsonschema.exceptions.best_match`, a wrong type before a wrong value).
        """
        from jsonschema.exceptions import best_match

        errors = list(self.validator.iter_errors(value))
        if not errors:
            return
        # a key present with the wrong type is named before keys that are missing (the
        # shallowest such key): a document of the wrong shape is told what its shape is
        wrong = [e for e in errors if e.validator == "type" and e.absolute_path]
        if wrong:
            err = min(wrong, key=lambda e: len(e.absolute_path))
        else:
            err = best_match(errors)
            # at the key best_match names, a wrong type says more than the value it cannot
            # hold
            err = next((e for e in errors if e.validator == "type"
                        and e.absolute_path == err.absolute_path), err)
        key, message = _message(err)
        raise InputError(message, path, column=key or "(document)")


def _no_duplicates(pairs):
    out = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate key {key!r}")
        out[key] = value
    return out


def _refuse_constant(name):
    raise ValueError(f"{name} is not a number JSON allows")


def _finite_float(text):
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"number {text[:30]} is too large for a float")
    return v


#: Deepest nesting of objects and lists :func:`load_json` accepts.
MAX_DEPTH = 64


def _depth(document):
    """The deepest nesting of objects and lists in a parsed document (0 for a scalar).

    Level by level, without recursion: its memory is a list of references of one level, and
    its time linear in the document's values.
    """
    depth, level = 0, [document]
    while level := [v for v in level if isinstance(v, (dict, list))]:
        depth += 1
        level = [x for v in level for x in (v.values() if isinstance(v, dict) else v)]
    return depth


def load_json(path: str | os.PathLike[str], what: str = "JSON") -> Any:
    """Read a JSON file strictly.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    what : str, optional
        What the file should be, for messages (e.g. ``"simplified-model JSON"``).

    Returns
    -------
    object
        The document.

    Raises
    ------
    InputError
        If the file is missing, a folder, unreadable, not UTF-8, not JSON, has a duplicate
        key, NaN or Infinity, a number beyond a float, or nesting deeper than
        :data:`MAX_DEPTH`. One line.
    """
    path = str(path)
    regular_file(path, f"a {what} file")
    try:
        with open(path, encoding="utf-8") as fh:
            document = json.loads(fh.read(), object_pairs_hook=_no_duplicates,
                                  parse_constant=_refuse_constant, parse_float=_finite_float)
        if _depth(document) > MAX_DEPTH:     # the parser's own limit is deeper, or none
            raise RecursionError
        return document
    except RecursionError:
        raise InputError(f"not a {what} file: nested too deeply", path) from None
    except UnicodeDecodeError:
        raise InputError(f"not a {what} file: not UTF-8 text", path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    except ValueError as exc:                     # JSONDecodeError is a ValueError
        msg = " ".join(str(exc).split())[:200]
        raise InputError(f"not a {what} file: {msg}", path) from None


#: The layout of simplified_model.json (schema_version 2; 1 lacks the explicit model's keys): the
#: package's ``model_schema.json``. The element keys of ``choices`` are checked against the
#: robot's n by the loader; the robot's parameters by
#: :func:`gd_analyze.model.robot_spec.robot_from_dict`.
MODEL_SCHEMA = Schema(json.loads(resources.files(__package__).joinpath("model_schema.json")
                                 .read_text(encoding="utf-8")))
