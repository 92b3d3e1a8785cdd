"""A static study or a load-factor sweep run with the kinematics its scene asks for
(``kinematics``: ``exact``, ``linear`` or ``auto``; :mod:`sliders.app.kinematics` states the
exact path and the linear answer's bound).

:func:`choose` says which path to take and the one line that says which and why
(:attr:`sliders.app.run.Results.kinematics`): ``auto`` solves linearly, keeps that answer
when its bound is within the study's ``tol`` (or when the exact path does not carry the
scene, naming the item), and solves exactly otherwise, and at once for a scene with joints
(exact only, :mod:`sliders.app.scene_joints`); ``exact`` refuses a scene it does not
carry (:class:`~sliders.app.errors.SceneError` naming the item); ``linear`` warns when its
bound is above the study's ``tol``; ``auto`` takes a modes study about a loaded state that
the exact path carries exact (:data:`PRELOADED`).  :func:`exact_samples` solves on the
exact path: a sweep is a continuation (each value from the last converged state), with a
progress bar on a terminal, failed values recorded, Ctrl-C keeping the completed ones.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from fvbeam.structure import Structure
from sliders.app.dead_loads import dead_load
from sliders.app.errors import Problem, SceneError
from sliders.app.kinematics import (
    ExactPath,
    ExactSolution,
    exact_problems,
    modes_loads_off_nodes,
    neglected,
    unsupported,
)
from sliders.app.model import Model
from sliders.app.scene_joints import NEEDS_EXACT, joints
from sliders.app.schema import ModesStudy, StaticStudy, SweepStudy
from sliders.solve.statics import SliderStatics

#: Why ``auto`` takes a modes study about a loaded state exact: the geometric stiffness
#: changes ``omega^2`` by the load over the buckling load, first order in the load, which
#: the bound (second order) does not measure.
PRELOADED = "modes about a loaded state take the geometric stiffness of the preload"


@dataclass(frozen=True)
class Choice:
    """The path to take (``exact`` or not), the line that says why, and whether it is a
    warning."""

    exact: bool
    statement: str
    warning: bool = False


def choose(
    model: Model, kind: str, linear: Sequence[tuple[Structure, np.ndarray]], source: str
) -> Choice:
    """The path for kinematics ``kind`` (module docstring), from the ``linear`` answers
    (each converged sample's structure and dofs; none for ``exact``)."""
    scene = model.scene
    if kind == "exact" or scene.joint:
        problems = exact_problems(scene, model.structure)
        if scene.joint and kind == "linear":
            problems.append(Problem("kinematics", NEEDS_EXACT))
        if problems:
            raise SceneError(source, problems)
        if kind == "exact":
            return Choice(True, "kinematics: exact (asked)")
        return Choice(True, f"kinematics: exact ({kind}: the scene has joints, exact only)")
    if not linear:
        return Choice(False, f"kinematics: linear ({kind}: no converged linear answer to bound)")
    bound = max((neglected(structure, q) for structure, q in linear), key=lambda b: b.eta)
    tol = scene.study.tol
    within = f"{'within' if bound.eta <= tol else 'above'} the study's tol {tol:g}"
    if kind == "linear":
        if bound.eta > tol:
            return Choice(False, f"warning: kinematics linear: {bound.describe()}, {within}", True)
        return Choice(False, "")
    item = unsupported(scene) or modes_loads_off_nodes(scene, model.structure)
    if item is not None:
        return Choice(
            False,
            f"kinematics: linear (auto: the exact path does not carry {item[0]}, {item[1]}; "
            f"{bound.describe()})",
        )
    if isinstance(scene.study, ModesStudy) and any(np.any(q != 0) for _, q in linear):
        return Choice(True, f"kinematics: exact (auto: {PRELOADED})")
    if bound.eta <= tol:
        return Choice(False, f"kinematics: linear (auto: {bound.describe()}, {within})")
    reason = f"the linear answer's {bound.describe()}, {within}"
    return Choice(True, f"kinematics: exact (auto: {reason})")


def dynamic_choice(model: Model, q: np.ndarray) -> Choice:
    """What a dynamic study's kinematics says (the exact path carries no dynamics): the
    line of :func:`choose` for the scene's ``kinematics``, the bound from the last state
    ``q``."""
    return choose(model, model.scene.kinematics, [(model.structure, q)], "scene")


@dataclass
class ExactRun:
    """The samples solved on the exact path, each ``(index, value, statics, load, solution,
    error)`` (:class:`sliders.app.run.Sample`'s fields; ``load`` at the converged state, the
    lever arms of loads between nodes its own, as the reactions take it), how many were
    ``planned``, whether Ctrl-C ended the sweep, and the wall time."""

    samples: list[tuple] = field(default_factory=list)
    planned: int = 1
    interrupted: bool = False
    seconds: float = 0.0


def exact_samples(model: Model, progress: bool) -> ExactRun:
    """The samples of the static study or load-factor sweep on the exact path."""
    from tqdm import tqdm

    study = model.scene.study
    assert isinstance(study, (StaticStudy, SweepStudy))  # unsupported() refuses the others
    start = time.perf_counter()
    statics, _ = model.problem()
    path = ExactPath(
        statics.structure,
        statics.structure.support_dofs(model.supports),
        study.max_iterations,
        study.load_steps,
        joints(model.scene),
        statics.sliders,
        statics.forces,
    )
    values: list[float | None] = [None]
    continuation = stop = False
    if isinstance(study, SweepStudy) and study.parameter is not None:  # not a modes study's
        values = [float(v) for v in study.sweep_values()]
        continuation, stop = study.continuation, study.stop_on_failure
    run = ExactRun(planned=len(values))
    state = None
    sweep = isinstance(study, SweepStudy) and study.parameter is not None
    desc = model.scene.title or "load_factor"
    with tqdm(values, disable=None if (progress and sweep) else True, desc=desc) as bar:
        try:
            for k, value in enumerate(bar):
                problem: tuple[SliderStatics, np.ndarray] = model.problem(value)
                solution: ExactSolution | None = None
                error = None
                applied = problem[1]
                try:
                    load = dead_load(model, problem[0].structure, value)
                    solution = path.solve(load, state if continuation else None)
                    applied = load.vector(solution.state)  # the lever arms of the state
                except ValueError as exc:
                    error = str(exc)
                run.samples.append((k, value, problem[0], applied, solution, error))
                if solution is not None:
                    state = solution.state
                elif stop:
                    break
        except KeyboardInterrupt:
            run.interrupted = True
    run.seconds = time.perf_counter() - start
    return run
