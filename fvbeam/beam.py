"""A beam: mesh + section + formulation, assembled with scikit-fem.

Degrees of freedom: six per node, ``[u_x, u_y, u_z, theta_x, theta_y, theta_z]`` in global
axes, node ``k`` of the :class:`~fvbeam.mesh.BeamMesh` owning dofs ``6k .. 6k + 5``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property, partial
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from skfem import CellBasis, MeshLine1, asm
from skfem.assembly import Dofs

from fvbeam import assembly
from fvbeam import mass as beam_mass
from fvbeam.copies import shallow_copy
from fvbeam.forms import distributed_load, generalised_strain, internal_work
from fvbeam.formulations import Cubic, Formulation, composite_gauss
from fvbeam.formulations import formulation as get_formulation
from fvbeam.geometry import section_frames, sized, vector3, wrench
from fvbeam.mesh import BeamMesh
from fvbeam.section import Section
from fvbeam.smearing import KERNEL_GAUSS_POINTS, check_smearing, density, kernel_breaks

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
        ``fv2``, ``fv3``, ``galerkin-p1``, ``galerkin-p2``, ``cubic`` or a
        :class:`Formulation`.
    integration
        ``reduced`` or ``full``; Lagrange Galerkin formulations only.
    """

    def __init__(
        self,
        mesh: BeamMesh,
        section: Section,
        formulation: str | Formulation = "fv3",
        integration: str = "reduced",
    ) -> None:
        _check_type(mesh, BeamMesh, "mesh", "fvbeam.straight(...)")
        _check_type(section, Section, "section", "Section.diagonal(EA=..., ...)")
        if isinstance(formulation, str):
            form = get_formulation(formulation, integration)
        else:
            form = _check_type(formulation, Formulation, "formulation", "'fv3'")
        form.check(mesh)
        self.mesh, self.section, self.formulation = mesh, section, form
        self.skfem_mesh = MeshLine1(mesh.vertex_s[None, :], mesh.cells[:, :2].T.copy())
        self._test_element = form.test_element(mesh, section)
        self._quadrature = form.stiffness_quadrature(self._test_element)
        self._mass: dict[str, sp.csr_matrix] = {}
        #: What a rigid translation leaves unchanged and is built on demand (the recovery
        #: map), shared with translated copies (:meth:`translated`).
        self._shared: dict[str, Any] = {}

    def translated(self, offset: ArrayLike, name: str | None = None) -> "Beam":
        """The same beam moved rigidly by ``offset``, sharing everything a translation leaves
        unchanged (bases, stiffness): they are assembled here, once.  Its mesh is named
        ``name`` (default: this beam's)."""
        _ = self.stiffness
        moved = shallow_copy(self)
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

    def centreline(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The section frames ``[t, e2, e3]`` (nel, nqp, 3, 3) and the metric ``ds / d xi``
        (nel, nqp) at reference points X (1, nqp) of every element
        (:meth:`fvbeam.mesh.BeamMesh.frames`, :meth:`~fvbeam.mesh.BeamMesh.metric`)."""
        dx = self.mesh.element_tangents(X[0])
        metric = np.linalg.norm(dx, axis=-1) / self.mesh.element_length[:, None]
        return section_frames(dx, self.mesh.up), metric

    def geometry(self, X: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Form fields (tangent, metric, global section stiffness) at reference points X
        (1, nqp), and the section frames there, shape (nel, nqp, 3, 3)."""
        frames, metric = self.centreline(X)
        C = self.section.global_stiffness(frames)
        return {
            "t": np.moveaxis(frames[..., 0], -1, 0),
            "metric": metric,
            "C": np.moveaxis(C, (-2, -1), (0, 1)),
        }, frames

    @cached_property
    def trial_basis(self) -> CellBasis:
        """scikit-fem's trial basis on the stiffness quadrature, built when first asked for
        (the recovery and :meth:`reference_stiffness` read it)."""
        element = self.formulation.trial_element(self.mesh, self.section)
        return CellBasis(
            self.skfem_mesh, element, quadrature=self._quadrature, disable_doflocs=True
        )

    @cached_property
    def test_basis(self) -> CellBasis:
        """scikit-fem's test basis on the stiffness quadrature, built when first asked for."""
        return CellBasis(
            self.skfem_mesh,
            self._test_element,
            quadrature=self._quadrature,
            dofs=self._test_dofs,
            disable_doflocs=True,
        )

    @cached_property
    def _test_dofs(self) -> Dofs:
        """The test element's global dof numbering (the trial one's, six per node)."""
        return Dofs(self.skfem_mesh, self._test_element)

    @cached_property
    def _stiffness_geometry(self) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Geometry at the stiffness quadrature points, which are also the recovery points."""
        return self.geometry(self._quadrature[0])

    # -- residual and tangent ------------------------------------------------------------
    @cached_property
    def stiffness(self) -> sp.csr_matrix:
        """Tangent stiffness K (unsymmetric for fv test functions), assembled once: by the
        compiled element blocks of :mod:`fvbeam.assembly` (fv, Galerkin and cubic), which
        equal :meth:`reference_stiffness` to round-off (``tests/test_assembly.py``)."""
        if isinstance(self.formulation, Cubic):
            return assembly.cubic(self.mesh, self.section, "stiffness")
        if not assembly.compiled(self.formulation):
            return self.reference_stiffness()
        frames, metric = self.centreline(self._quadrature[0])
        return assembly.stiffness(
            self.mesh, self.formulation, self.section.stiffness, self._quadrature, frames, metric
        )

    def reference_stiffness(self) -> sp.csr_matrix:
        """The stiffness by its definition: scikit-fem's ``asm`` of the internal-work form
        (eq. T3, :func:`fvbeam.forms.internal_work`) on the trial and test bases."""
        K = asm(internal_work, self.trial_basis, self.test_basis, **self._stiffness_geometry[0])
        return sp.csr_matrix(K)

    def dofs_of(self, q: ArrayLike) -> np.ndarray:
        """``q`` as the beam's dof vector (six per node, :attr:`n_dofs`), or ``ValueError``
        naming its size: the check of every method taking one."""
        return sized(q, self.n_dofs, "q", f"the dofs of beam {self.mesh.name!r}: 6 per node")

    def residual(self, q: ArrayLike) -> np.ndarray:
        """Internal force vector ``r(q)``; equilibrium is ``r(q) = f``. Linear: ``K q``."""
        return self.stiffness @ self.dofs_of(q)

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
    def transfer(self, xi: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Test functions at abscissae ``xi`` as load-transfer matrices (eq. T6), compiled
        (:func:`fvbeam.pointwise.transfer_at`).

        Returns
        -------
        dofs : (n, 6 npe) -- the dofs of the element holding each point
        H : (n, 6 npe, 6) -- nodal loads of a unit force and couple ``[F; M]`` at the point
        dH : (n, 6 npe, 6) -- d H / d xi, where H is smooth (fv: away from the
            evaluation points, across which H jumps)
        """
        e, X = self.mesh.locate(np.atleast_1d(xi))
        H, dH = self.formulation.transfer(self.mesh, self.section, e, X)
        dofs = (6 * self.mesh.cells[e][:, :, None] + np.arange(6)).reshape(len(e), -1)
        return dofs, H, dH

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
        (:mod:`fvbeam.smearing`) and integrated exactly against the test functions, on the
        elements it touches (:meth:`kernel_transfer`); a beam end cutting the kernel rescales
        it so the whole load stays on the beam.  Without smearing the test functions are read
        at ``xi`` by the compiled :meth:`transfer`: the form's Dirac limit (tested equal to
        it) at a fifteenth of its cost, which matters to a moving load's every step.
        """
        smearing = check_smearing(smearing, kernel, self.mesh.length, f"beam {self.mesh.name!r}")
        load = wrench(force, moment)
        if smearing == 0:
            dofs, H, _ = self.transfer(xi)
            dofs, H, mass = dofs[0], H[0], 1.0
        else:
            self.mesh.locate(xi)
            kernels = (partial(density, smearing=smearing, kernel=kernel),)
            dofs, (H,), (mass,) = self.kernel_transfer(float(xi), smearing, kernels)
        f = np.zeros(self.n_dofs)
        f[dofs] = H @ load / mass
        return f

    def kernel_transfer(
        self,
        xi: float,
        smearing: float = 0.0,
        kernels: Sequence[Callable[[np.ndarray], np.ndarray]] = (np.ones_like,),
        window: tuple[float, float] | None = None,
    ) -> tuple[np.ndarray, list[np.ndarray], list[float]]:
        """A kernel at ``xi`` of half-width ``smearing`` integrated against the test functions
        (eq. T6) by the scikit-fem form :func:`fvbeam.forms.distributed_load`.

        For each function ``g`` of the offset ``r = s - xi`` in ``kernels`` (a kernel density,
        its slope...): the load-transfer matrix ``int g(s - xi) H(s) ds`` (k, 6) -- the nodal
        loads of the unit force and couple spread with density ``g`` -- and ``int g ds``.
        It is the distributed load (eq. T5) of the densities ``g e_c``, ``c = 1..6``, measured
        in the abscissa (metric 1), in which the kernel is a density; one assembly gives all
        of them (:meth:`_kernel_basis`).

        ``smearing`` 0 is the Dirac delta: the one-point rule at ``xi`` of weight 1 (a point on
        a vertex is read in the element after it), where ``g`` should be 1.  ``smearing > 0``:
        the part of ``[xi - smearing, xi + smearing]`` inside ``window`` (default the beam;
        ``xi`` need not lie on it), on the elements it touches.

        Returns
        -------
        dofs : (k,) -- the dofs of those elements
        H : one (k, 6) matrix per kernel function
        mass : ``int g ds`` per kernel function
        """
        basis = self._kernel_basis(xi, smearing, window, 6 * len(kernels))
        n = len(basis.tind) // (6 * len(kernels))
        r = np.asarray(basis.global_coordinates())[0, :n] - xi
        values = np.stack([g(r) for g in kernels])
        # copy 6 k + c of the elements carries the unit load e_c spread by kernel k
        fields = np.einsum("cd,knq->dkcnq", np.eye(6), values).reshape(6, -1, r.shape[-1])
        local = distributed_load.elemental(
            basis, f=fields[:3], m=fields[3:], metric=np.ones(fields.shape[1:])
        ).tolocal()
        local = local.reshape(len(kernels), 6, n, -1)
        element_dofs = basis.element_dofs[:, :n]
        dofs, where = np.unique(element_dofs, return_inverse=True)
        H = np.zeros((len(kernels), len(dofs), 6))
        # numpy's stubs reject the slice in ufunc.at's index tuple, which numpy takes
        index = (slice(None), where.reshape(element_dofs.shape).T)
        np.add.at(H, index, np.moveaxis(local, 1, -1))  # type: ignore[arg-type]
        return dofs, list(H), [float(np.sum(v * basis.dx[:n])) for v in values]

    def kernel_points(
        self, xi: float, smearing: float, window: tuple[float, float] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The abscissae and weights (in the abscissa) of the quadrature that integrates a
        kernel at ``xi`` of half-width ``smearing`` against the test functions exactly
        (:meth:`_kernel_basis`): ``smearing`` 0, the one-point rule at ``xi`` of weight 1;
        else composite 3-point Gauss rules on the part of ``[xi - smearing, xi + smearing]``
        inside ``window`` (default the beam), split at the element ends, the test functions'
        break points and the kernel's.  ``ValueError`` if the kernel does not reach
        ``window``."""
        if smearing == 0:
            return np.array([xi]), np.array([1.0])
        start, end = (0.0, self.mesh.length) if window is None else window
        lo, hi = max(start, xi - smearing), min(end, xi + smearing)
        if hi <= lo:
            raise ValueError(
                f"{self.mesh.name}: the kernel at xi = {xi} of half-width {smearing} "
                f"does not reach [{start}, {end}] of the beam"
            )
        vertices = self.mesh.vertex_s
        touched = np.flatnonzero((vertices[:-1] < hi) & (vertices[1:] > lo))
        local = self.mesh.abscissae(touched[:, None], self.formulation.breakpoints())
        breaks = np.concatenate([local.ravel(), kernel_breaks(xi, smearing)])
        return composite_gauss(np.unique(np.clip(breaks, lo, hi)), KERNEL_GAUSS_POINTS)

    def _kernel_basis(
        self, xi: float, smearing: float, window: tuple[float, float] | None, copies: int
    ) -> CellBasis:
        """The test basis on the elements a kernel at ``xi`` of half-width ``smearing``
        touches, with a quadrature integrating the kernel against the test functions exactly,
        the elements and their rules repeated ``copies`` times (copy-major) so that one
        assembly integrates ``copies`` loads, one per copy.

        The points are :meth:`kernel_points`: on each piece between their breaks kernel
        times test function is a polynomial of degree at most 3 in the abscissa.  The
        weights measure the abscissa ``xi``, the affine element coordinate that scikit-fem
        sees (``|det J| = h_e``).  Each element takes its own points (scikit-fem's points
        (1, nel, nq) and weights (nel, nq)), padded with zero weights to a common count.
        Raises ``ValueError`` if the kernel does not reach ``window``.
        """
        s, w = self.kernel_points(xi, smearing, window)
        e, X = self.mesh.locate(s)
        elements, first, counts = np.unique(e, return_index=True, return_counts=True)
        row = np.repeat(np.arange(len(elements)), counts)
        column = np.arange(len(e)) - first[row]
        points, weights = np.zeros((2, len(elements), counts.max()))
        points[row, column] = X
        weights[row, column] = w / self.mesh.element_length[e]
        return CellBasis(
            self.skfem_mesh,
            self._test_element,
            quadrature=(np.tile(points, (copies, 1))[None], np.tile(weights, (copies, 1))),
            elements=np.tile(elements, copies),
            dofs=self._test_dofs,
            disable_doflocs=True,
        )

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
        fields = {k: sample_field(v, xi, k) for k, v in (("f", force), ("m", moment))}
        return asm(distributed_load, basis, metric=geometry["metric"], **fields)

    # -- recovery -------------------------------------------------------------------------
    @property
    def recovery_abscissae(self) -> np.ndarray:
        """Abscissae of the recovery points (the stiffness quadrature points: fv evaluation
        points, Galerkin Gauss points), element by element, ``(n,)``."""
        return self._recovery[1]

    @property
    def recovery_frames(self) -> np.ndarray:
        """The section frames ``[t, e2, e3]`` (columns) at the recovery points, ``(n, 3,
        3)``: a section force ``f`` there is ``frames @ f`` in global axes."""
        return self._stiffness_geometry[1].reshape(-1, 3, 3)

    @property
    def recovery(self) -> sp.csr_matrix:
        """The internal forces at the recovery points as a linear map of the beam's dofs:
        ``(recovery @ q).reshape(-1, 6)`` is ``[N, V2, V3, T, M2, M3]`` at each point, in
        its section frame (:meth:`internal_forces`), built once and shared by translated
        copies."""
        return self._recovery[0]

    @property
    def _recovery(self) -> tuple[sp.csr_matrix, np.ndarray]:
        """Eq. (T2) at the recovery points, ``[F; M] = R^T C [nu; kappa]`` with the strains
        of eq. (T1), for every trial basis function of every element at once: the column of
        dof ``element_dofs[i, e]`` holds the section forces of basis function ``i`` at the
        points of element ``e``.  Any trial element (scikit-fem's ``basis.basis``: values and
        gradients of each local function) gives its own map."""
        if "recovery" not in self._shared:
            geometry, frames = self._stiffness_geometry
            basis = self.trial_basis
            RT = np.swapaxes(frames, -1, -2)  # (nel, nqp, 3, 3), global to section axes
            local = []
            for functions in basis.basis:
                strain = generalised_strain(functions[0], geometry["t"], geometry["metric"])
                stress = np.einsum("ij...,j...->...i", geometry["C"], strain)
                local.append(
                    np.concatenate(
                        [RT @ stress[..., :3, None], RT @ stress[..., 3:, None]], axis=-2
                    )[..., 0]
                )
            values = np.stack(local)  # (local function, element, point, component)
            n_functions, n_elements, n_points = values.shape[:3]
            rows = np.arange(n_elements * n_points * 6).reshape(values.shape[1:])
            columns = basis.element_dofs[:, :, None, None]
            R = sp.csr_matrix(
                (
                    values.ravel(),
                    (
                        np.broadcast_to(rows, values.shape).ravel(),
                        np.broadcast_to(columns, values.shape).ravel(),
                    ),
                ),
                shape=(n_elements * n_points * 6, self.n_dofs),
            )
            R.eliminate_zeros()
            X = basis.X[0]
            xi = self.mesh.abscissae(np.arange(n_elements)[:, None], X).ravel()
            self._shared["recovery"] = (R, xi)
        return self._shared["recovery"]

    def internal_forces(self, q: ArrayLike) -> InternalForces:
        """Internal forces at the recovery points, in section and global axes (eq. T2 on the
        strains of eq. T1: :attr:`recovery` times ``q``)."""
        R, xi = self._recovery
        section = (R @ self.dofs_of(q)).reshape(-1, 2, 3)
        frames = self._stiffness_geometry[1].reshape(-1, 3, 3)
        world = frames[:, None] @ section[..., None]
        return InternalForces(
            xi, section[:, 0], section[:, 1], world[:, 0, :, 0], world[:, 1, :, 0]
        )

    def displacements(self, q: ArrayLike, xi: np.ndarray | float) -> np.ndarray:
        """Displacement and rotation ``(n, 6)`` at abscissae ``xi`` (trial interpolation,
        :meth:`Formulation.interpolation`)."""
        e, X = self.mesh.locate(np.atleast_1d(xi))
        trial = self.formulation.interpolation(self.mesh, self.section, e, X)
        nodal = self.dofs_of(q).reshape(-1, 6)[self.mesh.cells[e]].reshape(len(e), -1)
        return np.einsum("nkc,nk->nc", trial, nodal)


