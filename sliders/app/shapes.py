"""The sizes and shapes a picture gives the parts: tube radii, wheels and the ground.

**Tube radii.**  A section built from its shape (:meth:`fvbeam.section.Section.from_shape`)
is drawn with the radius of the smallest circle about its centroid that holds it
(:meth:`fvbeam.shapes.Shape.enclosing_radius`): a tube's or a circle's outer radius, half the
diagonal of a rectangle or of an I-section's bounding rectangle.  A section given by its
stiffness is drawn as the thin-walled circular tube with the section's ratio of bending to
axial stiffness: with mean radius ``R`` and wall ``t``, ``A = 2 pi R t`` and ``J = pi R^3
t``, so ``R = sqrt(2 EJ / EA)`` (``EJ`` the mean of ``EJ2`` and ``EJ3``; the radius of
gyration is ``R / sqrt 2``).  A 54 x 4 mm steel tube (``EA = 1.3e8 N``, ``EJ = 4.1e4 N
m^2``) is drawn with ``R = 25 mm``, its mean radius.  Either radius is kept between
:data:`RADIUS_LIMITS` of the structure's size, so that no beam is invisible or a blob (a
rigid or a thread-like section): there the drawn size is not the section's.  In a
*telescope*, two beams each sliding in the other (a slider on either with its body on the
other: a piston in its cylinder), the inner beam is drawn at most :data:`INNER_FACTOR` of
the outer's radius and the outer one translucent, so the inner one shows through it: the
inner beam is the one with the smaller radius, or, for equal radii, the one declared
second.  The VTU files carry the same radii (:func:`sliders.app.vtu.to_meshio`).

**Rigid lines and force elements.**  A rigid line a slider runs on is drawn as a thin
dark rail, :data:`RAIL_FACTOR` of the largest tube radius, through :data:`LINE_SAMPLES`
points (on an arc or a helix of radius ``R`` and length ``l`` the chords' sag is at most
``R (1 - cos(l / (2 R (LINE_SAMPLES - 1))))``: 7.6e-5 ``R`` for a whole turn).  An axial force
element (a strut, a spring-damper: :class:`sliders.forces.elements.AxialForce`) is drawn as
a coil spring of :data:`COIL_TURNS` turns between its two nodes' drawn points, of radius
:data:`COIL_FACTOR` of the largest tube radius (inside a cylinder drawn around it).

**Wheels and ground.**  A tyre (:class:`sliders.forces.elements.Tyre`) is drawn as a wheel:
a black tyre of its rolling radius and a grey hub of :data:`HUB_FACTOR` of it, centred on
the axle's drawn point, turning about ``normal x forward``, with a white pin through it
that turns with the wheel's spin; and the ground it rolls on as a slab under its plane.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from fvbeam.section import Section
from fvbeam.structure import Structure
from sliders.forces.elements import AxialForce, ForceElement, Tyre
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import RigidLine

#: Smallest and largest drawn tube radius, fractions of the structure's size.
RADIUS_LIMITS = (0.003, 0.04)
#: The inner beam of a telescope: at most this fraction of the outer's radius.
INNER_FACTOR = 0.7
#: The hub's radius and the tyre's and hub's widths, fractions of the rolling radius.
HUB_FACTOR, TYRE_WIDTH, HUB_WIDTH = 0.55, 0.35, 0.45
#: The ground slab's thickness, a fraction of the structure's size.
GROUND_THICKNESS = 0.03
#: The ground's margin around what is drawn, a fraction of the structure's size.
GROUND_MARGIN = 0.25
#: A rigid line's drawn radius, a fraction of the largest tube radius; its points.
RAIL_FACTOR, LINE_SAMPLES = 0.4, 257
#: An axial force element's coil: its turns, its radius (a fraction of the largest tube
#: radius) and its wire's radius (a fraction of the coil's).
COIL_TURNS, COIL_FACTOR, WIRE_FACTOR = 8, 0.6, 0.12


def section_radius(section: Section) -> float:
    """The drawn radius of ``section`` (module docstring): its shape's enclosing radius,
    else ``sqrt(2 EJ / EA)``, the mean radius of the thin-walled circular tube with the
    section's bending to axial stiffness ratio."""
    if section.shape is not None:
        return float(section.shape.enclosing_radius())
    K = section.stiffness
    return float(np.sqrt((K[4, 4] + K[5, 5]) / K[0, 0]))


def telescopes(structure: Structure, sliders: Sequence[Slider]) -> set[tuple[int, int]]:
    """The pairs of beams ``(i, j)``, ``i < j``, each with a slider on it whose body is a
    node of the other."""
    pairs: set[tuple[int, int]] = set()
    for slider in sliders:
        body = structure.resolve_node(slider.body)
        if isinstance(slider.line, BeamChain) and not isinstance(body, str):
            pairs |= {(line, body[0]) for line in slider.line.indices if line != body[0]}
    return {(i, j) for i, j in pairs if i < j and (j, i) in pairs}


@dataclass(frozen=True)
class TubeSizes:
    """Per beam the drawn ``radii`` and whether it is drawn ``translucent`` (the outer beam
    of a telescope); ``marker``, the largest radius (the size of sliders and bodies)."""

    radii: np.ndarray
    translucent: np.ndarray
    marker: float


def tube_sizes(structure: Structure, sliders: Sequence[Slider], size: float) -> TubeSizes:
    """The radii of the module docstring for a structure of size ``size``."""
    low, high = RADIUS_LIMITS
    radii = np.array(
        [np.clip(section_radius(b.section), low * size, high * size) for b in structure.beams]
    )
    translucent = np.zeros(len(radii), dtype=bool)
    for i, j in sorted(telescopes(structure, sliders)):
        outer, inner = (j, i) if radii[j] > radii[i] else (i, j)
        radii[inner] = min(radii[inner], INNER_FACTOR * radii[outer])
        translucent[outer] = True
    return TubeSizes(radii, translucent, float(radii.max()) if len(radii) else low * size)


