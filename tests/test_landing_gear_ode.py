"""The rigid landing gear as ODEs (studies/landing_gear_ode.py), docs/landing_gear.md.

Sources of truth:
* statics: the touchdown state is a static balance (accelerations zero), and with no sink
  and no forward speed nothing moves;
* the piston's equilibrium solved as a linear system for the bearing reactions, and the
  bearing lever (L + s) / (L - s) = 7 at full extension (the notes);
* conservation: energy plus the dissipated work is constant (to the integrator's
  tolerance, and shrinking with it); I_w omega + R0 M (u - u0) is a linear invariant of the
  equations (kept by Radau to roundoff);
* the spin-up event's definition, and a rigid leg's attachment load never reversing after
  spin-up (kappa = 0 is a fixed point of the spin equation, docs/landing_gear.md);
* two integrators (Radau, LSODA) agreeing;
* the paper's "about 13 000 N" peak vertical load that the orifice was tuned to.
"""

import csv

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from studies import landing_gear_ode as ode

EPS = float(np.finfo(float).eps)
GEAR = ode.Gear()
#: The tolerance of the shared runs: peaks converge to ~1e-9 there (docs/landing_gear.md).
RTOL = 1e-8


@pytest.fixture(scope="module")
def run():
    return ode.simulate(GEAR, rtol=RTOL)


@pytest.fixture(scope="module")
def summary(run):
    return ode.summary(run)


def test_touchdown_is_a_static_balance():
    """F_s(S0, 0) = -m_u g; S0 is the linearised balance -(F_gas(0) + m_u g) / (k_stop +
    F_gas'(0)) to its second-order term (F_gas'' S0^2 / 2 / k_stop, relative 2e-9), and the
    accelerations of both masses vanish at touchdown (no tyre force at d = 0)."""
    S0 = ode.initial_stroke(GEAR)
    force, slope, _ = GEAR.strut(S0, 0.0)
    weight = GEAR.unsprung_mass * GEAR.gravity
    assert float(force) == pytest.approx(-weight, abs=4 * EPS * 1e8 * abs(S0))
    gas, gas_slope = GEAR.strut.gas(0.0)
    assert S0 == pytest.approx(-(gas + weight) / (1e8 + gas_slope), rel=1e-8)
    y0 = ode.initial_state(GEAR)
    assert y0[1] == GEAR.radius
    rates = ode.rates(0.0, y0, GEAR, True)
    # the stop's force k |S0| ~ 600 N against roundoff in the balance: a few ulps of it / m_u
    np.testing.assert_allclose(rates[4:6], 0.0, atol=16 * EPS * 1e8 * abs(S0) / 12.0)


def test_at_rest_nothing_moves():
    """No sink, no forward speed: the touchdown state is an equilibrium and stays."""
    gear = ode.Gear(sink=0.0, forward=0.0)
    rest = ode.simulate(gear, rtol=RTOL, t_end=0.05)
    y = rest.y(np.linspace(0.0, 0.05, 11))
    np.testing.assert_allclose(
        y - y[:, :1], 0.0, atol=RTOL * np.max(ode.SCALE), err_msg="the gear moved"
    )


@settings(max_examples=50, deadline=None)
@given(load=st.floats(-2e4, 2e4, allow_subnormal=False), stroke=st.floats(-1e-3, 0.16))
def test_bearing_reactions_hold_the_piston(load, stroke):
    """The two reactions solve the rigid piston's force and moment balance (about its lower
    end, an independent pair of equations), solved here by numpy."""
    top, bottom = ode.bearing_reactions(np.array(load), np.array(stroke), GEAR)
    s = GEAR.extension - stroke
    L = GEAR.length
    # forces: R_top + R_bot = -P; moments about the lower end (abscissa L on the piston):
    # R_top (0 - L) + R_bot ((L - s) - L) = 0
    expected = np.linalg.solve([[1.0, 1.0], [-L, -s]], [-load, 0.0])
    np.testing.assert_allclose([top, bottom], expected, rtol=1e-12, atol=1e-12 * abs(load))


def test_bearing_lever_at_full_extension():
    """(|R_top| + |R_bot|) / |P| = (L + s) / (L - s) = 7 at s = 0.45 m (the notes)."""
    top, bottom = ode.bearing_reactions(np.array(1.0), np.array(0.0), GEAR)
    assert abs(top) + abs(bottom) == pytest.approx(7.0, rel=4 * EPS)