def internal_forces_reference(beam: Beam, q: ArrayLike) -> np.ndarray:
    """Section forces ``[N, V2, V3, T, M2, M3]`` at the recovery points, ``(n, 6)``, through
    scikit-fem's interpolation of the trial field: eq. (T1) on the interpolated field, then
    (T2) and the rotation to the section frame, point by point.  The definition
    :attr:`Beam.recovery` is held to (``tests/test_recovery.py``), a product with it cheaper
    by far for a state's every step."""
    geometry, frames = beam._stiffness_geometry
    field = beam.trial_basis.interpolate(beam.dofs_of(q))
    strain = generalised_strain(field, geometry["t"], geometry["metric"])
    stress = np.einsum("ij...,j...->...i", geometry["C"], strain).reshape(-1, 2, 3)
    RT = np.swapaxes(frames, -1, -2).reshape(-1, 1, 3, 3)
    return (RT @ stress[..., None]).reshape(-1, 6)


def sample_field(value: Field, xi: np.ndarray, name: str) -> np.ndarray:
    """A constant 3-vector or a function of xi, as a (3, nel, nqp) field."""
    if callable(value):
        out = np.asarray(value(xi.ravel()), dtype=float)
        if out.shape != (xi.size, 3) or not np.all(np.isfinite(out)):
            raise ValueError(f"distributed load {name!r} must return finite (n, 3) values")
        return np.moveaxis(out.reshape(xi.shape + (3,)), -1, 0)
    v = vector3(value, f"distributed load {name!r}")
    return np.broadcast_to(v[:, None, None], (3,) + xi.shape).copy()


def _check_type(value: object, kind: type, name: str, example: str) -> Any:
    """``value`` if it is a ``kind``, else ``ValueError`` naming the argument ``name``, the
    type found and an example of the right one."""
    if not isinstance(value, kind):
        raise ValueError(
            f"{name} must be a {kind.__name__} (e.g. {example}), "
            f"got {type(value).__name__} {value!r:.60}"
        )
    return value
