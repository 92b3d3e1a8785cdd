"""Derived results of a dynamic study: attachment loads, slider forces, peaks, events.

Per step (``history.csv`` columns, computed only when a scene asks for them):

* a slider's ``force`` (the magnitude of its reaction ``lambda``, or of its components on
  chosen global ``axes``), ``friction`` (the bearing friction along its line in the dynamics,
  :meth:`sliders.joints.packed.JointPack.frictions`; zero without friction) and ``couple``
  (the magnitude of its orientation multipliers): :func:`slider_probe`;
* a body's attachment load (:func:`load_probe`): the force and moment the rest of the model
  exerts on it, from its equations of motion, ``M_b (qdd - g) - f_b`` on its six dofs, ``M_b``
  the body's own mass matrix (:meth:`fvbeam.body.RigidBody.mass_matrix`) and ``f_b`` the loads
  applied at its node; on a free dof nothing else acts on the body.

After the run, from the ``history.csv`` columns (:func:`summary`, written as ``summary.csv``
by :func:`write_summary`):

* events: a force element's first ``contact`` (a tyre's deflection becoming positive), a
  tyre's ``lift_off`` (its deflection falling through zero after the contact) and
  ``spin_up`` (``omega R0`` reaching ``fraction`` of the axle's forward speed, while that
  speed is above the tyre's ``speed_eps``: :func:`spin_up`), an axial
  force's ``stop`` (its stroke beyond ``stroke_max``, or below ``stroke_min``): the first time,
  the largest penetration and its time, and the force then.  An event that does not happen
  has no time (NaN, an empty cell);
* peaks (:func:`peak`) of a column, or of the sum of several columns' magnitudes, in a window
  of times or events, with their times and the values of other columns then;
* frequencies (:func:`frequency`) of a column's oscillation from its zero crossings.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from fvbeam.structure import Structure
from sliders.app.errors import Problems
from sliders.app.schema import EventSpec, Output
from sliders.forces.elements import AxialForce, ForceElement, Tyre
from sliders.forces.laws import Strut
from sliders.joints.packed import JointPack

if TYPE_CHECKING:
    from sliders.app.probes import Probe
    from sliders.solve.dynamics import Dynamics
    from sliders.solve.integrator import State

#: A body's load components, in the order of its dofs.
COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: What a slider reports per step (:func:`slider_probe`).
SLIDER_VALUES = ("force", "friction", "couple")
#: The force element outputs each kind of event reads (``FORCE.VALUE`` columns).
EVENT_READS = {
    "contact": ("deflection",),
    "lift_off": ("deflection",),
    "spin_up": ("spin", "forward_speed"),
    "stop": ("stroke", "force"),
}
#: The element class each kind of event needs.
EVENT_ELEMENT = {"contact": Tyre, "lift_off": Tyre, "spin_up": Tyre, "stop": AxialForce}
SIGNS = {"magnitude": 0.0, "positive": 1.0, "negative": -1.0}


# -- time series ---------------------------------------------------------------------------
def peak(
    t: np.ndarray,
    y: np.ndarray,
    sign: float = 0.0,
    start: float = -math.inf,
    stop: float = math.inf,
) -> tuple[float, float]:
    """The largest magnitude of ``y`` (signed; with ``sign`` +1 or -1 the largest value of
    that sign) at the times ``t`` between ``start`` and ``stop``, and its time: the largest
    sample, refined by the parabola through it and its two neighbours (the peak of a smooth
    signal sampled at step ``h`` is then found to ``O(h^3)`` in value).  NaN where the window
    holds no sample.

    >>> t = np.linspace(0.0, 1.0, 11)
    >>> value, when = peak(t, 1 - (t - 0.53) ** 2)
    >>> round(value, 12), round(when, 12)
    (1.0, 0.53)
    """
    inside = (t >= start) & (t <= stop)
    if not inside.any():
        return math.nan, math.nan
    size = np.abs(y) if sign == 0 else sign * y
    i = int(np.argmax(np.where(inside, size, -np.inf)))
    if 0 < i < len(y) - 1:
        a, b, c = y[i - 1], y[i], y[i + 1]
        curvature = a - 2 * b + c
        if curvature != 0:
            shift = 0.5 * (a - c) / curvature
            if abs(shift) <= 1:
                h = 0.5 * (t[i + 1] - t[i - 1])
                return float(b - 0.25 * (a - c) * shift), float(t[i] + shift * h)
    return float(y[i]), float(t[i])


def crossing(t: np.ndarray, y: np.ndarray, after: float = -math.inf, rising: bool = True) -> float:
    """The first time after ``after`` at which ``y`` crosses zero (upward if ``rising``),
    interpolated linearly between the samples; NaN if it does not.

    >>> crossing(np.array([0.0, 1.0, 2.0]), np.array([-1.0, -1.0, 3.0]))
    1.25
    """
    s = y if rising else -y
    mask = (s[:-1] < 0) & (s[1:] >= 0) & (t[1:] > after)
    if not mask.any():
        return math.nan
    i = int(np.argmax(mask))
    return float(t[i] + (t[i + 1] - t[i]) * (-s[i]) / (s[i + 1] - s[i]))


def spin_up(
    t: np.ndarray,
    spin: np.ndarray,
    forward_speed: np.ndarray,
    radius: float,
    fraction: float,
    speed_eps: float,
) -> float:
    """The first time a wheel's rim speed ``omega R0`` reaches ``fraction`` of its axle's
    forward speed ``u`` (:func:`crossing` of ``omega R0 - fraction u``, upward), counted
    only between two samples at which the axle rolls forward faster than the tyre's
    ``speed_eps``; NaN if it does not.

    The rule reads the slip ``(u - omega R0) / u`` falling to ``1 - fraction``.  The tyre's
    slip law is ``(u - omega R0) / sqrt(u^2 + speed_eps^2)``
    (:func:`sliders.forces.laws.slip_ratio`): the plain slip for ``u >> speed_eps``, within
    a factor ``sqrt(2)`` of it at ``u = speed_eps``, and ``u / speed_eps`` times it below,
    where the tyre sees no slip to spin the wheel up against.  So the speed ``speed_eps`` is
    the scale of the rule: below it there is no spin-up, and a forward speed that is
    round-off (a drop at 0 m/s, whose ``u`` and ``omega`` are zero to round-off) is below it
    by many orders and fires none.

    >>> t = np.array([0.0, 1.0, 2.0])
    >>> spin_up(t, np.array([0.0, 6.0, 10.0]), np.full(3, 4.0), 0.5, 1.0, 0.1)
    1.5
    >>> spin_up(t, np.array([0.0, 6e-20, 10e-20]), np.full(3, 4e-20), 0.5, 1.0, 0.1)
    nan
    """
    speed = spin * radius - fraction * forward_speed
    return crossing(t, np.where(forward_speed > speed_eps, speed, np.nan))


def first_above(t: np.ndarray, y: np.ndarray) -> float:
    """The first time ``y`` is positive: ``t[0]`` if it is at the start, else where it
    rises through zero (interpolated linearly from the last sample at or below zero); NaN if
    it never is.

    >>> first_above(np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.0, 2.0]))
    1.0
    """
    above = y > 0
    if not above.any():
        return math.nan
    i = int(np.argmax(above))
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (t[i] - t[i - 1]) * (-y[i - 1]) / (y[i] - y[i - 1]))


def frequency(
    t: np.ndarray, y: np.ndarray, start: float = -math.inf, stop: float = math.inf
) -> float:
    """The frequency [Hz] of the oscillation of ``y`` between ``start`` and ``stop`` from its
    ``n`` zero crossings there (interpolated linearly): ``(n - 1) / (2 (t_n - t_1))``; NaN
    for fewer than three.

    >>> t = np.linspace(0.0, 1.0, 1001)
    >>> round(frequency(t, np.sin(2 * np.pi * 5 * t + 0.1)), 6)
    5.0
    """
    s = np.where((t >= start) & (t <= stop), y, np.nan)
    flips = np.flatnonzero(np.sign(s[:-1]) * np.sign(s[1:]) < 0)
    times = t[flips] - s[flips] * (t[flips + 1] - t[flips]) / (s[flips + 1] - s[flips])
    if len(times) < 3:
        return math.nan
    return float((len(times) - 1) / (2 * (times[-1] - times[0])))


# -- per-step columns ----------------------------------------------------------------------
def slider_probe(j: int, n_unknowns: int, value: str, axes: Sequence[str] | None) -> Probe:
    """Slider ``j``'s ``value`` (:data:`SLIDER_VALUES`, module docstring) at a state; with
    ``axes`` (``x``, ``y``, ``z``) the force is the magnitude of those global components of
    its reaction ``lambda``."""
    if value == "force":
        picked = [1 + "xyz".index(a) for a in (axes or "xyz")]

        def force(state: State, dynamics: Dynamics) -> float:
            c = state.unknowns[j][picked]
            return float(np.sqrt(np.add.reduce(c * c)))

        return force
    if value == "couple":

        def couple(state: State, dynamics: Dynamics) -> float:
            c = state.unknowns[j][4:n_unknowns]
            return float(np.sqrt(np.add.reduce(c * c)))

        return couple
    packs: dict[int, JointPack] = {}

    def friction(state: State, dynamics: Dynamics) -> float:
        if not packs:
            packs[0] = JointPack(dynamics.sliders, dynamics.structure)
        y = np.concatenate(state.unknowns)
        return float(packs[0].frictions(state.q, state.v, y)[0, j])

    return friction


def load_probe(
    structure: Structure, body: str, component: str, gravity: Sequence[float] | None
) -> Probe:
    """Component ``component`` (:data:`COMPONENTS`) of the load the rest of the model exerts
    on rigid body ``body`` (module docstring), ``gravity`` the study's."""
    names = [b.name for b in structure.bodies]
    row = structure.bodies[names.index(body)].mass_matrix()[COMPONENTS.index(component)]
    dofs = structure.node_dofs(body)
    dof = int(dofs[COMPONENTS.index(component)])
    g = np.concatenate([np.zeros(3) if gravity is None else np.asarray(gravity), np.zeros(3)])

    def load(state: State, dynamics: Dynamics) -> float:
        applied = dynamics.load(state.t)[dof] - dynamics.f_gravity[dof]
        return float(row @ (state.qdd[dofs] - g) - applied)

    return load


