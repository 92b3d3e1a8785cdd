"""The rigid landing gear as ordinary differential equations (``solve_ivp``).

An independent reference for the ``rigid`` model of the Figure 7 study: the same strut, tyre
and masses, a rigid vertical leg, integrated by scipy's Radau (or LSODA) at tight tolerances.
The equations, the bearing reactions and the initial state are derived in
``docs/landing_gear.md`` (section "The rigid gear as ODEs"); the force laws are
:mod:`sliders.forces.laws`.

States ``y`` (SI units)::

    x, z_u     airframe position forward, axle height (z up, ground at 0); the airframe's
               attachment (the cylinder top) is at z_a = z_u + s_ext + L - S
    S          stroke, positive in compression
    u, v_u     forward speed of airframe and axle (one, the leg being rigid); axle's z rate
    S'         stroke rate
    omega      wheel spin, positive rolling forward
    W_*        work dissipated so far by the orifice, the tyre's radial damping, the tyre's
               slip and the bearing friction (quadratures, for the energy balance)

Equations (``M = m_a + m_u``, lift ``M g`` on the airframe)::

    M u'        = F_x
    m_a v_a'    = F_s - F_f + m_u g,               v_a = v_u - S'
    m_u v_u'    = F_z - F_s + F_f - m_u g,         S'' = v_u' - v_a'
    I_w omega'  = -F_x R0

with the strut force ``F_s(S, S')``, the tyre's ``F_z(d, d')`` (``d = R0 - z_u``) and
``F_x = -mu(kappa) F_z``, and the bearing friction on the piston
``F_f = -mu_b N tanh(S' / v_eps)``, ``N = |R_top| + |R_bot|`` when friction is on.

Run as ``python -m studies.landing_gear_ode --out DIR``: writes ``DIR/landing_gear_ode.csv``
(the Figure 7 study's columns for ``rigid-ode`` and ``rigid-ode-friction``), ``DIR/landing_gear_ode_
summary.csv`` (peaks with their times, spin-up, lift-off, friction) and
``DIR/landing_gear_ode_convergence.csv`` (the figures against rtol and method), and prints
them.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from fvbeam.io import write_atomic
from sliders.forces.laws import (
    coulomb_friction,
    orifice_damper,
    tyre_energy,
    tyre_longitudinal,
    tyre_radial,
)
from sliders.gear import outputs as gear_outputs
from sliders.gear.parameters import ISSUE_14, Gear

#: The output columns of the Figure 7 study, in order.
COLUMNS = ("model", "t", *gear_outputs.COLUMNS)
#: State names, in the order of ``y``.
STATES = (
    "x",
    "z_u",
    "S",
    "u",
    "v_u",
    "S_rate",
    "omega",
    "W_damper",
    "W_tyre",
    "W_slip",
    "W_bearing",
)
#: Typical size of each state, the scale of its absolute tolerance (``atol = rtol * SCALE``).
SCALE = np.array([10.0, 1.0, 0.1, 40.0, 3.0, 3.0, 180.0, 1e3, 1e3, 1e3, 1e3])
#: Spin-up: the wheel reaches this fraction of the rolling speed u / R0.
SPIN_UP = gear_outputs.SPIN_UP


def bearing_reactions(
    load: np.ndarray, stroke: np.ndarray, gear: Gear
) -> tuple[np.ndarray, np.ndarray]:
    """Transverse reactions on the rigid piston at its two bearings (signed, same axis as
    ``load``): the piston top (the top slider, at the piston's abscissa 0) and the cylinder
    bottom (the bottom slider, at ``L - s``), for a transverse ``load`` at the piston's lower
    end (``L``), ``s = s_ext - S``.  Moments about the piston top and the force balance::

        R_bot (L - s) + P L = 0,      R_top + R_bot + P = 0
        R_bot = -P L / (L - s),        R_top = P s / (L - s)
    """
    s = gear.extension - stroke
    lever = gear.length - s
    return load * s / lever, -load * gear.length / lever


@dataclass(frozen=True)
class Forces:
    """Every force of the rigid gear at one state (arrays over times when ``y`` has a time
    axis)."""

    strut: np.ndarray
    damper: np.ndarray
    vertical: np.ndarray
    longitudinal: np.ndarray
    attachment: np.ndarray
    top: np.ndarray
    bottom: np.ndarray
    bearing: np.ndarray


def forces(y: np.ndarray, gear: Gear, friction: bool) -> Forces:
    """The forces at state ``y`` (``docs/landing_gear.md``): strut, tyre, attachment load
    ``P = m_a F_x / M`` (the piston's transverse load, ground force less the unsprung mass's
    inertia), the bearing reactions and the bearing friction on the piston."""
    _, z_u, S, u, v_u, S_rate, omega = y[:7]
    strut, _, _ = gear.strut(S, S_rate)
    damper, _ = orifice_damper(
        S_rate, compression=gear.strut.compression, rebound=gear.strut.rebound
    )
    vertical, _, _ = tyre_radial(
        gear.radius - z_u, -v_u, stiffness=gear.tyre_stiffness, damping=gear.tyre_damping
    )
    longitudinal, _, _, _ = tyre_longitudinal(
        u,
        omega,
        vertical,
        radius=gear.radius,
        B=gear.B,
        C=gear.C,
        D=gear.D,
        speed_eps=gear.speed_eps,
    )
    attachment = gear.airframe_mass / gear.mass * longitudinal
    top, bottom = bearing_reactions(attachment, S, gear)
    normal = np.abs(top) + np.abs(bottom)
    bearing = (
        coulomb_friction(S_rate, normal, mu=gear.bearing_mu, v_eps=gear.bearing_v_eps)[0]
        if friction
        else np.zeros_like(normal)
    )
    return Forces(strut, damper, vertical, longitudinal, attachment, top, bottom, bearing)


def rates(t: float, y: np.ndarray, gear: Gear, friction: bool) -> np.ndarray:
    """``dy/dt`` (module docstring), for one state or (columns) several.

    A state whose stroke leaves no gas (``S >= V0 / A``) is no solution but can be a trial
    iterate of the implicit solver's Newton loop (a large first step over the touchdown's
    jump, say): it gets NaN rates, which Radau and BDF answer by rejecting the step and
    halving it, where the gas law's error would end the integration.
    """
    if np.any(y[2] >= gear.strut.volume / gear.strut.area):
        return np.full(np.shape(y), np.nan)
    f = forces(y, gear, friction)
    m_a, m_u, g = gear.airframe_mass, gear.unsprung_mass, gear.gravity
    a_a = (f.strut - f.bearing + m_u * g) / m_a
    a_u = (f.vertical - f.strut + f.bearing - m_u * g) / m_u
    u, v_u, S_rate, omega = y[3], y[4], y[5], y[6]
    deflection = gear.radius - y[1]
    spring = np.where(deflection > 0, gear.tyre_stiffness * deflection, 0.0)
    return np.array(
        [
            u,
            v_u,
            S_rate,
            f.longitudinal / gear.mass,
            a_u,
            a_u - a_a,
            -f.longitudinal * gear.radius / gear.spin_inertia,
            f.damper * S_rate,
            -(f.vertical - spring) * v_u,
            -f.longitudinal * (u - omega * gear.radius),
            -f.bearing * S_rate,
        ]
    )


def initial_stroke(gear: Gear) -> float:
    """The stroke at touchdown: the strut on its extension stop in static balance, the stop
    holding the gas preload and the unsprung weight, ``F_s(S0, 0) = -m_u g`` (Newton from
    ``S = 0``; ``F_s`` is increasing, so it converges to the one root, ``S0 < 0``)."""
    target = -gear.unsprung_mass * gear.gravity
    S = 0.0
    for _ in range(50):
        force, slope, _ = gear.strut(S, 0.0)
        step = (float(force) - target) / float(slope)
        S -= step
        if abs(step) <= 4 * np.finfo(float).eps * max(abs(S), 1e-12):
            return S
    raise RuntimeError(f"the touchdown stroke did not converge (last step {step:.3g} m)")


def initial_state(gear: Gear) -> np.ndarray:
    """Touchdown: the axle at ``z = R0`` (tyre just touching), everything sinking
    at ``sink`` and moving forward at ``forward``, the wheel still, the strut on its
    extension stop in static balance (:func:`initial_stroke`)."""
    S0 = initial_stroke(gear)
    return np.array([0.0, gear.radius, S0, gear.forward, -gear.sink, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])


def energy(y: np.ndarray, gear: Gear) -> np.ndarray:
    """Mechanical energy (kinetic, gravity less lift, strut, tyre spring) plus the work
    dissipated so far: constant along an exact solution (``docs/landing_gear.md``)."""
    _, z_u, S, u, v_u, S_rate, omega = y[:7]
    v_a = v_u - S_rate
    kinetic = 0.5 * (
        gear.mass * u * u
        + gear.airframe_mass * v_a * v_a
        + gear.unsprung_mass * v_u * v_u
        + gear.spin_inertia * omega * omega
    )
    # gravity on both masses, lift (m_a + m_u) g on the airframe: m_u g (z_u - z_a)
    potential = -gear.unsprung_mass * gear.gravity * (gear.extension + gear.length - S)
    stored = gear.strut.energy(S) + tyre_energy(gear.radius - z_u, stiffness=gear.tyre_stiffness)
    return kinetic + potential + stored + np.sum(y[7:11], axis=0)


@dataclass
class Run:
    """One integration: the solver's result (dense), the settings, events and wall time."""

    gear: Gear
    friction: bool
    method: str
    rtol: float
    solution: Any  # scipy's OdeResult, with dense output and events
    seconds: float

    def y(self, t: np.ndarray) -> np.ndarray:
        """The states at times ``t`` (dense output), ``(11, len(t))``."""
        return self.solution.sol(np.asarray(t, dtype=float))

    def outputs(self, t: np.ndarray) -> dict[str, np.ndarray]:
        """At times ``t``: the Figure 7 study's columns (slider loads as magnitudes), then the
        bearings' normal force ``|R_top| + |R_bot|``, its friction ``mu_b N`` (what the
        post-processing takes) and the friction force in the dynamics (zero without)."""
        y = self.y(t)
        f = forces(y, self.gear, self.friction)
        normal = np.abs(f.top) + np.abs(f.bottom)
        return {
            "t": np.asarray(t, dtype=float),
            "attachment_longitudinal": f.attachment,
            "ground_vertical": f.vertical,
            "ground_longitudinal": f.longitudinal,
            "top_slider": np.abs(f.top),
            "bottom_slider": np.abs(f.bottom),
            "stroke": y[2],
            "wheel_speed": y[6],
            "bearing_normal": normal,
            "friction_post": self.gear.bearing_mu * normal,
            "friction_dynamic": np.abs(f.bearing),
        }


