"""Rigid C1 lines a body can slide on: straight line, circular arc, helix, cubic spline.

Every line is parametrised by an abscissa ``xi`` in ``[0, length]`` and gives, at ``xi``
(paper Sec. 3):

* ``x``: the point; ``l = x_/xi``: the (un-normalised) direction; ``l_xi``: the line's
  curvature vector ``l_/xi`` of eq. (4); ``l_xixi``: its derivative (for Newton's Jacobian);
* ``R = [t, e2, e3]``: the line's frame for the spline slider (Sec. 3.3), built from the
  tangent and a reference vector ``up`` (``e3`` is ``up`` made orthogonal to ``t``);
* ``k = ax(R_/xi R^T)``: the frame's curvature vector (Sec. 4), and ``k_xi``, its derivative.

Straight lines, arcs and helices are parametrised by arc length (``|l| = 1``); a cubic spline
by the cumulative chord length of its points (``|l|`` close to, not exactly, 1).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import (
    check_up,
    closest_to_up,
    cross,
    direction,
    locate_abscissa,
    norm,
    number,
    section_frames,
    vector3,
)
from sliders.lines.rigid_kernel import HELICAL, POLYNOMIAL


@dataclass(frozen=True)
class LinePoint:
    """Geometry of a line at one abscissa (all global axes)."""

    xi: float
    x: np.ndarray
    l: np.ndarray
    l_xi: np.ndarray
    l_xixi: np.ndarray
    R: np.ndarray
    k: np.ndarray
    k_xi: np.ndarray


def axial(A: np.ndarray) -> np.ndarray:
    """``ax(A)``: the vector of the skew-symmetric part of 3x3 matrices ``(..., 3, 3)``."""
    return 0.5 * np.stack(
        [A[..., 2, 1] - A[..., 1, 2], A[..., 0, 2] - A[..., 2, 0], A[..., 1, 0] - A[..., 0, 1]],
        axis=-1,
    )


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a . b`` over the last axis, kept as a length-1 axis for broadcasting."""
    return np.sum(a * b, axis=-1, keepdims=True)


