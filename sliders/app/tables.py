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
  reference position, then its displacement and small rotation
* ``sliders``: ``slider, xi, x, y, z, lambda_x, lambda_y, lambda_z, mu_2, mu_3, mu_1`` --
  the abscissa of the contact, its deformed position, the reaction force on the body and the
  multipliers of the orientation constraints
* ``internal_forces``: ``beam, xi,`` :data:`FORCE_NAMES` -- at the beam's recovery points,
  in the section frame ``(t, e2, e3)``: axial force, shears, twisting and bending moments
* ``reactions``: ``node, fx, fy, fz, mx, my, mz`` -- what each support (and, in a dynamic
  study, each dof drive) exerts on its node, global axes, on the dofs it holds

A static run writes its tables, ``scene.toml`` (the scene as it was validated) and the
states and renders the scene asks for (``states/states.pvd`` with
``states/step_NNNNNN.vtu``, one per converged sample, the sample's value as its time, or its
index for a static study or repeated values; ``render_NNNNNN.png``) into a new directory
that then replaces the output directory (:func:`fvbeam.io.replace_directory`).
"""

from __future__ import annotations

import csv
import importlib.util
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fvbeam.io import OUTPUT_MARKER as MARKER
from fvbeam.io import replace_directory
from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES, Support
from sliders.app.run import Results, Sample
from sliders.app.scene import dump_scene
from sliders.app.vtu import Frame, contact_point, write_series
from sliders.joints.slider import UNKNOWNS, Slider

#: Internal forces in the section frame ``(t, e2, e3)``: axial force, shears along e2 and
#: e3, twisting moment, bending moments about e2 and e3 (static and dynamic tables alike).
FORCE_NAMES = ("N", "V2", "V3", "T", "M2", "M3")
#: The columns of the tables of one solved state, after the head.
STATE_COLUMNS = {
    "nodes": ("part", "xi", "x", "y", "z", *DOF_NAMES),
    "sliders": ("slider", UNKNOWNS[0], "x", "y", "z", *UNKNOWNS[1:]),
    "internal_forces": ("beam", "xi", *FORCE_NAMES),
    "reactions": ("node", "fx", "fy", "fz", "mx", "my", "mz"),
}
#: Columns of the tables of a static study or a sweep: a row per sample and item.
COLUMNS = {
    "samples": ("sample", "value", "converged", "iterations", "error"),
    **{name: ("sample", "value", *columns) for name, columns in STATE_COLUMNS.items()},
}
#: Columns of the per-step tables of a dynamic study: a row per time step and item.
STEP_COLUMNS = {name: ("step", "t", *columns) for name, columns in STATE_COLUMNS.items()}


@dataclass(frozen=True)
class Snapshot:
    """One solved state, as the tables read it.

    ``residual`` is the structure's own equations without the supports and joints: ``K q -
    f`` in statics, ``M qdd + C v + K q - f`` in dynamics.  On a held dof, that less the
    force the joints exert there is the support's reaction.
    """

    structure: Structure
    q: np.ndarray
    sliders: Sequence[Slider]
    unknowns: Sequence[np.ndarray]
    supports: Sequence[Support]
    residual: np.ndarray


def node_label(structure: Structure, support: Support) -> str:
    """A support's node as a scene names it: ``BEAM.start``, ``BEAM.end`` (``BEAM.k`` for
    an inner node ``k``) with ``BEAM`` the beam's mesh name, or the body's name."""
    if isinstance(support.beam, str):
        return support.beam
    beam = structure.beams[support.beam]
    ends = {beam.node_index(end): end for end in ("start", "end")}
    return f"{beam.mesh.name}.{ends.get(beam.node_index(support.node), support.node)}"


def _nodes_rows(state: Snapshot) -> Iterator[list]:
    structure, q = state.structure, state.q
    for i, beam in enumerate(structure.beams):
        mesh = beam.mesh
        u = structure.local(i, q).reshape(-1, 6)
        xi = mesh.node_abscissae()
        for k in np.argsort(xi, kind="stable"):
            yield [mesh.name, xi[k], *mesh.points[k], *u[k]]
    for body in structure.bodies:
        yield [body.name, None, *body.position, *q[structure.node_dofs(body.name)]]


def _sliders_rows(state: Snapshot) -> Iterator[list]:
    for slider, y in zip(state.sliders, state.unknowns, strict=True):
        x = np.sum(contact_point(slider, state.q, y), axis=0)
        mu = list(y[4:]) + [None] * (len(UNKNOWNS) - len(y))
        yield [slider.name, float(y[0]), *x, *y[1:4], *mu]


def _internal_forces_rows(state: Snapshot) -> Iterator[list]:
    structure = state.structure
    for i, beam in enumerate(structure.beams):
        forces = beam.internal_forces(structure.local(i, state.q))
        for xi, f, m in zip(forces.xi, forces.force, forces.moment, strict=True):
            yield [beam.mesh.name, xi, *f, *m]


def _reactions_rows(state: Snapshot) -> Iterator[list]:
    structure = state.structure
    held = state.residual.copy()
    for slider, y in zip(state.sliders, state.unknowns, strict=True):
        dofs, r_q, _, _ = slider.assemble(structure, state.q, y)
        np.add.at(held, dofs, r_q)
    for support in state.supports:
        dofs = support.dofs()
        values: list = [None] * 6
        for c, dof in zip(dofs, structure.node_dofs(support.ref)[dofs], strict=True):
            values[c] = held[dof]
        yield [node_label(structure, support), *values]


#: Rows of the tables of one solved state, without the head.
STATE_ROWS: dict[str, Callable[[Snapshot], Iterator[list]]] = {
    "nodes": _nodes_rows,
    "sliders": _sliders_rows,
    "internal_forces": _internal_forces_rows,
    "reactions": _reactions_rows,
}


def cell(value) -> str:
    """A table cell: blank for ``None``, floats in full precision (``repr``)."""
    if value is None:
        return ""
    return repr(float(value)) if isinstance(value, (float, np.floating)) else str(value)


def _samples_rows(results: Results) -> Iterator[list]:
    for s in results.samples:
        converged = s.solution is not None
        yield [
            s.index,
            s.value,
            str(converged).lower(),
            s.solution.iterations if converged else None,
            s.error,
        ]


def _snapshot(results: Results, sample: Sample) -> Snapshot:
    statics, solution = sample.statics, sample.solution
    return Snapshot(
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        results.model.supports,
        statics.K @ solution.q - sample.load,
    )


def _rows(results: Results, name: str) -> Iterator[list]:
    if name == "samples":
        yield from _samples_rows(results)
        return
    for sample in _converged(results):
        for row in STATE_ROWS[name](_snapshot(results, sample)):
            yield [sample.index, sample.value, *row]


def _converged(results: Results) -> Iterator[Sample]:
    return (s for s in results.samples if s.solution is not None)


def write_table(results: Results, name: str, path: Path) -> None:
    """Write the table ``name`` of ``results`` to ``path``."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS[name])
        for row in _rows(results, name):
            writer.writerow([cell(v) for v in row])


