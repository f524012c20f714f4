"""Declarative validation of JSON documents, and the schema of simplified_model.json.

A schema is built from a few node types: :class:`Obj` (a JSON object with named fields, each
required or optional; unknown keys refused), :class:`MapOf` (an object whose keys are data),
:class:`ListOf`, :class:`Num`, :class:`Int`, :class:`Str`, :class:`Const` and :class:`AnyJSON`.
``schema.check(document, path)`` raises an :class:`~gd_analyze.errors.InputError` of one line
naming the key (``robot.parameters``, ``choices.D11``, ``cost.additions``) at the first
fault, and returns nothing.

:func:`load_json` reads a file with duplicate keys, NaN, Infinity, numbers beyond a float and
deep nesting refused, so a schema never sees them.

To add a key to the model file, add one line to :data:`MODEL_SCHEMA`.
"""

from __future__ import annotations

import json
import math
import re

from ..errors import InputError

__all__ = ["Obj", "MapOf", "ListOf", "Num", "Int", "Str", "Const", "Consts", "AnyJSON",
           "Field", "load_json", "MODEL_SCHEMA", "COST_SCHEMA", "MAX_DEPTH", "MAX_HARMONIC"]


def _kind(value):
    return {dict: "an object", list: "a list", str: "a string", bool: "true/false",
            type(None): "null", int: "an integer", float: "a number"}.get(type(value),
                                                                       type(value).__name__)


class _Node:
    expected = "a value"

    def check(self, value, path, where=""):
        """Validate a value against this schema.

        Parameters
        ----------
        value : object
            The parsed JSON value.
        path : str
            The file, for the message.
        where : str, optional
            The value's key path in the document (e.g. ``"robot.parameters"``).

        Raises
        ------
        InputError
            At the first fault, one line naming the key.
        """
        self._check(value, path, where)

    def _check(self, value, path, where):
        raise NotImplementedError

    def fail(self, message, path, where):
        raise InputError(message, path, column=where or "(document)")

    def expect(self, value, path, where):
        self.fail(f"expected {self.expected}, got {_kind(value)}", path, where)


class AnyJSON(_Node):
    """Any JSON value (already free of NaN, duplicates and deep nesting by :func:`load_json`)."""

    def _check(self, value, path, where):
        pass


class Const(_Node):
    """Exactly this value (and type: ``true`` is not ``1``).

    Parameters
    ----------
    value : object
        The only value accepted.
    """

    def __init__(self, value):
        self.value = value
        self.expected = repr(value)

    def _check(self, value, path, where):
        if type(value) is not type(self.value) or value != self.value:
            self.fail(f"expected {self.value!r}, got {value!r}"[:120], path, where)


class Consts(_Node):
    """One of these values (and types: ``true`` is not ``1``).

    Parameters
    ----------
    *values : object
        The values accepted.
    """

    def __init__(self, *values):
        self.values = values
        self.expected = " or ".join(repr(v) for v in values)

    def _check(self, value, path, where):
        if not any(type(value) is type(v) and value == v for v in self.values):
            self.fail(f"expected {self.expected}, got {value!r}"[:200], path, where)


class Num(_Node):
    """A finite number (an integer counts) in [lo, hi].

    Parameters
    ----------
    lo, hi : float, optional
        The accepted range (default: any finite number).
    lo_open : bool, optional
        Exclude lo.
    """

    expected = "a number"

    def __init__(self, lo=-math.inf, hi=math.inf, lo_open=False):
        self.lo, self.hi, self.lo_open = lo, hi, lo_open

    def _check(self, value, path, where):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.expect(value, path, where)
        try:
            v = float(value)
        except OverflowError:
            self.fail("number too large for a float", path, where)
        ok = math.isfinite(v) and (self.lo < v if self.lo_open else self.lo <= v) \
            and v <= self.hi
        if not ok:
            bracket = "(" if self.lo_open else "["
            self.fail(f"expected a number in {bracket}{self.lo:g}, {self.hi:g}], got {v:g}",
                      path, where)


class Int(Num):
    """An integer in [lo, hi] (parameters as :class:`Num`)."""

    expected = "an integer"

    def _check(self, value, path, where):
        if isinstance(value, bool) or not isinstance(value, int):
            self.expect(value, path, where)
        if not self.lo <= value <= self.hi:
            self.fail(f"expected an integer in [{self.lo:g}, {self.hi:g}]", path, where)


