"""The stiffness of a beam assembled element by element into 6x6 node blocks, compiled (numba).

The definition of the stiffness is the scikit-fem form :func:`fvbeam.forms.internal_work`
(eq. T3) on the trial and test bases of :class:`fvbeam.beam.Beam`, assembled by
``skfem.asm`` (:meth:`fvbeam.beam.Beam.reference_stiffness`).  scikit-fem evaluates a form
once per pair of an element's local functions, each time over arrays of all elements'
quadrature points: for a 3-node element, 324 passes over the mesh, each computing both
strains and contracting the 6x6 section stiffness again, and a coordinate list of
``324 n_elements`` entries before the sparse matrix is summed (``docs/performance.md``,
"Large meshes").  :func:`element_blocks` computes the same integral element by element, in
one pass: per quadrature point the section forces of each trial function once, then their
work on each test function, added into the 6x6 block of each pair of nodes
(:func:`node_blocks`, the pattern of a block-sparse matrix).  It applies to the formulations
with Lagrange trial functions: finite volume and Galerkin (:func:`compiled`); the others are
assembled by scikit-fem.

With ``d/ds`` the derivative in arc length, ``t`` the unit tangent, ``C`` the section
stiffness in global axes (eq. T2), trial function ``N_b e_k`` of node ``b`` has the
generalised strain (eq. T1)::

    k < 3:   eps = [dN_b/ds e_k; 0]
    k >= 3:  eps = [-N_b e_(k-3) x t; dN_b/ds e_(k-3)]

and the section force and moment ``sigma = C eps``.  A Galerkin test function ``N_a e_c``
(strain likewise) takes ``int eps_a . sigma_b ds``; an fv test function of node ``a`` (eq.
T4) is a rigid motion of its influence region, strain-free inside it, so its work is that of
the spikes of the region's indicator at the evaluation points ``p``: ``jump_a(p)`` times the
force ``F`` and the moment about the node ``M + (x_p - x_a) x F`` of ``sigma`` there (the
region's balance, ``docs/theory.md`` eq. T7).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np
import scipy.sparse as sp

from fvbeam.elements import jumps
from fvbeam.formulations import FiniteVolume, Formulation, Galerkin, gauss
from fvbeam.kernel_cache import guard
from fvbeam.mesh import BeamMesh
from fvbeam.pointwise import cubic_local_at, shape_at
from fvbeam.section import Section

guard(__file__)  # numba's cache of these kernels, consistent with their sources


def compiled(formulation: Formulation) -> bool:
    """Whether :func:`stiffness` assembles the formulation: Lagrange trial functions with fv
    or Galerkin test functions."""
    return isinstance(formulation, (FiniteVolume, Galerkin))


def node_blocks(cells: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pairs of nodes that the elements ``cells`` (nel, npe) couple, compressed by rows.

    Returns
    -------
    indptr, indices : the coupled node pairs, by row node (columns sorted)
    block : (nel, npe, npe) -- the position among them of each element's pair (row node
        ``a``, column node ``b``)
    """
    keys = cells[:, :, None] * n_nodes + cells[:, None, :]
    unique, block = np.unique(keys, return_inverse=True)
    indptr = np.searchsorted(unique // n_nodes, np.arange(n_nodes + 1))
    return indptr, unique % n_nodes, block.reshape(keys.shape)


class Target(NamedTuple):
    """Where element matrices go: the CSR values ``data`` of the pattern
    :func:`dof_pattern`, read through the elements' nodes ``cells`` (nel, npe) and the node
    pairs ``block`` (nel, npe, npe), ``indptr`` (n_nodes + 1,) (:func:`node_blocks`)."""

    cells: np.ndarray
    block: np.ndarray
    indptr: np.ndarray
    data: np.ndarray


class Centreline(NamedTuple):
    """The elements as :func:`element_blocks` reads them: node positions (nel, npe, 3),
    lengths ``h`` (nel,) (``d xi / dX``), and at the quadrature points the section frames
    ``[t, e2, e3]`` (nel, nq, 3, 3) and ``metric`` ``ds / d xi`` (nel, nq)."""

    nodes: np.ndarray
    h: np.ndarray
    frames: np.ndarray
    metric: np.ndarray


@numba.njit(cache=True)
def dof_pattern(indptr: np.ndarray, indices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The CSR pattern of six dofs per node on the node pairs ``indptr``, ``indices``
    (:func:`node_blocks`): row ``6 A + i`` holds ``6 B + j`` for every ``B`` coupled to ``A``
    and every ``j``, so that node ``A``'s rows take ``36 indptr[A]`` onwards, ``6 deg(A)``
    entries each."""
    n = indptr.shape[0] - 1
    dof_indptr = np.empty(6 * n + 1, dtype=np.int64)
    dof_indices = np.empty(36 * indptr[n], dtype=np.int32)
    for A in range(n):
        width = 6 * (indptr[A + 1] - indptr[A])
        for i in range(6):
            start = 36 * indptr[A] + i * width
            dof_indptr[6 * A + i] = start
            for p in range(indptr[A], indptr[A + 1]):
                for j in range(6):
                    dof_indices[start + 6 * (p - indptr[A]) + j] = 6 * indices[p] + j
    dof_indptr[6 * n] = 36 * indptr[n]
    return dof_indptr, dof_indices


@numba.njit(cache=True, inline="never")
def rotated(R: np.ndarray, S: np.ndarray, C: np.ndarray) -> None:
    """``C = blockdiag(R, R) S blockdiag(R, R)^T`` (6x6): the section stiffness ``S`` in
    global axes for the frame ``R`` (eq. T2, :meth:`fvbeam.section.Section.global_stiffness`)."""
    for I in range(2):
        for J in range(2):
            for i in range(3):
                for j in range(3):
                    value = 0.0
                    for k in range(3):
                        RS = 0.0
                        for m in range(3):
                            RS += R[i, m] * S[3 * I + m, 3 * J + k]
                        value += RS * R[j, k]
                    C[3 * I + i, 3 * J + j] = value


@numba.njit(cache=True, inline="always")
def add_work(
    Ke: np.ndarray, r: int, sigma: np.ndarray, weight: float, lever: tuple[float, float, float]
) -> None:
    """Add to rows ``r .. r + 5`` of ``Ke`` the work of the section forces ``sigma[j] = [F;
    M]`` of every trial function ``j`` on one node's six test functions: ``weight F`` on the
    translations, ``weight M + lever x F`` on the rotations."""
    l0, l1, l2 = lever
    for j in range(sigma.shape[0]):
        F0, F1, F2 = sigma[j, 0], sigma[j, 1], sigma[j, 2]
        Ke[r, j] += weight * F0
        Ke[r + 1, j] += weight * F1
        Ke[r + 2, j] += weight * F2
        Ke[r + 3, j] += weight * sigma[j, 3] + l1 * F2 - l2 * F1
        Ke[r + 4, j] += weight * sigma[j, 4] + l2 * F0 - l0 * F2
        Ke[r + 5, j] += weight * sigma[j, 5] + l0 * F1 - l1 * F0


@numba.njit(cache=True)
def element_blocks(
    fv: bool,
    rule: tuple[np.ndarray, np.ndarray, np.ndarray],
    line: Centreline,
    S: np.ndarray,
    target: Target,
) -> None:
    """Add every element's stiffness (module docstring) into the CSR values of ``target``.

    Parameters
    ----------
    fv
        Finite-volume test functions (else Galerkin).
    rule
        ``X, W, jump``: the stiffness quadrature on the reference element [0, 1] (nq,):
        Gauss points, or the evaluation points (fv; ``W`` unused), and (npe, nq) the step of
        each node's region indicator at each evaluation point (fv).
    line
        The elements' nodes, lengths, frames and metric (:class:`Centreline`).
    S
        (6, 6): the section stiffness in its frame.
    target
        Where the blocks go (:class:`Target`).
    """
    X, W, jump = rule
    nodes, h, frames, metric = line
    nel, npe = nodes.shape[0], nodes.shape[1]
    nf = 6 * npe
    N, dN, d2N = np.empty(npe), np.empty(npe), np.empty(npe)
    sigma = np.empty((nf, 6))
    C = np.empty((6, 6))
    Ct = np.empty((6, 3))
    Ke = np.empty((nf, nf))
    for e in range(nel):
        Ke[:] = 0.0
        for q in range(X.shape[0]):
            shape_at(X[q], npe, N, dN, d2N)
            ds = h[e] * metric[e, q]
            rotated(frames[e, q], S, C)
            t0, t1, t2 = frames[e, q, 0, 0], frames[e, q, 1, 0], frames[e, q, 2, 0]
            # Ct[:, k] = C[:, :3] (e_k x t): the section forces of a unit rotation's shear
            for i in range(6):
                Ct[i, 0] = -C[i, 1] * t2 + C[i, 2] * t1
                Ct[i, 1] = C[i, 0] * t2 - C[i, 2] * t0
                Ct[i, 2] = -C[i, 0] * t1 + C[i, 1] * t0
            for b in range(npe):
                slope = dN[b] / ds
                for k in range(3):
                    for i in range(6):
                        sigma[6 * b + k, i] = slope * C[i, k]
                        sigma[6 * b + 3 + k, i] = slope * C[i, 3 + k] - N[b] * Ct[i, k]
            if fv:
                x0 = x1 = x2 = 0.0
                for b in range(npe):
                    x0 += N[b] * nodes[e, b, 0]
                    x1 += N[b] * nodes[e, b, 1]
                    x2 += N[b] * nodes[e, b, 2]
                for a in range(npe):
                    step = jump[a, q]
                    if step == 0.0:
                        continue
                    # the region's balance about its node x_a: F and M + (x - x_a) x F
                    v0, v1, v2 = x0 - nodes[e, a, 0], x1 - nodes[e, a, 1], x2 - nodes[e, a, 2]
                    add_work(Ke, 6 * a, sigma, step, (step * v0, step * v1, step * v2))
            else:
                weight = W[q] * ds
                for a in range(npe):
                    slope, value = dN[a] / ds * weight, N[a] * weight
                    # eps . sigma of N_a e_k: dN_a/ds F_k; of a rotation, dN_a/ds M_k minus
                    # N_a (e_k x t) . F = N_a e_k . (t x F)
                    add_work(Ke, 6 * a, sigma, slope, (-value * t0, -value * t1, -value * t2))
        add_element(Ke, e, target)


@numba.njit(cache=True, inline="never")
def add_element(Ke: np.ndarray, e: int, target: Target) -> None:
    """Add element ``e``'s matrix ``Ke`` (6 npe, 6 npe) into the CSR values of ``target``,
    node block by node block (:func:`node_blocks`)."""
    cells, block, indptr, data = target
    npe = cells.shape[1]
    for a in range(npe):
        A = cells[e, a]
        width = 6 * (indptr[A + 1] - indptr[A])
        for b in range(npe):
            start = 36 * indptr[A] + 6 * (block[e, a, b] - indptr[A])
            for i in range(6):
                for j in range(6):
                    data[start + i * width + j] += Ke[6 * a + i, 6 * b + j]


@numba.njit(cache=True, inline="never")
def rotated_blocks(R: np.ndarray, A: np.ndarray, scratch: np.ndarray) -> None:
    """``A`` (3k, 3k) replaced by ``T A T^T``, ``T`` the block diagonal of the rotation
    ``R`` (3, 3): each 3x3 block ``A_IJ`` by ``R A_IJ R^T`` (``scratch`` (3, 3))."""
    for I in range(0, A.shape[0], 3):
        for J in range(0, A.shape[1], 3):
            for i in range(3):
                for j in range(3):
                    total = 0.0
                    for k in range(3):
                        total += A[I + i, J + k] * R[j, k]
                    scratch[i, j] = total  # A_IJ R^T
            for i in range(3):
                for j in range(3):
                    A[I + i, J + j] = (
                        R[i, 0] * scratch[0, j] + R[i, 1] * scratch[1, j] + R[i, 2] * scratch[2, j]
                    )


@numba.njit(cache=True, inline="never")
def add_products(Ke: np.ndarray, weight: float, A: np.ndarray, B: np.ndarray) -> None:
    """``Ke += weight A B^T`` (``A``, ``B`` (n, 6)): the work of each row of ``B`` on each
    row of ``A`` at one quadrature point."""
    for i in range(A.shape[0]):
        for j in range(B.shape[0]):
            total = 0.0
            for c in range(6):
                total += A[i, c] * B[j, c]
            Ke[i, j] += weight * total


@numba.njit(cache=True)
def cubic_blocks(
    mass: bool,
    rule: tuple[np.ndarray, np.ndarray],
    elements: tuple[np.ndarray, np.ndarray],
    section: tuple[np.ndarray, np.ndarray, float, np.ndarray],
    target: Target,
) -> None:
    """Add every cubic element's stiffness, or with ``mass`` its consistent mass, into the
    CSR values of ``target``.

    The element's twelve functions ``(u, theta)`` in its section axes
    (:func:`fvbeam.pointwise.cubic_local_at`, eq. T11: they read the ``diagonal`` (6,) of the
    section stiffness) give, at each point ``X`` (nq,) of the ``rule = (X, W)`` on [0, 1], the
    strains ``[u' + e1 x theta; theta']`` (eq. T1 with ``t = e1``) whose work through the
    section stiffness ``S`` (6, 6, section frame) sums to the stiffness (eq. T3), or the
    fields whose kinetic energy through ``m`` and the section inertia ``J`` (3, 3) sums to
    the mass (eq. T12); each element's matrix is then turned to global axes by its section
    frame (``frames`` (nel, 3, 3), the element's own, as the functions take it) and added.
    ``elements = (h, frames)``, ``h`` (nel,) the element lengths; ``section = (diagonal, S,
    m, J)``."""
    X, W = rule
    h, frames = elements
    diagonal, S, m, J = section
    L0, L1 = np.empty((12, 6)), np.empty((12, 6))
    strain, force = np.empty((12, 6)), np.empty((12, 6))
    Ke, block3 = np.empty((12, 12)), np.empty((3, 3))
    for e in range(len(h)):
        Ke[:] = 0.0
        for q in range(len(X)):
            weight = W[q] * h[e]
            cubic_local_at(diagonal, h[e], X[q], 0, L0)
            if mass:  # the fields' momenta (m u, J theta)
                for i in range(12):
                    for c in range(3):
                        force[i, c] = m * L0[i, c]
                        force[i, 3 + c] = (
                            J[c, 0] * L0[i, 3] + J[c, 1] * L0[i, 4] + J[c, 2] * L0[i, 5]
                        )
                add_products(Ke, weight, L0, force)
                continue
            cubic_local_at(diagonal, h[e], X[q], 1, L1)
            for i in range(12):
                strain[i, 0] = L1[i, 0]
                strain[i, 1] = L1[i, 1] - L0[i, 5]
                strain[i, 2] = L1[i, 2] + L0[i, 4]
                for c in range(3, 6):
                    strain[i, c] = L1[i, c]
            for i in range(12):
                for c in range(6):
                    total = 0.0
                    for k in range(6):
                        total += S[c, k] * strain[i, k]
                    force[i, c] = total
            add_products(Ke, weight, strain, force)
        rotated_blocks(frames[e], Ke, block3)
        add_element(Ke, e, target)


def matrix(mesh: BeamMesh, fill: Callable[[Target], None]) -> sp.csr_matrix:
    """A beam matrix on the node blocks of ``mesh`` (six dofs per node, node ``k`` owning
    ``6k .. 6k + 5``): ``fill(target)`` adds the elements into the CSR values of ``target``
    (:func:`add_element`); a CSR matrix without explicit zeros (as ``skfem.asm`` gives
    it)."""
    indptr, indices, block = node_blocks(mesh.cells, mesh.n_nodes)
    dof_indptr, dof_indices = dof_pattern(indptr, indices)
    data = np.zeros(len(dof_indices))
    fill(Target(mesh.cells, block, indptr, data))
    n = 6 * mesh.n_nodes
    K = sp.csr_matrix((data, dof_indices, dof_indptr), shape=(n, n))
    K.eliminate_zeros()
    return K


def cubic(mesh: BeamMesh, section: Section, kind: str) -> sp.csr_matrix:
    """The cubic element's ``stiffness`` (2-point Gauss rule: its shear strain is constant
    and its curvature linear, so exact) or ``consistent`` mass (4 points: exact for the
    product of two cubic deflections) by :func:`cubic_blocks`; the definitions are
    scikit-fem's forms on :class:`fvbeam.elements.ElementBeamCubic`
    (:meth:`fvbeam.beam.Beam.reference_stiffness`, :func:`fvbeam.mass.reference_consistent`),
    which it equals to round-off (``tests/test_assembly.py``)."""
    X, W = gauss(2 if kind == "stiffness" else 4)
    frames = mesh.frames(np.arange(mesh.n_elements), np.full(mesh.n_elements, 0.5))

    elements = (np.ascontiguousarray(mesh.element_length), np.ascontiguousarray(frames))
    properties = (
        np.ascontiguousarray(np.diag(section.stiffness)),
        np.ascontiguousarray(section.stiffness, dtype=float),
        float(section.mass_per_length),
        np.ascontiguousarray(section.inertia, dtype=float),
    )

    def fill(target: Target) -> None:
        cubic_blocks(kind != "stiffness", (X, W), elements, properties, target)

    return matrix(mesh, fill)


def stiffness(
    mesh: BeamMesh,
    formulation: Formulation,
    section: np.ndarray,
    quadrature: tuple[np.ndarray, np.ndarray],
    frames: np.ndarray,
    metric: np.ndarray,
) -> sp.csr_matrix:
    """The stiffness of a beam (six dofs per node, node ``k`` owning ``6k .. 6k + 5``) by
    :func:`element_blocks`, as a CSR matrix without explicit zeros (as ``skfem.asm`` gives
    it).

    ``section``: the 6x6 section stiffness in its frame; ``quadrature``: the stiffness
    quadrature ``(X (1, nq), W (nq,))``; ``frames`` (nel, nq, 3, 3) and ``metric`` (nel, nq)
    there (:meth:`fvbeam.beam.Beam.centreline`).
    """
    if not compiled(formulation):
        raise ValueError(f"{formulation.name}: no compiled stiffness; assemble it with asm")
    X, W = (np.ascontiguousarray(a, dtype=float).ravel() for a in quadrature)
    npe = mesh.nodes_per_element
    fv = isinstance(formulation, FiniteVolume)
    step = jumps(npe) if fv else np.zeros((npe, len(X)))

    rule = (X, W, np.ascontiguousarray(step, dtype=float))
    line = Centreline(
        np.ascontiguousarray(mesh.points[mesh.cells]),
        np.ascontiguousarray(mesh.element_length),
        np.ascontiguousarray(frames),
        np.ascontiguousarray(metric),
    )

    def fill(target: Target) -> None:
        element_blocks(fv, rule, line, np.ascontiguousarray(section, dtype=float), target)

    return matrix(mesh, fill)
