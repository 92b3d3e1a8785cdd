"""Section properties: validation of the stiffness and mass, rotation to global axes."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import block_diag
from scipy.spatial.transform import Rotation

from fvbeam import Section
from fvbeam.section import COMPONENTS

EPS = np.finfo(float).eps
GOOD = dict(EA=7.0, GAy=2.0, GAz=3.0, GJ=1.5, EJy=1.2, EJz=0.8)


@pytest.mark.parametrize("component", COMPONENTS)
@pytest.mark.parametrize("value", [0.0, -1.0, np.nan, np.inf, -np.inf])
def test_diagonal_rejects_bad_stiffness_and_names_it(component, value):
    values = dict(GOOD, **{component: value})
    with pytest.raises(ValueError, match=rf"\b{component} must be finite and > 0, got {value}"):
        Section.diagonal(**values)


def test_diagonal_builds_the_diagonal_in_component_order():
    s = Section.diagonal(**GOOD)
    np.testing.assert_array_equal(s.stiffness, np.diag([GOOD[k] for k in COMPONENTS]))


def _coupled() -> np.ndarray:
    """A symmetric positive definite section with extension-twist and shear-bending coupling."""
    C = np.diag([GOOD[k] for k in COMPONENTS])
    C[0, 3] = C[3, 0] = 0.5 * np.sqrt(GOOD["EA"] * GOOD["GJ"])
    C[1, 5] = C[5, 1] = -0.3 * np.sqrt(GOOD["GAy"] * GOOD["EJz"])
    C[4, 5] = C[5, 4] = 0.2 * np.sqrt(GOOD["EJy"] * GOOD["EJz"])
    return C


def test_full_coupled_matrix_is_accepted():
    C = _coupled()
    assert np.linalg.eigvalsh(C).min() > 0  # the oracle: C is SPD
    s = Section(C, mass_per_length=2.5)
    np.testing.assert_array_equal(s.stiffness, C)
    assert s.mass_per_length == 2.5


def test_non_symmetric_matrix_is_rejected():
    C = _coupled()
    C[0, 3] *= 1.01  # 1 % asymmetry, far above 1e-12
    with pytest.raises(ValueError, match=r"stiffness must be symmetric"):
        Section(C)


def test_indefinite_matrix_with_positive_diagonal_is_rejected():
    C = np.diag([GOOD[k] for k in COMPONENTS])
    # coupling larger than sqrt(EA EJy): the 2x2 minor EA EJy - c^2 < 0, so C is indefinite
    # although every diagonal entry is positive
    C[0, 4] = C[4, 0] = 2 * np.sqrt(GOOD["EA"] * GOOD["EJy"])
    assert np.linalg.eigvalsh(C).min() < 0
    with pytest.raises(ValueError, match=r"positive definite \(smallest eigenvalue -"):
        Section(C)


def test_full_matrix_with_a_negative_diagonal_entry_names_it():
    C = _coupled()
    C[4, 4] = -1.0
    with pytest.raises(ValueError, match=r"positive definite \(EJy = -1\)"):
        Section(C)


def test_non_finite_full_matrix_is_rejected():
    C = _coupled()
    C[2, 2] = np.nan
    with pytest.raises(ValueError, match=r"non-finite"):
        Section(C)


@pytest.mark.parametrize("mass", [-1.0, np.nan, np.inf])
def test_bad_mass_is_rejected(mass):
    with pytest.raises(ValueError, match=rf"mass_per_length must be finite and >= 0, got {mass}"):
        Section.diagonal(**GOOD, mass_per_length=mass)


def test_global_stiffness_of_identity_frame_is_the_section_stiffness():
    s = Section(_coupled())
    # R6 = I: the products are exact (multiplications by 1 and additions of 0)
    np.testing.assert_array_equal(s.global_stiffness(np.eye(3)), s.stiffness)


def test_global_stiffness_is_the_rotated_matrix():
    s = Section(_coupled())
    frames = Rotation.random(5, random_state=11).as_matrix()
    Cg = s.global_stiffness(frames)
    assert Cg.shape == (5, 6, 6)
    for R, C in zip(frames, Cg, strict=True):
        R6 = block_diag(R, R)
        # roundoff: two 6x6 products, 6 terms each, relative to max |C|
        np.testing.assert_allclose(
            C, R6 @ s.stiffness @ R6.T, rtol=0, atol=50 * EPS * np.abs(s.stiffness).max()
        )


def test_global_stiffness_of_a_beam_along_y_permutes_the_components():
    # t = e_y, e3 = e_z, e2 = e3 x t = -e_x: global x carries the e2 components, y the axial
    # ones.  Signs cancel on the diagonal, so C_global = diag(GAy, EA, GAz, EJy, GJ, EJz).
    s = Section.diagonal(**GOOD)
    frame = np.column_stack([[0, 1, 0], [-1, 0, 0], [0, 0, 1]]).astype(float)
    expected = np.diag([GOOD[k] for k in ("GAy", "EA", "GAz", "EJy", "GJ", "EJz")])
    np.testing.assert_array_equal(s.global_stiffness(frame), expected)
