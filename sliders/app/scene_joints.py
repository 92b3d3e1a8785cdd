"""A scene's ``[[joint]]`` tables: joints with finite rotations between nodes, bodies and the
ground, on the exact path only (``docs/scenes.md``, "Joints").

:func:`joint_problems` checks each table by its key path (``joint[1].kind``, ``joint[0].a``):
its kind (:func:`sliders.joints.exact_laws.selected_rows`), its ends (a node, a body or
``"ground"``, not both the ground, not one node twice, nor two tied nodes:
:func:`tied_ends`) and its axes (``axis`` or ``frame``, not both), and that the scene's
kinematics can carry joints: the rows of a joint are written for finite rotations
(:mod:`sliders.joints.exact_laws`), so ``kinematics = "linear"`` is refused and ``"auto"``
takes the exact path.  :func:`joints` builds the :class:`~sliders.joints.exact_model.Joint`
of each table; :func:`write_joints` writes ``joints.csv``: what each joint exerts on each
of its nodes, force and couple about the node, global axes.
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from fvbeam.geometry import direction
from fvbeam.structure import Structure
from sliders.app.errors import Problems
from sliders.app.schema import JointSpec, Scene
from sliders.app.state_tables import cell

if TYPE_CHECKING:  # the exact joints are imported by the scenes that have joints only
    from sliders.joints.exact_model import Joint

#: The columns of ``joints.csv``.
COLUMNS = ("sample", "value", "joint", "node", "fx", "fy", "fz", "mx", "my", "mz")

#: Why a scene with joints is refused under linear kinematics.
NEEDS_EXACT = "joints need kinematics = 'exact' (or 'auto', which then takes the exact path)"


def joint_problems(scene: Scene, node_ok: Callable[[str, str], object], problems: Problems) -> None:
    """Every problem of ``scene``'s joints, by key path (module docstring); ``node_ok(path,
    ref)`` checks a node reference and reports it."""
    if not scene.joint:
        return
    from sliders.joints.exact_laws import selected_rows
    from sliders.joints.exact_model import GROUND

    for i, spec in enumerate(scene.joint):
        path = f"joint[{i}]"
        problems.attempt(f"{path}.kind", partial(selected_rows, spec.kind, path), spec.kind)
        if spec.a == GROUND and spec.b == GROUND:
            problems.add(path, "both ends are the ground", [spec.a, spec.b])
        elif spec.a == spec.b:
            problems.add(f"{path}.b", "is the same node as a", spec.b)
        for side in ("a", "b"):
            ref = getattr(spec, side)
            if ref != GROUND:
                node_ok(f"{path}.{side}", ref)
        if spec.axis is not None and spec.frame is not None:
            problems.add(f"{path}.axis", "give an axis or a frame, not both")
        elif spec.axis is not None:
            problems.attempt(f"{path}.axis", partial(direction, spec.axis, "the axis"), spec.axis)
    if scene.kinematics == "linear":
        problems.add("kinematics", NEEDS_EXACT, scene.kinematics)
    if any(body.name == GROUND for body in scene.body):
        problems.add("body", f"a body named {GROUND!r} in a scene with joints (the fixed frame)")


def tied_ends(scene: Scene, structure: Structure, problems: Problems) -> None:
    """A joint whose ends are one node of ``structure`` (tied together), at its ``b``."""
    if not scene.joint:
        return
    from sliders.joints.exact_model import GROUND

    for i, spec in enumerate(scene.joint):
        if GROUND in (spec.a, spec.b) or spec.a == spec.b:
            continue
        if structure.node_dofs(spec.a)[0] == structure.node_dofs(spec.b)[0]:
            problems.add(
                f"joint[{i}].b", f"is tied to {spec.a!r}: one node, nothing to join", spec.b
            )


def joint(spec: JointSpec) -> Joint:
    """The joint of a ``[[joint]]`` table (its ``frame`` rows are the axes, the joint's
    columns)."""
    from sliders.joints.exact_model import Joint

    frame = None if spec.frame is None else np.array(spec.frame).T
    position = None if spec.position is None else np.array(spec.position)
    axis = None if spec.axis is None else np.array(spec.axis)
    return Joint(spec.kind, spec.a, spec.b, position, frame, axis)


def joints(scene: Scene) -> list[Joint]:
    """The joints of ``scene``'s ``[[joint]]`` tables, in order."""
    return [joint(spec) for spec in scene.joint]


def write_joints(path: Path, scene: Scene, samples: Sequence[Any]) -> None:
    """Write ``joints.csv`` (:data:`COLUMNS`) of the converged ``samples`` (each with its
    ``index``, ``value`` and an exact ``solution``): per sample, joint and end that is not
    the ground, what the joint exerts on the node, the opposite of its share ``B^T lambda``
    of the node's balance (:meth:`sliders.joints.exact_model.ExactModel.reactions`)."""
    from sliders.joints.exact_model import GROUND

    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS)
        for sample in samples:
            reactions = sample.solution.joints
            for i, (spec, reaction) in enumerate(zip(scene.joint, reactions, strict=True)):
                for k, node in enumerate((spec.a, spec.b)):
                    if node != GROUND:
                        head = [sample.index, sample.value, i, node]
                        writer.writerow([cell(v) for v in head + list(-reaction[k])])
