"""The compiled stiffness (fvbeam/assembly.py) against its definition, scikit-fem's ``asm`` of
the internal-work form (``Beam.reference_stiffness``), and the sparse structure it is built on.

Tolerance: both compute each entry ``sum_q w_q eps_v . C eps_u`` from the same inputs in a
different order (the fv path also drops the strain terms of a rigid motion, which the form
computes and cancels).  Each term passes through at most 32 roundings on either path: the
strains (the derivative scaled by the metric, a cross product of 2 products and a
difference, their sum: 5), the section force ``C eps`` (6 products and 5 sums: 11), the
work ``eps_v . sigma`` (11 more), the weights ``metric |det J| W`` (3) and the sum over the
points (2).  So each path lies within ``32 EPS B`` of the exact value, ``B`` the same sum taken
over the absolute values of every term (:func:`magnitude`), and the two within ``64 EPS B``.
"""

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import BilinearForm, CellBasis, asm

from fvbeam import Beam, RigidBody, Section, Structure, arc, from_curve, straight
from fvbeam.assembly import compiled, node_blocks
from fvbeam.formulations import gauss
from fvbeam.mass import reference_consistent

EPS = np.finfo(float).eps
#: Roundings on either path (module docstring), twice.
ROUNDINGS = 64


def coupled_section() -> Section:
    """A section whose stiffness couples every strain to every other (random SPD)."""
    rng = np.random.default_rng(7)
    A = rng.standard_normal((6, 6))
    return Section(A @ A.T + np.diag([40.0, 9.0, 11.0, 3.0, 5.0, 4.0]))


def meshes(npe: int) -> dict:
    """A straight oblique beam, an arc, and a helix with unequal elements (the tangent turns
    out of every plane, so every block of the stiffness couples)."""
    return {
        "straight": straight((0.1, -0.2, 0.3), (1.2, 0.5, -0.4), 5, npe),
        "arc": arc((0.0, 0.0, 0.0), 2.0, 0.1, 2.4, 4, npe),
        "helix": from_curve(
            lambda u: np.column_stack([np.cos(3 * u), np.sin(3 * u), 0.7 * u**2]), 6, npe
        ),
    }


@BilinearForm
def magnitude(u, v, w):
    """:func:`fvbeam.forms.internal_work` with every product and sum taken in absolute value:
    the scale ``B`` of its round-off (module docstring)."""
    t, metric, C = (np.abs(np.asarray(x)) for x in (w.t, w.metric, w.C))

    def strain(field):
        value, d = np.abs(np.asarray(field)), np.abs(field.grad[:, 0]) / metric
        lever = np.stack(
            [
                value[4] * t[2] + value[5] * t[1],
                value[5] * t[0] + value[3] * t[2],
                value[3] * t[1] + value[4] * t[0],
            ]
        )
        return np.concatenate([d[:3] + lever, d[3:]])

    return np.einsum("i...,ij...,j...->...", strain(v), C, strain(u)) * metric


CASES = [
    ("fv2", "reduced"),
    ("fv3", "reduced"),
    ("galerkin-p1", "reduced"),
    ("galerkin-p1", "full"),
    ("galerkin-p2", "reduced"),
    ("galerkin-p2", "full"),
]


@pytest.mark.parametrize("name,integration", CASES)
@pytest.mark.parametrize("shape", ["straight", "arc", "helix"])
def test_compiled_stiffness_equals_the_scikit_fem_form(name, integration, shape):
    npe = 2 if name in ("fv2", "galerkin-p1") else 3
    beam = Beam(meshes(npe)[shape], coupled_section(), name, integration)
    assert compiled(beam.formulation)
    K, reference = beam.stiffness, beam.reference_stiffness()
    bound = asm(
        magnitude, beam.trial_basis, beam.test_basis, **beam.geometry(beam._quadrature[0])[0]
    )
    error = np.abs((K - reference).toarray())
    assert np.all(error <= ROUNDINGS * EPS * bound.toarray())
    assert K.has_canonical_format and not np.any(K.data == 0)


