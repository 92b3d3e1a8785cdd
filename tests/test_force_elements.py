"""Force elements (:mod:`sliders.forces.elements`, compiled in :mod:`sliders.forces.kernel`):
the kernel against its numpy reference, the Jacobian against central differences, and the
elements in statics and dynamics against closed forms.

Tolerances: kernel and reference evaluate the same expressions (the laws' twins agree to a
few ulp, ``tests/test_laws_kernel.py``), so they agree within ``64 eps`` of the largest entry.
The central difference of step ``h`` errs by ``h^2 f''' / 6`` plus ``eps |f| / h``; at
``h = 1e-6`` of the states' scale, the laws' third derivatives give at most ``1e-6`` of the
largest entry.
"""

from __future__ import annotations

import numpy as np
import pytest

from fvbeam import RigidBody, Structure, Support
from sliders.forces.elements import AxialForce, Tyre
from sliders.forces.kernel import evaluate_element, reference
from sliders.gear.parameters import ISSUE_14
from sliders.solve.dynamics import Dynamics
from sliders.solve.statics import SliderStatics

EPS = np.finfo(float).eps
STRUT = ISSUE_14.strut
TYRE = dict(radius=0.22, stiffness=2.5e5, damping=250.0, B=10.0, C=1.65, D=0.8)


def gear(mass: float = 12.0) -> tuple[Structure, AxialForce, Tyre]:
    """A strut from a held top node down to an axle body, and a wheel body beside it."""
    top = RigidBody("top", (0.0, 0.0, 1.0))
    axle = RigidBody("axle", (0.0, 0.0, 0.2), mass=mass, inertia=np.eye(3))
    wheel = RigidBody("wheel", (0.0, 0.0, 0.2), mass=0.0, inertia=0.15 * np.eye(3))
    structure = Structure([], bodies=[top, axle, wheel])
    strut = AxialForce("top", "axle", STRUT, extended=0.8, name="strut")
    tyre = Tyre("axle", "wheel", **TYRE, name="tyre")
    return structure, strut, tyre


def states(rng: np.random.Generator) -> list[tuple[np.ndarray, np.ndarray]]:
    """Displacements and velocities of the six slots: strokes inside the free range and on
    both stops, tyre in and out of contact, spin around rolling speed."""
    out = []
    for _ in range(6):
        q = rng.normal(0.0, 0.02, 6)
        v = np.concatenate([rng.normal(0, 2.0, 3), rng.normal(0, 2.0, 3)])
        v[0] += 40.0
        v[4] += rng.uniform(0, 200)
        out.append((q, v))
    return out


@pytest.mark.parametrize("which", ["strut", "tyre"])
def test_kernel_equals_reference_and_jacobian_is_the_derivative(which) -> None:
    structure, strut, tyre = gear()
    element = strut if which == "strut" else tyre
    p = element.packed(structure)
    r, J = np.zeros(6), np.zeros((6, 6))
    for q, v in states(np.random.default_rng(1)):
        if which == "tyre":
            q[2] = -abs(q[2]) - 0.01  # in contact
        r_ref, dq, dv = reference(element.kind, p, q, v)
        for c_v, scale in ((0.0, 1.0), (37.0, 0.01)):
            evaluate_element(element.kind, p, q, v, c_v, scale, r, J)
            big = max(np.abs(r_ref).max(), np.abs(dq).max(), np.abs(dv).max(), 1.0)
            assert np.abs(r - scale * r_ref).max() <= 64 * EPS * scale * big
            assert np.abs(J - scale * (dq + c_v * dv)).max() <= 64 * EPS * scale * big * (1 + c_v)
        h = 1e-6
        for which_state, derivative in ((0, dq), (1, dv)):
            for j in range(6):
                step = np.zeros(6)
                step[j] = h
                args = [q, v]
                plus, minus = list(args), list(args)
                plus[which_state] = args[which_state] + step
                minus[which_state] = args[which_state] - step
                fd = reference(element.kind, p, *plus)[0] - reference(element.kind, p, *minus)[0]
                fd /= 2 * h
                assert np.abs(fd - derivative[:, j]).max() <= 1e-6 * max(
                    np.abs(derivative).max(), 1.0
                )


