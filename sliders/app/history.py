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

On request, ``displacements.csv`` (``t`` and every global dof, named as
:meth:`fvbeam.structure.Structure.dof_name`), ``internal_forces.csv`` (``t`` and, per beam
and recovery point, ``N, Vy, Vz, T, My, Mz`` in the section frame) and ``reactions.csv``
(``t`` and what the supports and dof drives exert on each dof they hold, global axes:
``M qdd + C v + K q - f`` there).

Rows are written as they come into ``NAME.csv.part`` files and flushed; :meth:`Recorder.close`
renames them to ``NAME.csv``.  :meth:`sliders.solve.dynamics.Dynamics.run` closes the recorder on
every exit, so an interrupted or failed integration leaves whole rows of what it computed.
A recorder kept in memory (no directory) writes the same files later, :meth:`Recorder.write`.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

import numpy as np

from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State

#: A probe: an extra ``history.csv`` column computed from the state and the dynamics.
Probe = Callable[[State, "Dynamics"], float]

ENERGIES = ("kinetic", "strain", "external_work", "constraint_work", "dissipated", "energy_error")
FORCE_NAMES = ("N", "Vy", "Vz", "T", "My", "Mz")


class Recorder:
    """Collects the per-step outputs of :meth:`sliders.solve.dynamics.Dynamics.run`.

    Parameters
    ----------
    directory
        Where the CSV files go (created if missing); None keeps everything in memory only.
    displacements, internal_forces, reactions
        Also keep (and write) every dof, the beams' internal forces, and the reactions on
        the held dofs.
    probes
        Extra columns: name to ``probe(state, dynamics)``.
    every
        Also keep every ``every``-th state (and the start) in :attr:`states` (0: none); the
        last recorded state is always :attr:`last`.
    """

    def __init__(
        self,
        directory: str | Path | None = None,
        displacements: bool = False,
        internal_forces: bool = False,
        probes: dict[str, Probe] | None = None,
        every: int = 0,
        reactions: bool = False,
    ) -> None:
        self.directory = None if directory is None else Path(directory)
        self.keep_displacements, self.keep_forces = displacements, internal_forces
        self.keep_reactions = reactions
        self.reactions: list[np.ndarray] = []
        self.probes = dict(probes or {})
        self.every = every
        self.states: list[State] = []
        self.last: State | None = None
        self.rows: list[list[float]] = []
        self.displacements: list[np.ndarray] = []
        self.internal_forces: list[np.ndarray] = []
        self.columns: list[str] = []
        self.headers: dict[str, list[str]] = {}
        self._files: dict[str, tuple[TextIO, csv.writer]] = {}
        self._work = np.zeros(3)
        self._reference: float | None = None

    def table(self) -> dict[str, np.ndarray]:
        """``history.csv`` as arrays, one per column."""
        data = np.array(self.rows, dtype=float).reshape(len(self.rows), len(self.columns))
        return {name: data[:, i] for i, name in enumerate(self.columns)}

    def start(self, dynamics: "Dynamics", state: State) -> None:
        """Name the columns, open the files and record the start."""
        self.columns = ["step", "t", "h", "iterations", *ENERGIES]
        for s in dynamics.sliders:
            self.columns += [f"{s.name}.{u}" for u in s.unknown_names] + [f"{s.name}.residual"]
        self.columns += list(self.probes)
        self.rows, self.displacements, self.internal_forces, self.states = [], [], [], []
        self.reactions = []
        self._held = np.setdiff1d(np.arange(dynamics.structure.n_dofs), dynamics.free)
        self._work = np.zeros(3)
        self._reference = None
        structure = dynamics.structure
        self.headers = {"history": self.columns}
        if self.keep_displacements:
            self.headers["displacements"] = ["t"] + [
                structure.dof_name(d) for d in range(structure.n_dofs)
            ]
        if self.keep_forces:
            header = ["t"]
            for b, beam in enumerate(structure.beams):
                points = len(beam.internal_forces(np.zeros(beam.n_dofs)).xi)
                header += [f"beam {b} point {i} {c}" for i in range(points) for c in FORCE_NAMES]
            self.headers["internal_forces"] = header
        if self.keep_reactions:
            self.headers["reactions"] = ["t"] + [structure.dof_name(d) for d in self._held]
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            for name, header in self.headers.items():
                self._open(name, header)
        self._append(dynamics, state, None)

    def record(self, dynamics: "Dynamics", new: State, old: State) -> None:
        """Record the accepted step from ``old`` to ``new``."""
        self._append(dynamics, new, old)

    def write(self, directory: str | Path) -> None:
        """Write the tables recorded so far into ``directory`` (which must exist), the same
        files a recorder streaming there would have left: what a recorder kept in memory
        (``directory=None``) writes once the run is over."""
        times = [row[1] for row in self.rows]
        kept = {
            "displacements": self.displacements,
            "internal_forces": self.internal_forces,
            "reactions": self.reactions,
        }
        for name, header in self.headers.items():
            rows = (
                self.rows
                if name == "history"
                else ([t, *v] for t, v in zip(times, kept[name], strict=True))
            )
            with open(Path(directory) / f"{name}.csv", "w", newline="") as stream:
                writer = csv.writer(stream)
                writer.writerow(header)
                writer.writerows(_cells(row) for row in rows)

    def close(self) -> None:
        """Flush the files and give them their final names."""
        for name, (stream, _) in self._files.items():
            stream.close()
            part = self.directory / f"{name}.csv.part"
            os.replace(part, self.directory / f"{name}.csv")
        self._files = {}

    def _open(self, name: str, header: list[str]) -> None:
        stream = open(self.directory / f"{name}.csv.part", "w", newline="")
        writer = csv.writer(stream)
        writer.writerow(header)
        self._files[name] = (stream, writer)

    def _write(self, name: str, row: list[float]) -> None:
        if name in self._files:
            stream, writer = self._files[name]
            writer.writerow(_cells(row))
            stream.flush()

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
        self._write("history", row)
        if self.keep_displacements:
            self.displacements.append(state.q.copy())
            self._write("displacements", [state.t, *state.q])
        if self.keep_forces:
            forces = np.concatenate(
                [
                    np.column_stack([i.force, i.moment]).ravel()
                    for i in (
                        beam.internal_forces(dynamics.structure.local(b, state.q))
                        for b, beam in enumerate(dynamics.structure.beams)
                    )
                ]
            )
            self.internal_forces.append(forces)
            self._write("internal_forces", [state.t, *forces])
        if self.keep_reactions:
            self.reactions.append(reaction[self._held])
            self._write("reactions", [state.t, *reaction[self._held]])


def _cells(row: list[float]) -> list[str]:
    """A row as its CSV cells: integers as they are, floats by ``repr`` (exact round trip)."""
    return [str(x) if isinstance(x, (int, np.integer)) else repr(float(x)) for x in row]
