"""A chain of deformable beams as one line with a continuous arc-length abscissa ``xi``.

The beams of a :class:`~fvbeam.statics.Structure` listed in order, each beam's end vertex being
the next beam's start vertex (the same structure node).  ``xi`` runs from 0 at the first
beam's start to the sum of the beam lengths; the chain finds the beam and element, so the user
never keeps offsets or indices.  Deformed geometry (paper Sec. 4): with ``X_i`` the node
positions and ``u_i`` their displacements, ``x(xi) = sum N_i (X_i + u_i)``,
``l = x_/xi`` and ``l_xi = l_/xi`` in the element's arc-length coordinate.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from fvbeam.geometry import locate_abscissa
from fvbeam.mesh import shape_functions
from fvbeam.statics import Structure


def second_derivatives(nodes_per_element: int) -> np.ndarray:
    """d^2 N / dX^2 of the Lagrange shape functions on [0, 1] (constant)."""
    return np.zeros(2) if nodes_per_element == 2 else np.array([4.0, 4.0, -8.0])


class BeamChain:
    """Beams ``beams`` (indices into ``structure``) joined end to start, as one line.

    Raises ``ValueError`` naming the pair of beams that are not joined.
    """

    def __init__(self, structure: Structure, beams: Sequence[int], name: str = "chain") -> None:
        self.structure, self.indices, self.name = structure, list(beams), name
        if not self.indices:
            raise ValueError(f"{name}: a chain needs at least one beam")
        self.beams = [structure.beams[structure.beam_index(b)] for b in self.indices]
        for (a, beam_a), (b, beam_b) in zip(zip(self.indices, self.beams),
                                            zip(self.indices[1:], self.beams[1:])):
            end = structure.dof_maps[a][6 * beam_a.node_index("end")]
            start = structure.dof_maps[b][6 * beam_b.node_index("start")]
            if end != start:
                raise ValueError(f"{name}: beam {a} does not end where beam {b} starts "
                                 "(tie its end node to the next beam's start node)")
        self.offsets = np.concatenate([[0.0], np.cumsum([b.mesh.length for b in self.beams])])
        self.length = float(self.offsets[-1])

    def locate(self, xi: float) -> tuple[int, float]:
        """Position in the chain of the beam holding ``xi``, and ``xi`` along that beam."""
        k, offset = locate_abscissa(float(xi), self.offsets, self.name, "the chain")
        return int(k), float(offset)

    def geometry(self, xi: float, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l = x_/xi`` and ``l_/xi`` of the deformed chain (global dofs ``q``)."""
        k, local = self.locate(xi)
        beam = self.beams[k]
        mesh = beam.mesh
        e, X = mesh.locate(local)
        h = mesh.element_length[e]
        nodes = mesh.cells[e]
        u = self.structure.local(self.indices[k], q).reshape(-1, 6)[nodes, :3]
        current = mesh.points[nodes] + u
        N, dN = shape_functions(X, mesh.nodes_per_element)
        d2N = second_derivatives(mesh.nodes_per_element)
        return N @ current, dN @ current / h, d2N @ current / h**2
