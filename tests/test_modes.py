"""Mass matrices and natural frequencies (fvbeam.mass, fvbeam.modes, docs/dynamics.md).

Tolerance sources:

* ``ROUNDOFF`` (1e-12): identities of the discrete scheme (total mass, rigid-body inertia):
  sums of O(100) positive terms, each exact to a few ulps (2.2e-16), leave margin ~1e2.
* The Euler-Bernoulli limit of the Timoshenko reference: the shear reduces ``beta L`` by
  ``(beta L)^2 s^2 / 4`` to leading order, ``s^2 = EJ / (GA L^2)``; the bound is twice that.
* Mesh convergence: the observed order ``log2(e_n / e_2n)`` on n = 8, 16, 32 elements must be
  within 0.5 of the expected one (fv3 lumped: 2, the influence-region lumping is a quadrature
  exact for linear fields only, see the rotary-inertia identity below; galerkin-p2: 2p = 4,
  the eigenvalue error of a degree-p Galerkin method, Strang and Fix, "An Analysis of the Finite
  Element Method", Sec. 6.3, kept by the 2-point reduced stiffness rule and by Simpson lumping,
  both exact to degree 3), and the finest error below ``e_16 / 2^(p - 0.5)``.
"""

import numpy as np
import pytest

import fvbeam.modes
from fvbeam import Beam, RigidBody, Section, Structure, Support, closed_forms, formulation, straight
from fvbeam.modes import natural_frequencies

ROUNDOFF = 1e-12
#: Free-beam section: inertia per length (section frame t, e2, e3).
INERTIA = np.diag([2e-3, 1e-3, 1.5e-3])
#: Cantilever: EJ = m = L = 1, s^2 = EJ / (GA L^2) = 0.01, r^2 = rhoJ / (m L^2) = 1e-3.
EJ, GA, RHO_J = 1.0, 100.0, 1e-3
#: Euler-Bernoulli cantilever roots beta L (Blevins, "Formulas for Natural Frequency and Mode
#: Shape", Table 8-1).
EB_BETA_L = np.array([1.87510407, 4.69409113, 7.85475744])
#: Lumped rigid-rotation inertia = (m L^3 / 12)(1 + c / n^2): c = 12 E(x^2), with E(x^2) the
#: error of the nodal weights on x^2 over a unit element: trapezoid 1/6 (fv2: regions of h/2
#: each side; galerkin-p1 row sums), fv3 regions (1 - 1/sqrt(3))/2, 1/sqrt(3), (1 - 1/sqrt(3))/2:
#: 1/6 - 1/(4 sqrt(3)), Simpson (galerkin-p2 row sums): 0.
LUMPED_C = {"fv2": 2.0, "fv3": 2.0 - np.sqrt(3.0), "galerkin-p1": 2.0, "galerkin-p2": 0.0}
CASES = [
    ("fv2", "lumped"),
    ("fv3", "lumped"),
    ("galerkin-p1", "lumped"),
    ("galerkin-p2", "lumped"),
    ("galerkin-p1", "consistent"),
    ("galerkin-p2", "consistent"),
]


def npe(name: str) -> int:
    return formulation(name).nodes_per_element


def beam(
    name: str,
    n: int,
    m: float = 1.0,
    inertia=INERTIA,
    end=(1.0, 0.0, 0.0),
    GA_: float = 1.0,
    EJ_: float = 1.0,
) -> Beam:
    section = Section.diagonal(
        EA=1e3,
        GAy=GA_,
        GAz=GA_,
        GJ=1.0,
        EJy=EJ_,
        EJz=EJ_,
        mass_per_length=m,
        inertia=inertia,
        name="steel",
    )
    return Beam(straight((0, 0, 0), end, n, npe(name)), section, name)


@pytest.mark.parametrize("name,kind", CASES)
@pytest.mark.parametrize("n", [1, 3, 8])
def test_free_beam_mass_and_rigid_rotation_inertia_match_closed_forms(name, kind, n):
    L, m = 1.0, 2.5
    b = beam(name, n, m=m)
    M = b.mass(kind)
    x = b.mesh.points[:, 0] - L / 2
    for c in range(3):
        unit = np.zeros((b.mesh.n_nodes, 6))
        unit[:, c] = 1.0
        q = unit.ravel()
        np.testing.assert_allclose(q @ M @ q, m * L, rtol=ROUNDOFF)
        np.testing.assert_allclose((M @ q).reshape(-1, 6)[:, 3:], 0.0, atol=ROUNDOFF)
    rotation = np.zeros((b.mesh.n_nodes, 6))
    rotation[:, 1], rotation[:, 5] = x, 1.0  # theta_z = 1 about the centre: u_y = x
    q = rotation.ravel()
    c = LUMPED_C[name] if kind == "lumped" else 0.0
    expected = m * L**3 / 12 * (1 + c / n**2) + INERTIA[2, 2] * L
    np.testing.assert_allclose(q @ M @ q, expected, rtol=ROUNDOFF)


@pytest.mark.parametrize("name,kind", CASES)
def test_section_inertia_is_rotated_to_global_axes(name, kind):
    b = beam(name, 3, end=(0.0, 2.0, 0.0))  # t = y, e3 = z, e2 = e3 x t = -x
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    blocks = b.mass(kind).toarray().reshape(b.mesh.n_nodes, 6, b.mesh.n_nodes, 6)
    total = blocks[:, 3:, :, 3:].sum(axis=(0, 2))
    np.testing.assert_allclose(total, 2.0 * R @ INERTIA @ R.T, atol=ROUNDOFF)


