"""Shear locking of a thin cantilever: full vs reduced Galerkin P1, fv2, fv3, Galerkin P2.

Closed forms used below (tip force F on a cantilever of n equal elements, h = L / n):

* One-point (reduced) P1.  The element shear force is F and the element bending moment is the
  exact moment at the element mid-point, so the nodal rotations are exact and the tip
  deflection is FL/GA plus the composite trapezoid rule of the exact (quadratic) rotation::

      v_reduced = F L^3 / (3 EJ) (1 - 1 / (4 n^2)) + F L / GA        (n = 1: F L^3/(4 EJ) + F L/GA)

* Two-point (full) P1.  Split the rotation on each element into its mean and its linear part:
  the shear strain ``v' - theta`` (v' piecewise constant) has an L2-orthogonal part
  ``-theta' (x - x_mid)`` costing ``GA h^2 / 12 * theta'^2`` per unit length.  That is reduced P1
  with the bending stiffness ``EJ* = EJ + GA h^2 / 12``: the tip deflection is ``v_reduced`` with
  EJ replaced by EJ*.  For GA L^2 / EJ = 1e6 the ratio to the exact deflection is about
  12 n^2 EJ / (GA L^2): 1.2e-5, 1.9e-4, 3.1e-3 for n = 1, 4, 16 (locking).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fvbeam import Beam, LinearStatics, Section, Support, arc, closed_forms, straight

EPS = np.finfo(float).eps
L, EJ, GA, F = 1.0, 1.0, 1.0e6, 1.0  # GA L^2 / EJ = 1e6: a thin beam
SECTION = Section.diagonal(EA=10 * GA, GAy=GA, GAz=GA, GJ=1.0, EJy=EJ, EJz=EJ)
V_FLEX, V_SHEAR, PHI = closed_forms.cantilever_exact(L, L, EJ, GA, F)
V_EXACT = V_FLEX + V_SHEAR
RTOL_FORMULA = 1e1 * EPS  # roundoff of evaluating a closed form: ~10 operations


def _tip(form: str, integration: str, n: int):
    """Tip displacement/rotation and a componentwise roundoff bound on them."""
    npe = 2 if form in ("fv2", "galerkin-p1") else 3
    beam = Beam(straight((0, 0, 0), (L, 0, 0), n, npe), SECTION, form, integration)
    statics = LinearStatics(beam, [Support(0, "start")])
    f = beam.point_load(L, force=(0, F, 0))
    q = statics.solve(f)
    # roundoff of the LU solve, componentwise (Skeel / Higham Thm 9.4, no pivot growth in a
    # banded stiffness): |dq| <= gamma_3n |K^-1| (|K| |q| + |f|), gamma_3n ~ 3 n eps
    A = statics.K[statics.free][:, statics.free].toarray()
    x, b = q[statics.free], f[statics.free]
    bound = np.zeros_like(q)
    bound[statics.free] = (
        3 * len(x) * EPS * np.abs(np.linalg.inv(A)) @ (np.abs(A) @ np.abs(x) + np.abs(b))
    )
    # xi = L is the last vertex: the tip values are exactly its nodal dofs
    tip = beam.node_dofs(beam.mesh.n_elements)
    np.testing.assert_array_equal(beam.displacements(q, L)[0], q[tip])
    return q[tip], bound[tip], beam


def _p1_tip(n: int, EJ_eff: float) -> float:
    return F * L**3 / (3 * EJ_eff) * (1 - 1 / (4 * n**2)) + F * L / GA


@pytest.mark.parametrize("n", [1, 4, 16])
def test_full_p1_locks(n):
    tip, tol, _ = _tip("galerkin-p1", "full", n)
    EJ_star = EJ + GA * (L / n) ** 2 / 12
    np.testing.assert_allclose(tip[1], _p1_tip(n, EJ_star), rtol=RTOL_FORMULA, atol=tol[1])
    ratio = tip[1] / V_EXACT
    # locking: ratio ~ 12 n^2 EJ / (GA L^2) <= 12 * 256 / 1e6 = 3.1e-3 for n <= 16;
    # at least ten times too stiff
    assert ratio < 0.1


def test_reduced_p1_one_element_closed_form():
    tip, tol, _ = _tip("galerkin-p1", "reduced", 1)
    np.testing.assert_allclose(
        tip[1], F * L**3 / (4 * EJ) + F * L / GA, rtol=RTOL_FORMULA, atol=tol[1]
    )


def test_reduced_p1_converges_quadratically():
    ns = np.array([1, 2, 4, 8, 16])
    err = []
    for n in ns:
        tip, tol, _ = _tip("galerkin-p1", "reduced", n)
        np.testing.assert_allclose(tip[1], _p1_tip(n, EJ), rtol=RTOL_FORMULA, atol=tol[1])
        # nodal rotations are exact (mid-point rule on the linear moment)
        np.testing.assert_allclose(tip[5], PHI, rtol=RTOL_FORMULA, atol=tol[5])
        err.append((tip[1] - V_EXACT) / V_FLEX)
    err = np.array(err)
    # closed form: relative flexural error -1 / (4 n^2) exactly
    order = np.log2(err[:-1] / err[1:])
    # roundoff (< 1e-5 of v, bound above) on errors >= 1e-3 of v: log2 shifts by < 1e-2
    assert np.all(np.abs(order - 2) < 1e-2), order


GENERAL = Section.diagonal(7, 2, 3, 1.5, 1.2, 0.8)
Q5 = Rotation.random(random_state=5).as_matrix()


@pytest.mark.parametrize(
    "mesh, section",
    [
        (straight((0, 0, 0), (L, 0, 0), 1, 2), SECTION),
        (straight((0, 0, 0), (L, 0, 0), 4, 2), SECTION),
        (straight((0, 0, 0), Q5 @ [2.0, 0, 0], 4, 2, up=Q5 @ [0, 0, 1.0]), GENERAL),
        (arc((0.3, 0.1, 0.2), 1.3, 0.2, 2.5, 5, 2), GENERAL),
    ],
    ids=["thin-1", "thin-4", "rotated-4", "arc-5"],
)
def test_fv2_stiffness_equals_one_point_p1(mesh, section):
    K_fv = Beam(mesh, section, "fv2").stiffness.toarray()
    K_p1 = Beam(mesh, section, "galerkin-p1", "reduced").stiffness.toarray()
    # roundoff: each entry sums a few (< 1e2) products of O(max |K|) terms
    np.testing.assert_allclose(K_fv, K_p1, rtol=0, atol=1e2 * EPS * np.abs(K_p1).max())


@pytest.mark.parametrize("form", ["fv3", "galerkin-p2"])
def test_three_node_reduced_does_not_lock(form):
    tip, tol, _ = _tip(form, "reduced", 4)
    # both are exact for a tip load on a straight beam (fv3: closed_forms.cantilever_fv3 at
    # xi = L; P2 with 2-point Gauss: the shear is constant and the moment linear)
    assert closed_forms.cantilever_fv3(L, L, EJ, GA, F)[0] == pytest.approx(
        V_FLEX, rel=RTOL_FORMULA
    )
    np.testing.assert_allclose(tip[1], V_EXACT, rtol=RTOL_FORMULA, atol=tol[1])
    np.testing.assert_allclose(tip[5], PHI, rtol=RTOL_FORMULA, atol=tol[5])
