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

import bisect
import csv
import io
import operator
import os
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

import numpy as np
import scipy.sparse as sp

from fvbeam.names import suggest
from sliders.app.columns import ENERGIES, STEP, history_columns
from sliders.app.probes import LinearProbe, Probe
from sliders.app.state_tables import (
    STEP_COLUMNS,
    Selection,
    Snapshot,
    StateTable,
    lines,
    quote,
    state_table,
)
from sliders.solve.integrator import State

if TYPE_CHECKING:  # what records a run is imported before the time integration is
    from sliders.solve.dynamics import Dynamics

#: Steps and seconds between the blocks a streaming recorder writes.
FLUSH_ROWS, FLUSH_SECONDS = 1000, 5.0


class _Records:
    """Records of equal shape, one per step (a row as a list, or a block of rows as an
    array), kept as arrays: appended one by one into a list gathered into an array every
    ``BLOCK`` records, or a block of them at once (:meth:`extend`).  :meth:`forget` drops
    the arrays of records already written."""

    BLOCK = 512

    def __init__(self) -> None:
        self.blocks: list[np.ndarray] = []
        self.starts: list[int] = []
        self.pending: list = []
        self.count = 0

    def append(self, record) -> None:
        self.pending.append(record)
        self.count += 1
        if len(self.pending) == self.BLOCK:
            self._settle()

    def extend(self, records: np.ndarray) -> None:
        """Records ``records[0], records[1] ...`` at once."""
        self._settle()
        self.blocks.append(records)
        self.starts.append(self.count)
        self.count += len(records)

    def _settle(self) -> None:
        if self.pending:
            self.blocks.append(np.array(self.pending, dtype=float))
            self.starts.append(self.count - len(self.pending))
            self.pending = []

    def array(self, start: int, stop: int) -> np.ndarray:
        """Records ``start:stop`` (not forgotten) as one array, records along axis 0."""
        self._settle()
        first = max(bisect.bisect_right(self.starts, start) - 1, 0)
        parts = self.blocks[first : bisect.bisect_left(self.starts, stop)]
        return np.concatenate(parts)[start - self.starts[first] : stop - self.starts[first]]

    def forget(self, upto: int) -> None:
        """Drop the arrays whose records all lie before ``upto``."""
        self._settle()
        ends = [*self.starts[1:], self.count]
        drop = sum(1 for end in ends if end <= upto)
        self.blocks, self.starts = self.blocks[drop:], self.starts[drop:]


def _times(A: sp.csr_matrix, X: np.ndarray) -> np.ndarray:
    """``A`` times each row of ``X``, as rows (C order: a row's sums then run in the same
    order however many rows there are)."""
    return np.ascontiguousarray((A @ X.T).T)


