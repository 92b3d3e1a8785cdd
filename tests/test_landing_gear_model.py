"""The landing gear built from the library (sliders/gear), docs/landing_gear.md.

Sources of truth:
* the independent rigid reference, studies/landing_gear_ode.py (solve_ivp at rtol 1e-8, its
  peaks converged to ~1e-9): issue 14 asks the rigid model to agree with it to 1e-3 in peak
  loads and their times.  The error budget: generalized-alpha's O(h^2) at h = 1e-4 (measured
  below 1e-4 for the loads, docs/landing_gear.md) plus the rigid factor's O(1 / factor)
  (3e-4 at 1e5);
* the touchdown state: the strut's static balance F_s(S0, 0) = -m_u g, solved by the ODE
  study's Newton on the strut law alone;
* the two-beam closed form of the sliding-beams setup (sliders.sliding_beams.exact) for the
  leg's fore-aft stiffness at full extension, within the paper's Figure 5 error bounds;
* a linear invariant: the ground's fore-aft force alone changes the gear's fore-aft momentum
  P and the wheel's spin, so I_w omega + R0 (P - P0) = 0 along the discrete solution (the
  scheme is linear in the accelerations, the joints' and beams' forces are internal);
* the paper: a rigid leg has no spring-back, a flexible one has.
"""

from __future__ import annotations

import numpy as np
import pytest

from sliders.gear.model import MODELS, GearModel, elements
from sliders.sliding_beams.exact import sliding_beams
from studies import landing_gear_ode as ode

#: Issue 14's agreement of the rigid model with its ODEs, relative.
AGREEMENT = 1e-3
STEP = 1e-4


@pytest.fixture(scope="module")
def reference():
    return ode.summary(ode.simulate(rtol=1e-8))


@pytest.fixture(scope="module")
def rigid():
    return {
        kind: GearModel("rigid", slider=kind).simulate(step=STEP)
        for kind in ("spherical", "classical")
    }


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_the_rigid_leg_agrees_with_its_odes(rigid, reference, kind):
    """Peaks and their times, spin-up and lift-off.  The slider reactions are the ODE's rigid
    piston on two point bearings (R_top = P s / (L - s), R_bot = -P L / (L - s)) only for
    spherical sliders: classical ones also carry couples, which share the piston's moment
    (the closed form below)."""
    ours = rigid[kind].summary()
    names = ["ground_vertical", "ground_longitudinal", "attachment_longitudinal", "stroke"]
    if kind == "spherical":
        names += ["top_slider", "bottom_slider", "friction_post"]
    for name in names:
        assert abs(ours[name]) == pytest.approx(abs(reference[name]), rel=AGREEMENT), name
        time = f"{name}_time"
        assert ours[time] == pytest.approx(reference[time], rel=AGREEMENT), time
    for name in ("spin_up_time", "lift_off_time"):
        assert ours[name] == pytest.approx(reference[name], rel=AGREEMENT), name


def test_the_rigid_leg_with_bearing_friction_agrees_with_its_odes():
    """Bearing friction in the dynamics (mu_b = 0.02 on both sliders, issue 14): the rigid
    leg with spherical sliders (the ODE's two point bearings) against the ODEs with the
    friction F_f = -mu_b N tanh(S' / v_eps) on the piston, to issue 14's 1e-3 in the peaks
    (the friction's with the others) and their times; the friction's work shows in both as a
    change of the peaks beyond that agreement (docs/landing_gear.md: +1 % vertical)."""
    reference = ode.summary(ode.simulate(rtol=1e-8, friction=True))
    run = GearModel("rigid", slider="spherical", friction=True).simulate(step=STEP)
    ours = run.summary()
    pairs = [(name, name) for name in ("ground_vertical", "ground_longitudinal", "stroke")]
    for mine, theirs in pairs + [("friction_dynamic", "friction_dynamic")]:
        assert abs(ours[mine]) == pytest.approx(abs(reference[theirs]), rel=AGREEMENT), mine
        time = ours[f"{mine}_time"]
        assert time == pytest.approx(reference[f"{theirs}_time"], rel=AGREEMENT), mine
    frictionless = ode.summary(ode.simulate(rtol=1e-8))
    assert ours["ground_vertical"] > (1 + 2 * AGREEMENT) * frictionless["ground_vertical"]


