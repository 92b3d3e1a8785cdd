"""Per-step outputs of a time integration, kept in memory and streamed to CSV.

``history.csv`` has one row per accepted step (row 0: the start):

* ``step, t, h, iterations``;
* energies: ``kinetic = v.M v / 2``, ``strain = q.K q / 2`` (the fv stiffness is not
  symmetric, so for fv beams this is the energy of its symmetric part, an approximation of
  the same order as the discretisation), and, accumulated by the trapezoidal rule over each
  step, ``external_work`` (of the loads), ``constraint_work`` (of the supports, drives and
  joints: ``M qdd + C v + K q - f``), ``dissipated`` (``v.C v`` over time);
  ``energy_error`` is the drift of ``kinetic + strain + dissipated - external_work -
  constraint_work`` from its start value, zero for an exact solution;
* per slider ``NAME.xi``, its multipliers (``NAME.lambda_x`` ...), and ``NAME.residual``,
  the largest violation of its position and orientation constraints;
* the ``probes`` asked for (:mod:`sliders.app.probes`: a name and a function of the state
  and the dynamics, or a value linear in ``q``).

``history`` may name the columns to keep after ``step, t`` (the probes are always kept);
what no kept column needs is not computed: the energies (four sparse products, as one
product with the block diagonal of ``M, C, K, M``), the joints' residuals.

On request, the per-step tables of :mod:`sliders.app.state_tables` (``nodes``, ``sliders``,
``internal_forces``, ``reactions``, each with a :class:`~sliders.app.state_tables.Selection`
of its rows and columns): the same columns as a static study's, with ``step, t`` in place of
``sample, value`` (:data:`sliders.app.state_tables.STEP_COLUMNS`), one row per step and
node, slider, recovery point or held node.  The reactions are what the supports and dof
drives exert (:attr:`sliders.solve.dynamics.Dynamics.supports`): ``M qdd + C v + K q - f``
on the dofs they hold, less the forces the joints exert there, as in statics.

Every record is kept as numbers (a step's history row, each table's block of rows) and
turned into CSV cells only when written, a block of steps at a time
(:func:`sliders.app.state_tables.cells`).  With a directory, the rows are appended to
``NAME.csv.part`` files in blocks, every ``flush_rows`` steps or ``flush_seconds`` of wall
time, and the per-step tables' rows are then forgotten (``history`` stays in memory, for
:meth:`Recorder.table`); :meth:`Recorder.close` writes the rest and renames the files to
``NAME.csv``.  :meth:`sliders.solve.dynamics.Dynamics.run` closes the recorder on every exit,
so an interrupted or failed integration leaves whole rows of what it computed.

A recorder in memory can be checkpointed (:mod:`sliders.app.checkpoint`): its rows as CSV
cells (:meth:`Recorder.cells`), what its next record builds on (:meth:`Recorder.carry`: the
work integrals) and its kept states; :meth:`Recorder.resume` takes them back, and the records
that follow are those of the uninterrupted run.
"""

from __future__ import annotations

import csv
import os
import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

import numpy as np
import scipy.sparse as sp

from fvbeam.names import suggest
from sliders.app.probes import LinearProbe, Probe
from sliders.app.state_tables import (
    STEP_COLUMNS,
    Selection,
    Snapshot,
    StateTable,
    cells,
    state_table,
)
from sliders.joints.slider import Slider
from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State

if TYPE_CHECKING:
    import _csv

ENERGIES = ("kinetic", "strain", "external_work", "constraint_work", "dissipated", "energy_error")
#: The columns of ``history.csv`` before the energies; ``step, t`` are always kept.
STEP = ("step", "t", "h", "iterations")
#: Steps and seconds between the blocks a streaming recorder writes.
FLUSH_ROWS, FLUSH_SECONDS = 1000, 5.0


