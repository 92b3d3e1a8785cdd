"""A sparse LU factorisation that compiled code solves with.

scipy's SuperLU (:func:`scipy.sparse.linalg.splu`) factorises ``Pr A Pc = L U`` with a
fill-reducing column ordering; its ``solve`` is a Python call.  The Newton step that runs
compiled (:mod:`sliders.solve.newton_kernel`) solves with the operator several times per
iteration, so :class:`Factor` exports the factors as compressed-column arrays and
:func:`factor_solve` does the two triangular solves in compiled code::

    A x = b   <=>   L U z = Pr b,  x = Pc z

(``(Pr b)[perm_r[i]] = b[i]``, ``x[i] = z[perm_c[i]]``).  The reference is SuperLU's own
``solve``; ``tests/test_factor.py`` holds the two equal to roundoff.  A solve costs one pass
over the factors' nonzeros: linear in the size for a chain of beams.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources


class Factors(NamedTuple):
    """The factors of ``Pr A Pc = L U`` as :func:`factor_solve` reads them: ``L`` and ``U``
    in compressed columns (row indices sorted, so that a column's diagonal entry is the first
    of ``L``'s and the last of ``U``'s) and the row and column permutations."""

    L_ptr: np.ndarray
    L_row: np.ndarray
    L_val: np.ndarray
    U_ptr: np.ndarray
    U_row: np.ndarray
    U_val: np.ndarray
    perm_r: np.ndarray
    perm_c: np.ndarray


class Factor:
    """``A`` (square, sparse) factorised once by SuperLU, its factors kept as arrays.

    Raises ``ValueError`` when SuperLU finds ``A`` exactly singular."""

    def __init__(self, A: sp.spmatrix) -> None:
        try:
            self.lu = spla.splu(sp.csc_matrix(A))
        except RuntimeError as exc:
            raise ValueError(f"the matrix is singular ({exc})") from exc
        L, U = self.lu.L.tocsc(), self.lu.U.tocsc()
        L.sort_indices()
        U.sort_indices()
        self.n = A.shape[0]
        columns = np.arange(self.n)
        if not (
            np.array_equal(L.indices[L.indptr[:-1]], columns)
            and np.array_equal(U.indices[U.indptr[1:] - 1], columns)
        ):
            raise ValueError("the factors lack a stored diagonal entry (a singular matrix)")
        #: The factors as :func:`factor_solve` reads them.
        self.arrays = Factors(
            L.indptr.astype(np.int64),
            L.indices.astype(np.int64),
            L.data,
            U.indptr.astype(np.int64),
            U.indices.astype(np.int64),
            U.data,
            self.lu.perm_r.astype(np.int64),
            self.lu.perm_c.astype(np.int64),
        )

    @property
    def pivots(self) -> np.ndarray:
        """The diagonal of ``U``."""
        return self.lu.U.diagonal()

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``A^{-1} b`` for one right-hand side (n,), compiled (:func:`factor_solve`)."""
        out = np.empty(self.n)
        factor_solve(self.arrays, np.ascontiguousarray(b, dtype=float), out, np.empty(self.n))
        return out


@numba.njit(cache=True, inline="never")
def factor_solve(factors: Factors, b: np.ndarray, x: np.ndarray, z: np.ndarray) -> None:
    """``x = A^{-1} b`` from the ``factors`` of ``Pr A Pc = L U`` (``z`` a scratch vector):
    ``L U z = Pr b`` column by column, forward through ``L`` then backward through ``U``,
    and ``x = Pc z``."""
    L_ptr, L_row, L_val, U_ptr, U_row, U_val, perm_r, perm_c = factors
    n = len(b)
    for i in range(n):
        z[perm_r[i]] = b[i]
    for j in range(n):
        first = L_ptr[j]
        zj = z[j] / L_val[first]
        z[j] = zj
        if zj != 0.0:
            for p in range(first + 1, L_ptr[j + 1]):
                z[L_row[p]] -= L_val[p] * zj
    for j in range(n - 1, -1, -1):
        last = U_ptr[j + 1] - 1
        zj = z[j] / U_val[last]
        z[j] = zj
        if zj != 0.0:
            for p in range(U_ptr[j], last):
                z[U_row[p]] -= U_val[p] * zj
    for i in range(n):
        x[i] = z[perm_c[i]]
