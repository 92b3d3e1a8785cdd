"""Linear statics of a supported structure on a cached factorisation: ``K q = f``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse.linalg as spla

from fvbeam.beam import Beam
from fvbeam.structure import Structure
from fvbeam.support import Support


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
            raise ValueError(
                "the stiffness is singular: the supports leave a rigid-body "
                "motion free (clamp or pin more nodes)"
            ) from exc
        diag = np.abs(self.lu.U.diagonal())
        if diag.min() <= 1e-13 * diag.max():
            raise ValueError(
                "the stiffness is singular to working precision: the supports "
                "leave a rigid-body motion free (clamp or pin more nodes)"
            )

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
