"""Linear statics of a supported structure on a cached factorisation: ``K q = f``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fvbeam.beam import Beam
from fvbeam.factorisation import SparseLU
from fvbeam.mechanism import free_motion_message, motion_phrases, rigid_modes
from fvbeam.structure import Structure
from fvbeam.support import Support, complement


class LinearStatics:
    """``K q = f`` with supports, factorised once; every further load case is one solve.

    Raises ``ValueError`` naming every rigid motion the supports leave free
    (:mod:`fvbeam.mechanism`): the stiffness is singular then.
    """

    def __init__(self, structure: Structure | Beam, supports: Sequence[Support]) -> None:
        if isinstance(structure, Beam):
            structure = Structure([structure])
        self.structure = structure
        self.fixed = structure.support_dofs(supports)
        self.free = complement(structure.n_dofs, self.fixed)
        modes = rigid_modes(structure, self.free)
        if modes.k:
            raise ValueError(
                free_motion_message(
                    "supports", motion_phrases(modes, np.eye(modes.k)), "support more dofs"
                )
            )
        self.K = structure.tangent(np.zeros(structure.n_dofs))
        self.lu = SparseLU(self.K, self.free, structure.dof_rank)

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
