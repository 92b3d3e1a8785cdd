"""Condensed Newton step for sliders on linear beams: factorise ``K`` once, solve small systems.

The beams are linear, so their stiffness ``K`` (free dofs) is constant, and the sliders touch
only a few dofs.  ``K`` may be singular: a part held only by sliders (the piston of the
sliding-beams setup) keeps the rigid motions its supports leave free.  Their basis ``Phi``
(:func:`fvbeam.mechanism.rigid_modes`) spans both null spaces of ``K``: ``K Phi = 0`` (a
rigid motion does not strain) and ``Phi^T K = 0`` (a rigid virtual motion does no internal
work; the fv regions and the Galerkin shape functions both reproduce rigid motions).  The
bordered operator

    B = [K, s Phi; s Phi^T, 0]          (s = max |K|, to balance the pivots)

is then regular and is factorised once per structure and support set.  ``B^{-1}[b; 0] =
[x; z]`` gives ``K x = b - s Phi z`` with ``Phi^T x = 0`` and ``z = 0`` exactly when ``b`` is
self-equilibrated on every free part (``Phi^T b = 0``).

The joints give their residuals and Jacobians on *slots* (:meth:`sliders.joints.slider.SliderBatch.
evaluate`): ``P`` injects the slots into the free dofs (a dof may hold several slots; the
supported ones are dropped).  A Newton step solves ``K dq + P g = -r_q``,
``C P^T dq + D dy = -r_y`` with ``g = E P^T dq + A dy`` the slot force increments
(``E, A, C, D``: the joints' Jacobian blocks).  ``E`` reads only a few slots ``c`` (the body
rotations, times the multipliers; none when the sliding point is on the node), so
``g = F u`` with ``F = [E_c, A]`` and ``u = [w_c; dy]``, ``w_c = P_c^T dq``.  Writing
``dq = x + Phi a`` with ``[x; z] = -B^{-1}[r_q + P g; 0]``, ``[x_r; z_r] = B^{-1}[r_q; 0]``
and ``Y = B^{-1}[P F; 0]`` (from the columns of ``B^{-1}`` at the slots that carry forces,
cached per dof), the conditions are::

    w_c + Y_c u - Phi_c a           = -x_r,c          (nc rows: w_c is dq on c)
    Y_z u                           = -z_r            (k rows: z = 0, self-equilibrium)
    -C Y_x u + [0, D] u + C Phi a   = -r_y + C x_r    (m rows: the joint equations)

a dense system of size ``nc + m + k`` (``C`` read on the slots it touches); then
``dq = -B^{-1}[r_q + P F u; 0]_x + Phi a``.  :meth:`CondensedOperator.step` does this for
``B`` independent members sharing ``K`` at once (one stacked solve; ``B = 1`` for a single
problem).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from sliders.joints.blocks import SlotJacobian
from sliders.solve.condensed_kernel import Columns, Jacobians, condensed_step
from sliders.solve.factor import Factor

#: A small system whose row- and column-equilibrated reciprocal condition number (1-norm)
#: falls below this is singular: the threshold of the bordered diagnostic
#: (:meth:`sliders.solve.statics.SliderStatics._singular`).
SINGULAR_RCOND = 1e-12

#: Up to this size (free dofs and rigid modes) every column of ``B^{-1}`` is computed at
#: once (at most 72 MB) and the solves are dense products: on the sliding-beams operator
#: (128 unknowns, 96 right-hand sides, one BLAS thread) SuperLU's triangular solves take
#: 0.5 ms, the dense product 0.24 ms.
DENSE_LIMIT = 3000


class CondensedOperator:
    """``B`` factorised once, with the columns of ``B^{-1}`` cached per free dof; ``K`` is
    the structure's global stiffness (or the time integrator's operator), ``free`` its
    unsupported dofs, ``phi`` the free rigid motions it does not resist
    (:attr:`sliders.solve.statics.SliderStatics.rigid`).

    Raises ``ValueError`` when ``B`` is singular: the supports leave a mechanism that is not
    a rigid motion of a part (use the bordered back end, which lets the sliders hold it).
    """

    def __init__(self, K: sp.spmatrix, free: np.ndarray, phi: np.ndarray) -> None:
        K_free = sp.csr_matrix(K)[free][:, free]
        self.phi = np.ascontiguousarray(phi)
        self.n_free, self.n_rigid = len(free), self.phi.shape[1]
        largest = np.abs(K_free).max()
        # a structure held by force elements alone has no stiffness: any scale then
        scale = largest if largest > 0 else 1.0
        B = sp.bmat(
            [[K_free, scale * sp.csr_matrix(self.phi)], [scale * sp.csr_matrix(self.phi.T), None]],
            format="csc",
        )
        message = (
            "the stiffness without the free parts' rigid motions is singular: the "
            "supports leave a mechanism; solve with method='bordered'"
        )
        try:
            #: ``B`` factorised, its factors kept for compiled solves
            #: (:mod:`sliders.solve.newton_kernel`).
            self.factor = Factor(B)
        except ValueError as exc:
            raise ValueError(message) from exc
        self.lu = self.factor.lu
        pivots = np.abs(self.factor.pivots)
        if pivots.min() <= 1e-13 * pivots.max():
            raise ValueError(message)
        self._slot = np.full(self.n_free, -1)
        self._store = np.zeros((0, self.n_free + self.n_rigid))
        # below the limit every column is stored, in order: the store is the dense inverse,
        # computed when first asked for (the compiled Newton step keeps columns of its own)
        self._dense = self.n_free + self.n_rigid <= DENSE_LIMIT

    def _inverse(self) -> None:
        """Below :data:`DENSE_LIMIT`, every column of ``B^{-1}``, in order, once."""
        if self._dense and not len(self._store):
            self._columns(np.arange(self.n_free))

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``B^{-1} [b; 0]`` for right-hand sides ``b`` (B, n_free) on the free dofs:
        (B, n_free + k); from the dense inverse below :data:`DENSE_LIMIT` (its columns
        computed in order when first needed)."""
        self._inverse()
        if self._dense:
            return b @ self._store
        rhs = np.concatenate([b, np.zeros((len(b), self.n_rigid))], axis=1)
        return self.lu.solve(np.asfortranarray(rhs.T)).T  # SuperLU reads columns

    def _columns(self, positions: np.ndarray) -> None:
        """Store the columns ``B^{-1}[U; 0]`` of the free dofs at ``positions`` as rows of
        ``_store`` (``_slot``: the row of each free dof, -1 until computed); each column is
        computed once and kept."""
        missing = np.unique(positions[self._slot[positions] < 0])
        if not missing.size:
            return
        unit = np.zeros((self.n_free + self.n_rigid, missing.size), order="F")
        unit[missing, np.arange(missing.size)] = 1.0
        if self._dense:  # every column, once, at construction
            solved = self.lu.solve(unit)
        else:
            # one at a time: SuperLU solves several right-hand sides in blocks whose roundoff
            # depends on the block, and a column's bits must not depend on the columns missing
            # with it (a time integration resumed from a checkpoint asks for them in other
            # groups, and repeats the uninterrupted run's arithmetic)
            solved = np.column_stack([self.lu.solve(unit[:, [k]]) for k in range(missing.size)])
        self._slot[missing] = len(self._store) + np.arange(missing.size)
        self._store = np.vstack([self._store, solved.T])

    def step(
        self,
        r_free: np.ndarray,
        slots: list[np.ndarray],
        blocks: list[SlotJacobian],
        r_y: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Newton increments of ``B`` members sharing this operator (module docstring): the
        small systems formed and solved per member by
        :func:`sliders.solve.condensed_kernel.condensed_step`.

        Parameters
        ----------
        r_free : (B, n_free)
            The structure residuals.
        slots : list of (k B, t_j)
            Per batch of ``k`` alike joints (:meth:`sliders.joints.slider.SliderBatch.joined`; one
            joint, ``k = 1``), the free-dof position of each of their slots, -1 where
            supported: joint ``i`` of member ``b`` in row ``i B + b``.
        blocks : list of SlotJacobian
            Per batch, its joints' Jacobians on ``[q_slots; y_j]`` by slot groups, members
            in the rows of ``slots``.
        r_y : (B, m)
            The joints' residuals, joint after joint (batch after batch).

        Returns
        -------
        The increments on the free dofs (B, n_free) and on ``y`` (B, m), and which members'
        small systems are regular (the increments of the others are not to be used).
        """
        B, m, n = len(r_free), r_y.shape[1], self.n_free
        self._inverse()
        layout = _Layout(slots, blocks, B)
        if not self._dense:
            self._columns(layout.force_dofs)
        r_free = np.ascontiguousarray(r_free, dtype=float)
        force, z, regular = condensed_step(
            Columns(self._store, self._slot, self.phi),
            self.solve(r_free),
            r_free,
            np.ascontiguousarray(r_y, dtype=float),
            layout.jacobians,
            SINGULAR_RCOND,
        )
        dq = -self.solve(force)[:, :n] + z[:, layout.nc + m :] @ self.phi.T
        return dq, z[:, layout.nc : layout.nc + m], regular


class _Layout:
    """The joints of a condensed step laid out for :func:`sliders.solve.condensed_kernel.
    condensed_step`: every batch's slot positions (int64), Jacobian values and tables
    flattened one batch after the other, per batch its sizes and offsets (``batches``), the
    index of each structure slot among the joint's ``c`` slots (the columns the force
    Jacobian reads: the structure groups with a block in a structure row; -1 for the
    others), the ``c`` slots of a member (``nc``) and the free dofs that carry forces
    (``force_dofs``: the held slots of the structure groups with a block)."""

    def __init__(self, slots: list[np.ndarray], blocks: list[SlotJacobian], B: int) -> None:
        rows, c_of = [], []
        at = np.zeros(4, dtype=np.int64)
        self.nc = 0
        self._forces = []
        for p, J in zip(slots, blocks, strict=True):
            k, t = len(p) // B, p.shape[1]
            c, forces, index = J.coupling()
            c_of.append(index)
            self._forces.append((p, forces))
            rows.append(
                [
                    k,
                    t,
                    J.n - t,
                    J.values.shape[1],
                    at[0],
                    at[1],
                    at[2],
                    at[2] + len(J.table),
                    at[3],
                    len(c),
                ]
            )
            at += [p.size, J.values.size, len(J.table), t]
            self.nc += k * len(c)
        self.batches = np.array(rows, dtype=np.int64)
        self.slots = _flat([p.astype(np.int64, copy=False) for p in slots])
        self.values = _flat([J.values for J in blocks])
        self.tables = np.ascontiguousarray(np.concatenate([J.table for J in blocks]))
        self.c_of = np.concatenate(c_of)

    @property
    def jacobians(self) -> Jacobians:
        """The layout as the compiled step reads it
        (:class:`sliders.solve.condensed_kernel.Jacobians`)."""
        return Jacobians(self.slots, self.values, self.tables, self.c_of, self.batches, self.nc)

    @property
    def force_dofs(self) -> np.ndarray:
        """The free dofs that carry forces: the held slots of the structure groups with a
        block."""
        held = np.concatenate([p[:, f].ravel() for p, f in self._forces])
        return held[held >= 0]


def _flat(arrays: list[np.ndarray]) -> np.ndarray:
    """The arrays raveled one after the other, C-contiguous (a view of a single contiguous
    array)."""
    if len(arrays) == 1:
        return np.ascontiguousarray(arrays[0]).ravel()
    return np.concatenate([a.ravel() for a in arrays])
