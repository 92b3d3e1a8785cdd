"""The recovery map (``Beam.recovery``): internal forces at the recovery points as one sparse
matrix built once, held to the scikit-fem field path it replaces.

Source of truth: the field path (``fvbeam.beam.internal_forces_reference``), eqs. (T1) and
(T2) evaluated on the trial field that scikit-fem interpolates from ``q``
(``basis.interpolate``): ``[F; M] = R^T C [nu; kappa]``.
Both paths sum the same products in another order, so they agree to round-off: an entry is
a sum of at most ``m = 3 x 6 x 6 npe`` products (frame row, section stiffness row, strain
terms of ``npe`` nodes), and a sum of ``m`` products is off by at most ``m eps`` times the
sum of their magnitudes (Higham, gamma_m), bounded here by ``m eps`` times the largest
``|R| |q|`` (the map with every entry made positive, on ``|q|``), times the condition of the
rotation to the section frame (1).
"""

import numpy as np
import pytest

from fvbeam import FORMULATIONS, Beam, Section, arc, formulation, from_curve, straight
from fvbeam.beam import internal_forces_reference

EPS = np.finfo(float).eps


def section() -> Section:
    """A section coupling every strain to every force (symmetric positive definite)."""
    rng = np.random.default_rng(7)
    A = rng.standard_normal((6, 6))
    return Section(A @ A.T + 6 * np.eye(6))


def meshes(npe: int):
    yield straight((0, 0, 0), (1.0, 0.3, 0.2), 4, npe, name="skew")
    yield arc((0.5, 0, 0), 1.5, 0.1, 2.0, 5, npe, name="arc")
    yield from_curve(
        lambda u: np.stack([np.cos(3 * u), np.sin(3 * u), 0.4 * u], axis=1), 6, npe, name="helix"
    )


CASES = [(name, "reduced") for name in FORMULATIONS] + [
    (name, "full") for name in FORMULATIONS if name.startswith("galerkin")
]


@pytest.mark.parametrize("name, integration", CASES)
def test_the_recovery_map_is_the_field_path_for_every_formulation(name, integration):
    npe = formulation(name, integration).nodes_per_element
    rng = np.random.default_rng(3)
    for mesh in meshes(npe):
        beam = Beam(mesh, section(), name, integration)
        q = rng.standard_normal(beam.n_dofs)
        forces = beam.internal_forces(q)
        reference = internal_forces_reference(beam, q)
        scale = (abs(beam.recovery) @ np.abs(q)).max()
        tol = 3 * 6 * 6 * npe * EPS * scale
        assert np.abs(np.hstack([forces.force, forces.moment]) - reference).max() <= tol
        frames = beam._stiffness_geometry[1].reshape(-1, 3, 3)
        world = np.einsum("nij,nj->ni", frames, reference[:, :3])
        assert np.abs(forces.force_global - world).max() <= 2 * tol
        assert forces.xi.shape == (len(reference),)
        np.testing.assert_array_equal(forces.xi, beam.recovery_abscissae)


def test_the_map_is_built_once_and_shared_by_translated_copies():
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 3), Section.diagonal(1, 2, 3, 4, 5, 6))
    moved = beam.translated((0.5, 0, 0))
    assert moved.recovery is beam.recovery
    assert beam.recovery.shape == (6 * len(beam.recovery_abscissae), beam.n_dofs)
