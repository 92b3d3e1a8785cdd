"""Running a scene's study: every sample's solution (or failure), or every step, in memory.

A static study has one sample; a sweep has one per parameter value, solved as a continuation
(:func:`sliders.solve.sweep.sweep`: a progress bar on a terminal, failed points recorded with their
message, Ctrl-C keeping the completed points).  A dynamic study is a time integration
(:func:`sliders.app.run_dynamic.integrate`).  A modes study adds the modes about every
converged sample (:func:`sliders.app.run_modes.modes_of`).  Writing is a separate step:
:func:`sliders.app.tables.write_results` for samples, :func:`sliders.app.run_dynamic.write_dynamic`
for a time integration.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from sliders.app.errors import SceneError
from sliders.app.model import Model
from sliders.app.schema import DynamicStudy, ModesStudy, Scene, SweepStudy
from sliders.solve.statics import SliderSolution, SliderStatics
from sliders.solve.sweep import sweep

if TYPE_CHECKING:  # the time integration is imported by a dynamic study only
    from sliders.app.run_dynamic import DynamicRun


@dataclass(frozen=True)
class Sample:
    """One study point: the parameter ``value`` (``None`` for a static study), its
    ``statics`` and ``load`` vector, and the ``solution`` or the ``error`` message."""

    index: int
    value: float | None
    statics: SliderStatics | None
    load: np.ndarray | None
    solution: SliderSolution | None
    error: str | None = None


@dataclass
class Results:
    """The samples computed for ``model``, in order; ``interrupted`` when Ctrl-C ended a
    sweep early; ``planned`` samples were asked for; ``seconds`` of wall time."""

    model: Model
    samples: list[Sample] = field(default_factory=list)
    planned: int = 1
    interrupted: bool = False
    seconds: float = 0.0
    #: A modes study's modes about every converged sample (:mod:`sliders.app.run_modes`).
    modes: list | None = None
    #: The line saying which kinematics was taken and why (:mod:`sliders.app.run_exact`),
    #: and whether it is a warning (linear kinematics beyond its bound).
    kinematics: str = ""
    kinematics_warning: bool = False

    @property
    def scene(self) -> Scene:
        return self.model.scene

    @property
    def failures(self) -> list[Sample]:
        """The samples that did not converge (or could not be built)."""
        return [s for s in self.samples if s.solution is None]


def run(model: Model, progress: bool = True, kinematics: str | None = None) -> Results | DynamicRun:
    """Solve the scene's study, of any kind.

    Parameters
    ----------
    model
        The built scene.
    progress
        A progress bar on sweeps and time integrations (shown only on a terminal).
    kinematics
        ``exact``, ``linear`` or ``auto`` (:mod:`sliders.app.run_exact`); default the
        scene's ``kinematics``.  ``exact`` raises :class:`~sliders.app.errors.SceneError`
        naming the first scene item exact kinematics does not carry.

    Returns
    -------
    Results
        For a static study or a sweep: every sample, converged or not (a static study that
        fails has one failed sample).
    DynamicRun
        For a dynamic study: every step (its recorder), the last state, and the failure or
        interruption that ended it early, if any.
    """
    from sliders.app.kinematics import KINDS, exact_problems

    study = model.scene.study
    kind = model.scene.kinematics if kinematics is None else kinematics
    if kind not in KINDS:
        raise ValueError(f"kinematics must be one of {', '.join(KINDS)}, got {kind!r}")
    if isinstance(study, DynamicStudy):
        if kind == "exact":
            raise SceneError(model.source, exact_problems(model.scene, model.structure))
        from sliders.app.run_dynamic import integrate

        return integrate(model, progress)
    results = _kinematic_samples(model, progress, kind)
    if isinstance(study, ModesStudy):
        from sliders.app.run_modes import modes_of
        from sliders.app.scene_joints import joints

        start = time.perf_counter()
        results.modes = modes_of(results.samples, study, progress, joints(model.scene))
        results.seconds += time.perf_counter() - start
    return results


def _kinematic_samples(model: Model, progress: bool, kind: str) -> Results:
    """The samples of a static study or a sweep with the kinematics ``kind``
    (:mod:`sliders.app.run_exact`): the linear samples unless ``kind`` is ``exact``, then
    the exact ones if the choice is so."""
    from sliders.app.run_exact import choose, exact_samples

    linear = None if kind == "exact" or model.scene.joint else _samples(model, progress)
    if linear is not None and linear.interrupted:  # Ctrl-C: no second path
        linear.kinematics = "kinematics: linear (interrupted before the choice)"
        return linear
    answers = [
        (s.statics.structure, s.solution.q)
        for s in (linear.samples if linear is not None else [])
        if s.statics is not None and s.solution is not None
    ]
    choice = choose(model, kind, answers, model.source)
    if linear is None or choice.exact:
        exact = exact_samples(model, progress)
        results = Results(
            model,
            [Sample(*sample) for sample in exact.samples],
            exact.planned,
            exact.interrupted,
            exact.seconds + (linear.seconds if linear is not None else 0.0),
        )
    else:
        results = linear
    results.kinematics, results.kinematics_warning = choice.statement, choice.warning
    return results


def _samples(model: Model, progress: bool) -> Results:
    """The samples of a static study or a sweep (a modes study's states)."""
    study = model.scene.study
    assert not isinstance(study, DynamicStudy)
    options: dict[str, Any] = dict(
        tol=study.tol, max_iterations=study.max_iterations, load_steps=study.load_steps
    )
    start = time.perf_counter()
    if not isinstance(study, SweepStudy) or study.parameter is None:
        statics, f = model.problem()
        try:
            sample = Sample(0, None, statics, f, statics.solve(f, **options))
        except ValueError as exc:
            sample = Sample(0, None, statics, f, None, str(exc))
        return Results(model, [sample], seconds=time.perf_counter() - start)
    built: list[tuple[SliderStatics, np.ndarray] | tuple[None, None]] = []

    def build(value: float) -> tuple[SliderStatics, np.ndarray]:
        built.append((None, None))
        problem = built[-1] = model.problem(float(value))
        return problem

    values = study.sweep_values()
    result = sweep(
        values,
        build,
        continuation=study.continuation,
        stop_on_failure=study.stop_on_failure,
        progress=progress,
        desc=model.scene.title or study.parameter.kind,
        **options,
    )
    samples = [
        Sample(k, float(p.value), built[k][0], built[k][1], p.solution, p.error)
        for k, p in enumerate(result.points)
    ]
    return Results(model, samples, len(values), result.interrupted, time.perf_counter() - start)
