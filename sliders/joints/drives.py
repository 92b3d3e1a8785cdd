"""Drives: prescribed motions against time.

A *motion* is a scalar function of time with its first two derivatives,
``motion(t) -> (value, rate, acceleration)``.  Three kinds:

``Linear``
    ``start + velocity (t - t0)``: constant speed (a body pushed along a beam).
``Ramp``
    from ``start`` to ``end`` between ``t0`` and ``t1``, constant outside.  ``shape="linear"``
    has a velocity jump at both ends; ``shape="cosine"`` (``(1 - cos)/2``) starts and stops
    with zero velocity.
``Tabulated``
    through ``(times, values)``: piecewise linear (``order=1``) or a not-a-knot cubic spline
    (``order=3``, :class:`scipy.interpolate.CubicSpline`), constant outside the table.

A motion drives one of two things (:class:`sliders.solve.dynamics.Dynamics`):

* a slider's abscissa (:attr:`sliders.joints.slider.Slider.drive`): the frictionless ``xi`` equation
  ``l . lambda = 0`` becomes ``xi - xi_d(t) = 0``, and ``l . lambda`` is the force that
  pushes the sliding point along the line;
* a structure dof (:class:`DofDrive`): the dof is prescribed like a support with a moving
  value, and its reaction is the driving force.

A motion that leaves a state at rest with a nonzero rate (:func:`initial_rate`: a ``Linear``
motion, a linear ramp or a table that starts moving at once) jumps what it drives to that
speed in the first step: with a mass there, an impulse and kinetic energy from nowhere
(:meth:`sliders.solve.dynamics.Dynamics.velocity_jumps`).  A cosine ramp starts at rest.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np

from fvbeam.names import NodeRef, parse_node
from fvbeam.support import DOF_NAMES

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline


class Motion(Protocol):
    """A prescribed scalar motion."""

    def __call__(self, t: float) -> tuple[float, float, float]:
        """Value, rate and acceleration at time ``t``."""


def _finite(value: float, name: str) -> float:
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value}")
    return value


@dataclass(frozen=True)
class Linear:
    """``start + velocity (t - t0)``."""

    start: float
    velocity: float
    t0: float = 0.0

    def __post_init__(self) -> None:
        for key in ("start", "velocity", "t0"):
            object.__setattr__(self, key, _finite(getattr(self, key), f"linear drive: {key}"))

    def __call__(self, t: float) -> tuple[float, float, float]:
        return self.start + self.velocity * (t - self.t0), self.velocity, 0.0

    def turning_times(self, t0: float, t1: float) -> np.ndarray:
        """The times in ``[t0, t1]`` at which the value may be least or greatest there: the
        ends (the motion is monotone)."""
        return np.array([t0, t1], dtype=float)

    def rate_after(self, t: float) -> float:
        """The rate just after ``t``: the velocity, at every time."""
        return self.velocity


@dataclass(frozen=True)
class Ramp:
    """From ``start`` (until ``t0``) to ``end`` (from ``t1``), ``linear`` or ``cosine``."""

    start: float
    end: float
    t0: float
    t1: float
    shape: str = "cosine"

    def __post_init__(self) -> None:
        for key in ("start", "end", "t0", "t1"):
            object.__setattr__(self, key, _finite(getattr(self, key), f"ramp drive: {key}"))
        if not self.t1 > self.t0:
            raise ValueError(f"ramp drive: t1 must be after t0, got t0={self.t0}, t1={self.t1}")
        if self.shape not in ("linear", "cosine"):
            raise ValueError(f"ramp drive: shape must be 'linear' or 'cosine', got {self.shape!r}")

    def __call__(self, t: float) -> tuple[float, float, float]:
        span, rise = self.t1 - self.t0, self.end - self.start
        if t <= self.t0 or t >= self.t1:
            return (self.start if t <= self.t0 else self.end), 0.0, 0.0
        s = (t - self.t0) / span
        if self.shape == "linear":
            return self.start + rise * s, rise / span, 0.0
        w = np.pi / span
        return (
            self.start + rise * (1 - np.cos(np.pi * s)) / 2,
            rise * w * np.sin(np.pi * s) / 2,
            rise * w * w * np.cos(np.pi * s) / 2,
        )

    def turning_times(self, t0: float, t1: float) -> np.ndarray:
        """The times in ``[t0, t1]`` at which the value may be least or greatest there: the
        ends (either shape is monotone)."""
        return np.array([t0, t1], dtype=float)

    def rate_after(self, t: float) -> float:
        """The rate just after ``t``: from ``t0`` the linear ramp's ``(end - start) / (t1 -
        t0)``, the cosine ramp's rate (zero at ``t0``)."""
        if not self.t0 <= t < self.t1:
            return 0.0
        if self.shape == "linear":
            return (self.end - self.start) / (self.t1 - self.t0)
        return self(t)[1]


