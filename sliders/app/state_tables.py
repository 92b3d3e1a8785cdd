"""The tables of one solved state, defined once for statics and dynamics.

Each table (``nodes``, ``sliders``, ``internal_forces``, ``reactions``; columns in
:data:`STATE_COLUMNS`, documented in ``docs/scenes.md``) is a function of a
:class:`Snapshot`: a static study writes its rows after ``sample, value``
(:mod:`sliders.app.tables`), a dynamic one after ``step, t`` (:data:`STEP_COLUMNS`,
:class:`sliders.app.history.Recorder`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES, Support
from sliders.app.vtu import contact_point
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
    resolved = structure.resolve_node(support.ref)
    if isinstance(resolved, str):
        return resolved
    beam = structure.beams[resolved[0]]
    ends = {beam.node_index(end): end for end in ("start", "end")}
    return f"{beam.mesh.name}.{ends.get(resolved[1], resolved[1])}"


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
