"""Scenes: one TOML file describes one model and one study (``docs/scenes.md``).

A scene is read with :mod:`tomllib` and validated into frozen pydantic models before anything
is built or solved, in three phases, each reporting all its problems at once in one
:class:`~sliders.app.errors.SceneError`, after the sizes of the file and of its arrays and
tables are checked (:mod:`sliders.app.limits`):

1. the schema (:mod:`sliders.app.schema`): keys, types, finite numbers, positive
   stiffnesses and masses, allowed kinds, with a did-you-mean for unknown keys and kinds;
2. references and consistency (:mod:`sliders.app.checks`): every name refers to something
   that exists, chains are tied end to start, the study's parameter makes sense; and the
   sizes asked for within their limits (elements, solves, time steps, mesh bytes);
3. geometry (:class:`sliders.app.model.Model`): mesh files, the library's own checks, every
   slider's body on its line (also at every value of a sweep that moves it).

Everything is referred to by name; units are SI (m, N, N m, kg, rad).  Arrays of tables carry
singular names (``[[beam]]``, ``[[slider]]``), so an error at ``slider[1].smearing`` is in the
second ``[[slider]]`` table.
"""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path

from pydantic import ValidationError

from sliders.app.checks import reference_problems
from sliders.app.errors import Problem, SceneError, schema_problems
from sliders.app.limits import (
    Limits,
    nesting_problems,
    read_at_most,
    shape_problems,
    size_problems,
)
from sliders.app.schema import Scene


def parse_scene(
    data: dict,
    base: str | Path | None = None,
    source: str = "scene",
    limits: Limits | None = None,
) -> Scene:
    """Validate a scene given as the dict ``tomllib`` reads (phases 1 and 2).

    Parameters
    ----------
    data
        The TOML document as a dict.
    base
        Folder that relative mesh paths start from (the scene file's).
    source
        Name of the scene in error messages.
    limits
        The sizes the scene may ask for (:mod:`sliders.app.limits`); default
        :meth:`Limits.from_environment`.

    Raises
    ------
    SceneError
        Listing every problem of the first phase that finds any: the size of the document's
        arrays and tables, the schema, then the references and the sizes asked for.
    """
    limits = Limits.from_environment() if limits is None else limits
    if not isinstance(data, dict):
        raise SceneError(source, [Problem("", "a scene is a TOML document (a table)")])
    problems = shape_problems(data, limits)
    if problems:
        raise SceneError(source, problems)
    try:
        scene = Scene.model_validate(data, context={"base": base})
    except ValidationError as exc:
        raise SceneError(source, schema_problems(exc, Scene)) from None
    problems = size_problems(scene, limits) + reference_problems(scene)
    if problems:
        raise SceneError(source, problems)
    return scene


def load_scene(
    path: str | Path | dict,
    limits: Limits | None = None,
    base: str | Path | None = None,
    source: str = "scene",
) -> Scene:
    """Read and validate a scene file (phases 1 and 2; :class:`sliders.app.model.Model` does the
    geometry).  Raises :class:`SceneError` for an unreadable, oversized, too deeply nested or
    invalid file; at most ``limits.scene_bytes + 1`` bytes are read (``limits``: see
    :func:`parse_scene`).

    ``path`` may also be a scene in memory, the dict ``tomllib`` reads: it is validated as
    :func:`parse_scene` does, relative mesh paths starting from ``base`` and messages naming
    it ``source`` (``base`` and ``source`` are for this form only; a file is its own)."""
    limits = Limits.from_environment() if limits is None else limits
    if isinstance(path, dict):
        return parse_scene(path, base, source, limits)
    path = Path(path)
    try:
        with path.open("rb") as file:
            raw = read_at_most(file, limits.scene_bytes)
            status = os.fstat(file.fileno())
    except OSError as exc:
        raise SceneError(
            str(path), [Problem("", f"cannot read the file: {exc.strerror}")]
        ) from None
    if len(raw) > limits.scene_bytes:
        size = status.st_size if stat.S_ISREG(status.st_mode) else f"more than {len(raw) - 1}"
        found = f"the file has {size} bytes"
        raise SceneError(str(path), [limits.problem("scene_bytes", "", found)])
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(str(path), [Problem("", f"not valid TOML (UTF-8): {exc}")]) from None
    problems = nesting_problems(text)
    if problems:
        raise SceneError(str(path), problems)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(str(path), [Problem("", f"not valid TOML: {exc}")]) from None
    return parse_scene(data, path.parent, str(path), limits)


def dump_scene(scene: Scene) -> str:
    """The scene as TOML text; :func:`parse_scene` of it gives an equal scene (mesh paths are
    written absolute)."""
    import tomli_w

    return tomli_w.dumps(scene.model_dump(mode="python", exclude_none=True))
