"""Phase 2 of scene validation: names, references and consistency, on the data alone.

Every name a scene uses must be defined (with a did-you-mean when it is not), chains must be
tied end to start, a slider must not slide on its own beam, and the study's parameter must
refer to something it can move.  Nothing is built here: the geometry is checked by
:class:`sliders.app.model.Model`.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Hashable, Iterable
from functools import partial

from fvbeam.names import suggest
from fvbeam.support import DOF_NAMES, held_dofs
from sliders.app.errors import Problem, Problems
from sliders.app.scene_joints import joint_problems
from sliders.app.schema import (
    Abscissa,
    DynamicStudy,
    ModesStudy,
    PointLoad,
    Scene,
    SectionSpec,
    SweepStudy,
    Translation,
)


def part_of(ref: str) -> str:
    """The beam or body a node reference belongs to (``'piston.end'`` -> ``'piston'``)."""
    return ref.split(".")[0]


def tied_parts(scene: Scene, part: str) -> set[str]:
    """The beams and bodies joined to ``part`` by ties, directly or through others (a
    search of the graph of ties: linear in their number)."""
    joined: dict[str, list[str]] = defaultdict(list)
    for tie in scene.tie:
        a, b = (part_of(n) for n in tie.nodes)
        joined[a].append(b)
        joined[b].append(a)
    group, todo = {part}, [part]
    while todo:
        for other in joined[todo.pop()]:
            if other not in group:
                group.add(other)
                todo.append(other)
    return group


def repeated(values: Iterable[Hashable]) -> list[str]:
    """The values listed more than once, sorted as text; one pass with a set of those seen
    (linear in the number of values, however many repeat)."""
    seen: set = set()
    twice: set = set()
    for value in values:
        (twice if value in seen else seen).add(value)
    return sorted(str(v) for v in twice)


class _Names:
    """The scene's names by kind, and the checks of references to them."""

    def __init__(self, scene: Scene, problems: Problems) -> None:
        self.sections = self._unique("section", scene.section, problems)
        parts = [("beam", scene.beam), ("body", scene.body), ("line", scene.line)]
        self.beams, self.bodies, self.lines = self._unique_across(parts, problems)
        actors = [("slider", scene.slider), ("load", scene.load), ("force", scene.force)]
        self.sliders, self.loads, self.forces = self._unique_across(actors, problems)

    @staticmethod
    def _unique(key: str, items: Iterable, problems: Problems) -> dict[str, int]:
        return _Names._unique_across([(key, items)], problems)[0]

    @staticmethod
    def _unique_across(groups, problems: Problems) -> list[dict[str, int]]:
        """Names of several kinds that share one namespace: ``{name: index}`` per kind."""
        seen: dict[str, str] = {}
        out = []
        for key, items in groups:
            names: dict[str, int] = {}
            for i, item in enumerate(items):
                name = getattr(item, "name", None)
                if name is None:
                    continue
                if name in seen:
                    problems.add(f"{key}[{i}].name", f"already the name of {seen[name]}", name)
                    continue
                seen[name], names[name] = f"{key}[{i}]", i
            out.append(names)
        return out

    def node(self, path: str, ref: str, problems: Problems) -> bool:
        """Check a node reference; record a problem and return False if it is wrong."""
        name, _, end = ref.partition(".")
        if end and name not in self.beams:
            hint = (
                f"'{name}' is a body: refer to it as '{name}'"
                if name in self.bodies
                else f"no beam named '{name}'{suggest(name, self.beams)}"
            )
            problems.add(path, hint, ref)
            return False
        if not end and name not in self.bodies:
            hint = (
                f"'{name}' is a beam: name one of its ends, '{name}.start' or '{name}.end'"
                if name in self.beams
                else f"no body named '{name}'{suggest(name, self.bodies)}"
            )
            problems.add(path, hint, ref)
            return False
        return True

    def beam(self, path: str, name: str, problems: Problems) -> bool:
        if name in self.beams:
            return True
        problems.add(path, f"no beam named '{name}'{suggest(name, self.beams)}", name)
        return False


