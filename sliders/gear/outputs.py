"""What a landing-gear run records, and the events derived from it (issue 14).

:class:`GearRecorder` is a :class:`sliders.solve.dynamics.Recorder` that keeps, at every
step, the few dofs, velocities and slider unknowns the outputs need; :meth:`GearRecorder.
result` turns them into a :class:`GearRun`: the issue's columns (:data:`COLUMNS`), velocities
and the bearing friction post-processed (:data:`EXTRA`), and the events: peaks with their
times, the spin-up time, lift-off and the spring-back frequency (:meth:`GearRun.summary`).

The columns, at each step (``docs/landing_gear.md``, "Outputs"):

``attachment_longitudinal``
    the fore-aft force of the gear on the airframe, forward positive: ``m_a x_a''`` (the
    airframe's equation of motion; nothing else acts on it fore-aft);
``ground_vertical``, ``ground_longitudinal``
    the tyre's ``F_z`` and ``F_x`` at the state (:meth:`sliders.forces.elements.Tyre.
    outputs`);
``top_slider``, ``bottom_slider``
    the magnitude of each slider's reaction force ``lambda`` across the strut's axis
    (its x and y components: the strut is vertical);
``stroke``, ``wheel_speed``
    the issue's ``S = s_ext - s``, ``s`` the top slider's abscissa on the cylinder (the strut
    element's stroke ``s_ext - |x_P.start - x_C.start|`` is ``strut_stroke``: shorter by the
    chord's shortening, second order in the cylinder's slope), and the wheel's spin (the
    tyre's :meth:`~sliders.forces.elements.ForceElement.outputs`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from fvbeam.structure import Structure
from sliders.app import events
from sliders.forces.elements import AxialForce, Tyre
from sliders.forces.laws import Strut
from sliders.gear.parameters import Gear
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.solve.integrator import State

if TYPE_CHECKING:
    from sliders.solve.dynamics import Dynamics


class Parts(Protocol):
    """What the recorder reads of a gear model (:class:`sliders.gear.model.GearModel`)."""

    model: str
    slider_kind: str
    gear: Gear
    structure: Structure
    strut: AxialForce
    tyre: Tyre
    sliders: list[Slider]


#: The issue's output columns after ``model, t`` (Figure 7 study), in order.
COLUMNS = (
    "attachment_longitudinal",
    "ground_vertical",
    "ground_longitudinal",
    "top_slider",
    "bottom_slider",
    "stroke",
    "wheel_speed",
)
#: Further outputs: the strut element's stroke (its chord's), velocities (airframe, axle, the
#: strut's stroke rate), the sliders' abscissae and
#: couples (the classical sliders' orientation multipliers), the bearings' normal force
#: ``|R_top| + |R_bot|`` and its friction ``mu_b N`` (post-processing), the bearing friction
#: in the dynamics (:func:`friction_along`, both sliders' summed; zero without it), and the
#: tyre's deflection.
EXTRA = (
    "strut_stroke",
    "strut_force",
    "airframe_forward_speed",
    "airframe_vertical_speed",
    "axle_forward_speed",
    "axle_vertical_speed",
    "stroke_rate",
    "top_xi",
    "bottom_xi",
    "top_couple",
    "bottom_couple",
    "bearing_normal",
    "friction_post",
    "friction",
    "tyre_deflection",
)
#: Spin-up: the wheel reaches this fraction of the rolling speed ``u / R0`` (issue 14).
SPIN_UP = 0.99
#: The smallest forward attachment load after the spin-up, relative to the spin-up's
#: backward peak, that counts as a spring-back (:meth:`GearRun.spring_back`).
SPRING_BACK = 0.01
#: The outputs whose peaks :meth:`GearRun.summary` reports.
PEAKS = (
    "ground_vertical",
    "ground_longitudinal",
    "attachment_longitudinal",
    "top_slider",
    "bottom_slider",
    "stroke",
    "friction_post",
)


class GearRecorder:
    """Keeps what the outputs need of every state of a run (module docstring): the time,
    the airframe's fore-aft acceleration, the Newton iterations, the displacements, the
    velocities and the sliders' unknowns."""

    def __init__(self, model: Parts, keep: bool = False) -> None:
        self.model = model
        #: With ``keep``, every state's time, displacements and slider unknowns (a render).
        self.states: list[tuple[float, np.ndarray, list[np.ndarray]]] | None = [] if keep else None
        self.airframe_x = int(model.structure.node_dofs("airframe")[0])
        self.head: list[tuple[float, float, int]] = []
        self.q: list[np.ndarray] = []
        self.v: list[np.ndarray] = []
        self.unknowns: list[np.ndarray] = []

    def start(self, dynamics: Dynamics, state: State) -> None:
        for kept in (self.head, self.q, self.v, self.unknowns):
            kept.clear()
        if self.states is not None:
            self.states.clear()
        self.record(dynamics, state, state)

    def record(self, dynamics: Dynamics, new: State, old: State) -> None:
        if self.states is not None:
            self.states.append((new.t, new.q, new.unknowns))
        self.head.append((new.t, new.qdd[self.airframe_x], new.iterations))
        self.q.append(new.q)
        self.v.append(new.v)
        self.unknowns.append(np.stack(new.unknowns))  # both sliders alike: (2, n_unknowns)

    def close(self) -> None:
        """Nothing is held open."""

    def result(self, seconds: float = math.nan) -> GearRun:
        """The outputs of the states recorded (module docstring)."""
        model, g = self.model, self.model.gear
        head = np.array(self.head)
        t, accel, iterations = head[:, 0], head[:, 1], head[:, 2]
        q, v, y = np.array(self.q), np.array(self.v), np.array(self.unknowns)
        tyre = model.tyre.outputs(model.structure, q, v)
        strut = model.strut.outputs(model.structure, q, v)
        across = np.linalg.norm(y[:, :, 1:3], axis=2)  # lambda across the strut (x, y)
        couples = np.linalg.norm(y[:, :, 4:6], axis=2)
        normal = across.sum(axis=1)
        s = model.structure
        airframe, axle = s.node_dofs("airframe"), s.node_dofs("axle")
        outputs = {
            "attachment_longitudinal": s.bodies[0].mass * accel,
            "ground_vertical": tyre["Fz"],
            "ground_longitudinal": tyre["Fx"],
            "top_slider": across[:, 0],
            "bottom_slider": across[:, 1],
            "stroke": g.extension - y[:, 0, 0],
            "wheel_speed": tyre["spin"],
            "airframe_forward_speed": v[:, airframe[0]],
            "airframe_vertical_speed": v[:, airframe[2]],
            "axle_forward_speed": v[:, axle[0]],
            "axle_vertical_speed": v[:, axle[2]],
            "strut_stroke": strut["stroke"],
            "strut_force": strut["force"],
            "stroke_rate": strut["rate"],
            "top_xi": y[:, 0, 0],
            "bottom_xi": y[:, 1, 0],
            "top_couple": couples[:, 0],
            "bottom_couple": couples[:, 1],
            "bearing_normal": normal,
            "friction_post": g.bearing_mu * normal,
            "friction": friction_along(model, q, v, y),
            "tyre_deflection": tyre["deflection"],
        }
        return GearRun(
            model.model,
            model.slider_kind,
            g.radius,
            g.speed_eps,
            g.strut,
            t,
            outputs,
            iterations,
            seconds,
            self.states,
        )


