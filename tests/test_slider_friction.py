"""Bearing friction on a slider (:class:`sliders.joints.friction.Friction`) in the packed
joint and in the dynamics.

* **Jacobian**: the ``xi`` row of a joint with friction against central differences in the
  dofs (the velocities tied to them by ``v = v_hat + c_v (q - q_hat)``, as in a step) and in
  the unknowns; the other rows are the frictionless joint's, bit for bit.  Tolerance: a
  central difference of step ``h`` errs by ``h^2 |f'''| / 6 + eps |f| / h``; with ``h = 1e-6``
  of the inputs' unit scale, ``v_eps = 0.5`` and ``c_v = 2`` (the tanh's third derivative
  ``(c_v / v_eps)^3 ~ 64``, the residual's entries ~10), both parts are below ``1e-8``: ``1e-7``
  of the largest entry of the row, a wrong term being of order one.
* **Kinematics**: the sliding velocity is the body point's relative to the line's material
  point: a body and line moving together rub nothing; a point turned about its node by an
  offset slides at ``theta' x f``.
* **Closed form**: a bead pressed on a straight rigid line by a constant force ``P`` and
  launched along it at ``v0`` decelerates at ``mu P / m`` (``tanh(v / v_eps) = 1`` to
  roundoff for ``v >= 500 v_eps``): ``x = v0 t - mu P t^2 / (2 m)``.  The generalized-alpha
  scheme integrates a constant acceleration exactly from a consistent start, so what is left
  is Newton's stopping error, below its increment rule ``tol = 1e-8`` of the state's reach
  per step (quadratic convergence), summed over the steps: ``steps x 1e-8`` of the reach.
  The joint's work on the bead (the history's ``constraint_work``) is the friction's,
  ``-mu P x``, and the energy balance closes to the same bound.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_joint_reference import OFFSETS, batch_of
from test_packed_joints import merged

from fvbeam import RigidBody, Structure, Support
from sliders.app.history import Recorder
from sliders.joints.friction import Friction, friction_term
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.lines.rigid import StraightLine
from sliders.solve.dynamics import Dynamics, DynamicsError
from sliders.solve.integrator import State

EPS = np.finfo(float).eps
FRICTION = Friction(0.3, 0.5)
C_V = 2.0


def rubbing(
    kind: str, orientation: str, line: str, offset: str
) -> tuple[JointPack, JointPack, Structure]:
    """Slider A of the sliding beams (or a tip on a rigid line) with friction and without,
    packed, and its structure."""
    batch = batch_of(kind, orientation, line, OFFSETS[offset])
    slider, structure = batch.sliders[0], batch.structures[0]
    with_friction = dataclasses.replace(slider, friction=FRICTION)
    return JointPack([with_friction], structure), JointPack([slider], structure), structure


def evaluate(pack: JointPack, q, y, velocity) -> tuple[np.ndarray, ...]:
    """The joint's merged dofs, residual and Jacobian at ``q, y`` moving at ``velocity``."""
    dofs, r, values = pack.evaluate(0, q, y, velocity=velocity)
    _, jacobian = pack.layouts[0]
    jacobian._views(values[None])
    return merged(dofs, r, jacobian.dense()[0])


def random_state(pack: JointPack, n: int, seed: int) -> tuple[np.ndarray, ...]:
    """Displacements ~1e-3, ``xi`` inside the line, multipliers and velocities ~1."""
    rng = np.random.default_rng(seed)
    q, q_hat, v_hat = rng.standard_normal((3, n)) * np.array([[1e-3], [1e-3], [1.0]])
    y = rng.standard_normal(pack.unknowns[0])
    y[0] = rng.uniform(0.1, 0.9) * pack.values[0, 1]
    return q, y, q_hat, v_hat


CASES = [("spherical", "section"), ("classical", "section"), ("spline", "section")]


@pytest.mark.parametrize("offset", list(OFFSETS))
@pytest.mark.parametrize("line", ["fv3", "cubic", "galerkin-p2", "arc"])
@pytest.mark.parametrize("kind,orientation", CASES)
def test_the_friction_row_is_differentiated_consistently(kind, orientation, line, offset) -> None:
    pack, plain, structure = rubbing(kind, orientation, line, offset)
    q, y, q_hat, v_hat = random_state(pack, structure.n_dofs, 5)
    velocity = (v_hat, q_hat, C_V)
    dofs, r, J = evaluate(pack, q, y, velocity)
    p_dofs, p_r, p_J = evaluate(plain, q, y, velocity)
    t = len(dofs)
    rows = np.arange(len(r)) != t
    assert np.array_equal(dofs, p_dofs) and abs(r[t] - p_r[t]) > 0
    assert np.array_equal(r[rows], p_r[rows]) and np.array_equal(J[rows], p_J[rows])

    def xi_row(q_, y_):
        return evaluate(pack, q_, y_, velocity)[1][t]

    h, fd = 1e-6, np.zeros(len(r))
    for i, dof in enumerate(dofs):
        e = np.zeros_like(q)
        e[dof] = h
        fd[i] = (xi_row(q + e, y) - xi_row(q - e, y)) / (2 * h)
    for k in range(len(y)):
        e = np.zeros_like(y)
        e[k] = h
        fd[t + k] = (xi_row(q, y + e) - xi_row(q, y - e)) / (2 * h)
    assert np.abs(fd - J[t]).max() <= 1e-7 * max(np.abs(J[t]).max(), 1.0)