def reference_problems(scene: Scene) -> list[Problem]:
    """Every problem of names, references and consistency in ``scene`` (phase 2)."""
    problems = Problems()
    names = _Names(scene, problems)
    if not scene.beam and not scene.body:
        problems.add("", "a scene needs at least one [[beam]] or [[body]]")
    _check_sections(scene, problems)
    _check_beams(scene, names, problems)
    ties_ok = True
    for i, tie in enumerate(scene.tie):
        ok = all([names.node(f"tie[{i}].nodes[{k}]", n, problems) for k, n in enumerate(tie.nodes)])
        if ok and tie.nodes[0] == tie.nodes[1]:
            problems.add(f"tie[{i}].nodes", "ties a node to itself", list(tie.nodes))
        ties_ok = ties_ok and ok
    for i, support in enumerate(scene.support):
        names.node(f"support[{i}].node", support.node, problems)
        problems.attempt(f"support[{i}].kind", partial(held_dofs, support.kind), support.kind)
    joint_problems(scene, lambda path, ref: names.node(path, ref, problems), problems)
    ties = {frozenset(t.nodes) for t in scene.tie}
    for i in range(len(scene.slider)):
        _check_slider(scene, i, names, problems, ties if ties_ok else None)
    for i, load in enumerate(scene.load):
        if load.kind == "nodal":
            names.node(f"load[{i}].node", load.node, problems)
        else:
            names.beam(f"load[{i}].beam", load.beam, problems)
    _check_forces(scene, names, problems)
    _check_study(scene, names, problems)
    _check_output(scene, names, problems)
    return list(problems)


#: The tables of ``[output]`` that select rows and columns, and the key naming their rows.
SELECTED = {
    "nodes": "nodes",
    "sliders": "sliders",
    "internal_forces": "beams",
    "reactions": "nodes",
}


def _check_output(scene: Scene, names: _Names, problems: Problems) -> None:
    """What ``[output]`` asks for fits the study and its tables; each probe names one node,
    or one beam and an abscissa.  The names of columns, fields and rows are checked against
    the built model (:class:`sliders.app.model.Model`)."""
    output = scene.output
    for key, values in (
        ("csv", output.csv),
        ("history", output.history or ()),
        ("vtu_fields", output.vtu_fields or ()),
    ):
        twice = repeated(values)
        if twice:
            problems.add(f"output.{key}", f"lists {', '.join(twice)} more than once", list(values))
    dynamic = isinstance(scene.study, DynamicStudy)
    derived = ("probe", "load", "peak", "event", "frequency")
    given_keys = [("history", output.history is not None)]
    for key, given in given_keys + [(k, bool(getattr(output, k))) for k in derived]:
        if given and not dynamic:
            problems.add(
                f"output.{key}",
                f"history.csv is a dynamic study's: study.kind = '{scene.study.kind}' has none",
            )
    if output.vtu_fields is not None and not output.vtu:
        problems.add("output.vtu_fields", "selects VTU fields, but output.vtu is false")
    for table, key in SELECTED.items():
        spec = getattr(output, table)
        if spec is None:
            continue
        if table not in output.csv:
            problems.add(f"output.{table}", f"selects from the {table} table, not in output.csv")
        twice = repeated([*(getattr(spec, key) or ()), *(spec.columns or ())])
        if twice:
            problems.add(f"output.{table}", f"lists {', '.join(twice)} more than once")
    seen: dict[str, int] = {}
    for i, probe in enumerate(output.probe):
        path = f"output.probe[{i}]"
        if probe.name in seen:
            problems.add(
                f"{path}.name", f"already the name of output.probe[{seen[probe.name]}]", probe.name
            )
        seen.setdefault(probe.name, i)
        targets = [k for k in ("node", "beam", "force", "slider") if getattr(probe, k) is not None]
        if len(targets) != 1:
            problems.add(path, "give exactly one of node, beam, force, slider")
        elif probe.force is not None or probe.slider is not None:
            key, known, what = (
                ("force", names.forces, "force element")
                if probe.force is not None
                else ("slider", names.sliders, "slider")
            )
            given = getattr(probe, key)
            if given not in known:
                problems.add(
                    f"{path}.{key}", f"no {what} named '{given}'{suggest(given, known)}", given
                )
            if probe.at is not None:
                problems.add(f"{path}.at", f"a {key} probe takes no abscissa (at is for a beam)")
        elif probe.node is not None:
            names.node(f"{path}.node", probe.node, problems)
            if probe.at is not None:
                problems.add(
                    f"{path}.at", "a node probe takes no abscissa (at is for a beam)", probe.at
                )
        else:
            assert probe.beam is not None
            names.beam(f"{path}.beam", probe.beam, problems)
            if probe.at is None:
                problems.add(path, "a beam probe needs at, the abscissa of its recovery point")