def spin_up(t: float, y: np.ndarray, gear: Gear, friction: bool) -> float:
    """Zero when the wheel reaches ``SPIN_UP`` of the rolling speed (crossing upward)."""
    return float(y[6] * gear.radius - SPIN_UP * y[3])


spin_up.direction = 1.0  # type: ignore[attr-defined]


def contact(t: float, y: np.ndarray, gear: Gear, friction: bool) -> float:
    """The tyre's deflection ``d = R0 - z_u``: zero when it touches the ground or leaves it."""
    return float(gear.radius - y[1])


def simulate(
    gear: Gear = ISSUE_14,
    *,
    friction: bool = False,
    t_end: float = 0.3,
    rtol: float = 1e-10,
    method: str = "Radau",
) -> Run:
    """Integrate the rigid gear from touchdown to ``t_end`` (dense output; events for the
    spin-up and the tyre's contact), ``atol = rtol * SCALE`` per state."""
    start = time.perf_counter()
    solution = solve_ivp(
        rates,
        (0.0, t_end),
        initial_state(gear),
        method=method,
        rtol=rtol,
        atol=rtol * SCALE,
        dense_output=True,
        events=[spin_up, contact],
        vectorized=True,
        args=(gear, friction),
    )
    if not solution.success:
        raise RuntimeError(f"solve_ivp ({method}, rtol {rtol}) failed: {solution.message}")
    return Run(gear, friction, method, rtol, solution, time.perf_counter() - start)


