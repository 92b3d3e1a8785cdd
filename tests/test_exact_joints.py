"""Joints with finite rotations (sliders.joints.exact_laws) and exact models of beams, rigid
bodies and joints (sliders.joints.exact_model) against finite differences, rigid motions and
closed-form statics.

Tolerances:

* finite differences: central differences of step ``h`` on the manifold, their truncation
  estimated from a second step ``2 h`` (``|D(2h) - D(h)| / 3``, Richardson for an ``h^2``
  error) and their rounding ``2 eps |terms| / h``; the assertions allow twice the sum;
* round-off: a row or a balance is a sum of a few products of terms of known size, each
  rounded to ``eps`` of its size; 16 bounds "a few" (``fvbeam.exact_statics.FLOOR_FACTOR``);
* a converged equilibrium: the residual on the round-off floor; a closed form then agrees to
  the next Newton correction, bounded by the floor divided by the smallest stiffness.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from fvbeam import rotations
from fvbeam.body import RigidBody
from fvbeam.exact_statics import FLOOR_FACTOR, solve_static
from sliders.joints.exact_laws import KINDS, JointLaw, derive, rows
from sliders.joints.exact_model import ExactModel, Joint, JointedState

EPS = np.finfo(float).eps
RNG = np.random.default_rng(25)
#: A joint frame with ``e_1`` along ``z``: a hinge in the ``x, y`` plane.
Z_AXIS = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
#: Every kind and a support's own choice of rows.
CHOICES = [*KINDS, "uy+rz", "ux+rx+ry"]


def solve(model: ExactModel, load: np.ndarray, state: JointedState | None = None):
    """``solve_static`` on an exact model, named in its messages by the model's name."""
    named = SimpleNamespace(**{k: getattr(model, k) for k in ("n_dofs", "name")})
    for method in ("reference", "points", "residual", "residual_floor", "tangent"):
        setattr(named, method, getattr(model, method))
    named.beam = SimpleNamespace(mesh=SimpleNamespace(name=model.name))
    return solve_static(named, load, [], state=state)


def random_ends(scale: float = 1.0):
    """Two nodes at random positions and finite rotations (up to about 2 rad)."""
    x_a, x_b = scale * RNG.standard_normal((2, 3))
    R_a, R_b = rotations.exp_map(RNG.uniform(-2, 2, (2, 3)))
    return x_a, R_a, x_b, R_b


def random_law(kind: str) -> JointLaw:
    frame = rotations.exp_map(RNG.uniform(-2, 2, 3))
    return JointLaw.at(
        kind, RNG.standard_normal(3), frame, RNG.standard_normal(3), RNG.standard_normal(3)
    )