def _check_forces(scene: Scene, names: _Names, problems: Problems) -> None:
    """Each force element's nodes: defined, and two different ones."""
    for i, force in enumerate(scene.force):
        path = f"force[{i}]"
        if force.kind == "axial":
            ends = [(f"{path}.nodes[{k}]", n) for k, n in enumerate(force.nodes)]
        else:
            ends = [(f"{path}.axle", force.axle), (f"{path}.wheel", force.wheel)]
        known = all([names.node(where, node, problems) for where, node in ends])
        if known and ends[0][1] == ends[1][1]:
            problems.add(ends[1][0], f"is the element's other node too ({ends[0][0]})", ends[1][1])


#: A section's stiffnesses, the form it may take instead of a material and a shape.
STIFFNESSES = ("EA", "GAy", "GAz", "GJ", "EJy", "EJz")


def _check_sections(scene: Scene, problems: Problems) -> None:
    """Each section given by exactly one of its two forms: the six stiffnesses (with
    ``mass_per_length`` and ``inertia``), or ``material`` and ``shape`` (which give them)."""
    for i, section in enumerate(scene.section):
        path = f"section[{i}]"
        given, geometry = _forms(section)
        if given and geometry:
            problems.add(
                path,
                "give either the six stiffnesses or material and shape, not both (found "
                f"{', '.join(given + geometry)})",
            )
        elif geometry:
            for key in {"material", "shape"} - set(geometry):
                problems.add(f"{path}.{key}", f"missing: a section's {geometry[0]} needs its {key}")
            material = section.material
            if material is not None and (material.nu is None) == (material.G is None):
                problems.add(f"{path}.material", "give exactly one of nu, G (the other follows)")
            for key in ("mass_per_length", "inertia"):
                if getattr(section, key) is not None:
                    problems.add(
                        f"{path}.{key}",
                        "follows from material.density and the shape: leave it out",
                        getattr(section, key),
                    )
        elif given:
            for key in STIFFNESSES:
                if key not in given:
                    problems.add(
                        f"{path}.{key}",
                        "missing: give all six stiffnesses, or material and shape instead",
                    )
        else:
            problems.add(
                path,
                f"give its six stiffnesses ({', '.join(STIFFNESSES)}), or its material and shape",
            )


def _forms(section: SectionSpec) -> tuple[list[str], list[str]]:
    """The stiffness keys and the geometry keys (``material``, ``shape``) ``section`` gives."""
    given = [k for k in STIFFNESSES if getattr(section, k) is not None]
    return given, [k for k in ("material", "shape") if getattr(section, k) is not None]


def _whole(section: SectionSpec) -> bool:
    """Whether ``section`` is given by exactly one whole form (:func:`_check_sections`)."""
    given, geometry = _forms(section)
    return (len(given) == len(STIFFNESSES) and not geometry) or (len(geometry) == 2 and not given)


