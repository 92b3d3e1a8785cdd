"""The compiled Newton step of one problem: what every solve path runs.

:class:`CompiledNewton` prepares, once per problem (structure, supports, joints and operator),
what :func:`sliders.solve.newton_kernel.newton` reads: the operator in compressed rows, the
factors of the bordered operator (:class:`sliders.solve.condensed.CondensedOperator`), the
joints packed (:class:`sliders.joints.packed.JointPack`) with their layout for the condensed
step, and a cache of columns of the inverse that lives as long as the problem.  A solve is
then one compiled call: the whole Newton loop (residual, joints, small system, increments,
convergence) runs without returning to Python.

It is the condensed back end of :func:`sliders.solve.statics.newton_many` for one member, the
same equations in the same order (``tests/test_compiled_newton.py`` holds the two equal to
the Newton tolerance); failures are reported as ``newton_many`` reports them (the free
motion named, the joint whose abscissa left its line, the last residual), by the same
Python code on the state where the loop stopped.
"""

from __future__ import annotations

import weakref
from collections.abc import Sequence
from typing import Protocol

import numpy as np
import scipy.sparse as sp

from fvbeam.copies import shallow_copy
from fvbeam.mechanism import node_positions
from fvbeam.structure import Structure
from sliders.forces.elements import ForceElement
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.solve.condensed import DENSE_LIMIT, SINGULAR_RCOND
from sliders.solve.factor import Factor
from sliders.solve.mechanism import joint_parts
from sliders.solve.newton_kernel import (
    CONVERGED,
    NOT_CONVERGED,
    NOT_CONVERGED_MESSAGE,
    OFF_LINE,
    OVERFLOW,
    SINGULAR,
    NewtonProblem,
    newton,
)


class Diagnosis(Protocol):
    """What names a failed solve (:class:`sliders.solve.statics.SliderStatics` is one): its
    structure and sliders, and the diagnosis of a singular or unconverged step."""

    structure: Structure
    sliders: list[Slider]

    def _diagnose(self, parts: list, fallback: str, cold: bool) -> str: ...


class Moved(Diagnosis, Protocol):
    """A problem a compiled loop moves to (:meth:`CompiledNewton.moved`): its force
    elements too."""

    forces: list[ForceElement]


#: Columns of the inverse kept beyond what one iteration needs, on problems too large to
#: keep every column (above :data:`sliders.solve.condensed.DENSE_LIMIT` unknowns).
SPARE_COLUMNS = 64
#: The most memory the columns of the inverse may take (bytes): a column is as long as the
#: problem, so joints on a mesh of a million dofs would need gigabytes; the bordered back end
#: (one factorisation per step, no columns) takes such problems (``auto`` falls back to it).
COLUMN_BYTES = 256 * 2**20


class ColumnStorageError(ValueError):
    """The condensed back end's columns would not fit :data:`COLUMN_BYTES`."""


