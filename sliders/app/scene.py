"""Scenes: one TOML file describes one model and one study (``docs/scenes.md``).

A scene is read with :mod:`tomllib` and validated into frozen pydantic models before anything
is built or solved, in three phases, each reporting all its problems at once in one
:class:`~sliders.app.errors.SceneError`:

1. the schema (:mod:`sliders.app.schema`): keys, types, finite numbers, positive
   stiffnesses and masses, allowed kinds, with a did-you-mean for unknown keys and kinds;
2. references and consistency (:mod:`sliders.app.checks`): every name refers to something
   that exists, chains are tied end to start, the study's parameter makes sense;
3. geometry (:class:`sliders.app.model.Model`): mesh files, the library's own checks, every
   slider's body on its line (also at every value of a sweep that moves it).

Everything is referred to by name; units are SI (m, N, N m, kg, rad).  Arrays of tables carry
singular names (``[[beam]]``, ``[[slider]]``), so an error at ``slider[1].smearing`` is in the
second ``[[slider]]`` table.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from pydantic import ValidationError

from sliders.app.checks import reference_problems
from sliders.app.errors import Problem, SceneError, schema_problems
from sliders.app.schema import Scene


def parse_scene(data: dict, base: str | Path | None = None, source: str = "scene") -> Scene:
    """Validate a scene given as the dict ``tomllib`` reads (phases 1 and 2).

    Parameters
    ----------
    data
        The TOML document as a dict.
    base
        Folder that relative mesh paths start from (the scene file's).
    source
        Name of the scene in error messages.

    Raises
    ------
    SceneError
        Listing every problem of the first phase that finds any.
    """
    if not isinstance(data, dict):
        raise SceneError(source, [Problem("", "a scene is a TOML document (a table)")])
    try:
        scene = Scene.model_validate(data, context={"base": base})
    except ValidationError as exc:
        raise SceneError(source, schema_problems(exc, Scene)) from None
    problems = reference_problems(scene)
    if problems:
        raise SceneError(source, problems)
    return scene


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file (phases 1 and 2; :class:`sliders.app.model.Model` does the
    geometry).  Raises :class:`SceneError` for an unreadable or invalid file."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as exc:
        raise SceneError(
            str(path), [Problem("", f"cannot read the file: {exc.strerror}")]
        ) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SceneError(str(path), [Problem("", f"not valid TOML: {exc}")]) from None
    return parse_scene(data, path.parent, str(path))


def dump_scene(scene: Scene) -> str:
    """The scene as TOML text; :func:`parse_scene` of it gives an equal scene (mesh paths are
    written absolute)."""
    import tomli_w

    return tomli_w.dumps(scene.model_dump(mode="python", exclude_none=True))
