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
from typing import Any

import numpy as np

from sliders.app.model import Model
from sliders.app.run_dynamic import DynamicRun, integrate
from sliders.app.schema import DynamicStudy, ModesStudy, Scene, SweepStudy
from sliders.solve.statics import SliderSolution, SliderStatics
from sliders.solve.sweep import sweep


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

    @property
    def scene(self) -> Scene:
        return self.model.scene

    @property
    def failures(self) -> list[Sample]:
        """The samples that did not converge (or could not be built)."""
        return [s for s in self.samples if s.solution is None]


def run(model: Model, progress: bool = True) -> Results | DynamicRun:
    """Solve the scene's study, of any kind.

    Parameters
    ----------
    model
        The built scene.
    progress
        A progress bar on sweeps and time integrations (shown only on a terminal).

    Returns
    -------
    Results
        For a static study or a sweep: every sample, converged or not (a static study that
        fails has one failed sample).
    DynamicRun
        For a dynamic study: every step (its recorder), the last state, and the failure or
        interruption that ended it early, if any.
    """
    study = model.scene.study
    if isinstance(study, DynamicStudy):
        return integrate(model, progress)
    results = _samples(model, progress)
    if isinstance(study, ModesStudy):
        from sliders.app.run_modes import modes_of

        start = time.perf_counter()
        results.modes = modes_of(results.samples, study, progress)
        results.seconds += time.perf_counter() - start
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
