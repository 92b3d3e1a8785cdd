"""Geometrically exact beams: the residual and its tangent.

The beam of Ghiringhelli, Masarati and Mantegazza (AIAA J. 38 (2000) 131-138), the
finite-volume beam of :mod:`fvbeam.beam` (``fv2``, ``fv3``) written on the current
configuration, and the Galerkin beams (``galerkin-p1``, ``galerkin-p2``, full or reduced
integration) with the same kinematics (Simo-Reissner, with the objective interpolation of
Crisfield and Jelenic, Proc. R. Soc. A 455 (1999) 1125).  Each node ``a`` has a position
``x_a`` and a rotation ``R_a`` (identity in the reference configuration; the section frames
of the mesh stay in the section stiffness),
updated on the manifold by spatial increments, ``x_a <- x_a + du_a``,
``R_a <- exp(dphi_a) R_a`` (:func:`fvbeam.rotations.update`): the six dofs of a node are
``[du, dphi]``, in global axes, as the linear beam's ``[u, theta]``.

**Interpolation.**  In each element, from a reference node ``r`` (node 0 of a 2-node
element, the mid node of a 3-node one), the relative rotation vectors
``psi_a = log(R_r^T R_a)`` are interpolated with the Lagrange shape functions ``N_a``
(objective: a rigid rotation of the whole beam leaves them unchanged)::

    x = sum N_a x_a,    psi = sum N_a psi_a,    Lambda = R_r exp(psi).

**Strains** at each evaluation point (fv) or quadrature point (Galerkin), in the frame
``Lambda`` of the reference axes (``'`` the derivative in reference arc length; ``x0'`` the
reference unit tangent)::

    nu = Lambda^T x' - x0',      kappa = J(psi)^T psi'          (Lambda^T Lambda' = skew(kappa))

and the stress resultants ``[F; M] = blockdiag(Lambda, Lambda) C [nu; kappa]``, ``C`` the
section stiffness in global axes at the point (:meth:`fvbeam.section.Section.global_stiffness`).

**Balance of each node's region** (the fv test functions, eq. T4, on the current
configuration): the evaluation points bound the regions, and node ``a``'s internal force is
the sum over the points ``p`` of its elements of ``jump_a(p) [F_p; M_p + (x_p - x_a) x F_p]``,
``jump_a(p) = chi_a(p+) - chi_a(p-)`` (:func:`fvbeam.elements.jumps`).  **Galerkin**: the
weak form ``r = sum_p w_p B_p^T C [nu; kappa]``, ``B = d [nu; kappa] / d q`` (below), ``w_p``
the quadrature weights in arc length.  Equilibrium is ``r(q) = f`` with the nodal loads
``f``.

**Tangent** (material + geometric), from the variations of the spatial section rotation
``d theta = dphi_r + R_r J(psi) d psi``, ``d psi_a = J(psi_a)^-1 R_r^T (dphi_a - dphi_r)``::

    d nu = Lambda^T (dx' + x' x d theta),    d kappa = Lambda^T d theta',
    d theta' = R_r (DJ(psi)[psi'] d psi + J(psi) d psi'),
    d F = d theta x F + Lambda dF_C,         d M = d theta x M + Lambda dM_C,

``[dF_C; dM_C] = C [d nu; d kappa]``, and ``d (x_p - x_a) x F`` for the lever arm.  Galerkin:
``B^T C B`` and the variation of ``B^T S = dx'^T F + dtheta^T (F x x') + dtheta'^T M`` at
fixed ``S``, which takes the second variation of the rotation interpolation
(:meth:`ExactBeam._second_variations`).  In the
reference configuration (``R = I``, no stress) the strains are the linear beam's
``u' - theta x t`` and ``theta'`` (eq. T1) and the tangent is the linear beam's stiffness:
linear kinematics is this law's first-order case (``tests/test_exact_beam.py`` holds the
two equal to round-off).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from fvbeam import exact_kernel, rotations
from fvbeam.beam import Beam, InternalForces
from fvbeam.elements import evaluation_points, jumps
from fvbeam.formulations import FiniteVolume, Galerkin
from fvbeam.geometry import cross, skew_matrices
from fvbeam.mesh import shape_functions

#: How many tangent patterns an :class:`ExactBeam` keeps.
PATTERNS = 4


@dataclass(frozen=True)
class ExactState:
    """A configuration of an exact beam: node positions ``x`` (n, 3) and rotations ``R``
    (n, 3, 3) from the reference (identity there)."""

    x: np.ndarray
    R: np.ndarray

    def updated(self, dq: np.ndarray) -> ExactState:
        """The state moved by the dof increments ``dq`` (6 per node, ``[du, dphi]``):
        ``x + du``, ``exp(dphi) R`` (:func:`fvbeam.rotations.update`, run compiled:
        :func:`fvbeam.exact_kernel.update`)."""
        d = np.asarray(dq, dtype=float).reshape(-1, 6)
        turned = exact_kernel.update(np.ascontiguousarray(self.R), np.ascontiguousarray(d[:, 3:]))
        return ExactState(self.x + d[:, :3], turned)


@dataclass(frozen=True)
class PointState:
    """Kinematics and stress at the evaluation points (P of them; ``npe`` nodes each)."""

    psi_nodes: np.ndarray  # (P, npe, 3) relative rotation vectors psi_a
    psi: np.ndarray  # (P, 3)
    dpsi: np.ndarray  # (P, 3) psi'
    Lambda: np.ndarray  # (P, 3, 3)
    x: np.ndarray  # (P, 3) position
    dx: np.ndarray  # (P, 3) x'
    strain: np.ndarray  # (P, 6) [nu, kappa]
    force: np.ndarray  # (P, 3) F, global
    moment: np.ndarray  # (P, 3) M, global

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The fields in their order (as :func:`fvbeam.exact_kernel.points` returns them)."""
        return (
            self.psi_nodes,
            self.psi,
            self.dpsi,
            self.Lambda,
            self.x,
            self.dx,
            self.strain,
            self.force,
            self.moment,
        )


