"""Natural frequencies and mode shapes of a supported structure: ``K phi = omega^2 M phi``.

The finite-volume stiffness is unsymmetric (Petrov-Galerkin), so the problem is solved in the
inverse form ``M phi = mu K phi``, ``mu = 1 / omega^2``: the supported ``K`` is regular (the
check of :class:`~fvbeam.linear_statics.LinearStatics`), while a lumped ``M`` may be singular (zero
section inertia), whose modes then have ``mu = 0`` (infinite frequency) and fall last.  Small
problems use dense solvers (``scipy.linalg.eigh`` when ``K`` is symmetric, ``eig`` otherwise);
large ones ARPACK in shift-invert mode about 0 (``eigsh`` / ``eigs``) on the factorised ``K``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from fvbeam.beam import Beam
from fvbeam.linear_statics import LinearStatics
from fvbeam.structure import Structure
from fvbeam.support import Support

#: Free dofs up to which the dense solvers are used.
DENSE_LIMIT = 800


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
    K = statics.K[free][:, free]
    symmetric = abs(K - K.T).max() <= 1e-12 * abs(K).max()
    if len(free) <= DENSE_LIMIT:
        Kd, Md = K.toarray(), M.toarray()
        mu, phi = sla.eigh(Md, Kd) if symmetric else sla.eig(Md, Kd)
    else:
        solve = spla.LinearOperator(K.shape, matvec=statics.lu.solve, dtype=float)
        eigen = spla.eigsh if symmetric else spla.eigs
        omega2, phi = eigen(K.tocsc(), k=n, M=M.tocsc(), sigma=0.0, which="LM", OPinv=solve)
        mu = 1 / omega2
    order = np.argsort(-mu.real)[:n]
    mu, phi = mu[order], phi[:, order]
    if np.abs(mu.imag).max() > 1e-8 * np.abs(mu.real).max() or mu.real.min() <= 0:
        raise ValueError(
            "the eigenvalues are not real and positive: the mass matrix lacks "
            f"inertia on some free dofs or the stiffness is indefinite (1/omega^2 "
            f"= {mu[:3]})"
        )
    phi = phi.real
    phi /= np.sqrt(np.einsum("ik,ik->k", phi, M @ phi))
    shapes = np.zeros((structure.n_dofs, n))
    shapes[free] = phi
    return Modes(1 / np.sqrt(mu.real), shapes)
