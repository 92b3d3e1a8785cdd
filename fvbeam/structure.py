"""Structures: beams and rigid bodies joined at shared nodes into one set of global dofs."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.geometry import wrench
from fvbeam.support import DOF_NAMES, NodeRef, Support


class Structure:
    """Beams and rigid bodies joined at shared nodes into one set of global dofs.

    Global nodes are numbered beam nodes first (in beam order) and then the bodies, each node
    with the six dofs ``ux uy uz rx ry rz``; tied nodes share one number.  Bodies add no
    stiffness: their rows stay zero unless they are tied, supported or held by a joint.

    Parameters
    ----------
    beams
        The beams, each with its own dofs.
    ties
        Pairs of nodes that become one node (same dofs): ``(ref_a, ref_b)`` with each ref
        ``(beam, node)`` or a body name, or the form ``(beam_a, node_a, beam_b, node_b)``
        (a body there as ``(..., "hub", None)``).  A tie involving a body must join
        coincident points (to 1e-9 of the structure's size): merging the dofs of points
        apart would not be a rigid joint.
    bodies
        :class:`~fvbeam.body.RigidBody` nodes, with unique names.
    """

    def __init__(
        self, beams: Sequence[Beam], ties: Sequence[tuple] = (), bodies: Sequence[RigidBody] = ()
    ) -> None:
        self.beams, self.bodies = list(beams), list(bodies)
        if not self.beams and not self.bodies:
            raise ValueError("a structure needs at least one beam or body")
        for i, body in enumerate(self.bodies):
            if not isinstance(body, RigidBody):
                raise ValueError(f"bodies[{i}] must be a RigidBody, got {type(body).__name__}")
        names = [body.name for body in self.bodies]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ValueError(f"rigid body names must be unique, repeated: {', '.join(repeated)}")
        self._body_index = {name: i for i, name in enumerate(names)}
        self._offsets = np.cumsum([0] + [b.mesh.n_nodes for b in self.beams])
        n_slots = self._offsets[-1] + len(self.bodies)
        parent = np.arange(n_slots)

        def root(k: int) -> int:
            while parent[k] != k:
                k = parent[k]
            return k

        for tie in ties:
            a, b = self._tie_ends(tie)
            ka, kb = self._slot(a), self._slot(b)
            if isinstance(a, str) or isinstance(b, str):
                self._check_coincident(tie, a, b)
            parent[max(root(ka), root(kb))] = min(root(ka), root(kb))
        roots = np.array([root(k) for k in range(n_slots)])
        _, self._node_number = np.unique(roots, return_inverse=True)
        self.n_nodes = int(self._node_number.max()) + 1
        self.dof_maps = [
            (
                6 * self._node_number[self._offsets[i] : self._offsets[i + 1], None] + np.arange(6)
            ).ravel()
            for i in range(len(self.beams))
        ]

    @staticmethod
    def _tie_ends(tie: tuple) -> tuple[NodeRef, NodeRef]:
        """The two node references of a tie in either accepted form."""
        if isinstance(tie, (tuple, list)) and len(tie) == 2:
            return tie[0], tie[1]
        if isinstance(tie, (tuple, list)) and len(tie) == 4:
            a, b = (
                x if isinstance(x, str) and n is None else (x, n) for x, n in (tie[:2], tie[2:])
            )
            return a, b
        raise ValueError(
            f"tie {tie!r} must be (ref_a, ref_b), each (beam, node) or a body "
            "name, or (beam_a, node_a, beam_b, node_b)"
        )

    def _slot(self, ref: NodeRef) -> int:
        """Index of a node reference before ties are merged (beam nodes, then bodies)."""
        if isinstance(ref, str):
            return int(self._offsets[-1]) + self.body_index(ref)
        if isinstance(ref, (tuple, list)) and len(ref) == 2:
            beam = self.beam_index(ref[0])
            return int(self._offsets[beam]) + self.beams[beam].node_index(ref[1])
        raise ValueError(f"node reference {ref!r} must be (beam, node) or a body name")

    def _check_coincident(self, tie: tuple, a: NodeRef, b: NodeRef) -> None:
        points = np.vstack(
            [beam.mesh.points for beam in self.beams] + [body.position for body in self.bodies]
        )
        size = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
        gap = np.linalg.norm(self.node_position(a) - self.node_position(b))
        if gap > 1e-9 * size:
            raise ValueError(
                f"tie {tie!r}: the nodes are {gap:.6g} apart; a tie merges their "
                "dofs, which joins a body rigidly only at a coincident point "
                "(place the body there, or use a slider's offset)"
            )

    def beam_index(self, i: int) -> int:
        if not (isinstance(i, (int, np.integer)) and 0 <= i < len(self.beams)):
            raise ValueError(
                f"beam {i!r} does not exist (the structure has {len(self.beams)} beams)"
            )
        return int(i)

    def body_index(self, name: str) -> int:
        """Position of the body named ``name`` in :attr:`bodies`."""
        if name not in self._body_index:
            known = ", ".join(repr(n) for n in self._body_index) or "none"
            raise ValueError(f"no rigid body named {name!r} (the structure's bodies: {known})")
        return self._body_index[name]

    def node_dofs(self, ref: NodeRef) -> np.ndarray:
        """The six global dofs ``ux uy uz rx ry rz`` of a node: ``(beam, node)`` (node: index,
        ``'start'`` or ``'end'``) or a body name."""
        return 6 * int(self._node_number[self._slot(ref)]) + np.arange(6)

    def node_position(self, ref: NodeRef) -> np.ndarray:
        """Reference position of a node: ``(beam, node)`` or a body name."""
        slot = self._slot(ref)
        if isinstance(ref, str):
            return self.bodies[slot - int(self._offsets[-1])].position.copy()
        beam = self.beams[ref[0]]
        return beam.mesh.points[beam.node_index(ref[1])].copy()

    def dof_name(self, dof: int) -> str:
        """A global dof by name, e.g. ``beam 0 node 3 uy`` or ``body 'hub' rx`` (the first
        beam node or body holding it)."""
        node, c = divmod(int(dof), 6)
        slots = np.flatnonzero(self._node_number == node)
        if not slots.size:
            return f"dof {dof}"
        slot = int(slots[0])
        if slot >= self._offsets[-1]:
            return f"body {self.bodies[slot - int(self._offsets[-1])].name!r} {DOF_NAMES[c]}"
        beam = int(np.searchsorted(self._offsets, slot, side="right")) - 1
        return f"beam {beam} node {slot - int(self._offsets[beam])} {DOF_NAMES[c]}"

    @property
    def n_dofs(self) -> int:
        return 6 * self.n_nodes

    @classmethod
    def from_shared_points(
        cls, beams: Sequence[Beam], bodies: Sequence[RigidBody] = ()
    ) -> "Structure":
        """Beams read together (:func:`fvbeam.mesh.read_beams`), joined where they share a
        mesh point (equal ``point_ids``), and the rigid ``bodies`` (tied to nothing)."""
        first: dict[int, tuple[int, int]] = {}
        ties = []
        for b, beam in enumerate(beams):
            ids = beam.mesh.point_ids
            assert ids is not None  # BeamMesh.__post_init__ numbers the nodes when not given
            for node, pid in enumerate(ids.tolist()):
                if pid in first:
                    ties.append(first[pid] + (b, node))
                else:
                    first[pid] = (b, node)
        return cls(beams, ties, bodies)

    def nodal_load(
        self, ref: NodeRef, force: ArrayLike = (0.0, 0.0, 0.0), moment: ArrayLike = (0.0, 0.0, 0.0)
    ) -> np.ndarray:
        """Global load vector of a force and couple applied to a node (``(beam, node)`` or a
        body name)."""
        f = np.zeros(self.n_dofs)
        f[self.node_dofs(ref)] = wrench(force, moment)
        return f

    def residual(self, q: np.ndarray) -> np.ndarray:
        """Internal force vector: the beams' residuals gathered on the global dofs."""
        r = np.zeros(self.n_dofs)
        for beam, dofs in zip(self.beams, self.dof_maps, strict=True):
            np.add.at(r, dofs, beam.residual(q[dofs]))
        return r

    def tangent(self, q: np.ndarray) -> sp.csr_matrix:
        """Global tangent: the beams' tangents scattered on the global dofs."""
        return self._scatter(
            [beam.tangent(q[dofs]) for beam, dofs in zip(self.beams, self.dof_maps, strict=True)]
        )

    def mass(self, kind: str = "lumped") -> sp.csr_matrix:
        """Global mass: the beams' mass matrices (:meth:`Beam.mass`, ``kind`` ``lumped`` or
        ``consistent``) on the global dofs, plus each rigid body's 6x6 mass matrix on its
        node (:meth:`~fvbeam.body.RigidBody.mass_matrix`: a centre of mass off the node
        couples translations and rotations)."""
        M = self._scatter([beam.mass(kind) for beam in self.beams]).tolil()
        for body in self.bodies:
            dofs = self.node_dofs(body.name)
            M[dofs[:, None], dofs] += body.mass_matrix()
        return M.tocsr()

    def _scatter(self, matrices: Sequence[sp.spmatrix]) -> sp.csr_matrix:
        """The beams' matrices, one per beam on its own dofs, summed on the global dofs."""
        rows, cols, vals = [np.zeros(0, dtype=int)], [np.zeros(0, dtype=int)], [np.zeros(0)]
        for A, dofs in zip(matrices, self.dof_maps, strict=True):
            A = A.tocoo()
            rows.append(dofs[A.row])
            cols.append(dofs[A.col])
            vals.append(A.data)
        return sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.n_dofs, self.n_dofs),
        )

    def gather(self, beam: int, f_local: np.ndarray) -> np.ndarray:
        """A beam's load vector as a global one."""
        f = np.zeros(self.n_dofs)
        np.add.at(f, self.dof_maps[self.beam_index(beam)], f_local)
        return f

    def local(self, beam: int, q: np.ndarray) -> np.ndarray:
        """A beam's share of a global dof vector."""
        return q[self.dof_maps[self.beam_index(beam)]]

    def support_dofs(self, supports: Sequence[Support]) -> np.ndarray:
        """Global dofs held by ``supports``."""
        fixed = [self.node_dofs(s.ref)[s.dofs()] for s in supports]
        return np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, dtype=int)
