"""Limits on the size of what a scene may ask for, checked before anything is allocated.

A few bytes of TOML can ask for any amount of work (``elements = 10000000000``, a sweep of a
billion samples) or hold more than a scene ever needs (a file of gigabytes, an array of
millions of entries, arrays nested thousands deep).  Each size is checked where it is first
known, before the work it asks for: the scene file's bytes before reading it, its nesting
before parsing it (:func:`nesting`), the entries and depth of its arrays and tables before
validating them (:func:`shape_problems`), the elements, static solves, time steps and mesh
bytes it asks for before building anything (:func:`size_problems`), and the elements of mesh
files once read, before any beam is assembled (:func:`element_problems`).

Every limit but the nesting depth is raised by an environment variable,
``FVSLIDER_MAX_<NAME>`` (:data:`LIMITS`); :meth:`Limits.from_environment` reads them, and a
:class:`Limits` can be passed to :func:`sliders.app.scene.load_scene` and
:class:`sliders.app.model.Model` from Python.  The defaults leave every shipped scene a
long way below them and keep the largest scene they admit within a few gigabytes and minutes
(``docs/scenes.md``, Limits, gives the measurements).
"""

from __future__ import annotations

import dataclasses
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO

from sliders.app.errors import Problem, Problems
from sliders.app.schema import DynamicStudy, Scene, SweepStudy

#: The nesting depth of arrays and tables a scene may have, fixed: the schema's deepest key,
#: a row of a slider's ``frame``, is 4 levels down (``slider[0].frame[0][0]``), and Python's
#: TOML reader recurses a few frames per level of arrays and inline tables, so that it runs out
#: of stack between 200 and 400 levels (measured, Python 3.11): there is nothing to raise it
#: for, and no room to.
DEPTH = 32
#: The largest value a limit may take, 2**53: every integer up to it is exact as a float (so
#: ``9e15`` reads as written), and sizes compared with it never overflow.  A limit is a
#: count compared with what a scene asks for, never an amount allocated: the scene file is
#: read in pieces of :data:`CHUNK` bytes (:func:`read_at_most`).
MAXIMUM = 2**53
#: The bytes of a scene file read at a time.
CHUNK = 1 << 20


@dataclass(frozen=True)
class Limits:
    """The sizes a scene may ask for (:data:`LIMITS` says what each counts); defaults in
    the field definitions, each raised by its environment variable (:meth:`variable`)."""

    scene_bytes: int = 1 << 20
    mesh_bytes: int = 16 << 20
    entries: int = 100_000
    elements: int = 100_000
    solves: int = 100_000
    steps: int = 100_000

    def __post_init__(self) -> None:
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAXIMUM:
                raise ValueError(
                    f"limit {field.name} must be an integer from 1 to 2**53, got {value!r}"
                )

    @staticmethod
    def variable(name: str) -> str:
        """The environment variable that raises the limit ``name``."""
        return f"FVSLIDER_MAX_{name.upper()}"

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] | None = None) -> "Limits":
        """The defaults, each replaced by its environment variable when set (an integer from
        1 to :data:`MAXIMUM`: ``2000000``, ``2_000_000`` or ``2e6``); a bad value raises
        :class:`~sliders.app.errors.SceneError` naming the variable."""
        environ = os.environ if environ is None else environ
        values: dict[str, int] = {}
        problems = Problems()
        for field in dataclasses.fields(cls):
            text = environ.get(cls.variable(field.name))
            number = None if text is None else _positive_integer(text)
            if number is not None:
                values[field.name] = number
            elif text is not None:
                problems.add(
                    cls.variable(field.name),
                    f"must be an integer from 1 to 2**53 = {MAXIMUM}: it raises the limit on "
                    f"{LIMITS[field.name]}",
                    text,
                )
        problems.raise_if_any("environment", "invalid limits")
        return cls(**values)

    def problem(self, name: str, path: str, found: str, value: Any = None) -> Problem:
        """``found`` (what the scene asks for) over the limit ``name``: the problem at
        ``path``, saying the limit and how to raise it."""
        limit = getattr(self, name)
        message = (
            f"{found}, more than the limit of {limit} {LIMITS[name]}; raise it with the "
            f"environment variable {self.variable(name)}"
        )
        return Problem(path, message) if value is None else Problem(path, message, value)


#: What each limit counts (in messages and ``docs/scenes.md``).
LIMITS = {
    "scene_bytes": "bytes in a scene file",
    "mesh_bytes": "bytes in the mesh files a scene reads, in all",
    "entries": "entries in one array or table",
    "elements": "beam elements, in one beam and in all",
    "solves": "static solves in a study (samples x load_steps)",
    "steps": "time steps in a dynamic study (t_end / step)",
}


def _positive_integer(text: str) -> int | None:
    """``text`` as an integer from 1 to :data:`MAXIMUM` (digits, or a float's form of one:
    ``2e6``), else None."""
    text = text.strip().replace("_", "")
    try:
        number = int(text) if text.lstrip("+").isdigit() else float(text)
    except (ValueError, OverflowError):
        return None
    if isinstance(number, float) and not number.is_integer():  # also inf and nan
        return None
    return int(number) if 1 <= number <= MAXIMUM else None


def read_at_most(file: BinaryIO, limit: int) -> bytes:
    """The first ``limit + 1`` bytes of ``file`` at most, read :data:`CHUNK` bytes at a time:
    the memory taken is that of the bytes the file has, never that of the limit (a read of
    ``limit + 1`` bytes at once allocates them first)."""
    chunks, total = [], 0
    while total <= limit:
        chunk = file.read(min(CHUNK, limit + 1 - total))
        if not chunk:
            break
        chunks.append(chunk)
        total += len(chunk)
    return b"".join(chunks)