class Str(_Node):
    """A string.

    Parameters
    ----------
    choices : sequence of str, optional
        The accepted values.
    pattern : str, optional
        A regular expression the whole string must match.
    max_len : int, optional
        Longest accepted string [characters].
    """

    expected = "a string"

    def __init__(self, choices=None, pattern=None, max_len=100_000):
        self.choices, self.max_len = choices, max_len
        self.pattern = None if pattern is None else re.compile(pattern)

    def _check(self, value, path, where):
        if not isinstance(value, str):
            self.expect(value, path, where)
        if len(value) > self.max_len:
            self.fail(f"string longer than {self.max_len} characters", path, where)
        if self.choices is not None and value not in self.choices:
            self.fail(f"expected one of {', '.join(self.choices)}, got {value[:40]!r}", path,
                      where)
        if self.pattern is not None and not self.pattern.fullmatch(value):
            self.fail(f"malformed value {value[:40]!r}", path, where)


class ListOf(_Node):
    """A list of items of one schema.

    Parameters
    ----------
    item : schema node
        The schema of every item.
    max_len : int, optional
        Most items accepted.
    """

    expected = "a list"

    def __init__(self, item, max_len=1_000_000):
        self.item, self.max_len = item, max_len

    def _check(self, value, path, where):
        if not isinstance(value, list):
            self.expect(value, path, where)
        if len(value) > self.max_len:
            self.fail(f"more than {self.max_len} items", path, where)
        for k, v in enumerate(value):
            self.item._check(v, path, f"{where}[{k}]")


class MapOf(_Node):
    """An object whose keys are data (e.g. element labels), all values of one schema.

    Parameters
    ----------
    value : schema node
        The schema of every value.
    """

    expected = "an object"

    def __init__(self, value):
        self.value = value

    def _check(self, value, path, where):
        if not isinstance(value, dict):
            self.expect(value, path, where)
        for k, v in value.items():
            self.value._check(v, path, f"{where}.{k}" if where else k)


class Field:
    """A field of an :class:`Obj`.

    Parameters
    ----------
    schema : schema node
        The field's schema.
    required : bool, optional
        Whether the key must be present (default True).
    """

    def __init__(self, schema, required=True):
        self.schema, self.required = schema, required


class Obj(_Node):
    """An object with named fields.

    Parameters
    ----------
    fields : dict
        Key -> :class:`Field`, or a schema node (a required field).
    open_keys : bool, optional
        Accept (and do not check) keys not in ``fields``; by default they are refused.
    """

    expected = "an object"

    def __init__(self, fields, open_keys=False):
        self.fields = {k: f if isinstance(f, Field) else Field(f) for k, f in fields.items()}
        self.open_keys = open_keys

    def _check(self, value, path, where):
        if not isinstance(value, dict):
            self.expect(value, path, where)
        for key, f in self.fields.items():
            sub = f"{where}.{key}" if where else key
            if key in value:
                f.schema._check(value[key], path, sub)
            elif f.required:
                self.fail("missing key", path, sub)
        unknown = sorted(set(value) - set(self.fields))
        if unknown and not self.open_keys:
            sub = f"{where}.{unknown[0]}" if where else unknown[0]
            self.fail(f"unknown key (known: {', '.join(self.fields)})", path, sub)


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


def _depth(text):
    """The deepest nesting of [ and { outside strings (an upper bound if the text is not JSON).

    Linear in the text's length: a quote ends a string unless an odd run of backslashes
    precedes it; no regular expression, whose backtracking over a run of escaped quotes with
    no closing one is quadratic (48 KB took 30 s).
    """
    import numpy as np

    codes = np.frombuffer(text.encode("utf-8", "replace"), np.uint8)
    if not codes.size:
        return 0
    index = np.arange(codes.size)
    slash = codes == 92
    last_other = np.maximum.accumulate(np.where(slash, -1, index))   # last non-backslash
    run = np.zeros(codes.size, np.int64)                 # backslashes just before each byte
    run[1:] = index[:-1] - last_other[:-1]
    quote = (codes == 34) & (run % 2 == 0)
    inside = (np.cumsum(quote) - quote) % 2 == 1         # within a string (its quotes: out)
    outside = ~inside & ~quote
    steps = (outside & ((codes == 91) | (codes == 123))).astype(np.int64) \
        - (outside & ((codes == 93) | (codes == 125)))
    return int(np.cumsum(steps).max())


def load_json(path, what="JSON"):
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
    import os

    path = str(path)
    if not os.path.exists(path):
        raise InputError("no such file", path)
    if not os.path.isfile(path):
        raise InputError(f"not a regular file: give a {what} file", path)
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        if _depth(text) > MAX_DEPTH:
            raise RecursionError
        return json.loads(text, object_pairs_hook=_no_duplicates,
                          parse_constant=_refuse_constant, parse_float=_finite_float)
    except RecursionError:
        raise InputError(f"not a {what} file: nested too deeply", path) from None
    except UnicodeDecodeError:
        raise InputError(f"not a {what} file: not UTF-8 text", path) from None
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    except ValueError as exc:                     # JSONDecodeError is a ValueError
        msg = " ".join(str(exc).split())[:200]
        raise InputError(f"not a {what} file: {msg}", path) from None