def _check_beams(scene: Scene, names: _Names, problems: Problems) -> None:
    for i, beam in enumerate(scene.beam):
        given = [k for k in ("straight", "arc", "mesh") if getattr(beam, k) is not None]
        if len(given) != 1:
            problems.add(
                f"beam[{i}]",
                f"give exactly one of straight, arc, mesh (found {', '.join(given) or 'none'})",
            )
        if beam.section not in names.sections:
            problems.add(
                f"beam[{i}].section",
                f"no section named '{beam.section}'{suggest(beam.section, names.sections)}",
                beam.section,
            )
        if beam.arc is not None and beam.up is not None:
            problems.add(
                f"beam[{i}].up",
                "an arc lies in a plane normal to z, which is its up: leave up out",
                list(beam.up),
            )


def _check_slider(
    scene: Scene, i: int, names: _Names, problems: Problems, ties: set[frozenset] | None
) -> None:
    """A slider's line, body and orientation (its chain's joints against ``ties``, the
    scene's, only when every tie is valid, else None: a broken tie is reported once, where
    it is)."""
    slider, path = scene.slider[i], f"slider[{i}]"
    chain = _check_line(path, slider.line, names, problems, ties)
    if names.node(f"{path}.body", slider.body, problems) and part_of(slider.body) in chain:
        problems.add(
            f"{path}.body",
            f"is a node of its own line's beam '{part_of(slider.body)}'",
            slider.body,
        )
    if slider.orientation == "slope" and slider.kind != "classical":
        problems.add(
            f"{path}.orientation",
            "'slope' is the classical slider's (paper eq. 4); "
            f"a {slider.kind} slider needs 'section'",
            slider.orientation,
        )


def _check_line(
    path: str,
    line: tuple[str, ...],
    names: _Names,
    problems: Problems,
    ties: set[frozenset] | None,
) -> list[str]:
    """Check a slider's line; return the beams of its chain (empty for a rigid line)."""
    if len(line) == 1 and line[0] in names.lines:
        return []
    for k, name in enumerate(line):
        if name in names.lines:
            problems.add(
                f"{path}.line[{k}]",
                f"'{name}' is a rigid line: a chain holds beams "
                "only (a rigid line is a line of its own)",
                name,
            )
        elif name not in names.beams:
            choices = list(names.beams) + (list(names.lines) if len(line) == 1 else [])
            problems.add(
                f"{path}.line[{k}]",
                f"no {'line or ' if len(line) == 1 else ''}"
                f"beam named '{name}'{suggest(name, choices)}",
                name,
            )
    twice = repeated(line)
    if twice:
        problems.add(f"{path}.line", f"lists beam {', '.join(twice)} more than once", list(line))
    elif ties is not None and all(name in names.beams for name in line):
        for a, b in zip(line[:-1], line[1:], strict=True):
            if frozenset((f"{a}.end", f"{b}.start")) not in ties:
                problems.add(
                    f"{path}.line",
                    f"beams '{a}' and '{b}' are not joined: a chain "
                    f"needs a [[tie]] with nodes = ['{a}.end', '{b}.start']",
                    list(line),
                )
    return [name for name in line if name in names.beams]


