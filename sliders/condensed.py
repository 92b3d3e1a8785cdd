"""Condensed Newton step for sliders on linear beams: factorise ``K`` once, solve small systems.

The beams are linear, so their stiffness ``K`` (free dofs) is constant, and the sliders touch
only a few dofs.  ``K`` may be singular: a part held only by sliders (the piston of the
sliding-beams setup) keeps the rigid motions its supports leave free.  Their basis ``Phi``
(:func:`rigid_modes`) spans both null spaces of ``K``: ``K Phi = 0`` (a rigid motion does not
strain) and ``Phi^T K = 0`` (a rigid virtual motion does no internal work; the fv regions and
the Galerkin shape functions both reproduce rigid motions).  The bordered operator

    B = [K, s Phi; s Phi^T, 0]          (s = max |K|, to balance the pivots)

is then regular and is factorised once per structure and support set.  ``B^{-1}[b; 0] =
[x; z]`` gives ``K x = b - s Phi z`` with ``Phi^T x = 0`` and ``z = 0`` exactly when ``b`` is
self-equilibrated on every free part (``Phi^T b = 0``).

The joints give their residuals and Jacobians on *slots* (:meth:`sliders.joint.SliderBatch.
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

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import connected_components

from fvbeam.statics import Structure
from sliders.slots import SlotJacobian

#: A small system whose row- and column-equilibrated reciprocal condition number (1-norm)
#: falls below this is singular: the threshold of the bordered diagnostic
#: (:meth:`sliders.statics.SliderStatics._singular`).
SINGULAR_RCOND = 1e-12

#: Up to this size (free dofs and rigid modes) every column of ``B^{-1}`` is computed at
#: once (at most 72 MB) and the solves are dense products: on the sliding-beams operator
#: (128 unknowns, 96 right-hand sides, one BLAS thread) SuperLU's triangular solves take
#: 0.5 ms, the dense product 0.24 ms.
DENSE_LIMIT = 3000


def node_positions(structure: Structure) -> np.ndarray:
    """Reference position of every structure node, beam nodes and rigid bodies,
    ``(n_nodes, 3)``."""
    x = np.zeros((structure.n_nodes, 3))
    for beam, dofs in zip(structure.beams, structure.dof_maps):
        x[dofs[::6] // 6] = beam.mesh.points
    for body in structure.bodies:
        x[structure.node_dofs(body.name)[0] // 6] = body.position
    return x


def rigid_modes(structure: Structure, K: sp.spmatrix, free: np.ndarray) -> np.ndarray:
    """Orthonormal basis ``(len(free), k)`` of the rigid motions the supports leave free.

    Every connected part of the structure (connected through the pattern of its global
    stiffness ``K``) moves rigidly
    with a translation and a rotation about its centroid (``u = t + w x (x - x_0)``,
    ``theta = w``, rotations scaled by the part's size); the combinations that vanish on the
    supported dofs are kept.
    """
    coo = K.tocoo()
    graph = sp.coo_matrix((np.ones(coo.nnz), (coo.row // 6, coo.col // 6)),
                          shape=(structure.n_nodes, structure.n_nodes))
    n_parts, part = connected_components(graph, directed=False)
    x = node_positions(structure)
    modes = np.zeros((structure.n_dofs, 6 * n_parts))
    for p in range(n_parts):
        nodes = np.flatnonzero(part == p)
        lever = x[nodes] - x[nodes].mean(axis=0)
        size = max(float(np.linalg.norm(lever, axis=1).max()), 1e-300)
        for i in range(3):
            e = np.eye(3)[i]
            modes[6 * nodes[:, None] + np.arange(3), 6 * p + i] = e
            modes[6 * nodes[:, None] + np.arange(3), 6 * p + 3 + i] = np.cross(e, lever) / size
            modes[6 * nodes + 3 + i, 6 * p + 3 + i] = 1.0 / size
    fixed = np.setdiff1d(np.arange(structure.n_dofs), free)
    combos = la.null_space(modes[fixed]) if fixed.size else np.eye(modes.shape[1])
    if combos.shape[1] == 0:
        return np.zeros((len(free), 0))
    return np.linalg.qr(modes[free] @ combos)[0]


def unresisted(phi: np.ndarray, K_free: sp.spmatrix) -> np.ndarray:
    """The combinations of the rigid motions ``phi`` that ``K_free`` does not resist
    (``|K_free phi a| <= 1e-8 max|K_free|`` for unit ``a``).  A stiffness keeps them all; the
    time integrator's operator ``M + c K`` (:mod:`sliders.dynamics`) keeps only those of the
    massless parts (a massless body held by its sliders alone)."""
    if phi.shape[1] == 0:
        return phi
    _, sigma, Vt = np.linalg.svd(K_free @ phi, full_matrices=True)
    sigma = np.concatenate([sigma, np.zeros(phi.shape[1] - len(sigma))])
    return phi @ Vt[sigma <= 1e-8 * abs(K_free).max()].T


class CondensedOperator:
    """``B`` factorised once, with the columns of ``B^{-1}`` cached per free dof; ``K`` is
    the structure's global stiffness, ``free`` its unsupported dofs.

    Raises ``ValueError`` when ``B`` is singular: the supports leave a mechanism that is not
    a rigid motion of a part (use the bordered back end, which lets the sliders hold it).
    """

    def __init__(self, structure: Structure, K: sp.spmatrix, free: np.ndarray) -> None:
        K_free = sp.csr_matrix(K)[free][:, free]
        self.phi = unresisted(rigid_modes(structure, K, free), K_free)
        self.n_free, self.n_rigid = len(free), self.phi.shape[1]
        scale = np.abs(K_free).max()
        B = sp.bmat([[K_free, scale * sp.csr_matrix(self.phi)],
                     [scale * sp.csr_matrix(self.phi.T), None]], format="csc")
        message = ("the stiffness without the free parts' rigid motions is singular: the "
                   "supports leave a mechanism; solve with method='bordered'")
        try:
            self.lu = spla.splu(B)
        except RuntimeError as exc:
            raise ValueError(message) from exc
        pivots = np.abs(self.lu.U.diagonal())
        if pivots.min() <= 1e-13 * pivots.max():
            raise ValueError(message)
        self._slot = np.full(self.n_free, -1)
        self._store = np.zeros((self.n_free + self.n_rigid, 0))
        self._inverse_T = None
        if self.n_free + self.n_rigid <= DENSE_LIMIT:
            self._columns(np.arange(self.n_free))
            self._inverse_T = np.ascontiguousarray(self._store.T)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``B^{-1} [b; 0]`` for right-hand sides ``b`` (B, n_free) on the free dofs:
        (B, n_free + k); from the dense inverse below :data:`DENSE_LIMIT` (its columns
        computed in order at construction)."""
        if self._inverse_T is not None:
            return b @ self._inverse_T
        rhs = np.concatenate([b, np.zeros((len(b), self.n_rigid))], axis=1)
        return self.lu.solve(np.asfortranarray(rhs.T)).T  # SuperLU reads columns

    def _columns(self, positions: np.ndarray) -> np.ndarray:
        """Store slots of the columns ``B^{-1}[U; 0]`` for the free dofs at ``positions``;
        each column is computed once and kept."""
        slots = self._slot[positions]
        if slots.min(initial=0) >= 0:
            return slots
        missing = np.unique(positions[slots < 0])
        unit = np.zeros((self.n_free + self.n_rigid, missing.size), order="F")
        unit[missing, np.arange(missing.size)] = 1.0
        self._slot[missing] = self._store.shape[1] + np.arange(missing.size)
        self._store = np.hstack([self._store, self.lu.solve(unit)])
        return self._slot[positions]

    def _read(self, rows: np.ndarray, columns: np.ndarray, F: np.ndarray) -> np.ndarray:
        """``Y = B^{-1}[rows, columns] F`` per member (``rows`` (B, r) free-dof positions,
        ``columns`` (B, f) store slots, ``F`` (B, f, p)): the block of ``B^{-1}`` is gathered
        once per distinct pair of index rows (the members of a sweep share a few elements, so
        a few patterns) and multiplies all members that have it."""
        patterns, groups = _patterns(np.concatenate([rows, columns], axis=1))
        r = rows.shape[1]
        if len(patterns) == 1:
            return self._store[patterns[0, :r, None], patterns[0, None, r:]] @ F
        Y = np.empty((len(F), r, F.shape[2]))
        for key, members in zip(patterns, groups):
            Y[members] = self._store[key[:r, None], key[None, r:]] @ F[members]
        return Y

    def step(self, r_free: np.ndarray, slots: list[np.ndarray], blocks: list[SlotJacobian],
             r_y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Newton increments of ``B`` members sharing this operator (module docstring).

        Parameters
        ----------
        r_free : (B, n_free)
            The structure residuals.
        slots : list of (k B, t_j)
            Per batch of ``k`` alike joints (:meth:`sliders.joint.SliderBatch.joined`; one
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
        B, m, k, n = len(r_free), r_y.shape[1], self.n_rigid, self.n_free
        parts = [part for p, J in zip(slots, blocks) for part in _joint_parts(p, J, B)]
        nc = sum(len(p.c) for p in parts)
        nf, nr = sum(len(p.forces) for p in parts), sum(len(p.reads) for p in parts)
        F, C, D = np.zeros((B, nf, nc + m)), np.zeros((B, m, nr)), np.zeros((B, m, m))
        at_f = at_c = at_r = at_y = 0
        for p in parts:
            f, c, r, y = len(p.forces), len(p.c), len(p.reads), p.D.shape[1]
            F[:, at_f:at_f + f, at_c:at_c + c] = p.E
            F[:, at_f:at_f + f, nc + at_y:nc + at_y + y] = p.A
            C[:, at_y:at_y + y, at_r:at_r + r] = p.C
            D[:, at_y:at_y + y, at_y:at_y + y] = p.D
            at_f, at_c, at_r, at_y = at_f + f, at_c + c, at_r + r, at_y + y
        force_at = np.concatenate([p.at[:, p.forces] for p in parts], axis=1)
        read_at = np.concatenate([p.at[:, p.reads] for p in parts], axis=1)
        c_at = np.concatenate([p.at[:, p.c] for p in parts], axis=1)
        in_c = np.concatenate([o + np.searchsorted(p.reads, p.c) for o, p in
                               zip(np.cumsum([0] + [len(p.reads) for p in parts]), parts)])
        columns = self._columns(force_at)
        Y = self._read(read_at, columns, F)
        Y_z = np.moveaxis(self._store[n:][:, columns], 0, 1) @ F
        base = self.solve(r_free)
        rows = np.arange(B)[:, None]
        phi = self.phi[read_at]
        small = np.zeros((B, nc + k + m, nc + m + k))
        small[:, :nc, :nc + m] = Y[:, in_c]
        small[:, np.arange(nc), np.arange(nc)] += 1.0
        small[:, :nc, nc + m:] = -phi[:, in_c]
        small[:, nc:nc + k, :nc + m] = Y_z
        small[:, nc + k:, :nc + m] = -C @ Y
        small[:, nc + k:, nc:nc + m] += D
        small[:, nc + k:, nc + m:] = C @ phi
        rhs = np.concatenate([-base[rows, c_at], -base[:, n:],
                              -r_y + np.einsum("bij,bj->bi", C, base[rows, read_at])], axis=1)
        z, regular = _equilibrated_solve(small, rhs)
        force = r_free.copy()
        np.add.at(force, (rows, force_at), np.einsum("bij,bj->bi", F, z[:, :nc + m]))
        dq = -self.solve(force)[:, :n] + z[:, nc + m:] @ self.phi.T
        return dq, z[:, nc:nc + m], regular


@dataclass(frozen=True)
class _JointPart:
    """One joint's share of a condensed step: its slots' free-dof positions ``at`` (B, t;
    supported ones read as 0, their entries zeroed), the slots that carry forces, the slots
    ``c`` whose displacements the force Jacobian reads, the slots the joint equations read
    (``reads``, containing ``c``), and its Jacobian blocks on them: ``E`` (forces x c), ``A``
    (forces x y), ``C`` (y x reads) and ``D`` (y x y)."""

    at: np.ndarray
    forces: np.ndarray
    c: np.ndarray
    reads: np.ndarray
    E: np.ndarray
    A: np.ndarray
    C: np.ndarray
    D: np.ndarray


def _joint_part(slots: np.ndarray, J: SlotJacobian) -> _JointPart:
    """The compact blocks of a joint's Jacobian ``J`` on its slots ``slots`` (B, t), the
    supported slots (-1) removed (:class:`_JointPart`): the pattern is that of the blocks
    the joint writes (:class:`sliders.slots.SlotJacobian`)."""
    held = slots >= 0
    forces_of = J.written_rows(J.structure)
    c_of = J.read(J.structure, J.structure)
    read = set(J.read(J.unknowns, J.structure) + c_of)
    reads_of = [g for g in J.structure if g in read]
    forces, c, reads = J.slots(forces_of), J.slots(c_of), J.slots(reads_of)
    rows = held[:, forces, None]
    return _JointPart(np.maximum(slots, 0), forces, c, reads,
                      J.gather(forces_of, c_of) * rows * held[:, None, c],
                      J.gather(forces_of, J.unknowns) * rows,
                      J.gather(J.unknowns, reads_of) * held[:, None, reads],
                      J.gather(J.unknowns, J.unknowns))


def _joint_parts(slots: np.ndarray, J: SlotJacobian, B: int) -> list[_JointPart]:
    """:func:`_joint_part` of a batch of ``k`` alike joints of ``B`` members (``slots``
    (k B, t), joint ``i`` of member ``b`` in row ``i B + b``), computed once and split
    per joint."""
    whole = _joint_part(slots, J)
    if len(slots) == B:
        return [whole]
    return [_JointPart(whole.at[rows], whole.forces, whole.c, whole.reads, whole.E[rows],
                       whole.A[rows], whole.C[rows], whole.D[rows])
            for rows in (slice(i * B, (i + 1) * B) for i in range(len(slots) // B))]


def _patterns(keys: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """The distinct rows of the non-negative integer array ``keys`` (B, w), in the order of
    their hashes, and the indices of the rows holding each (increasing): a stable sort of a
    polynomial hash of the rows (wrapping in 64 bits; its base odd, so that no power of it
    wraps to 0 and every column counts), checked; the exact sort of the rows
    (``np.unique(keys, axis=0)``) taken only if two distinct rows share a hash."""
    base = np.int64((keys.max(initial=0) + 1) | 1)
    hashes = keys @ np.cumprod(np.full(keys.shape[1], base, dtype=np.int64))
    order = np.argsort(hashes, kind="stable")
    ordered = hashes[order]
    starts = np.flatnonzero(np.concatenate([[True], ordered[1:] != ordered[:-1]]))
    groups = np.split(order, starts[1:])
    patterns = keys[order[starts]]
    if np.array_equal(np.repeat(patterns, np.diff(np.append(starts, len(keys))), axis=0),
                      keys[order]):
        return patterns, groups
    patterns, which = np.unique(keys, axis=0, return_inverse=True)
    which = which.ravel()
    order = np.argsort(which, kind="stable")
    return patterns, np.split(order, np.cumsum(np.bincount(which, minlength=len(patterns)))[:-1])


def _equilibrated_solve(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solutions of the stacked systems ``A x = b`` (B, n, n) after scaling their rows and
    columns to unit largest entries, and which are regular: reciprocal condition number
    (1-norm, of the scaled matrix) at least :data:`SINGULAR_RCOND`."""
    magnitude = np.abs(A)  # scaled alongside A: |a / s| is |a| / s, exactly
    rows = magnitude.max(axis=2).clip(1e-300)
    magnitude /= rows[:, :, None]
    cols = magnitude.max(axis=1).clip(1e-300)
    magnitude /= cols[:, None, :]
    A = A / rows[:, :, None] / cols[:, None, :]
    try:
        inverse = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        inverse = np.stack([_inverse_or_nan(a) for a in A])
    norm = magnitude.sum(axis=1).max(axis=1) * np.abs(inverse).sum(axis=1).max(axis=1)
    regular = 1.0 / norm >= SINGULAR_RCOND
    x = np.einsum("bij,bj->bi", inverse, b / rows) / cols
    return np.where(regular[:, None], x, 0.0), regular


def _inverse_or_nan(A: np.ndarray) -> np.ndarray:
    """``A^{-1}``, or NaN where ``A`` is exactly singular."""
    try:
        return np.linalg.inv(A)
    except np.linalg.LinAlgError:
        return np.full_like(A, np.nan)
