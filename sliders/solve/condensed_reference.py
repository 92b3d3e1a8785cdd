"""The condensed Newton step in dense numpy and scipy: the reference of the compiled kernel.

:func:`sliders.solve.condensed_kernel.condensed_step` forms and solves the small systems of
:mod:`sliders.solve.condensed` (module docstring) member by member, reading the joints'
Jacobian entries straight from their flat blocks.  This module states the same step for one
member as the block elimination it is, with dense matrices: the Newton equations

    K dq + P g = -r_q,    g = E P^T dq + A dy,    C P^T dq + D dy = -r_y

with ``dq = x + Phi a`` (``Phi`` the free parts' rigid motions, ``K Phi = 0``,
``Phi^T x = 0``) are written as one block system in ``[x; z]`` (the unknowns of the
bordered operator ``B = [K, s Phi; s Phi^T, 0]``, factorised once; ``z = 0`` is the
self-equilibrium of the free parts), the displacements ``w_c`` of the slots the force
Jacobian reads, the joint unknowns ``dy`` and the rigid amplitudes ``a``:

    [ B    A12 ] [ [x; z]      ]   [ b1 ]
    [ A21  A22 ] [ [w_c; dy; a] ] = [ b2 ]

(:func:`small_system` gives the blocks), and ``[x; z]`` is eliminated on the cached
factorisation of ``B``: the Schur complement ``S = A22 - A21 B^{-1} A12`` is the small
system, solved after equilibrating its rows and columns (LAPACK ``dgeequ``), regular when the
exact 1-norm reciprocal condition number of the equilibrated matrix is at least the
threshold (:data:`sliders.solve.condensed.SINGULAR_RCOND`).
It is slow and is not used by the solvers: it is what the kernel is tested against
(``tests/test_condensed_kernel.py``), and where to read what the kernel computes.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.linalg as la
from scipy.linalg.lapack import dgeequ

from sliders.joints.blocks import SlotJacobian
from sliders.solve.condensed import SINGULAR_RCOND, CondensedOperator


class JointBlocks(NamedTuple):
    """One joint of one member: the free-dof position of each of its ``t`` structure slots
    (-1 where supported), its Jacobian blocks ``E`` (t, t), ``A`` (t, m), ``C`` (m, t) and
    ``D`` (m, m) on ``[q(slots); y]`` (rows: the slot forces, then its equations), and its
    ``c`` slots (the slots ``E`` reads, :meth:`sliders.joints.blocks.SlotJacobian.coupling`)."""

    slots: np.ndarray
    E: np.ndarray
    A: np.ndarray
    C: np.ndarray
    D: np.ndarray
    c: np.ndarray


class SmallSystem(NamedTuple):
    """The Schur complement ``S`` of a member (rows: ``c`` slots, rigid modes, joint
    equations; columns: ``w_c``, ``dy``, ``a``), its right-hand side, and what gives the
    structure increment back: ``B^{-1} A12`` and ``B^{-1} b1``."""

    S: np.ndarray
    rhs: np.ndarray
    solved_A12: np.ndarray
    solved_b1: np.ndarray


def member_joints(
    slots: list[np.ndarray], blocks: list[SlotJacobian], member: int, members: int
) -> list[JointBlocks]:
    """The joints of ``member`` (of ``members``), batch after batch, joint ``i`` of a batch in
    its row ``i members + member`` (the layout of
    :meth:`sliders.solve.condensed.CondensedOperator.step`), each split into its blocks."""
    joints = []
    for positions, J in zip(slots, blocks, strict=True):
        t = positions.shape[1]
        dense = J.dense()
        c = J.coupling()[0]
        for row in range(member, len(positions), members):
            M = dense[row]
            joints.append(
                JointBlocks(positions[row], M[:t, :t], M[:t, t:], M[t:, :t], M[t:, t:], c)
            )
    return joints


def injection(slots: np.ndarray, n: int) -> np.ndarray:
    """``P`` (n, t): slot ``s`` into its free dof ``slots[s]``; a supported slot (-1) into
    none."""
    P = np.zeros((n, len(slots)))
    held = np.flatnonzero(slots >= 0)
    P[slots[held], held] = 1.0
    return P


def small_system(
    operator: CondensedOperator, joints: list[JointBlocks], r_q: np.ndarray, r_y: np.ndarray
) -> SmallSystem:
    """The block system of one member (module docstring) and its Schur complement on ``B``.

    ``P_c`` injects the ``c`` slots, ``F = [E_c, A]`` gives the slot forces from
    ``u = [w_c; dy]`` (a supported slot has ``w_c = 0``: its column of ``E_c`` carries
    nothing and is dropped), ``C P^T`` the joint equations' dependence on ``dq``; with ``k``
    rigid modes ``Phi``:

        B [x; z] + [P F u; 0]          = [-r_q; 0]   (K dq + P g = -r_q, Phi^T x = 0)
        w_c - P_c^T (x + Phi a)        = 0           (w_c is dq on the c slots)
        z                              = 0           (the load is self-equilibrated)
        C P^T (x + Phi a) + D dy       = -r_y        (the joint equations)
    """
    n, k = operator.n_free, operator.n_rigid
    nc, m = sum(len(j.c) for j in joints), sum(len(j.D) for j in joints)
    PF, CP, D, Pc = np.zeros((n, nc + m)), np.zeros((m, n)), np.zeros((m, m)), np.zeros((n, nc))
    c_at = y_at = 0
    for joint in joints:
        P = injection(joint.slots, n)
        c, mj = joint.c, len(joint.D)
        held = joint.slots[c] >= 0
        Pc[:, c_at : c_at + len(c)] = P[:, c]
        PF[:, c_at : c_at + len(c)] = P @ joint.E[:, c] * held
        PF[:, nc + y_at : nc + y_at + mj] = P @ joint.A
        CP[y_at : y_at + mj] = joint.C @ P.T
        D[y_at : y_at + mj, y_at : y_at + mj] = joint.D
        c_at, y_at = c_at + len(c), y_at + mj
    phi = operator.phi
    A12 = np.zeros((n + k, nc + m + k))
    A12[:n, : nc + m] = PF
    A21 = np.block(
        [
            [-Pc.T, np.zeros((nc, k))],
            [np.zeros((k, n)), np.eye(k)],
            [CP, np.zeros((m, k))],
        ]
    )
    A22 = np.block(
        [
            [np.eye(nc), np.zeros((nc, m)), -Pc.T @ phi],
            [np.zeros((k, nc + m + k))],
            [np.zeros((m, nc)), D, CP @ phi],
        ]
    )
    b1 = np.concatenate([-r_q, np.zeros(k)])
    b2 = np.concatenate([np.zeros(nc + k), -r_y])
    solved = operator.lu.solve(np.asfortranarray(np.column_stack([A12, b1])))
    solved_A12, solved_b1 = solved[:, :-1], solved[:, -1]
    return SmallSystem(A22 - A21 @ solved_A12, b2 - A21 @ solved_b1, solved_A12, solved_b1)


def equilibrated(S: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``S`` with its rows, then its columns, scaled to unit largest entries (LAPACK
    ``dgeequ``): the row and column factors ``r``, ``c`` and ``diag(r) S diag(c)``; None
    when a row or a column is zero."""
    r, c, _, _, _, info = dgeequ(S)
    if info != 0:
        return None
    return r, c, r[:, None] * S * c


