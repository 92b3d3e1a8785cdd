"""Sparse LU of a structure's matrices in an order that keeps a chain's fill linear.

A chain of ``n`` beam elements couples each node to its neighbours only: in the order of the
nodes along the chain its matrices are banded, and an LU factorisation without reordering
fills the band and nothing else, ``O(n)`` entries and work.  Each beam numbers its own nodes
vertices first and mid nodes after (scikit-fem's numbering), so that its matrices' natural
order is not banded; :meth:`fvbeam.structure.Structure.dof_rank` ranks the dofs by the reverse
Cuthill-McKee order of the structure's nodes (``scipy.sparse.csgraph``), which follows each
chain and keeps the band of a structure of several beams narrow.  :class:`SparseLU` factorises
in that order with SuperLU (``scipy.sparse.linalg.splu``, no column reordering of its own) and
a threshold on the pivots that prefers the diagonal (:data:`PIVOT_THRESHOLD`): fewer row
interchanges keep the fill in the band.  On a cantilever of 1e5 fv3 elements it takes about
two thirds of the time of SuperLU's default (COLAMD) order, and a solve a quarter
(``docs/performance.md``, "Large meshes").
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

#: SuperLU's ``diag_pivot_thresh``: the diagonal is kept as the pivot while it is at least this
#: fraction of the largest entry of its column (partial pivoting is 1).  A threshold of 0.1
#: bounds each step's growth of the entries by 11 instead of 2, the usual compromise (UMFPACK's
#: default); the stiffness of a beam has a dominant diagonal, and its pivots are the diagonal.
PIVOT_THRESHOLD = 0.1


class SparseLU:
    """``A[dofs][:, dofs]`` factorised with its rows and columns ordered by ``rank[dofs]``.

    Parameters
    ----------
    A
        A square sparse matrix (a structure's stiffness, or an operator on its dofs).
    dofs
        The rows and columns kept (e.g. the free dofs), in the order :meth:`solve` reads and
        returns them.
    rank
        The position of every row of ``A`` in the factorisation's order
        (:meth:`fvbeam.structure.Structure.dof_rank`); ties keep the order of ``dofs``.

    Raises ``RuntimeError`` (SuperLU's) when the matrix is exactly singular.
    """

    def __init__(self, A: sp.spmatrix, dofs: np.ndarray, rank: np.ndarray) -> None:
        dofs = np.asarray(dofs)
        self._order = np.argsort(np.asarray(rank)[dofs], kind="stable")
        kept = dofs[self._order]
        B = sp.csr_matrix(A)[kept][:, kept]
        # the rows of B compressed are the columns of B^T: SuperLU factorises B^T, which
        # solves B x = b as its transpose, without converting B to columns
        self.lu = spla.splu(B.T, permc_spec="NATURAL", diag_pivot_thresh=PIVOT_THRESHOLD)

    @property
    def shape(self) -> tuple[int, int]:
        return self.lu.shape

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``x`` with ``A[dofs][:, dofs] x = b`` (``b`` of shape ``(n,)`` or ``(n, k)``)."""
        b = np.asarray(b, dtype=float)
        x = np.empty_like(b)
        x[self._order] = self.lu.solve(b[self._order], trans="T")
        return x
