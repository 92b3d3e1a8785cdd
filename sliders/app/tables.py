"""CSV tables of a run, tidy: one row per sample (or time step) and per node, slider,
recovery point or support (``docs/scenes.md`` documents every column).  Units SI; a blank
cell is a value that does not apply (the ``value`` of a static study, ``mu_1`` of a
classical slider, the free components of a support).

Every table but ``samples`` describes one solved state, and is written the same way by a
static study or a sweep (its rows start with ``sample, value``: :data:`COLUMNS`) and by a
dynamic study, one set of rows per time step (``step, t``: :data:`STEP_COLUMNS`,
:class:`sliders.app.history.Recorder`).  After that head:

* ``samples`` (static and sweep only; a dynamic study's ``history.csv`` takes its place):
  ``converged, iterations, error``
* ``nodes``: ``part, xi, x, y, z, ux, uy, uz, rx, ry, rz`` -- every beam node (in order
  along the beam, ``xi`` its abscissa) and every body (``xi`` blank); ``x, y, z`` its
  reference position, then its displacement and small rotation (with exact kinematics the
  rotation vector, :mod:`sliders.app.kinematics`)
* ``sliders``: ``slider, xi, x, y, z, lambda_x, lambda_y, lambda_z, mu_2, mu_3, mu_1`` --
  the abscissa of the contact, its deformed position, the reaction force on the body and the
  multipliers of the orientation constraints
* ``internal_forces``: ``beam, xi,`` :data:`FORCE_NAMES`, :data:`GLOBAL_FORCE_NAMES` -- at
  the beam's recovery points, in the section frame ``(t, e2, e3)``: axial force, shears,
  twisting and bending moments; then force and moment in global axes
* ``reactions``: ``node, fx, fy, fz, mx, my, mz`` -- what each support (and, in a dynamic
  study, each dof drive) exerts on its node, global axes, on the dofs it holds
* ``joints`` (a scene with ``[[joint]]`` tables, always written):
  ``joint, node, fx, fy, fz, mx, my, mz`` -- what each joint exerts on each of its nodes
  (not the ground), couples about the node, global axes (:mod:`sliders.app.scene_joints`)

A static run writes its tables, ``scene.toml`` (the scene as it was validated) and the
states and renders the scene asks for (``states/states.pvd`` with
``states/step_NNNNNN.vtu``, one per converged sample, the sample's value as its time, or its
index for a static study or repeated values; ``render_NNNNNN.png``) into a new directory
that then replaces the output directory (:func:`fvbeam.io.replace_directory`).
"""

from __future__ import annotations

import csv
import importlib.util
import io
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from fvbeam.io import OUTPUT_MARKER as MARKER
from fvbeam.io import replace_directory
from fvbeam.support import complement
from sliders.app.run import Results, Sample
from sliders.app.scene import dump_scene
from sliders.app.scene_joints import write_joints
from sliders.app.schema import ModesStudy, Scene
from sliders.app.state_tables import (
    STATE_COLUMNS,
    Selection,
    Snapshot,
    cell,
    lines,
    quote,
    state_table,
)
from sliders.app.vtu import Frame, write_series
from sliders.solve.statics import SliderSolution, SliderStatics

if TYPE_CHECKING:  # the modes' writing is imported by a modes study only
    from sliders.app.run_modes import Animator, Painter

#: Columns of the tables of a static study or a sweep: a row per sample and item.
COLUMNS = {
    "samples": ("sample", "value", "converged", "iterations", "error"),
    **{name: ("sample", "value", *columns) for name, columns in STATE_COLUMNS.items()},
}


def _samples_rows(results: Results) -> Iterator[list]:
    for s in results.samples:
        converged = s.solution is not None
        yield [
            s.index,
            s.value,
            str(converged).lower(),
            s.solution.iterations if s.solution is not None else None,
            s.error,
        ]


def _snapshot(results: Results, sample: Sample) -> Snapshot:
    """A converged sample as the tables read it; with exact kinematics its residual and
    section forces are the exact state's (:class:`sliders.app.kinematics.ExactSolution`)."""
    statics, solution = _solved(sample)
    internal = getattr(solution, "internal", None)
    return Snapshot(
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        results.model.supports,
        (statics.K @ solution.q if internal is None else internal) - sample.load,
        getattr(solution, "forces", None),
        internal is not None,
    )


def _lines(results: Results, name: str, selection: Selection | None) -> Iterator[str]:
    """The CSV lines of table ``name``'s rows, sample by sample."""
    if name == "samples":
        for row in _samples_rows(results):
            buffer = io.StringIO()
            csv.writer(buffer).writerow([cell(v) for v in row])
            yield buffer.getvalue()[:-2]
        return
    for sample in _converged(results):
        snapshot = _snapshot(results, sample)
        table = state_table(
            name, snapshot.structure, snapshot.sliders, snapshot.supports, selection
        )
        head = f"{sample.index},{cell(sample.value)}"
        labels = [quote(label) for label in table.labels]
        body = lines(table.values(snapshot), table.blank)
        for label, line in zip(labels, body, strict=True):
            yield f"{head},{label},{line}" if table.blank.shape[1] else f"{head},{label}"


