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

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

from fvbeam import rotations
from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.exact_beam import ExactBeam, ExactState
from fvbeam.exact_statics import FLOOR_FACTOR, solve_static
from fvbeam.mesh import straight
from fvbeam.section import Section
from sliders.joints import exact_rows
from sliders.joints.exact_laws import KINDS, JointLaw, derive, derive_many, rows
from sliders.joints.exact_model import ExactModel, Joint, JointedState

EPS = np.finfo(float).eps
RNG = np.random.default_rng(25)
#: A joint frame with ``e_1`` along ``z``: a hinge in the ``x, y`` plane.
Z_AXIS = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
#: Every kind and a support's own choice of rows.
CHOICES = [*KINDS, "uy+rz", "ux+rx+ry"]


def solve(model: ExactModel, load: np.ndarray, state: JointedState | None = None, fixed=()):
    """``solve_static`` on an exact model (a :class:`fvbeam.exact_statics.StaticOperator`)."""
    return solve_static(model, load, fixed, state=state)


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


def test_the_generated_rows_are_the_statements():
    """:func:`derive_many` (the rows' generated form, :mod:`sliders.joints.exact_rows`) gives
    :func:`derive`'s rows, ``B`` and ``H`` (dual numbers on the same statement) for every
    kind and choice at once, random finite rotations, a ground end among them: to the
    rounding of sums of a few products of terms of the sizes of the positions, offsets and
    multipliers (64 eps of their products)."""
    laws = [random_law(kind) for kind in CHOICES]
    ends = [random_ends() for _ in laws]
    lam = [RNG.standard_normal(len(law.rows)) for law in laws]
    moving = np.ones((len(laws), 2), dtype=bool)
    moving[-1, 0] = False
    fields = [np.array([e[k] for e in ends]) for k in range(4)]
    many = derive_many(laws, *fields, lam, moving)
    for law, end, m, move, got in zip(laws, ends, lam, moving, many, strict=True):
        want = derive(law, *end, m, tuple(move))
        size = 1 + sum(np.linalg.norm(v) for v in (end[0], end[2], law.offset_a, law.offset_b))
        tol = 64 * EPS * size
        np.testing.assert_allclose(got.rows, want.rows, rtol=0, atol=tol)
        np.testing.assert_allclose(got.jacobian, want.jacobian, rtol=0, atol=tol)
        np.testing.assert_allclose(
            got.stiffness, want.stiffness, rtol=0, atol=tol * np.abs(m).sum()
        )


