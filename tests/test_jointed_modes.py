"""Modes about exact states with rigid bodies and joints (sliders.solve.modes.Preload.of_model,
fvbeam.exact_bodies.ExactBodies.mass, the modes study of a scene with joints).

Tolerance sources:

* The body's mass is its kinetic energy at rest (``ExactBodies.mass`` docstring): the
  quadratic form against ``m |du + dphi x (R c)|^2 + dphi . R J R^T dphi`` summed directly,
  to round-off (1e-13 of the energy: a few dozen products of unit-sized terms).
* Pendulums: one rigid body (or two) on hinges have closed-form frequencies about their
  equilibrium, and the model is exact (no discretisation): the state is solved to its
  rounding floor, the reduction and the dense eigen solve are backward stable, so they agree
  to the eigen solvers' backward error times small condition numbers (``EIGEN``, 1e-9, as
  ``tests/test_preloaded_modes.py``).
* The cantilever with a tip body: mesh convergence against the exact frequency equation
  (:func:`fvbeam.closed_forms.timoshenko_cantilever_determinant` with a tip mass and its
  rotary inertia, unloaded and under a dead axial tip force): observed order within 0.5 of
  2 on 8, 16, 32 fv2 elements and the finest error below ``e_16 / 2^1.5``, the unloaded
  beams' order (``tests/test_preloaded_modes.py``).
* The unloaded limit: a fixed joint at zero load is the linear tie; the two reductions
  differ in which dofs they eliminate, not in the problem, so they agree to ``EIGEN``.
"""

import tomllib

import numpy as np
import pytest

from fvbeam import Beam, RigidBody, Structure, Support, closed_forms, straight
from fvbeam.closed_forms import AxialForce
from fvbeam.exact_beam import ExactState
from fvbeam.exact_bodies import ExactBodies
from fvbeam.geometry import skew_matrices
from fvbeam.rotations import exp_map
from sliders.app.kinematics import ExactPath
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import parse_scene
from sliders.joints.exact_model import Joint
from sliders.solve.modes import Preload, StateModes, modes_about
from sliders.solve.statics import SliderStatics
from tests.test_preloaded_modes import EA, EJ, GA, RHO_J, M, section
from tests.test_scene_joints import pendulum

EIGEN = 1e-9


def test_a_bodys_mass_is_its_kinetic_energy_off_its_centre():
    rng = np.random.default_rng(1)
    A = rng.standard_normal((3, 3))
    J = A @ A.T + np.eye(3)
    body = RigidBody("b", [0.3, -0.2, 0.5], mass=2.5, inertia=J, centre=[0.4, -0.7, 0.2])
    R = exp_map(np.array([0.7, -1.1, 0.4]))
    M = ExactBodies([body]).mass(ExactState(np.zeros((1, 3)), R[None]))[0]
    c = R @ body.centre
    for _ in range(5):
        du, dphi = rng.standard_normal(3), rng.standard_normal(3)
        v = du + np.cross(dphi, c)
        energy = body.mass * v @ v + dphi @ R @ J @ R.T @ dphi
        increment = np.concatenate([du, dphi])
        assert abs(increment @ M @ increment - energy) < 1e-13 * energy
    # not the rotation block alone turned: the coupling turns with the centre
    S = skew_matrices(body.centre)
    assert not np.allclose(M[:3, 3:], -body.mass * S)


def modes(data: dict, tmp_path):
    results = run(Model(parse_scene(data, tmp_path, "scene.toml")), progress=False)
    assert results.kinematics.startswith("kinematics: exact")
    assert results.modes is not None and results.modes[0].modes is not None
    return results.modes[0].modes


def pendulum_modes(length: float, weight: float, tilt: float, count: int = 1) -> dict:
    """The pendulum scene of ``tests/test_scene_joints.py`` as a modes study."""
    data = tomllib.loads(pendulum(length, weight, tilt))
    data["study"] = {"kind": "modes", "count": count}
    return data


@pytest.mark.parametrize("tilt", [0.0, np.pi / 5])
def test_a_pendulum_swings_at_its_closed_form_about_a_tilted_state(tmp_path, tilt):
    """A dead weight ``W`` at the body's node, ``l_P`` below the hinge, the centre of mass
    ``l_c`` below it: tilted by a dead couple ``W l_P sin(tilt)``, the swing's stiffness is
    ``W l_P cos(tilt)`` and its inertia about the hinge ``J_z + m l_c^2``, with the centre
    turned with the body (unturned, it would be ``m |P + c|^2``, wrong off the vertical)."""
    W, l_P, l_c, m, J = 3.0, 1.5, 2.0, 0.4, 0.05
    data = pendulum_modes(l_P, W, tilt)
    data["body"][0].update(centre=[0.0, -(l_c - l_P), 0.0], mass=m, inertia=[0.3, 0.2, J])
    found = modes(data, tmp_path)
    omega2 = W * l_P * np.cos(tilt) / (J + m * l_c**2)
    assert found.omega.shape == (1,)
    assert abs(found.omega[0] ** 2 / omega2 - 1) < EIGEN


