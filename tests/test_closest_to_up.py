"""Where ``up`` may come closest to a centreline (:func:`fvbeam.geometry.closest_to_up`):
for elements whose tangent is linear in their reference coordinate, the stationary points of
the across part's square (a quadratic on each piece, solved in closed form) are the roots of
its derivative that scipy's piecewise polynomials find."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import PPoly

from fvbeam.geometry import closest_to_up


def reference(coefficients: np.ndarray, breaks: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The stationary points by :class:`scipy.interpolate.PPoly` (the general path)."""
    across = coefficients - np.einsum("kmj,j->km", coefficients, up)[..., None] * up
    square = np.array([(across[0] ** 2).sum(-1), 2 * (across[0] * across[1]).sum(-1)])
    square = np.vstack([square, (across[1] ** 2).sum(-1)])
    roots = PPoly(square, breaks).derivative().roots(discontinuity=False, extrapolate=False)
    return np.concatenate([breaks, roots[np.isfinite(roots)]])


def test_linear_tangents_match_the_piecewise_polynomial_roots() -> None:
    rng = np.random.default_rng(7)
    for pieces in (1, 5, 40):
        coefficients = rng.normal(size=(2, pieces, 3))
        breaks = np.arange(pieces + 1.0)
        up = np.array([0.0, 0.0, 1.0])
        found = closest_to_up(coefficients, breaks, up)
        expected = reference(coefficients, breaks, up)
        # the same points (each side's nearest on the other within round-off of a root of a
        # linear function of O(1) coefficients; a root on a break may appear twice)
        gap = np.abs(found[:, None] - expected[None, :])
        assert gap.min(axis=1).max() < 1e-9 and gap.min(axis=0).max() < 1e-9


def test_a_straight_element_has_no_stationary_point_inside() -> None:
    """A constant tangent (zero slope): the square is constant, only the breaks remain."""
    coefficients = np.stack([np.zeros((3, 3)), np.tile([1.0, 0.0, 0.0], (3, 1))])
    breaks = np.arange(4.0)
    assert np.array_equal(closest_to_up(coefficients, breaks, np.array([0.0, 1.0, 0.0])), breaks)