def test_a_mass_on_the_strut_rests_where_the_gas_carries_its_weight() -> None:
    """Statics: a mass standing on the strut compresses it to the stroke where the gas spring
    carries its weight ``m g`` (the gas law inverted in closed form); in load steps, as the
    gas spring stiffens twentyfold on the way (a first Newton step on its initial slope
    would overshoot the gas column)."""
    base, top = RigidBody("base", (0.0, 0.0, 0.0)), RigidBody("top", (0.0, 0.0, 0.8))
    structure = Structure([], bodies=[base, top])
    strut = AxialForce("base", "top", STRUT, extended=0.8, name="strut")
    supports = [Support("base"), Support("top", kind="ux+uy+rx+ry+rz")]
    statics = SliderStatics(structure, supports, [], forces=[strut])
    weight = 300.0 * 9.81
    q = statics.solve(structure.nodal_load("top", (0.0, 0.0, -weight)), load_steps=10).q
    A, p0, V0, n = 1.6e-3, 4.1e5, 2.8e-4, 1.3
    stroke = V0 / A * (1 - (p0 / (weight / A + 101_325.0)) ** (1 / n))
    assert q[structure.node_dofs("top")[2]] == pytest.approx(-stroke, rel=1e-8)


def test_a_spinning_wheel_dropped_at_speed_spins_up_to_rolling() -> None:
    """Dynamics: an axle moving forward at 40 m/s resting on its tyre, its wheel still: the
    longitudinal force spins the wheel up until it rolls (``omega R0 = u`` to the slip the
    friction needs to move the axle's inertia), and the angular momentum the ground gives
    the wheel equals the moment of the forward impulse it takes from the axle."""
    structure, _, tyre = gear(mass=12.0)
    supports = [
        Support("top"),
        Support("axle", kind="uy+rx+ry+rz"),
        Support("wheel", kind="ux+uy+uz+rx+rz"),
    ]
    d = Dynamics(
        structure, supports, [], structure.nodal_load("axle", (0, 0, -2.5e3)), forces=[tyre]
    )
    n = structure.n_dofs
    q, v = np.zeros(n), np.zeros(n)
    axle, wheel = structure.node_dofs("axle"), structure.node_dofs("wheel")
    q[axle[2]] = -0.01  # in contact, the static deflection of 2.5 kN
    v[axle[0]] = 40.0
    end = d.run(d.state(q, v), 0.3, 1e-4, progress=False)
    u, omega = end.v[axle[0]], end.v[wheel[4]]
    assert abs(omega * 0.22 - u) <= 1e-3 * u
    # the horizontal impulse on the axle, -12 (u - 40), turned the wheel by R0 times it
    assert 0.15 * omega == pytest.approx(0.22 * 12.0 * (40.0 - u), rel=1e-6)


@pytest.mark.parametrize("which", ["strut", "tyre"])
def test_outputs_are_the_forces_the_kernel_applies(which) -> None:
    """``outputs`` (numpy, many states at once) against the reference residual: the strut
    pushes ``b`` by ``F n``, the tyre pulls the axle by ``-(F_z N + F_x e)``; ``stroke``,
    ``deflection`` and the speeds are the module docstring's."""
    structure, strut, tyre = gear()
    element = strut if which == "strut" else tyre
    p = element.packed(structure)
    slots = element.slots(structure)
    pairs = states(np.random.default_rng(2))
    q, v = np.zeros((len(pairs), structure.n_dofs)), np.zeros((len(pairs), structure.n_dofs))
    for k, (qs, vs) in enumerate(pairs):
        if which == "tyre":
            qs[2] = -abs(qs[2]) - 0.01
        q[k, slots], v[k, slots] = qs, vs
    out = element.outputs(structure, q, v)
    for k, (qs, vs) in enumerate(pairs):
        r = reference(element.kind, p, qs, vs)[0]
        if which == "strut":
            d = p[3:6] + qs[3:6] - p[0:3] - qs[0:3]
            n = d / np.linalg.norm(d)
            assert out["force"][k] == pytest.approx(r[3:6] @ -n, rel=1e-12)
            assert out["stroke"][k] == pytest.approx(0.8 - np.linalg.norm(d), rel=1e-12)
        else:
            assert out["Fz"][k] == pytest.approx(-r[2], rel=1e-12, abs=1e-9)
            assert out["Fx"][k] == pytest.approx(-r[0], rel=1e-12, abs=1e-9)
            assert out["deflection"][k] == pytest.approx(0.22 - (0.2 + qs[2]), rel=1e-12)
            assert (out["forward_speed"][k], out["spin"][k]) == (vs[0], vs[4])