_HEX64 = Str(pattern=r"[0-9a-f]{64}")
#: An operation count, as issue 8's models record it.
COST_SCHEMA = Obj({"multiplications": Int(0, 10**15), "additions": Int(0, 10**15),
                   "sin": Field(Int(0, 10**15), required=False),
                   "cos": Field(Int(0, 10**15), required=False)})
#: Largest |entry| of a harmonic vector K of a model file: a harmonic's multiple of a joint angle,
#: or a power of a prismatic joint variable. The derivation gives at most 2 (D is quadratic in
#: each joint's rotation and in each prismatic variable); the straight-line code forms a
#: multiple angle or a power by recursion over this entry, so a larger one is refused.
MAX_HARMONIC = 16
#: The kept terms of an explicit model (issue 8), one list entry per term; lengths and ranges
#: are checked by :func:`gd_analyze.io.model_file.load_model`.
_TERMS_SCHEMA = Obj({
    "kind": ListOf(Str(choices=("D", "h", "c"))),
    "part": ListOf(Str(choices=("tran", "rot", "both", "grav"))),
    "i": ListOf(Int(-1, 10**6)), "j": ListOf(Int(-1, 10**6)), "k": ListOf(Int(-1, 10**6)),
    "K": ListOf(ListOf(Int(-MAX_HARMONIC, MAX_HARMONIC))),
    "sin": ListOf(AnyJSON()),
    "coef": ListOf(Num()),
})

_NUMS = ListOf(Num())
_NONNEG = ListOf(Num(0.0, math.inf))
#: Where a model's bound holds (issue 29): ``"region"`` (proved over the joint-limit region,
#: :mod:`gd_analyze.core.selection.region`) or ``"trajectory"`` (the trajectories it was built
#: on); lengths are checked by :meth:`gd_analyze.core.selection.guarantee.Guarantee.from_dict`.
#: The region of a guarantee (:meth:`gd_analyze.core.selection.region.Region.to_dict`): per
#: joint a position range [lo, hi] or "any angle (full turn)", velocity and acceleration
#: limits, which acceleration limits are assumed; ranges and lengths are checked by
#: :meth:`gd_analyze.core.selection.region.Region.from_dict`.
_REGION_SCHEMA = Obj({
    "units": Field(Str(max_len=200), required=False),
    "q": ListOf(AnyJSON()),
    "qd_max": ListOf(Num(0.0, math.inf, lo_open=True)),
    "qdd_max": ListOf(Num(0.0, math.inf, lo_open=True)),
    "qdd_max_assumed": ListOf(Consts(True, False)),
    "prismatic": ListOf(Consts(True, False)),
    "qdd_rule": Field(Str(max_len=200), required=False),
    "source": Field(Str(max_len=400), required=False),
    "notes": Field(ListOf(Str(max_len=400), max_len=10_000), required=False),
})

_GUARANTEE_SCHEMA = Obj({
    "kind": Str(choices=("region", "trajectory")),
    "statement": Field(Str(max_len=400), required=False),
    "q_min": Field(_NUMS, required=False), "q_max": Field(_NUMS, required=False),
    "qd_max": Field(_NONNEG, required=False), "qdd_max": Field(_NONNEG, required=False),
    "scale": Field(_NONNEG, required=False),
    "scale_state": Field(ListOf(_NUMS), required=False),
    "bound": _NONNEG,
    "sampled_error": Field(_NONNEG, required=False),
    "method": Field(Str(max_len=2000), required=False),
    "trajectory_sha256": Field(Str(pattern=r"[0-9a-f]{64}|"), required=False),
    "trajectories_sha256": Field(ListOf(Str(pattern=r"[0-9a-f]{64}|")), required=False),
    "region_sampled_error": Field(AnyJSON(), required=False),
    "region_missing": Field(Str(max_len=400), required=False),
    "region": Field(_REGION_SCHEMA, required=False),
})