def event_columns(spec: EventSpec) -> list[tuple[str, str]]:
    """The ``history.csv`` columns an event reads, as ``(column, element output)``."""
    return [(f"{spec.force}.{value}", value) for value in EVENT_READS[spec.kind]]


# -- after the run -------------------------------------------------------------------------
def _instant(at: str | float | None, events: Mapping[str, float], default: float) -> float:
    """A window's end: ``default`` if not given, an event's time, or a time."""
    if at is None:
        return default
    return events[at] if isinstance(at, str) else float(at)


def _event(
    spec: EventSpec, element: ForceElement, t: np.ndarray, table: Mapping[str, np.ndarray]
) -> dict[str, float]:
    """An event's columns (module docstring)."""
    read = {value: table[column] for column, value in event_columns(spec)}
    name = spec.name
    if spec.kind == "contact":
        return {name: first_above(t, read["deflection"])}
    if spec.kind == "lift_off":
        contact = first_above(t, read["deflection"])
        return {name: crossing(t, read["deflection"], after=contact, rising=False)}
    if spec.kind == "spin_up":
        assert isinstance(element, Tyre)
        return {
            name: spin_up(
                t,
                read["spin"],
                read["forward_speed"],
                element.radius,
                spec.fraction,
                element.speed_eps,
            )
        }
    assert isinstance(element, AxialForce)
    return stop_reached(name, t, read["stroke"], read["force"], element.law, spec.stop)


