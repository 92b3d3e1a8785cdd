"""Key paths into a scene document: read and set one value by the path its errors print.

A key path is what :class:`sliders.app.errors.Problem` prints: keys joined by dots, a table
of an array of tables by its index (``drive[0].motion.velocity``, ``beam[0].straight.
elements``, ``study.t_end``) or, where the tables have a ``name``, by that name in place of
the index (``body[airframe].mass``, ``force[tyre].D``); an element of an array by its index
(``study.start.velocity[2]``).  :func:`with_values` returns a copy of a scene document (the
dict ``tomllib`` reads) with values set at such paths, which the scene's validation then
checks like any other value (:func:`sliders.app.scene.parse_scene`).
"""

from __future__ import annotations

import copy
import re
from collections.abc import Mapping
from typing import Any

from fvbeam.names import suggest

#: One step of a key path: ``name`` or ``[index]`` / ``[name]``.
_STEP = re.compile(r"\.?([A-Za-z_][A-Za-z0-9_-]*)|\[([^\[\]]+)\]")


class KeyPathError(ValueError):
    """A key path that is malformed or leads nowhere in the scene; the message names it."""


def parse_key(key: str) -> tuple[str | int, ...]:
    """The steps of ``key``: table keys and names as ``str``, indexes as ``int``.

    >>> parse_key("drive[0].motion.velocity")
    ('drive', 0, 'motion', 'velocity')
    >>> parse_key("body[airframe].mass")
    ('body', '[airframe]', 'mass')
    """
    steps: list[str | int] = []
    position = 0
    while position < len(key):
        match = _STEP.match(key, position)
        if match is None or (position == 0 and key.startswith((".", "["))):
            raise KeyPathError(f"key {key!r}: cannot read it from {key[position:]!r} on")
        name, inside = match.groups()
        if name is not None:
            steps.append(name)
        elif inside.strip().lstrip("-").isdigit():
            steps.append(int(inside))
        else:
            steps.append(f"[{inside.strip()}]")
        position = match.end()
    if not steps:
        raise KeyPathError(f"key {key!r}: empty")
    return tuple(steps)


def _step_into(node: Any, step: str | int, key: str, done: str) -> tuple[Any, str | int]:
    """The container ``node`` and the key or index in it that ``step`` names."""
    here = done or "(scene)"
    if isinstance(step, int):
        if not isinstance(node, list):
            raise KeyPathError(f"key {key!r}: {here} is not an array, so it has no [{step}]")
        if not -len(node) <= step < len(node):
            raise KeyPathError(f"key {key!r}: {here} has {len(node)} entries, no [{step}]")
        return node, step
    if step.startswith("["):
        name = step[1:-1]
        if not isinstance(node, list):
            raise KeyPathError(f"key {key!r}: {here} is not an array of tables")
        names = [t.get("name") for t in node if isinstance(t, Mapping)]
        for index, table in enumerate(node):
            if isinstance(table, Mapping) and table.get("name") == name:
                return node, index
        known = [n for n in names if isinstance(n, str)]
        raise KeyPathError(
            f"key {key!r}: no table of {here} is named {name!r}"
            f"{suggest(name, known) if known else ' (its tables have no names: use an index)'}"
        )
    if not isinstance(node, dict):
        raise KeyPathError(f"key {key!r}: {here} is not a table, so it has no key {step!r}")
    return node, step


def _walk(document: dict, key: str) -> tuple[Any, str | int]:
    """The container holding ``key``'s last step, and that step (the last key may be absent
    from its table: setting it adds it; every step before must exist)."""
    steps = parse_key(key)
    node: Any = document
    done = ""
    for k, step in enumerate(steps):
        container, at = _step_into(node, step, key, done)
        done += f"[{at}]" if isinstance(at, int) else (f".{at}" if done else str(at))
        if k == len(steps) - 1:
            return container, at
        if isinstance(at, str) and at not in container:
            raise KeyPathError(f"key {key!r}: the scene has no {done}")
        node = container[at]
    raise AssertionError("unreachable")  # parse_key never returns no steps


def get_value(document: dict, key: str) -> Any:
    """The value at ``key`` in ``document`` (:class:`KeyPathError` if there is none)."""
    container, at = _walk(document, key)
    if isinstance(at, str) and at not in container:
        raise KeyPathError(f"key {key!r}: the scene has no such key")
    return container[at]


def check_key(document: dict, key: str) -> None:
    """Raise :class:`KeyPathError` unless ``key`` can be set in ``document``: every step but
    the last exists (a table's last key may be absent: the scene's default)."""
    _walk(document, key)


def with_values(document: dict, values: Mapping[str, Any]) -> dict:
    """A deep copy of ``document`` with each ``values[key]`` set at its key path.

    >>> scene = {"study": {"kind": "dynamic", "t_end": 1.0}, "body": [{"name": "a", "mass": 2.0}]}
    >>> with_values(scene, {"study.t_end": 0.5, "body[a].mass": 3.0})["body"]
    [{'name': 'a', 'mass': 3.0}]
    >>> scene["body"][0]["mass"]
    2.0
    """
    resolved = copy.deepcopy(document)
    for key, value in values.items():
        container, at = _walk(resolved, key)
        container[at] = copy.deepcopy(value)
    return resolved
