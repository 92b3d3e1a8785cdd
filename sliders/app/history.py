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
* the ``probes`` asked for (a name and a function of the state and the dynamics).

On request, the per-step tables of :mod:`sliders.app.tables` (``nodes``, ``sliders``,
``internal_forces``, ``reactions``): the same columns as a static study's, with ``step, t``
in place of ``sample, value`` (:data:`sliders.app.tables.STEP_COLUMNS`), one row per step
and node, slider, recovery point or held node.  The reactions are what the supports and dof
drives exert (:attr:`sliders.solve.dynamics.Dynamics.supports`): ``M qdd + C v + K q - f``
on the dofs they hold, less the forces the joints exert there, as in statics.

Rows are written as they come into ``NAME.csv.part`` files and flushed; :meth:`Recorder.close`
renames them to ``NAME.csv``.  :meth:`sliders.solve.dynamics.Dynamics.run` closes the recorder on
every exit, so an interrupted or failed integration leaves whole rows of what it computed.

A recorder in memory can be checkpointed (:mod:`sliders.app.checkpoint`): its rows as CSV
cells (:meth:`Recorder.cells`), what its next record builds on (:meth:`Recorder.carry`: the
work integrals) and its kept states; :meth:`Recorder.resume` takes them back, and the records
that follow are those of the uninterrupted run.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

import numpy as np

from sliders.app.state_tables import STATE_ROWS, STEP_COLUMNS, Snapshot, cell
from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State

if TYPE_CHECKING:
    import _csv

#: A probe: an extra ``history.csv`` column computed from the state and the dynamics.
Probe = Callable[[State, "Dynamics"], float]

ENERGIES = ("kinetic", "strain", "external_work", "constraint_work", "dissipated", "energy_error")