def test_mass_is_cached_and_shared_by_a_translated_copy():
    b = beam("galerkin-p2", 2)
    assert b.mass("consistent") is b.mass("consistent")
    assert b.translated((1.0, 0.0, 0.0)).mass("consistent") is b.mass("consistent")


def test_structure_mass_adds_rigid_bodies_on_their_node():
    b = beam("fv3", 2)
    J = np.diag([1.0, 2.0, 3.0])
    hub = RigidBody("hub", (1.0, 0.0, 0.0), mass=4.0, inertia=J)
    free = RigidBody("free", (5.0, 0.0, 0.0), mass=0.5)
    s = Structure([b], [((0, "end"), "hub")], [hub, free])
    M = s.mass("lumped")
    dofs = s.node_dofs("hub")
    expected = b.mass().toarray()[np.ix_(b.node_dofs("end"), b.node_dofs("end"))]
    expected[:3, :3] += 4.0 * np.eye(3)
    expected[3:, 3:] += J
    np.testing.assert_allclose(M[dofs][:, dofs].toarray(), expected, atol=ROUNDOFF)
    ux = np.zeros(s.n_dofs)
    ux[0::6] = 1.0
    np.testing.assert_allclose(ux @ M @ ux, 1.0 + 4.0 + 0.5, rtol=ROUNDOFF)


def test_mass_errors_name_the_problem():
    with pytest.raises(ValueError, match="beam 'beam'.*section 'steel'.*mass_per_length 0"):
        beam("fv3", 2, m=0.0).mass()
    with pytest.raises(ValueError, match="unknown mass kind 'diagonal'"):
        beam("fv3", 2).mass("diagonal")
    with pytest.raises(ValueError, match="finite-volume beams take the lumped mass only"):
        beam("fv3", 2).mass("consistent")
    with pytest.raises(ValueError, match="unknown mass kind"):
        Structure([beam("galerkin-p2", 2)]).mass("diagonal")


def test_timoshenko_reference_has_the_euler_bernoulli_limit():
    GA_ = 1e4
    beta_L = np.sqrt(closed_forms.timoshenko_cantilever_frequencies(3, GA=GA_))
    s2 = 1.0 / GA_
    assert np.all(beta_L < EB_BETA_L)
    assert np.all(EB_BETA_L - beta_L < EB_BETA_L**3 * s2 / 2)


def planar_cantilever(name: str, n: int) -> tuple[Beam, list[Support]]:
    """Clamped at 0; every other node held in ux, uz, rx, ry: bending in the x-y plane only
    (u_y, theta_z), whose rotary inertia is the section's J_33 = RHO_J."""
    b = beam(name, n, inertia=np.diag([2 * RHO_J, RHO_J, RHO_J]), GA_=GA, EJ_=EJ)
    supports = [Support(0, "start")] + [
        Support(0, k, "ux+uz+rx+ry") for k in range(1, b.mesh.n_nodes)
    ]
    return b, supports


def relative_errors(name: str, kind: str, n: int) -> np.ndarray:
    exact = closed_forms.timoshenko_cantilever_frequencies(3, EJ=EJ, GA=GA, rhoJ=RHO_J)
    b, supports = planar_cantilever(name, n)
    return np.abs(natural_frequencies(b, supports, 3, kind).omega / exact - 1)


@pytest.mark.parametrize(
    "name,kind,order",
    [("fv3", "lumped", 2), ("galerkin-p2", "lumped", 4), ("galerkin-p2", "consistent", 4)],
)
def test_cantilever_frequencies_converge_to_timoshenko_at_the_expected_order(name, kind, order):
    e8, e16, e32 = (relative_errors(name, kind, n) for n in (8, 16, 32))
    for coarse, fine in ((e8, e16), (e16, e32)):
        observed = np.log2(coarse / fine)
        assert np.all(np.abs(observed - order) < 0.5), observed
    assert np.all(e32 < e16 / 2 ** (order - 0.5))


@pytest.mark.parametrize("name,kind", [("fv3", "lumped"), ("galerkin-p2", "consistent")])
def test_sparse_shift_invert_matches_dense_and_shapes_have_unit_modal_mass(name, kind, monkeypatch):
    b, supports = planar_cantilever(name, 6)
    dense = natural_frequencies(b, supports, 4, kind)
    monkeypatch.setattr(fvbeam.modes, "DENSE_LIMIT", 0)
    sparse = natural_frequencies(b, supports, 4, kind)
    np.testing.assert_allclose(sparse.omega, dense.omega, rtol=1e-10)
    M = b.mass(kind)
    for modes in (dense, sparse):
        np.testing.assert_allclose(
            np.einsum("ik,ik->k", modes.shapes, M @ modes.shapes), 1.0, rtol=1e-10
        )
        np.testing.assert_allclose(modes.hertz, modes.omega / (2 * np.pi), rtol=ROUNDOFF)


def test_natural_frequencies_rejects_a_bad_mode_count():
    b, supports = planar_cantilever("fv3", 2)
    with pytest.raises(ValueError, match="n must be an integer"):
        natural_frequencies(b, supports, 0)