def _check_study(scene: Scene, names: _Names, problems: Problems) -> None:
    study = scene.study
    if scene.drive and not isinstance(study, DynamicStudy):
        problems.add(
            "drive",
            f"drives prescribe motions in time: they need study.kind = "
            f"'dynamic', not '{study.kind}'",
        )
    if isinstance(study, DynamicStudy):
        _check_dynamic(scene, study, names, problems)
        _check_start(scene, study, names, problems)
    else:
        if study.gravity is not None and not _has_mass(scene):
            # named where the mass is missing: every beam's section (no body has a mass)
            weightless = "study.gravity (nothing has a mass: it would weigh nothing)"
            _check_masses(scene, weightless, problems)
        if isinstance(study, ModesStudy):
            _check_masses(scene, "a modes study", problems)
            if study.window is not None and study.window[0] >= study.window[1]:
                problems.add("study.window", "f_min must be below f_max", list(study.window))
        for i, body in enumerate(scene.body):
            for key in ("velocity", "angular_velocity"):
                if getattr(body, key) is not None:
                    problems.add(
                        f"body[{i}].{key}",
                        f"an initial velocity needs study.kind = 'dynamic', not '{study.kind}'",
                        list(getattr(body, key)),
                    )
    if study.method == "condensed" and not scene.slider:
        problems.add(
            "study.method",
            "'condensed' eliminates slider unknowns and needs at least one slider; use 'bordered'",
            study.method,
        )
    if not isinstance(study, SweepStudy) or study.parameter is None:
        if isinstance(study, SweepStudy) and (study.values, study.range) != (None, None):
            problems.add("study", "values and range sweep a parameter: give one")
        return
    if (study.values is None) == (study.range is None):
        problems.add("study", "give exactly one of values, range")
    if isinstance(study.parameter, Translation):
        _check_translation(scene, study.parameter, names, problems)
    elif isinstance(study.parameter, Abscissa):
        _check_abscissa(scene, study.parameter.of, names, problems)


def _check_dynamic(scene: Scene, study: DynamicStudy, names: _Names, problems: Problems) -> None:
    """The drives' references (a slider or dof driven once), their tables, the steps, and
    the mass of every beam's section."""
    _check_masses(scene, "a dynamic study", problems)
    supports = defaultdict(list)
    for j, support in enumerate(scene.support):
        supports[support.node].append((j, support.kind))
    driven: dict[str, int] = {}
    for i, drive in enumerate(scene.drive):
        path = f"drive[{i}]"
        if drive.kind == "abscissa":
            key = drive.slider
            if drive.slider not in names.sliders:
                problems.add(
                    f"{path}.slider",
                    f"no slider named '{drive.slider}'{suggest(drive.slider, names.sliders)}",
                    drive.slider,
                )
        else:
            key = f"{drive.node}.{drive.dof}"
            names.node(f"{path}.node", drive.node, problems)
            for j, kind in supports.get(drive.node, ()):
                if _holds(kind, drive.dof):  # named where the support holds it
                    problems.add(
                        f"support[{j}].kind",
                        f"holds {drive.node} {drive.dof}, which {path} drives",
                        kind,
                    )
        if key in driven:
            problems.add(path, f"drives what drive[{driven[key]}] already drives ({key})")
        driven.setdefault(key, i)
        motion = drive.motion
        if motion.kind == "tabulated":
            if len(motion.times) != len(motion.values):
                problems.add(
                    f"{path}.motion.values",
                    f"has {len(motion.values)} values for {len(motion.times)} times",
                    list(motion.values),
                )
            if any(b <= a for a, b in zip(motion.times[:-1], motion.times[1:], strict=True)):
                problems.add(f"{path}.motion.times", "must increase strictly", list(motion.times))
            if motion.order == 3 and len(motion.times) < 4:
                problems.add(
                    f"{path}.motion.order", "a cubic table needs at least 4 points", motion.order
                )
        elif motion.kind == "ramp" and not motion.t1 > motion.t0:
            problems.add(f"{path}.motion.t1", f"must be after t0 = {motion.t0}", motion.t1)
    if study.step > study.t_end:
        problems.add("study.step", f"is longer than t_end = {study.t_end}", study.step)
    adaptive = study.adaptive
    if adaptive is not None and adaptive.h_max is not None and adaptive.h_max <= adaptive.h_min:
        problems.add(
            "study.adaptive.h_max", f"must exceed h_min = {adaptive.h_min}", adaptive.h_max
        )


def _check_masses(scene: Scene, study: str, problems: Problems) -> None:
    """The mass of every beam's section: its ``mass_per_length``, or its material's
    ``density``."""
    for i, section in enumerate(scene.section):
        if not any(b.section == section.name for b in scene.beam):
            continue
        if section.material is not None and section.material.density is None:
            key = "material.density"
        elif section.material is None and section.mass_per_length is None:
            key = "mass_per_length"
        else:
            continue
        problems.add(f"section[{i}].{key}", f"{study} needs the mass of every beam's section")


