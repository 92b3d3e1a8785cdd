"""Checkpoints of a dynamic run, and resuming from them (``fvslider run SCENE --resume DIR``).

A run of the command into ``DIR`` writes its outputs only at its end
(:func:`sliders.app.run_dynamic.write_dynamic`); meanwhile it keeps a checkpoint beside them,
in ``DIR.checkpoint`` (:func:`checkpoint_directory`), every ``study.checkpoint.steps`` steps
or ``study.checkpoint.seconds`` of wall time (default: every 500 steps or every minute,
whichever comes first), and on Ctrl-C.  It
holds what the run needs to go on as if it had never stopped:

* ``cursor_NNNNNN.npz``: the integrator's state after step ``NNNNNN``
  (:meth:`sliders.solve.integrator.State.save`: ``q``, ``v``, the scheme's ``a``, ``qdd``,
  the joints' unknowns, the last step);
* ``history.csv`` and the per-step tables ``output.csv`` asks for: the recorder's rows so far,
  as the text the outputs will hold (:meth:`sliders.app.history.Recorder.text`), appended at
  each checkpoint (never rewritten);
* ``states/NNNNNN.npz``: the states kept for the VTU series and the renders;
* ``checkpoint.npz``, the commit, written last and atomically: the scene, the cursor
  (:class:`sliders.solve.dynamics.Cursor`: which state file, the next step's size, the fixed
  steps left), the length of every table file, how many kept states, and what the
  recorder's next row builds on (:meth:`sliders.app.history.Recorder.carry`); and the
  SHA-256 of every file it keeps (each table up to its length, each state, the cursor's)
  and of every file the scene names (its mesh files, its restart state).

Whatever a kill interrupts, ``checkpoint.npz`` describes a whole checkpoint: the bytes of a
table beyond its length and the files it does not name are ignored (and cut off by the next
checkpoint).  The end of the run removes the checkpoint, after its outputs are written.

Resuming (:meth:`Checkpoints.resume`) checks that the scene is the checkpoint's (all but
``study.checkpoint``, which changes no result) and so are the files it names, byte for byte;
that every array of the commit has its shape, count and range (a time within the study, no
more steps left than its end allows), and every file kept its checksum; then it restores the
recorder and returns the cursor:
the integration then repeats the arithmetic of the uninterrupted run and writes the same
files, byte for byte.
"""

from __future__ import annotations

import csv
import hashlib
import io
import os
import shutil
import tempfile
import time
import tomllib
import warnings
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from fvbeam.io import OUTPUT_MARKER, check_replaceable, replace_directory, write_atomic
from sliders.app.history import Recorder
from sliders.app.scene import dump_scene
from sliders.app.schema import Scene
from sliders.solve.integrator import State

if TYPE_CHECKING:  # a static run clears checkpoints without the time integration
    from sliders.solve.dynamics import Cursor, Dynamics

#: The file that marks a directory as a checkpoint this program wrote.
MARKER = ".fvslider-checkpoint"
#: The commit: written last, it names a whole checkpoint.
COMMIT = "checkpoint.npz"
#: ``DIR.checkpoint`` keeps the checkpoint of a run into ``DIR``.
SUFFIX = ".checkpoint"
#: What a file that fails to read as a checkpoint's part raises.
_UNREADABLE = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, UnicodeDecodeError)


def checkpoint_directory(out: str | Path) -> Path:
    """Where a run into the output directory ``out`` keeps its checkpoint: ``OUT.checkpoint``
    beside it."""
    out = Path(out)
    out = out if out.name else out.absolute()
    return out.with_name(out.name + SUFFIX)


class Complete(Exception):
    """Nothing to resume: the output directory holds the scene's finished run."""


@dataclass(frozen=True)
class _Saved:
    """What the last checkpoint holds: per table its rows, its file's length in bytes and
    the SHA-256 of those bytes (a running hash, extended by each checkpoint's rows), the
    kept states and their files' SHA-256, the cursor's state file and its step."""

    rows: dict[str, int]
    sizes: dict[str, int]
    states: int
    cursor: str
    step: int
    tables: dict[str, Any]
    kept: tuple[str, ...]


def _sha256(path: Path) -> str:
    with open(path, "rb") as file:
        return hashlib.file_digest(file, "sha256").hexdigest()