class Recorder:
    """Collects the per-step outputs of :meth:`sliders.solve.dynamics.Dynamics.run`.

    Parameters
    ----------
    directory
        Where the CSV files go (created if missing); None keeps every table in memory, for
        :meth:`write` once the run is over.
    tables
        Per-step tables to keep, from ``nodes``, ``sliders``, ``internal_forces`` and
        ``reactions`` (module docstring).
    probes
        Extra columns: name to ``probe(state, dynamics)``.
    every
        Also keep every ``every``-th state (and the start) in :attr:`states` (0: none); the
        last recorded state is always :attr:`last`.
    """

    def __init__(
        self,
        directory: str | Path | None = None,
        tables: Sequence[str] = (),
        probes: dict[str, Probe] | None = None,
        every: int = 0,
    ) -> None:
        self.directory = None if directory is None else Path(directory)
        self.tables = list(tables)
        for i, name in enumerate(self.tables):
            if name not in STEP_COLUMNS:
                raise ValueError(
                    f"tables[{i}] must be one of {', '.join(STEP_COLUMNS)}, got {name!r}"
                )
        self.probes = dict(probes or {})
        self.every = every
        self.states: list[State] = []
        self.last: State | None = None
        self.rows: list[list[float]] = []
        self.columns: list[str] = []
        #: Each table's header, ``history`` first.
        self.headers: dict[str, Sequence[str]] = {}
        #: Without a directory, each per-step table's rows as CSV cells.
        self.kept: dict[str, list[list[str]]] = {}
        self._files: dict[str, tuple[TextIO, _csv.Writer]] = {}
        self._work = np.zeros(3)
        self._reference: float | None = None
        # the load, constraint forces and damping power of the last state (_append)
        self._f: np.ndarray
        self._reaction: np.ndarray
        self._power: float

    def table(self) -> dict[str, np.ndarray]:
        """``history.csv`` as arrays, one per column."""
        data = np.array(self.rows, dtype=float).reshape(len(self.rows), len(self.columns))
        return {name: data[:, i] for i, name in enumerate(self.columns)}

    def start(self, dynamics: "Dynamics", state: State) -> None:
        """Name the columns, open the files and record the start."""
        self._name(dynamics)
        self.rows, self.states = [], []
        self._work = np.zeros(3)
        self._reference = None
        self.kept = {name: [] for name in self.tables}
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            for name, header in self.headers.items():
                self._open(name, header)
        self._append(dynamics, state, None)

    def record(self, dynamics: "Dynamics", new: State, old: State) -> None:
        """Record the accepted step from ``old`` to ``new``."""
        self._append(dynamics, new, old)

    def write(self, directory: str | Path) -> None:
        """Write the tables recorded in memory (``directory=None``) into ``directory`` (which
        must exist): the same files a recorder streaming there would have left."""
        for name, header in self.headers.items():
            with open(Path(directory) / f"{name}.csv", "w", newline="") as stream:
                writer = csv.writer(stream)
                writer.writerow(header)
                writer.writerows(self.cells(name))

    def cells(self, name: str, start: int = 0, stop: int | None = None) -> Iterator[list[str]]:
        """Rows ``start:stop`` of table ``name`` (``history`` or a per-step table) kept in
        memory, as the CSV cells :meth:`write` writes."""
        if name == "history":
            return ([cell(x) for x in row] for row in self.rows[start:stop])
        return iter(self.kept[name][start:stop])

    def count(self, name: str) -> int:
        """How many rows table ``name`` holds in memory."""
        return len(self.rows) if name == "history" else len(self.kept[name])

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

    def resume(
        self,
        dynamics: "Dynamics",
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
        self._name(dynamics)
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
        self.rows = [[_number(x) for x in row] for row in history]
        self.kept = {name: [list(row) for row in cells[name]] for name in self.tables}
        self._work = np.array(carry["work"], dtype=float)
        self._reference = float(carry["reference"])
        self._f, self._reaction = carry["f"], carry["reaction"]
        self._power = float(carry["power"])
        self.states = list(states)
        if kept and (len(history) - 1) % self.every == 0:
            self.states[-1] = last  # the last row's state is kept: the same object, as recorded
        self.last = last

    def _name(self, dynamics: "Dynamics") -> None:
        """The columns of ``history`` and the headers of every table."""
        self.columns = ["step", "t", "h", "iterations", *ENERGIES]
        for s in dynamics.sliders:
            self.columns += [f"{s.name}.{u}" for u in s.unknown_names] + [f"{s.name}.residual"]
        self.columns += list(self.probes)
        self.headers = {"history": self.columns} | {
            name: STEP_COLUMNS[name] for name in self.tables
        }

    def close(self) -> None:
        """Flush the files and give them their final names."""
        for name, (stream, _) in self._files.items():
            stream.close()
            assert self.directory is not None  # files are opened only with a directory
            part = self.directory / f"{name}.csv.part"
            os.replace(part, self.directory / f"{name}.csv")
        self._files = {}

    def _open(self, name: str, header: Sequence[str]) -> None:
        assert self.directory is not None  # start opens files only with a directory
        stream = open(self.directory / f"{name}.csv.part", "w", newline="")
        writer = csv.writer(stream)
        writer.writerow(header)
        self._files[name] = (stream, writer)

    def _write(self, name: str, rows: list[list]) -> None:
        cells = [[cell(x) for x in row] for row in rows]
        if name in self._files:
            stream, writer = self._files[name]
            writer.writerows(cells)
            stream.flush()
        elif name in self.kept:
            self.kept[name].extend(cells)

    def _append(self, dynamics: "Dynamics", state: State, old: State | None) -> None:
        f = dynamics.load(state.t)
        reaction = dynamics.constraint_forces(state)
        power = state.v @ (dynamics.C @ state.v)
        if old is not None:
            dq = state.q - old.q
            self._work += [
                (self._f + f) @ dq / 2,
                (self._reaction + reaction) @ dq / 2,
                state.h * (self._power + power) / 2,
            ]
        self._f, self._reaction, self._power = f, reaction, power
        kinetic = state.v @ (dynamics.M @ state.v) / 2
        strain = state.q @ (dynamics.K @ state.q) / 2
        external, constraint, dissipated = self._work
        balance = kinetic + strain + dissipated - external - constraint
        if self._reference is None:
            self._reference = balance
        row = [
            len(self.rows),
            state.t,
            state.h,
            state.iterations,
            kinetic,
            strain,
            external,
            constraint,
            dissipated,
            balance - self._reference,
        ]
        residuals = dynamics.joint_residuals(state)
        for y, residual in zip(state.unknowns, residuals, strict=True):
            row += list(y) + [residual]
        row += [probe(state, dynamics) for probe in self.probes.values()]
        if self.every and len(self.rows) % self.every == 0:
            self.states.append(state)
        self.last = state
        self.rows.append(row)
        self._write("history", [row])
        if self.tables:
            snapshot = Snapshot(
                dynamics.structure,
                state.q,
                dynamics.sliders,
                state.unknowns,
                dynamics.supports,
                reaction,
            )
            head = [row[0], state.t]
            for name in self.tables:
                self._write(name, [head + r for r in STATE_ROWS[name](snapshot)])


def _number(text: str) -> int | float:
    """A ``history.csv`` cell back as the number :func:`sliders.app.state_tables.cell` wrote:
    an integer from its digits, a float from its ``repr`` (exactly)."""
    try:
        return int(text)
    except ValueError:
        return float(text)
