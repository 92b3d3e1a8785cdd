"""Structures of several beams, supports, and the linear static solve on a cached factorisation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.beam import Beam

#: Names of the six nodal dofs, in order.
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass(frozen=True)
class Support:
    """A node held fixed: ``clamp`` (all six dofs), ``pin`` (the three translations), or the
    dofs named and joined by ``+`` (from ``ux uy uz rx ry rz``), e.g. ``"ux+rx"``."""

    beam: int
    node: int | str
    kind: str = "clamp"

    def __post_init__(self) -> None:
        self.dofs()

    def dofs(self) -> np.ndarray:
        """Local dof indices (0..5) the support holds."""
        if self.kind == "clamp":
            return np.arange(6)
        if self.kind == "pin":
            return np.arange(3)
        names = self.kind.split("+")
        unknown = [n for n in names if n not in DOF_NAMES]
        if unknown or not names:
            raise ValueError(f"support kind must be 'clamp', 'pin' or dof names from "
                             f"{' '.join(DOF_NAMES)} joined by '+', got {self.kind!r}")
        return np.array(sorted({DOF_NAMES.index(n) for n in names}))


class Structure:
    """Beams joined at shared nodes into one set of global dofs.

    Parameters
    ----------
    beams
        The beams, each with its own dofs.
    ties
        ``(beam_a, node_a, beam_b, node_b)``: the two nodes become one node (same dofs).
    """

    def __init__(self, beams: Sequence[Beam], ties: Sequence[tuple] = ()) -> None:
        self.beams = list(beams)
        if not self.beams:
            raise ValueError("a structure needs at least one beam")
        offsets = np.cumsum([0] + [b.mesh.n_nodes for b in self.beams])
        parent = np.arange(offsets[-1])

        def root(k: int) -> int:
            while parent[k] != k:
                k = parent[k]
            return k

        for tie in ties:
            a, na, b, nb = tie
            ka = offsets[self.beam_index(a)] + self.beams[a].node_index(na)
            kb = offsets[self.beam_index(b)] + self.beams[b].node_index(nb)
            parent[max(root(ka), root(kb))] = min(root(ka), root(kb))
        roots = np.array([root(k) for k in range(offsets[-1])])
        _, node_number = np.unique(roots, return_inverse=True)
        self.n_nodes = int(node_number.max()) + 1
        self.dof_maps = [(6 * node_number[offsets[i]:offsets[i + 1], None]
                          + np.arange(6)).ravel() for i in range(len(self.beams))]

    def beam_index(self, i: int) -> int:
        if not (isinstance(i, (int, np.integer)) and 0 <= i < len(self.beams)):
            raise ValueError(f"beam {i!r} does not exist (the structure has "
                             f"{len(self.beams)} beams)")
        return int(i)

    @property
    def n_dofs(self) -> int:
        return 6 * self.n_nodes

    @classmethod
    def from_shared_points(cls, beams: Sequence[Beam]) -> "Structure":
        """Beams read together (:func:`fvbeam.mesh.read_beams`), joined where they share a
        mesh point (equal ``point_ids``)."""
        first: dict[int, tuple[int, int]] = {}
        ties = []
        for b, beam in enumerate(beams):
            for node, pid in enumerate(beam.mesh.point_ids.tolist()):
                if pid in first:
                    ties.append(first[pid] + (b, node))
                else:
                    first[pid] = (b, node)
        return cls(beams, ties)

    def residual(self, q: np.ndarray) -> np.ndarray:
        """Internal force vector: the beams' residuals gathered on the global dofs."""
        r = np.zeros(self.n_dofs)
        for beam, dofs in zip(self.beams, self.dof_maps):
            np.add.at(r, dofs, beam.residual(q[dofs]))
        return r

    def tangent(self, q: np.ndarray) -> sp.csr_matrix:
        """Global tangent: the beams' tangents scattered on the global dofs."""
        rows, cols, vals = [], [], []
        for beam, dofs in zip(self.beams, self.dof_maps):
            K = beam.tangent(q[dofs]).tocoo()
            rows.append(dofs[K.row])
            cols.append(dofs[K.col])
            vals.append(K.data)
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(self.n_dofs, self.n_dofs))

    def gather(self, beam: int, f_local: np.ndarray) -> np.ndarray:
        """A beam's load vector as a global one."""
        f = np.zeros(self.n_dofs)
        np.add.at(f, self.dof_maps[self.beam_index(beam)], f_local)
        return f

    def local(self, beam: int, q: np.ndarray) -> np.ndarray:
        """A beam's share of a global dof vector."""
        return q[self.dof_maps[self.beam_index(beam)]]

    def support_dofs(self, supports: Sequence[Support]) -> np.ndarray:
        fixed = []
        for s in supports:
            beam = self.beams[self.beam_index(s.beam)]
            node = beam.node_index(s.node)
            dofs = self.dof_maps[s.beam][6 * node:6 * node + 6]
            fixed.append(dofs[s.dofs()])
        return np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, dtype=int)


class LinearStatics:
    """``K q = f`` with supports, factorised once; every further load case is one solve.

    Raises ``ValueError`` naming the problem when the supports leave a rigid motion free.
    """

    def __init__(self, structure: Structure | Beam, supports: Sequence[Support]) -> None:
        if isinstance(structure, Beam):
            structure = Structure([structure])
        self.structure = structure
        self.fixed = structure.support_dofs(supports)
        self.free = np.setdiff1d(np.arange(structure.n_dofs), self.fixed)
        self.K = structure.tangent(np.zeros(structure.n_dofs))
        Kff = self.K[self.free][:, self.free].tocsc()
        try:
            self.lu = spla.splu(Kff)
        except RuntimeError as exc:
            raise ValueError("the stiffness is singular: the supports leave a rigid-body "
                             "motion free (clamp or pin more nodes)") from exc
        diag = np.abs(self.lu.U.diagonal())
        if diag.min() <= 1e-13 * diag.max():
            raise ValueError("the stiffness is singular to working precision: the supports "
                             "leave a rigid-body motion free (clamp or pin more nodes)")

    def solve(self, f: np.ndarray) -> np.ndarray:
        """Displacements for the load vector ``f`` (global dofs; zero at the supports)."""
        f = np.asarray(f, dtype=float)
        if f.shape[0] != self.structure.n_dofs or not np.all(np.isfinite(f)):
            raise ValueError(f"load vector must be finite with {self.structure.n_dofs} rows")
        q = np.zeros_like(f)
        q[self.free] = self.lu.solve(f[self.free])
        return q

    def reactions(self, q: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Support reactions ``K q - f`` on the fixed dofs (global vector, zero elsewhere)."""
        r = np.zeros_like(f)
        r[self.fixed] = (self.K @ q - f)[self.fixed]
        return r