# -- before parsing -----------------------------------------------------------------------
#: TOML's strings and comments (in which brackets do not nest), and its brackets.
_TOKENS = re.compile(
    r'"""(?:\\.|[^\\])*?"""|\'\'\'.*?\'\'\'|"(?:\\.|[^"\\\n])*"|\'[^\'\n]*\'|#[^\n]*|[\[\]{}]',
    re.S,
)


def nesting(text: str) -> tuple[int, int]:
    """The deepest nesting of arrays and inline tables (and table headers) in the TOML
    ``text``, and the line where it is first reached, found without parsing: brackets and
    braces counted outside strings and comments."""
    depth = deepest = 0
    where = 0
    for match in _TOKENS.finditer(text):
        token = match.group()
        if token in "[{":
            depth += 1
            if depth > deepest:
                deepest, where = depth, match.start()
        elif token in "]}":
            depth = max(depth - 1, 0)
    return deepest, text.count("\n", 0, where) + 1


def nesting_problems(text: str) -> list[Problem]:
    """A problem if the TOML ``text`` nests brackets deeper than :data:`DEPTH` (found before
    parsing it)."""
    deepest, line = nesting(text)
    if deepest <= DEPTH:
        return []
    return [
        Problem(
            "",
            f"line {line} nests arrays and inline tables {deepest} levels deep, more than "
            f"the {DEPTH} a scene may nest (its deepest key, slider[0].frame[0][0], is 4 "
            "levels down; this limit is fixed)",
        )
    ]


# -- before validating ----------------------------------------------------------------------
def shape_problems(data: Mapping[str, Any], limits: Limits) -> list[Problem]:
    """The arrays and tables of a scene document (as :mod:`tomllib` reads it) with more
    entries than the limit, or nested deeper than :data:`DEPTH`; walked without recursion,
    nothing past a problem is visited."""
    problems: list[Problem] = []
    stack: list[tuple[Any, str, int]] = [(data, "", 0)]
    while stack:
        value, path, depth = stack.pop()
        if depth > DEPTH:
            problems.append(
                Problem(
                    path,
                    f"nested more than {DEPTH} levels deep, the most a scene may nest (its "
                    "deepest key, slider[0].frame[0][0], is 4 levels down; this limit is fixed)",
                )
            )
            continue
        if len(value) > limits.entries:
            problems.append(limits.problem("entries", path, f"has {len(value)} entries"))
            continue
        items = value.items() if isinstance(value, Mapping) else enumerate(value)
        children = [
            (child, _child_path(path, key), depth + 1)
            for key, child in items
            if isinstance(child, (Mapping, list, tuple))
        ]
        stack.extend(reversed(children))
    return problems


def _child_path(path: str, key: Any) -> str:
    if isinstance(key, int):
        return f"{path}[{key}]"
    return f"{path}.{key}" if path else str(key)


# -- before building ----------------------------------------------------------------------
def size_problems(scene: Scene, limits: Limits) -> list[Problem]:
    """What a valid scene asks for over the limits: the elements of its generated beams
    (each and in all), the static solves of its study, the time steps of a dynamic one, and
    the bytes of the mesh files it reads (each time it reads them)."""
    problems: list[Problem] = []
    counts = []
    for i, beam in enumerate(scene.beam):
        geometry = beam.straight or beam.arc
        if geometry is not None:
            kind = "straight" if beam.straight is not None else "arc"
            counts.append((f"beam[{i}].{kind}.elements", geometry.elements))
    problems += element_problems(counts, limits)
    problems += _study_problems(scene, limits)
    total = 0
    for i, beam in enumerate(scene.beam):
        if beam.mesh is None:
            continue
        try:
            total += Path(beam.mesh).stat().st_size
        except OSError:
            continue  # a missing or unreadable file is reported where it is read
        if total > limits.mesh_bytes:
            found = f"the scene's mesh files have {total} bytes up to this one"
            problems.append(limits.problem("mesh_bytes", f"beam[{i}].mesh", found, beam.mesh))
            break
    return problems


def element_problems(counts: Sequence[tuple[str, int]], limits: Limits) -> list[Problem]:
    """Beams with more elements than the limit, each at its path, then the total of
    ``counts`` (path, elements) if it is over the limit and no single beam is."""
    problems = [
        limits.problem("elements", path, f"{n} elements")
        for path, n in counts
        if n > limits.elements
    ]
    total = sum(n for _, n in counts)
    if not problems and total > limits.elements:
        problems.append(
            limits.problem("elements", "beam", f"the beams have {total} elements in all")
        )
    return problems


def _study_problems(scene: Scene, limits: Limits) -> list[Problem]:
    """The time steps of a dynamic study, or the static solves of a static study or sweep
    (at the larger of its two factors, the samples and the load steps)."""
    study = scene.study
    if isinstance(study, DynamicStudy):
        steps = study.t_end / study.step
        if steps <= limits.steps:
            return []
        found = f"t_end / step = {study.t_end:g} / {study.step:g} = {steps:.6g} time steps"
        return [limits.problem("steps", "study.step", found, study.step)]
    samples, path, value = 1, "study", None
    if isinstance(study, SweepStudy) and study.values is not None:
        samples, path = len(study.values), "study.values"
    elif isinstance(study, SweepStudy) and study.range is not None:
        samples, path, value = study.range.num, "study.range.num", study.range.num
    solves = samples * study.load_steps
    if solves <= limits.solves:
        return []
    if study.load_steps > samples:
        path, value = "study.load_steps", study.load_steps
    found = (
        f"{_count(samples, 'sample')} x {_count(study.load_steps, 'load step')} = "
        f"{solves} static solves"
    )
    return [limits.problem("solves", path, found, value)]


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'s' if n != 1 else ''}"
