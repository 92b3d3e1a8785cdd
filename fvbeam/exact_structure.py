"""Geometrically exact structures: the exact beams and rigid bodies of a
:class:`~fvbeam.structure.Structure` on its global node numbering.

Each beam of the structure becomes an :class:`~fvbeam.exact_beam.ExactBeam`; tied nodes
are one global node, with one position ``x`` and one rotation ``R`` (a rigid joint of the
beams' sections, as a tie is in the linear structure), updated on the manifold per global
node, ``x <- x + du``, ``R <- exp(dphi) R`` (:meth:`fvbeam.exact_beam.ExactState.updated`
on the global state).  The residual, its round-off floor and the tangent are the beams'
gathered on the global dofs (:attr:`fvbeam.structure.Structure.dof_maps`), so an
:class:`ExactStructure` is an operator :func:`fvbeam.exact_statics.solve_static` solves,
as one beam is.

Rigid bodies are nodes with finite rotations (:class:`~fvbeam.exact_bodies.ExactBodies`):
their rows are zero (a body has no internal forces; its loads and the joints holding it,
:mod:`sliders.joints.exact_model`, balance it), a body tied to a beam node is that node
(the linear structure has checked that they coincide).  A tie of two beam nodes apart is
refused: the linear structure merges their dofs, which at finite rotation would not be a
rigid joint.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from fvbeam import rotations
from fvbeam.beam import InternalForces
from fvbeam.exact_beam import ExactBeam, ExactState, PointState
from fvbeam.exact_bodies import ExactBodies
from fvbeam.structure import Structure, on_dofs

#: Largest distance between tied beam nodes, relative to the structure's size (the linear
#: structure's own test for a tie joining a body, :class:`fvbeam.structure.Structure`).
TIE_GAP = 1e-9


class ExactStructure:
    """The exact beams of ``structure`` on its global dofs (module docstring).

    Parameters
    ----------
    structure
        Beams, ties and rigid bodies.

    Attributes
    ----------
    beams
        The :class:`~fvbeam.exact_beam.ExactBeam` of each beam, in the structure's order.
    node_maps
        Each beam's global node numbers, one per mesh node.
    bodies
        The rigid bodies as nodes with finite rotations, at the global nodes
        :attr:`body_nodes`.
    """

    def __init__(self, structure: Structure) -> None:
        self.structure = structure
        self.beams = [ExactBeam(beam) for beam in structure.beams]
        self.node_maps = [dofs[::6] // 6 for dofs in structure.dof_maps]
        self.n_dofs = structure.n_dofs
        #: No multipliers (:class:`~fvbeam.exact_statics.StaticOperator`).
        self.position_multipliers = np.zeros(0, dtype=np.int64)
        self._X = np.zeros((structure.n_nodes, 3))
        for beam, nodes in zip(structure.beams, self.node_maps, strict=True):
            self._X[nodes] = beam.mesh.points
        self.bodies = ExactBodies(structure.bodies)
        self.body_nodes = np.array(
            [structure.node_dofs(body.name)[0] // 6 for body in structure.bodies], dtype=np.int64
        )
        self._X[self.body_nodes] = self.bodies.reference().x
        self._check_ties()

    @property
    def name(self) -> str:
        """The beams' names, in messages."""
        return ", ".join(beam.beam.mesh.name for beam in self.beams)

    def _check_ties(self) -> None:
        """``ValueError`` naming a tie of two beam nodes apart."""
        points = self.structure.slot_points()
        size = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
        for beam, nodes in zip(self.structure.beams, self.node_maps, strict=True):
            gap = np.linalg.norm(beam.mesh.points - self._X[nodes], axis=1)
            k = int(np.argmax(gap))
            if gap[k] > TIE_GAP * size:
                ends = {beam.node_index(end): end for end in ("start", "end")}
                node = f"{beam.mesh.name}.{ends.get(k, k)}"
                raise ValueError(
                    f"node {node!r} is tied to a node {gap[k]:.6g} away: "
                    "exact kinematics joins tied beam nodes only where they coincide"
                )

    def reference(self) -> ExactState:
        """The reference configuration: the meshes' nodes, identity rotations."""
        n = len(self._X)
        return ExactState(self._X.copy(), np.broadcast_to(np.eye(3), (n, 3, 3)))

    def local(self, state: ExactState, beam: int) -> ExactState:
        """Beam ``beam``'s (index) share of a global state."""
        nodes = self.node_maps[beam]
        return ExactState(state.x[nodes], state.R[nodes])

    def points(self, state: ExactState) -> list[PointState]:
        """Each beam's strains and stresses at its evaluation points
        (:meth:`fvbeam.exact_beam.ExactBeam.points`)."""
        return [beam.points(self.local(state, i)) for i, beam in enumerate(self.beams)]

    def _gathered(
        self, state: ExactState, pts: Sequence[PointState] | None, which: str
    ) -> np.ndarray:
        """The beams' vectors ``which`` (``residual`` or ``residual_floor``) summed on the
        global dofs."""
        pts = self.points(state) if pts is None else pts
        out = np.zeros(self.n_dofs)
        for i, (beam, dofs) in enumerate(zip(self.beams, self.structure.dof_maps, strict=True)):
            out += np.bincount(
                dofs, getattr(beam, which)(self.local(state, i), pts[i]), minlength=self.n_dofs
            )
        return out

    def residual(self, state: ExactState, pts: Sequence[PointState] | None = None) -> np.ndarray:
        """Internal force vector ``r(q)`` on the global dofs (6 per node): the beams'
        :meth:`~fvbeam.exact_beam.ExactBeam.residual` gathered."""
        return self._gathered(state, pts, "residual")

    def residual_floor(
        self, state: ExactState, pts: Sequence[PointState] | None = None
    ) -> np.ndarray:
        """The residual's rounding bound on the global dofs: the beams'
        :meth:`~fvbeam.exact_beam.ExactBeam.residual_floor` summed (a tied dof sums the
        terms of every beam at it)."""
        return self._gathered(state, pts, "residual_floor")

    def tangent(
        self,
        state: ExactState,
        pts: Sequence[PointState] | None = None,
        keep: np.ndarray | None = None,
    ) -> sp.csc_matrix:
        """``d r / d q`` on the global dofs (the beams' tangents scattered); with ``keep``
        (sorted dofs) its rows and columns on those dofs only."""
        pts = self.points(state) if pts is None else pts
        K = sp.csr_matrix((self.n_dofs, self.n_dofs))
        for i, (beam, dofs) in enumerate(zip(self.beams, self.structure.dof_maps, strict=True)):
            K = K + on_dofs(beam.tangent(self.local(state, i), pts[i]), dofs, self.n_dofs)
        if keep is not None:
            K = K[keep][:, keep]
        return sp.csc_matrix(K)

    def mass(self, state: ExactState, kind: str = "lumped") -> sp.csr_matrix:
        """The structure's mass about ``state`` on the global dofs, in the spatial increments
        of the tangent (``[du, dphi]``): the linear structure's mass
        (:meth:`fvbeam.structure.Structure.mass`) with each node's rotation blocks turned by
        its rotation, ``M_ab -> T_a M_ab T_b^T``, ``T_a = diag(I, R_a)``.

        About a state at rest the linearised inertia is ``m du'' `` on the translations (the
        mass per reference length, which no motion changes) and ``R J_0 R^T dphi''`` on the
        spatial rotation increments (the current section's inertia; no gyroscopic term at
        zero angular velocity).  The lumped mass carries each node's region inertia at its
        node (no translation-rotation coupling, :mod:`fvbeam.mass`), so turning its blocks
        by the node's ``R`` is exact; the consistent mass's coupling of two nodes is turned
        by their two rotations, exact to first order in their difference, ``O(h)``.  A rigid
        body's mass turns whole, its translations with its rotation
        (:meth:`~fvbeam.exact_bodies.ExactBodies.mass`: exact off its centre of mass).
        """
        M = self.structure.mass(kind).tocsr()
        n = self.structure.n_nodes
        T = np.zeros((n, 6, 6))
        T[:, :3, :3] = np.eye(3)
        T[:, 3:, 3:] = state.R
        T_sparse = sp.bsr_matrix((T, np.arange(n), np.arange(n + 1)), shape=(6 * n, 6 * n))
        turned = sp.csr_matrix(T_sparse @ M @ T_sparse.T)
        if not self.structure.bodies:
            return turned
        # a body's centre off its node couples its translations: its whole mass turns
        # (:meth:`~fvbeam.exact_bodies.ExactBodies.mass`), not its rotation block alone
        nodes = self.body_nodes
        M0 = np.array([body.mass_matrix() for body in self.structure.bodies])
        change = self.bodies.mass(ExactState(state.x[nodes], state.R[nodes])) - (
            T[nodes] @ M0 @ T[nodes].transpose(0, 2, 1)
        )
        dofs = 6 * nodes[:, None] + np.arange(6)
        rows, cols = np.broadcast_arrays(dofs[:, :, None], dofs[:, None, :])
        shape = (6 * n, 6 * n)
        return sp.csr_matrix(
            turned + sp.csr_matrix((change.ravel(), (rows.ravel(), cols.ravel())), shape=shape)
        )

    def displacements(self, state: ExactState) -> np.ndarray:
        """The global dof vector of a state: each node's displacement and rotation vector
        ``log(R)`` (6 per node), the linear structure's ``[u, theta]`` to first order."""
        return np.hstack([state.x - self._X, rotations.log_map(state.R)]).ravel()

    def internal_forces(self, state: ExactState) -> list[InternalForces]:
        """Each beam's section forces at its evaluation points, in the current section frame
        and in global axes (:meth:`fvbeam.exact_beam.ExactBeam.internal_forces`)."""
        return [beam.internal_forces(self.local(state, i)) for i, beam in enumerate(self.beams)]