def test_node_blocks_list_each_coupled_pair_once():
    cells = np.array([[0, 1, 3], [1, 2, 4]])
    indptr, indices, block = node_blocks(cells, 5)
    pattern = sp.csr_matrix((np.arange(len(indices)), indices, indptr), shape=(5, 5))
    rows, cols = np.broadcast_arrays(cells[:, :, None], cells[:, None, :])
    assert np.array_equal(np.asarray(pattern[rows.ravel(), cols.ravel()]).ravel(), block.ravel())
    expected = {(int(a), int(b)) for a, b in zip(rows.ravel(), cols.ravel(), strict=True)}
    coo = pattern.tocoo()
    assert set(zip(coo.row.tolist(), coo.col.tolist(), strict=True)) == expected
    assert len(indices) == len(expected)


def coordinate_sum(structure: Structure, matrices: list) -> np.ndarray:
    """The beams' matrices summed on the global dofs entry by entry (the definition)."""
    total = np.zeros((structure.n_dofs, structure.n_dofs))
    for A, dofs in zip(matrices, structure.dof_maps, strict=True):
        coo = sp.coo_matrix(A)
        np.add.at(total, (dofs[coo.row], dofs[coo.col]), coo.data)
    return total


@pytest.mark.parametrize(
    "ties",
    [
        [],
        [("a.end", "b.start"), ("b.end", "c.start")],
        [("b.end", "a.start"), ("c.start", "hub")],
        [("a.start", "a.end"), ("a.end", "b.start")],
    ],
    ids=["untied", "chain", "backwards-and-body", "ring"],
)
def test_structure_sums_the_beams_matrices_on_the_global_dofs(ties):
    """Untied beams, a chain, ties that number a beam's end before its start (and a body),
    and a beam tied into a ring (two of its nodes share dofs): the global stiffness is the
    sum of the beams' entries on the global dofs, as coordinates sum them.  A global entry
    sums at most three (the ring's node, also b's start), whose order may differ: two
    roundings, at most ``2 EPS`` of the sum of their magnitudes."""
    section = coupled_section()
    beams = [
        Beam(straight((0, 0, 0), (1, 0, 0), 3, 3, name="a"), section, "fv3"),
        Beam(arc((1, 1, 0), 1.0, -np.pi / 2, 0.0, 2, 3, name="b"), section, "galerkin-p2"),
        Beam(straight((2, 1, 0), (2, 1, 1), 2, 3, name="c"), section, "fv3"),
    ]
    if ties and ties[0] == ("a.start", "a.end"):
        beams[0] = Beam(arc((0, 0.5, 0), 0.5, -np.pi / 2, 1.5 * np.pi, 4, 3, name="a"), section)
        beams[1] = Beam(straight((0, 0, 0), (0, -1, 0), 2, 3, name="b"), section)
    bodies = [RigidBody("hub", position=beams[2].mesh.points[0])]
    structure = Structure(beams, ties, bodies)
    K = structure.tangent(np.zeros(structure.n_dofs))
    expected = coordinate_sum(structure, [beam.stiffness for beam in beams])
    scale = coordinate_sum(structure, [abs(beam.stiffness) for beam in beams])
    assert np.all(np.abs(K.toarray() - expected) <= 2 * EPS * scale)
    assert K.has_canonical_format


#: The cubic element's section: distinct stiffnesses and a full section inertia (its
#: functions read the stiffness's diagonal, eq. T11; its mass the inertia, eq. T12).
CUBIC_SECTION = Section(
    np.diag([40.0, 9.0, 11.0, 3.0, 5.0, 4.0]),
    mass_per_length=2.5,
    inertia=np.array([[0.7, 0.1, -0.05], [0.1, 0.4, 0.02], [-0.05, 0.02, 0.3]]),
)


@BilinearForm
def inertia_magnitude(u, v, w):
    """:func:`fvbeam.forms.inertia` with every product and sum in absolute value: the scale
    of its round-off."""
    u, v = np.abs(np.asarray(u)), np.abs(np.asarray(v))
    J = np.abs(np.asarray(w.J))
    rotary = np.einsum("ij...,j...->i...", J, u[3:])
    return (
        w.m * np.einsum("i...,i...->...", v[:3], u[:3]) + np.einsum("i...,i...->...", v[3:], rotary)
    ) * w.metric


