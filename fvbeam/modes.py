"""Natural frequencies and mode shapes: the pencil solver and the bare structure's modes.

:func:`lowest_modes` solves a linearised problem given as sparse matrices: the undamped pencil
``K x = omega^2 M x``, or with a damping matrix ``C`` the quadratic one ``(s^2 M + s C + K) x
= 0``, for its eigenvalues of smallest distance to a shift.  ``K`` may be unsymmetric (the
finite-volume stiffness is Petrov-Galerkin) and ``M`` singular (a massless dof, a
rotation without section inertia in the lumped mass): those dofs carry infinite
eigenvalues, which the inverse form, ``nu = 1 / (s - sigma)``, maps to 0, never picked
among the largest ``nu``.  Small problems use dense solvers (``scipy.linalg.eig`` of the
inverse pencil); large ones ARPACK (``scipy.sparse.linalg.eigs``) on the
shift-invert operator, with one sparse LU of ``K - sigma M`` (of ``K + sigma C + sigma^2 M``
for the quadratic problem, in its first-order form ``x, v = s x``: Tisseur and Meerbergen,
"The quadratic eigenvalue problem", SIAM Review 43 (2001) 235, Sec. 3.4), in the
structure's banded order when it is given.

:func:`natural_frequencies` is the supported structure's case: ``K`` and ``M`` on the free
dofs (the supported ``K`` is regular: the check of :class:`~fvbeam.linear_statics.
LinearStatics`).  A lumped ``M`` may be singular (zero section inertia), whose modes then
have infinite frequency and are not returned.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.beam import Beam
from fvbeam.factorisation import PIVOT_THRESHOLD
from fvbeam.linear_statics import LinearStatics
from fvbeam.structure import Structure
from fvbeam.support import Support

#: Unknowns up to which the dense solvers are used.
DENSE_LIMIT = 200


@dataclass(frozen=True)
class Spectrum:
    """Eigenvalues ``s`` (k,) of a linearised problem, ordered by distance to the shift, and
    their vectors (N, k): the undamped problem's ``s = omega^2`` (real) and real vectors;
    the damped one's ``s`` complex (``x e^{s t}``, one of each conjugate pair, ``Im s >
    0``) and complex vectors."""

    s: np.ndarray
    vectors: np.ndarray


def _finite(values: np.ndarray, vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    keep = np.isfinite(values)
    return values[keep], vectors[:, keep]


def _start(op: spla.LinearOperator, N: int) -> np.ndarray:
    """ARPACK's start vector: a fixed random vector mapped three times by the operator, which
    takes out its components along the infinite eigenvalues (the null space of ``M`` and the
    Jordan chains of constraints, up to index 3: Nour-Omid, Parlett, Ericsson and Jensen,
    "How to implement the spectral transformation", Math. Comp. 48 (1987) 663), so that no
    spurious root enters the Krylov space; fixed, so a solve repeats exactly."""
    v = np.random.default_rng(0).standard_normal(N).astype(op.dtype)
    for _ in range(3):
        v = op.matvec(v)
        v /= np.linalg.norm(v)
    return v


def _factorised(
    A: sp.spmatrix, ranks: tuple[np.ndarray, np.ndarray] | None
) -> Callable[[np.ndarray], np.ndarray]:
    """The solve ``b -> A^-1 b`` of one sparse LU of ``A``: with ``ranks`` (the rows' and
    the columns' positions in a banded order, :meth:`fvbeam.structure.Structure.dof_rank`)
    factorised in that order with a diagonal-preferring pivot, as
    :class:`fvbeam.factorisation.SparseLU` (the fill stays in the band: on a chain a
    third of SuperLU's own column order's solve time); else in SuperLU's order."""
    if ranks is None:
        lu = spla.splu(sp.csc_matrix(A))
        return lu.solve
    rows, cols = (np.argsort(rank, kind="stable") for rank in ranks)
    B = sp.csr_matrix(A)[rows][:, cols]
    # B^T's columns are B's compressed rows: SuperLU factorises B^T and solves with its
    # transpose, as SparseLU does
    lu = spla.splu(B.T, permc_spec="NATURAL", diag_pivot_thresh=PIVOT_THRESHOLD)

    def solve(b: np.ndarray) -> np.ndarray:
        x = np.empty_like(b, dtype=np.result_type(b, B.dtype))
        x[cols] = lu.solve(b[rows], trans="T")
        return x

    return solve


def lowest_modes(
    K: sp.spmatrix,
    M: sp.spmatrix,
    count: int,
    C: sp.spmatrix | None = None,
    shift: float = 0.0,
    ranks: tuple[np.ndarray, np.ndarray] | None = None,
) -> Spectrum:
    """The ``count`` eigenpairs nearest ``shift`` (module docstring).

    Parameters
    ----------
    K, M
        Square sparse matrices of one size ``N``; ``K - shift M`` regular.
    count
        Number of eigenpairs, ``>= 1``; fewer come back when the problem has fewer finite
        eigenvalues (a singular ``M``).
    C
        Damping matrix; None (or all zero): the undamped problem, ``s = omega^2``.
    shift
        Undamped: ``sigma = shift`` in ``omega^2``; damped: ``sigma = i sqrt(shift)``, the
        root of an undamped oscillation at that ``omega^2``.
    ranks
        The rows' and the columns' positions in a banded order, for the sparse LU
        (:func:`_factorised`); None: SuperLU's own.
    """
    N = K.shape[0]
    damped = C is not None and C.nnz > 0 and abs(C).max() > 0
    if not damped:
        if N <= DENSE_LIMIT:  # the inverse pencil: infinite eigenvalues at nu = 0
            nu, vectors = sla.eig(M.toarray(), (K - shift * M).toarray())
        else:
            solve = _factorised(K - shift * M, ranks)
            op = spla.LinearOperator((N, N), matvec=lambda x: solve(M @ x), dtype=float)
            nu, vectors = spla.eigs(op, k=min(count, N - 2), which="LM", v0=_start(op, N))
        nu, vectors = _finite(nu, vectors)
        order = np.argsort(-np.abs(nu))[:count]
        nu, vectors = nu[order], vectors[:, order]
        keep = np.abs(nu) > 0
        return Spectrum(shift + 1 / nu[keep].real, vectors[:, keep].real)
    assert C is not None
    sigma = 1j * np.sqrt(shift) if shift > 0 else 0.0
    if 2 * N <= DENSE_LIMIT:  # the inverse pencil: infinite eigenvalues at nu = 0
        Z, eye = np.zeros((N, N)), np.eye(N)
        A = np.block([[Z, eye], [-K.toarray(), -C.toarray()]])
        B = np.block([[eye, Z], [Z, M.toarray()]])
        nu, vectors = _finite(*sla.eig(B, A - sigma * B))
        keep = np.abs(nu) > 0
        values, vectors = sigma + 1 / nu[keep], vectors[:, keep]
    else:
        solve_P = _factorised(K + sigma * C + sigma**2 * M, ranks)
        C_s = (C + sigma * M).tocsr()

        def solve(b: np.ndarray) -> np.ndarray:
            # (A - sigma B) x = B b in the first-order form (module docstring):
            # x2 = b1 + sigma x1, P x1 = -(M b2 + (C + sigma M) b1)
            b1, b2 = b[:N], b[N:]
            x1 = solve_P(-(M @ b2 + C_s @ b1))
            return np.concatenate([x1, b1 + sigma * x1])

        kind = complex if isinstance(sigma, complex) else float
        op = spla.LinearOperator((2 * N, 2 * N), matvec=solve, dtype=kind)
        v0 = _start(op, 2 * N)
        nu, vectors = spla.eigs(op, k=min(2 * count + 2, 2 * N - 2), which="LM", v0=v0)
        values = sigma + 1 / nu
    oscillating = values.imag > 1e-9 * np.abs(values)
    values, vectors = values[oscillating], vectors[:N, oscillating]
    order = np.argsort(np.abs(values - sigma))[:count]
    return Spectrum(values[order], vectors[:, order])


@dataclass(frozen=True)
class Modes:
    """``omega`` (n,): circular natural frequencies in rad/s, ascending; ``shapes``
    (n_dofs, n): mode shapes on the global dofs (zero at the supports), scaled to unit modal
    mass ``phi^T M phi = 1``."""

    omega: np.ndarray
    shapes: np.ndarray

    @property
    def hertz(self) -> np.ndarray:
        """Natural frequencies in Hz, ``omega / 2 pi``."""
        return self.omega / (2 * np.pi)


def natural_frequencies(
    structure: Structure | Beam, supports: Sequence[Support], n: int, mass: str = "lumped"
) -> Modes:
    """The ``n`` lowest natural frequencies (rad/s) and mode shapes.

    Parameters
    ----------
    structure
        A structure, or one beam.
    supports
        Supports that leave no rigid motion free.
    n
        Number of modes, ``1 <= n < number of free dofs``.
    mass
        ``lumped`` or ``consistent`` (:meth:`fvbeam.beam.Beam.mass`).
    """
    statics = LinearStatics(structure, supports)
    structure = statics.structure
    free = statics.free
    if not (isinstance(n, (int, np.integer)) and 1 <= n < len(free)):
        raise ValueError(
            f"n must be an integer in 1..{len(free) - 1} (free dofs: {len(free)}), got {n!r}"
        )
    M = structure.mass(mass)[free][:, free]
    rank = structure.dof_rank[free]
    spectrum = lowest_modes(statics.K[free][:, free], M, n, ranks=(rank, rank))
    omega2, phi = spectrum.s, spectrum.vectors
    if len(omega2) < n or omega2.min() <= 0:
        raise ValueError(
            "the eigenvalues are not real and positive: the mass matrix lacks "
            f"inertia on some free dofs or the stiffness is indefinite (omega^2 "
            f"= {omega2[:3]})"
        )
    phi = phi / np.sqrt(np.einsum("ik,ik->k", phi, M @ phi))
    shapes = np.zeros((structure.n_dofs, n))
    shapes[free] = phi
    return Modes(np.sqrt(omega2), shapes)