def stop_reached(
    name: str, t: np.ndarray, stroke: np.ndarray, force: np.ndarray, law: Strut, stop: str
) -> dict[str, float]:
    """A strut's ``stop`` (``compression``: its stroke beyond ``stroke_max``; ``extension``:
    below ``stroke_min``): ``name``, the first time it is reached; ``name_penetration``, the
    largest penetration (:func:`peak`; zero if never reached) and ``name_penetration_time``
    its time; ``name_force``, the strut's force then.  The times are NaN if it is never
    reached."""
    beyond = stroke - law.stroke_max if stop == "compression" else law.stroke_min - stroke
    first = first_above(t, beyond)
    if math.isnan(first):
        return {
            name: math.nan,
            f"{name}_penetration": 0.0,
            f"{name}_penetration_time": math.nan,
            f"{name}_force": math.nan,
        }
    depth, when = peak(t, beyond, +1.0)
    return {
        name: first,
        f"{name}_penetration": depth,
        f"{name}_penetration_time": when,
        f"{name}_force": float(np.interp(when, t, force)),
    }


def _series(of: str | Sequence[str], table: Mapping[str, np.ndarray]) -> np.ndarray:
    """A column, or the sum of the magnitudes of several."""
    if isinstance(of, str):
        return table[of]
    total = np.abs(table[of[0]])
    for column in of[1:]:
        total = total + np.abs(table[column])
    return total


