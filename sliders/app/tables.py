"""CSV tables of a run, tidy: one row per sample and per node, slider, recovery point or
support (``docs/scenes.md`` documents every column).  Units SI; a blank cell is a value that
does not apply (the ``value`` of a static study, ``mu_1`` of a classical slider, the free
components of a support).

* ``samples``: ``sample, value, converged, iterations, error``
* ``nodes``: ``sample, value, part, xi, x, y, z, ux, uy, uz, rx, ry, rz`` -- every beam node
  (in order along the beam, ``xi`` its abscissa) and every body (``xi`` blank); ``x, y, z``
  its reference position at that sample, then its displacement and small rotation
* ``sliders``: ``sample, value, slider, xi, x, y, z, lambda_x, lambda_y, lambda_z, mu_2,
  mu_3, mu_1`` -- the abscissa of the contact, its deformed position, the reaction force on
  the body and the couples of the orientation constraints
* ``internal_forces``: ``sample, value, beam, xi, N, V2, V3, T, M2, M3`` -- at the beam's
  recovery points, in the section frame ``(t, e2, e3)``: axial force, shears, twisting and
  bending moments
* ``reactions``: ``sample, value, node, fx, fy, fz, mx, my, mz`` -- what each support exerts
  on its node, global axes, on the dofs it holds

A run writes its tables, ``scene.toml`` (the scene as it was validated) and the states and
renders the scene asks for (``states/states.pvd`` with ``states/step_NNNNNN.vtu``, one per
converged sample, the sample's value as its time, or its index for a static study or
repeated values; ``render_NNNNNN.png``) into a new directory that then replaces the output
directory (:func:`fvbeam.io.replace_directory`).
"""

from __future__ import annotations

import csv
import importlib.util
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from fvbeam.io import OUTPUT_MARKER as MARKER
from fvbeam.io import replace_directory
from sliders.app.run import Results, Sample
from sliders.app.scene import dump_scene
from sliders.app.vtu import Frame, contact_point, write_series
from sliders.solve.statics import SliderSolution, SliderStatics

COLUMNS = {
    "samples": ("sample", "value", "converged", "iterations", "error"),
    "nodes": ("sample", "value", "part", "xi", "x", "y", "z", "ux", "uy", "uz", "rx", "ry", "rz"),
    "sliders": (
        "sample",
        "value",
        "slider",
        "xi",
        "x",
        "y",
        "z",
        "lambda_x",
        "lambda_y",
        "lambda_z",
        "mu_2",
        "mu_3",
        "mu_1",
    ),
    "internal_forces": ("sample", "value", "beam", "xi", "N", "V2", "V3", "T", "M2", "M3"),
    "reactions": ("sample", "value", "node", "fx", "fy", "fz", "mx", "my", "mz"),
}


def _head(sample: Sample) -> list:
    return [sample.index, sample.value]


def _samples_rows(results: Results) -> Iterator[list]:
    for s in results.samples:
        converged = s.solution is not None
        yield _head(s) + [
            str(converged).lower(),
            s.solution.iterations if s.solution is not None else None,
            s.error,
        ]


def _nodes_rows(results: Results) -> Iterator[list]:
    for s in _converged(results):
        statics, solution = _solved(s)
        structure, q = statics.structure, solution.q
        for i, spec in enumerate(results.scene.beam):
            mesh = structure.beams[i].mesh
            u = structure.local(i, q).reshape(-1, 6)
            xi = mesh.node_abscissae()
            for k in np.argsort(xi, kind="stable"):
                yield _head(s) + [spec.name, xi[k], *mesh.points[k], *u[k]]
        for body in structure.bodies:
            yield _head(s) + [body.name, None, *body.position, *q[structure.node_dofs(body.name)]]


def _sliders_rows(results: Results) -> Iterator[list]:
    for s in _converged(results):
        statics, solution = _solved(s)
        q = solution.q
        for slider, y in zip(statics.sliders, solution.unknowns, strict=True):
            x = np.sum(contact_point(slider, q, y), axis=0)
            mu = list(y[4:]) + [None] * (7 - len(y))
            yield _head(s) + [slider.name, float(y[0]), *x, *y[1:4], *mu]


def _internal_forces_rows(results: Results) -> Iterator[list]:
    for s in _converged(results):
        statics, solution = _solved(s)
        structure = statics.structure
        for i, spec in enumerate(results.scene.beam):
            forces = structure.beams[i].internal_forces(structure.local(i, solution.q))
            for xi, f, m in zip(forces.xi, forces.force, forces.moment, strict=True):
                yield _head(s) + [spec.name, xi, *f, *m]


def _reactions_rows(results: Results) -> Iterator[list]:
    for s in _converged(results):
        statics, solution = _solved(s)
        structure, q = statics.structure, solution.q
        residual = statics.K @ q - s.load
        for slider, y in zip(statics.sliders, solution.unknowns, strict=True):
            dofs, r_q, _, _ = slider.assemble(structure, q, y)
            np.add.at(residual, dofs, r_q)
        for spec, support in zip(results.scene.support, results.model.supports, strict=True):
            held = support.dofs()
            values: list = [None] * 6
            for c, dof in zip(held, structure.node_dofs(support.ref)[held], strict=True):
                values[c] = residual[dof]
            yield _head(s) + [spec.node, *values]


def _converged(results: Results) -> Iterator[Sample]:
    return (s for s in results.samples if s.solution is not None)


def _solved(sample: Sample) -> tuple[SliderStatics, SliderSolution]:
    """The statics and the solution of a converged sample."""
    assert sample.statics is not None and sample.solution is not None, "not converged"
    return sample.statics, sample.solution


ROWS = {
    "samples": _samples_rows,
    "nodes": _nodes_rows,
    "sliders": _sliders_rows,
    "internal_forces": _internal_forces_rows,
    "reactions": _reactions_rows,
}


def _cell(value) -> str:
    if value is None:
        return ""
    return repr(float(value)) if isinstance(value, (float, np.floating)) else str(value)


def write_table(results: Results, name: str, path: Path) -> None:
    """Write the table ``name`` of ``results`` to ``path``."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS[name])
        for row in ROWS[name](results):
            writer.writerow([_cell(v) for v in row])


def write_results(results: Results, out: str | Path, tables: Sequence[str] | None = None) -> None:
    """Write ``tables`` (default: the scene's ``output.csv``) and ``scene.toml`` into a new
    directory that replaces ``out`` whole."""
    output = results.scene.output
    tables = output.csv if tables is None else tables
    converged = [s for s in results.samples if s.solution is not None]
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
    )


def _render(sample: Sample, path: Path, title: str) -> None:
    from sliders.app.render import render

    value = "" if sample.value is None else f", value {sample.value:g}"
    statics, solution = _solved(sample)
    render(
        path,
        statics.structure,
        solution.q,
        statics.sliders,
        solution.unknowns,
        title=f"{title or 'scene'}: sample {sample.index}{value}",
    )