@pytest.mark.parametrize("line", ["fv3", "cubic", "arc"])
def test_the_sliding_velocity_is_relative_to_the_line(line) -> None:
    """Every node moving at one velocity ``U`` (a rigid translation: the line's
    interpolation is a partition of unity on translations): nothing rubs.  The body still
    and its point turned about the node at ``theta'`` with the offset ``f``: the friction
    is :func:`friction_term` of the sliding velocity ``theta' x f`` (the line still)."""
    pack, plain, structure = rubbing("spherical", "section", line, "off the node")
    q, y, _, _ = random_state(pack, structure.n_dofs, 7)
    n = structure.n_dofs
    still = (np.zeros(n), q, 0.0)
    frictionless = evaluate(plain, q, y, still)[1]
    t = len(evaluate(pack, q, y, still)[0])
    if line != "arc":  # a rigid line does not move
        U = np.tile(np.concatenate([[0.4, -1.1, 0.7], np.zeros(3)]), n // 6)
        together = evaluate(pack, q, y, (U, q, 0.0))[1]
        assert abs(together[t] - frictionless[t]) <= 16 * EPS * np.abs(y).max()
    slider = pack.sliders[0]
    spin, theta_rate = np.zeros(n), np.array([0.3, -0.8, 0.5])
    spin[slider.body_dofs(structure)[3:]] = theta_rate
    got = evaluate(pack, q, y, (spin, q, 0.0))[1][t] - frictionless[t]
    tangent = slider.batch(structure).joint_inputs(q[None], y[None])[1].tangent[0]
    w = np.cross(theta_rate, slider.offset)
    expected = friction_term(tangent, w, y[1:4], FRICTION.mu, FRICTION.v_eps)[0]
    assert abs(got - expected) <= 64 * EPS * max(abs(expected), np.abs(y).max())


def bead(m: float, P: float, mu: float, v0: float) -> tuple[Dynamics, State]:
    """A bead of mass ``m`` on a straight rigid rail along x, pressed on it by ``P`` (along
    -y), friction ``mu`` (``v_eps = 1e-3``), launched at ``v0`` along the rail with the
    consistent deceleration ``mu P / m``; its dynamics and start."""
    line = StraightLine((-1.0, 0.0, 0.0), (5.0, 0.0, 0.0), name="rail")
    structure = Structure([], bodies=[RigidBody("bead", np.zeros(3), mass=m)])
    slider = Slider("spherical", line, "bead", friction=Friction(mu, 1e-3), name="bead")
    f = np.zeros(structure.n_dofs)
    f[1] = -P
    dynamics = Dynamics(structure, [Support("bead", kind="rx+ry+rz")], [slider], f)
    v, qdd = np.zeros(structure.n_dofs), np.zeros(structure.n_dofs)
    v[0], qdd[0] = v0, -mu * P / m
    return dynamics, dynamics.state(np.zeros(structure.n_dofs), v, qdd=qdd)


def test_a_bead_stops_and_sticks_in_split_steps() -> None:
    """The bead decelerates at 1 m/s^2 from 1 m/s and stops at 0.5 m after 1 s.  Steps of
    0.01 s cross the friction's band (the speed changes by 10 v_eps in a step): the step
    across the stop fails Newton (it cycles between the two signs of the speed) and is
    taken in halves (:meth:`Dynamics.split_step`).  The bead then rests: only the viscous
    part of the friction acts, decaying the speed with ``tau = m v_eps / (mu P) = 1 ms``, so
    speed and reaction along the rail vanish to Newton's tolerance.  The stop: the
    acceleration jumps inside one step, where the scheme errs by at most ``decel h^2``."""
    m, P, mu, v0, h = 2.0, 10.0, 0.2, 1.0, 0.01
    dynamics, start = bead(m, P, mu, v0)
    before = dynamics.run(start, 0.995, h, progress=False)
    with pytest.raises(DynamicsError):
        dynamics.step(before, h)
    end = dynamics.run(before, 1.5, h, progress=False)
    decel = mu * P / m
    assert abs(end.q[0] - v0**2 / (2 * decel)) <= decel * h**2
    assert abs(end.v[0]) <= 1e-8 * v0 and abs(end.unknowns[0][1]) <= 1e-8 * P


def test_a_bead_pressed_on_a_line_decelerates_at_mu_p_over_m() -> None:
    """The closed form of the module docstring."""
    m, P, mu, v0, steps = 2.0, 10.0, 0.2, 1.0, 50
    decel = mu * P / m  # 1 m/s^2: v falls from 1 to 0.5 in 0.5 s
    dynamics, start = bead(m, P, mu, v0)
    T = 0.5
    recorder = Recorder()
    end = dynamics.run(start, T, T / steps, recorder=recorder, progress=False)
    x, speed = end.q[0], end.v[0]
    reach = v0 * T
    assert abs(x - (v0 * T - decel * T**2 / 2)) <= steps * 1e-8 * reach
    assert abs(speed - (v0 - decel * T)) <= steps * 1e-8 * v0
    xi, lam = end.unknowns[0][0], end.unknowns[0][1:4]
    assert abs(xi - (1.0 + x)) <= steps * 1e-8 * reach
    assert np.abs(lam - np.array([mu * P, -P, 0.0])).max() <= steps * 1e-8 * P
    # the joint's work on the bead is the friction's, -mu P x; the balance closes
    table = recorder.table()
    energy = m * v0**2 / 2
    assert abs(table["constraint_work"][-1] + mu * P * x) <= steps * 1e-8 * energy
    assert np.abs(table["energy_error"]).max() <= steps * 1e-8 * energy