def test_energy_balance(run, summary):
    """Energy plus dissipated work stays at its touchdown value to the integrator's relative
    tolerance (of the states' scale, the forward kinetic energy dominating), and the error
    shrinks with the tolerance (rtol 1e-6: over ten times larger)."""
    assert summary["energy_error"] <= RTOL * summary["energy"]
    coarse = ode.summary(ode.simulate(GEAR, rtol=1e-6))
    assert coarse["energy_error"] > 10 * summary["energy_error"]


def test_spin_and_forward_motion_share_one_impulse(run):
    """M u' = F_x and I_w omega' = -F_x R0: I_w omega + R0 M (u - u0) = 0 for all t, kept by
    a Runge-Kutta method to roundoff accumulated over the steps (a few ulps of each term per
    step)."""
    t = np.linspace(0.0, 0.3, 301)
    y = run.y(t)
    invariant = GEAR.spin_inertia * y[6] + GEAR.radius * GEAR.mass * (y[3] - GEAR.forward)
    steps = len(run.solution.t)
    scale = GEAR.radius * GEAR.mass * GEAR.forward + GEAR.spin_inertia * np.max(y[6])
    assert np.max(np.abs(invariant)) <= steps * 4 * EPS * scale


def test_spin_up_event(run, summary):
    """At the spin-up time the wheel turns at 99 % of the rolling speed, once."""
    t = summary["spin_up_time"]
    assert len(run.solution.t_events[0]) == 1
    y = run.y(np.array([t]))[:, 0]
    assert y[6] * GEAR.radius / y[3] == pytest.approx(ode.SPIN_UP, rel=RTOL * 100)
    assert 0.0 < t < summary["lift_off_time"]


def test_rigid_leg_has_no_spring_back(summary):
    """After spin-up the slip decays to zero without crossing it, so the attachment load
    stays a drag: at most the slip's error (about rtol) times the curve's slope B C D = 13.2
    times the peak vertical load may show as a forward load."""
    assert summary["forward_after_spin_up"] <= 13.2 * RTOL * summary["ground_vertical"]


def test_radau_and_lsoda_agree(summary):
    """Peak loads and the spin-up time of two integrators at rtol 1e-8 agree to 1e-6 (their
    own convergence to ~1e-8, docs/landing_gear.md, with a margin of 100); peak times of
    the flat vertical peak to its resolution, sqrt(1e-8) relative."""
    other = ode.summary(ode.simulate(GEAR, rtol=RTOL, method="LSODA"))
    for name in ("ground_vertical", "ground_longitudinal", "top_slider", "bottom_slider"):
        assert other[name] == pytest.approx(summary[name], rel=1e-6), name
    assert other["spin_up_time"] == pytest.approx(summary["spin_up_time"], rel=1e-6)
    assert other["ground_vertical_time"] == pytest.approx(summary["ground_vertical_time"], rel=1e-4)


def test_peak_vertical_is_the_papers(summary):
    """The orifice was tuned to the paper's "about 13 000 N" (read off its Figure 7; taken
    as +-5 %), and the stroke stays short of the bottoming stop (0.16 m)."""
    assert summary["ground_vertical"] == pytest.approx(13e3, rel=0.05)
    assert summary["stroke"] < 0.16


def test_friction_in_the_dynamics():
    """Bearing friction opposes the stroke: it dissipates (positive work) and stiffens the
    strut (a higher vertical peak than without); its peak, a full sliding mu_b N, equals the
    post-processed mu_b (|R_top| + |R_bot|) of the same run."""
    friction = ode.summary(ode.simulate(GEAR, rtol=1e-7, friction=True))
    assert friction["bearing_work"] > 0
    assert friction["friction_dynamic"] == pytest.approx(friction["friction_post"], rel=1e-6)
    plain = ode.summary(ode.simulate(GEAR, rtol=1e-7))
    assert friction["ground_vertical"] > plain["ground_vertical"]
    assert np.isnan(plain["friction_dynamic"]) and plain["bearing_work"] == 0.0


def test_command_writes_the_tables(tmp_path):
    """The command's three tables: the issue's columns for both models on 0..0.3 s."""
    ode.main(["--out", str(tmp_path), "--rtol", "1e-6", "--convergence", "1e-5"])
    with open(tmp_path / "landing_gear_ode.csv") as f:
        rows = list(csv.DictReader(f))
    assert tuple(rows[0]) == ode.COLUMNS
    assert {r["model"] for r in rows} == {"rigid-ode", "rigid-ode-friction"}
    assert len(rows) == 2 * 3001 and float(rows[-1]["t"]) == 0.3
    with open(tmp_path / "landing_gear_ode_convergence.csv") as f:
        assert [r["rtol"] for r in csv.DictReader(f)] == ["1e-06", "1e-05", "1e-06"]