@dataclass(frozen=True)
class Wheel:
    """A drawn wheel: its ``centre``, its spin ``axis``, the ``forward`` and ``normal`` of
    its ground and a point ``ground`` of it, its rolling ``radius`` and its ``spin`` angle
    (rad, about ``axis``).  Its tyre is drawn cut off at the ground: the flat of a deflected
    tyre."""

    centre: np.ndarray
    axis: np.ndarray
    forward: np.ndarray
    normal: np.ndarray
    ground: np.ndarray
    radius: float
    spin: float

    def mark(self) -> np.ndarray:
        """The point of the spin mark, on the hub's rim: ``forward`` turned by ``spin``
        about ``axis`` (``axis x forward = -normal``)."""
        turned = np.cos(self.spin) * self.forward - np.sin(self.spin) * self.normal
        return self.centre + HUB_FACTOR * self.radius * turned


def tyres(forces: Sequence[ForceElement]) -> list[Tyre]:
    """The tyres among ``forces``."""
    return [f for f in forces if isinstance(f, Tyre)]


def wheel(
    tyre: Tyre, structure: Structure, q: np.ndarray, centre: np.ndarray, shift: np.ndarray
) -> Wheel:
    """The wheel of ``tyre`` at the drawn axle point ``centre`` in the state ``q``, its
    ground moved by ``-shift``."""
    normal, forward = np.asarray(tyre.normal, float), np.asarray(tyre.forward, float)
    axis = np.cross(normal, forward)
    spin = float(q[structure.node_dofs(tyre.wheel)[3:]] @ axis)
    ground = np.asarray(tyre.ground, float) - shift
    return Wheel(centre, axis, forward, normal, ground, float(tyre.radius), spin)


@dataclass(frozen=True)
class Ground:
    """The ground slab under a tyre's plane: its top face's ``centre``, ``normal``,
    ``forward``, the lengths of the face along ``forward`` and across, and its
    ``thickness``."""

    centre: np.ndarray
    normal: np.ndarray
    forward: np.ndarray
    length: float
    width: float
    thickness: float

    def corners(self) -> np.ndarray:
        """The slab's eight corners (8, 3)."""
        across = np.cross(self.normal, self.forward)
        signs = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (0, -1)])
        return (
            self.centre
            + 0.5 * signs[:, :1] * self.length * self.forward
            + 0.5 * signs[:, 1:2] * self.width * across
            + signs[:, 2:] * self.thickness * self.normal
        )


def ground_under(tyre: Tyre, points: np.ndarray, size: float, shift: np.ndarray) -> Ground:
    """The ground of ``tyre`` under the drawn ``points`` (n, 3): its plane moved by
    ``-shift``, spanning their extent along ``forward`` and across, with a margin of
    :data:`GROUND_MARGIN` of ``size`` on every side."""
    normal, forward = np.asarray(tyre.normal, float), np.asarray(tyre.forward, float)
    across = np.cross(normal, forward)
    origin = np.asarray(tyre.ground, float) - shift
    along, side = (points - origin) @ forward, (points - origin) @ across
    margin = GROUND_MARGIN * size
    centre = (
        origin
        + 0.5 * (along.min() + along.max()) * forward
        + 0.5 * (side.min() + side.max()) * across
    )
    return Ground(
        centre,
        normal,
        forward,
        float(np.ptp(along)) + 2 * margin,
        float(np.ptp(side)) + 2 * margin,
        GROUND_THICKNESS * size,
    )


def rigid_lines(sliders: Sequence[Slider]) -> list[RigidLine]:
    """The rigid lines the ``sliders`` run on, each once, in the sliders' order."""
    lines: dict[int, RigidLine] = {}
    for slider in sliders:
        if isinstance(slider.line, RigidLine):
            lines.setdefault(id(slider.line), slider.line)
    return list(lines.values())


def line_points(line: RigidLine) -> np.ndarray:
    """:data:`LINE_SAMPLES` points (n, 3) along ``line``, its ends among them."""
    xi = np.linspace(0.0, line.length, LINE_SAMPLES)
    return np.array([line.derivatives(x)[0] for x in xi])


def axial_forces(forces: Sequence[ForceElement]) -> list[AxialForce]:
    """The axial force elements (struts, spring-dampers) among ``forces``."""
    return [f for f in forces if isinstance(f, AxialForce)]


def coil(a: np.ndarray, b: np.ndarray, radius: float, samples_per_turn: int = 24) -> np.ndarray:
    """The points (n, 3) of a coil spring of :data:`COIL_TURNS` turns and ``radius`` from
    ``a`` to ``b``: straight from ``a`` to the first turn and from the last to ``b``."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    axis = b - a
    length = float(np.linalg.norm(axis))
    if length == 0.0:
        return np.vstack([a, b])
    t = axis / length
    other = np.eye(3)[int(np.argmin(np.abs(t)))]
    e1 = np.cross(t, other)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(t, e1)
    phase = np.linspace(0.0, 2 * np.pi * COIL_TURNS, COIL_TURNS * samples_per_turn + 1)
    along = 0.1 + 0.8 * phase / phase[-1]
    turns = (
        a
        + np.outer(along * length, t)
        + radius * (np.outer(np.cos(phase), e1) + np.outer(np.sin(phase), e2))
    )
    return np.vstack([a, a + 0.1 * axis, turns, b - 0.1 * axis, b])