def friction_along(model: Parts, q: np.ndarray, v: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The bearing friction in the dynamics at each state (``q``, ``v`` (k, n), the
    sliders' unknowns ``y`` (k, J, m)): the sum over the sliders of the magnitude of the
    friction force along the line (:meth:`sliders.joints.packed.JointPack.frictions`); zero
    for sliders without friction."""
    if all(s.friction is None for s in model.sliders):
        return np.zeros(len(q))
    pack = JointPack(model.sliders, model.structure)
    return np.abs(pack.frictions(q, v, y.reshape(len(y), -1))).sum(axis=1)


@dataclass
class GearRun:
    """One run's time series (:data:`COLUMNS`, :data:`EXTRA`) and its events."""

    model: str
    slider: str
    radius: float
    #: The tyre's regularising speed (:meth:`spin_up_time`).
    speed_eps: float
    #: The strut's law (its stops, :meth:`summary`).
    strut: Strut
    t: np.ndarray
    outputs: dict[str, np.ndarray]
    iterations: np.ndarray
    seconds: float = math.nan
    #: Every step's time, displacements and slider unknowns, when the recorder kept them.
    states: list[tuple[float, np.ndarray, list[np.ndarray]]] | None = None

    def peak(
        self, name: str, sign: float = 0.0, start: float = -math.inf, stop: float = math.inf
    ) -> tuple[float, float]:
        """The largest magnitude of output ``name`` (signed; with ``sign`` +1 or -1 the
        largest value of that sign) between ``start`` and ``stop``, and its time
        (:func:`sliders.app.events.peak`: refined by a parabola)."""
        return events.peak(self.t, self.outputs[name], sign, start, stop)

    def spin_up_time(self) -> float:
        """When the wheel first reaches :data:`SPIN_UP` of the rolling speed,
        ``omega R0 = 0.99 u_axle``, the axle faster than the tyre's ``speed_eps``
        (:func:`sliders.app.events.spin_up`)."""
        o = self.outputs
        return events.spin_up(
            self.t,
            o["wheel_speed"],
            o["axle_forward_speed"],
            self.radius,
            SPIN_UP,
            self.speed_eps,
        )

    def lift_off_time(self) -> float:
        """When the tyre first leaves the ground (its deflection falls through zero)."""
        return events.crossing(self.t, self.outputs["tyre_deflection"], after=0.0, rising=False)

    def spring_back(self) -> tuple[float, float, float]:
        """The spring-back after the spin-up: the largest forward attachment load after it
        and its time, and the frequency [Hz] of the attachment load's oscillation from its
        zero crossings between the spin-up and the lift-off (or the end)
        (:func:`sliders.app.events.frequency`).  None (all three NaN) where the forward load
        stays below :data:`SPRING_BACK` of the spin-up load: the rigid leg, whose stiffened
        tubes ring with an amplitude that vanishes as their stiffness grows
        (``docs/landing_gear.md``, "No spring-back in a rigid leg").  The frequency is NaN
        too where there are fewer than three crossings."""
        start, stop = self.spin_up_time(), self.lift_off_time()
        if math.isnan(start):
            return math.nan, math.nan, math.nan
        stop = self.t[-1] if math.isnan(stop) else stop
        forward, when = self.peak("attachment_longitudinal", +1.0, start)
        spin_up, _ = self.peak("attachment_longitudinal", -1.0, stop=start)
        if not forward > SPRING_BACK * abs(spin_up):
            return math.nan, math.nan, math.nan
        y = self.outputs["attachment_longitudinal"]
        return forward, when, events.frequency(self.t, y, start, stop)

    def summary(self) -> dict[str, float | str]:
        """Peaks with their times (:data:`PEAKS`; and the largest backward attachment and
        ground loads up to the spin-up, ``*_spin_up``), spin-up and lift-off times, the
        spring-back (:meth:`spring_back`), the peak bearing friction in the dynamics
        (``friction_dynamic``: zero without friction on the sliders) and its time, the
        friction fractions (peak friction over peak vertical load: post-processed and in the
        dynamics), the Newton iterations and the run time."""
        out: dict[str, float | str] = {"model": self.model, "slider": self.slider}
        for name in PEAKS:
            out[name], out[f"{name}_time"] = self.peak(name)
        spin_up = self.spin_up_time()
        for name in ("attachment_longitudinal", "ground_longitudinal"):
            key = f"{name}_spin_up"
            out[key], out[f"{key}_time"] = self.peak(name, -1.0, stop=spin_up)
        vertical = float(out["ground_vertical"])
        out["friction_dynamic"], out["friction_dynamic_time"] = self.peak("friction")
        out["friction_post_fraction"] = float(out["friction_post"]) / vertical
        out["friction_dynamic_fraction"] = float(out["friction_dynamic"]) / vertical
        out["spin_up_time"] = spin_up
        out["lift_off_time"] = self.lift_off_time()
        forward, when, frequency = self.spring_back()
        out["spring_back"], out["spring_back_time"] = forward, when
        out["spring_back_frequency"] = frequency
        strut = self.outputs["strut_stroke"], self.outputs["strut_force"]
        out |= events.stop_reached("bottoming", self.t, *strut, self.strut, "compression")
        out["steps"] = float(len(self.t) - 1)
        out["iterations"] = float(np.mean(self.iterations[1:])) if len(self.t) > 1 else 0.0
        out["seconds"] = self.seconds
        return out
