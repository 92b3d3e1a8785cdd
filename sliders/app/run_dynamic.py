"""Running a scene's dynamic study into an output directory.

The integration (:class:`sliders.solve.dynamics.Dynamics`) starts from the static equilibrium at
``t = 0`` or from the saved state ``study.restart``, and streams its steps into the new
directory (:mod:`sliders.app.history`), which then replaces the output directory whole:

* ``history.csv`` always (in place of ``samples``); ``nodes.csv``, ``sliders.csv``,
  ``internal_forces.csv``, ``reactions.csv`` when ``output.csv`` lists them: the static
  tables' columns, one set of rows per step (:data:`sliders.app.tables.STEP_COLUMNS`);
* ``state.npz``, the last converged state (restart from it with ``study.restart``);
* ``scene.toml``; with ``output.vtu``, a VTU per kept state (``study.every``) and their
  ``.pvd``; with ``output.png``, renders of the last state (``last``) or of every kept one.

A failed step or Ctrl-C still writes everything computed up to the last converged step.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fvbeam.io import OUTPUT_MARKER, replace_directory
from sliders.app.history import Recorder
from sliders.app.model import Model
from sliders.app.scene import dump_scene
from sliders.app.tables import STEP_COLUMNS
from sliders.app.vtu import Frame, write_series
from sliders.solve.dynamics import Adaptive, DynamicsError
from sliders.solve.integrator import State


@dataclass
class DynamicRun:
    """What a dynamic study did: the ``recorder`` with every step, the last converged
    ``state`` (None when even the start failed), the ``error`` message of a failure,
    ``interrupted`` by Ctrl-C, and the wall-clock ``seconds``."""

    recorder: Recorder
    state: State | None = None
    error: str | None = None
    interrupted: bool = False
    seconds: float = 0.0


def run_dynamic(model: Model, out: str | Path, progress: bool = True) -> DynamicRun:
    """Integrate ``model``'s dynamic study and write its outputs into ``out`` (replaced
    whole; ``ValueError`` if ``out`` is not ours, or the restart file is not a state of this
    scene)."""
    scene = model.scene
    study, output = scene.study, scene.output
    dynamics = model.dynamics()
    held = np.setdiff1d(np.arange(model.structure.n_dofs), dynamics.free)
    start = None
    if study.restart is not None:
        start = State.load(study.restart)
        if start.q.shape != (model.structure.n_dofs,) or len(start.unknowns) != len(model.sliders):
            raise ValueError(
                f"{study.restart}: a state of another model ({len(start.q)} "
                f"dofs, {len(start.unknowns)} sliders)"
            )
    keep = study.every if (output.vtu or output.png == "all") else 0
    outcome = DynamicRun(Recorder())
    adaptive = None
    if study.adaptive is not None:
        spec = study.adaptive
        adaptive = Adaptive(
            spec.rtol, spec.atol, spec.h_min, spec.h_max if spec.h_max is not None else float("inf")
        )

    def fill(directory: Path) -> None:
        (directory / "scene.toml").write_text(dump_scene(scene))
        outcome.recorder = Recorder(
            directory, [name for name in output.csv if name in STEP_COLUMNS], every=keep
        )
        clock = time.perf_counter()
        try:
            first = start if start is not None else dynamics.static_state()
            outcome.state = dynamics.run(
                first, study.t_end, study.step, adaptive, outcome.recorder, progress
            )
        except DynamicsError as exc:
            outcome.error, outcome.state = str(exc), outcome.recorder.last
        except KeyboardInterrupt:
            outcome.interrupted, outcome.state = True, outcome.recorder.last
        outcome.seconds = time.perf_counter() - clock
        if outcome.state is None:
            return
        outcome.state.save(directory / "state.npz")
        kept = list(outcome.recorder.states)
        if output.vtu:
            if not kept or kept[-1] is not outcome.state:
                kept.append(outcome.state)
            write_series(directory / "states", (_frame(model, held, s) for s in kept))
        rendered = {"none": [], "last": [outcome.state], "all": kept}[output.png]
        for k, state in enumerate(rendered):
            _render(model, held, state, directory / f"render_{k:06d}.png")

    replace_directory(out, fill, OUTPUT_MARKER)
    return outcome


def _frame(model: Model, held: np.ndarray, state: State) -> Frame:
    return Frame(state.t, model.structure, state.q, model.sliders, state.unknowns, held)


def _render(model: Model, held: np.ndarray, state: State, path: Path) -> None:
    from sliders.app.render import render

    render(
        path,
        model.structure,
        state.q,
        model.sliders,
        state.unknowns,
        title=f"{model.scene.title or 'scene'}: t = {state.t:.4g} s",
        held=held,
    )