def named_files(scene: Scene) -> list[str]:
    """The files the scene names (resolved paths): its mesh files and its restart state."""
    named = [beam.mesh for beam in scene.beam if beam.mesh is not None]
    restart = getattr(scene.study, "restart", None)
    return list(dict.fromkeys(named + ([restart] if restart is not None else [])))


class Checkpoints:
    """The checkpoints of a dynamic run into ``out``, recorded by ``recorder`` (in memory).

    Called after every step with its cursor (the ``checkpoint`` of
    :meth:`sliders.solve.dynamics.Dynamics.run`), it writes a checkpoint every ``steps``
    steps or ``seconds`` of wall time, whichever comes first (0: not by that rule);
    :meth:`save` writes one of the last step at once.  ``toml``: the scene, as every
    checkpoint keeps it.  ``ValueError`` if ``OUT.checkpoint`` exists and is not a
    checkpoint.
    """

    def __init__(
        self,
        out: str | Path,
        scene: Scene,
        recorder: Recorder,
        steps: int = 0,
        seconds: float = 60.0,
    ) -> None:
        self.out = Path(out)
        self.directory = checkpoint_directory(self.out)
        check_replaceable(self.directory, MARKER)
        self.toml, self.recorder = dump_scene(scene), recorder
        self.scene = scene
        self.steps, self.seconds = steps, seconds
        self._pending: tuple[Cursor, dict[str, int], int] | None = None
        self._saved: _Saved | None = None
        self._clock = time.monotonic()

    @property
    def enabled(self) -> bool:
        """Whether checkpoints are written at all."""
        return self.steps > 0 or self.seconds > 0

    def __call__(self, cursor: Cursor) -> None:
        """Note the step just recorded; write a checkpoint if one is due."""
        recorder = self.recorder
        counts = {name: recorder.count(name) for name in recorder.headers}
        self._pending = (cursor, counts, len(recorder.states))
        done = counts["history"] - 1 - (self._saved.step if self._saved else 0)
        if (self.steps and done >= self.steps) or (
            self.seconds and time.monotonic() - self._clock >= self.seconds
        ):
            self.save()

    def save(self) -> None:
        """Write a checkpoint of the last step noted (none before the first step).  One that
        cannot be written (a full disk, the place taken) warns (``RuntimeWarning``) and ends
        the checkpoints: the run goes on, and the last checkpoint written stays whole."""
        if self._pending is None or not self.enabled:
            return
        try:
            if self._saved is None:
                written: list[_Saved] = []
                replace_directory(
                    self.directory, lambda tmp: written.append(self._write(tmp)), MARKER
                )
                self._saved = written[0]
            else:
                self._saved = self._write(self.directory)
        except (OSError, ValueError) as exc:
            self.steps, self.seconds = 0, 0.0
            if isinstance(exc, ValueError):  # fvbeam.io's OutputError names its path
                text = str(exc)
            else:
                text = f"cannot write {self.directory}: {exc.strerror or exc}"
            warnings.warn(
                f"{text}; the run goes on without checkpoints", RuntimeWarning, stacklevel=2
            )
        self._clock = time.monotonic()

    def written(self) -> dict[str, tuple[Path, int, int]]:
        """Per table of the last checkpoint written: its file, rows and length in bytes (the
        header and those rows as :meth:`sliders.app.history.Recorder.text` gives them, which
        :meth:`~sliders.app.history.Recorder.write` copies instead of formatting them
        again); empty before the first."""
        saved = self._saved
        if saved is None:
            return {}
        return {
            name: (self.directory / f"{name}.csv", saved.rows[name], saved.sizes[name])
            for name in saved.rows
        }

    def remove(self) -> None:
        """Remove the checkpoint (the run's outputs are written): renamed aside, then
        deleted, so that it is either whole or gone.  One that cannot be removed warns
        (``RuntimeWarning``)."""
        self._saved = None
        if not (self.directory / MARKER).is_file():
            return
        try:
            aside = tempfile.mkdtemp(
                prefix=f".{self.directory.name}.old.", dir=self.directory.parent
            )
            os.replace(self.directory, aside)
            shutil.rmtree(aside)
        except OSError as exc:
            warnings.warn(
                f"{self.directory}: cannot remove the checkpoint of the finished run "
                f"({exc.strerror or exc})",
                RuntimeWarning,
                stacklevel=2,
            )

    def _write(self, directory: Path) -> _Saved:
        """Append to ``directory``'s files what the last checkpoint lacks, then commit."""
        assert self._pending is not None  # save writes only after a step was noted
        cursor, counts, kept = self._pending
        carry = self.recorder.carry(cursor.state, counts["history"])
        old = self._saved
        rows, sizes, hashes = {}, {}, {}
        for name, header in self.recorder.headers.items():
            start, size = (old.rows[name], old.sizes[name]) if old else (0, 0)
            buffer = io.StringIO(newline="")
            if old is None:
                csv.writer(buffer).writerow(header)
            buffer.write(self.recorder.text(name, start, counts[name]))
            data = buffer.getvalue().encode()
            with open(directory / f"{name}.csv", "r+b" if old else "wb") as stream:
                stream.truncate(size)  # cut off what an interrupted checkpoint appended
                stream.seek(size)
                stream.write(data)
            rows[name], sizes[name] = counts[name], size + len(data)
            hashes[name] = old.tables[name].copy() if old else hashlib.sha256()
            hashes[name].update(data)
        states = list(old.kept if old else ())
        for k in range(old.states if old else 0, kept):
            path = directory / "states" / f"{k:06d}.npz"
            self.recorder.states[k].save(path)
            states.append(_sha256(path))
        step = counts["history"] - 1
        name = f"cursor_{step:06d}.npz"
        cursor.state.save(directory / name)
        named = named_files(self.scene)

        arrays: dict[str, Any] = {
            "scene": np.array(self.toml),
            "cursor": np.array(name),
            "h": np.array(cursor.h),
            "steps": np.array(-1 if cursor.steps is None else cursor.steps),
            "tables": np.array(list(rows)),
            "rows": np.array(list(rows.values())),
            "sizes": np.array(list(sizes.values())),
            "states": np.array(kept),
            "tables_sha256": np.array([hashes[t].hexdigest() for t in rows], dtype=str),
            "states_sha256": np.array(states, dtype=str),
            "cursor_sha256": np.array(_sha256(directory / name)),
            "named": np.array(named, dtype=str),
            "named_sha256": np.array([_sha256(Path(f)) for f in named], dtype=str),
        } | {f"carry_{key}": value for key, value in carry.items()}

        def commit(tmp: Path) -> None:
            np.savez(tmp, **arrays)

        write_atomic(directory / COMMIT, commit)
        if old is not None and old.cursor != name:
            (directory / old.cursor).unlink(missing_ok=True)
        return _Saved(rows, sizes, kept, name, step, hashes, tuple(states))

    @classmethod
    def resume(
        cls,
        out: str | Path,
        scene: Scene,
        dynamics: Dynamics,
        recorder: Recorder,
        steps: int = 0,
        seconds: float = 60.0,
    ) -> tuple[Checkpoints, Cursor]:
        """The checkpoints of the run into ``out`` of ``scene``, and the cursor to go on from,
        ``recorder`` restored to it; later checkpoints go on from it.

        Raises :class:`Complete` when there is no checkpoint and ``out`` holds the scene's
        finished run, and ``ValueError`` (one message naming the file or the first
        difference) when there is no checkpoint, when it is another scene's, or when it
        does not read.
        """
        self = cls(out, scene, recorder, steps, seconds)
        commit = self.directory / COMMIT
        if not commit.is_file():
            finished = self._finished()
            if finished is not None:
                raise Complete(finished)
            raise ValueError(
                f"{self.out}: no checkpoint to resume from ({commit} does not exist); a run "
                "writes one every study.checkpoint.seconds of wall time (default 60 s)"
            )
        try:
            with np.load(commit) as data:
                fields = {key: data[key] for key in data.files}
            text = str(fields["scene"])
        except _UNREADABLE as exc:
            raise ValueError(f"{commit}: not a checkpoint ({exc})") from exc
        difference = _difference(_results_of(text), _results_of(self.toml))
        if difference is not None:
            raise ValueError(
                f"{self.directory}: the checkpoint of another scene ({difference}); run "
                "without --resume to start over"
            )
        self._check_named(fields)
        try:
            cursor, saved = self._restore(fields, dynamics)
        except _UNREADABLE as exc:
            raise ValueError(f"{self.directory}: a damaged checkpoint ({exc})") from exc
        self._saved = saved
        return self, cursor

    def _check_named(self, fields: dict[str, np.ndarray]) -> None:
        """The files the scene names are those the checkpoint was computed from, byte for
        byte (``ValueError`` naming the first that differs)."""
        try:
            recorded = dict(
                zip(_texts(fields, "named"), _texts(fields, "named_sha256"), strict=True)
            )
        except (KeyError, ValueError) as exc:
            raise ValueError(f"{self.directory}: a damaged checkpoint ({exc})") from exc
        for path in named_files(self.scene):
            try:
                current = _sha256(Path(path))
            except OSError as exc:
                raise ValueError(f"{path}: cannot read it ({exc.strerror or exc})") from exc
            if recorded.get(path) != current:
                raise ValueError(
                    f"{path}: changed since the checkpoint in {self.directory} was written "
                    "(its SHA-256 differs), so the run cannot go on from it; run without "
                    "--resume to start over"
                )

    def _restore(self, fields: dict[str, np.ndarray], dynamics: Dynamics) -> tuple[Cursor, _Saved]:
        """The cursor and the recorder of the checkpoint whose commit holds ``fields``, after
        checking every array's shape, count and range and every file's checksum."""
        from sliders.solve.dynamics import Cursor  # imported by then: dynamics is given

        tables = _texts(fields, "tables")
        count = len(tables)
        rows = dict(zip(tables, _counts(fields, "rows", count), strict=True))
        sizes = dict(zip(tables, _counts(fields, "sizes", count), strict=True))
        sums = dict(zip(tables, _texts(fields, "tables_sha256", count), strict=True))
        if "history" not in tables:
            raise ValueError(f"{COMMIT} names no history table")
        cells, headers, hashes = {}, {}, {}
        for name in tables:
            data = (self.directory / f"{name}.csv").read_bytes()
            if len(data) < sizes[name]:
                raise ValueError(f"{name}.csv is shorter than its checkpoint")
            hashes[name] = hashlib.sha256(data[: sizes[name]])
            if hashes[name].hexdigest() != sums[name]:
                raise ValueError(f"{name}.csv differs from its checkpoint (its SHA-256)")
            table = list(csv.reader(io.StringIO(data[: sizes[name]].decode(), newline="")))
            if len(table) != rows[name] + 1:
                raise ValueError(f"{name}.csv holds {len(table) - 1} rows, not {rows[name]}")
            headers[name], cells[name] = table[0], table[1:]
        (kept,) = _counts(fields, "states", None)
        kept_sha = _texts(fields, "states_sha256", kept)
        states = []
        for k in range(kept):
            path = self.directory / "states" / f"{k:06d}.npz"
            if _sha256(path) != kept_sha[k]:
                raise ValueError(f"states/{path.name} differs from its checkpoint (its SHA-256)")
            states.append(State.load(path))
        name = str(fields["cursor"])
        if Path(name).name != name or not name.startswith("cursor_"):
            raise ValueError(f"{COMMIT} names the cursor {name!r}, not a file of the checkpoint")
        if _sha256(self.directory / name) != str(fields["cursor_sha256"]):
            raise ValueError(f"{name} differs from its checkpoint (its SHA-256)")
        state = State.load(self.directory / name)
        _check_cursor(fields, state, self.scene)
        n = dynamics.structure.n_dofs
        if any(x.shape != (n,) for x in (state.q, state.v, state.a, state.qdd)) or len(
            state.unknowns
        ) != len(dynamics.sliders):
            raise ValueError(f"{name} is not a state of this model")
        carry = {key[6:]: value for key, value in fields.items() if key.startswith("carry_")}
        self.recorder.resume(dynamics, cells, carry, states, state)
        for file, header in headers.items():
            if header != list(self.recorder.headers[file]):
                raise ValueError(f"{file}.csv has the columns of another recording")
        steps = int(fields["steps"])
        cursor = Cursor(state, float(fields["h"]), None if steps < 0 else steps)
        step = rows["history"] - 1
        return cursor, _Saved(rows, sizes, kept, name, step, hashes, tuple(kept_sha))

    def _finished(self) -> str | None:
        """A message if ``out`` holds this scene's finished run, else None."""
        try:
            if not (self.out / OUTPUT_MARKER).is_file():
                return None
            written = _results_of((self.out / "scene.toml").read_text())
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
            return None
        if _difference(written, _results_of(self.toml)) is not None:
            return None
        try:
            reached = f" to t = {State.load(self.out / 'state.npz').t:.6g} s"
        except _UNREADABLE:
            reached = ""
        return f"{self.out}: nothing to resume, it holds the finished run of this scene{reached}"


