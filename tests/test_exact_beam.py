"""The geometrically exact beam's law (fvbeam.exact_beam) and its rotation tools
(fvbeam.rotations): the tangent against finite differences at large rotations, its
reference value against the linear beam's stiffness, and objectivity.

Tolerances:

* round-off: an entry of a stiffness is a sum of a few products of the section stiffness with
  the geometry, each rounded to ``eps`` of its size; ``64 eps`` of the largest entry bounds
  the sum of a few tens of such roundings;
* central differences with step ``h``: the error is ``c h^2`` (truncation) plus
  ``eps |terms| / h`` (the residual's rounding, :meth:`ExactBeam.residual_floor`, divided by
  the step); the truncation is estimated by Richardson from the steps ``h`` and ``2h``,
  ``(D(2h) - D(h)) / 3``, and the assertion allows twice the sum (the estimate's own
  higher-order terms).
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, from_curve, rotations
from fvbeam.exact_beam import ExactBeam, ExactState

EPS = np.finfo(float).eps
RNG = np.random.default_rng(20000131)


#: The formulations with exact kinematics, with their integration.
FORMULATIONS = [
    ("fv2", "reduced"),
    ("fv3", "reduced"),
    ("galerkin-p1", "reduced"),
    ("galerkin-p2", "reduced"),
    ("galerkin-p1", "full"),
    ("galerkin-p2", "full"),
]


def curved_beam(name: str, integration: str = "reduced", n: int = 3) -> Beam:
    """A 3-D curved beam with distinct stiffnesses (bending, shear and torsion coupled by
    the curvature)."""
    npe = 2 if name in ("fv2", "galerkin-p1") else 3
    mesh = from_curve(lambda u: np.column_stack([3 * u, np.sin(2 * u), 0.5 * u**2]), n, npe)
    section = Section.diagonal(EA=100.0, GAy=50.0, GAz=40.0, GJ=3.0, EJy=2.0, EJz=1.5)
    return Beam(mesh, section, name, integration)


def random_state(exact: ExactBeam, displacement: float, angle: float) -> ExactState:
    """Nodes moved by ``displacement`` and turned by up to about ``angle`` at random."""
    ref = exact.reference()
    n = len(ref.x)
    turn = rotations.exp_map(angle * RNG.uniform(-1, 1, (n, 3)))
    return ExactState(ref.x + displacement * RNG.standard_normal((n, 3)), turn)


def central_differences(exact: ExactBeam, state: ExactState, h: float) -> np.ndarray:
    """``d r / d q`` by central differences of step ``h`` on the manifold."""
    D = np.empty((exact.n_dofs, exact.n_dofs))
    for k in range(exact.n_dofs):
        dq = np.zeros(exact.n_dofs)
        dq[k] = h
        D[:, k] = (exact.residual(state.updated(dq)) - exact.residual(state.updated(-dq))) / (2 * h)
    return D


@pytest.mark.parametrize("name,integration", FORMULATIONS)
def test_reference_tangent_is_the_linear_stiffness(name, integration):
    """Linear kinematics is the exact law's first-order case: at the reference configuration
    the exact tangent is the linear beam's stiffness, and the residual vanishes."""
    beam = curved_beam(name, integration)
    exact = ExactBeam(beam)
    ref = exact.reference()
    K, K_linear = exact.tangent(ref).toarray(), beam.stiffness.toarray()
    assert np.abs(K - K_linear).max() <= 64 * EPS * np.abs(K_linear).max()
    assert np.abs(exact.residual(ref)).max() == 0.0