@dataclass(frozen=True)
class Variations:
    """First variations at the points per unit element dof ``[du_a, dphi_a]`` (P, 3 or 6,
    6 npe), and the operators they are made of (module docstring)."""

    theta: np.ndarray  # d theta, the section's spatial rotation
    theta_s: np.ndarray  # d theta'
    x: np.ndarray  # d x
    x_s: np.ndarray  # d x'
    psi: np.ndarray  # d psi
    psi_s: np.ndarray  # d psi'
    psi_nodes: np.ndarray  # d psi_a (P, npe, 3, 6 npe)
    strain: np.ndarray  # d [nu; kappa] (P, 6, 6 npe)
    J: np.ndarray  # J(psi) (P, 3, 3)
    dJ: np.ndarray  # DJ(psi)[psi'] (P, 3, 3)
    Jinv_nodes: np.ndarray  # J(psi_a)^-1 (P, npe, 3, 3)


class ExactBeam:
    """A geometrically exact beam on a linear :class:`~fvbeam.beam.Beam`'s mesh, section
    and formulation (``fv2``, ``fv3``, ``galerkin-p1``, ``galerkin-p2``); the module
    docstring states the law.

    Parameters
    ----------
    beam
        The beam (any formulation but the cubic element, which is refused).
    compiled
        Whether the points, and an fv beam's balances, their floor and tangent, run as the
        compiled kernels of :mod:`fvbeam.exact_kernel` (the default), else as the numpy
        statement here (for reading and testing; the two agree to round-off).
    """

    def __init__(self, beam: Beam, compiled: bool = True) -> None:
        form = beam.formulation
        if not isinstance(form, (FiniteVolume, Galerkin)):
            raise ValueError(
                f"{beam.mesh.name}: exact kinematics is built for the formulations fv2, fv3, "
                f"galerkin-p1 and galerkin-p2, not {form.name}"
            )
        self.beam = beam
        self.compiled = compiled
        #: Whether the balances are the fv regions' (else Galerkin's weak form).
        self.finite_volume = isinstance(form, FiniteVolume)
        mesh = beam.mesh
        npe = mesh.nodes_per_element
        if self.finite_volume:
            Xp = evaluation_points(npe)
            Wp = np.zeros(len(Xp))
        else:
            X, Wp = form.stiffness_quadrature(beam._test_element)
            Xp = X[0]
        n_el, n_p = mesh.n_elements, len(Xp)
        N, dN = shape_functions(Xp, npe)  # (npe, n_p)
        self.npe = npe
        self.reference_node = 0 if npe == 2 else 2
        #: The element of each point (P,), its nodes (P, npe).
        self.element = np.repeat(np.arange(n_el), n_p)
        self.nodes = mesh.cells[self.element]
        frames, metric = beam.centreline(Xp[None, :])  # (n_el, n_p, 3, 3), (n_el, n_p)
        ds = (mesh.element_length[:, None] * metric).ravel()  # d s / d X
        #: Shape functions and their arc-length derivatives at each point (P, npe).
        self.N = np.tile(N.T, (n_el, 1))
        self.dN = np.tile(dN.T, (n_el, 1)) / ds[:, None]
        #: Reference section frames ``[t, e2, e3]`` at each point (P, 3, 3) and their
        #: abscissae (P,).
        self.frames = frames.reshape(-1, 3, 3)
        self.xi = mesh.abscissae(self.element, np.tile(Xp, n_el))
        #: Section stiffness in global axes at each point (P, 6, 6).
        self.C = beam.section.global_stiffness(self.frames)
        #: fv: ``jump_a(p)`` of each point's nodes (P, npe); Galerkin: the quadrature
        #: weights in arc length (P,).
        self.jump = np.tile(jumps(npe).T, (n_el, 1)) if self.finite_volume else np.zeros(0)
        self.weight = np.tile(Wp, n_el) * ds
        self.dx0 = np.einsum("pa,pak->pk", self.dN, mesh.points[self.nodes])
        self.n_dofs = beam.n_dofs
        #: No multipliers (:class:`~fvbeam.exact_statics.StaticOperator`).
        self.position_multipliers = np.zeros(0, dtype=np.int64)
        #: What the compiled kernels read of the beam (:mod:`fvbeam.exact_kernel`): the
        #: points' nodes, the reference node, ``N``, ``N'``, ``x0'``, ``C`` and the jumps
        #: (fv; an empty (0, npe) for Galerkin).
        self.geometry = (
            self.nodes,
            self.reference_node,
            self.N,
            self.dN,
            self.dx0,
            self.C,
            self.jump if self.finite_volume else np.zeros((0, npe)),
        )
        #: The tangent's compressed-column patterns by the dofs kept (:meth:`_pattern`).
        self._patterns: dict[bytes, tuple[np.ndarray, ...]] = {}

    @property
    def name(self) -> str:
        """The beam's name (its mesh's), in messages."""
        return self.beam.mesh.name

    def reference(self) -> ExactState:
        """The reference configuration: the mesh's nodes, identity rotations."""
        n = self.beam.mesh.n_nodes
        return ExactState(self.beam.mesh.points.copy(), np.broadcast_to(np.eye(3), (n, 3, 3)))

    def displacements(self, state: ExactState) -> np.ndarray:
        """Nodal displacements and rotation vectors ``log(R)`` (n, 6): the linear beam's
        ``[u, theta]`` to first order."""
        return np.hstack([state.x - self.beam.mesh.points, rotations.log_map(state.R)])

    # -- kinematics and stress ---------------------------------------------------------
    def points(self, state: ExactState) -> PointState:
        """Strains and stress resultants at the evaluation points (module docstring)."""
        if self.compiled:
            R = np.ascontiguousarray(state.R)
            return PointState(*exact_kernel.points(state.x, R, self.geometry))
        Rr = state.R[self.nodes[:, self.reference_node]]  # (P, 3, 3)
        Rn = state.R[self.nodes]  # (P, npe, 3, 3)
        psi_nodes = rotations.log_map(np.swapaxes(Rr, -1, -2)[:, None] @ Rn)
        psi = np.einsum("pa,pak->pk", self.N, psi_nodes)
        dpsi = np.einsum("pa,pak->pk", self.dN, psi_nodes)
        Lam = Rr @ rotations.exp_map(psi)
        xn = state.x[self.nodes]
        x = np.einsum("pa,pak->pk", self.N, xn)
        dx = np.einsum("pa,pak->pk", self.dN, xn)
        nu = np.einsum("pji,pj->pi", Lam, dx) - self.dx0
        kappa = np.einsum("pji,pj->pi", rotations.left_jacobian(psi), dpsi)
        strain = np.hstack([nu, kappa])
        stress = np.einsum("pij,pj->pi", self.C, strain)
        force = np.einsum("pij,pj->pi", Lam, stress[:, :3])
        moment = np.einsum("pij,pj->pi", Lam, stress[:, 3:])
        return PointState(psi_nodes, psi, dpsi, Lam, x, dx, strain, force, moment)

    @cached_property
    def _dofs(self) -> np.ndarray:
        """Global dofs of each point's element (P, 6 npe)."""
        return (6 * self.nodes[:, :, None] + np.arange(6)).reshape(len(self.nodes), -1)

    def _nodal_terms(self, state: ExactState, pts: PointState) -> np.ndarray:
        """Each point's contributions to its nodes' balances (P, npe, 6)."""
        arm = pts.x[:, None, :] - state.x[self.nodes]  # (P, npe, 3)
        moment = pts.moment[:, None, :] + cross(arm, pts.force[:, None, :])
        terms = np.concatenate([np.broadcast_to(pts.force[:, None, :], arm.shape), moment], axis=-1)
        return self.jump[:, :, None] * terms

    def residual(self, state: ExactState, pts: PointState | None = None) -> np.ndarray:
        """Internal force vector ``r(q)`` (6 per node); equilibrium is ``r = f``.  ``pts``:
        the state's :meth:`points`, when the caller has them."""
        pts = self.points(state) if pts is None else pts
        if self.finite_volume and self.compiled:
            return exact_kernel.fv_residual(state.x, self.geometry, pts.arrays(), self.n_dofs)
        if self.finite_volume:
            terms = self._nodal_terms(state, pts)
        else:
            stress = np.einsum("pij,pj->pi", self.C, pts.strain)
            B = self._variations(state, pts).strain
            terms = self.weight[:, None] * np.einsum("pij,pi->pj", B, stress)
        return np.bincount(self._dofs.ravel(), terms.reshape(-1), minlength=self.n_dofs)

    def residual_floor(self, state: ExactState, pts: PointState | None = None) -> np.ndarray:
        """A bound on each dof's residual (6 per node) in units of its rounding: the sum over
        its terms of ``|F| + |dF|`` and ``|M| + |dM| + |x_p - x_a| (|F| + |dF|)``, with
        ``[dF; dM] = |C| [e_nu; e_kappa]`` the stresses' share of the strains' rounding,
        ``e_nu = |x'| + |x0'| + sum |N_a'| |x_a|`` (the terms of ``nu``, which cancel, and
        the positions' own rounding, ``eps |x_a|``, differenced over an element) and
        ``e_kappa = |kappa| + sum |N_a'| (1 + |psi_a|)`` (the relative rotation vectors carry
        rounding of ``eps (1 + |psi_a|)``).  ``eps`` times this is the residual's round-off
        floor (:mod:`fvbeam.exact_statics`)."""
        pts = self.points(state) if pts is None else pts
        if self.finite_volume and self.compiled:
            return exact_kernel.fv_floor(state.x, self.geometry, pts.arrays(), self.n_dofs)
        e_nu = np.linalg.norm(pts.dx, axis=-1) + np.linalg.norm(self.dx0, axis=-1)
        e_nu += np.einsum("pa,pa->p", np.abs(self.dN), np.linalg.norm(state.x[self.nodes], axis=-1))
        e_kappa = np.linalg.norm(pts.strain[:, 3:], axis=-1) + np.einsum(
            "pa,pa->p", np.abs(self.dN), 1 + np.linalg.norm(pts.psi_nodes, axis=-1)
        )
        errors = np.repeat(np.column_stack([e_nu, e_kappa]), 3, axis=1)
        d_stress = np.einsum("pij,pj->pi", np.abs(self.C), errors)
        if not self.finite_volume:
            bound = np.abs(np.einsum("pij,pj->pi", self.C, pts.strain)) + d_stress
            B = np.abs(self._variations(state, pts).strain)
            terms = self.weight[:, None] * np.einsum("pij,pi->pj", B, bound)
            return np.bincount(self._dofs.ravel(), terms.reshape(-1), minlength=self.n_dofs)
        F = np.linalg.norm(pts.force, axis=-1) + np.linalg.norm(d_stress[:, :3], axis=-1)
        M = np.linalg.norm(pts.moment, axis=-1) + np.linalg.norm(d_stress[:, 3:], axis=-1)
        arm = np.linalg.norm(pts.x[:, None, :] - state.x[self.nodes], axis=-1)  # (P, npe)
        terms = np.abs(self.jump)[:, :, None] * np.concatenate(
            [
                np.broadcast_to(F[:, None, None], arm.shape + (3,)),
                np.broadcast_to((M[:, None] + arm * F[:, None])[..., None], arm.shape + (3,)),
            ],
            axis=-1,
        )
        return np.bincount(self._dofs.ravel(), terms.reshape(-1), minlength=self.n_dofs)

    def internal_forces(self, state: ExactState) -> InternalForces:
        """The section forces at the evaluation (fv) or quadrature (Galerkin) points: in the
        current section frame
        ``Lambda [t, e2, e3]`` (axial force, two shears; twisting moment, two bending moments)
        and in global axes.  Each is the force and couple that the part of the beam beyond
        the point exerts on the part before it; fv: the region balances make them the
        resultant of the loads beyond the point, about it, in the current configuration."""
        pts = self.points(state)
        current = pts.Lambda @ self.frames
        local = np.einsum("pji,pj->pi", current, pts.force)
        return InternalForces(
            self.xi,
            local,
            np.einsum("pji,pj->pi", current, pts.moment),
            pts.force,
            pts.moment,
        )

    # -- tangent ---------------------------------------------------------------------
    def _variations(self, state: ExactState, pts: PointState) -> Variations:
        """The first variations at the points (module docstring)."""
        P, npe, r = len(self.nodes), self.npe, self.reference_node
        Rr = state.R[self.nodes[:, r]]
        RrT = np.swapaxes(Rr, -1, -2)
        # d psi_a = J(psi_a)^-1 R_r^T (dphi_a - dphi_r): (P, npe, 3, 6 npe)
        Jinv = rotations.inverse_left_jacobian(pts.psi_nodes)
        dpsi_a = np.zeros((P, npe, 3, 6 * npe))
        for a in range(npe):
            if a == r:
                continue
            block = Jinv[:, a] @ RrT
            dpsi_a[:, a, :, 6 * a + 3 : 6 * a + 6] += block
            dpsi_a[:, a, :, 6 * r + 3 : 6 * r + 6] -= block
        d_psi = np.einsum("pa,paij->pij", self.N, dpsi_a)
        d_dpsi = np.einsum("pa,paij->pij", self.dN, dpsi_a)
        J = rotations.left_jacobian(pts.psi)
        dJ = rotations.left_jacobian_derivative(pts.psi, pts.dpsi)
        d_theta = Rr @ J @ d_psi
        d_theta[:, :, 6 * r + 3 : 6 * r + 6] += np.eye(3)
        d_theta_s = Rr @ (dJ @ d_psi + J @ d_dpsi)
        d_x = np.zeros((P, 3, 6 * npe))
        d_xs = np.zeros((P, 3, 6 * npe))
        for a in range(npe):
            d_x[:, :, 6 * a : 6 * a + 3] = self.N[:, a, None, None] * np.eye(3)
            d_xs[:, :, 6 * a : 6 * a + 3] = self.dN[:, a, None, None] * np.eye(3)
        LamT = np.swapaxes(pts.Lambda, -1, -2)
        d_nu = LamT @ (d_xs + skew_matrices(pts.dx) @ d_theta)
        d_kappa = LamT @ d_theta_s
        strain = np.concatenate([d_nu, d_kappa], axis=1)
        return Variations(d_theta, d_theta_s, d_x, d_xs, d_psi, d_dpsi, dpsi_a, strain, J, dJ, Jinv)

    def _second_variations(
        self, state: ExactState, pts: PointState, var: Variations, v: np.ndarray, m: np.ndarray
    ) -> np.ndarray:
        """``d (dtheta^T v) + d (dtheta'^T m)`` at fixed ``v``, ``m`` (P, 3) as matrices
        (P, 6 npe, 6 npe): the rotation interpolation's share of a Galerkin beam's geometric
        stiffness.  With ``y = R_r^T v``, ``u = J^T y`` and ``w_a = J(psi_a)^-T u``,
        ``dtheta^T v`` puts ``N_a R_r w_a`` on node ``a``'s rotation and takes it from the
        reference node's; with ``y_m = R_r^T m``,
        ``c_a = N_a DJ(psi)[psi']^T y_m + N_a' J^T y_m`` and ``z_a = J(psi_a)^-T c_a``,
        ``dtheta'^T m`` does so with ``R_r z_a``.  Their variations follow from
        ``d R_r = skew(dphi_r) R_r``, ``d J(psi_a)^-T c = -J^-T L(psi_a, J^-T c) d psi_a``
        (:func:`fvbeam.rotations.transposed_jacobian_derivative` ``L``) and the second
        derivative of ``J^T`` (:func:`~fvbeam.rotations.transposed_jacobian_second_derivative`).
        """
        P, npe, r = len(self.nodes), self.npe, self.reference_node
        Rr = state.R[self.nodes[:, r]]
        RrT = np.swapaxes(Rr, -1, -2)
        JT = np.swapaxes(var.J, -1, -2)
        Er = np.zeros((3, 6 * npe))
        Er[:, 6 * r + 3 : 6 * r + 6] = np.eye(3)
        mv = lambda A, x: np.einsum("pij,pj->pi", A, x)  # noqa: E731 - batched A x
        y = mv(RrT, v)
        u = mv(JT, y)
        du = (
            rotations.transposed_jacobian_derivative(pts.psi, y) @ var.psi
            + (JT @ RrT @ skew_matrices(v)) @ Er
        )
        ym = mv(RrT, m)
        Lm = rotations.transposed_jacobian_derivative(pts.psi, ym)
        L2m = rotations.transposed_jacobian_second_derivative(pts.psi, ym, pts.dpsi)
        dym = RrT @ skew_matrices(m) @ Er
        dJT = np.swapaxes(var.dJ, -1, -2)
        H = np.zeros((P, 6 * npe, 6 * npe))
        for a in range(npe):
            if a == r:
                continue
            JaT = np.swapaxes(var.Jinv_nodes[:, a], -1, -2)
            Na, dNa = self.N[:, a, None, None], self.dN[:, a, None, None]
            psi_a, dpsi_a = pts.psi_nodes[:, a], var.psi_nodes[:, a]
            w = mv(JaT, u)
            Lw = rotations.transposed_jacobian_derivative(psi_a, w)
            d_Rw = -skew_matrices(mv(Rr, w)) @ Er + Rr @ (-JaT @ Lw @ dpsi_a + JaT @ du)
            c = Na[..., 0] * mv(Lm, pts.dpsi) + dNa[..., 0] * mv(JT, ym)
            z = mv(JaT, c)
            dc = Na * (L2m @ var.psi + Lm @ var.psi_s + dJT @ dym) + dNa * (Lm @ var.psi + JT @ dym)
            Lz = rotations.transposed_jacobian_derivative(psi_a, z)
            d_Rz = -skew_matrices(mv(Rr, z)) @ Er + Rr @ (-JaT @ Lz @ dpsi_a + JaT @ dc)
            total = Na * d_Rw + d_Rz
            H[:, 6 * a + 3 : 6 * a + 6] += total
            H[:, 6 * r + 3 : 6 * r + 6] -= total
        return H

    def tangent(
        self, state: ExactState, pts: PointState | None = None, keep: np.ndarray | None = None
    ) -> sp.csc_matrix:
        """``d r / d q`` for the spatial increments ``[du, dphi]`` (material + geometric);
        with ``keep`` (sorted dofs) its rows and columns on those dofs only, assembled so
        (a Newton step's free block)."""
        pts = self.points(state) if pts is None else pts
        keep = np.arange(self.n_dofs) if keep is None else np.asarray(keep)
        dofs = self._dofs
        if self.finite_volume and self.compiled and np.all(keep % 6 < 3):
            # positions only: their block, which the rotations alone set
            square = exact_kernel.fv_position_blocks(self.geometry, pts.arrays())
            dofs = self._position_dofs
        elif self.finite_volume and self.compiled:
            R = np.ascontiguousarray(state.R)
            square = exact_kernel.fv_blocks(state.x, R, self.geometry, pts.arrays())
        else:
            var = self._variations(state, pts)
            blocks = self._fv_blocks if self.finite_volume else self._galerkin_blocks
            square = blocks(state, pts, var)
        inside, order, indices, indptr = self._pattern(keep, dofs)
        data = np.bincount(order, square.ravel()[inside], minlength=len(indices))
        return sp.csc_matrix((data, indices, indptr), shape=(len(keep), len(keep)))

    @cached_property
    def _position_dofs(self) -> np.ndarray:
        """Global position dofs of each point's element (P, 3 npe)."""
        return (6 * self.nodes[:, :, None] + np.arange(3)).reshape(len(self.nodes), -1)

    def _pattern(self, keep: np.ndarray, blocks: np.ndarray) -> tuple[np.ndarray, ...]:
        """The tangent's compressed-column structure on the dofs ``keep`` from the points'
        blocks on the dofs ``blocks`` (:attr:`_dofs` or :attr:`_position_dofs`), built once
        per ``keep``: which entries of the blocks fall inside, the slot of each in the
        matrix's data (duplicates summed there), the rows of the slots and the columns'
        starts.  The few last are kept (a solver alternates the free dofs and the free
        positions)."""
        key = keep.tobytes() + bytes([blocks.shape[1]])
        if key in self._patterns:
            return self._patterns[key]
        if len(self._patterns) >= PATTERNS:
            self._patterns.clear()
        number = np.full(self.n_dofs, -1)
        number[keep] = np.arange(len(keep))
        dofs = number[blocks]
        shape = dofs.shape + dofs.shape[1:]
        rows = np.broadcast_to(dofs[:, :, None], shape).ravel()
        cols = np.broadcast_to(dofs[:, None, :], shape).ravel()
        inside = np.flatnonzero((rows >= 0) & (cols >= 0))
        slots, order = np.unique(cols[inside] * len(keep) + rows[inside], return_inverse=True)
        index = np.int32 if len(slots) < np.iinfo(np.int32).max else np.int64
        indices = (slots % len(keep)).astype(index)
        indptr = np.searchsorted(slots // len(keep), np.arange(len(keep) + 1)).astype(index)
        self._patterns[key] = (inside, order, indices, indptr)
        return self._patterns[key]

    def _fv_blocks(self, state: ExactState, pts: PointState, var: Variations) -> np.ndarray:
        """Each point's tangent block of the region balances (P, 6 npe, 6 npe)."""
        d_stress = np.einsum("pij,pjk->pik", self.C, var.strain)
        F_hat, M_hat = skew_matrices(pts.force), skew_matrices(pts.moment)
        dF = -F_hat @ var.theta + pts.Lambda @ d_stress[:, :3]
        dM = -M_hat @ var.theta + pts.Lambda @ d_stress[:, 3:]
        arm = pts.x[:, None, :] - state.x[self.nodes]  # (P, npe, 3)
        blocks = np.empty((len(self.nodes), self.npe, 6, 6 * self.npe))
        for a in range(self.npe):
            d_arm = var.x.copy()
            d_arm[:, :, 6 * a : 6 * a + 3] -= np.eye(3)
            blocks[:, a, :3] = dF
            blocks[:, a, 3:] = dM + skew_matrices(arm[:, a]) @ dF - F_hat @ d_arm
        blocks *= self.jump[:, :, None, None]
        return blocks.reshape(len(self.nodes), 6 * self.npe, 6 * self.npe)

    def _galerkin_blocks(self, state: ExactState, pts: PointState, var: Variations) -> np.ndarray:
        """Each point's tangent block of the weak form ``int B^T S ds`` (P, 6 npe, 6 npe):
        ``B^T C B`` and the geometric part, the variation of
        ``B^T S = dx'^T F + dtheta^T (F x x') + dtheta'^T M`` at fixed ``S``."""
        T = lambda A: np.swapaxes(A, -1, -2)  # noqa: E731
        B = var.strain
        material = T(B) @ self.C @ B
        F_hat, M_hat = skew_matrices(pts.force), skew_matrices(pts.moment)
        geometric = (
            -T(var.x_s) @ F_hat @ var.theta
            + T(var.theta) @ (skew_matrices(pts.dx) @ F_hat @ var.theta + F_hat @ var.x_s)
            - T(var.theta_s) @ M_hat @ var.theta
            + self._second_variations(state, pts, var, cross(pts.force, pts.dx), pts.moment)
        )
        return self.weight[:, None, None] * (material + geometric)