def test_a_double_pendulum_held_by_its_weights_has_both_closed_form_modes(tmp_path):
    """Point masses ``m`` on massless links ``l`` under dead weights ``m g``: ``omega^2 = (g /
    l) (2 -+ sqrt 2)`` (e.g. Goldstein, Classical Mechanics, Sec. 6.4), the joints'
    geometric stiffness alone holding them (the bodies' own stiffness is zero)."""
    data = pendulum_modes(1.0, 9.81, 0.0, count=2)
    data["body"].append({"name": "lower", "position": [0.0, -2.0, 0.0], "mass": 1.0})
    hinge = dict(data["joint"][0], a="upper", b="lower", position=[0.0, -1.0, 0.0])
    data["joint"].append(hinge)
    data["load"].append(dict(data["load"][0], node="lower", moment=[0.0, 0.0, 0.0]))
    data["body"][0]["name"] = data["joint"][0]["b"] = data["load"][0]["node"] = "upper"
    found = modes(data, tmp_path)
    expected = 9.81 * (2 + np.array([-1.0, 1.0]) * np.sqrt(2))
    np.testing.assert_allclose(found.omega**2, expected, rtol=EIGEN)
    # the lower mode: the links turn the same way, the lower sqrt 2 times as far, so the
    # lower mass moves 1 + sqrt 2 times as far as the upper one
    shape = found.shapes[:, 0].reshape(-1, 6)
    assert abs(shape[1, 0] / shape[0, 0] - (1 + np.sqrt(2))) < EIGEN


TIP_MASS, TIP_J = 0.5, 0.02


def tip_body() -> RigidBody:
    return RigidBody("tip", [1.0, 0.0, 0.0], TIP_MASS, np.diag([0.03, 0.025, TIP_J]))


def tip_modes(n: int, force: tuple, count: int = 1, tied: bool = False) -> StateModes:
    """The modes of the clamped beam of ``n`` fv2 elements with the tip body on a fixed
    joint at its end (or ``tied`` to it), under a dead ``force`` on the body, about its
    exact state."""
    ties = [("beam.end", "tip")] if tied else []
    structure = Structure(
        [Beam(straight((0, 0, 0), (1, 0, 0), n, 2), section(), "fv2")], ties, [tip_body()]
    )
    supports = [Support(0, "start")]
    joints = [] if tied else [Joint("fixed", "beam.end", "tip")]
    path = ExactPath(structure, structure.support_dofs(supports), joints=joints, load_steps=4)
    solution = path.solve(structure.nodal_load("tip", force))
    assert path.model is not None
    preload = Preload.of_model(path.model, solution.state)  # type: ignore[arg-type]
    return modes_about(SliderStatics(structure, supports, []), solution, count, preload=preload)


@pytest.mark.parametrize("P", [0.0, 1.0])
def test_a_tip_body_on_a_fixed_joint_meets_the_tip_mass_frequency_equation(P):
    """Under a dead axial force ``P`` (compressive) on the body."""
    args = (1.0, EJ, GA, M, RHO_J, AxialForce(P, EA), TIP_MASS, TIP_J)
    exact = closed_forms.frequency_roots(
        closed_forms.timoshenko_cantilever_determinant, 1, 0.01, args
    )[0]
    errors = [abs(tip_modes(n, (-P, 0.0, 0.0)).omega[0] / exact - 1) for n in (8, 16, 32)]
    for coarse, fine in zip(errors, errors[1:], strict=False):
        assert abs(np.log2(coarse / fine) - 2) < 0.5, np.log2(coarse / fine)
    assert errors[2] < errors[1] / 2**1.5


def test_unloaded_a_fixed_joint_has_the_linear_tied_modes():
    structure = Structure(
        [Beam(straight((0, 0, 0), (1, 0, 0), 8, 2), section(), "fv2")],
        [("beam.end", "tip")],
        [tip_body()],
    )
    statics = SliderStatics(structure, [Support(0, "start")], [])
    linear = modes_about(statics, statics.solve(np.zeros(structure.n_dofs)), 6)
    exact = tip_modes(8, (0.0, 0.0, 0.0), 6)
    np.testing.assert_allclose(exact.omega, linear.omega, rtol=EIGEN)


def test_under_a_bending_load_a_fixed_joint_is_the_tie():
    """The tip bent by a dead transverse force ``P L^2 / EJ = 1`` (about half a radian): the
    body on a fixed joint (its rows and geometric stiffness, its own rotation) and the body
    tied to the beam's end node (one node) are one problem, so their modes agree to
    ``EIGEN`` (measured 6e-12); and the load moves them (measured 8 % for the first: the
    agreement is the preload's)."""
    loaded = tip_modes(8, (0.0, 1.0, 0.0), 4)
    np.testing.assert_allclose(
        loaded.omega, tip_modes(8, (0.0, 1.0, 0.0), 4, tied=True).omega, rtol=EIGEN
    )
    unloaded = tip_modes(8, (0.0, 0.0, 0.0), 4)
    assert np.abs(loaded.omega / unloaded.omega - 1).max() > 1e-3