def frame_and_curvature(
    l: np.ndarray, l_xi: np.ndarray, up: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Frame ``R = [t, e2, e3]`` from the direction and ``up``, and ``k = ax(R_/xi R^T)``.

    With ``t = l / |l|`` and ``n = up - (up . t) t``, ``e3 = n / |n|``, ``e2 = e3 x t``;
    the derivatives follow by the chain rule from ``l_xi``.  Vectors of shape ``(..., 3)``
    (``up`` broadcast); returns ``(..., 3, 3)`` and ``(..., 3)``.
    """
    R = section_frames(l, up)
    t, e3 = R[..., 0], R[..., 2]
    norm_l = np.linalg.norm(l, axis=-1, keepdims=True)
    t_xi = (l_xi - _dot(t, l_xi) * t) / norm_l
    n = up - _dot(up, t) * t
    norm_n = np.linalg.norm(n, axis=-1, keepdims=True)
    n_xi = -_dot(up, t_xi) * t - _dot(up, t) * t_xi
    e3_xi = (n_xi - _dot(e3, n_xi) * e3) / norm_n
    e2_xi = cross(e3_xi, t) + cross(e3, t_xi)
    R_xi = np.stack([t_xi, e2_xi, e3_xi], axis=-1)
    return R, axial(R_xi @ np.swapaxes(R, -1, -2))


def curvature_rate(
    l: np.ndarray, l_xi: np.ndarray, l_xixi: np.ndarray, up: np.ndarray
) -> np.ndarray:
    """``k_/xi``, the derivative of the frame's curvature vector (vectors ``(..., 3)``).

    A central difference of :func:`frame_and_curvature` over ``xi +- d``, the direction and its
    derivative carried there by their Taylor expansions (``l_xixi`` taken constant), with
    ``d = 1e-4 / |l_xi|`` (a hundredth of a per cent of the radius of curvature): the
    error is ``d^2 k''' / 6``, about 1e-9 of ``|k|``.  Zero on straight parts.
    """
    scale = np.linalg.norm(l_xi, axis=-1, keepdims=True)
    curved = scale > 1e-12 * np.linalg.norm(l, axis=-1, keepdims=True)
    if not np.any(curved):
        return np.zeros(np.broadcast_shapes(l.shape, l_xi.shape))
    d = 1e-4 / np.where(curved, scale, 1.0)
    ahead = frame_and_curvature(l + d * l_xi + 0.5 * d * d * l_xixi, l_xi + d * l_xixi, up)[1]
    behind = frame_and_curvature(l - d * l_xi + 0.5 * d * d * l_xixi, l_xi - d * l_xixi, up)[1]
    return np.where(curved, (ahead - behind) / (2 * d), 0.0)


def project(
    curve: Callable[[np.ndarray], tuple[np.ndarray, ...]],
    grid: np.ndarray,
    points: np.ndarray,
    sampled: np.ndarray | None = None,
) -> np.ndarray:
    """Abscissae of the points of ``B`` curves closest to ``points`` ``(B, 3)``, one each.

    ``curve(xi)`` returns ``x, l, l_xi`` ``(B, 3)`` of the curves at abscissae ``xi``
    ``(B,)``.  The closest of the sample abscissae ``grid`` (increasing, from 0 to the length)
    starts Newton on ``l . (x - point) = 0``, which stays within the ends.  ``sampled``: the
    curves' points at the grid, ``(B, len(grid), 3)``, when the caller has them at once
    (else ``curve`` is asked grid point by grid point).
    """
    points = np.asarray(points, dtype=float)
    length = grid[-1]
    if sampled is None:
        sampled = np.stack([curve(np.full(len(points), s))[0] for s in grid], axis=1)
    xi = grid[np.argmin(np.sum((sampled - points[:, None]) ** 2, axis=2), axis=1)]
    for _ in range(50):
        x, l, l_xi = curve(xi)
        gap = x - points
        h = np.sum(l * l + l_xi * gap, axis=1)
        step = np.where(h > 0, -np.sum(l * gap, axis=1) / np.where(h > 0, h, 1.0), 0.0)
        xi = np.clip(xi + step, 0.0, length)
        if np.all(np.abs(step) <= 1e-14 * max(length, 1.0)):
            break
    return xi


def project_one(
    curve: Callable[[float], tuple[np.ndarray, ...]], grid: np.ndarray, point: np.ndarray
) -> float:
    """:func:`project` for one curve given point by point: ``curve(xi)`` returns ``x, l, l_xi``
    (3,) at a scalar ``xi``."""

    def batched(xi: np.ndarray) -> tuple[np.ndarray, ...]:
        return tuple(v[None] for v in curve(float(xi[0])))

    return float(project(batched, grid, np.asarray(point, dtype=float)[None])[0])


class RigidLine:
    """Base of the rigid lines: subclasses give ``length`` and the derivatives of ``x``."""

    length: float
    up: np.ndarray
    name: str

    def derivatives(self, xi: float) -> tuple[np.ndarray, ...]:
        """``x, x', x'', x'''`` at ``xi``."""
        raise NotImplementedError

    def check_xi(self, xi: float) -> float:
        """``xi`` clipped to the line; ``ValueError`` beyond its ends."""
        _, offset = locate_abscissa(float(xi), np.array([0.0, self.length]), self.name, "the line")
        return float(offset)

    def at(self, xi: float) -> LinePoint:
        """Geometry at abscissa ``xi`` (``ValueError`` outside ``[0, length]``)."""
        xi = self.check_xi(xi)
        x, l, l_xi, l_xixi = self.derivatives(xi)
        R, k = frame_and_curvature(l, l_xi, self.up)
        return LinePoint(xi, x, l, l_xi, l_xixi, R, k, curvature_rate(l, l_xi, l_xixi, self.up))

    def project(self, point: np.ndarray) -> float:
        """Abscissa of the point of the line closest to ``point`` (initial ``xi``)."""
        return project_one(
            lambda xi: self.derivatives(xi)[:3], np.linspace(0, self.length, 65), point
        )

    def compiled(self) -> tuple[int, np.ndarray, np.ndarray]:
        """The line as :func:`sliders.lines.rigid_kernel.line_at` takes it: its shape
        (``POLYNOMIAL`` or ``HELICAL``), parameters and piece breaks."""
        raise NotImplementedError


class StraightLine(RigidLine):
    """Segment from ``start`` to ``end``, arc-length parametrised."""

    def __init__(
        self,
        start: ArrayLike,
        end: ArrayLike,
        up: ArrayLike = (0.0, 0.0, 1.0),
        name: str = "straight line",
    ) -> None:
        self.name = name
        self.start = vector3(start, f"{name}: start")
        d = vector3(end, f"{name}: end") - self.start
        self.length = number(float(norm(d)), f"{name}: length", "> 0")
        self.t = d / self.length
        self.up = vector3(up, f"{name}: up")
        check_up(direction(up, f"{name}: up"), self.t[None], np.zeros(1), name)

    def derivatives(self, xi: float) -> tuple[np.ndarray, ...]:
        zero = np.zeros(3)
        return self.start + xi * self.t, self.t.copy(), zero, zero

    def compiled(self) -> tuple[int, np.ndarray, np.ndarray]:
        params = np.concatenate([np.zeros(6), self.t, self.start])
        return POLYNOMIAL, params, np.array([0.0, self.length])


class CircularArc(RigidLine):
    """Arc of radius ``radius`` about ``center`` in the plane normal to z, from ``angle0`` to
    ``angle1`` (radians, either direction), arc-length parametrised."""

    def __init__(
        self,
        center: ArrayLike,
        radius: float,
        angle0: float,
        angle1: float,
        name: str = "circular arc",
    ) -> None:
        self.name = name
        self.center = vector3(center, f"{name}: center")
        self.radius = number(radius, f"{name}: radius", "> 0")
        self.angle0, self.sense = float(angle0), float(np.sign(angle1 - angle0))
        self.length = number(self.radius * abs(angle1 - angle0), f"{name}: angle span", "> 0")
        self.up = np.array([0.0, 0.0, 1.0])

    def derivatives(self, xi: float) -> tuple[np.ndarray, ...]:
        r, w = self.radius, self.sense / self.radius
        a = self.angle0 + w * xi
        c, s = np.cos(a), np.sin(a)
        return (
            self.center + r * np.array([c, s, 0.0]),
            r * w * np.array([-s, c, 0.0]),
            r * w**2 * np.array([-c, -s, 0.0]),
            r * w**3 * np.array([s, -c, 0.0]),
        )

    def compiled(self) -> tuple[int, np.ndarray, np.ndarray]:
        params = [*self.center, self.radius, 0.0, self.angle0, self.sense / self.radius]
        return HELICAL, np.array(params), np.zeros(0)


class Helix(RigidLine):
    """Helix about the z axis through ``center``: radius, rise per turn ``pitch``, ``turns``
    turns, arc-length parametrised."""

    def __init__(
        self, center: ArrayLike, radius: float, pitch: float, turns: float, name: str = "helix"
    ) -> None:
        self.name = name
        self.center = vector3(center, f"{name}: center")
        self.radius = number(radius, f"{name}: radius", "> 0")
        self.rise = float(pitch) / (2 * np.pi)
        if not np.isfinite(self.rise):
            raise ValueError(f"{name}: pitch must be finite, got {pitch}")
        speed = np.hypot(self.radius, self.rise)
        self.length = number(2 * np.pi * float(turns) * speed, f"{name}: turns", "> 0")
        self.w = 1.0 / speed
        self.up = np.array([0.0, 0.0, 1.0])

    def derivatives(self, xi: float) -> tuple[np.ndarray, ...]:
        r, h, w = self.radius, self.rise, self.w
        a = w * xi
        c, s = np.cos(a), np.sin(a)
        return (
            self.center + np.array([r * c, r * s, h * a]),
            w * np.array([-r * s, r * c, h]),
            w**2 * np.array([-r * c, -r * s, 0.0]),
            w**3 * np.array([r * s, -r * c, 0.0]),
        )

    def compiled(self) -> tuple[int, np.ndarray, np.ndarray]:
        params = [*self.center, self.radius, self.rise, 0.0, self.w]
        return HELICAL, np.array(params), np.zeros(0)


class CubicSpline(RigidLine):
    """C2 cubic spline through ``points`` (natural end conditions), parametrised by the
    cumulative chord length."""

    def __init__(
        self, points: ArrayLike, up: ArrayLike = (0.0, 0.0, 1.0), name: str = "cubic spline"
    ) -> None:
        self.name = name
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 3 or not np.all(np.isfinite(pts)):
            raise ValueError(f"{name}: points must be at least 3 finite 3-D points")
        chords = norm(np.diff(pts, axis=0))
        if np.any(chords <= 0):
            raise ValueError(
                f"{name}: points {int(np.argmin(chords))} and {int(np.argmin(chords)) + 1} coincide"
            )
        u = np.concatenate([[0.0], np.cumsum(chords)])
        from scipy.interpolate import CubicSpline as Spline  # imported by splines only

        self.spline = Spline(u, pts, bc_type="natural")
        self.length = float(u[-1])
        self.up = vector3(up, f"{name}: up")
        unit, tangent = direction(up, f"{name}: up"), self.spline.derivative()
        xi = closest_to_up(tangent.c, tangent.x, unit)
        check_up(unit, tangent(xi), xi, name)

    def derivatives(self, xi: float) -> tuple[np.ndarray, ...]:
        return tuple(self.spline(xi, nu) for nu in range(4))

    def compiled(self) -> tuple[int, np.ndarray, np.ndarray]:
        coefficients = np.moveaxis(self.spline.c, 0, 1)  # (pieces, 4, 3)
        return POLYNOMIAL, np.ascontiguousarray(coefficients).ravel(), self.spline.x.copy()
