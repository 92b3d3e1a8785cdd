"""The compiled exact beam (fvbeam.exact_kernel) against its numpy statement
(fvbeam.exact_beam with ``compiled=False``): one law, two forms, equal to round-off.

Tolerances: each compared quantity is a sum of a few products, each rounded to ``eps`` of its
size, summed in another order by the two forms:

* kinematics and stress at the points: ``16 eps`` of the field's largest entry (a few
  tens of roundings of terms of that size; the rotation vectors from two algorithms for the
  logarithm, each accurate to a few ``eps``);
* the residual: 16 eps of its round-off floor (:meth:`ExactBeam.residual_floor`, the bound of
  its terms' sizes), the solver's own convergence test;
* the floor itself (positive terms): ``16 eps`` relative;
* the tangent: ``64 eps`` of its largest entry, as the tangent's own tests
  (``tests/test_exact_beam.py``).
"""

from dataclasses import fields

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fvbeam import exact_kernel, rotations
from fvbeam.exact_beam import ExactBeam
from tests.test_exact_beam import curved_beam, random_state

EPS = np.finfo(float).eps
FIELDS = ("psi_nodes", "psi", "dpsi", "Lambda", "x", "dx", "strain", "force", "moment")


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
@pytest.mark.parametrize("angle", [1e-3, 1.0, 2.5])
def test_compiled_law_equals_its_statement(name, angle):
    """At random states with nodal rotations of up to ``angle`` (series and closed forms of
    the rotation coefficients; relative rotations beyond a half turn of each other reach the
    logarithm's far branch): points for every formulation, and the fv balances, their floor
    and tangent (on a subset of the dofs, as Newton assembles them)."""
    compiled = ExactBeam(curved_beam(name))
    statement = ExactBeam(compiled.beam, compiled=False)
    state = random_state(compiled, 0.3, angle)
    fast, slow = compiled.points(state), statement.points(state)
    for field in FIELDS:
        a, b = getattr(fast, field), getattr(slow, field)
        assert np.abs(a - b).max() <= 16 * EPS * np.abs(b).max(), field
    floor = statement.residual_floor(state)
    np.testing.assert_allclose(compiled.residual_floor(state), floor, rtol=16 * EPS)
    residual = compiled.residual(state) - statement.residual(state)
    assert np.all(np.abs(residual) <= 16 * EPS * floor)
    keep = np.arange(6, compiled.n_dofs)
    K, K_statement = compiled.tangent(state, keep=keep), statement.tangent(state, keep=keep)
    assert K.shape == (len(keep), len(keep))
    assert abs(K - K_statement).max() <= 64 * EPS * abs(K_statement).max()


def test_rotation_logarithm_and_exponential_equal_scipys():
    """``log_at`` and ``exp_at`` against scipy's ``Rotation`` (the statement's) at angles from
    1e-9 to within 1e-6 of a half turn about random axes: the rotation vectors agree to
    ``16 eps`` of the angle, plus the logarithm's conditioning near a half turn (the axis
    from ``R - R^T``, of size ``sin t``: ``eps / sin t``)."""
    rng = np.random.default_rng(7)
    for angle in (1e-9, 1e-5, 1e-3, 0.04, 0.06, 1.0, 3.0, np.pi - 1e-6):
        axis = rng.standard_normal(3)
        psi = angle * axis / np.linalg.norm(axis)
        R = Rotation.from_rotvec(psi).as_matrix()
        np.testing.assert_allclose(exact_kernel.exp_at(psi), R, rtol=0, atol=16 * EPS)
        tol = 16 * EPS * (angle + 1 / np.sin(angle))
        np.testing.assert_allclose(exact_kernel.log_at(R), rotations.log_map(R), rtol=0, atol=tol)


def test_compiled_update_equals_the_statements():
    """``ExactState.updated`` turns the rotations as :func:`fvbeam.rotations.update` does (to
    ``16 eps``, the matrices' entries being of size 1), the positions by the increment."""
    exact = ExactBeam(curved_beam("fv3"))
    state = random_state(exact, 0.3, 1.0)
    dq = np.random.default_rng(3).uniform(-2.0, 2.0, exact.n_dofs)
    moved = state.updated(dq)
    turn = rotations.update(state.R, dq.reshape(-1, 6)[:, 3:])
    np.testing.assert_allclose(moved.R, turn, rtol=0, atol=16 * EPS)
    np.testing.assert_array_equal(moved.x, state.x + dq.reshape(-1, 6)[:, :3])


def test_point_state_arrays_are_its_fields_in_order():
    """``PointState.arrays`` hands the kernels the fields in the order they are declared (and
    :func:`fvbeam.exact_kernel.points` returns them)."""
    exact = ExactBeam(curved_beam("fv2"))
    pts = exact.points(random_state(exact, 0.3, 1.0))
    assert [f.name for f in fields(pts)] == list(FIELDS)
    assert all(a is getattr(pts, name) for a, name in zip(pts.arrays(), FIELDS, strict=True))


@pytest.mark.parametrize("name", ["fv2", "fv3"])
def test_position_block_is_the_tangents(name):
    """The tangent on the positions alone (the force correction's) from its own kernel
    equals the full tangent's block on them (64 eps of its largest entry)."""
    exact = ExactBeam(curved_beam(name))
    state = random_state(exact, 0.3, 1.0)
    keep = np.arange(6, exact.n_dofs)
    positions = keep[keep % 6 < 3]
    full = exact.tangent(state, keep=keep).toarray()
    inside = np.searchsorted(keep, positions)
    block = exact.tangent(state, keep=positions).toarray()
    assert np.abs(block - full[np.ix_(inside, inside)]).max() <= 64 * EPS * np.abs(full).max()
    assert np.abs(block).max() > 0.1 * np.abs(full).max()  # the axial and shear stiffness
