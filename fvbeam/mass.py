"""Beam mass matrices (``docs/dynamics.md``).

Both kinds act on the beam's dofs ``[u, theta]`` per node (global axes) and carry the section's
mass per length ``m`` on the translations and its inertia per length ``J`` (section frame,
rotated to global axes as ``R J R^T``) on the rotations; the translation-rotation coupling of an
offset centre of mass is not modelled (the section has no such offset).

``lumped``
    Block-diagonal: node ``a`` gets ``int phi_a (m I, R J R^T) ds`` with ``phi_a`` its weight
    function.  Finite volume: ``phi_a`` is the indicator of the node's influence region
    (:func:`fvbeam.elements.indicator`), so the node carries the mass and the section rotary
    inertia of its region, as point mass and rotary inertia *at the node*: the region's
    centroid offset (end regions) and its own length inertia ``m l^2 / 12`` about the
    transverse axes are **not** added.  That inertia is the translational mass spread along the
    region, which the translations of the neighbouring nodes already represent; adding it
    counts it twice, an O(h^2) spurious rotary inertia (the tests of the reference
    implementation, MBDyn's ``beam slider``, add it to their nodal bodies).
    Galerkin: ``phi_a`` is the shape function ``N_a``, which is the block row sum of the
    consistent matrix (``sum_b N_b = 1``); for P2 the weights ``1/6, 2/3, 1/6`` of Simpson's
    rule are positive.  Cubic: ``phi_a`` is the linear ``N_a`` of its two nodes (half the
    element's mass and section inertia on each node), which lumps away the interpolation's
    coupling of deflections and rotations: first order in the mass, so second order in the
    frequencies, against the fourth of the consistent mass (``docs/theory.md`` Sec. 9).
``consistent``
    Galerkin and cubic: ``int N_a . N_b`` of the trial functions, ``N_a`` the field
    ``(u, theta)`` of dof ``a``, weighted by ``(m I, R J R^T)``, on a Gauss rule exact for
    the product of two trial functions on straight elements (``degree + 1`` points):
    assembled with scikit-fem (:func:`fvbeam.forms.inertia`), the cubic element's compiled
    (:func:`fvbeam.assembly.cubic`).  The cubic element's deflections
    read its nodal rotations, so its mass couples them (eq. T12).  The fv test functions are
    not the trial ones, so a "consistent" fv mass would be a Petrov-Galerkin product; it is
    not offered.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from skfem import CellBasis, MeshLine1, asm

from fvbeam import assembly
from fvbeam.elements import indicator
from fvbeam.forms import inertia
from fvbeam.formulations import Cubic, FiniteVolume, Formulation, gauss
from fvbeam.mesh import BeamMesh, shape_functions
from fvbeam.section import Section


class MassSource(Protocol):
    """What a mass matrix reads of a beam (:class:`fvbeam.beam.Beam` is one)."""

    mesh: BeamMesh
    section: Section
    formulation: Formulation
    skfem_mesh: MeshLine1

    def centreline(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...


#: Mass matrix kinds.
KINDS = ("lumped", "consistent")


def check_kind(beam: MassSource, kind: str) -> None:
    """``ValueError`` naming the beam when ``kind`` is unknown, or not available for its
    formulation, or when its section has no mass."""
    name = f"beam {beam.mesh.name!r} ({beam.formulation.name})"
    if kind not in KINDS:
        raise ValueError(f"{name}: unknown mass kind {kind!r}; choose one of {', '.join(KINDS)}")
    if kind == "consistent" and isinstance(beam.formulation, FiniteVolume):
        raise ValueError(
            f"{name}: finite-volume beams take the lumped mass only (their test "
            "functions are not their shape functions)"
        )
    if beam.section.mass_per_length <= 0:
        raise ValueError(
            f"{name}: section {beam.section.name!r} has mass_per_length "
            f"{beam.section.mass_per_length:g}; give it a positive mass per length "
            "to assemble a mass matrix"
        )


def acceleration(n_dofs: int, g: ArrayLike) -> np.ndarray:
    """A uniform acceleration ``g`` (a 3-vector) on every node's translations, none on its
    rotations: a global vector of ``n_dofs`` rows (six per node)."""
    return np.tile(np.concatenate([np.asarray(g, dtype=float), np.zeros(3)]), n_dofs // 6)


def weight(M: sp.spmatrix, g: ArrayLike) -> np.ndarray:
    """The load of gravity ``g`` on the masses ``M``, ``M a`` with ``a`` the uniform
    :func:`acceleration`.  A beam's lumped mass gives ``int phi_a m g ds`` at node ``a``: the
    distributed load ``m g`` on its test functions (finite volume) or shape functions
    (Galerkin; the cubic element's consistent mass gives its consistent load, end couples
    included); a rigid body's gives its weight at its centre of mass, a force and its moment
    about the body's node."""
    return M @ acceleration(M.shape[0], g)


