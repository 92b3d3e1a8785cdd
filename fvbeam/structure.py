"""Structures: beams and rigid bodies joined at shared nodes into one set of global dofs."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cached_property
from itertools import combinations

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.csgraph import reverse_cuthill_mckee

from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.copies import shallow_copy
from fvbeam.geometry import sized, wrench
from fvbeam.names import NodeRef, is_index, known, parse_node, suggest
from fvbeam.support import DOF_NAMES, Support


class Structure:
    """Beams and rigid bodies joined at shared nodes into one set of global dofs.

    Global nodes are numbered beam nodes first (in beam order) and then the bodies, each node
    with the six dofs ``ux uy uz rx ry rz``; tied nodes share one number.  Bodies add no
    stiffness: their rows stay zero unless they are tied, supported or held by a joint.

    Beams are named by their mesh's ``name`` (``straight(..., name="C")``), bodies by theirs;
    wherever a method takes a node or a beam it takes the scene's names (``"C.end"``,
    ``"hub"``, ``"C"``) or indices (``(0, "end")``, ``0``): :mod:`fvbeam.names`.  Beams left
    with the same name (the default ``"beam"``) are referred to by index.

    Parameters
    ----------
    beams
        The beams, each with its own dofs.
    ties
        Pairs of nodes that become one node (same dofs): ``(ref_a, ref_b)`` with each ref a
        node reference (``"C.end"``, ``"hub"``, ``(beam, node)``), or the form ``(beam_a,
        node_a, beam_b, node_b)`` (a body there as ``(..., "hub", None)``).  A tie involving
        a body must join coincident points (to 1e-9 of the structure's size): merging the
        dofs of points apart would not be a rigid joint.
    bodies
        :class:`~fvbeam.body.RigidBody` nodes, with unique names, none of the form
        ``'X.start'`` or ``'X.end'`` (a beam's node).
    """

    def __init__(
        self, beams: Sequence[Beam], ties: Sequence[tuple] = (), bodies: Sequence[RigidBody] = ()
    ) -> None:
        self.beams, self.bodies = list(beams), list(bodies)
        self._ties = list(ties)
        if not self.beams and not self.bodies:
            raise ValueError("a structure needs at least one beam or body")
        for i, body in enumerate(self.bodies):
            if not isinstance(body, RigidBody):
                raise ValueError(f"bodies[{i}] must be a RigidBody, got {type(body).__name__}")
        names = [body.name for body in self.bodies]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ValueError(f"rigid body names must be unique, repeated: {', '.join(repeated)}")
        for name in names:
            if not isinstance(parse_node(name), str):
                raise ValueError(f"rigid body name {name!r} has the form of a beam's node")
        self._body_index = {name: i for i, name in enumerate(names)}
        self._beam_names = [beam.mesh.name for beam in self.beams]
        self._offsets = np.cumsum([0] + [b.mesh.n_nodes for b in self.beams])
        n_slots = self._offsets[-1] + len(self.bodies)
        parent = np.arange(n_slots)

        def root(k: int) -> int:
            while parent[k] != k:
                k = parent[k]
            return k

        for tie in ties:
            a, b = (self.resolve_node(ref) for ref in self._tie_ends(tie))
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

    def moved(self, beams: Sequence[Beam], bodies: Sequence[RigidBody] = ()) -> "Structure":
        """This structure with its beams and bodies replaced by ``beams`` and ``bodies``, each
        the one it replaces moved rigidly (:meth:`fvbeam.beam.Beam.translated`, a body's
        position changed): the same ties, names, node numbering and dof maps, shared, not
        built again (a sweep over positions).  The ties that join a body are checked again (a
        body tied at a point it has left); ``ValueError`` when a beam or body is not a moved
        copy of the one it replaces (other stiffness, mesh size or name)."""
        beams, bodies = list(beams), list(bodies)
        if len(beams) != len(self.beams) or len(bodies) != len(self.bodies):
            raise ValueError(
                f"a moved structure has {len(self.beams)} beams and {len(self.bodies)} "
                f"bodies, got {len(beams)} and {len(bodies)}"
            )
        for i, (new, old) in enumerate(zip(beams, self.beams, strict=True)):
            if new is not old and (
                new.stiffness is not old.stiffness
                or new.mesh.n_nodes != old.mesh.n_nodes
                or new.mesh.name != old.mesh.name
            ):
                raise ValueError(f"beams[{i}] is not beam {i} moved rigidly (Beam.translated)")
        for i, (body, was) in enumerate(zip(bodies, self.bodies, strict=True)):
            if not isinstance(body, RigidBody) or body.name != was.name:
                raise ValueError(f"bodies[{i}] is not body {was.name!r} moved")
        out = shallow_copy(self)
        out.beams, out.bodies = beams, bodies
        for tie in self._ties:
            a, b = (out.resolve_node(ref) for ref in out._tie_ends(tie))
            if isinstance(a, str) or isinstance(b, str):
                out._check_coincident(tie, a, b)
        return out

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

    def _slot(self, node: str | tuple[int, int]) -> int:
        """Index of a resolved node (:meth:`resolve_node`) before ties are merged (beam
        nodes, then bodies)."""
        if isinstance(node, str):
            return int(self._offsets[-1]) + self._body_index[node]
        return int(self._offsets[node[0]]) + node[1]

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

    def beam_index(self, beam: int | str) -> int:
        """Position in :attr:`beams` of the beam ``beam``: its index, or its mesh's name."""
        if isinstance(beam, str):
            hits = [i for i, name in enumerate(self._beam_names) if name == beam]
            if len(hits) == 1:
                return hits[0]
            if hits:
                raise ValueError(
                    f"beam name {beam!r} is shared by beams {', '.join(map(str, hits))}: "
                    "refer to them by index, or name their meshes apart "
                    "(e.g. straight(..., name='C'))"
                )
            if beam in self._body_index:
                raise ValueError(f"{beam!r} is a rigid body, not a beam")
            raise ValueError(
                f"no beam named {beam!r} (the structure's beams: "
                f"{known(self._beam_names)}){suggest(beam, self._beam_names)}"
            )
        if not (is_index(beam) and 0 <= beam < len(self.beams)):
            raise ValueError(
                f"beam {beam!r} does not exist (the structure has {len(self.beams)} beams)"
            )
        return int(beam)

    def body_index(self, name: str) -> int:
        """Position of the body named ``name`` in :attr:`bodies`."""
        if name not in self._body_index:
            if name in self._beam_names:
                raise ValueError(
                    f"{name!r} is a beam, not a node: name one of its ends, "
                    f"'{name}.start' or '{name}.end'"
                )
            raise ValueError(
                f"no rigid body named {name!r} (the structure's bodies: "
                f"{known(list(self._body_index))}){suggest(name, self._body_index)}"
            )
        return self._body_index[name]

    def resolve_node(self, ref: NodeRef) -> str | tuple[int, int]:
        """What a node reference (:mod:`fvbeam.names`: ``"C.end"``, ``"hub"``, ``(beam,
        node)``) names: ``(beam index, mesh node index)``, or the body's name.  ``ValueError``
        naming the reference when its form is wrong or its beam, body or node does not
        exist (with the closest name)."""
        parsed = parse_node(ref)
        if isinstance(parsed, str):
            self.body_index(parsed)
            return parsed
        beam = self.beam_index(parsed[0])
        return beam, self.beams[beam].node_index(parsed[1])

    def node_dofs(self, ref: NodeRef) -> np.ndarray:
        """The six global dofs ``ux uy uz rx ry rz`` of a node (:meth:`resolve_node`)."""
        return 6 * int(self._node_number[self._slot(self.resolve_node(ref))]) + np.arange(6)

    def node_slot(self, ref: NodeRef) -> int:
        """The row of a node (:meth:`resolve_node`) in :meth:`slot_points`."""
        return self._slot(self.resolve_node(ref))

    def slot_points(self) -> np.ndarray:
        """Reference positions of the nodes before ties merge them, ``(slots, 3)``: each
        beam's mesh nodes in their order, beam after beam, then the bodies (a moved
        structure, :meth:`moved`, keeps the rows)."""
        bodies = [np.reshape(body.position, (1, 3)) for body in self.bodies]
        return np.concatenate([beam.mesh.points for beam in self.beams] + bodies)

    def node_position(self, ref: NodeRef) -> np.ndarray:
        """Reference position of a node (:meth:`resolve_node`)."""
        ref = self.resolve_node(ref)
        if isinstance(ref, str):
            return self.bodies[self._body_index[ref]].position.copy()
        return self.beams[ref[0]].mesh.points[ref[1]].copy()

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
        """Global load vector of a force and couple applied to a node
        (:meth:`resolve_node`)."""
        f = np.zeros(self.n_dofs)
        f[self.node_dofs(ref)] = wrench(force, moment)
        return f

    def dofs_of(self, q: ArrayLike) -> np.ndarray:
        """``q`` as a global dof vector (six per node, :attr:`n_dofs`), or ``ValueError``
        naming its size: the check of every method taking one."""
        return sized(q, self.n_dofs, "q", "the structure's dofs: 6 per node")

    def residual(self, q: ArrayLike) -> np.ndarray:
        """Internal force vector: the beams' residuals gathered on the global dofs."""
        q = self.dofs_of(q)
        r = np.zeros(self.n_dofs)
        for beam, dofs in zip(self.beams, self.dof_maps, strict=True):
            np.add.at(r, dofs, beam.residual(q[dofs]))
        return r

    def tangent(self, q: np.ndarray) -> sp.csr_matrix:
        """Global tangent: the beams' tangents scattered on the global dofs."""
        return self._scatter(
            [beam.tangent(q[dofs]) for beam, dofs in zip(self.beams, self.dof_maps, strict=True)]
        )

    def mass(self, kind: str = "lumped", massless: bool = False) -> sp.csr_matrix:
        """Global mass: the beams' mass matrices (:meth:`Beam.mass`, ``kind`` ``lumped`` or
        ``consistent``) on the global dofs, plus each rigid body's 6x6 mass matrix on its
        node (:meth:`~fvbeam.body.RigidBody.mass_matrix`: a centre of mass off the node
        couples translations and rotations).  A beam whose section has no mass is an error
        (``ValueError`` naming it), or with ``massless`` carries none (a static weight)."""
        M = self._scatter(
            [
                sp.csr_matrix((b.n_dofs, b.n_dofs))
                if massless and b.section.mass_per_length == 0
                else b.mass(kind)
                for b in self.beams
            ]
        )
        if not self.bodies:
            return M
        dofs = np.array([self.node_dofs(body.name) for body in self.bodies])
        blocks = np.array([body.mass_matrix() for body in self.bodies])
        rows, cols = np.broadcast_arrays(dofs[:, :, None], dofs[:, None, :])
        bodies = sp.csr_matrix(
            (blocks.ravel(), (rows.ravel(), cols.ravel())), shape=(self.n_dofs, self.n_dofs)
        )
        return (M + bodies).tocsr()

    def _scatter(self, matrices: Sequence[sp.spmatrix]) -> sp.csr_matrix:
        """The beams' matrices, one per beam on its own dofs, summed on the global dofs
        (:func:`on_dofs` each, then added pairwise, so that each entry is added about
        ``log2(beams)`` times)."""
        n = self.n_dofs
        parts = [on_dofs(A, dofs, n) for A, dofs in zip(matrices, self.dof_maps, strict=True)]
        if not parts:
            return sp.csr_matrix((n, n))
        while len(parts) > 1:
            pairs = [a + b for a, b in zip(parts[::2], parts[1::2], strict=False)]
            parts = pairs + parts[2 * len(pairs) :]
        total = sp.csr_matrix(parts[0])
        total.sum_duplicates()
        return total

    def gather(self, beam: int | str, f_local: np.ndarray) -> np.ndarray:
        """A beam's (index or name) load vector as a global one (the entries of tied dofs
        summed)."""
        return np.bincount(
            self.dof_maps[self.beam_index(beam)], weights=f_local, minlength=self.n_dofs
        )

    def local(self, beam: int | str, q: ArrayLike) -> np.ndarray:
        """A beam's (index or name) share of a global dof vector."""
        return self.dofs_of(q)[self.dof_maps[self.beam_index(beam)]]

    def node_graph(self) -> sp.csr_matrix:
        """The structure's nodes joined by its beams' elements (each pair of an element's
        nodes, once), ``(n_nodes, n_nodes)``, upper triangle in the beams' numbering; tied
        nodes are one node already, a body tied to nothing joins nothing."""
        edges = [np.zeros((0, 2), dtype=np.int64)]
        for beam, dofs in zip(self.beams, self.dof_maps, strict=True):
            cells = (dofs[::6] // 6)[beam.mesh.cells]
            edges += [cells[:, [a, b]] for a, b in combinations(range(cells.shape[1]), 2)]
        pairs = np.vstack(edges)
        n = self.n_nodes
        return sp.csr_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))

    @cached_property
    def dof_rank(self) -> np.ndarray:
        """Each global dof's position in an order in which the structure's matrices are
        banded along its chains: the reverse Cuthill-McKee order of the nodes
        (:meth:`node_graph`), six dofs per node (:class:`fvbeam.factorisation.SparseLU`)."""
        graph = self.node_graph()
        order = reverse_cuthill_mckee((graph + graph.T).tocsr(), symmetric_mode=True)
        rank = np.empty(self.n_nodes, dtype=np.int64)
        rank[order] = np.arange(self.n_nodes)
        return np.repeat(6 * rank, 6) + np.tile(np.arange(6), self.n_nodes)

    def support_dofs(self, supports: Sequence[Support]) -> np.ndarray:
        """Global dofs held by ``supports``."""
        fixed = [self.node_dofs(s.ref)[s.dofs()] for s in supports]
        return np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, dtype=int)


