"""Scene validation errors: one exception that lists every problem found, each at its key path.

A :class:`Problem` names the key path in the scene (``slider[1].smearing``: the second
``[[slider]]`` table, its ``smearing`` key), the value found there and what is allowed.
:class:`SceneError` carries all the problems of one validation phase and formats them as one
message.  :func:`schema_problems` turns pydantic's errors into problems: the path in scene
terms (pydantic's union tags removed), a plain message, and a did-you-mean for unknown keys,
kinds and names (:func:`fvbeam.names.suggest`).
"""

from __future__ import annotations

import reprlib
import types
import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from pydantic import BaseModel, ValidationError
from pydantic_core import ErrorDetails

from fvbeam.names import suggest


class _NoValue:
    def __repr__(self) -> str:
        return "<no value>"


#: Marker for a problem that has no value to show (a missing key, a whole table).
NO_VALUE: Any = _NoValue()


#: What a build that leaves the floating-point range is told (:meth:`Problems.attempt`).
NON_FINITE = (
    "its numbers make one that is not finite (beyond the range of double precision, or "
    "undefined): scale the model's units"
)


#: ``repr`` that stops after a few entries and characters: a message shows at most 60
#: characters of a value, however large the value (an array of millions of numbers).
_SHORT = reprlib.Repr()
_SHORT.maxlist = _SHORT.maxtuple = _SHORT.maxdict = _SHORT.maxset = 10
_SHORT.maxstring = _SHORT.maxother = _SHORT.maxlong = 60


def show(value: Any, limit: int = 60) -> str:
    """A value as the message shows it: ``repr``, shortened to ``limit`` characters."""
    text = _SHORT.repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


@dataclass(frozen=True)
class Problem:
    """One thing wrong with a scene: where (``path``), what was found (``value``) and what is
    allowed (``message``)."""

    path: str
    message: str
    value: Any = NO_VALUE

    def __str__(self) -> str:
        found = "" if self.value is NO_VALUE else f" = {show(self.value)}"
        return f"{self.path or '(scene)'}{found}: {self.message}"


class SceneError(ValueError):
    """An invalid scene: every problem found, in one message (``source`` names the file).

    Attributes
    ----------
    source : str
        The scene file (or a label) the problems were found in.
    problems : tuple of Problem
        What is wrong, in the order found.
    """

    def __init__(
        self, source: str, problems: Sequence[Problem], what: str = "invalid scene"
    ) -> None:
        self.source, self.problems = source, tuple(problems)
        count = len(self.problems)
        head = f"{source}: {what}, {count} problem{'s' if count != 1 else ''}"
        super().__init__("\n  ".join([head] + [str(p) for p in self.problems]))


class Problems(list):
    """A list of :class:`Problem` that collects the ``ValueError`` of a build step."""

    def add(self, path: str, message: str, value: Any = NO_VALUE) -> None:
        self.append(Problem(path, message, value))

    def attempt(self, path: str, build: Callable[[], Any], value: Any = NO_VALUE) -> Any:
        """``build()``, or ``None`` with its ``ValueError`` recorded at ``path``.  A number
        out of floating-point range on the way (numpy's overflow, division by zero or
        undefined result, raised here; Python's ``ArithmeticError``) is recorded too: finite
        values that make a non-finite one (a length of ``1e200`` squared) are refused where
        they are built, never carried into a solve."""
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise"):
                return build()
        except ArithmeticError as exc:  # FloatingPointError, OverflowError, ZeroDivisionError
            self.add(path, f"{NON_FINITE} ({exc})", value)
        except ValueError as exc:
            self.add(path, str(exc), value)
        return None

    def raise_if_any(self, source: str, what: str = "invalid scene") -> None:
        if self:
            raise SceneError(source, self, what)


# -- pydantic's errors in scene terms ---------------------------------------------------------
_TYPES = {
    "float_type": "a number",
    "int_type": "an integer",
    "int_from_float": "an integer",
    "string_type": "a string",
    "bool_type": "true or false",
    "tuple_type": "a list",
    "list_type": "a list",
    "model_type": "a table",
    "model_attributes_type": "a table",
    "dict_type": "a table",
}


def _unwrap(annotation: Any) -> Any:
    """The type inside ``Annotated[...]`` and ``X | None``."""
    while True:
        if typing.get_origin(annotation) is typing.Annotated:
            annotation = typing.get_args(annotation)[0]
            continue
        args = _union_members(annotation)
        if args is not None and type(None) in args and len(args) == 2:
            annotation = next(a for a in args if a is not type(None))
            continue
        return annotation


def _union_members(annotation: Any) -> tuple | None:
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return typing.get_args(annotation)
    return None


def _sequence(annotation: Any) -> bool:
    """Whether ``annotation`` is a tuple or list type."""
    return typing.get_origin(annotation) in (tuple, list)


def _sequence_label(label: str) -> bool:
    """Whether pydantic's name of a union member, ``label``, is a tuple's or a list's."""
    return label.startswith(("tuple[", "list["))


def _kind_tag(model: Any) -> str | None:
    """The literal ``kind`` of a tagged table class, if it has one."""
    field = getattr(model, "model_fields", {}).get("kind")
    if field is None:
        return None
    args = typing.get_args(_unwrap(field.annotation))
    return args[0] if len(args) == 1 else None


@dataclass
class _Place:
    """Where a pydantic error location points in the scene: the display path, the table class
    holding its last key, that key's field, the annotation reached and the tags of a
    union on the way."""

    path: str = ""
    table: Any = None
    field: Any = None
    annotation: Any = None
    tags: tuple[str, ...] = ()