def peak(run: Run, name: str) -> tuple[float, float]:
    """The largest magnitude of output ``name`` (:meth:`Run.outputs`) and its time: the
    largest at the solver's steps, refined by Brent's method on the dense output over the
    steps beside it."""
    steps = run.solution.t
    values = np.abs(run.outputs(steps)[name])
    i = int(np.argmax(values))
    lo, hi = steps[max(i - 1, 0)], steps[min(i + 1, len(steps) - 1)]

    def negative(t: float) -> float:
        return -float(np.abs(run.outputs(np.array([t]))[name][0]))

    found = minimize_scalar(negative, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    t = float(found.x) if -found.fun >= values[i] else float(steps[i])
    return float(run.outputs(np.array([t]))[name][0]), t


#: The outputs whose peaks :func:`summary` reports.
PEAKS = (*gear_outputs.PEAKS, "friction_dynamic")


def summary(run: Run) -> dict[str, float]:
    """Derived events of one run (``docs/landing_gear.md``, "Measured"): peaks with their
    times, spin-up time, lift-off, the largest forward attachment load after spin-up (the
    spring-back a rigid leg lacks), the friction fractions (NaN for the friction in the
    dynamics of a run without it), the bearing friction's work, the energy at touchdown and
    the energy balance's largest error [J]."""
    out: dict[str, float] = {}
    for name in PEAKS:
        out[name], out[f"{name}_time"] = (
            peak(run, name) if run.friction or name != "friction_dynamic" else (math.nan,) * 2
        )
    for name in ("friction_post", "friction_dynamic"):
        out[f"{name}_fraction"] = out[name] / out["ground_vertical"]
    spin_up_times = run.solution.t_events[0]
    out["spin_up_time"] = float(spin_up_times[0]) if len(spin_up_times) else math.nan
    touching = zip(run.solution.t_events[1], run.solution.y_events[1], strict=True)
    leaving = [t for t, y in touching if t > 0 and y[4] > 0]
    out["lift_off_time"] = float(leaving[0]) if leaving else math.nan
    t = np.linspace(0.0, run.solution.t[-1], 30001)
    outputs = run.outputs(t)
    after = t >= out["spin_up_time"]
    out["forward_after_spin_up"] = float(np.max(outputs["attachment_longitudinal"][after]))
    y = run.y(t)
    out["bearing_work"] = float(y[10, -1])
    e = energy(y, run.gear)
    out["energy"] = float(e[0])
    out["energy_error"] = float(np.max(np.abs(e - e[0])))
    out["seconds"] = run.seconds
    out["steps"] = float(len(run.solution.t) - 1)
    return out


def write_table(path: Path, rows: list[dict], columns: tuple[str, ...]) -> None:
    """Rows as CSV (floats at full precision), atomically."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            writer.writeheader()
            writer.writerows(rows)

    write_atomic(path, write)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--rtol", type=float, default=1e-10, help="of the two models' runs")
    parser.add_argument(
        "--convergence",
        type=lambda text: [float(r) for r in text.split(",")],
        default=[1e-6, 1e-7, 1e-8, 1e-9, 1e-11],
        help="further rtols of the frictionless model (Radau), comma-separated",
    )
    args = parser.parse_args(argv)
    from tqdm.auto import tqdm

    jobs = [
        ("rigid-ode", False, "Radau", args.rtol),
        ("rigid-ode-friction", True, "Radau", args.rtol),
    ]
    jobs += [("rigid-ode", False, "Radau", rtol) for rtol in args.convergence]
    jobs += [("rigid-ode", False, "LSODA", args.rtol)]
    rows, summaries = [], []
    t = np.linspace(0.0, 0.3, 3001)
    for k, (model, friction, method, rtol) in enumerate(tqdm(jobs, desc="rigid gear", unit="run")):
        run = simulate(friction=friction, rtol=rtol, method=method)
        summaries.append({"model": model, "method": method, "rtol": rtol, **summary(run)})
        if k < 2:
            outputs = run.outputs(t)
            rows += [
                {"model": model, **{name: float(outputs[name][i]) for name in COLUMNS[1:]}}
                for i in range(len(t))
            ]
    names = tuple(summaries[0])
    write_table(args.out / "landing_gear_ode.csv", rows, COLUMNS)
    write_table(args.out / "landing_gear_ode_summary.csv", summaries[:2], names)
    write_table(
        args.out / "landing_gear_ode_convergence.csv", [summaries[0], *summaries[2:]], names
    )
    for row in summaries:
        print(
            ", ".join(
                f"{k}={v:.9g}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()
            )
        )


if __name__ == "__main__":
    main()