def history_columns(sliders: Sequence[Slider]) -> list[str]:
    """Every column ``history.csv`` can hold for a dynamics of ``sliders``, before its
    probes."""
    columns = [*STEP, *ENERGIES]
    for s in sliders:
        columns += [f"{s.name}.{u}" for u in s.unknown_names] + [f"{s.name}.residual"]
    return columns


class _Records:
    """Records of equal shape appended one per step (a row as a list, or a block of rows as
    an array), kept as arrays of ``BLOCK`` records (the newest in a list until there are
    ``BLOCK``).  The records before :attr:`offset` are forgotten (:meth:`forget`)."""

    BLOCK = 512

    def __init__(self) -> None:
        self.blocks: list[np.ndarray] = []
        self.pending: list = []
        self.offset = 0
        self.count = 0

    def append(self, record) -> None:
        self.pending.append(record)
        self.count += 1
        if len(self.pending) == self.BLOCK:
            self.blocks.append(np.array(self.pending, dtype=float))
            self.pending = []

    def array(self, start: int = 0, stop: int | None = None) -> np.ndarray:
        """Records ``start:stop`` (not forgotten) as one array, records along axis 0."""
        stop = self.count if stop is None else stop
        first = (start - self.offset) // self.BLOCK
        parts = self.blocks[first : -(-(stop - self.offset) // self.BLOCK)]
        if self.pending and stop > self.count - len(self.pending):
            parts = [*parts, np.array(self.pending, dtype=float)]
        if not parts:
            return np.zeros((0,))
        base = self.offset + first * self.BLOCK
        return np.concatenate(parts)[start - base : stop - base]

    def forget(self, upto: int) -> None:
        """Forget the whole blocks of records before ``upto`` (they are written)."""
        drop = min((upto - self.offset) // self.BLOCK, len(self.blocks))
        self.blocks = self.blocks[drop:]
        self.offset += drop * self.BLOCK


class Recorder:
    """Collects the per-step outputs of :meth:`sliders.solve.dynamics.Dynamics.run`.

    Parameters
    ----------
    directory
        Where the CSV files go (created if missing); None keeps every table in memory, for
        :meth:`write` once the run is over.
    tables
        Per-step tables to keep, from ``nodes``, ``sliders``, ``internal_forces`` and
        ``reactions`` (module docstring): names (every row and column), or names to their
        :class:`~sliders.app.state_tables.Selection`.
    probes
        Extra columns: name to probe (:mod:`sliders.app.probes`).
    every
        Also keep every ``every``-th state (and the start) in :attr:`states` (0: none); the
        last recorded state is always :attr:`last`.
    history
        The columns of ``history.csv`` to keep after ``step, t`` (:func:`history_columns`,
        checked at :meth:`start`); None: all.
    flush_rows, flush_seconds
        With a directory, write a block of rows every so many steps or seconds.
    """

    def __init__(
        self,
        directory: str | Path | None = None,
        tables: Sequence[str] | Mapping[str, Selection] = (),
        probes: Mapping[str, Probe] | None = None,
        every: int = 0,
        history: Sequence[str] | None = None,
        flush_rows: int = FLUSH_ROWS,
        flush_seconds: float = FLUSH_SECONDS,
    ) -> None:
        self.directory = None if directory is None else Path(directory)
        selections = dict(tables) if isinstance(tables, Mapping) else dict.fromkeys(tables)
        for i, name in enumerate(selections):
            if name not in STEP_COLUMNS:
                raise ValueError(
                    f"tables[{i}] must be one of {', '.join(STEP_COLUMNS)}, got {name!r}"
                    f"{suggest(name, STEP_COLUMNS)}"
                )
        self.selections: dict[str, Selection | None] = selections
        self.tables = list(selections)
        self.probes = dict(probes or {})
        self.every = every
        self.history = None if history is None else tuple(history)
        self.flush_rows, self.flush_seconds = flush_rows, flush_seconds
        self.states: list[State] = []
        self.last: State | None = None
        #: The columns of ``history.csv``.
        self.columns: list[str] = []
        #: Each table's header, ``history`` first.
        self.headers: dict[str, Sequence[str]] = {}
        self._layouts: dict[str, StateTable] = {}
        self._records: dict[str, _Records] = {}
        self._files: dict[str, tuple[TextIO, _csv.Writer, int]] = {}
        self._clock = time.monotonic()
        self._work = np.zeros(3)
        self._reference: float | None = None
        # the load, constraint forces and damping power of the last state (_append)
        self._f: np.ndarray
        self._reaction: np.ndarray
        self._power: float

    # -- reading what was recorded ---------------------------------------------------------
    def table(self) -> dict[str, np.ndarray]:
        """``history.csv`` as arrays, one per column."""
        data = self._records["history"].array().reshape(-1, len(self.columns))
        return {name: data[:, i] for i, name in enumerate(self.columns)}

    @property
    def rows(self) -> list[list[float]]:
        """``history.csv``'s rows as numbers (a copy)."""
        if "history" not in self._records:
            return []
        return self._records["history"].array().reshape(-1, len(self.columns)).tolist()

    def count(self, name: str) -> int:
        """How many rows table ``name`` holds (recorded so far)."""
        if name == "history":
            return self._records["history"].count
        return self._records[name].count * self._layouts[name].n_rows

    def cells(self, name: str, start: int = 0, stop: int | None = None) -> Iterator[list[str]]:
        """Rows ``start:stop`` of table ``name`` (``history`` or a per-step table) kept in
        memory, as the CSV cells :meth:`write` writes."""
        stop = self.count(name) if stop is None else stop
        return iter(self._cells(name, start, stop))

    def _cells(self, name: str, start: int, stop: int) -> list[list[str]]:
        if stop <= start:
            return []
        if name == "history":
            rows = self._records["history"].array(start, stop).reshape(stop - start, -1)
            return cells(rows, integers=self._integers)
        layout = self._layouts[name]
        n = layout.n_rows
        first, last = start // n, -(-stop // n)
        values = self._records[name].array(first, last)
        steps = len(values)
        history = self._records["history"].array(first, last).reshape(steps, -1)
        body = cells(values.reshape(steps * n, -1), np.tile(layout.blank, (steps, 1)))
        heads = cells(history[:, :2], integers=(0,))
        out = [[*heads[k // n], layout.labels[k % n], *row] for k, row in enumerate(body)]
        return out[start - first * n : stop - first * n]

    def carry(self) -> dict[str, np.ndarray]:
        """What the next record builds on, as arrays (a checkpoint saves them; :meth:`resume`
        takes them back): the work integrals so far, the energy balance at the start, and
        the last state's load, constraint forces and damping power."""
        if self._reference is None:
            raise ValueError("the recorder has not started: nothing to carry")
        return {
            "work": self._work.copy(),
            "reference": np.array(self._reference),
            "f": self._f,
            "reaction": self._reaction,
            "power": np.array(self._power),
        }

    # -- recording -------------------------------------------------------------------------
    def start(self, dynamics: Dynamics, state: State) -> None:
        """Name the columns, open the files and record the start."""
        self._prepare(dynamics)
        self.states = []
        self._work = np.zeros(3)
        self._reference = None
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            for name, header in self.headers.items():
                self._open(name, header)
        self._append(dynamics, state, None)

    def record(self, dynamics: Dynamics, new: State, old: State) -> None:
        """Record the accepted step from ``old`` to ``new``."""
        self._append(dynamics, new, old)
        if self._files and (
            self._records["history"].count - self._files["history"][2] >= self.flush_rows
            or time.monotonic() - self._clock >= self.flush_seconds
        ):
            self._flush()

    def write(self, directory: str | Path) -> None:
        """Write the tables recorded in memory (``directory=None``) into ``directory`` (which
        must exist): the same files a recorder streaming there would have left."""
        for name, header in self.headers.items():
            with open(Path(directory) / f"{name}.csv", "w", newline="") as stream:
                writer = csv.writer(stream)
                writer.writerow(header)
                writer.writerows(self._cells(name, 0, self.count(name)))

    def resume(
        self,
        dynamics: Dynamics,
        cells: dict[str, list[list[str]]],
        carry: dict[str, np.ndarray],
        states: Sequence[State],
        last: State,
    ) -> None:
        """Take back a recording that stopped at the state ``last``, in memory
        (``directory=None``): ``cells``, every table's rows (``history`` and the per-step
        tables, without headers) as :meth:`cells` gave them, ``carry`` as :meth:`carry` gave
        it after the last of them, and the kept ``states``.  The records that follow are
        those of the uninterrupted recording (:meth:`sliders.solve.dynamics.Dynamics.resume`);
        ``ValueError`` if the pieces do not fit this recorder."""
        if self.directory is not None:
            raise ValueError("a recorder resumes in memory only (directory=None)")
        self._prepare(dynamics)
        if set(cells) != set(self.headers):
            raise ValueError(
                f"tables {', '.join(sorted(cells))} given, {', '.join(self.headers)} recorded"
            )
        history = cells["history"]
        widths = {len(row) for row in history}
        if not history or widths != {len(self.columns)}:
            raise ValueError(
                f"history rows of {len(self.columns)} cells needed, got {len(history)} rows "
                f"of {sorted(widths)}"
            )
        kept = (len(history) - 1) // self.every + 1 if self.every else 0
        if len(states) != kept:
            raise ValueError(
                f"{kept} kept states needed for {len(history)} rows, got {len(states)}"
            )
        for row in history:
            self._records["history"].append([float(x) for x in row])
        for name in self.tables:
            self._take_back(name, cells[name], len(history))
        self._work = np.array(carry["work"], dtype=float)
        self._reference = float(carry["reference"])
        self._f, self._reaction = carry["f"], carry["reaction"]
        self._power = float(carry["power"])
        self.states = list(states)
        if kept and (len(history) - 1) % self.every == 0:
            self.states[-1] = last  # the last row's state is kept: the same object, as recorded
        self.last = last

    def _take_back(self, name: str, rows: list[list[str]], steps: int) -> None:
        """A per-step table's rows, as cells, back into records of ``steps`` steps."""
        layout = self._layouts[name]
        n, width = layout.n_rows, len(layout.columns) + 2
        if len(rows) != steps * n or any(len(row) != width for row in rows):
            raise ValueError(f"{name}: {steps * n} rows of {width} cells needed")
        numbers = [[float(x) if x else np.nan for x in row[3:]] for row in rows]
        values = np.array(numbers, dtype=float).reshape(steps, n, width - 3)
        for block in values:
            self._records[name].append(block)

    def close(self) -> None:
        """Write the rows not yet written and give the files their final names."""
        if self._files:
            self._flush()
        for name, (stream, _, _) in self._files.items():
            stream.close()
            assert self.directory is not None  # files are opened only with a directory
            part = self.directory / f"{name}.csv.part"
            os.replace(part, self.directory / f"{name}.csv")
        self._files = {}

    def _prepare(self, dynamics: Dynamics) -> None:
        """The columns of ``history``, the layout of every table and empty records."""
        every = history_columns(dynamics.sliders)
        keep = set(STEP[:2]) | set(every if self.history is None else self.history)
        for i, column in enumerate(self.history or ()):
            if column not in every:
                raise ValueError(
                    f"history[{i}] = {column!r}: no such column{suggest(column, every)}"
                )
        self._pick = [every.index(c) for c in every if c in keep]
        self.columns = [every[i] for i in self._pick] + list(self.probes)
        self._integers = [i for i, c in enumerate(self.columns) if c in ("step", "iterations")]
        kept = set(self.columns)
        self._energies = bool(kept & set(ENERGIES))
        self._residuals = any(c.endswith(".residual") for c in kept)
        self._layouts = {
            name: state_table(
                name, dynamics.structure, dynamics.sliders, dynamics.supports, selection
            )
            for name, selection in self.selections.items()
        }
        self.headers = {"history": self.columns} | {
            name: ("step", "t", *layout.columns) for name, layout in self._layouts.items()
        }
        self._records = {name: _Records() for name in self.headers}
        M, C, K = dynamics.M, dynamics.C, dynamics.K
        #: M qdd, C v, K q, M v in one product (the energies and the constraint forces)
        self._products = sp.block_diag([M, C, K, M], format="csr")
        linear = [
            (k, p.weights) for k, p in enumerate(self.probes.values()) if isinstance(p, LinearProbe)
        ]
        self._linear = [k for k, _ in linear]
        self._weights = sp.vstack([w for _, w in linear], format="csr") if linear else None
        self._calls = [
            (k, p) for k, p in enumerate(self.probes.values()) if not isinstance(p, LinearProbe)
        ]

    def _open(self, name: str, header: Sequence[str]) -> None:
        assert self.directory is not None  # start opens files only with a directory
        stream = open(self.directory / f"{name}.csv.part", "w", newline="")
        writer = csv.writer(stream)
        writer.writerow(header)
        self._files[name] = (stream, writer, 0)

    def _flush(self) -> None:
        """Append the rows recorded since the last block to the files."""
        for name, (stream, writer, written) in self._files.items():
            count = self.count(name)
            writer.writerows(self._cells(name, written, count))
            stream.flush()
            self._files[name] = (stream, writer, count)
            if name != "history":
                self._records[name].forget(self._records[name].count)
        self._clock = time.monotonic()

    def _append(self, dynamics: Dynamics, state: State, old: State | None) -> None:
        history = self._records["history"]
        q, v = state.q, state.v
        row = [history.count, state.t, state.h, state.iterations]
        reaction = None
        if self._energies:
            f = dynamics.load(state.t)
            x = np.concatenate((state.qdd, v, q, v))
            y = (self._products @ x).reshape(4, -1)
            reaction = y[0] + y[1] + y[2] - f
            # qdd.M qdd (unused), v.C v, q.K q, v.M v
            _, power, qKq, vMv = np.einsum("ij,ij->i", x.reshape(4, -1), y).tolist()
            if old is not None:
                dq = q - old.q
                self._work += (
                    (self._f + f) @ dq / 2,
                    (self._reaction + reaction) @ dq / 2,
                    state.h * (self._power + power) / 2,
                )
            self._f, self._reaction, self._power = f, reaction, power
            external, constraint, dissipated = self._work.tolist()
            kinetic, strain = vMv / 2, qKq / 2
            balance = kinetic + strain + dissipated - external - constraint
            if self._reference is None:
                self._reference = balance
            row += [
                kinetic,
                strain,
                external,
                constraint,
                dissipated,
                balance - self._reference,
            ]
        else:
            if self._reference is None:
                self._reference = 0.0
                self._f = self._reaction = np.zeros(0)
                self._power = 0.0
            row += [np.nan] * len(ENERGIES)
        residuals = (
            dynamics.joint_residuals(state).tolist()
            if self._residuals
            else [np.nan] * len(state.unknowns)
        )
        for y_j, residual in zip(state.unknowns, residuals, strict=True):
            row += y_j.tolist()
            row.append(residual)
        row = [row[i] for i in self._pick]
        if self.probes:
            values = [0.0] * len(self.probes)
            if self._weights is not None:
                for k, value in zip(self._linear, (self._weights @ q).tolist(), strict=True):
                    values[k] = value
            for k, probe in self._calls:
                values[k] = probe(state, dynamics)
            row += values
        if self.every and history.count % self.every == 0:
            self.states.append(state)
        self.last = state
        history.append(row)
        if self._layouts:
            if reaction is None and "reactions" in self._layouts:
                reaction = dynamics.constraint_forces(state)
            snapshot = Snapshot(
                dynamics.structure, q, dynamics.sliders, state.unknowns, dynamics.supports, reaction
            )
            for name, layout in self._layouts.items():
                self._records[name].append(layout.values(snapshot))