def _converged(results: Results) -> Iterator[Sample]:
    return (s for s in results.samples if s.solution is not None)


def _solved(sample: Sample) -> tuple[SliderStatics, SliderSolution]:
    """The statics and the solution of a converged sample."""
    assert sample.statics is not None and sample.solution is not None, "not converged"
    return sample.statics, sample.solution


def write_table(
    results: Results, name: str, path: Path, selection: Selection | None = None
) -> None:
    """Write the table ``name`` of ``results`` to ``path``: the rows and columns of
    ``selection`` (default all)."""
    model = results.model
    header = COLUMNS[name][:2] + (
        COLUMNS[name][2:]
        if name == "samples"
        else state_table(name, model.structure, model.sliders, model.held(), selection).columns
    )
    with open(path, "w", newline="") as handle:
        csv.writer(handle).writerow(header)
        handle.writelines(line + "\r\n" for line in _lines(results, name, selection))


def write_results(results: Results, out: str | Path, tables: Sequence[str] | None = None) -> None:
    """Write ``tables`` (default: the scene's ``output.csv``) and ``scene.toml`` into a new
    directory that replaces ``out`` whole."""
    output = results.scene.output
    tables = output.csv if tables is None else tables
    selections = results.model.selections()
    converged = list(_converged(results))
    rendered = {"none": [], "last": converged[-1:], "all": converged}[output.png]
    if rendered and importlib.util.find_spec("pyvista") is None:
        raise ValueError("output.png needs pyvista: pip install 'fvslider[render]'")

    def fill(directory: Path) -> None:
        (directory / "scene.toml").write_text(dump_scene(results.scene))
        for name in tables:
            if name != "modes":
                write_table(results, name, directory / f"{name}.csv", selections.get(name))
        study = results.scene.study
        if results.modes is not None and isinstance(study, ModesStudy):
            from sliders.app.run_modes import write_modes

            default = "csv" not in output.model_fields_set
            sweep = study.parameter is not None
            write_modes(
                results.modes,
                directory,
                default or "modes" in tables,
                sweep,
                _animator(results),
                _painter(results, rendered),
            )
        if results.scene.joint:
            write_joints(directory / "joints.csv", results.scene, converged)
        if output.vtu:
            write_series(
                directory / "states",
                (_frame(s, converged) for s in converged),
                fields=output.vtu_fields,
            )
        for sample in rendered:
            _render(sample, directory / f"render_{sample.index:06d}.png", results.scene)

    replace_directory(out, fill, MARKER)


def _animator(results: Results) -> tuple[str, Animator] | None:
    """The format of ``output.animation`` and what writes an animation of the scene (its
    force elements and render options), or None without one."""
    output = results.scene.output
    if output.animation == "none":
        return None
    from sliders.app.render import Options, animate

    options = Options.of(output.render)

    def write(path: Path, frames: Sequence[Frame], title: str) -> object:
        heading = f"{results.scene.title}, {title}" if results.scene.title else title
        return animate(path, frames, heading, results.model.forces, options, output.render.fps)

    return output.animation, write


def _painter(results: Results, rendered: list[Sample]) -> tuple[set[int], Painter] | None:
    """The indices of the ``rendered`` samples and what renders a mode of one (the scene's
    force elements and render options), or None without any."""
    if not rendered:
        return None
    from sliders.app.render import Options, render_frame

    scene = results.scene
    options = Options.of(scene.output.render)

    def paint(path: Path, frame: Frame, title: str) -> object:
        heading = f"{scene.title or 'scene'}: {title}"
        return render_frame(path, frame, heading, results.model.forces, options)

    return {sample.index for sample in rendered}, paint


def _held(sample: Sample) -> np.ndarray:
    """The dofs the supports hold at ``sample``."""
    statics, _ = _solved(sample)
    return complement(statics.structure.n_dofs, statics.free)


def _frame(sample: Sample, converged: list[Sample]) -> Frame:
    """A converged sample as a state of the series: its value as the time, or its index when
    the values are absent or repeat."""
    values = [s.value for s in converged]
    distinct = None not in values and len(set(values)) == len(values)
    statics, solution = _solved(sample)
    return Frame(
        float(sample.value) if distinct and sample.value is not None else float(sample.index),
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        _held(sample),
        getattr(solution, "forces", None),
    )


def _render(sample: Sample, path: Path, scene: Scene) -> None:
    from sliders.app.render import Options, render

    value = "" if sample.value is None else f", value {sample.value:g}"
    statics, solution = _solved(sample)
    options = Options.of(scene.output.render)
    render(
        path,
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        options.magnification,
        f"{scene.title or 'scene'}: sample {sample.index}{value}",
        view=options.view,
        window_size=options.window_size,
        held=_held(sample),
        forces=statics.forces,
        follow=options.follow,
        section_forces=getattr(solution, "forces", None),
    )