def on_dofs(A: sp.spmatrix, dofs: np.ndarray, n: int) -> sp.csr_matrix:
    """``A`` (on a beam's dofs) as a matrix on ``n`` global dofs, ``dofs[i]`` the global dof
    of its row and column ``i``: its compressed rows reordered by their global dof and its
    column indices renamed, without a coordinate list.  A beam numbered as the structure (the
    first beam, untied) keeps its arrays: no copy of a large mesh's matrix.  Two of a beam's
    nodes tied together (a ring) share a dof: their entries are summed through coordinates."""
    A = sp.csr_matrix(A)
    if np.array_equal(dofs, np.arange(len(dofs))):
        indptr = np.concatenate([A.indptr, np.full(n - len(dofs), A.indptr[-1])])
        return sp.csr_matrix((A.data, A.indices, indptr), shape=(n, n))
    order = np.argsort(dofs, kind="stable")
    ranked = dofs[order]
    if np.any(ranked[1:] == ranked[:-1]):
        coo = A.tocoo()
        return sp.csr_matrix((coo.data, (dofs[coo.row], dofs[coo.col])), shape=(n, n))
    A = A[order]
    lengths = np.zeros(n + 1, dtype=np.int64)
    lengths[ranked + 1] = np.diff(A.indptr)
    return sp.csr_matrix((A.data, dofs[A.indices], np.cumsum(lengths)), shape=(n, n))
