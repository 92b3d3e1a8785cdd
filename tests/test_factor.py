"""The compiled solve on exported SuperLU factors (:mod:`sliders.solve.factor`) against
SuperLU's own solve, to roundoff.

Both apply the same triangular factors to the same right-hand side, in possibly different
orders of summation: the difference is bounded by the backward error of a triangular solve,
``n eps |L||U|``-sized (Higham, Thm. 8.5), so the two agree within ``n eps`` times the
condition number of ``A`` times ``|x|``; the test matrices are well conditioned (diagonally
dominant, cond < 10), bound ``10 n eps |x|``.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from fvbeam import Beam, Section, Structure, straight
from sliders.solve.factor import Factor

EPS = np.finfo(float).eps


@pytest.mark.parametrize("n", [1, 7, 60, 400])
def test_compiled_solve_equals_superlu(n: int) -> None:
    rng = np.random.default_rng(n)
    A = sp.random(n, n, density=min(1.0, 5 / n), random_state=n, format="csc")
    A = A + sp.diags(np.abs(A).sum(axis=1).A1 + 1.0)  # diagonally dominant, unsymmetric
    factor = Factor(A)
    for _ in range(3):
        b = rng.standard_normal(n)
        x = factor.solve(b)
        reference = factor.lu.solve(b)
        assert np.abs(x - reference).max() <= 10 * n * EPS * np.abs(reference).max()


def test_a_beam_stiffness() -> None:
    """An unsymmetric fv3 stiffness, clamped (condition number measured): the two solves
    agree within ``n eps cond(K) |x|``."""
    section = Section.diagonal(EA=1e3, GAy=1, GAz=1, GJ=1, EJy=1, EJz=1)
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 8, 3, name="b"), section, "fv3")
    K = Structure([beam]).tangent(np.zeros(beam.n_dofs)).tocsc()[6:, 6:]
    factor = Factor(K)
    b = np.random.default_rng(1).standard_normal(K.shape[0])
    x = factor.solve(b)
    bound = K.shape[0] * EPS * np.linalg.cond(K.toarray()) * np.abs(x).max()
    assert np.abs(x - factor.lu.solve(b)).max() <= bound


def test_a_singular_matrix_is_refused() -> None:
    with pytest.raises(ValueError, match="singular"):
        Factor(sp.csc_matrix(np.array([[1.0, 2.0], [2.0, 4.0]])))
