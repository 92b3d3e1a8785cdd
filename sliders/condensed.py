"""Condensed Newton step for sliders on linear beams: factorise ``K`` once, solve small systems.

The beams are linear, so their stiffness ``K`` (free dofs) is constant, and the sliders touch
only a few dofs ``T``.  ``K`` may be singular: a part held only by sliders (the piston of the
sliding-beams setup) keeps the rigid motions its supports leave free.  Their basis ``Phi``
(:func:`rigid_modes`) spans both null spaces of ``K``: ``K Phi = 0`` (a rigid motion does not
strain) and ``Phi^T K = 0`` (a rigid virtual motion does no internal work; the fv regions and
the Galerkin shape functions both reproduce rigid motions).  The bordered operator

    B = [K, s Phi; s Phi^T, 0]          (s = max |K|, to balance the pivots)

is then regular and is factorised once per structure and support set.  ``B^{-1}[b; 0] =
[x; z]`` gives ``K x = b - s Phi z`` with ``Phi^T x = 0`` and ``z = 0`` exactly when ``b`` is
self-equilibrated on every free part (``Phi^T b = 0``).

A Newton step solves ``K dq + U g = -r_q``, ``C w + D dy = -r_y`` with ``w = U^T dq`` the
increments on ``T``, ``g = E w + A dy`` the slider force increments (``E, A, C, D``: the
sliders' Jacobian blocks) and ``U`` the injection of ``T``.  Writing
``dq = x + Phi a`` with ``[x; z] = -B^{-1}[r_q + U g; 0]`` and ``H = B^{-1}[U; 0]`` (columns
cached per dof), the conditions are, with ``[x_r; z_r] = B^{-1}[r_q; 0]``::

    (I + H_x,T E) w + H_x,T A dy - Phi_T a = -x_r,T     (t rows: w is the increment on T)
    H_z E w + H_z A dy                     = -z_r       (k rows: z = 0, self-equilibrium)
    C w + D dy                             = -r_y       (slider equations)

a dense system of size ``t + k + m``; then ``dq = -x_r - H_x g + Phi a``.  Without free
parts (``k = 0``) this is ``(I + C_TT E) w + C_TT A dy = -(K^{-1} r_q)_T`` with
``C_TT = (K^{-1})_TT``.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import connected_components

from fvbeam.statics import Structure

#: A small system whose row- and column-equilibrated reciprocal condition number (1-norm)
#: falls below this is singular: the threshold of the bordered diagnostic
#: (:meth:`sliders.statics.SliderStatics._singular`).
SINGULAR_RCOND = 1e-12


def node_positions(structure: Structure) -> np.ndarray:
    """Reference position of every structure node, ``(n_nodes, 3)``."""
    x = np.zeros((structure.n_nodes, 3))
    for beam, dofs in zip(structure.beams, structure.dof_maps):
        x[dofs[::6] // 6] = beam.mesh.points
    return x


def rigid_modes(structure: Structure, K: sp.spmatrix, free: np.ndarray) -> np.ndarray:
    """Orthonormal basis ``(len(free), k)`` of the rigid motions the supports leave free.

    Every connected part of the structure (connected through the pattern of its global
    stiffness ``K``) moves rigidly
    with a translation and a rotation about its centroid (``u = t + w x (x - x_0)``,
    ``theta = w``, rotations scaled by the part's size); the combinations that vanish on the
    supported dofs are kept.
    """
    coo = K.tocoo()
    graph = sp.coo_matrix((np.ones(coo.nnz), (coo.row // 6, coo.col // 6)),
                          shape=(structure.n_nodes, structure.n_nodes))
    n_parts, part = connected_components(graph, directed=False)
    x = node_positions(structure)
    modes = np.zeros((structure.n_dofs, 6 * n_parts))
    for p in range(n_parts):
        nodes = np.flatnonzero(part == p)
        lever = x[nodes] - x[nodes].mean(axis=0)
        size = max(float(np.linalg.norm(lever, axis=1).max()), 1e-300)
        for i in range(3):
            e = np.eye(3)[i]
            modes[6 * nodes[:, None] + np.arange(3), 6 * p + i] = e
            modes[6 * nodes[:, None] + np.arange(3), 6 * p + 3 + i] = np.cross(e, lever) / size
            modes[6 * nodes + 3 + i, 6 * p + 3 + i] = 1.0 / size
    fixed = np.setdiff1d(np.arange(structure.n_dofs), free)
    combos = la.null_space(modes[fixed]) if fixed.size else np.eye(modes.shape[1])
    if combos.shape[1] == 0:
        return np.zeros((len(free), 0))
    return np.linalg.qr(modes[free] @ combos)[0]


class CondensedOperator:
    """``B`` factorised once, with the columns of ``B^{-1}`` cached per free dof; ``K`` is
    the structure's global stiffness, ``free`` its unsupported dofs.

    Raises ``ValueError`` when ``B`` is singular: the supports leave a mechanism that is not
    a rigid motion of a part (use the bordered back end, which lets the sliders hold it).
    """

    def __init__(self, structure: Structure, K: sp.spmatrix, free: np.ndarray) -> None:
        self.phi = rigid_modes(structure, K, free)
        K_free = sp.csr_matrix(K)[free][:, free]
        self.n_free, self.n_rigid = len(free), self.phi.shape[1]
        scale = np.abs(K_free).max()
        B = sp.bmat([[K_free, scale * sp.csr_matrix(self.phi)],
                     [scale * sp.csr_matrix(self.phi.T), None]], format="csc")
        message = ("the stiffness without the free parts' rigid motions is singular: the "
                   "supports leave a mechanism; solve with method='bordered'")
        try:
            self.lu = spla.splu(B)
        except RuntimeError as exc:
            raise ValueError(message) from exc
        pivots = np.abs(self.lu.U.diagonal())
        if pivots.min() <= 1e-13 * pivots.max():
            raise ValueError(message)
        self._slot = np.full(self.n_free, -1)
        self._store = np.zeros((self.n_free + self.n_rigid, 0))

    def solve(self, b: np.ndarray) -> np.ndarray:
        """``B^{-1} [b; 0]`` for ``b`` on the free dofs."""
        return self.lu.solve(np.concatenate([b, np.zeros(self.n_rigid)]))

    def columns(self, positions: np.ndarray) -> np.ndarray:
        """``B^{-1}[U; 0]`` for the free dofs at ``positions``, ``(n_free + k, t)``; each
        column is computed once and kept."""
        missing = np.unique(positions[self._slot[positions] < 0])
        if missing.size:
            unit = np.zeros((self.n_free + self.n_rigid, missing.size))
            unit[missing, np.arange(missing.size)] = 1.0
            self._slot[missing] = self._store.shape[1] + np.arange(missing.size)
            self._store = np.hstack([self._store, self.lu.solve(unit)])
        return self._store[:, self._slot[positions]]

    def step(self, r_free: np.ndarray, touched: np.ndarray, J: np.ndarray,
             r_y: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """Newton increments on the free dofs and the slider unknowns, or None when the small
        system is singular.

        ``touched``: positions (in the free dofs) of the ``t`` touched dofs; ``J``: the
        sliders' Jacobian on ``[q_T; y]``, ``(t + m, t + m)``; ``r_free``, ``r_y``: residuals.
        """
        t, k, m = len(touched), self.n_rigid, len(r_y)
        H = self.columns(touched)
        base = self.solve(r_free)
        Hx, Hz = H[touched], H[self.n_free:]
        small = np.zeros((t + m + k, t + m + k))
        small[:t, :t + m] = Hx @ J[:t]                # [H_x,T E, H_x,T A]
        small[np.arange(t), np.arange(t)] += 1.0
        small[:t, t + m:] = -self.phi[touched]
        small[t:t + k, :t + m] = Hz @ J[:t]
        small[t + k:, :t + m] = J[t:]
        rhs = -np.concatenate([base[touched], base[self.n_free:], r_y])
        rows = np.abs(small).max(axis=1).clip(1e-300)
        small = small / rows[:, None]
        cols = np.abs(small).max(axis=0).clip(1e-300)
        small = small / cols
        with warnings.catch_warnings():  # an exact zero pivot is reported through rcond
            warnings.simplefilter("ignore", la.LinAlgWarning)
            lu = la.lu_factor(small, check_finite=False)
        rcond = la.lapack.dgecon(lu[0], np.abs(small).sum(axis=0).max(), norm="1")[0]
        if not rcond >= SINGULAR_RCOND:
            return None
        z = la.lu_solve(lu, rhs / rows, check_finite=False) / cols
        g = J[:t] @ z[:t + m]                          # E w + A dy
        dq = -base[:self.n_free] - H[:self.n_free] @ g + self.phi @ z[t + m:]
        return dq, z[t:t + m]