class CompiledNewton:
    """The Newton loop of a problem, compiled (module docstring): ``sliders`` on
    ``structure``, the operator ``K`` (n, n) with its ``free`` dofs, the ``factor`` of the
    bordered operator on them and the rigid modes ``phi`` that border it.  ``statics``: the
    problem's :class:`~sliders.solve.statics.SliderStatics`, whose Python code names what
    makes a solve fail (:attr:`~sliders.solve.statics.SliderStatics.compiled` builds both);
    without it, only :attr:`problem` is of use (a structure without sliders,
    :mod:`sliders.solve.dynamics_kernel`).  ``forces``: the force elements; ``pinned``: per
    joint, the unknowns a planar solve pins (:func:`sliders.solve.planar.pinned`).

    The loop holds its statics by a weak reference: the statics holds the loop, and a
    reference back would make each problem a cycle that only the garbage collector frees
    (a sweep drops a problem per point: their memory would wait for the collector instead
    of being reused at once)."""

    def __init__(
        self,
        structure: Structure,
        sliders: Sequence[Slider],
        K: sp.spmatrix,
        free: np.ndarray,
        factor: Factor,
        phi: np.ndarray,
        statics: Diagnosis | None = None,
        forces: Sequence[ForceElement] = (),
        pinned: Sequence[Sequence[int]] | None = None,
    ) -> None:
        self._statics = None if statics is None else weakref.ref(statics)
        K = sp.csr_matrix(K)
        K.sort_indices()
        self.operator = (K.indptr.astype(np.int64), K.indices.astype(np.int64), K.data)
        self.free = np.asarray(free, dtype=np.int64)
        self.position = np.full(structure.n_dofs, -1, dtype=np.int64)
        self.position[self.free] = np.arange(len(self.free))
        self.factor = factor.arrays
        self.phi = np.ascontiguousarray(phi, dtype=float).reshape(len(self.free), -1)
        self.pack = JointPack(sliders, structure, pinned)
        tables, c_of, rows, forces_at = [], [], [], []
        at = np.zeros(4, dtype=np.int64)
        nc = 0
        for (_, jacobian), t, m, width in zip(
            self.pack.layouts,
            self.pack.slots,
            self.pack.unknowns,
            self.pack.widths,
            strict=True,
        ):
            c, carry, index = jacobian.coupling()
            rows.append(
                [1, t, m, width, at[0], at[1], at[2], at[2] + len(jacobian.table), at[3], len(c)]
            )
            tables.append(jacobian.table)
            c_of.append(index)
            forces_at.append(at[0] + carry)
            at += [t, width, len(jacobian.table), t]
            nc += len(c)
        # each force element: one dense 6 x 6 block on its six slots, all of them read
        element = np.array([[0, 6, 0, 6, 0]], dtype=np.int64)
        packed = [e.packed(structure) for e in forces]
        self.elements = (
            np.array([e.kind for e in forces], dtype=np.int64),
            np.array([e.slots(structure) for e in forces], dtype=np.int64).reshape(-1, 6),
            np.concatenate([np.zeros(0)] + packed),
            np.cumsum([0] + [len(p) for p in packed]).astype(np.int64),
        )
        for _ in forces:
            rows.append([1, 6, 0, 36, at[0], at[1], at[2], at[2] + 1, at[3], 6])
            tables.append(element)
            c_of.append(np.arange(6))
            forces_at.append(at[0] + np.arange(6))
            at += [6, 36, 1, 6]
            nc += 6
        self.tables = np.concatenate(tables + [np.zeros((0, 5), dtype=np.int64)])
        self.c_of = np.concatenate(c_of + [np.zeros(0)]).astype(np.int64)
        self.batches = np.array(rows, dtype=np.int64).reshape(len(rows), 10)
        self.force_slots = np.concatenate(forces_at + [np.zeros(0)]).astype(np.int64)
        self.nc = nc
        n_free, k = len(self.free), self.phi.shape[1]
        capacity = n_free if n_free + k <= DENSE_LIMIT else len(self.force_slots) + SPARE_COLUMNS
        if capacity * (n_free + k) * 8 > COLUMN_BYTES:
            raise ColumnStorageError(
                f"the condensed back end would keep {capacity} columns of {n_free + k} "
                f"unknowns ({capacity * (n_free + k) * 8 / 2**30:.1f} GiB): solve with "
                "method='bordered'"
            )
        self.store = np.zeros((max(capacity, 1), n_free + k))
        self.column = np.full(n_free, -1, dtype=np.int64)
        self.count = np.zeros(1, dtype=np.int64)
        positions = node_positions(structure)
        self.resolution = 4 * np.finfo(float).eps * max(1.0, np.abs(positions).max())
        self.sizes = [s.n_unknowns for s in sliders]
        #: Whether a joint is driven (its abscissa read at each solve's time); if none is,
        #: the solves share one array of zero drives, read only.
        self.driven = any(s.drive is not None for s in sliders)
        self.undriven = np.zeros(len(self.sizes))
        #: The velocities ``(v_hat, q_hat, c_v)`` of a solve at rest (:meth:`solve`), read
        #: only: zeros (with ``c_v = 0``, ``q_hat`` only meets a zero factor).
        self.at_rest = (np.zeros(structure.n_dofs), np.zeros(structure.n_dofs), 0.0)
        #: Each joint's first and last-plus-one unknown among the joints' side by side.
        starts = np.cumsum([0] + self.sizes)[:-1].tolist()
        self.bounds = [(a, a + m) for a, m in zip(starts, self.sizes, strict=True)]
        #: What :func:`sliders.solve.newton_kernel.newton` reads of the problem.
        self.problem = NewtonProblem(
            *self.operator,
            self.free,
            self.position,
            self.factor,
            self.phi,
            self.store,
            self.column,
            self.count,
            self.pack.pool,
            *self.elements,
            self.tables,
            self.c_of,
            self.batches,
            self.force_slots,
            self.nc,
            SINGULAR_RCOND,
            self.resolution,
        )

    @property
    def statics(self) -> Diagnosis | None:
        """The problem this loop solves (None without one, or once it is gone)."""
        return None if self._statics is None else self._statics()

    def moved(self, statics: Moved, known_moved: bool = False) -> CompiledNewton | None:
        """This loop for ``statics``, a problem on the same operator whose joints are this
        one's moved rigidly (:meth:`sliders.joints.packed.JointPack.moved`): everything
        shared but the joints' positions and the force elements' constants; None when the
        joints are not this loop's moved (build it anew).  ``known_moved``: the caller made
        ``statics``' sliders from this loop's by :meth:`sliders.joints.slider.Slider.moved`
        (:meth:`sliders.solve.statics.SliderStatics.moved`), so they are not compared again."""
        pack = self.pack.moved(statics.sliders, statics.structure, known_moved)
        if pack is None or len(statics.forces) != len(self.elements[0]):
            return None
        out = shallow_copy(self)
        out._statics, out.pack = weakref.ref(statics), pack
        if not known_moved:  # a moved slider keeps its drive
            out.driven = any(s.drive is not None for s in statics.sliders)
        if statics.forces:  # without force elements, their (empty) constants are kept
            packed = [e.packed(statics.structure) for e in statics.forces]
            out.elements = (*self.elements[:2], np.concatenate(packed), self.elements[3])
        out.problem = self.problem._replace(joints=pack.pool, element_values=out.elements[2])
        return out

    def solve(
        self,
        f: np.ndarray,
        q: np.ndarray,
        unknowns: Sequence[np.ndarray],
        tol: float,
        max_iterations: int,
        time: float = 0.0,
        scale: float = 1.0,
        velocity: tuple[np.ndarray, np.ndarray, float] | None = None,
    ) -> tuple[np.ndarray, list[np.ndarray], list[float]] | str:
        """Newton from ``q`` and the joints' ``unknowns`` under the load ``f``: the
        converged ``q``, unknowns and scaled residual history, or the message of the
        failure (as :func:`sliders.solve.statics.newton_many` gives them for one member).
        ``velocity``: ``(v_hat, q_hat, c_v)``, the velocities ``v_hat + c_v (q - q_hat)``
        the force elements read (default: at rest).  ``ValueError`` (the joint named) when an
        abscissa leaves its line."""
        statics = self.statics
        if statics is None:
            raise ValueError("a compiled Newton loop without its statics does not solve")
        q0 = q  # the start, unchanged (the loop works on copies), for a failure's diagnosis
        q, y = np.array(q, dtype=float), np.concatenate([*unknowns, ()], dtype=float)
        drives = (
            np.array([s.drive(time)[0] if s.drive is not None else 0.0 for s in statics.sliders])
            if self.driven
            else self.undriven
        )
        history = np.zeros(max_iterations + 1)
        status, evaluations, joint = newton(
            self.problem,
            np.ascontiguousarray(f, dtype=float),
            q,
            y,
            drives,
            float(scale),
            float(tol),
            int(max_iterations),
            history,
            velocity if velocity is not None else self.at_rest,
            np.zeros(len(self.sizes)),
        )
        split = [y[a:b] for a, b in self.bounds]
        if status == CONVERGED:
            return q, split, history[:evaluations].tolist()
        if status in (OFF_LINE, OVERFLOW):
            # the Python evaluation of the joint raises the reference's error
            slider = statics.sliders[joint]
            at = int(np.cumsum([0] + self.sizes)[joint])
            slider.batch(statics.structure).evaluate(
                q[None], y[None, at : at + self.sizes[joint]], time, scale
            )
            raise RuntimeError(f"slider {slider.name!r}: the compiled joint failed ({status})")
        multipliers = np.ones(len(y), dtype=bool)
        multipliers[np.cumsum([0] + self.sizes)[:-1].astype(int)] = False
        if status == SINGULAR:
            parts = joint_parts(statics.structure, statics.sliders, q, split, time, scale)
            return statics._diagnose(
                parts,
                "the condensed system has no finite solution",
                not np.any(y[multipliers]),
            )
        assert status == NOT_CONVERGED
        y0 = np.concatenate([*unknowns, ()], dtype=float)
        first = joint_parts(
            statics.structure,
            statics.sliders,
            np.asarray(q0, dtype=float),
            np.split(y0, np.cumsum(self.sizes)[:-1]) if self.sizes else [],
            time,
            scale,
        )
        return statics._diagnose(
            first,
            f"{NOT_CONVERGED_MESSAGE} in {max_iterations} iterations "
            f"(scaled residual {history[max_iterations]:.3g})",
            not np.any(y0[multipliers]),
        )