class _Balance:
    """The columns computed a block of steps at a time from the steps' ``q, v, qdd`` and
    load ``f`` (copied into buffers of :attr:`size` steps, at most ``BUFFER`` bytes): the
    energies (``ENERGIES``) and the linear probes (``weights @ q``), as :attr:`records`.

    A block's energies are a few products of the matrices with the block's vectors, and the
    work integrals a cumulative sum from the last block's totals: each step's numbers do not
    depend on where a block starts, so a resumed run writes the uninterrupted one's bytes.
    """

    BUFFER = 2**23

    def __init__(self, dynamics: Dynamics, energies: bool, weights: sp.csr_matrix | None) -> None:
        self.M, self.C, self.K = dynamics.M, dynamics.C, dynamics.K
        self.load = dynamics.load
        self.energies, self.weights = energies, weights
        n = dynamics.structure.n_dofs
        self.size = max(1, min(512, self.BUFFER // (32 * max(n, 1))))
        kinds = 4 if energies else 1
        self.buffers = np.empty((kinds, self.size, n))
        self.h = np.empty(self.size)
        self.k = 0
        self.width = (len(ENERGIES) if energies else 0) + (
            0 if weights is None else weights.shape[0]
        )
        self.records = _Records()
        self.work = np.zeros(3)
        self.reference: float | None = None
        self.f = self.reaction = np.zeros(n if energies else 0)
        self.power = 0.0
        self.previous: np.ndarray | None = None

    def add(self, state: State, f: np.ndarray | None, old: State | None) -> None:
        """Keep a step's vectors; compute the block when the buffers are full."""
        if self.k == 0:
            self.previous = None if old is None else old.q.copy()
        buffers = self.buffers
        buffers[0, self.k] = state.q
        if self.energies:
            buffers[1, self.k] = state.v
            buffers[2, self.k] = state.qdd
            buffers[3, self.k] = f
            self.h[self.k] = state.h
        self.k += 1
        if self.k == self.size:
            self.settle()

    def settle(self) -> None:
        """Compute the columns of the steps kept since the last block."""
        k, self.k = self.k, 0
        if k == 0:
            return
        Q = self.buffers[0, :k]
        out = []
        if self.energies:
            V, A, F = self.buffers[1:, :k]
            out.append(self._energies(Q, V, A, F, self.h[:k]))
        if self.weights is not None:
            out.append(_times(self.weights, Q))
        self.records.extend(np.concatenate(out, axis=1) if out else np.zeros((k, 0)))

    def carry(self, state: State, row: int) -> dict[str, np.ndarray]:
        """What the step after row ``row`` (of state ``state``) builds on
        (:meth:`Recorder.carry`): the row's work integrals, as recorded; its load, constraint
        forces ``M qdd + C v + K q - f`` and damping power ``v.C v`` as :meth:`_energies`
        computes them for a block of one step."""
        self.settle()
        reference = np.array(np.nan if self.reference is None else self.reference)
        if not self.energies:
            return {
                "work": self.work.copy(),
                "reference": reference,
                "f": self.f,
                "reaction": self.reaction,
                "power": np.array(self.power),
            }
        work = self.records.array(row, row + 1)[0, 2:5].copy()  # ENERGIES' work columns
        Q, V, A = state.q[None], state.v[None], state.qdd[None]
        F = np.asarray(self.load(state.t), dtype=float)[None]
        CV = _times(self.C, V)
        reaction = _times(self.M, A) + CV + _times(self.K, Q) - F
        power = (V * CV).sum(axis=1)
        return {
            "work": work,
            "reference": reference,
            "f": F[0],
            "reaction": reaction[0],
            "power": np.array(float(power[0])),
        }

    def _energies(
        self, Q: np.ndarray, V: np.ndarray, A: np.ndarray, F: np.ndarray, h: np.ndarray
    ) -> np.ndarray:
        """Kinetic and strain energy, the work integrals and the balance's drift per step
        (module docstring): ``v.M v / 2``, ``q.K q / 2``, ``v.C v`` (the damping's power) and
        the constraint forces ``M qdd + C v + K q - f``, then the trapezoidal rule over each
        step from the last step before the block."""
        MV, CV, KQ = _times(self.M, V), _times(self.C, V), _times(self.K, Q)
        reaction = _times(self.M, A) + CV + KQ - F
        kinetic, strain = (V * MV).sum(axis=1) / 2, (Q * KQ).sum(axis=1) / 2
        power = (V * CV).sum(axis=1)
        increments = np.zeros((len(Q), 3))
        start = 0 if self.previous is not None else 1  # the start has no step before it
        if self.previous is not None:
            Q = np.concatenate([self.previous[None], Q])
            F = np.concatenate([self.f[None], F])
            R = np.concatenate([self.reaction[None], reaction])
            P = np.concatenate([[self.power], power])
        else:
            R, P = reaction, power
        dq = Q[1:] - Q[:-1]
        increments[start:, 0] = ((F[:-1] + F[1:]) * dq).sum(axis=1) / 2
        increments[start:, 1] = ((R[:-1] + R[1:]) * dq).sum(axis=1) / 2
        increments[start:, 2] = h[start:] * (P[:-1] + P[1:]) / 2
        work = np.cumsum(np.concatenate([self.work[None], increments]), axis=0)[1:]
        external, constraint, dissipated = work.T
        balance = kinetic + strain + dissipated - external - constraint
        if self.reference is None:
            self.reference = float(balance[0])
        self.work, self.f, self.reaction = work[-1], F[-1].copy(), reaction[-1].copy()
        self.power = float(power[-1])
        return np.stack(
            [kinetic, strain, external, constraint, dissipated, balance - self.reference], axis=1
        )


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
        The columns of ``history.csv`` to keep (:func:`history_columns`, checked at
        :meth:`start`; ``step, t`` are always kept); None: all.
    flush_rows, flush_seconds
        With a directory, write a block of rows every so many steps or seconds.
    """

    def __init__(
        self,
        directory: str | Path | None = None,
        tables: Sequence[str] | Mapping[str, Selection | None] = (),
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
        self._prefixes: dict[str, list[str]] = {}
        self._records: dict[str, _Records] = {}
        self._files: dict[str, tuple[TextIO, int]] = {}
        self._clock = time.monotonic()

    # -- what was recorded -----------------------------------------------------------------
    def table(self) -> dict[str, np.ndarray]:
        """``history.csv`` as arrays, one per column."""
        data = self._history(0, self.count("history"))
        return {name: data[:, i] for i, name in enumerate(self.columns)}

    @property
    def rows(self) -> list[list[float]]:
        """``history.csv``'s rows as numbers (a copy)."""
        return self._history(0, self.count("history")).tolist() if self._records else []

    def count(self, name: str) -> int:
        """How many rows table ``name`` holds (recorded so far; none before the start)."""
        if name not in self._records:
            return 0
        if name == "history":
            return self._records["history"].count
        return self._records[name].count * self._layouts[name].n_rows

    def text(self, name: str, start: int = 0, stop: int | None = None) -> str:
        """Rows ``start:stop`` of table ``name`` (``history`` or a per-step table) kept in
        memory, as the CSV text :meth:`write` writes (each line ended by ``\\r\\n``, as
        :mod:`csv` ends them)."""
        rows = self._lines(name, start, self.count(name) if stop is None else stop)
        return "".join(line + "\r\n" for line in rows)

    def carry(self, state: State | None = None, rows: int | None = None) -> dict[str, np.ndarray]:
        """What the record after the first ``rows`` rows (default all of them) builds on, as
        arrays (a checkpoint saves them; :meth:`resume` takes them back): the work integrals
        up to that row, the energy balance at the start, and the load, constraint forces and
        damping power of the row's ``state`` (default the last recorded), by the products a
        block of steps takes (the same numbers).  A checkpoint of a step asks for them when
        it is written, so that the energies are still computed a block of steps at a time."""
        if not self._records:
            raise ValueError("the recorder has not started: nothing to carry")
        rows = self.count("history") if rows is None else rows
        state = self.last if state is None else state
        assert state is not None  # the recorder has started: its start is recorded
        return self._balance.carry(state, rows - 1)

    def _history(self, start: int, stop: int) -> np.ndarray:
        """Rows ``start:stop`` of ``history.csv`` as numbers."""
        if stop <= start:
            return np.zeros((0, len(self.columns)))
        self._balance.settle()
        parts = [self._records["history"].array(start, stop).reshape(stop - start, -1)]
        if self._balance.width:
            parts.append(self._balance.records.array(start, stop))
        return np.concatenate(parts, axis=1)[:, self._order]

    def _lines(self, name: str, start: int, stop: int) -> list[str]:
        """Rows ``start:stop`` of table ``name`` as CSV lines."""
        if stop <= start:
            return []
        if name == "history":
            return lines(self._history(start, stop), integers=self._integers)
        layout, prefixes = self._layouts[name], self._prefixes[name]
        n, fixed = layout.n_rows, layout.fixed.shape[1]
        first, last = start // n, -(-stop // n)
        values = self._records[name].array(first, last)
        steps = len(values)
        blank = np.tile(layout.blank[:, fixed:], (steps, 1))
        body = lines(values.reshape(steps * n, -1), blank)
        heads = lines(self._history(first, last)[:, :2], integers=(0,))
        if blank.shape[1]:
            out = [f"{heads[k // n]},{prefixes[k % n]},{row}" for k, row in enumerate(body)]
        else:
            out = [f"{heads[k // n]},{prefixes[k % n]}" for k in range(len(body))]
        return out[start - first * n : stop - first * n]

    # -- recording -------------------------------------------------------------------------
    def start(self, dynamics: Dynamics, state: State) -> None:
        """Name the columns, open the files and record the start."""
        self._prepare(dynamics)
        self.states = []
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            for name, header in self.headers.items():
                self._open(name, header)
        self._append(dynamics, state, None)

    def record(self, dynamics: Dynamics, new: State, old: State) -> None:
        """Record the accepted step from ``old`` to ``new``."""
        self._append(dynamics, new, old)
        if self._files and (
            self._records["history"].count - self._files["history"][1] >= self.flush_rows
            or time.monotonic() - self._clock >= self.flush_seconds
        ):
            self._flush()

    def write(
        self, directory: str | Path, written: Mapping[str, tuple[Path, int, int]] | None = None
    ) -> None:
        """Write the tables recorded in memory (``directory=None``) into ``directory`` (which
        must exist): the same files a recorder streaming there would have left.

        ``written``: per table, a file holding its header and first rows as this recorder
        writes them, their count and the file's length in bytes (the last checkpoint's,
        :meth:`sliders.app.checkpoint.Checkpoints.written`): those bytes are copied and only
        the rows after them turned into text; a file that cannot be read is written whole."""
        for name, header in self.headers.items():
            head = io.StringIO(newline="")
            csv.writer(head).writerow(header)
            data, rows = head.getvalue().encode(), 0
            if written and name in written:
                source, count, size = written[name]
                try:
                    with open(source, "rb") as stream:
                        copied = stream.read(size)
                    if len(copied) == size:
                        data, rows = copied, count
                except OSError:
                    pass
            with open(Path(directory) / f"{name}.csv", "wb") as stream:
                stream.write(data)
                stream.write(self.text(name, rows).encode())

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
        tables, without headers) as :mod:`csv` reads back what :meth:`text` gave, ``carry``
        as :meth:`carry` gave it after the last of them, and the kept ``states``.  The
        records that follow are those of the uninterrupted recording
        (:meth:`sliders.solve.dynamics.Dynamics.resume`); ``ValueError`` if the pieces do
        not fit this recorder."""
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
        numbers = np.full((len(history), self._width), np.nan)
        numbers[:, self._order] = np.array(history, dtype=float)
        base = self._width - self._balance.width
        self._records["history"].extend(numbers[:, :base])
        if self._balance.width:
            self._balance.records.extend(numbers[:, base:])
        for name in self.tables:
            self._take_back(name, cells[name], len(history))
        balance = self._balance
        balance.work = np.array(carry["work"], dtype=float)
        reference = float(carry["reference"])
        balance.reference = None if np.isnan(reference) else reference
        balance.f, balance.reaction = carry["f"], carry["reaction"]
        balance.power = float(carry["power"])
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
        skip = 3 + layout.fixed.shape[1]  # step, t, the label and the shared columns
        numbers = [[float(x) if x else np.nan for x in row[skip:]] for row in rows]
        self._records[name].extend(np.array(numbers, dtype=float).reshape(steps, n, width - skip))

    def close(self) -> None:
        """Write the rows not yet written and give the files their final names."""
        if self._files:
            self._flush()
        for name, (stream, _) in self._files.items():
            stream.close()
            assert self.directory is not None  # files are opened only with a directory
            part = self.directory / f"{name}.csv.part"
            os.replace(part, self.directory / f"{name}.csv")
        self._files = {}

    def _prepare(self, dynamics: Dynamics) -> None:
        """The columns of ``history``, the layout of every table, empty records, and what
        each step computes: the energies if a kept column needs them, the joints'
        residuals if one is kept, the linear probes as one matrix."""
        every = history_columns(dynamics.sliders)
        for i, column in enumerate(self.history or ()):
            if column not in every:
                raise ValueError(
                    f"history[{i}] = {column!r}: no such column{suggest(column, every)}"
                )
        keep = set(STEP[:2]) | set(every if self.history is None else self.history)
        self.columns = [c for c in every if c in keep] + list(self.probes)
        self._integers = [i for i, c in enumerate(self.columns) if c in ("step", "iterations")]
        energies = bool(keep & set(ENERGIES))
        self._residuals = any(c.endswith(".residual") for c in keep)
        linear = {name: p for name, p in self.probes.items() if isinstance(p, LinearProbe)}
        weights = [p.weights for p in linear.values()]
        self._balance = _Balance(
            dynamics, energies, sp.vstack(weights, format="csr") if weights else None
        )
        # a step's row: the kept columns but the energies, then the callable probes;
        # _Balance's: the kept energies' block (all six), then the linear probes
        stepwise = [i for i, c in enumerate(every) if c in keep and c not in ENERGIES]
        self._stepwise = operator.itemgetter(*stepwise)  # step and t: at least two
        self._calls = [
            (name, p) for name, p in self.probes.items() if not isinstance(p, LinearProbe)
        ]
        names = [every[i] for i in stepwise] + [name for name, _ in self._calls]
        names += list(ENERGIES) if energies else []
        names += list(linear)
        self._width = len(names)
        self._order = np.array([names.index(c) for c in self.columns], dtype=int)
        self._layouts = {
            name: state_table(
                name, dynamics.structure, dynamics.sliders, dynamics.supports, selection
            )
            for name, selection in self.selections.items()
        }
        # each row's label and shared columns (StateTable.fixed) as text, once
        self._prefixes = {
            name: [
                ",".join([quote(label), cells]) if layout.fixed.shape[1] else quote(label)
                for label, cells in zip(
                    layout.labels,
                    lines(layout.fixed, layout.blank[:, : layout.fixed.shape[1]]),
                    strict=True,
                )
            ]
            for name, layout in self._layouts.items()
        }
        self.headers = {"history": self.columns} | {
            name: ("step", "t", *layout.columns) for name, layout in self._layouts.items()
        }
        self._records = {name: _Records() for name in self.headers}

    def _open(self, name: str, header: Sequence[str]) -> None:
        assert self.directory is not None  # start opens files only with a directory
        stream = open(self.directory / f"{name}.csv.part", "w", newline="")
        csv.writer(stream).writerow(header)
        self._files[name] = (stream, 0)

    def _flush(self) -> None:
        """Append the rows recorded since the last block to the files."""
        for name, (stream, written) in self._files.items():
            count = self.count(name)
            stream.write(self.text(name, written, count))
            stream.flush()
            self._files[name] = (stream, count)
            if name != "history":
                self._records[name].forget(self._records[name].count)
        self._clock = time.monotonic()

    def _append(self, dynamics: Dynamics, state: State, old: State | None) -> None:
        history = self._records["history"]
        step = history.count
        row = [step, state.t, state.h, state.iterations, *_ENERGY_SLOTS]
        residuals = (
            dynamics.joint_residuals(state).tolist()
            if self._residuals
            else [np.nan] * len(state.unknowns)
        )
        for y, residual in zip(state.unknowns, residuals, strict=True):
            row += y.tolist()
            row.append(residual)
        kept = self._stepwise(row)
        if self._calls:
            kept += tuple(probe(state, dynamics) for _, probe in self._calls)
        history.append(kept)
        balance = self._balance
        if balance.energies or balance.weights is not None:
            balance.add(state, dynamics.load(state.t) if balance.energies else None, old)
        if self.every and step % self.every == 0:
            self.states.append(state)
        self.last = state
        if self._layouts:
            snapshot = Snapshot(
                dynamics.structure,
                state.q,
                dynamics.sliders,
                state.unknowns,
                dynamics.supports,
                dynamics.constraint_forces(state) if "reactions" in self._layouts else None,
            )
            for name, layout in self._layouts.items():
                self._records[name].append(layout.values(snapshot)[:, layout.fixed.shape[1] :])


#: Placeholders of the energies in a step's full row (they are computed by blocks).
_ENERGY_SLOTS = (0.0,) * len(ENERGIES)
