"""TOML types are taken strictly, as ``docs/scenes.md`` promises: ``"1.5"`` is not a number,
``1`` is not ``true``, ``"yes"`` is not a flag.  Checked for every scalar key of the schema
at once (each carries pydantic's ``Strict``, or a validator that refuses what it would
coerce), then for the keys that took ``output.vtu = "yes"``, ``study.planar = 0`` and a
tabulated motion's ``order = 1.0``."""

import tomllib
import typing

import pytest
from pydantic import BaseModel, Strict
from test_scenes import SCENES, problems

from sliders.app import schema

SCALARS = (bool, int, float, str)


def loose_keys(model: type[BaseModel], path: str = "", seen: set | None = None) -> list[str]:
    """The scalar keys of ``model`` and the tables under it that pydantic would coerce: a
    ``bool``, ``int``, ``float`` or ``str`` without ``Strict`` (nor a ``BeforeValidator``)."""
    seen = set() if seen is None else seen
    if model in seen:
        return []
    seen.add(model)
    out = []
    for name, field in model.model_fields.items():
        out += _loose(field.annotation, field.metadata, f"{path}{name}", seen)
    return out


def _loose(annotation, metadata, path: str, seen: set) -> list[str]:
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Annotated:
        return _loose(args[0], [*metadata, *args[1:]], path, seen)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return loose_keys(annotation, f"{path}.", seen)
    if annotation in SCALARS:
        strict = any(isinstance(m, Strict) or getattr(m, "strict", None) for m in metadata)
        return [] if strict else [path]
    if origin is typing.Literal:
        kinds = {type(a) for a in args}
        guarded = any(type(m).__name__ == "BeforeValidator" for m in metadata)
        return [] if kinds <= {str} or guarded else [path]
    return [key for arg in args for key in _loose(arg, [], path, seen)]


def test_every_scalar_key_of_the_schema_is_strict():
    assert loose_keys(schema.Scene) == []


def fig4() -> dict:
    return tomllib.loads((SCENES / "fig4_sliding_beams.toml").read_text())


@pytest.mark.parametrize(
    "where,key,value",
    [("output", "vtu", "yes"), ("study", "planar", 0), ("output", "vtu", 1)],
)
def test_a_flag_must_be_true_or_false(where, key, value):
    data = fig4()
    data[where][key] = value
    (problem,) = problems(data)
    assert problem.path == f"{where}.{key}" and problem.message == "must be true or false"


@pytest.mark.parametrize("order", [1.0, True])
def test_a_tabulated_order_must_be_an_integer(order):
    data = tomllib.loads((SCENES / "pushed_body.toml").read_text())
    drive = data["drive"][0]
    drive["motion"] = {"kind": "tabulated", "times": [0.0, 1.0], "values": [0.0, 0.1]}
    drive["motion"]["order"] = order
    (problem,) = problems(data)
    assert problem.path == "drive[0].motion.order" and "must be an integer" in problem.message