def test_regenerating_the_rows_changes_nothing():
    """The committed :mod:`sliders.joints.exact_rows` is the generator's text."""
    pytest.importorskip("sympy")
    from sliders.joints import exact_generate

    assert exact_generate.source() == Path(exact_rows.__file__).read_text()


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
    both nodes together; a turn it does not allow leaves a rotation row of the turn's sine
    (the dot product of two axes it keeps orthogonal)."""
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
    # a turn by 0.3 about the joint's point and an axis the kind holds (e_2 for the
    # revolute, the twist e_1 for the others): a rotation row of sin(0.3) exactly
    if kind != "spherical":
        G = rotations.exp_map(0.3 * law.frame_a[:, 1 if kind == "revolute" else 0])
        point, x_ref = law.offset_a, law.offset_a - law.offset_b
        turned = rows(law, np.zeros(3), np.eye(3), point + G @ (x_ref - point), G)
        assert abs(np.abs(turned.astype(float)).max() - np.sin(0.3)) <= tol


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


def truss(formulation: str = "fv2", n: int = 2, Q: np.ndarray | None = None) -> ExactModel:
    """Two bars from the ground at ``(-1, 0)`` and ``(1, 0)`` to an apex at ``(0, 1)``, hinged
    (revolute, axis ``z``) to the ground and to each other: stocky bars (``EA = 100``,
    ``EJ = 100``: Euler's load is far above their force), so they only shorten; everything
    turned by ``Q``."""
    Q = np.eye(3) if Q is None else Q
    section = Section.diagonal(EA=100.0, GAy=100.0, GAz=100.0, GJ=100.0, EJy=100.0, EJz=100.0)
    npe = 2 if formulation in ("fv2", "galerkin-p1") else 3
    bars = [
        ExactBeam(
            Beam(
                straight(Q @ start, Q @ [0, 1, 0], n, npe, up=Q @ [0, 0, 1], name=name),
                section,
                formulation,
            )
        )
        for name, start in (("left", [-1, 0, 0]), ("right", [1, 0, 0]))
    ]
    hinges = [
        Joint("revolute", "ground", "left.start", frame=Q @ Z_AXIS),
        Joint("revolute", "ground", "right.start", frame=Q @ Z_AXIS),
        Joint("revolute", "left.end", "right.end", frame=Q @ Z_AXIS),
    ]
    return ExactModel(beams=bars, joints=hinges, name="truss")


def truss_load(
    model: ExactModel, height: float, apex: str = "left.end"
) -> tuple[np.ndarray, float, float]:
    """The load on node ``apex`` that brings the apex to ``height`` (closed form: each bar of length
    ``l = sqrt(1 + h^2)`` carries ``N = EA (l / L_0 - 1)``, and ``P = -2 N h / l``), with
    ``N`` and ``l``."""
    EA, L0 = 100.0, np.sqrt(2.0)
    length = np.hypot(1.0, height)
    force = EA * (length / L0 - 1.0)
    load = np.zeros(model.n_dofs)
    load[int(model.structure.node_dofs(apex)[1])] = 2 * force * height / length
    return load, force, length


@pytest.mark.parametrize("formulation", ["fv2", "galerkin-p2"])
def test_a_hinged_two_bar_truss_meets_its_closed_form(formulation):
    """The toggle: an apex load ``P`` lowers the apex of a hinged two-bar truss from 1 to
    0.6 (each bar turned by 0.245 rad, shortened by 26 %), as the closed form of
    :func:`truss_load` gives; each ground hinge pushes its bar along the bar with ``|N|``.
    A straight bar in uniform axial strain is exact in every formulation, so the agreement
    is to round-off: the next Newton correction, the floor over the axial stiffness."""
    model = truss(formulation)
    load, force, length = truss_load(model, 0.6)
    result = solve(model, load)
    apex = result.state.nodes.x[model.structure.node_dofs("left.end")[0] // 6]
    tol = FLOOR_FACTOR * EPS * 100.0 * 8  # floor of terms of size EA, stiffness about EA/8
    np.testing.assert_allclose(apex, [0.0, 0.6, 0.0], rtol=0, atol=tol)
    for i, root in enumerate(([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0])):
        along = (np.array([0.0, 0.6, 0.0]) - root) / length
        pushed = -model.reactions(result.state)[i][1, :3]  # the hinge's force on the bar
        np.testing.assert_allclose(pushed, -force * along, rtol=0, atol=tol * 100.0)


def test_a_truss_of_tied_halves_and_a_tied_apex_body_is_the_same_truss():
    """The toggle of :func:`truss` with its left bar as two beams tied at the middle and a
    rigid body ``apex`` tied to the left bar's end (one node each, the structure's
    numbering), hinged to the right bar: the same closed form (:func:`truss_load`), the
    load on the body; straight bars in uniform strain, so to round-off as there."""
    section = Section.diagonal(EA=100.0, GAy=100.0, GAz=100.0, GJ=100.0, EJy=100.0, EJz=100.0)
    ends = {"lower": ([-1, 0, 0], [-0.5, 0.5, 0]), "upper": ([-0.5, 0.5, 0], [0, 1, 0])}
    ends["right"] = ([1, 0, 0], [0, 1, 0])
    bars = [
        ExactBeam(Beam(straight(a, b, 1, 2, name=name), section, "fv2"))
        for name, (a, b) in ends.items()
    ]
    hinges = [
        Joint("revolute", "ground", "lower.start", frame=Z_AXIS),
        Joint("revolute", "ground", "right.start", frame=Z_AXIS),
        Joint("revolute", "apex", "right.end", frame=Z_AXIS),
    ]
    model = ExactModel(
        beams=bars,
        bodies=[RigidBody("apex", [0.0, 1.0, 0.0])],
        joints=hinges,
        name="tied truss",
        ties=[("lower.end", "upper.start"), ("upper.end", "apex")],
    )
    assert model.n_nodes == 5  # 6 beam nodes and a body, two ties
    apex = int(model.structure.node_dofs("apex")[0]) // 6
    assert apex == int(model.structure.node_dofs("upper.end")[0]) // 6
    load, force, length = truss_load(model, 0.6, "apex")
    result = solve(model, load)
    tol = FLOOR_FACTOR * EPS * 100.0 * 8  # as the untied truss
    np.testing.assert_allclose(result.state.nodes.x[apex], [0.0, 0.6, 0.0], rtol=0, atol=tol)
    pushed = -model.reactions(result.state)[0][1, :3]
    along = np.array([1.0, 0.6, 0.0]) / length
    np.testing.assert_allclose(pushed, -force * along, rtol=0, atol=tol * 100.0)


def chain(Q: np.ndarray | None = None) -> ExactModel:
    """Two bobs on a chain of two hinges (axis ``z``): the first at ``(0, -1)`` hung from the
    origin, the second at ``(0, -3)`` hung from the first at ``(0, -1.5)`` (an offset on
    both)."""
    bobs = [RigidBody("upper", [0.0, -1.0, 0.0]), RigidBody("lower", [0.0, -3.0, 0.0])]
    hinges = [
        Joint("revolute", "ground", "upper", position=[0.0, 0.0, 0.0], frame=Z_AXIS),
        Joint("revolute", "upper", "lower", position=[0.0, -1.5, 0.0], frame=Z_AXIS),
    ]
    return ExactModel(bodies=bobs, joints=hinges, name="chain")


def chain_state(first: float, second: float) -> ExactState:
    """The chain's bodies with the links turned by ``first`` and ``second`` from the
    vertical (an exact configuration of the mechanism)."""
    upper = rotations.exp_map([0.0, 0.0, first])
    lower = rotations.exp_map([0.0, 0.0, second])
    knee = upper @ [0.0, -1.5, 0.0]
    x = np.array([upper @ [0.0, -1.0, 0.0], knee + lower @ [0.0, -1.5, 0.0]])
    return ExactState(x, np.array([upper, lower]))


def test_the_truss_is_invariant_under_a_rigid_rotation():
    """The toggle built turned by a finite rotation ``Q`` (bars, section axes, hinges and
    load) reaches ``Q`` times the unturned equilibrium: positions ``Q x``, rotations
    ``Q R Q^T``, to the round-off of the truss test."""
    Q = rotations.exp_map([0.9, -1.7, 0.4])
    here, there = truss(), truss(Q=Q)
    load, _, _ = truss_load(here, 0.6)
    n = 6 * here.n_nodes
    turned = load.copy()
    turned[:n] = np.kron(np.eye(2 * here.n_nodes), Q) @ load[:n]  # forces and couples
    a, b = solve(here, load).state.nodes, solve(there, turned).state.nodes
    tol = FLOOR_FACTOR * EPS * 100.0 * 8
    np.testing.assert_allclose(b.x, a.x @ Q.T, rtol=0, atol=tol)
    np.testing.assert_allclose(b.R, Q @ a.R @ Q.T, rtol=0, atol=tol)


def test_a_hinged_chain_meets_its_closed_form_and_is_stationary():
    """Two bobs (weights 1 and 2) on a chain of hinges, the lower pulled sideways by 3: the
    lower link hangs at ``tan(theta_2) = P / W_2 = 3 / 2`` and the upper at
    ``tan(theta_1) = 1.5 P / (W_1 + 1.5 W_2) = 4.5 / 4`` (moments about each hinge: the
    upper bob 1 below the top hinge, the knee 1.5).  The equilibrium is a stationary point
    of the potential of the dead loads, ``-sum f . x``, along the mechanism's exact motions
    (the two hinge angles): its central differences vanish to their truncation, ``h^2``
    times the potential's third derivatives (of the size of the loads times the arms, 10),
    and rounding, while at a configuration off the equilibrium they are of the loads' size.
    """
    model = chain()
    load = np.zeros(model.n_dofs)
    load[1], load[7], load[6] = -1.0, -2.0, 3.0
    result = solve(model, load, model.balanced(model.reference(), load))
    first, second = np.arctan(4.5 / 4.0), np.arctan(1.5)
    expected = chain_state(first, second)
    assert (
        np.abs(model.residual(JointedState(expected, result.state.multipliers))[12:]).max()
        <= 16 * EPS * 4
    )
    tol = FLOOR_FACTOR * EPS * 10 / 2.0  # the floor over the chain's smallest stiffness
    np.testing.assert_allclose(result.state.nodes.x, expected.x, rtol=0, atol=tol)
    np.testing.assert_allclose(result.state.nodes.R, expected.R, rtol=0, atol=tol)

    def potential(angles: np.ndarray) -> float:
        x = chain_state(*angles).x
        return -float(load[0:3] @ x[0] + load[6:9] @ x[1])

    h = 1e-4
    for angles, stationary in (((first, second), True), ((first + 0.2, second), False)):
        slope = [
            (potential(np.add(angles, h * e)) - potential(np.subtract(angles, h * e))) / (2 * h)
            for e in np.eye(2)
        ]
        bound = 2 * (10.0 * h**2 + EPS * 10.0 / h)
        assert (np.abs(slope).max() <= bound) == stationary


def test_the_models_tangent_matches_finite_differences():
    """The bordered tangent of an exact beam (fv3, one element) hinged to a body by a
    universal joint, at a random state (nodes moved by 0.3, turned by up to about a radian)
    with random multipliers: the beam's material and geometric stiffness, the joint's
    geometric stiffness and its rows' borders, against central differences of the residual
    (tolerance as in the beam's own test)."""
    section = Section.diagonal(EA=100.0, GAy=50.0, GAz=40.0, GJ=3.0, EJy=2.0, EJz=1.5)
    beam = ExactBeam(Beam(straight([0, 0, 0], [2, 1, 0], 1, 3, name="arm"), section, "fv3"))
    frame = rotations.exp_map([0.4, -0.3, 1.0])
    model = ExactModel(
        beams=[beam],
        bodies=[RigidBody("hub", [2.5, 1.5, 0.5])],
        joints=[Joint("universal", "arm.end", "hub", position=[2.2, 1.2, 0.1], frame=frame)],
    )
    ref = model.reference()
    n = len(ref.nodes.x)
    nodes = ExactState(
        ref.nodes.x + 0.3 * RNG.standard_normal((n, 3)),
        rotations.exp_map(RNG.uniform(-1, 1, (n, 3))),
    )
    state = JointedState(nodes, 10 * RNG.standard_normal(len(ref.multipliers)))
    K = model.tangent(state).toarray()

    def differences(h):
        columns = []
        for dq in h * np.eye(model.n_dofs):
            columns.append(
                (model.residual(state.updated(dq)) - model.residual(state.updated(-dq))) / (2 * h)
            )
        return np.column_stack(columns)

    h = 1e-5
    D1, D2 = differences(h), differences(2 * h)
    truncation = np.abs(D2 - D1).max() / 3
    rounding = 2 * EPS * model.residual_floor(state).max() / h
    assert np.abs(K - D1).max() <= 2 * (truncation + rounding)
    # the joint's geometric stiffness is felt: without it the tangent is off
    joint = model.points(state).joints[0].stiffness
    assert np.abs(joint).max() > 1e3 * (truncation + rounding)


def test_a_prismatic_support_in_an_inclined_frame_carries_what_is_across_its_axis():
    """A body on a prismatic support whose axis ``e_1`` is inclined in space, held along it
    by a second support of the one row ``ux`` in the same frame: the load's part across the
    axis (with the couple) is the prismatic support's, its multipliers the components in the
    support's frame (position rows: ``e_2, e_3``; rotation rows ``rx, ry, rz``, to first
    order ``-theta_1, theta_2, -theta_3``: the couple's components with those signs), the
    part along the axis the other's; the body does not move."""
    frame = rotations.exp_map([0.5, -0.9, 0.7])
    model = ExactModel(
        bodies=[RigidBody("slider", [1.0, 2.0, 3.0])],
        joints=[
            Joint("prismatic", "ground", "slider", frame=frame),
            Joint("ux", "ground", "slider", frame=frame),
        ],
    )
    force = frame @ [1.5, 2.0, -0.5]
    couple = frame @ [0.3, -0.2, 0.7]
    load = np.concatenate([force, couple, np.zeros(6)])
    result = solve(model, load)
    tol = FLOOR_FACTOR * EPS * 8
    np.testing.assert_allclose(result.state.nodes.x[0], [1.0, 2.0, 3.0], rtol=0, atol=tol)
    np.testing.assert_allclose(result.state.nodes.R[0], np.eye(3), rtol=0, atol=tol)
    expected = [2.0, -0.5, -0.3, -0.2, -0.7, 1.5]
    np.testing.assert_allclose(result.state.multipliers, expected, rtol=0, atol=tol)
    prismatic, axial = model.reactions(result.state)
    np.testing.assert_allclose(
        prismatic[1], load[:6] - 1.5 * np.r_[frame[:, 0], 0, 0, 0], rtol=0, atol=tol
    )
    np.testing.assert_allclose(axial[1], 1.5 * np.r_[frame[:, 0], 0, 0, 0], rtol=0, atol=tol)


@pytest.mark.parametrize(
    "joint,message",
    [
        (Joint("hinge", "ground", "hub"), r"joints\[0\]: 'hinge' is neither a kind"),
        (Joint("ux+ux", "ground", "hub"), r"joints\[0\]: a row is named twice"),
        (Joint("fixed", "ground", "hbu"), r"joints\[0\]: b: .*'hbu'"),
        (Joint("fixed", "ground", "ground"), r"joints\[0\]: both ends are the ground"),
        (Joint("fixed", "hub", "arm.middle"), r"joints\[0\]: b: "),
        (Joint("fixed", "hub", "ground", frame=np.ones((3, 3))), r"joints\[0\]: frame must be"),
        (Joint("fixed", "hub", "ground", position=[0, np.nan, 0]), r"joints\[0\]: position"),
        (Joint("fixed", "hub", "ground", frame=np.eye(3), axis=[0, 0, 1]), r"not both"),
        (Joint("revolute", "hub", "ground", axis=[0, 0, 0]), r"joints\[0\]: axis must be"),
    ],
)
def test_bad_joints_are_refused_by_name(joint, message):
    """A wrong kind, row, node or frame: one ValueError naming the joint and the item."""
    with pytest.raises(ValueError, match=message):
        ExactModel(bodies=[RigidBody("hub", [0, 0, 0])], joints=[joint])


def test_an_axis_gives_a_straight_beams_section_frame():
    """``axis`` is ``e_1``; ``e_3`` is ``z`` made orthogonal to it (``y`` near ``z``)."""
    frame = Joint("revolute", "ground", "hub", axis=[2.0, 0.0, 0.0]).axes("joint")
    np.testing.assert_allclose(frame, np.eye(3), rtol=0, atol=EPS)
    frame = Joint("revolute", "ground", "hub", axis=[0.0, 0.0, 3.0]).axes("joint")
    np.testing.assert_allclose(frame, Z_AXIS, rtol=0, atol=EPS)


def test_other_beams_and_a_body_named_ground_are_refused():
    section = Section.diagonal(EA=1.0, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)
    linear = Beam(straight([0, 0, 0], [1, 0, 0], 2, 2, name="C"), section, "fv2")
    with pytest.raises(ValueError, match=r"beams\[0\] must be an ExactBeam"):
        ExactModel(beams=[linear])
    with pytest.raises(ValueError, match="may not be named 'ground'"):
        ExactModel(bodies=[RigidBody("ground", [0, 0, 0])])


def test_a_pendulum_hung_from_a_cantilevers_tip():
    """A bob hung 0.5 below the tip of an elastic cantilever (fv3, ``EJ = 1``, ``L = 1``) by
    a hinge about ``z``, under its weight 1 and a side pull 0.5: the bob swings to
    ``tan(theta) = 0.5`` about the tip, and the beam is the cantilever under the tip force
    ``(0.5, -1)`` (the hinge carries no couple about its axis), solved alone: the two
    agree to their round-off floors (``16 eps`` of terms of size ``EA = 1e4`` over the tip's
    stiffness ``3 EJ / L^3``, twice)."""
    section = Section.diagonal(EA=1e4, GAy=1e4, GAz=1e4, GJ=1.0, EJy=1.0, EJz=1.0)
    beam = ExactBeam(Beam(straight([0, 0, 0], [1, 0, 0], 4, 3, name="C"), section, "fv3"))
    model = ExactModel(
        beams=[beam],
        bodies=[RigidBody("bob", [1.0, -0.5, 0.0])],
        joints=[Joint("revolute", "C.end", "bob", position=[1, 0, 0], axis=[0, 0, 1])],
    )
    pull = np.array([0.5, -1.0, 0.0])
    load = np.zeros(model.n_dofs)
    bob = model.structure.node_dofs("bob")
    load[bob[:3]] = pull
    clamp = beam.beam.node_dofs("start")
    start = model.balanced(model.reference(), load, clamp)
    nodes = solve(model, load, start, clamp).state.nodes
    alone = solve_static(beam, beam.beam.nodal_load("end", force=pull), clamp).state
    tol = 2 * FLOOR_FACTOR * EPS * 1e4 / 3
    np.testing.assert_allclose(nodes.x[: len(alone.x)], alone.x, rtol=0, atol=tol)
    np.testing.assert_allclose(nodes.R[: len(alone.x)], alone.R, rtol=0, atol=tol)
    theta = np.arctan(0.5)
    tip = alone.x[beam.beam.node_index("end")]
    swing = 0.5 * np.array([np.sin(theta), -np.cos(theta), 0.0])
    np.testing.assert_allclose(nodes.x[bob[0] // 6], tip + swing, rtol=0, atol=tol)
    np.testing.assert_allclose(nodes.R[bob[0] // 6], rotations.exp_map([0, 0, theta]), atol=tol)


def test_the_linear_model_is_the_first_order_case():
    """The toggle's linear solution, the reference tangent (the beams' linear stiffness
    bordered by the joints' first-order rows) solved once, is the limit of the exact one:
    their difference (displacements, rotation vectors and multipliers) falls as the square
    of the load (measured slope; the next term is of third order, loads of 1e-3 of the
    toggle's)."""
    model = truss()
    reference = model.reference()
    K = model.tangent(reference).tocsc()
    differences = []
    loads = (1e-3, 2e-3, 4e-3)
    for s in loads:
        load, _, _ = truss_load(model, 0.6)
        load = s * load
        load[int(model.structure.node_dofs("left.end")[0])] = 0.3 * load.min()
        linear = scipy.sparse.linalg.spsolve(K, load)
        state = solve(model, load).state
        exact = np.concatenate(
            [
                np.hstack(
                    [state.nodes.x - reference.nodes.x, rotations.log_map(state.nodes.R)]
                ).ravel(),
                state.multipliers,
            ]
        )
        differences.append(np.abs(exact - linear).max())
    slopes = np.diff(np.log(differences)) / np.diff(np.log(loads))
    np.testing.assert_allclose(slopes, 2.0, atol=0.01)


def is_stationary(
    potential: Callable, projected: Callable, state: Any, directions: np.ndarray, size: float
) -> bool:
    """Whether the central slopes of ``potential`` at ``state`` along ``directions`` (each
    step projected back onto the constraints by ``projected(state, step)``) vanish to their
    truncation, estimated from a doubled step (Richardson, ``|D(2h) - D(h)| / 3``), and
    rounding, ``2 eps size / h`` (``size`` the potential's terms), with twice their sum
    allowed; ``h = 1e-4``."""
    h = 1e-4

    def slopes(step: float) -> np.ndarray:
        return np.array(
            [
                (potential(projected(state, step * v)) - potential(projected(state, -step * v)))
                / (2 * step)
                for v in directions
            ]
        )

    D1, D2 = slopes(h), slopes(2 * h)
    truncation = np.abs(D2 - D1).max() / 3
    return bool(np.abs(D1).max() <= 2 * (truncation + 2 * EPS * size / h))


def test_the_elastic_toggle_is_a_stationary_point_of_its_potential():
    """A conservative problem with elastic energy: the Galerkin toggle (``galerkin-p2``)
    under a dead apex load, its equilibrium a stationary point of the potential
    ``U - f . x`` (``U = sum_p w_p [nu; kappa]^T C [nu; kappa] / 2`` of the bars) on the
    joints' manifold.  Perturbations along random directions of the rows' null space,
    projected back onto ``c = 0`` (Gauss-Newton, to round-off): the central slope of the
    potential vanishes to its truncation (estimated from a doubled step) and rounding, and
    does not at the equilibrium of a load 10 % smaller (the same potential)."""
    model = truss("galerkin-p2")
    load, _, _ = truss_load(model, 0.6)
    n = 6 * model.n_nodes

    def potential(state: JointedState) -> float:
        energy = 0.0
        for i, beam in enumerate(model.exact.beams):
            strain = beam.points(model.exact.local(state.nodes, i)).strain
            energy += 0.5 * float(np.einsum("p,pi,pij,pj->", beam.weight, strain, beam.C, strain))
        return energy - float(load[:n].reshape(-1, 6)[:, :3].ravel() @ state.nodes.x.ravel())

    def projected(state: JointedState, dq: np.ndarray) -> JointedState:
        state = state.updated(np.concatenate([dq, np.zeros(model.n_dofs - n)]))
        for _ in range(20):
            rows = model.residual(state)[n:]
            if np.abs(rows).max() <= 16 * EPS:
                return state
            B = model.tangent(state)[n:, :n].toarray()
            step = -np.linalg.lstsq(B, rows, rcond=None)[0]
            state = state.updated(np.concatenate([step, np.zeros(model.n_dofs - n)]))
        raise AssertionError("the projection onto the joints' rows did not converge")

    for factor, stationary in ((1.0, True), (0.9, False)):
        state = solve(model, factor * load).state
        B = model.tangent(state)[n:, :n].toarray()
        free = scipy.linalg.null_space(B)
        directions = (free @ RNG.standard_normal((free.shape[1], 2))).T
        directions /= np.linalg.norm(directions, axis=1)[:, None]
        size = abs(potential(state)) + 100.0  # terms of size EA = 100
        assert is_stationary(potential, projected, state, directions, size) == stationary


#: A four-bar linkage: crank ``a``, coupler ``b``, rocker ``c``, ground pivots ``d`` apart.
FOUR_BAR = (1.0, 2.2, 1.5, 2.0)


def four_bar_geometry(crank: float) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The crank's tip ``A``, the rocker's tip ``B`` (the open branch: two circles'
    upper intersection) and the coupler's and rocker's angles at the crank angle ``crank``."""
    a, b, c, d = FOUR_BAR
    A, pivot = a * np.array([np.cos(crank), np.sin(crank), 0.0]), np.array([d, 0.0, 0.0])
    gap = np.linalg.norm(pivot - A)
    u = (pivot - A) / gap
    along = (b * b - c * c + gap * gap) / (2 * gap)
    B = A + along * u + np.sqrt(b * b - along * along) * np.array([-u[1], u[0], 0.0])
    return A, B, np.arctan2(*(B - A)[1::-1]), np.arctan2(*(B - pivot)[1::-1])


def four_bar_ratio(crank: float) -> float:
    """``d theta_4 / d theta_2``: the loop ``a e_2 + b e_3 - c e_4 = d e_1`` differentiated
    and dotted with ``e_3``, ``a sin(theta_3 - theta_2) / (c sin(theta_3 - theta_4))``."""
    a, _, c, _ = FOUR_BAR
    _, _, coupler, rocker = four_bar_geometry(crank)
    return a * np.sin(coupler - crank) / (c * np.sin(coupler - rocker))


def test_a_four_bar_linkage_balances_by_virtual_work():
    """A spatial four-bar of rigid bodies that moves in its plane: hinges (revolute, ``z``)
    to the ground at the crank and the rocker, a spherical joint from crank to coupler and a
    universal joint from coupler to rocker (its pins ``z`` and across the coupler; it stops
    the coupler's spin about its axis, so the 17 rows hold 18 dofs to one motion, without a
    redundant row).  Built at a crank angle of 80 degrees, under a dead couple ``T`` on the
    rocker and ``M = -T d theta_4 / d theta_2`` at 60 degrees on the crank (virtual work):
    the crank turns to 60 degrees and the rocker and coupler to the closed-form loop's
    angles, to the floor over the mechanism's stiffness ``T d^2 theta_4 / d theta_2^2``."""
    a, b, c, d = FOUR_BAR
    start, target = np.radians(80.0), np.radians(60.0)
    A, B, _, _ = four_bar_geometry(start)
    pivot, z = np.array([d, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    u = (B - A) / b
    model = ExactModel(
        bodies=[
            RigidBody("crank", A / 2),
            RigidBody("coupler", (A + B) / 2),
            RigidBody("rocker", (pivot + B) / 2),
        ],
        joints=[
            Joint("revolute", "ground", "crank", position=[0.0, 0.0, 0.0], axis=z),
            Joint("spherical", "crank", "coupler", position=A),
            Joint(
                "universal",
                "coupler",
                "rocker",
                position=B,
                frame=np.column_stack([u, z, np.cross(u, z)]),
            ),
            Joint("revolute", "ground", "rocker", position=pivot, axis=z),
        ],
        name="four-bar",
    )
    T = 1.0
    load = np.zeros(model.n_dofs)
    load[5], load[17] = -T * four_bar_ratio(target), T
    result = solve(model, load, model.balanced(model.reference(), load))
    step = 1e-4  # the stiffness needs only its size: its central difference
    stiffness = T * abs(four_bar_ratio(target + step) - four_bar_ratio(target - step)) / (2 * step)
    tol = FLOOR_FACTOR * EPS * 4 * (a + b + c) / stiffness
    A_t, B_t, coupler, rocker = four_bar_geometry(target)
    _, _, coupler_0, rocker_0 = four_bar_geometry(start)
    nodes = result.state.nodes
    for R, turn in zip(
        nodes.R, (target - start, coupler - coupler_0, rocker - rocker_0), strict=True
    ):
        np.testing.assert_allclose(R, rotations.exp_map(turn * z), rtol=0, atol=tol)
    expected = np.array([A_t / 2, (A_t + B_t) / 2, (pivot + B_t) / 2])
    np.testing.assert_allclose(nodes.x, expected, rtol=0, atol=tol * (a + b + c))