def _has_mass(scene: Scene) -> bool:
    """Whether a beam's section or a body has a mass (or may: a beam whose section is not
    defined or not given whole, an error of its own, is not taken as massless)."""
    used = {b.section for b in scene.beam}
    if used - {s.name for s in scene.section}:
        return True
    if any(not _whole(s) for s in scene.section if s.name in used):
        return True
    return any(b.mass for b in scene.body) or any(
        s.mass_per_length or (s.material is not None and s.material.density)
        for s in scene.section
        if s.name in used
    )


def _check_start(scene: Scene, study: DynamicStudy, names: _Names, problems: Problems) -> None:
    """``study.start`` and the bodies' velocities: not with a restart (its state has its own
    velocities); the nodes ``hold`` clamps, defined and listed once."""
    moving = [
        (f"body[{i}].{key}", getattr(body, key))
        for i, body in enumerate(scene.body)
        for key in ("velocity", "angular_velocity")
        if getattr(body, key) is not None
    ]
    if study.start is not None:
        moving.insert(0, ("study.start", study.start.velocity))
        for k, node in enumerate(study.start.hold):
            names.node(f"study.start.hold[{k}]", node, problems)
        twice = repeated(study.start.hold)
        if twice:
            problems.add("study.start.hold", f"lists {', '.join(twice)} more than once")
    if study.restart is not None:
        for where, _ in moving:
            problems.add(
                where,
                "a restart starts from its saved state, velocities included: give either "
                "study.restart or initial velocities",
            )


def _holds(kind: str, dof: str) -> bool:
    """Whether a support of ``kind`` holds ``dof`` (no: a wrong kind, reported where it is)."""
    try:
        return DOF_NAMES.index(dof) in held_dofs(kind)
    except ValueError:
        return False


def _check_translation(
    scene: Scene, parameter: Translation, names: _Names, problems: Problems
) -> None:
    path = "study.parameter"
    moved = set(parameter.move)
    for k, name in enumerate(parameter.move):
        if name not in names.beams and name not in names.bodies:
            problems.add(
                f"{path}.move[{k}]",
                f"no beam or body named '{name}'"
                f"{suggest(name, list(names.beams) + list(names.bodies))}",
                name,
            )
    if not any(parameter.direction):
        problems.add(f"{path}.direction", "must not be zero", list(parameter.direction))
    known = set(names.beams) | set(names.bodies)
    for k, tie in enumerate(scene.tie):
        a, b = (part_of(n) for n in tie.nodes)
        if a not in known or b not in known or not moved <= known:
            continue  # an undefined name, reported where it is
        if (a in moved) != (b in moved):
            problems.add(
                f"{path}.move",
                f"moves '{a if a in moved else b}' but not "
                f"'{b if a in moved else a}', tied to it by tie[{k}]: move both or "
                "neither",
                list(parameter.move),
            )


def _check_abscissa(scene: Scene, of: str, names: _Names, problems: Problems) -> None:
    path = "study.parameter.of"
    if of in names.sliders:
        slider = scene.slider[names.sliders[of]]
        carried = tied_parts(scene, part_of(slider.body)) & set(slider.line)
        if carried:
            problems.add(
                path,
                f"moving the body of slider '{of}' would move its own line (beam "
                f"{', '.join(sorted(carried))} is tied to the body)",
                of,
            )
        return
    if of in names.loads and isinstance(scene.load[names.loads[of]], PointLoad):
        return
    if of in names.loads:
        problems.add(
            path, f"load '{of}' is not a point load: only a point load has an abscissa", of
        )
        return
    problems.add(
        path,
        f"no slider or named point load '{of}'"
        f"{suggest(of, list(names.sliders) + list(names.loads))}",
        of,
    )