@dataclass(frozen=True, eq=False)
class Tabulated:
    """Through the points ``(times, values)``; ``order`` 1 (linear) or 3 (cubic spline)."""

    times: np.ndarray
    values: np.ndarray
    order: int = 1
    _spline: CubicSpline | None = field(init=False, repr=False, default=None)

    def __post_init__(self) -> None:
        times = np.asarray(self.times, dtype=float)
        values = np.asarray(self.values, dtype=float)
        if times.ndim != 1 or times.shape != values.shape or len(times) < 2:
            raise ValueError(
                "tabulated drive: times and values must be 1-D of one length >= 2, "
                f"got shapes {times.shape} and {values.shape}"
            )
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(values))):
            raise ValueError("tabulated drive: times and values must be finite")
        if np.any(np.diff(times) <= 0):
            raise ValueError("tabulated drive: times must increase strictly")
        if self.order not in (1, 3):
            raise ValueError(f"tabulated drive: order must be 1 or 3, got {self.order!r}")
        if self.order == 3 and len(times) < 4:
            raise ValueError("tabulated drive: a cubic table needs at least 4 points")
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "values", values)
        if self.order == 3:
            from scipy.interpolate import CubicSpline  # imported by cubic tables only

            object.__setattr__(self, "_spline", CubicSpline(times, values))

    def __call__(self, t: float) -> tuple[float, float, float]:
        times, values = self.times, self.values
        if t <= times[0] or t >= times[-1]:
            return float(values[0] if t <= times[0] else values[-1]), 0.0, 0.0
        if self._spline is not None:
            spline = self._spline
            return float(spline(t, 0)), float(spline(t, 1)), float(spline(t, 2))
        k = int(np.searchsorted(times, t, side="right")) - 1
        rate = (values[k + 1] - values[k]) / (times[k + 1] - times[k])
        return float(values[k] + rate * (t - times[k])), float(rate), 0.0

    def turning_times(self, t0: float, t1: float) -> np.ndarray:
        """The times in ``[t0, t1]`` at which the value may be least or greatest there: the
        ends, the table's times, and where the cubic spline's rate vanishes."""
        inside = list(self.times)
        if self._spline is not None:
            inside += list(self._spline.derivative().roots(extrapolate=False))
        return np.array([t0, t1] + [t for t in inside if t0 < t < t1], dtype=float)

    def rate_after(self, t: float) -> float:
        """The rate just after ``t``: at a point of the table, that of the piece it starts
        (the spline's one-sided derivative there); zero from the last time on."""
        times = self.times
        if not times[0] <= t < times[-1]:
            return 0.0
        if self._spline is not None:
            return float(self._spline(t, 1))
        k = int(np.searchsorted(times, t, side="right")) - 1
        return float((self.values[k + 1] - self.values[k]) / (times[k + 1] - times[k]))


def initial_rate(motion: Motion, t: float) -> float:
    """The rate with which ``motion`` leaves ``t``: the right-hand limit of its rate (at the
    first point of a linear ramp or of a table, the rate of the piece that starts there;
    their ``rate_after``); for a motion of another kind, its rate at ``t``."""
    after = getattr(motion, "rate_after", None)
    return float(after(t)) if after is not None else float(motion(t)[1])


@dataclass(frozen=True)
class DofDrive:
    """Prescribe one dof of a structure node (:mod:`fvbeam.names`: ``"C.end"``, a body's
    name, ``(beam, node)``): ``dof`` is one of ``ux uy uz rx ry rz``; its value follows
    ``motion`` (displacement from the reference configuration)."""

    node: NodeRef
    dof: str
    motion: Motion

    def __post_init__(self) -> None:
        parse_node(self.node, "drive")
        if self.dof not in DOF_NAMES:
            raise ValueError(
                f"drive of {self.node!r}: dof must be one of "
                f"{' '.join(DOF_NAMES)}, got {self.dof!r}"
            )
        if not callable(self.motion):
            raise ValueError(f"drive of {self.node!r}.{self.dof}: motion must be callable")