def write_results(results: Results, out: str | Path, tables: Sequence[str] | None = None) -> None:
    """Write ``tables`` (default: the scene's ``output.csv``) and ``scene.toml`` into a new
    directory that replaces ``out`` whole."""
    output = results.scene.output
    tables = output.csv if tables is None else tables
    converged = list(_converged(results))
    rendered = {"none": [], "last": converged[-1:], "all": converged}[output.png]
    if rendered and importlib.util.find_spec("pyvista") is None:
        raise ValueError("output.png needs pyvista: pip install 'fvslider[render]'")

    def fill(directory: Path) -> None:
        (directory / "scene.toml").write_text(dump_scene(results.scene))
        for name in tables:
            write_table(results, name, directory / f"{name}.csv")
        if output.vtu:
            write_series(directory / "states", (_frame(s, converged) for s in converged))
        for sample in rendered:
            _render(sample, directory / f"render_{sample.index:06d}.png", results.scene.title)

    replace_directory(out, fill, MARKER)


def _held(sample: Sample) -> np.ndarray:
    """The dofs the supports hold at ``sample``."""
    statics = sample.statics
    return np.setdiff1d(np.arange(statics.structure.n_dofs), statics.free)


def _frame(sample: Sample, converged: list[Sample]) -> Frame:
    """A converged sample as a state of the series: its value as the time, or its index when
    the values are absent or repeat."""
    values = [s.value for s in converged]
    distinct = None not in values and len(set(values)) == len(values)
    statics, solution = sample.statics, sample.solution
    return Frame(
        float(sample.value) if distinct else float(sample.index),
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        _held(sample),
    )


def _render(sample: Sample, path: Path, title: str) -> None:
    from sliders.app.render import render

    value = "" if sample.value is None else f", value {sample.value:g}"
    statics, solution = sample.statics, sample.solution
    render(
        path,
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        title=f"{title or 'scene'}: sample {sample.index}{value}",
        held=_held(sample),
    )