def summary(
    output: Output, forces: Sequence[ForceElement], table: Mapping[str, np.ndarray]
) -> dict[str, float]:
    """The events, peaks and frequencies ``output`` asks for, from the ``history.csv``
    columns ``table`` (module docstring): each event's time (and a stop's penetration, its
    time and the force then), each peak ``NAME`` with ``NAME_time``, ``NAME.COLUMN`` of its
    concurrent columns and ``NAME_fraction`` of the peak it is ``per``, each frequency."""
    t = table["t"]
    elements = {e.name: e for e in forces}
    out: dict[str, float] = {}
    events: dict[str, float] = {}
    for spec in output.event:
        values = _event(spec, elements[spec.force], t, table)
        events[spec.name] = values[spec.name]
        out.update(values)
    peaks: dict[str, float] = {}
    for p in output.peak:
        y = _series(p.of, table)
        if p.scale != 1.0 or p.offset != 0.0:
            y = p.offset + p.scale * y
        start, stop = _instant(p.after, events, -math.inf), _instant(p.before, events, math.inf)
        value, when = peak(t, y, SIGNS[p.sign], start, stop)
        peaks[p.name] = out[p.name] = value
        out[f"{p.name}_time"] = when
        for column in p.concurrent:
            out[f"{p.name}.{column}"] = (
                math.nan if math.isnan(when) else float(np.interp(when, t, table[column]))
            )
        if p.per is not None:
            out[f"{p.name}_fraction"] = value / peaks[p.per]
    for f in output.frequency:
        start = _instant(f.after, events, -math.inf)
        stop = _instant(f.before, events, math.nan)
        stop = float(t[-1]) if math.isnan(stop) else stop
        out[f.name] = math.nan if math.isnan(start) else frequency(t, table[f.of], start, stop)
    return out


def write_summary(path: Path, values: Mapping[str, float]) -> None:
    """``values`` as a CSV of one header row and one row of numbers (full precision; NaN, an
    event that did not happen, as an empty cell)."""
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(values)
        writer.writerow("" if math.isnan(v) else repr(float(v)) for v in values.values())


def asked(output: Output) -> bool:
    """Whether ``output`` asks for a summary."""
    return bool(output.event or output.peak or output.frequency)


# -- checks --------------------------------------------------------------------------------
def check(
    output: Output,
    forces: Sequence[ForceElement],
    columns: Sequence[str],
    probes: Sequence[str],
    problems: Problems,
) -> None:
    """The names the derived results use, against the model: the events' force elements
    and their kinds, the windows' events, the peaks' and frequencies' columns (``columns``:
    the kept ``history.csv`` columns; ``probes``: the probe columns, loads and event reads
    included), the peaks a peak is ``per``, and every name once."""
    elements = {e.name: e for e in forces}
    names: dict[str, str] = {}
    events: set[str] = set()

    def unique(path: str, name: str) -> None:
        if name in names:
            problems.add(f"{path}.name", f"already the name of {names[name]}", name)
        names.setdefault(name, path)

    for i, spec in enumerate(output.event):
        path = f"output.event[{i}]"
        unique(path, spec.name)
        element = elements.get(spec.force)
        need = EVENT_ELEMENT[spec.kind]
        if element is None:
            problems.add(f"{path}.force", "no force element of that name", spec.force)
        elif not isinstance(element, need):
            problems.add(
                f"{path}.force",
                f"a {spec.kind} event needs a {need.__name__}, "
                f"'{spec.force}' is a {type(element).__name__}",
                spec.force,
            )
        events.add(spec.name)
    known = set(columns) | set(probes)

    def window(path: str, at: str | float | None) -> None:
        if isinstance(at, str) and at not in events:
            problems.add(path, "no [[output.event]] of that name", at)

    def column(path: str, name: str) -> None:
        if name not in known:
            problems.add(path, "not a column of history.csv (output.history, probes)", name)

    peaks: set[str] = set()
    for i, p in enumerate(output.peak):
        path = f"output.peak[{i}]"
        unique(path, p.name)
        for k, name in enumerate([p.of] if isinstance(p.of, str) else p.of):
            column(f"{path}.of" if isinstance(p.of, str) else f"{path}.of[{k}]", name)
        for k, name in enumerate(p.concurrent):
            column(f"{path}.concurrent[{k}]", name)
        window(f"{path}.after", p.after)
        window(f"{path}.before", p.before)
        if p.per is not None and p.per not in peaks:
            problems.add(f"{path}.per", "no [[output.peak]] of that name before this one", p.per)
        peaks.add(p.name)
    for i, f in enumerate(output.frequency):
        path = f"output.frequency[{i}]"
        unique(path, f.name)
        column(f"{path}.of", f.of)
        window(f"{path}.after", f.after)
        window(f"{path}.before", f.before)