def test_cubic_compiled_matrices_equal_the_scikit_fem_forms():
    """Stiffness (2 Gauss points) and consistent mass (4) of cubic elements of unequal
    lengths along x, whose section frames are the coordinate axes (turning them rounds
    nothing), against scikit-fem's forms on the element's functions: within ``64 EPS B`` of
    the module docstring (the mass's terms pass through fewer roundings than the
    stiffness's: the fields, ``m u`` or ``J theta`` (5), the product (11), weights and sum)."""
    mesh = from_curve(lambda u: np.column_stack([u + 0.6 * u**2, 0 * u, 0 * u]), 5, 2)
    beam = Beam(mesh, CUBIC_SECTION, "cubic")
    frames = mesh.frames(np.arange(mesh.n_elements), np.full(mesh.n_elements, 0.5))
    assert np.all(np.isin(frames, (-1.0, 0.0, 1.0)))  # the premise: exact turns
    K, reference = beam.stiffness, beam.reference_stiffness()
    bound = asm(
        magnitude, beam.trial_basis, beam.test_basis, **beam.geometry(beam._quadrature[0])[0]
    )
    assert np.all(np.abs((K - reference).toarray()) <= ROUNDINGS * EPS * bound.toarray())
    assert K.has_canonical_format and not np.any(K.data == 0)
    M, reference = beam.mass("consistent"), reference_consistent(beam)
    X, W = gauss(4)
    basis = CellBasis(
        beam.skfem_mesh,
        beam.formulation.trial_element(mesh, CUBIC_SECTION),
        quadrature=(X[None, :], W),
        disable_doflocs=True,
    )
    bound = asm(
        inertia_magnitude,
        basis,
        m=np.full((mesh.n_elements, 4), CUBIC_SECTION.mass_per_length),
        J=np.broadcast_to(CUBIC_SECTION.inertia[:, :, None, None], (3, 3, mesh.n_elements, 4)),
        metric=np.ones((mesh.n_elements, 4)),
    )
    assert np.all(np.abs((M - reference).toarray()) <= ROUNDINGS * EPS * bound.toarray())


def test_cubic_matrices_turn_with_the_beam():
    """The same cubic beam along x and along an oblique direction: the oblique matrices are
    ``T A T^T``, ``T`` the block diagonal of its section frame ``R`` (the x beam's is the
    identity).  Each side turns each term through 2 three-term products (6 roundings), the
    element lengths, computed from the node positions within 2 EPS, enter the stiffness at
    most cubed: ``32 EPS |T| B |T|^T``, ``B`` the sum of the elements' ``|A_e|`` (the
    assembled ``A`` cancels between neighbours, its terms do not).  Each element's own
    frame is ``R + E`` with ``|E| <= delta`` (measured, a few EPS), which adds
    ``E A_e R^T + R A_e E^T + E A_e E^T``: at most ``delta (O B |T|^T + |T| B O^T + delta O B
    O^T)``, ``O`` the block diagonal of 3x3 ones."""
    length, n = 1.7, 4
    d = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    start = np.array([0.2, 0.1, -0.3])
    along_x = Beam(straight((0, 0, 0), (length, 0, 0), n, 2), CUBIC_SECTION, "cubic")
    oblique = Beam(straight(start, start + length * d, n, 2), CUBIC_SECTION, "cubic")
    element = Beam(straight((0, 0, 0), (length / n, 0, 0), 1, 2), CUBIC_SECTION, "cubic")
    frames = oblique.mesh.frames(np.arange(n), np.full(n, 0.5))
    R = frames[0]
    delta = np.abs(frames - R).max()
    assert delta <= 4 * EPS  # the premise: one frame, to round-off
    assert np.array_equal(along_x.mesh.frames(np.array([0]), np.array([0.5]))[0], np.eye(3))
    R_T = sp.block_diag([R] * (2 * (n + 1))).toarray()
    T, O = np.abs(R_T), sp.block_diag([np.ones((3, 3))] * (2 * (n + 1))).toarray()
    for matrix in (lambda b: b.stiffness, lambda b: b.mass("consistent")):
        A, turned = matrix(along_x).toarray(), matrix(oblique).toarray()
        B = np.zeros_like(A)
        for e in range(n):
            B[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += np.abs(matrix(element).toarray())
        frame = 32 * EPS * T @ B @ T.T + delta * (O @ B @ T.T + T @ B @ O.T + delta * O @ B @ O.T)
        assert np.all(np.abs(turned - R_T @ A @ R_T.T) <= frame)
