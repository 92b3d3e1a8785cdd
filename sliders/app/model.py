"""A validated scene as fvbeam and sliders objects, and the problem of each study point.

:class:`Model` builds the sections, beams, bodies, rigid lines, supports and sliders of a
:class:`~sliders.app.schema.Scene` by name, and checks the geometry and the files the scene
names (phase 3 of validation): the mesh files read, the library's own checks on every part,
ties between coincident nodes, point loads on their beams, every slider's body on its line,
in the scene and at every value of a sweep that moves it; a dynamic study's restart state
read and matched to the model, and every abscissa drive on its line from the start to
``t_end``; every rigid motion held (:meth:`Model._check_held`), and no drive of a dynamic
study setting a mass moving at once from the static start
(:meth:`Model._check_velocity_jumps`).  Nothing is assembled or solved until
:meth:`Model.problem` is called.

The body-on-line tolerance is ``1e-6`` of the line's size (the largest of its length and of
the distances from the origin of its ends and of the sliding point): coordinates written with
six significant digits are off by at most ``5e-7`` of their magnitude, so a point meant to be
on the line passes, and a point a millionth of the line away is a mistake, not rounding.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from functools import cached_property, partial
from typing import TYPE_CHECKING

import numpy as np

from fvbeam import Beam, BeamMesh, RigidBody, Section, Structure, Support, arc, straight
from fvbeam.formulations import formulation as get_formulation
from fvbeam.geometry import direction, norm
from fvbeam.mass import acceleration, check_kind, weight
from fvbeam.mechanism import rigid_modes, unresisted
from fvbeam.names import suggest
from fvbeam.shapes import SHAPES, Material
from fvbeam.smearing import check_smearing
from fvbeam.support import DOF_NAMES, complement
from sliders.app import events
from sliders.app.checks import SELECTED, part_of, tied_parts
from sliders.app.columns import history_columns
from sliders.app.errors import Problems
from sliders.app.limits import Limits, element_problems
from sliders.app.probes import (
    VELOCITY_NAMES,
    ElementOutputs,
    Probe,
    element_probe,
    force_probe,
    node_probe,
    velocity_probe,
)
from sliders.app.scene_joints import tied_ends
from sliders.app.schema import (
    Abscissa,
    BeamSpec,
    DofDriveSpec,
    DynamicStudy,
    LoadFactor,
    ModesStudy,
    PointLoad,
    Scene,
    SliderSpec,
    SweepStudy,
    Translation,
)
from sliders.app.state_tables import CHOICES, FORCE_NAMES, KEY_COLUMNS, Selection, items
from sliders.forces.elements import AxialForce, ForceElement, Tyre
from sliders.forces.laws import Strut
from sliders.joints.drives import DofDrive, Linear, Ramp, Tabulated, initial_rate
from sliders.joints.friction import Friction
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import (
    CircularArc,
    CubicSpline,
    Helix,
    RigidLine,
    StraightLine,
    project_one,
)
from sliders.solve.integrator import State
from sliders.solve.jumps import velocity_jumps
from sliders.solve.mechanism import MASSLESS_REMEDY, REMEDY, free_motion, joint_parts
from sliders.solve.planar import PLANES, check, check_load, out_of_plane_names
from sliders.solve.statics import SliderStatics

if TYPE_CHECKING:  # the time integration is imported by the dynamic studies only
    from sliders.solve.dynamics import Dynamics

#: Body-on-line tolerance, relative to the line's size (module docstring).
ON_LINE = 1e-6
#: Ties join coincident nodes to this fraction of the scene's size (as fvbeam.Structure does
#: for bodies).
COINCIDENT = 1e-9
#: What holds a rigid motion left free at the static start of a dynamic study.
START_REMEDY = (
    "a dynamic study starts from the static equilibrium at t = 0, which needs it held: a "
    "support, a slider or a drive; or start from a saved state, study.restart"
)


def _choose(
    problems: Problems,
    path: str,
    given: Sequence[str],
    allowed: Sequence[str],
    always: Sequence[str] = (),
    single: bool = False,
) -> None:
    """A problem for each name of ``given`` not in ``allowed`` (at ``path[i]``, or at
    ``path`` for a ``single`` name): always written if in ``always``, else the allowed
    names with a did-you-mean (``allowed`` looked up as a set: linear in the names)."""
    known = set(allowed)
    for i, name in enumerate(given):
        if name in known:
            continue
        where = path if single else f"{path}[{i}]"
        if name in always:
            problems.add(where, "a key column, always written", name)
        else:
            choices = ", ".join(f"'{a}'" for a in allowed) or "none"
            problems.add(where, f"must be one of {choices}{suggest(name, allowed)}", name)


def _inside(xi: float, length: float) -> bool:
    """Whether the abscissa ``xi`` lies on a line of ``length``, to the ``1e-12`` of its length
    that :func:`fvbeam.geometry.locate_abscissa` allows."""
    return -1e-12 * length <= xi <= length * (1 + 1e-12)


def _section(spec) -> Section:
    """A ``[[section]]``'s section: from its material and shape, or its six stiffnesses
    (:func:`sliders.app.checks.reference_problems`: exactly one of the two)."""
    if spec.material is not None:
        material = Material(**spec.material.model_dump(exclude_none=True))
        shape = SHAPES[spec.shape.kind](**spec.shape.model_dump(exclude={"kind"}))
        return Section.from_shape(material, shape, spec.name)
    return Section.diagonal(
        spec.EA,
        spec.GAy,
        spec.GAz,
        spec.GJ,
        spec.EJy,
        spec.EJz,
        mass_per_length=spec.mass_per_length or 0.0,
        inertia=spec.inertia or (0.0, 0.0, 0.0),
        name=spec.name,
    )


def _mesh(spec: BeamSpec, formulation: str) -> BeamMesh:
    npe = get_formulation(formulation).nodes_per_element
    if spec.straight is not None:
        s = spec.straight
        return straight(s.start, s.end, s.elements, npe, up=spec.up, name=spec.name)
    if spec.arc is not None:
        a = spec.arc
        return arc(a.center, a.radius, a.angle0, a.angle1, a.elements, npe, name=spec.name)
    assert spec.mesh is not None  # checks.py: exactly one of straight, arc, mesh
    return BeamMesh.read(spec.mesh, up=spec.up or (0.0, 0.0, 1.0), name=spec.name)


def _body(spec) -> RigidBody:
    frame = None if spec.frame is None else np.array(spec.frame).T
    return RigidBody(
        spec.name,
        np.array(spec.position),
        spec.mass or 0.0,
        np.array(spec.inertia or np.zeros((3, 3))),
        frame,
        np.array(spec.centre),
    )


def _force(spec, where: str, problems: Problems) -> ForceElement | None:
    """A ``[[force]]`` table's element, or None with its problems recorded at their keys: an
    axial element's law at ``WHERE.law``, a tyre's directions at ``WHERE.normal`` and
    ``WHERE.forward``, the rest (what the element checks of its parts together) at
    ``WHERE``."""
    found = len(problems)
    if spec.kind == "axial":
        fields = {k: v for k, v in spec.law.model_dump().items() if k != "kind"}
        law = problems.attempt(f"{where}.law", partial(Strut, **fields))
        if len(problems) > found:
            return None
        build = partial(AxialForce, spec.nodes[0], spec.nodes[1], law, spec.extended)
        return problems.attempt(where, partial(build, name=spec.name))
    for key in ("normal", "forward"):
        problems.attempt(f"{where}.{key}", partial(direction, getattr(spec, key), key))
    if len(problems) > found:
        return None
    keys = ("radius", "stiffness", "damping", "B", "C", "D", "speed_eps")
    tyre = partial(
        Tyre,
        spec.axle,
        spec.wheel,
        **{k: getattr(spec, k) for k in keys},
        ground=spec.ground,
        normal=spec.normal,
        forward=spec.forward,
        name=spec.name,
    )
    return problems.attempt(where, tyre)


def _motion(spec) -> Linear | Ramp | Tabulated:
    if spec.kind == "linear":
        return Linear(spec.start, spec.velocity, spec.t0)
    if spec.kind == "ramp":
        return Ramp(spec.start, spec.end, spec.t0, spec.t1, spec.shape)
    return Tabulated(np.array(spec.times), np.array(spec.values), spec.order)


def _rigid_line(spec) -> RigidLine:
    if spec.kind == "straight":
        return StraightLine(spec.start, spec.end, spec.up, name=spec.name)
    if spec.kind == "arc":
        return CircularArc(spec.center, spec.radius, spec.angle0, spec.angle1, name=spec.name)
    if spec.kind == "helix":
        return Helix(spec.center, spec.radius, spec.pitch, spec.turns, name=spec.name)
    return CubicSpline(spec.points, spec.up, name=spec.name)


class _Probe:
    """Distances from points to a slider's line in its reference configuration (``zero``:
    no displacement), and the on-line tolerance (module docstring); ``pack``: the slider
    packed alone (:class:`sliders.joints.packed.JointPack`), whose compiled line geometry
    then takes the place of the chain's (the same numbers, a sixth of the time)."""

    def __init__(
        self, line: BeamChain | RigidLine, zero: np.ndarray, pack: JointPack | None = None
    ) -> None:
        self.curve: Callable[[float], tuple[np.ndarray, ...]]
        self.project: Callable[[np.ndarray], float]
        if isinstance(line, BeamChain):
            self.curve = (
                (lambda xi: line.geometry(xi, zero))
                if pack is None
                else (lambda xi: pack.curve(0, zero, xi))
            )
            self.project = lambda point: line.project(point, zero)
        else:
            self.curve = lambda xi: line.derivatives(xi)[:3]
            self.project = line.project
        self.length = line.length
        ends = [float(norm(self.curve(xi)[0])) for xi in (0.0, line.length)]
        self.size = max([line.length] + ends)

    def gap(self, point: np.ndarray, start: float | None = None) -> tuple[float, float, float]:
        """Distance from ``point`` to the line, the tolerance, and the abscissa of the closest
        point; from the abscissa ``start`` of a nearby point when given (a continuation along
        a sweep), else from the line's own search."""
        xi = (
            self.project(point)
            if start is None
            else project_one(self.curve, np.array([start, self.length]), point)
        )
        gap = float(norm(point - self.curve(xi)[0]))
        return gap, ON_LINE * max(self.size, float(norm(point))), xi