def test_a_rigid_leg_has_no_spring_back(rigid):
    """After the spin-up the rigid leg's attachment load stays a drag (docs/landing_gear.md,
    "No spring-back in a rigid leg"), up to the ringing of its stiffened tubes, below
    SPRING_BACK of the spin-up peak: the summary gives it no spring-back (NaN: an empty
    cell), no time and no frequency."""
    for run in rigid.values():
        summary = run.summary()
        for name in ("spring_back", "spring_back_time", "spring_back_frequency"):
            assert np.isnan(summary[name]), name
        ringing, _ = run.peak("attachment_longitudinal", +1.0, summary["spin_up_time"])
        assert 0 < ringing < 1e-3 * abs(summary["attachment_longitudinal_spin_up"])


def test_touchdown_is_the_issues_state():
    """The strut on its extension stop in static balance (the ODE study's S0), the axle at
    R0, every part moving at the touchdown speeds, the wheel still."""
    model = GearModel("fv3-3")
    state = model.touchdown()
    s = model.structure
    x = {n: s.node_position(n) + state.q[s.node_dofs(n)[:3]] for n in ("C.start", "P.start")}
    stroke = model.gear.extension - np.linalg.norm(x["P.start"] - x["C.start"])
    S0 = ode.initial_stroke(model.gear)
    # Newton's increments below 1e-8 of the largest displacement (the drop to the ground)
    assert stroke == pytest.approx(S0, abs=1e-8 * np.abs(state.q).max())
    axle = s.node_dofs("axle")
    assert s.node_position("axle")[2] + state.q[axle[2]] == pytest.approx(model.gear.radius)
    moving = np.setdiff1d(np.arange(s.n_dofs), s.node_dofs("wheel"))
    np.testing.assert_array_equal(state.v[moving[moving % 6 == 0]], model.gear.forward)
    np.testing.assert_array_equal(state.v[moving[moving % 6 == 2]], -model.gear.sink)
    assert not state.v[s.node_dofs("wheel")].any() and not state.qdd.any()


@pytest.mark.parametrize("model", MODELS[1:])
@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_the_legs_fore_aft_stiffness_is_the_two_beam_closed_form(model, kind):
    """At full extension the leg is the paper's Figure 3 setup at s / L = 0.75: its tip
    stiffness within the paper's Figure 5 error of the mesh (5-7 % for one element, 2 % and
    2.5 % for three and five)."""
    g = GearModel(model, slider=kind).gear
    exact = sliding_beams(g.extension, g.length, g.EJ, g.GA, kind)["k_norm"] * g.EJ / g.length**3
    bound = {1: 0.07, 3: 0.02, 5: 0.025}[elements(model)]
    assert GearModel(model, slider=kind).fore_aft_mode().stiffness == pytest.approx(
        exact, rel=bound
    )


def test_the_ground_alone_turns_the_wheel_and_slows_the_gear():
    """``I_w omega + R0 (P - P0) = 0`` at every step, ``P`` the fore-aft momentum of every
    mass (``M v`` summed over the x dofs), against the wheel's angular momentum at the end
    (measured: 4e-9 of it over 1000 steps)."""
    model = GearModel("fv3-1")
    dynamics = model.dynamics
    x_dofs = np.arange(0, model.structure.n_dofs, 6)
    masses = dynamics.M.diagonal()[x_dofs]
    spin = model.structure.node_dofs("wheel")[4]
    states = []

    class Keep:
        def start(self, dynamics, state):
            states.append(state)

        def record(self, dynamics, new, old):
            states.append(new)

        def close(self):
            pass

    dynamics.run(model.touchdown(), 0.1, STEP, recorder=Keep(), progress=False)
    P0 = masses @ states[0].v[x_dofs]
    invariant = np.array(
        [
            model.gear.spin_inertia * s.v[spin] + model.gear.radius * (masses @ s.v[x_dofs] - P0)
            for s in states
        ]
    )
    scale = model.gear.spin_inertia * abs(states[-1].v[spin])
    # each step's Newton leaves its equations wrong by at most its tolerance (1e-8) of
    # their scale; at worst the steps' errors add up
    assert np.abs(invariant).max() <= 1e-8 * (len(states) - 1) * scale


def test_a_flexible_leg_springs_back():
    """The paper: after the spin-up the flexible leg springs forward (a forward attachment
    load of the order of the spin-up drag) and rings at its fore-aft bending frequency."""
    summary = GearModel("fv3-1").simulate(step=STEP).summary()
    assert summary["spring_back"] > 0.5 * abs(summary["attachment_longitudinal_spin_up"])
    assert np.isfinite(summary["spring_back_frequency"])