def moved(x: np.ndarray, R: np.ndarray, dq: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return x + dq[:3], rotations.exp_map(dq[3:]) @ R


def differences(f, h: float) -> np.ndarray:
    """Central differences of ``f(dq)`` (dq the ends' twelve increments) of step ``h``."""
    return np.column_stack([(f(h * e) - f(-h * e)) / (2 * h) for e in np.eye(12)])


@pytest.mark.parametrize("kind", CHOICES)
def test_jacobian_and_geometric_stiffness_match_finite_differences(kind):
    """``B = dc/dq`` and ``H = d(B^T lambda)/dq`` derived by nested dual numbers agree with
    central differences of the rows and of ``B^T lambda`` on the manifold
    (``x + du``, ``exp(dphi) R``) at random finite rotations of both nodes."""
    law = random_law(kind)
    ends = random_ends()
    lam = RNG.standard_normal(len(law.rows))
    derived = derive(law, *ends, lam)

    def state(dq):
        return (*moved(ends[0], ends[1], dq[:6]), *moved(ends[2], ends[3], dq[6:]))

    def c(dq):
        return rows(law, *state(dq)).astype(float)

    def load(dq):
        return derive(law, *state(dq), lam).jacobian.T @ lam

    size = 1 + sum(np.linalg.norm(v) for v in (ends[0], ends[2], law.offset_a, law.offset_b))
    h = 1e-5
    for f, exact, terms in (
        (c, derived.jacobian, size),
        (load, derived.stiffness, size * np.abs(lam).sum()),
    ):
        D1, D2 = differences(f, h), differences(f, 2 * h)
        truncation = np.abs(D2 - D1).max() / 3
        rounding = 2 * EPS * terms / h
        assert np.abs(exact - D1).max() <= 2 * (truncation + rounding)
    # the check has teeth: the geometric stiffness is not small beside it
    assert np.abs(derived.stiffness).max() > 1e3 * (truncation + rounding)


@pytest.mark.parametrize("kind", CHOICES)
def test_a_joint_to_the_ground_has_no_columns_of_the_ground(kind):
    """A support: the ground does not move, its columns are zero; the node's agree with the
    same joint to a node that stays where the ground is."""
    law = random_law(kind)
    x_a, R_a, x_b, R_b = random_ends()
    lam = RNG.standard_normal(len(law.rows))
    grounded = derive(law, x_a, np.eye(3), x_b, R_b, lam, moving=(False, True))
    free = derive(law, x_a, np.eye(3), x_b, R_b, lam)
    assert np.all(grounded.jacobian[:, :6] == 0) and np.all(grounded.stiffness[:6] == 0)
    np.testing.assert_array_equal(grounded.rows, free.rows)
    np.testing.assert_allclose(
        grounded.jacobian[:, 6:], free.jacobian[:, 6:], rtol=0, atol=16 * EPS
    )
    np.testing.assert_allclose(
        grounded.stiffness[6:, 6:],
        free.stiffness[6:, 6:],
        rtol=0,
        atol=16 * EPS * np.abs(lam).sum() * 8,
    )


def allowed_motion(kind: str, law: JointLaw, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """A finite motion of node b about the joint that the kind allows (a rotation ``Q`` about
    the joint's point ``P``, then a translation ``t``), node a at rest in the reference."""
    e = law.frame_a
    point = law.offset_a  # node a at the origin
    if kind == "spherical":
        Q, t = rotations.exp_map(angle * np.array([0.6, -0.8, 0.3])), np.zeros(3)
    elif kind == "revolute":
        Q, t = rotations.exp_map(angle * e[:, 0]), np.zeros(3)
    elif kind == "universal":  # about the pin on a, then about the pin on b, turned with it
        first = rotations.exp_map(angle * e[:, 1])
        Q, t = rotations.exp_map(-0.7 * angle * (first @ e[:, 2])) @ first, np.zeros(3)
    elif kind == "prismatic":
        Q, t = np.eye(3), 3.0 * angle * e[:, 0]
    else:
        Q, t = np.eye(3), np.zeros(3)
    x_b = point + Q @ (-law.offset_b) + t  # node b's reference position is P - p_b
    return x_b, Q


@pytest.mark.parametrize("kind", list(KINDS))
def test_rows_vanish_on_the_motions_the_joint_allows(kind):
    """Each kind's rows are zero, to round-off, after a finite motion it allows (1.3 rad
    about the free axes, a slide of 4 along a prismatic axis), and after a rigid motion of
    both nodes together; a motion it does not allow leaves a row of the motion's size."""
    law = JointLaw.at(
        kind, [0.4, -0.2, 0.9], rotations.exp_map([0.3, 1.1, -0.5]), [0, 0, 0], [1, 2, -1]
    )
    x_b, Q = allowed_motion(kind, law, 1.3)
    # rows: products of unit vectors and of the gap's terms (positions of size 3)
    tol = FLOOR_FACTOR * EPS * 8
    assert np.abs(rows(law, np.zeros(3), np.eye(3), x_b, Q).astype(float)).max() <= tol
    G, t = rotations.exp_map([2.0, -1.0, 0.5]), np.array([5.0, 1.0, -2.0])
    both = rows(law, t, G, G @ x_b + t, G @ Q).astype(float)
    assert np.abs(both).max() <= tol * 2
    # a turn about the axis every kind but the spherical one holds (e_2 for the revolute)
    held = rotations.exp_map(0.3 * law.frame_a[:, 1 if kind in ("revolute", "universal") else 0])
    if kind != "spherical":
        assert np.abs(rows(law, np.zeros(3), np.eye(3), x_b, held @ Q).astype(float)).max() > 0.1


def test_first_order_rows_are_the_linear_joints():
    """At the reference the fixed joint's Jacobian is the linear joint's: position rows the
    gap's components in the frame, ``F^T (du_b + dphi_b x p_b - du_a - dphi_a x p_a)``, and
    rotation rows ``(-1, 1, -1)`` times the relative rotation's components ``F^T (dphi_b -
    dphi_a)`` (module docstring of sliders.joints.exact_laws)."""
    F = rotations.exp_map([0.3, -1.2, 0.8])
    law = JointLaw.at("fixed", [1.0, 2.0, 0.5], F, [0, 0, 0], [2.0, 1.0, 1.0])
    B = derive(law, np.zeros(3), np.eye(3), [2.0, 1.0, 1.0], np.eye(3), np.zeros(6)).jacobian
    skew = lambda p: np.cross(np.eye(3), p)  # noqa: E731 - rows: e_k x p, so skew @ w = -p x w
    expected = np.zeros((6, 12))
    expected[:3, 0:3], expected[:3, 6:9] = -F.T, F.T
    expected[:3, 3:6] = F.T @ skew(law.offset_a)  # -(dphi x p) = p x dphi
    expected[:3, 9:12] = -F.T @ skew(law.offset_b)
    signs = np.diag([-1.0, 1.0, -1.0])
    expected[3:, 3:6], expected[3:, 9:12] = -signs @ F.T, signs @ F.T
    np.testing.assert_allclose(B, expected, rtol=0, atol=16 * EPS * 4)


# -- exact models -------------------------------------------------------------------------
def pendulum(length: float, frame: np.ndarray = Z_AXIS, Q: np.ndarray | None = None) -> ExactModel:
    """A bob hanging ``length`` below a hinge at the origin (axis ``e_1`` of ``frame``),
    everything turned by ``Q``."""
    Q = np.eye(3) if Q is None else Q
    bob = RigidBody("bob", Q @ [0.0, -length, 0.0])
    hinge = Joint("revolute", "ground", "bob", position=[0.0, 0.0, 0.0], frame=Q @ frame)
    return ExactModel(bodies=[bob], joints=[hinge], name="pendulum")


@pytest.mark.parametrize("angle", [np.pi / 6, np.pi / 3, 1.4])
def test_a_pendulum_on_a_hinge_balances_its_couple(angle):
    """A bob of weight ``W`` on an arm ``L`` under a dead couple ``M`` about the hinge's
    axis: ``M = W L sin(theta)`` (the static moment balance), the hinge carrying the
    weight; the arm turned by ``theta`` from the vertical, about the axis only."""
    L, W = 1.5, 2.0
    model = pendulum(L)
    load = np.zeros(model.n_dofs)
    load[1], load[5] = -W, W * L * np.sin(angle)
    result = solve(model, load, model.balanced(model.reference(), load))
    x, R = result.state.nodes.x[0], result.state.nodes.R[0]
    # the solution is off by the next Newton correction: the residual's floor (16 eps
    # times terms of size W L) over the pendulum's stiffness W L cos(theta)
    tol = FLOOR_FACTOR * EPS * 4 / np.cos(angle)
    np.testing.assert_allclose(
        x, L * np.array([np.sin(angle), -np.cos(angle), 0.0]), rtol=0, atol=tol
    )
    np.testing.assert_allclose(R, rotations.exp_map([0.0, 0.0, angle]), rtol=0, atol=tol)
    force, couple = model.reactions(result.state)[0][1, :3], model.reactions(result.state)[0][1, 3:]
    np.testing.assert_allclose(force, [0.0, -W, 0.0], rtol=0, atol=tol * W)
    np.testing.assert_allclose(couple, [0.0, 0.0, W * L * np.sin(angle)], rtol=0, atol=tol * W * L)


def test_the_model_is_invariant_under_a_rigid_rotation():
    """The pendulum built turned by a finite rotation ``Q`` (its bob, hinge and loads)
    reaches ``Q`` times the unturned equilibrium, and ``Q R Q^T`` for the bob's rotation."""
    L, W, angle = 1.5, 2.0, 1.0
    Q = rotations.exp_map([0.9, -1.7, 0.4])
    here, there = pendulum(L), pendulum(L, Q=Q)
    load = np.zeros(here.n_dofs)
    load[1], load[5] = -W, W * L * np.sin(angle)
    turned = load.copy()
    turned[:3], turned[3:6] = Q @ load[:3], Q @ load[3:6]
    a = solve(here, load, here.balanced(here.reference(), load)).state.nodes
    b = solve(there, turned, there.balanced(there.reference(), turned)).state.nodes
    tol = FLOOR_FACTOR * EPS * 8 / np.cos(angle)
    np.testing.assert_allclose(b.x[0], Q @ a.x[0], rtol=0, atol=tol * L)
    np.testing.assert_allclose(b.R[0], Q @ a.R[0] @ Q.T, rtol=0, atol=tol)