class Model:
    """The scene's objects, built once; :meth:`problem` gives each study point's statics.

    Parameters
    ----------
    scene
        A scene that passed :func:`sliders.app.scene.parse_scene`.
    source
        Name of the scene in error messages.
    limits
        The sizes the scene may ask for: the elements of the beams read from mesh files are
        checked once read, before any beam is assembled (:mod:`sliders.app.limits`; default
        from the environment).

    Raises
    ------
    SceneError
        Listing every geometric problem (validation phase 3).
    """

    def __init__(self, scene: Scene, source: str = "scene", limits: Limits | None = None) -> None:
        self.scene = scene
        problems = Problems()
        sections = {
            s.name: problems.attempt(f"section[{i}]", partial(_section, s))
            for i, s in enumerate(scene.section)
        }
        forms = [spec.formulation or scene.formulation for spec in scene.beam]
        wheres = [
            f"beam[{i}].mesh" if spec.mesh is not None else f"beam[{i}]"
            for i, spec in enumerate(scene.beam)
        ]
        meshes = [
            problems.attempt(where, partial(_mesh, spec, form))
            for where, spec, form in zip(wheres, scene.beam, forms, strict=True)
        ]
        limits = Limits.from_environment() if limits is None else limits
        counts = [(w, m.n_elements) for w, m in zip(wheres, meshes, strict=True) if m is not None]
        too_many = element_problems(counts, limits)
        problems += too_many
        self.beams: list[Beam] = []
        for where, spec, form, mesh in zip(wheres, scene.beam, forms, meshes, strict=True):
            if mesh is not None and sections[spec.section] is not None and not too_many:
                self.beams.append(
                    problems.attempt(
                        where,
                        partial(Beam, mesh, sections[spec.section], form, scene.integration),
                    )
                )
        self.bodies = [
            problems.attempt(f"body[{i}]", partial(_body, s)) for i, s in enumerate(scene.body)
        ]
        self.lines = {
            s.name: problems.attempt(f"line[{i}]", partial(_rigid_line, s))
            for i, s in enumerate(scene.line)
        }
        problems.raise_if_any(source)
        parts = Structure(self.beams, bodies=self.bodies)
        self._check_ties(parts, problems)
        self._check_point_loads(parts, problems)
        problems.raise_if_any(source)
        self.ties = [tie.nodes for tie in scene.tie]
        self.supports = [Support.at(s.node, s.kind) for s in scene.support]
        self.slider_drives = {
            d.slider: _motion(d.motion) for d in scene.drive if d.kind == "abscissa"
        }
        self.structure = Structure(self.beams, self.ties, self.bodies)
        tied_ends(scene, self.structure, problems)
        frictions = [  # at their own key: what the friction law checks of its coefficients
            problems.attempt(f"slider[{i}].friction", partial(Friction, **s.friction.model_dump()))
            if s.friction
            else None
            for i, s in enumerate(scene.slider)
        ]
        self.sliders = [
            problems.attempt(f"slider[{i}]", partial(self._slider, s, self.structure, friction))
            for i, (s, friction) in enumerate(zip(scene.slider, frictions, strict=True))
        ]
        forces = [_force(s, f"force[{i}]", problems) for i, s in enumerate(scene.force)]
        self.forces = [f for f in forces if f is not None]  # None: a problem, raised next
        problems.raise_if_any(source)
        self._check_force_geometry(problems)
        self._check_back_end(problems)
        self._check_on_lines(problems)
        #: The state a dynamic study starts from (``study.restart``), or None.
        self.restart = self._restart(problems)
        self._check_drives_on_lines(problems)
        problems.raise_if_any(source)
        self._check_held(problems)
        self._check_velocity_jumps(problems)
        self._check_output(problems)
        #: The weight of a static study's gravity on the structure, or None (:meth:`_weight`).
        self.weight = problems.attempt("study.mass", self._weight)
        if scene.kinematics == "exact" or scene.joint:  # joints are exact only
            from sliders.app.kinematics import exact_problems

            problems += exact_problems(scene, self.structure)
        problems.raise_if_any(source)
        #: The scene's name in messages.
        self.source = source
        self._previous: SliderStatics | None = None

    def _weight(self) -> np.ndarray | None:
        """The weight ``M g`` of a static study's (or a sweep's) ``gravity`` with its
        ``mass`` matrix (:func:`fvbeam.mass.weight`; the one a dynamic study with that mass
        applies; a massless beam weighs nothing); None without gravity or in a dynamic study
        (its time integration adds it).
        A sweep's moved parts keep it: the mass is invariant under translation."""
        study = self.scene.study
        if isinstance(study, DynamicStudy) or study.gravity is None:
            return None
        return weight(self.structure.mass(study.mass, massless=True), study.gravity)

    def _line(self, spec: SliderSpec, structure: Structure) -> BeamChain | RigidLine:
        """The line of the slider ``spec`` on ``structure``: a rigid line, or a chain of
        the structure's beams."""
        if spec.line[0] in self.lines:
            return self.lines[spec.line[0]]
        return BeamChain(structure, spec.line)

    def _slider(self, spec: SliderSpec, structure: Structure, friction: Friction | None) -> Slider:
        return Slider(
            spec.kind,
            self._line(spec, structure),
            spec.body,
            np.array(spec.offset),
            np.array(spec.frame).T,
            spec.smearing,
            spec.kernel,
            spec.orientation,
            spec.end_stops,
            self.slider_drives.get(spec.name),
            friction,
            spec.name,
        )

    # -- geometric checks -------------------------------------------------------------------
    def _size(self) -> float:
        points = np.vstack([b.mesh.points for b in self.beams] + [b.position for b in self.bodies])
        return float(norm(points.max(axis=0) - points.min(axis=0)))

    def _check_ties(self, parts: Structure, problems: Problems) -> None:
        """Ties join coincident nodes (``parts``: the beams and bodies, not yet tied)."""
        tol = COINCIDENT * self._size()
        for i, tie in enumerate(self.scene.tie):
            a, b = (parts.node_position(node) for node in tie.nodes)
            gap = float(norm(a - b))
            if gap > tol:
                problems.add(
                    f"tie[{i}].nodes",
                    f"the nodes are {gap:.6g} m apart; a tie joins "
                    f"coincident nodes (to {COINCIDENT:g} of the scene's size, "
                    f"{tol:.3g} m)",
                    list(tie.nodes),
                )

    def _check_point_loads(self, parts: Structure, problems: Problems) -> None:
        """A point load on its beam, its kernel no wider than the beam
        (:func:`fvbeam.smearing.check_smearing`)."""
        for i, load in enumerate(self.scene.load):
            if isinstance(load, PointLoad):
                length = self.beams[parts.beam_index(load.beam)].mesh.length
                if load.at > length * (1 + 1e-12):
                    problems.add(
                        f"load[{i}].at",
                        f"beyond the end of beam '{load.beam}' (length {length:.6g} m)",
                        load.at,
                    )
                on = f"beam {load.beam!r}"
                check = partial(check_smearing, load.smearing, load.kernel, length, on)
                problems.attempt(f"load[{i}].smearing", check, load.smearing)

    def _check_force_geometry(self, problems: Problems) -> None:
        """An axial element's nodes apart (it acts along the line between them), and its
        law's stops within its stroke ``extended - |x_b - x_a|``, which is ``extended`` when
        the nodes meet: a stop at or beyond it is never reached."""
        tol = COINCIDENT * self._size()
        for i, spec in enumerate(self.scene.force):
            if spec.kind != "axial":
                continue
            a, b = (self.structure.node_position(node) for node in spec.nodes)
            length = float(norm(b - a))
            if length <= tol:
                problems.add(
                    f"force[{i}].nodes",
                    f"the nodes are {length:.3g} m apart: an axial element acts along the "
                    "line between its nodes, which needs them apart",
                    list(spec.nodes),
                )
            if spec.law.stroke_max >= spec.extended:
                problems.add(
                    f"force[{i}].law.stroke_max",
                    f"at or beyond the element's extended length {spec.extended:g} m: the "
                    "stroke, extended - |x_b - x_a|, reaches it only when the nodes meet",
                    spec.law.stroke_max,
                )

    def _check_back_end(self, problems: Problems) -> None:
        """What the study's back end and mass kind take (as the solves check them, before
        any): the bordered back end runs no force element, nor a dynamic study's slider
        friction (:meth:`sliders.solve.statics.SliderStatics`); a consistent mass is a
        Galerkin beam's (:func:`fvbeam.mass.check_kind`)."""
        study = self.scene.study
        instead = "runs on the condensed back end: study.method 'condensed' or 'auto'"
        if study.method == "bordered" and self.scene.force:
            problems.add("study.method", f"the scene has force elements, which {instead}")
        if not isinstance(study, DynamicStudy):
            return
        if study.method == "bordered":
            for i, slider in enumerate(self.scene.slider):
                if slider.friction is not None:
                    problems.add(f"slider[{i}].friction", f"slider friction {instead}")
        if study.mass == "consistent":
            for beam in self.beams:
                found = len(problems)
                problems.attempt("study.mass", partial(check_kind, beam, study.mass), study.mass)
                if len(problems) > found:
                    break

    def _check_on_lines(self, problems: Problems) -> None:
        """Every slider's body on its line, in the scene and at every sweep value."""
        zero = np.zeros(self.structure.n_dofs)
        for i, slider in enumerate(self.sliders):
            unknowns = problems.attempt(
                f"slider[{i}]", partial(slider.initial_unknowns, self.structure, zero)
            )
            if unknowns is not None:
                gap, tol, _ = _Probe(slider.line, zero).gap(slider.reference_point(self.structure))
                if gap > tol:
                    problems.add(
                        f"slider[{i}].body",
                        f"its sliding point is {gap:.3g} m from "
                        f"line '{slider.line.name}' (allowed {tol:.3g} m)",
                        self.scene.slider[i].body,
                    )
        study = self.scene.study
        if not problems and isinstance(study, SweepStudy) and study.parameter is not None:
            self._check_sweep(study, problems)

    def _check_held(self, problems: Problems) -> None:
        """Every rigid motion held at the scene's placement, from rest: by the supports and
        sliders (and the dof drives of a dynamic study), the check every solve makes at its
        start (:func:`sliders.solve.mechanism.free_motion`).  A dynamic study starts from the
        static equilibrium, unless it restarts from a saved state: then the masses hold a
        part's motions and only the massless parts' must be held."""
        study = self.scene.study
        if self.forces or self.scene.joint:
            return  # force elements and joints may hold what supports and sliders leave free
        supports = list(self.supports)
        remedy = REMEDY
        if isinstance(study, DynamicStudy):
            supports += [Support.at(d.node, d.dof) for d in self.scene.drive if d.kind == "dof"]
            if study.start is not None:
                supports += [Support(node) for node in study.start.hold]
            remedy = START_REMEDY if study.restart is None else MASSLESS_REMEDY
        n = self.structure.n_dofs
        free = complement(n, self.structure.support_dofs(supports))
        modes = rigid_modes(self.structure, free)
        if isinstance(study, DynamicStudy) and study.restart is not None and modes.k:
            modes = unresisted(modes, self.structure.mass(study.mass)[free][:, free])
        if not modes.k:
            return
        position = np.full(n, -1)
        position[free] = np.arange(len(free))
        zero = np.zeros(n)
        unknowns = [s.initial_unknowns(self.structure, zero) for s in self.sliders]
        parts = joint_parts(self.structure, self.sliders, zero, unknowns)
        found = free_motion(modes, position, parts, self.sliders, remedy)
        if found:
            problems.add("support", found)

    def _check_velocity_jumps(self, problems: Problems) -> None:
        """No drive of a dynamic study that starts from the static equilibrium (at rest) sets
        a mass moving at once (:func:`sliders.solve.jumps.velocity_jumps`).  The message
        offers a motion that starts at rest: the cosine shape of a linear ramp from
        ``t0 = 0``, else the cosine ramp over the study's time from the motion's value at
        ``t = 0`` to its value at ``t_end``."""
        study = self.scene.study
        if not isinstance(study, DynamicStudy) or study.restart is not None:
            return
        motions = [_motion(d.motion) for d in self.scene.drive]
        if not any(initial_rate(m, 0.0) for m in motions):
            return
        dof, drives = self._dof_drives()
        zero = np.zeros(self.structure.n_dofs)
        unknowns = [s.initial_unknowns(self.structure, zero) for s in self.sliders]
        rest = State(0.0, zero, zero, zero, zero, unknowns)
        M = self.structure.mass(study.mass)
        for jump in velocity_jumps(self.structure, M, drives, self.sliders, rest):
            if isinstance(jump.drive, DofDrive):
                i = dof[drives.index(jump.drive)]
            else:
                i = next(
                    k
                    for k, d in enumerate(self.scene.drive)
                    if d.kind == "abscissa" and d.slider == jump.drive.name
                )
            spec = self.scene.drive[i].motion
            if spec.kind == "ramp" and spec.shape == "linear" and spec.t0 == 0:
                instead = 'shape = "cosine" (the same ramp, at rest at both ends)'
            else:
                start, end = motions[i](0.0)[0], motions[i](study.t_end)[0]
                instead = (
                    f'motion = {{ kind = "ramp", start = {start:.6g}, end = {end:.6g}, '
                    f"t0 = 0, t1 = {study.t_end:g} }} (a cosine ramp: at rest at both ends)"
                )
            problems.add(f"drive[{i}].motion", f"{jump}; start it at rest instead, e.g. {instead}")

    def _check_sweep(self, study: SweepStudy, problems: Problems) -> None:
        where = "study.values" if study.values is not None else "study.range"
        values = study.sweep_values()
        parameter = study.parameter
        if isinstance(parameter, Abscissa):
            length = self._abscissa_length(parameter.of)
            outside = [v for v in values if not _inside(v, length)]
            if outside:
                problems.add(
                    where,
                    f"the abscissa of '{parameter.of}' must lie in "
                    f"[0, {length:.6g}] m (the length of its line)",
                    outside[0],
                )
                return
        moved = self.moved_parts()
        for i, slider in enumerate(self.sliders):
            sign = (part_of(self.scene.slider[i].body) in moved) - self._line_moves(i, moved)
            if not moved or sign == 0:
                continue
            # a chain read compiled: the slider's joint packed (its line's geometry)
            pack = (
                JointPack([slider], self.structure) if isinstance(slider.line, BeamChain) else None
            )
            probe = _Probe(slider.line, np.zeros(self.structure.n_dofs), pack)
            point, xi, bad = slider.reference_point(self.structure), None, []
            for v in values:
                gap, tol, xi = probe.gap(point + sign * self.offset(v), xi)
                if gap > tol:
                    bad.append((v, gap, tol))
            if bad:
                v, g, t = bad[0]
                more = f" (and {len(bad) - 1} more values)" if len(bad) > 1 else ""
                problems.add(
                    where,
                    f"at {v:g}{more}: the sliding point of slider "
                    f"'{slider.name}' is {g:.3g} m from line '{slider.line.name}' "
                    f"(allowed {t:.3g} m)",
                    float(v),
                )

    def _restart(self, problems: Problems) -> State | None:
        """The state ``study.restart`` names, read and matched to the model: its dofs, its
        sliders and the unknowns of each kind, every slider on its line, a time before
        ``t_end`` (None, with the problems recorded, when it is not one)."""
        study = self.scene.study
        if not isinstance(study, DynamicStudy) or study.restart is None:
            return None
        state = problems.attempt("study.restart", partial(State.load, study.restart))
        if state is None:
            return None
        found = len(problems)
        other = f"{study.restart} is a state of another model:"
        if len(state.q) != self.structure.n_dofs:
            problems.add(
                "study.restart",
                f"{other} {len(state.q)} dofs, where this scene has {self.structure.n_dofs}",
            )
        if len(state.unknowns) != len(self.sliders):
            problems.add(
                "study.restart",
                f"{other} {len(state.unknowns)} sliders, where this scene has {len(self.sliders)}",
            )
        for slider, y in zip(self.sliders, state.unknowns, strict=False):
            if len(y) != slider.n_unknowns:
                problems.add(
                    "study.restart",
                    f"{other} {len(y)} unknowns for slider '{slider.name}', a {slider.kind} "
                    f"slider with {slider.n_unknowns} here",
                )
            elif not _inside(float(y[0]), slider.line.length):
                problems.add(
                    "study.restart",
                    f"puts slider '{slider.name}' at xi = {y[0]:.6g} m, outside its line "
                    f"'{slider.line.name}' [0, {slider.line.length:.6g}] m",
                )
        if state.t >= study.t_end:
            problems.add(
                "study.t_end",
                f"must be after the restart state's time, t = {state.t:.6g} s",
                study.t_end,
            )
        return state if len(problems) == found else None

    def _check_drives_on_lines(self, problems: Problems) -> None:
        """Every abscissa drive keeps its slider on its line over the whole integration, from
        its start (``t = 0`` or the restart state's time) to ``t_end``: the motion is checked
        at every time it may be least or greatest (``turning_times``)."""
        study = self.scene.study
        if not isinstance(study, DynamicStudy):
            return
        start = self.restart.t if self.restart is not None else 0.0
        for i, spec in enumerate(self.scene.drive):
            if spec.kind != "abscissa":
                continue
            line = self.sliders[self._slider_names().index(spec.slider)].line
            motion = self.slider_drives[spec.slider]
            for t in motion.turning_times(start, study.t_end):
                xi = motion(t)[0]
                if not _inside(xi, line.length):
                    problems.add(
                        f"drive[{i}].motion",
                        f"takes slider '{spec.slider}' to xi = {xi:.6g} m at t = {t:.6g} s, "
                        f"outside its line '{line.name}' [0, {line.length:.6g}] m",
                    )
                    break

    def _slider_names(self) -> list[str]:
        return [s.name for s in self.scene.slider]

    def _abscissa_length(self, of: str) -> float:
        if of in self._slider_names():
            return self.sliders[self._slider_names().index(of)].line.length
        load = next(p for p in self.scene.load if p.name == of and isinstance(p, PointLoad))
        return self.beams[self.structure.beam_index(load.beam)].mesh.length

    def _line_moves(self, i: int, moved: set[str]) -> bool:
        return self.scene.slider[i].line[0] in moved

    # -- the study's points -----------------------------------------------------------------
    def moved_parts(self) -> set[str]:
        """The beams and bodies a sweep moves (none for a static study or a load sweep)."""
        study = self.scene.study
        if not isinstance(study, SweepStudy):
            return set()
        parameter = study.parameter
        if isinstance(parameter, Translation):
            return set(parameter.move)
        if isinstance(parameter, Abscissa) and parameter.of in self._slider_names():
            spec = self.scene.slider[self._slider_names().index(parameter.of)]
            return tied_parts(self.scene, part_of(spec.body))
        return set()

    def offset(self, value: float) -> np.ndarray:
        """How far a sweep value moves the moved parts from their scene placement."""
        study = self.scene.study
        if not isinstance(study, SweepStudy) or isinstance(study.parameter, LoadFactor):
            raise ValueError("only a sweep over a translation or an abscissa moves parts")
        parameter = study.parameter
        if isinstance(parameter, Translation):
            return value * direction(parameter.direction, "study.parameter.direction")
        slider = self.sliders[self._slider_names().index(parameter.of)]
        zero = np.zeros(self.structure.n_dofs)
        target = (
            slider.line.geometry(value, zero)[0]
            if isinstance(slider.line, BeamChain)
            else slider.line.at(value).x
        )
        return target - slider.reference_point(self.structure)

    @cached_property
    def plane(self) -> str | None:
        """The coordinate plane the scene lies in, or None: its nodes, joints and lines, its
        loads, gravity and driven dofs, the direction its parts move in a sweep and its
        restart state, with no stiffness or mass coupling the plane's dofs with the others
        (:func:`sliders.solve.planar.check`).  Its studies then solve on the in-plane dofs
        (``study.planar``, default true; not with the bordered back end, which cannot pin
        the joints' out-of-plane reactions)."""
        study = self.scene.study
        if not study.planar or study.method == "bordered" or isinstance(study, ModesStudy):
            return None  # the modes are the 3-D problem's (sliders.solve.modes)
        structure = self.structure
        matrices = [structure.tangent(np.zeros(structure.n_dofs))]
        vectors = [("the loads", self.load_vector(structure, None))]
        if isinstance(study, DynamicStudy):
            matrices.append(structure.mass(study.mass))
            if study.gravity is not None:
                vectors.append(("gravity", acceleration(structure.n_dofs, study.gravity)))
            if self.restart is not None:
                vectors += [("the restart", self.restart.q), ("the restart", self.restart.v)]
        elif study.gravity is not None:
            vectors.append(("gravity", self.weight))
        # directions that must lie in the plane, and rotation rates that must turn about
        # its normal: the start's velocities, the tyres' ground
        along: list[np.ndarray] = [np.asarray(b.velocity) for b in self.scene.body if b.velocity]
        about = [np.asarray(b.angular_velocity) for b in self.scene.body if b.angular_velocity]
        if isinstance(study, DynamicStudy) and study.start is not None:
            along.append(np.asarray(study.start.velocity))
        for force in self.forces:
            if isinstance(force, Tyre):
                along += [np.asarray(force.normal), np.asarray(force.forward)]
        drives = self._dof_drives()[1]
        parameter = study.parameter if isinstance(study, SweepStudy) else None
        for plane, axis in PLANES.items():
            try:
                check(structure, self.sliders, plane, matrices)
                for what, f in vectors:
                    check_load(structure, f, plane, what)
            except ValueError:
                continue
            if any(d.dof in out_of_plane_names(axis) for d in drives):
                continue
            if any(abs(v[axis]) > 0 for v in along) or any(
                np.any(np.delete(w, axis) != 0) for w in about
            ):
                continue
            if isinstance(parameter, Translation) and abs(parameter.direction[axis]) > 0:
                continue
            return plane
        return None

    def problem(self, value: float | None = None) -> tuple[SliderStatics, np.ndarray]:
        """The statics and the load vector of the study point ``value`` (``None``: the scene
        as written)."""
        moved = self.moved_parts() if value is not None else set()
        method = self.scene.study.method
        if moved or self._previous is None:
            shift = self.offset(value) if moved and value is not None else np.zeros(3)
            beams = [
                b.translated(shift) if s.name in moved else b
                for s, b in zip(self.scene.beam, self.beams, strict=True)
            ]
            bodies = [
                dataclasses.replace(b, position=b.position + shift) if b.name in moved else b
                for b in self.bodies
            ]
            if self._previous is None:
                structure = Structure(beams, self.ties, bodies)
                sliders = [
                    self._slider(s, structure, built.friction)
                    for s, built in zip(self.scene.slider, self.sliders, strict=True)
                ]
                self._previous = SliderStatics(
                    structure,
                    self.supports,
                    sliders,
                    method=method,
                    forces=self.forces,
                    plane=self.plane,
                )
            else:  # the last point's parts moved: its numbering and checked sliders kept
                self._previous = self._previous.moved(beams, bodies)
        f = self.load_vector(self._previous.structure, value)
        return self._previous, f if self.weight is None else f + self.weight

    def dynamics(self) -> Dynamics:
        """The time integration of a dynamic study's scene."""
        study = self.scene.study
        if not isinstance(study, DynamicStudy):
            raise ValueError(f"a {study.kind} study has no time integration")
        from sliders.solve.dynamics import Dynamics

        return Dynamics(
            self.structure,
            self.supports,
            self.sliders,
            self.load_vector(self.structure, None),
            forces=self.forces,
            mass=study.mass,
            damping=study.damping,
            gravity=study.gravity,
            drives=self._dof_drives()[1],
            rho_inf=study.rho_inf,
            method=study.method,
            tol=study.tol,
            max_iterations=study.max_iterations,
            plane=self.plane,
        )

    def start_state(self, dynamics: Dynamics) -> State:
        """Where a dynamic study starts: the restart state; or the static equilibrium at
        ``t = 0``, solved with ``study.start.hold``'s nodes clamped and set moving at
        ``study.start.velocity`` and the bodies' own velocities (the held dofs at rest),
        accelerations zero (:meth:`sliders.solve.dynamics.Dynamics.state`); or, with no
        velocity given, at rest (:meth:`~sliders.solve.dynamics.Dynamics.static_state`)."""
        study = self.scene.study
        assert isinstance(study, DynamicStudy)
        if self.restart is not None:
            return self.restart
        start = study.start
        moving = [b for b in self.scene.body if b.velocity or b.angular_velocity]
        if start is None and not moving:
            return dynamics.static_state()
        hold = [Support(node) for node in (start.hold if start is not None else ())]
        first = dynamics.prescribe(np.zeros(self.structure.n_dofs), 0.0)
        unknowns = [s.initial_unknowns(self.structure, first) for s in self.sliders]
        statics = SliderStatics(
            self.structure,
            dynamics.supports + hold,
            self.sliders,
            method=study.method,
            forces=self.forces,
        )
        try:
            solution = statics.solve(
                dynamics.load(0.0), (first, unknowns), study.tol, study.max_iterations
            )
        except ValueError as exc:
            from sliders.solve.dynamics import DynamicsError

            rest = np.zeros(self.structure.n_dofs)
            raise DynamicsError(
                f"t = 0: the static start: {exc}", State(0.0, first, rest, rest, rest, unknowns)
            ) from exc
        v = np.zeros(self.structure.n_dofs)
        if start is not None:
            v[0::6], v[1::6], v[2::6] = start.velocity
        for body in moving:
            dofs = self.structure.node_dofs(body.name)
            v[dofs[:3]] = body.velocity if body.velocity is not None else v[dofs[:3]]
            v[dofs[3:]] = body.angular_velocity if body.angular_velocity is not None else 0.0
        held = np.setdiff1d(np.arange(len(v)), dynamics.free)
        v[held] = 0.0
        return dynamics.state(solution.q, v, 0.0, solution.unknowns)

    # -- outputs -------------------------------------------------------------------------------
    def held(self) -> list[Support]:
        """What holds nodes, as the ``reactions`` table lists them: the supports, and a
        dynamic study's dof drives (:attr:`sliders.solve.dynamics.Dynamics.supports`)."""
        drives = self._dof_drives()[1] if isinstance(self.scene.study, DynamicStudy) else []
        return self.supports + [Support.at(d.node, d.dof) for d in drives]

    def selections(self) -> dict[str, Selection]:
        """The rows and columns ``[output]`` asks of each table it lists but ``samples``."""
        output = self.scene.output
        out: dict[str, Selection] = {}
        for name in output.csv:
            if name in SELECTED:
                spec = getattr(output, name)
                out[name] = Selection(
                    None if spec is None else getattr(spec, SELECTED[name]),
                    None if spec is None else spec.columns,
                )
        return out

    def probes(self) -> dict[str, Probe]:
        """The ``[[output.probe]]`` columns of ``history.csv``, by name."""
        out: dict[str, Probe] = {}
        elements = {e.name: e for e in self.forces}
        output = self.scene.output
        shared = {name: ElementOutputs(e) for name, e in elements.items()}
        for spec in output.probe:
            if spec.force is not None:
                out[spec.name] = element_probe(elements[spec.force], spec.value, shared[spec.force])
            elif spec.slider is not None:
                j = [s.name for s in self.sliders].index(spec.slider)
                n = self.sliders[j].n_unknowns
                out[spec.name] = events.slider_probe(j, n, spec.value, spec.axes)
            elif spec.node is not None and spec.value in VELOCITY_NAMES:
                out[spec.name] = velocity_probe(self.structure, spec.node, spec.value)
            elif spec.node is not None:
                out[spec.name] = node_probe(self.structure, spec.node, spec.value)
            else:
                assert spec.beam is not None and spec.at is not None  # checks.py
                out[spec.name] = force_probe(self.structure, spec.beam, spec.at, spec.value)
        gravity = getattr(self.scene.study, "gravity", None)
        for load in output.load:
            for c in load.components or self._free_components(load.body):
                out[f"{load.name}.{c}"] = events.load_probe(self.structure, load.body, c, gravity)
        for event in output.event:
            for column, value in events.event_columns(event):
                probe = element_probe(elements[event.force], value, shared[event.force])
                out.setdefault(column, probe)
        return out

    def _free_components(self, body: str) -> tuple[str, ...]:
        """The load components of ``body``'s dofs that no support or drive holds."""
        held = self.structure.support_dofs(self.held())
        dofs = self.structure.node_dofs(body)
        return tuple(c for c, d in zip(events.COMPONENTS, dofs, strict=True) if d not in held)

    def _check_output(self, problems: Problems) -> None:
        """The names ``[output]`` uses, against the model: ``history`` columns
        (:func:`sliders.app.columns.history_columns`), each table's rows and columns
        (:func:`sliders.app.state_tables.items`, :data:`~sliders.app.state_tables.CHOICES`),
        VTU fields (:data:`sliders.app.vtu.FIELDS`), probes' values and abscissae."""
        output = self.scene.output
        columns = history_columns(self.sliders)
        taken, outputs = set(columns), {e.name: e.OUTPUTS for e in self.forces}
        choose = partial(_choose, problems)
        if output.history is not None:
            choose("output.history", output.history, columns)
        if output.vtu_fields is not None:
            from sliders.app.vtu import FIELDS  # meshio: only for a scene that names fields

            choose("output.vtu_fields", output.vtu_fields, FIELDS)
        for table, key in SELECTED.items():
            spec = getattr(output, table)
            if spec is not None:
                known = items(table, self.structure, self.sliders, self.held())
                choose(f"output.{table}.{key}", getattr(spec, key) or (), known)
                choose(
                    f"output.{table}.columns",
                    spec.columns or (),
                    CHOICES[table],
                    KEY_COLUMNS[table],
                )
        if "modes" in output.csv and not isinstance(self.scene.study, ModesStudy):
            problems.add(
                "output.csv",
                f"modes.csv is a modes study's, not a {self.scene.study.kind} study's",
                "modes",
            )
        if not self.structure.beams and not self.sliders:  # bodies alone: nothing to draw
            drawn = {
                "vtu": output.vtu,
                "png": output.png != "none",
                "animation": output.animation != "none",
            }
            for key, asked in drawn.items():
                if asked:
                    problems.add(
                        f"output.{key}",
                        "draws the beams, the lines and what rides on them: this scene has "
                        "none (its bodies' states are in the tables)",
                        getattr(output, key),
                    )
        if output.animation != "none" and not isinstance(
            self.scene.study, DynamicStudy | ModesStudy
        ):
            problems.add(
                "output.animation",
                "animates a dynamic study's states or a modes study's modes, not a "
                f"{self.scene.study.kind} study's",
                output.animation,
            )
        if output.render.follow is not None:
            try:
                self.structure.node_dofs(output.render.follow)
            except ValueError as exc:
                problems.add("output.render.follow", str(exc), output.render.follow)
        for i, spec in enumerate(output.probe):
            path = f"output.probe[{i}]"
            if spec.name in taken:
                problems.add(f"{path}.name", "already a column of history.csv", spec.name)
            if spec.axes is not None and (spec.slider is None or spec.value != "force"):
                problems.add(f"{path}.axes", "axes are for a slider's force", list(spec.axes))
            if spec.force is not None:
                allowed = outputs[spec.force]
            elif spec.slider is not None:
                allowed = events.SLIDER_VALUES
            elif spec.node is not None:
                allowed = DOF_NAMES + VELOCITY_NAMES
            else:
                allowed = FORCE_NAMES
            choose(f"{path}.value", (spec.value,), allowed, single=True)
            if spec.beam is not None and spec.at is not None:
                length = self.structure.beams[self.structure.beam_index(spec.beam)].mesh.length
                if spec.at > length * (1 + 1e-12):
                    problems.add(
                        f"{path}.at",
                        f"beyond the end of beam '{spec.beam}' (length {length:.6g} m)",
                        spec.at,
                    )
        self._check_derived(problems)

    def _check_derived(self, problems: Problems) -> None:
        """The attachment loads' bodies and components, and the names the summary reads
        (:func:`sliders.app.events.check`)."""
        output = self.scene.output
        bodies = [b.name for b in self.structure.bodies]
        for i, load in enumerate(output.load):
            path = f"output.load[{i}]"
            if load.body not in bodies:
                problems.add(f"{path}.body", f"no body of that name{suggest(load.body, bodies)}")
                continue
            free = self._free_components(load.body)
            for k, c in enumerate(load.components or ()):
                if c not in free:
                    problems.add(
                        f"{path}.components[{k}]",
                        f"'{load.body}' is held there: its support's reaction "
                        "(the reactions table) carries it",
                        c,
                    )
        if not events.asked(output) and not output.load:
            return
        probes = [p.name for p in output.probe]
        # an attachment load on an undefined body (an error of its own) still names its
        # columns, so that what reads them is not reported again
        every = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
        probes += [
            f"{load.name}.{c}"
            for load in output.load
            for c in load.components
            or (self._free_components(load.body) if load.body in bodies else every)
        ]
        probes += [c for e in output.event for c, _ in events.event_columns(e)]
        kept = history_columns(self.sliders)
        if output.history is not None:
            kept = [c for c in kept if c in ("step", "t", *output.history)]
        events.check(output, self.forces, kept, probes, problems)

    def _dof_drives(self) -> tuple[list[int], list[DofDrive]]:
        """The scene's dof drives: their indices in ``[[drive]]`` and the drives."""
        specs = [(i, d) for i, d in enumerate(self.scene.drive) if isinstance(d, DofDriveSpec)]
        return [i for i, _ in specs], [DofDrive(d.node, d.dof, _motion(d.motion)) for _, d in specs]

    def load_vector(self, structure: Structure, value: float | None) -> np.ndarray:
        """The scene's loads on ``structure`` at the study point ``value``."""
        f = np.zeros(structure.n_dofs)
        for spec in self.scene.load:
            if spec.kind == "nodal":
                f += structure.nodal_load(spec.node, spec.force, spec.moment)
                continue
            i = structure.beam_index(spec.beam)
            beam = structure.beams[i]
            if spec.kind == "distributed":
                f += structure.gather(i, beam.distributed_load(spec.force, spec.moment))
                continue
            at = self.load_at(spec, value)
            f += structure.gather(
                i, beam.point_load(at, spec.force, spec.moment, spec.smearing, spec.kernel)
            )
        return f * self.load_factor(value)

    def load_at(self, spec: PointLoad, value: float | None) -> float:
        """The abscissa of the point load ``spec`` at the study point ``value``: the value
        of a sweep over its abscissa, else its ``at``."""
        study = self.scene.study
        parameter = study.parameter if isinstance(study, SweepStudy) else None
        moves = isinstance(parameter, Abscissa) and parameter.of == spec.name
        return value if moves and value is not None else spec.at

    def load_factor(self, value: float | None) -> float:
        """The factor on the scene's loads at the study point ``value``: the value of a
        load-factor sweep, else 1."""
        study = self.scene.study
        parameter = study.parameter if isinstance(study, SweepStudy) else None
        return value if isinstance(parameter, LoadFactor) and value is not None else 1.0