def _walk(root: type[BaseModel], loc: Sequence[Any]) -> _Place:
    place, node = _Place(), typing.cast(Any, root)
    for item in loc:
        node = _unwrap(node)
        members = _union_members(node)
        if members is not None:
            tags = {_kind_tag(m): m for m in members}
            if item in tags:
                node = tags[item]
                continue
            if isinstance(item, str) and all(t is None for t in tags):
                # an untagged union's member, named by pydantic (``tuple[...]`` for the
                # sequence): not a key of the scene
                node = next((m for m in members if _sequence(m) == _sequence_label(item)), None)
                continue
        if isinstance(node, type) and issubclass(node, BaseModel):
            place.table, place.field = node, node.model_fields.get(item)
            place.path += f".{item}" if place.path else str(item)
            node = place.field.annotation if place.field is not None else None
        elif isinstance(item, int):
            place.path += f"[{item}]"
            args = typing.get_args(node)
            node = args[0] if args else None
            place.field = None
        else:
            place.path += f".{item}" if place.path else str(item)
            node = None
    place.annotation = _unwrap(node)
    members = _union_members(place.annotation)
    if members is not None:
        place.tags = tuple(t for t in map(_kind_tag, members) if t is not None)
    return place


def _choices(annotation: Any) -> list[str]:
    """The allowed strings of a ``Literal`` annotation (or of a tuple of them)."""
    if typing.get_origin(annotation) is typing.Literal:
        return [str(a) for a in typing.get_args(annotation)]
    args = typing.get_args(annotation)
    if typing.get_origin(annotation) is tuple and args:
        return _choices(_unwrap(args[0]))
    return []


def _message(error: ErrorDetails, place: _Place) -> tuple[str, str]:
    """The path and message of one pydantic error (``place``: where its location points)."""
    kind, ctx, value = error["type"], error.get("ctx", {}), error.get("input")
    described = place.field.description if place.field is not None else None
    if kind == "extra_forbidden":
        allowed = list(place.table.model_fields) if place.table is not None else []
        key = str(error["loc"][-1])
        return place.path, (
            f"unknown key{suggest(key, allowed)}; allowed here: {', '.join(allowed)}"
        )
    if kind == "missing":
        return place.path, "missing: this key is required" + (
            f" ({described})" if described else ""
        )
    if kind in ("union_tag_invalid", "union_tag_not_found"):
        tags = ", ".join(repr(t) for t in place.tags)
        if kind == "union_tag_not_found":
            return f"{place.path}.kind", f"missing: this key is required (one of {tags})"
        return f"{place.path}.kind", (f"must be one of {tags}{suggest(ctx.get('tag'), place.tags)}")
    if kind == "literal_error":
        choices = _choices(place.annotation)
        return place.path, (
            f"must be one of {', '.join(repr(c) for c in choices)}{suggest(value, choices)}"
        )
    if kind in ("too_short", "too_long"):
        low, high = ctx.get("min_length"), ctx.get("max_length")
        size = (
            f"exactly {high}"
            if low == high and low is not None
            else f"at least {low}"
            if kind == "too_short"
            else f"at most {high}"
        )
        what = f" ({described})" if described else ""
        return place.path, f"must have {size} entries{what}, got {ctx.get('actual_length')}"
    if kind == "finite_number":
        return place.path, "must be a finite number (not nan or inf)"
    if kind in ("greater_than", "greater_than_equal", "less_than_equal"):
        sign = {"greater_than": "> ", "greater_than_equal": ">= ", "less_than_equal": "<= "}
        bound = next(iter(ctx.values()))
        return place.path, f"must be {sign[kind]}{bound}"
    if kind in _TYPES or kind == "string_pattern_mismatch":
        return place.path, f"must be {described or _TYPES.get(kind, 'a string')}"
    if kind == "value_error":
        return place.path, str(ctx.get("error", error["msg"]))
    return place.path, error["msg"]


def _one_branch(errors: list[ErrorDetails]) -> list[ErrorDetails]:
    """The errors of an untagged union of a value and a sequence of it (``X | tuple[X, ...]``)
    from the branch the input's shape chose: a list in the scene is judged as the sequence,
    anything else as the value (pydantic reports both branches, each under its label)."""
    unions = {
        e["loc"][:i]
        for e in errors
        for i, item in enumerate(e["loc"])
        if isinstance(item, str) and _sequence_label(item)
    }
    is_sequence = {  # the value branch's error is at the union itself: its input the value
        e["loc"][:-1]: isinstance(e.get("input"), list | tuple)
        for e in errors
        if e["loc"][:-1] in unions and isinstance(e["loc"][-1], str)
    }

    def chosen(error: ErrorDetails) -> bool:
        loc = error["loc"]
        for at in unions:
            n = len(at)
            label = loc[n] if len(loc) > n else None
            if at in is_sequence and loc[:n] == at and isinstance(label, str):
                return _sequence_label(label) == is_sequence[at]
        return True

    return [e for e in errors if chosen(e)]


def schema_problems(exc: ValidationError, root: type[BaseModel]) -> list[Problem]:
    """The errors of validating ``root`` as problems at their scene paths.

    A list's length is only reported when none of its entries is wrong (pydantic counts the
    entries that passed)."""
    problems = []
    errors = _one_branch(exc.errors(include_url=False))
    for error in errors:
        loc = error["loc"]
        if error["type"] in ("too_short", "too_long") and any(
            len(e["loc"]) > len(loc) and e["loc"][: len(loc)] == loc for e in errors
        ):
            continue
        place = _walk(root, error["loc"])
        path, message = _message(error, place)
        missing = error["type"] in ("missing", "union_tag_not_found")
        value = NO_VALUE if missing else error.get("input", NO_VALUE)
        if error["type"] == "union_tag_invalid":
            value = error.get("ctx", {}).get("tag", NO_VALUE)
        problems.append(Problem(path, message, value))
    return problems