@pytest.mark.parametrize("name,integration", FORMULATIONS)
def test_tangent_matches_finite_differences_at_large_rotations(name, integration):
    """Material and geometric tangent at a random state: displacements of a third of an
    element, nodal rotations up to about a radian about random axes (Galerkin: the second
    variation of the rotation interpolation included)."""
    exact = ExactBeam(curved_beam(name, integration))
    state = random_state(exact, 0.3, 1.0)
    K = exact.tangent(state).toarray()
    h = 1e-5
    D1, D2 = central_differences(exact, state, h), central_differences(exact, state, 2 * h)
    truncation = np.abs(D2 - D1).max() / 3
    rounding = 2 * EPS * exact.residual_floor(state).max() / h
    assert np.abs(K - D1).max() <= 2 * (truncation + rounding)
    # the check has teeth: the geometric part alone exceeds it
    assert np.abs(K - exact.tangent(exact.reference()).toarray()).max() > 1e3 * (
        truncation + rounding
    )


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
def test_rigid_motion_is_stress_free(name):
    """Objectivity: a finite rigid rotation and translation of the whole beam leaves it
    unstrained (the relative rotation vectors and ``Lambda^T x'`` are invariant)."""
    exact = ExactBeam(curved_beam(name))
    ref = exact.reference()
    Q = rotations.exp_map(np.array([1.2, -0.7, 2.1]))
    moved = ExactState(ref.x @ Q.T + np.array([3.0, -1.0, 2.0]), np.broadcast_to(Q, ref.R.shape))
    points = exact.points(moved)
    # the terms of nu (|x'|, |x0'|, of size 1) and of kappa (psi_a of rounding eps times the
    # shape-function slopes) cancel to a few eps of their sizes; 16 bounds "a few"
    slopes = np.abs(exact.dN).sum(axis=1)
    assert np.all(np.abs(points.strain[:, :3]) <= 16 * EPS * 2)
    assert np.all(np.abs(points.strain[:, 3:]) <= 16 * EPS * slopes[:, None])
    assert np.all(np.abs(exact.residual(moved)) <= 16 * EPS * exact.residual_floor(moved))


def test_rotation_tangent_operators_match_finite_differences():
    """``exp(psi + h w) exp(psi)^T = exp(h J(psi) w + O(h^2))``, ``J^-1 J = I``, and the
    derivative of ``J`` along ``w``, at angles on both sides of the series' threshold."""
    h = 1e-6
    for angle in (1e-3, 0.04, 0.06, 1.0, 3.0):
        psi = angle * np.array([0.6, -0.8, 0.0])
        w = RNG.standard_normal(3)
        J = rotations.left_jacobian(psi)
        turn = rotations.exp_map(psi + h * w) @ rotations.exp_map(psi - h * w).T
        # central: the O(h^2) term of log(...) / (2h) is bounded by |w|^3 h^2 (J and its
        # derivatives are of size 1), round-off by eps / h
        tol = 4 * (np.linalg.norm(w) ** 3 * h**2 + EPS / h)
        np.testing.assert_allclose(rotations.log_map(turn) / (2 * h), J @ w, atol=tol)
        np.testing.assert_allclose(
            rotations.inverse_left_jacobian(psi) @ J, np.eye(3), atol=64 * EPS
        )
        dJ = (rotations.left_jacobian(psi + h * w) - rotations.left_jacobian(psi - h * w)) / (2 * h)
        np.testing.assert_allclose(rotations.left_jacobian_derivative(psi, w), dJ, atol=tol)


def test_the_cubic_element_is_refused():
    section = Section.diagonal(EA=1.0, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)
    beam = Beam(from_curve(lambda u: np.column_stack([u, 0 * u, 0 * u]), 2, 2), section, "cubic")
    with pytest.raises(ValueError, match="not cubic"):
        ExactBeam(beam)


@pytest.mark.parametrize("name,integration", FORMULATIONS[2:])
def test_galerkin_residual_is_the_strain_energys_gradient(name, integration):
    """A Galerkin beam is conservative: its residual is the gradient of the strain energy
    ``U = sum_p w_p [nu; kappa]^T C [nu; kappa] / 2`` along the manifold's increments, at a
    random large-rotation state (central differences, tolerance as for the tangent)."""
    exact = ExactBeam(curved_beam(name, integration))
    state = random_state(exact, 0.3, 1.0)

    def energy(s: ExactState) -> float:
        strain = exact.points(s).strain
        return 0.5 * float(np.einsum("p,pi,pij,pj->", exact.weight, strain, exact.C, strain))

    def gradient(h: float) -> np.ndarray:
        g = np.empty(exact.n_dofs)
        for k in range(exact.n_dofs):
            dq = np.zeros(exact.n_dofs)
            dq[k] = h
            g[k] = (energy(state.updated(dq)) - energy(state.updated(-dq))) / (2 * h)
        return g

    h = 1e-5
    g1, g2 = gradient(h), gradient(2 * h)
    truncation = np.abs(g2 - g1).max() / 3
    rounding = 2 * EPS * energy(state) / h
    assert np.abs(exact.residual(state) - g1).max() <= 2 * (truncation + rounding)
