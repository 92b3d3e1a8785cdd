"""A beam: mesh + section + formulation, assembled with scikit-fem.

Degrees of freedom: six per node, ``[u_x, u_y, u_z, theta_x, theta_y, theta_z]`` in global
axes, node ``k`` of the :class:`~fvbeam.mesh.BeamMesh` owning dofs ``6k .. 6k + 5``.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from skfem import CellBasis, MeshLine1, asm

from fvbeam import mass as beam_mass
from fvbeam.forms import distributed_load, generalised_strain, internal_work
from fvbeam.formulations import Formulation, composite_gauss
from fvbeam.formulations import formulation as get_formulation
from fvbeam.geometry import vector3, wrench
from fvbeam.mesh import BeamMesh, shape_functions
from fvbeam.section import Section
from fvbeam.smearing import check_smearing, density, kernel_breaks

Field = ArrayLike | Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class InternalForces:
    """Internal forces at the recovery points (fv: evaluation points; Galerkin: Gauss points).

    ``force`` and ``moment`` are ``(n, 3)`` in the section frame ``(t, e2, e3)``: axial force,
    two shears; twisting moment, two bending moments.  ``*_global`` in global axes.
    """

    xi: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    force_global: np.ndarray
    moment_global: np.ndarray


class Beam:
    """Assembled linear Timoshenko beam.

    Parameters
    ----------
    mesh
        The centreline.
    section
        Section properties (uniform along the beam).
    formulation
        ``fv2``, ``fv3``, ``galerkin-p1``, ``galerkin-p2`` or a :class:`Formulation`.
    integration
        ``reduced`` or ``full``; Galerkin formulations only.
    """

    def __init__(
        self,
        mesh: BeamMesh,
        section: Section,
        formulation: str | Formulation = "fv3",
        integration: str = "reduced",
    ) -> None:
        form = (
            get_formulation(formulation, integration)
            if isinstance(formulation, str)
            else formulation
        )
        form.check(mesh)
        self.mesh, self.section, self.formulation = mesh, section, form
        self.skfem_mesh = MeshLine1(mesh.vertex_s[None, :], mesh.cells[:, :2].T.copy())
        self._test_element = form.test_element(mesh)
        quadrature = form.stiffness_quadrature(self._test_element)
        self.trial_basis = CellBasis(self.skfem_mesh, form.trial_element(), quadrature=quadrature)
        self.test_basis = CellBasis(
            self.skfem_mesh, self._test_element, quadrature=quadrature, disable_doflocs=True
        )
        self._mass: dict[str, sp.csr_matrix] = {}

    def translated(self, offset: ArrayLike, name: str | None = None) -> "Beam":
        """The same beam moved rigidly by ``offset``, sharing everything a translation leaves
        unchanged (bases, stiffness, transfer jumps): they are assembled here, once.  Its mesh
        is named ``name`` (default: this beam's)."""
        self.stiffness, self.transfer_jumps()
        moved = copy.copy(self)
        moved.mesh = self.mesh.translated(vector3(offset, "offset"), name)
        return moved

    @property
    def n_dofs(self) -> int:
        return 6 * self.mesh.n_nodes

    def node_index(self, node: int | str) -> int:
        """Mesh node index from an index or ``'start'`` / ``'end'`` (the end vertices)."""
        if node == "start":
            return 0
        if node == "end":
            return self.mesh.n_elements
        if isinstance(node, (int, np.integer)) and 0 <= node < self.mesh.n_nodes:
            return int(node)
        raise ValueError(
            f"{self.mesh.name}: node {node!r} is not 'start', 'end' or an index "
            f"in 0..{self.mesh.n_nodes - 1}"
        )

    def node_dofs(self, node: int | str) -> np.ndarray:
        """The six dofs of a mesh node (index, ``'start'`` or ``'end'``)."""
        return 6 * self.node_index(node) + np.arange(6)

    def geometry(self, X: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Form fields (tangent, metric, global section stiffness) at reference points X
        (1, nqp), and the section frames there, shape (nel, nqp, 3, 3)."""
        e = np.repeat(np.arange(self.mesh.n_elements)[:, None], X.shape[-1], axis=1)
        Xe = np.broadcast_to(X[0], e.shape)
        dx = self.mesh.tangent_vectors(e, Xe)
        frames = self.mesh.frames(e, Xe)
        C = self.section.global_stiffness(frames)
        return {
            "t": np.moveaxis(dx / np.linalg.norm(dx, axis=-1, keepdims=True), -1, 0),
            "metric": self.mesh.metric(e, Xe),
            "C": np.moveaxis(C, (-2, -1), (0, 1)),
        }, frames

    @cached_property
    def _stiffness_geometry(self) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Geometry at the stiffness quadrature points, which are also the recovery points."""
        return self.geometry(self.trial_basis.X)

    # -- residual and tangent ------------------------------------------------------------
    @cached_property
    def stiffness(self) -> sp.csr_matrix:
        """Tangent stiffness K (unsymmetric for fv test functions), assembled once."""
        K = asm(internal_work, self.trial_basis, self.test_basis, **self._stiffness_geometry[0])
        return sp.csr_matrix(K)

    def residual(self, q: np.ndarray) -> np.ndarray:
        """Internal force vector ``r(q)``; equilibrium is ``r(q) = f``. Linear: ``K q``."""
        return self.stiffness @ q

    def tangent(self, q: np.ndarray) -> sp.csr_matrix:
        """d r / d q (constant for linear kinematics)."""
        return self.stiffness

    def mass(self, kind: str = "lumped") -> sp.csr_matrix:
        """Mass matrix, ``lumped`` or ``consistent`` (Galerkin only), assembled once per kind
        (:mod:`fvbeam.mass`); a rigid translation leaves it unchanged, so a translated copy
        shares it."""
        beam_mass.check_kind(self, kind)
        if kind not in self._mass:
            self._mass[kind] = getattr(beam_mass, kind)(self)
        return self._mass[kind]

    # -- loads ----------------------------------------------------------------------------
    def transfer(self, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Test functions at abscissae ``xi`` as load-transfer matrices (eq. T6).

        Returns
        -------
        dofs : (n, 6 npe) -- the dofs of the element holding each point
        H : (n, 6 npe, 6) -- nodal loads of a unit force and couple ``[F; M]`` at the point
        dH : (n, 6 npe, 6) -- d H / d xi, where H is smooth (fv: away from the
            evaluation points, across which H jumps)
        """
        e, X = self.mesh.locate(np.atleast_1d(xi))
        H, dH = self.formulation.transfer(self.mesh, e, X)
        dofs = (6 * self.mesh.cells[e][:, :, None] + np.arange(6)).reshape(len(e), -1)
        return dofs, H, dH

    @cached_property
    def _transfer_jumps(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        e, X, J = self.formulation.transfer_jumps(self.mesh)
        dofs = (6 * self.mesh.cells[e][:, :, None] + np.arange(6)).reshape(len(e), J.shape[1])
        return self.mesh.abscissae(e, X), dofs, J

    def transfer_jumps(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Abscissae (m,), dofs (m, 6 npe) and jumps ``H(xi+) - H(xi-)`` (m, 6 npe, 6) of the
        transfer matrices inside the beam (fv: at the evaluation points; Galerkin: none)."""
        return self._transfer_jumps

    def nodal_load(
        self,
        node: int | str,
        force: ArrayLike = (0.0, 0.0, 0.0),
        moment: ArrayLike = (0.0, 0.0, 0.0),
    ) -> np.ndarray:
        """Load vector of a force and couple applied directly to a mesh node."""
        f = np.zeros(self.n_dofs)
        f[self.node_dofs(node)] = wrench(force, moment)
        return f

    def point_load(
        self,
        xi: float,
        force: ArrayLike = (0.0, 0.0, 0.0),
        moment: ArrayLike = (0.0, 0.0, 0.0),
        smearing: float = 0.0,
        kernel: str = "box",
    ) -> np.ndarray:
        """Load vector of a force and couple at abscissa ``xi`` (eq. T6).

        With ``smearing > 0`` the load is spread by a kernel of half-width ``smearing``
        (:mod:`fvbeam.smearing`) and integrated exactly against the test functions.
        """
        smearing = check_smearing(smearing, kernel)
        load = wrench(force, moment)
        if smearing == 0:
            points, weights = np.array([float(xi)]), np.array([1.0])
        else:
            self.mesh.locate(xi)
            points, weights = self._kernel_quadrature(float(xi), smearing, kernel)
        dofs, values, _ = self.transfer(points)
        f = np.zeros(self.n_dofs)
        np.add.at(f, dofs, np.einsum("n,nij,j->ni", weights, values, load))
        return f

    def _kernel_quadrature(
        self, xi: float, smearing: float, kernel: str
    ) -> tuple[np.ndarray, np.ndarray]:
        """Points and weights integrating kernel x test function exactly on the beam."""
        e, _ = self.mesh.locate(np.clip([xi - smearing, xi + smearing], 0, self.mesh.length))
        local = self.formulation.breakpoints()
        elements = np.arange(e[0], e[1] + 1)
        breaks = self.mesh.abscissae(elements[:, None], local).ravel()
        breaks = np.concatenate([breaks, kernel_breaks(xi, smearing)])
        breaks = np.unique(
            np.clip(breaks, max(xi - smearing, 0.0), min(xi + smearing, self.mesh.length))
        )
        s, w = composite_gauss(breaks, 3)
        w = w * density(s - xi, smearing, kernel)
        return s, w / w.sum()

    def distributed_load(
        self, force: Field = (0.0, 0.0, 0.0), moment: Field = (0.0, 0.0, 0.0)
    ) -> np.ndarray:
        """Load vector of a force and couple per unit length, constant or functions of ``xi``.

        A callable receives the abscissae, shape (n,), and returns (n, 3).
        """
        X, W = self.formulation.load_quadrature()
        basis = CellBasis(
            self.skfem_mesh, self._test_element, quadrature=(X, W), disable_doflocs=True
        )
        geometry, _ = self.geometry(X)
        xi = self.mesh.abscissae(np.arange(self.mesh.n_elements)[:, None], X)
        fields = {k: _sample(v, xi, k) for k, v in (("f", force), ("m", moment))}
        return asm(distributed_load, basis, metric=geometry["metric"], **fields)

    # -- recovery -------------------------------------------------------------------------
    def internal_forces(self, q: np.ndarray) -> InternalForces:
        """Internal forces at the recovery points, in section and global axes."""
        geometry, frames = self._stiffness_geometry
        field = self.trial_basis.interpolate(q)
        strain = generalised_strain(field, geometry["t"], geometry["metric"])
        stress = np.einsum("ij...,j...->...i", geometry["C"], strain).reshape(-1, 6)
        RT = np.swapaxes(frames, -1, -2).reshape(-1, 3, 3)
        X = self.trial_basis.X[0]
        xi = self.mesh.abscissae(np.arange(self.mesh.n_elements)[:, None], X).ravel()
        return InternalForces(
            xi,
            np.einsum("nij,nj->ni", RT, stress[:, :3]),
            np.einsum("nij,nj->ni", RT, stress[:, 3:]),
            stress[:, :3],
            stress[:, 3:],
        )

    def displacements(self, q: np.ndarray, xi: np.ndarray | float) -> np.ndarray:
        """Displacement and rotation ``(n, 6)`` at abscissae ``xi`` (trial interpolation)."""
        e, X = self.mesh.locate(np.atleast_1d(xi))
        N, _ = shape_functions(X, self.mesh.nodes_per_element)
        nodal = q.reshape(-1, 6)[self.mesh.cells[e]]
        return np.einsum("an,nac->nc", N, nodal)


def _sample(value: Field, xi: np.ndarray, name: str) -> np.ndarray:
    """A constant 3-vector or a function of xi, as a (3, nel, nqp) field."""
    if callable(value):
        out = np.asarray(value(xi.ravel()), dtype=float)
        if out.shape != (xi.size, 3) or not np.all(np.isfinite(out)):
            raise ValueError(f"distributed load {name!r} must return finite (n, 3) values")
        return np.moveaxis(out.reshape(xi.shape + (3,)), -1, 0)
    v = vector3(value, f"distributed load {name!r}")
    return np.broadcast_to(v[:, None, None], (3,) + xi.shape).copy()