def _section_fields(beam: MassSource, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Global section inertia ``R J R^T`` (nel, nqp, 3, 3) and ``ds / dX`` (nel, nqp) at
    reference points ``X`` (1, nqp)."""
    frames, metric = beam.centreline(X)
    J = frames @ beam.section.inertia @ np.swapaxes(frames, -1, -2)
    return J, metric * beam.mesh.element_length[:, None]


def lumped(beam: MassSource) -> sp.csr_matrix:
    """Block-diagonal mass: each node carries ``int phi_a (m, R J R^T) ds`` (module doc)."""
    npe = beam.mesh.nodes_per_element
    X, W = beam.formulation.load_quadrature()
    if isinstance(beam.formulation, FiniteVolume):
        phi = indicator(X[0], npe)
    else:
        phi = shape_functions(X[0], npe)[0]
    J, ds = _section_fields(beam, X)
    weight = np.einsum("aq,q,eq->ea", phi, W, ds)  # (nel, npe)
    rotary = np.einsum("aq,q,eq,eqij->eaij", phi, W, ds, J)  # (nel, npe, 3, 3)
    blocks = np.zeros((beam.mesh.n_nodes, 6, 6))
    np.add.at(
        blocks[:, :3, :3],
        beam.mesh.cells,
        beam.section.mass_per_length * weight[..., None, None] * np.eye(3),
    )
    np.add.at(blocks[:, 3:, 3:], beam.mesh.cells, rotary)
    n = beam.mesh.n_nodes
    M = sp.bsr_matrix((blocks, np.arange(n), np.arange(n + 1)), shape=(6 * n, 6 * n)).tocsr()
    M.eliminate_zeros()
    return M


def consistent(beam: MassSource) -> sp.csr_matrix:
    """Galerkin mass ``int N_a . (m I, R J R^T) N_b ds`` on the trial functions: the cubic
    element's compiled (:func:`fvbeam.assembly.cubic`, equal to :func:`reference_consistent`
    to round-off), the others' by :func:`reference_consistent`."""
    if isinstance(beam.formulation, Cubic):
        return assembly.cubic(beam.mesh, beam.section, "consistent")
    return reference_consistent(beam)


def reference_consistent(beam: MassSource) -> sp.csr_matrix:
    """Galerkin mass ``int N_a . (m I, R J R^T) N_b ds`` (scikit-fem, :func:`forms.inertia`)
    on the trial functions, Gauss rule of ``degree + 1`` points: the definition."""
    X, W = gauss(beam.formulation.degree + 1)
    basis = CellBasis(
        beam.skfem_mesh,
        beam.formulation.trial_element(beam.mesh, beam.section),
        quadrature=(X[None, :], W),
        disable_doflocs=True,
    )
    J, ds = _section_fields(beam, X[None, :])
    metric = ds / beam.mesh.element_length[:, None]
    M = asm(
        inertia,
        basis,
        m=np.full(metric.shape, beam.section.mass_per_length),
        J=np.moveaxis(J, (-2, -1), (0, 1)),
        metric=metric,
    )
    return sp.csr_matrix(M)