#: A model of the recursive form (issue 17): its base parameters, the dropped (parameter,
#: part) pairs and its bound; checked against the robot by
#: :meth:`gd_analyze.core.symbolic.recursive_model.RecursiveModel.from_dict`.
_RECURSIVE_SCHEMA = Obj({
    "base_parameters": ListOf(Str(max_len=16)),
    "beta": ListOf(Num()),
    "dropped": ListOf(ListOf(Str(max_len=16))),
    "scale": ListOf(Num(0.0, math.inf)),
    "bound": ListOf(Num(0.0, math.inf)),
    "bound_by_part": Obj({"inertial": ListOf(Num(0.0, math.inf)),
                          "velocity": ListOf(Num(0.0, math.inf)),
                          "gravity": ListOf(Num(0.0, math.inf)),
                          "whole": ListOf(Num(0.0, math.inf))}),
    # the pairs whose contribution was round-off where the model was built (absent before)
    "round_off": Field(ListOf(ListOf(Str(max_len=16))), required=False),
    # the round-off pairs left out with their dropped parameter; "dropped" names only pairs
    # that contribute, as the reports do (issue 31; absent before: "dropped" held both)
    "dropped_round_off": Field(ListOf(ListOf(Str(max_len=16))), required=False),
})

#: The proof that D_s is positive definite where the bound holds (issue 40 item 1;
#: :func:`gd_analyze.core.selection.positive_definite.with_inertia_check`). Read but never
#: believed: a model read from a file states no proof it has not made again. Files of issue
#: 30's layout (a sampled ``positive_definite``) are still read.
_OPT_NUM = Field(AnyJSON(), required=False)
_INERTIA_CHECK_SCHEMA = Obj({
    "where": Str(choices=("region", "trajectory")),
    "proved": Field(Consts(True, False), required=False),
    "lower_bound": _OPT_NUM,
    "ratio": _OPT_NUM,
    "d_upper": _OPT_NUM,
    "witness": Field(ListOf(AnyJSON()), required=False),
    "floor": Field(ListOf(AnyJSON()), required=False),
    "boxes": Field(Int(0, 10**9), required=False),
    "samples": Int(0, 10**9),
    "sampled_min_eigenvalue": _OPT_NUM,
    "seconds": _OPT_NUM,
    "why": Field(Str(max_len=2000), required=False),
    "unit": Field(Str(max_len=200), required=False),
    "statement": Field(Str(max_len=2000), required=False),
    "restored": ListOf(Str(max_len=16)),
    "method": Str(max_len=2000),
}, open_keys=True)

#: The layout of simplified_model.json (schema_version 2; 1 lacks the keys of issue 8). The element keys of ``choices`` are
#: checked against the robot's n by the loader; the robot's parameters by
#: :func:`gd_analyze.core.model.robot_spec.robot_from_dict`.
MODEL_SCHEMA = Obj({
    "schema_version": Consts(1, 2),
    "kind": Field(Str(max_len=200), required=False),
    "robot": Obj({
        "name": Str(max_len=200),
        "sha256": Str(pattern=r"[0-9a-f]{64}|"),
        "parameters_sha256": _HEX64,
        "source": Field(Str(max_len=4096), required=False),
        "parameters": Obj({}, open_keys=True),
    }),
    # the key of issue 32: the mounting the model was built with (its gravity is turned)
    "mounting": Field(Obj({"base_rpy_deg": _NUMS, "gravity_world": _NUMS}), required=False),
    "dominance_threshold": Num(0.5, 1.0, lo_open=True),
    "negligible_threshold": Num(0.0, 1.0),
    "choices": MapOf(Str(choices=("tran", "rot", "both", "none", "pruned"))),
    "trajectory_sha256": Field(Str(pattern=r"[0-9a-f]{64}|"), required=False),
    "validation": Field(Obj({}, open_keys=True), required=False),
    "provenance": Field(Obj({}, open_keys=True), required=False),
    # the keys of issue 8 (tolerance-driven simplification, explicit model)
    "tolerance": Field(Num(0.0, math.inf), required=False),
    "rule": Field(Str(choices=("budget", "chapter")), required=False),
    "torque_floor": Field(Num(0.0, math.inf), required=False),
    "cost": Field(COST_SCHEMA, required=False),
    "full_cost": Field(COST_SCHEMA, required=False),
    "bound": Field(ListOf(AnyJSON()), required=False),
    "explicit_terms": Field(_TERMS_SCHEMA, required=False),
    # the keys of issue 17 (the recursive form, and the costs of the models compared)
    "form": Field(Str(choices=("explicit", "recursive")), required=False),
    "recursive": Field(_RECURSIVE_SCHEMA, required=False),
    "costs": Field(MapOf(COST_SCHEMA), required=False),
    # the key of issue 29: where the bound holds (a region of states, or one trajectory)
    "guarantee": Field(_GUARANTEE_SCHEMA, required=False),
    # the key of issue 30: D_s positive definite where the bound holds (proved)
    "inertia_check": Field(_INERTIA_CHECK_SCHEMA, required=False),
})