def reciprocal_condition(S: np.ndarray) -> float:
    """The exact reciprocal condition number of ``S`` in the 1-norm,
    ``1 / (|S|_1 |S^{-1}|_1)``, from its inverse; 0 when it has none."""
    try:
        inverse = np.linalg.inv(S)
    except np.linalg.LinAlgError:
        return 0.0
    return 1.0 / float(np.linalg.norm(S, 1) * np.linalg.norm(inverse, 1))


def equilibrated_solve(
    S: np.ndarray, rhs: np.ndarray, threshold: float = SINGULAR_RCOND
) -> np.ndarray | None:
    """``S^{-1} rhs``, or None when ``S`` is singular: its :func:`equilibrated` form has a
    zero row or column, or a :func:`reciprocal_condition` below ``threshold``."""
    scaling = equilibrated(S)
    if scaling is None:
        return None
    r, c, scaled = scaling
    if not reciprocal_condition(scaled) >= threshold:
        return None
    return c * la.solve(scaled, r * rhs)


def condensed_step(
    operator: CondensedOperator,
    r_free: np.ndarray,
    slots: list[np.ndarray],
    blocks: list[SlotJacobian],
    r_y: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The Newton increments of ``B`` members, as :meth:`sliders.solve.condensed.
    CondensedOperator.step` (same arguments and results: ``dq`` (B, n_free), ``dy`` (B, m)
    and which members are regular; the increments of the others, not to be used, are zero
    here), member by member: the :func:`small_system` solved (:func:`equilibrated_solve`),
    then ``[x; z] = B^{-1} (b1 - A12 [u; a])`` and ``dq = x + Phi a``."""
    B, n, m = len(r_free), operator.n_free, r_y.shape[1]
    dq, dy, regular = np.zeros((B, n)), np.zeros((B, m)), np.zeros(B, dtype=bool)
    for b in range(B):
        joints = member_joints(slots, blocks, b, B)
        system = small_system(operator, joints, r_free[b], r_y[b])
        solution = equilibrated_solve(system.S, system.rhs)
        if solution is None:
            continue
        nc = sum(len(j.c) for j in joints)
        x = (system.solved_b1 - system.solved_A12 @ solution)[:n]
        dq[b] = x + operator.phi @ solution[nc + m :]
        dy[b], regular[b] = solution[nc : nc + m], True
    return dq, dy, regular