def _texts(fields: dict[str, np.ndarray], key: str, count: int | None = None) -> list[str]:
    """The commit's array ``key`` as strings: one dimension of ``count`` entries (any when
    None), else ``ValueError`` naming it."""
    array = fields[key]
    if array.ndim != 1 or array.dtype.kind != "U" or (count is not None and len(array) != count):
        raise ValueError(f"{COMMIT}: {key} is not a list of {count or 'some'} names")
    return [str(x) for x in array]


def _counts(fields: dict[str, np.ndarray], key: str, count: int | None) -> list[int]:
    """The commit's array ``key`` as integers >= 0: ``count`` of them in one dimension, or
    one scalar when ``count`` is None; else ``ValueError`` naming it."""
    array = fields[key]
    shape = () if count is None else (count,)
    if array.shape != shape or array.dtype.kind not in "iu" or np.any(array < 0):
        what = "an integer" if count is None else f"{count} integers"
        raise ValueError(f"{COMMIT}: {key} is not {what} >= 0 (shape {array.shape})")
    return [int(x) for x in np.atleast_1d(array)]


def _check_cursor(fields: dict[str, np.ndarray], state: State, scene: Scene) -> None:
    """The cursor's time within the study, its next step a finite positive size no longer
    than the study asks (or within its adaptive bounds), and with fixed steps no more steps
    left than reach ``t_end`` from its time; else ``ValueError`` naming what is wrong."""
    study = scene.study
    h, steps = fields["h"], fields["steps"]
    if h.shape != () or h.dtype.kind != "f" or steps.shape != () or steps.dtype.kind not in "iu":
        raise ValueError(f"{COMMIT}: h and steps must be one number each")
    t_end = float(getattr(study, "t_end", np.inf))
    # the time is a sum of steps: t_end to the rounding of a few thousand of them
    if not (np.isfinite(state.t) and 0 <= state.t <= t_end * (1 + 1e-9)):
        raise ValueError(f"the cursor's time t = {state.t} lies outside the study [0, {t_end}]")
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"{COMMIT}: the next step h = {h} must be finite and > 0")
    if steps >= 0:
        reach = int(np.ceil((t_end - state.t) / float(h) * (1 + 1e-9))) + 1
        if steps > reach:
            raise ValueError(
                f"{COMMIT}: {int(steps)} steps left from t = {state.t:.6g} s, more than the "
                f"{reach} of h = {float(h):.6g} s that reach t_end = {t_end:g} s"
            )


def _results_of(text: str) -> dict[str, Any]:
    """A scene's TOML as a dict, without what changes no result (``study.checkpoint``)."""
    data = tomllib.loads(text)
    study = data.get("study")
    if isinstance(study, dict):
        study.pop("checkpoint", None)
    return data


def _difference(there: Any, here: Any, path: str = "") -> str | None:
    """The first key path at which the checkpoint's scene (``there``) and this one differ,
    with both values; None if they are equal."""
    if isinstance(there, dict) and isinstance(here, dict):
        for key in [*there, *(k for k in here if k not in there)]:
            where = f"{path}.{key}" if path else key
            if key not in here or key not in there:
                side = "the checkpoint's" if key in there else "this"
                return f"{where} is set only in {side} scene"
            found = _difference(there[key], here[key], where)
            if found is not None:
                return found
        return None
    if isinstance(there, list) and isinstance(here, list):
        if len(there) != len(here):
            return f"{path} has {len(there)} entries there, {len(here)} here"
        for i, (a, b) in enumerate(zip(there, here, strict=True)):
            found = _difference(a, b, f"{path}[{i}]")
            if found is not None:
                return found
        return None
    if there == here:
        return None
    return f"{path} = {there!r} there, {here!r} here"
