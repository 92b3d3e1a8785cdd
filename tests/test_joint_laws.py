"""The joints' laws are written once: dual numbers derive their Jacobian, and the compiled
kernel is held to it.

- Dual numbers (:mod:`sliders.joints.dual`) give the exact derivative of arithmetic: a
  polynomial and a quotient against their derivatives in closed form, to the roundoff of
  evaluating those (a few ulps of the terms).
- A mutation check: changing one term of one law's statement (the section axis'
  ``xi``-derivative ``t_0/xi = k_0 x t_0``, scaled by 1 + 1e-3) changes the reference's
  residual and its Jacobian together (no second copy of the Jacobian beside the law), and the
  compiled kernel no longer meets the reference within the roundoff bound that it meets
  unchanged: the kernel is held to the one statement.
- The pattern a law writes is its sparsity: the slope form's couple reads the body's
  rotation, the section form's does not.
"""

import numpy as np
import pytest
from test_joint_reference import (
    OFFSETS,
    assert_equal_to_roundoff,
    batch_of,
    kernel_equations,
    random_state,
    roundoff_bounds,
)

from sliders.joints import equations
from sliders.joints.dual import Dual, gradients, seeded, values
from sliders.joints.equations import JointInputs, joint_reference, pattern

EPS = np.finfo(float).eps


def test_duals_differentiate_a_polynomial_and_a_quotient():
    """``f = x^2 y - 3 x / y`` at (x, y) = (1.3, -0.7): its gradient
    ``(2 x y - 3 / y, x^2 + 3 x / y^2)``, within 8 ulps of the largest term (each entry a
    sum of three products or quotients, rounded once each, then summed)."""
    x, y = 1.3, -0.7
    dx, dy = seeded(np.array([x, y]), {0: np.array([1.0, 0.0]), 1: np.array([0.0, 1.0])})
    f = dx * dx * dy - 3 * dx / dy
    assert isinstance(f, Dual)
    exact = np.array([2 * x * y - 3 / y, x**2 + 3 * x / y**2])
    terms = np.array([abs(2 * x * y) + abs(3 / y), x**2 + abs(3 * x / y**2)])
    assert abs(values(np.array([f]))[0] - (x * x * y - 3 * x / y)) <= 8 * EPS * 5
    assert np.all(np.abs(gradients(np.array([f]), 2)[0].astype(float) - exact) <= 8 * EPS * terms)


def test_a_constant_has_no_gradient_and_arrays_keep_their_own_arithmetic():
    """A dual times a float array is the array's elementwise product (an object array of
    duals), and a quantity that reads no seeded direction has an exactly zero gradient."""
    (a,) = seeded(np.array([2.0]), {0: np.array([1.0])})
    product = np.array([1.0, -2.0, 0.5]) * a
    assert product.dtype == object and product.shape == (3,)
    assert [p.value for p in product] == [2.0, -4.0, 1.0]
    assert [p.grad for p in product] == [{0: 1.0}, {0: -2.0}, {0: 0.5}]
    (c,) = seeded(np.array([3.0]), {})
    assert np.all(gradients(np.array([c * c + 1.0]), 4) == 0.0)


@pytest.mark.parametrize("line", ["fv3", "arc"])
def test_changing_one_term_of_a_law_changes_the_reference_and_parts_it_from_the_kernel(
    line, monkeypatch
):
    """The mutation check (module docstring), for the classical slider on the section frame,
    at inputs drawn at random (a curved section frame, so that ``t_0/xi`` is not zero): with
    the term scaled, the reference's ``xi`` row and its ``(xi, xi)`` and ``(xi, mu)`` blocks
    move by much more than their roundoff bounds, and the kernel, which meets the unchanged
    reference, fails the mutated one."""
    kind, orientation = "classical", "section"
    batch = batch_of(kind, orientation, line, OFFSETS["off the node"])
    rng = np.random.default_rng(8)
    _, inputs = batch.joint_inputs(*random_state(batch, rng))
    drawn = JointInputs(
        *(a if np.asarray(a).dtype.kind == "i" else rng.uniform(-1, 1, np.shape(a)) for a in inputs)
    )
    drawn = drawn._replace(offset=OFFSETS["off the node"], scale=1.0)
    r, J = batch.joint_equations(drawn)
    kernel = kernel_equations(r, J)
    bound = roundoff_bounds(kind, orientation, drawn)
    before = joint_reference(kind, orientation, drawn)
    assert_equal_to_roundoff(kernel, before, bound)

    section_axis = equations._section_axis

    def mutated(line_point):
        t0, t1 = section_axis(line_point)
        return t0, t1 * 1.001

    monkeypatch.setattr(equations, "_section_axis", mutated)
    after = joint_reference(kind, orientation, drawn)
    moved = np.abs(after.residual["xi"] - before.residual["xi"])
    assert np.all(moved > 1e3 * bound.residual["xi"])
    for block in (("xi", "xi"), ("xi", "mu")):
        change = np.abs(after.jacobian[block] - before.jacobian[block])
        assert np.any(change > 1e3 * bound.jacobian[block]), block
    with pytest.raises(AssertionError):
        assert_equal_to_roundoff(kernel, after, bound)


def test_the_pattern_is_the_laws_sparsity():
    """The slope form's couple ``mu_j e_bj x l`` turns with the body (``(turn, turn)``) and
    reads the line's gradient (``(mu, interp)``); the section form's orientation rows read
    the section rotation (``(mu, rotation)``) instead.  Off the node, the lever arm adds
    ``(turn, turn)`` and ``(lam, turn)`` to every kind; on it, ``(turn, lam)`` is zero."""
    slope = pattern("classical", "slope", False, False)
    section = pattern("classical", "section", False, True)
    assert ("turn", "turn") in slope and ("mu", "interp") in slope
    assert ("turn", "turn") not in section and ("mu", "interp") not in section
    assert ("mu", "rotation") in section and ("mu", "rotation") not in slope
    for kind in ("spherical", "classical", "spline"):
        on, off = pattern(kind, "section", False, False), pattern(kind, "section", True, False)
        assert ("turn", "lam") not in on and {("turn", "lam"), ("lam", "turn")} <= set(off)
