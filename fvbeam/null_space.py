"""A sparse basis of the null space of a few sparse constraint rows, the master-slave way.

Constraint rows ``G x = 0`` (``r`` rows on ``n`` unknowns, each row touching few unknowns:
a joint's rows on the dofs of its body and of the line element it rides on) leave the
motions ``x = Z w`` free.  :func:`null_basis` eliminates one unknown per independent row
(a *slave*), expressed in the others (the *masters*), which stay unknowns of their own::

    x_slaves = S x_masters,      Z = P [I; S]

so ``Z`` is the identity on the masters plus ``S``, whose entries lie only in the columns of
the masters the rows touch: ``nnz(Z) = n - r + nnz(S)``, and a matrix ``K`` projected as
``Y^T K Z`` keeps its sparsity but for the few touched rows and columns.  The slaves are
chosen among the touched unknowns by a QR factorisation with column pivoting of the touched
columns (dense: ``r`` by at most a few hundred), ``G_T P = Q [R_11 R_12]``, whose pivots
give a well-conditioned ``R_11`` (Golub and Van Loan, "Matrix Computations", 4th ed.,
Sec. 5.4.2) and the rank: redundant rows (a constraint repeated) are dropped, with
``numpy.linalg.matrix_rank``'s tolerance ``max(r, t) u |R_00|``.  Then ``S = -R_11^{-1}
R_12``.  A sparse QR of ``G^T`` would give an orthonormal basis, but dense in the touched
rows and with a library (SuiteSparseQR) that scipy does not ship.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp


def null_basis(G: sp.spmatrix) -> tuple[sp.csc_matrix, np.ndarray]:
    """A basis ``Z`` (n, n - rank) of the null space of the sparse rows ``G`` (r, n):
    ``G Z = 0``, the identity on the unknowns kept, and those unknowns, the masters
    (n - rank,), ascending: column ``j`` of ``Z`` is master ``j`` (module docstring).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> Z, masters = null_basis(sp.csr_matrix([[1.0, -1.0, 0.0]]))
    >>> Z.toarray()
    array([[1., 0.],
           [1., 0.],
           [0., 1.]])
    >>> masters
    array([1, 2])
    """
    G = sp.csc_matrix(G)
    G.eliminate_zeros()
    n = G.shape[1]
    touched = np.flatnonzero(np.diff(G.indptr))
    if touched.size == 0:
        return sp.identity(n, format="csc"), np.arange(n)
    R, pivots = sla.qr(G[:, touched].toarray(), mode="r", pivoting=True)
    diagonal = np.abs(np.diag(R))
    tol = max(G.shape[0], touched.size) * np.finfo(float).eps * diagonal[0]
    rank = int(np.sum(diagonal > tol))
    slaves, kept = touched[pivots[:rank]], touched[pivots[rank:]]
    S = -sla.solve_triangular(R[:rank, :rank], R[:rank, rank:])
    masters = np.setdiff1d(np.arange(n), slaves)
    column = np.empty(n, dtype=int)
    column[masters] = np.arange(masters.size)
    rows = np.concatenate([masters, np.repeat(slaves, kept.size)])
    cols = np.concatenate([np.arange(masters.size), np.tile(column[kept], rank)])
    values = np.concatenate([np.ones(masters.size), S.ravel()])
    return sp.csc_matrix((values, (rows, cols)), shape=(n, masters.size)), masters
