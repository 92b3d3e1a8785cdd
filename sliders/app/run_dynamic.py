"""A scene's dynamic study: integrated in memory, then written into an output directory.

:func:`integrate` (what :func:`sliders.app.run.run` does for a dynamic study) starts the
integration (:class:`sliders.solve.dynamics.Dynamics`) from the static equilibrium at ``t = 0``
or from the saved state ``study.restart`` and records every step in memory
(:class:`sliders.app.history.Recorder`); a failed step or Ctrl-C ends it with everything up to
the last converged step.  Given the output directory, it keeps checkpoints beside it
(:mod:`sliders.app.checkpoint`) and can resume from the last one instead of starting.
:func:`write_dynamic` then writes a new directory, which replaces the output directory whole
(and removes the checkpoint of a run that ended):

* ``history.csv`` always (in place of ``samples``; the columns ``output.history`` keeps, and
  the ``output.probe`` ones); ``nodes.csv``, ``sliders.csv``, ``internal_forces.csv``,
  ``reactions.csv`` when ``output.csv`` lists them: the static tables' columns, one set of
  rows per step (:data:`sliders.app.state_tables.STEP_COLUMNS`), the rows and columns
  ``[output]`` selects (:meth:`sliders.app.model.Model.selections`);
* ``summary.csv`` when ``[output]`` asks for peaks, events or frequencies
  (:mod:`sliders.app.events`), from the history's columns;
* ``state.npz``, the last converged state (restart from it with ``study.restart``);
* ``scene.toml``; with ``output.vtu``, a VTU per kept state (``study.every``) with the
  fields of ``output.vtu_fields``, and their ``.pvd``; with ``output.png``, renders of the
  last state (``last``) or of every kept one; with ``output.animation``, the kept states as
  ``animation.mp4`` or ``animation.gif`` (:func:`sliders.app.render.animate`: one camera,
  magnification and colour range for all, the time in the title).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fvbeam.io import OUTPUT_MARKER, replace_directory
from fvbeam.support import complement
from sliders.app import events
from sliders.app.checkpoint import Checkpoints
from sliders.app.history import Recorder
from sliders.app.model import Model
from sliders.app.render import Options, animate, render_frame
from sliders.app.scene import dump_scene
from sliders.app.schema import CheckpointSpec, DynamicStudy, Output, Scene
from sliders.app.vtu import Frame, write_series
from sliders.solve.dynamics import Adaptive, DynamicsError
from sliders.solve.integrator import State


@dataclass
class DynamicRun:
    """What a dynamic study did: the ``model``, the ``recorder`` with every step in memory
    (:meth:`~sliders.app.history.Recorder.table` is ``history.csv``), the last converged
    ``state`` (None when even the start failed), the ``error`` message of a failure,
    ``interrupted`` by Ctrl-C, the wall-clock ``seconds``, the ``held`` dofs (supports
    and dof drives: what the rigid part of the drawn motion keeps in place,
    :func:`sliders.app.motion.rigid_motion`), and its ``checkpoints`` (None without an
    output directory)."""

    model: Model
    recorder: Recorder
    held: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    state: State | None = None
    error: str | None = None
    interrupted: bool = False
    seconds: float = 0.0
    checkpoints: Checkpoints | None = None

    @property
    def scene(self) -> Scene:
        return self.model.scene

    def frames(self) -> list[Frame]:
        """The kept states (one in ``study.every`` when the scene asks for VTU or for every
        render) and the last one, as the frames of a VTU series: ``write_series(directory,
        run.frames())`` (:func:`sliders.app.vtu.write_series`)."""
        kept = list(self.recorder.states)
        if self.state is not None and (not kept or kept[-1] is not self.state):
            kept.append(self.state)
        return [Frame.of(self.model, state, held=self.held) for state in kept]


def integrate(
    model: Model, progress: bool = True, out: str | Path | None = None, resume: bool = False
) -> DynamicRun:
    """Integrate ``model``'s dynamic study, every step recorded in memory, from the static
    equilibrium or from the restart state the model read and checked (``model.restart``).

    Parameters
    ----------
    model
        The built scene.
    progress
        A progress bar of simulated time (on a terminal).
    out
        The output directory the run is for (:func:`write_dynamic`): its checkpoints go
        beside it, as ``study.checkpoint`` asks (:mod:`sliders.app.checkpoint`), and one on
        Ctrl-C.  None: none.
    resume
        Go on from the last checkpoint of the run into ``out`` instead of starting.

    Raises
    ------
    ValueError
        ``out``'s checkpoint is missing, another scene's or damaged.
    sliders.app.checkpoint.Complete
        ``resume`` and ``out`` holds the scene's finished run (nothing to do).
    """
    study, output = model.scene.study, model.scene.output
    if not isinstance(study, DynamicStudy):
        raise ValueError(f"a {study.kind} study: integrate runs dynamic studies")
    if resume and out is None:
        raise ValueError("resume needs the output directory out whose checkpoint to go on from")
    dynamics = model.dynamics()
    adaptive = None
    if study.adaptive is not None:
        spec = study.adaptive
        adaptive = Adaptive(
            spec.rtol, spec.atol, spec.h_min, spec.h_max if spec.h_max is not None else float("inf")
        )
    recorder = Recorder(
        None,
        model.selections(),
        model.probes(),
        every=study.every if keeps_states(output) else 0,
        history=output.history,
    )
    held = complement(model.structure.n_dofs, dynamics.free)
    outcome = DynamicRun(model, recorder, held)
    period = study.checkpoint or CheckpointSpec()
    cursor = None
    if out is not None and resume:
        outcome.checkpoints, cursor = Checkpoints.resume(
            out, model.scene, dynamics, recorder, period.steps, period.seconds
        )
    elif out is not None:
        outcome.checkpoints = Checkpoints(out, model.scene, recorder, period.steps, period.seconds)
    save = outcome.checkpoints if outcome.checkpoints and outcome.checkpoints.enabled else None
    clock = time.perf_counter()
    try:
        if cursor is not None:
            outcome.state = dynamics.resume(cursor, study.t_end, adaptive, recorder, progress, save)
        else:
            first = model.start_state(dynamics)
            outcome.state = dynamics.run(
                first, study.t_end, study.step, adaptive, recorder, progress, save
            )
    except DynamicsError as exc:
        outcome.error, outcome.state = str(exc), recorder.last
    except KeyboardInterrupt:
        outcome.interrupted, outcome.state = True, recorder.last
        if save is not None:
            save.save()  # the last whole step, to resume from
    outcome.seconds = time.perf_counter() - clock
    return outcome


def write_dynamic(outcome: DynamicRun, out: str | Path) -> None:
    """Write ``outcome`` into a new directory that replaces ``out`` whole (module docstring;
    ``ValueError`` if ``out`` is not a directory ``fvslider`` wrote); then, unless Ctrl-C
    interrupted it, remove the run's checkpoint: the run is over."""
    model = outcome.model
    output = model.scene.output

    def fill(directory: Path) -> None:
        (directory / "scene.toml").write_text(dump_scene(model.scene))
        checkpoints = outcome.checkpoints
        outcome.recorder.write(directory, checkpoints.written() if checkpoints else None)
        if events.asked(output) and outcome.recorder.count("history"):
            values = events.summary(output, model.forces, outcome.recorder.table())
            events.write_summary(directory / "summary.csv", values)
        if outcome.state is None:
            return
        outcome.state.save(directory / "state.npz")
        frames = outcome.frames()
        if output.vtu:
            write_series(directory / "states", frames, fields=output.vtu_fields)
        kept = frames if output.vtu else frames[: len(outcome.recorder.states)]
        rendered = {"none": [], "last": frames[-1:], "all": kept}[output.png]
        options = Options.of(output.render)
        for k, frame in enumerate(rendered):
            _render(model, frame, directory / f"render_{k:06d}.png", options)
        if output.animation != "none":
            animate(
                directory / f"animation.{output.animation}",
                frames,
                model.scene.title,
                model.forces,
                options,
                output.render.fps,
            )

    replace_directory(out, fill, OUTPUT_MARKER)
    if outcome.checkpoints is not None and not outcome.interrupted:
        outcome.checkpoints.remove()


def keeps_states(output: Output) -> bool:
    """Whether the outputs need the kept states (VTU, every render, an animation)."""
    return output.vtu or output.png == "all" or output.animation != "none"


def _render(model: Model, frame: Frame, path: Path, options: Options) -> None:
    title = f"{model.scene.title or 'scene'}: t = {frame.time:.4g} s"
    render_frame(path, frame, title, model.forces, options)
