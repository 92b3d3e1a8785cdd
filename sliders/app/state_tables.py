"""The tables of one solved state, defined once for statics and dynamics.

Each table (``nodes``, ``sliders``, ``internal_forces``, ``reactions``; columns in
:data:`STATE_COLUMNS`, documented in ``docs/scenes.md``) is a :class:`StateTable` built once
for a structure, its sliders and supports, and a :class:`Selection` of its items (the nodes,
sliders, beams or held nodes its rows are for) and columns.  Its rows are fixed: a label,
the key columns that tell the rows apart (``xi`` of a node or recovery point), which cells
are blank; :meth:`StateTable.values` computes their numbers for a :class:`Snapshot` in a few
array operations (the nodes' dofs gathered by one index, the internal forces of every asked
recovery point by one product with the beams' recovery maps,
:attr:`fvbeam.beam.Beam.recovery`).  A static study writes its rows after ``sample, value``
(:mod:`sliders.app.tables`), a dynamic one after ``step, t`` (:data:`STEP_COLUMNS`,
:class:`sliders.app.history.Recorder`), and :func:`lines` turns a block of rows into CSV
lines at once.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fvbeam.beam import InternalForces
from fvbeam.names import suggest
from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES, Support
from sliders.joints.slider import UNKNOWNS, Slider
from sliders.lines.chain import BeamChain

#: Internal forces in the section frame ``(t, e2, e3)``: axial force, shears along e2 and
#: e3, twisting moment, bending moments about e2 and e3 (static and dynamic tables alike).
FORCE_NAMES = ("N", "V2", "V3", "T", "M2", "M3")
#: The same internal forces in global axes: force and moment.
GLOBAL_FORCE_NAMES = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: Components of a reaction, global axes.
REACTION_NAMES = ("fx", "fy", "fz", "mx", "my", "mz")
#: The columns of the tables of one solved state, after the head.
STATE_COLUMNS = {
    "nodes": ("part", "xi", "x", "y", "z", *DOF_NAMES),
    "sliders": ("slider", UNKNOWNS[0], "x", "y", "z", *UNKNOWNS[1:]),
    "internal_forces": ("beam", "xi", *FORCE_NAMES, *GLOBAL_FORCE_NAMES),
    "reactions": ("node", *REACTION_NAMES),
}
#: The columns that tell a table's rows apart, always written: the rest can be chosen.
KEY_COLUMNS = {
    "nodes": ("part", "xi"),
    "sliders": ("slider",),
    "internal_forces": ("beam", "xi"),
    "reactions": ("node",),
}
#: The columns a :class:`Selection` chooses from, per table.
CHOICES = {
    name: tuple(c for c in columns if c not in KEY_COLUMNS[name])
    for name, columns in STATE_COLUMNS.items()
}
#: Columns of the per-step tables of a dynamic study: a row per time step and item.
STEP_COLUMNS = {name: ("step", "t", *columns) for name, columns in STATE_COLUMNS.items()}


@dataclass(frozen=True)
class Selection:
    """Which rows and columns of a table to write: ``items`` names the nodes (a beam's or
    body's name for all its nodes, ``BEAM.start``, ``BEAM.end``), sliders, beams or held
    nodes (``reactions``) the rows are for, ``columns`` the columns after the key columns
    (:data:`CHOICES`); None: all.  Rows and columns keep the table's order."""

    items: tuple[str, ...] | None = None
    columns: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Snapshot:
    """One solved state, as the tables read it.

    ``residual`` is the structure's own equations without the supports and joints: ``K q -
    f`` in statics, ``M qdd + C v + K q - f`` in dynamics.  On a held dof, that less the
    force the joints exert there is the support's reaction (None: not computed, no
    ``reactions`` table).  ``section_forces``: each beam's section forces at its recovery points
    when they are not the linear map of ``q`` (a state of exact kinematics).
    ``sliders_in_residual``: the residual holds the sliders' forces already (a state of
    exact kinematics), else the reactions add them.
    """

    structure: Structure
    q: np.ndarray
    sliders: Sequence[Slider]
    unknowns: Sequence[np.ndarray]
    supports: Sequence[Support]
    residual: np.ndarray | None = None
    section_forces: Sequence[InternalForces] | None = None
    sliders_in_residual: bool = False


@dataclass(frozen=True)
class StateTable:
    """A table's rows for one structure and selection: ``columns`` after the head (the label
    column first), a ``label`` per row, the ``blank`` cells of the numeric columns (rows,
    columns - 1), and ``values(snapshot)``, the numbers (NaN where blank).  ``fixed``: the
    leading numeric columns every state shares (rows, k), as ``values`` gives them (a node's
    abscissa and reference position, a recovery point's abscissa): a recording of many
    states keeps and formats them once."""

    name: str
    columns: tuple[str, ...]
    labels: list[str]
    blank: np.ndarray
    values: Callable[[Snapshot], np.ndarray]
    fixed: np.ndarray

    @property
    def n_rows(self) -> int:
        return len(self.labels)


def contact_point(slider: Slider, q: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference point and displacement of the line at the slider's ``xi``; their sum is
    the deformed contact point ``x(xi)``."""
    xi = float(y[0])
    if isinstance(slider.line, BeamChain):
        interp = slider.line.interpolation(xi)
        return interp.reference[0], interp.N @ q[interp.dofs]
    return slider.line.at(xi).x, np.zeros(3)


def node_label(structure: Structure, support: Support) -> str:
    """A support's node as a scene names it: ``BEAM.start``, ``BEAM.end`` (``BEAM.k`` for
    an inner node ``k``) with ``BEAM`` the beam's mesh name, or the body's name."""
    resolved = structure.resolve_node(support.ref)
    if isinstance(resolved, str):
        return resolved
    beam = structure.beams[resolved[0]]
    ends = {beam.node_index(end): end for end in ("start", "end")}
    return f"{beam.mesh.name}.{ends.get(resolved[1], resolved[1])}"


def state_table(
    name: str,
    structure: Structure,
    sliders: Sequence[Slider] = (),
    supports: Sequence[Support] = (),
    selection: Selection | None = None,
) -> StateTable:
    """The table ``name`` of states of ``structure`` with ``sliders`` and ``supports``, its
    rows and columns as ``selection`` asks (default all); ``ValueError`` naming an unknown
    table, item or column, with a did-you-mean."""
    if name not in STATE_COLUMNS:
        raise ValueError(
            f"table {name!r}: must be one of {', '.join(STATE_COLUMNS)}"
            f"{suggest(name, STATE_COLUMNS)}"
        )
    selection = selection or Selection()
    chosen = _chosen(name, selection.columns)
    known = items(name, structure, sliders, supports)
    if selection.items is not None:
        for i, item in enumerate(selection.items):
            if item not in known:
                raise ValueError(
                    f"{name} items[{i}] = {item!r}: no such item{suggest(item, known)}"
                )
    wanted = None if selection.items is None else set(selection.items)
    build = {
        "nodes": _nodes,
        "sliders": _sliders,
        "internal_forces": _internal_forces,
        "reactions": _reactions,
    }[name]
    labels, blank, values, fixed = build(structure, sliders, supports, wanted, chosen)
    columns = KEY_COLUMNS[name] + tuple(CHOICES[name][c] for c in chosen)
    return StateTable(name, columns, labels, blank, values, fixed)


def items(
    name: str, structure: Structure, sliders: Sequence[Slider], supports: Sequence[Support]
) -> list[str]:
    """The names a :class:`Selection` of table ``name`` may list."""
    if name == "nodes":
        beams = [beam.mesh.name for beam in structure.beams]
        ends = [f"{b}.{end}" for b in beams for end in ("start", "end")]
        return beams + ends + [body.name for body in structure.bodies]
    if name == "sliders":
        return [s.name for s in sliders]
    if name == "internal_forces":
        return [beam.mesh.name for beam in structure.beams]
    return list(dict.fromkeys(node_label(structure, s) for s in supports))


def _chosen(name: str, columns: Sequence[str] | None) -> np.ndarray:
    """Indices in :data:`CHOICES` of the chosen columns, in the table's order."""
    choices = CHOICES[name]
    if columns is None:
        return np.arange(len(choices))
    for i, column in enumerate(columns):
        if column not in choices:
            hint = "a key column, always written" if column in KEY_COLUMNS[name] else None
            raise ValueError(
                f"{name} columns[{i}] = {column!r}: "
                + (hint or f"must be one of {', '.join(choices)}{suggest(column, choices)}")
            )
    return np.array([i for i, c in enumerate(choices) if c in columns], dtype=int)


Built = tuple[list[str], np.ndarray, Callable[[Snapshot], np.ndarray], np.ndarray]


def _nodes(structure, sliders, supports, wanted, chosen) -> Built:
    """Every beam node (in order along its beam) and every body: ``xi, x, y, z`` of the
    reference configuration (the structure's: a sweep's moved parts moved) and the dofs."""
    labels, keyed, dofs = [], [], []
    for i, beam in enumerate(structure.beams):
        mesh = beam.mesh
        ends = {f"{mesh.name}.{end}": beam.node_index(end) for end in ("start", "end")}
        xi = mesh.node_abscissae()
        for k in np.argsort(xi, kind="stable"):
            if (
                wanted is None
                or mesh.name in wanted
                or any(ends[e] == k for e in ends if e in wanted)
            ):
                labels.append(mesh.name)
                keyed.append([xi[k], *mesh.points[k]])
                dofs.append(structure.dof_maps[i][6 * k : 6 * k + 6])
    for body in structure.bodies:
        if wanted is None or body.name in wanted:
            labels.append(body.name)
            keyed.append([np.nan, *body.position])
            dofs.append(structure.node_dofs(body.name))
    fixed = np.array(keyed, dtype=float).reshape(-1, 4)
    # the chosen columns among x, y, z (fixed) and the six dofs (gathered from q)
    places = fixed[:, 1 + chosen[chosen < 3]]
    index = np.array(dofs, dtype=int).reshape(-1, 6)[:, chosen[chosen >= 3] - 3]
    head = np.concatenate([fixed[:, :1], places], axis=1)
    blank = np.zeros((len(labels), 1 + len(chosen)), dtype=bool)
    blank[:, 0] = np.isnan(fixed[:, 0])

    def values(state: Snapshot) -> np.ndarray:
        return np.concatenate([head, state.q[index]], axis=1)

    return labels, blank, values, head


def _sliders(structure, sliders, supports, wanted, chosen) -> Built:
    """Each slider's ``xi``, contact point ``x, y, z`` (deformed) and multipliers."""
    rows = [j for j, s in enumerate(sliders) if wanted is None or s.name in wanted]
    labels = [sliders[j].name for j in rows]
    # columns (CHOICES order): xi, x, y, z, then y[1:], blank beyond the slider's unknowns
    width = len(CHOICES["sliders"])
    blank = np.zeros((len(rows), width), dtype=bool)
    for r, j in enumerate(rows):
        blank[r, 3 + sliders[j].n_unknowns :] = True
    blank = blank[:, chosen]
    contact = bool(np.isin(chosen, [1, 2, 3]).any())

    def values(state: Snapshot) -> np.ndarray:
        out = np.full((len(rows), width), np.nan)
        for r, j in enumerate(rows):
            y = np.asarray(state.unknowns[j], dtype=float)
            out[r, 0] = y[0]
            out[r, 4 : 3 + len(y)] = y[1:]
            if contact:
                out[r, 1:4] = np.sum(contact_point(sliders[j], state.q, y), axis=0)
        return out[:, chosen]

    return labels, blank, values, np.zeros((len(labels), 0))


def _internal_forces(structure, sliders, supports, wanted, chosen) -> Built:
    """The section forces at every recovery point of the asked beams, in the section frame
    and in global axes: the rows of their recovery maps (the global ones turned by the
    points' section frames) that the chosen columns need, on the global dofs, stacked, one
    product; or, for a state that carries its forces (exact kinematics), those."""
    labels, xis, blocks, asked = [], [], [], []
    for i, beam in enumerate(structure.beams):
        if wanted is None or beam.mesh.name in wanted:
            R, xi = beam.recovery, beam.recovery_abscissae
            both = sp.vstack([R, _turned(R, beam.recovery_frames)], format="csr")
            points = np.arange(len(xi))[:, None]
            rows = np.where(chosen < 6, 6 * points + chosen, 6 * (len(xi) + points) + chosen - 6)
            block = both[rows.ravel()].tocoo()
            blocks.append(
                sp.csr_matrix(
                    (block.data, (block.row, structure.dof_maps[i][block.col])),
                    shape=(rows.size, structure.n_dofs),
                )
            )
            labels += [beam.mesh.name] * len(xi)
            xis.append(xi)
            asked.append(i)
    n = len(labels)
    R = sp.vstack(blocks, format="csr") if blocks else sp.csr_matrix((0, structure.n_dofs))
    xi = np.concatenate(xis)[:, None] if xis else np.zeros((0, 1))
    blank = np.zeros((n, 1 + len(chosen)), dtype=bool)

    def values(state: Snapshot) -> np.ndarray:
        if state.section_forces is None:
            return np.concatenate([xi, (R @ state.q).reshape(n, len(chosen))], axis=1)
        exact = [state.section_forces[i] for i in asked]
        table = np.vstack(
            [np.hstack([f.force, f.moment, f.force_global, f.moment_global]) for f in exact]
            or [np.zeros((0, 12))]
        )
        return np.concatenate([xi, table[:, chosen]], axis=1)

    return labels, blank, values, xi


def _turned(R: sp.csr_matrix, frames: np.ndarray) -> sp.csr_matrix:
    """The recovery map ``R`` (6 rows per point, section frame) in global axes: each point's
    force and moment rows turned by its section frame ``[t, e2, e3]`` (P, 3, 3)."""
    blocks = np.repeat(frames, 2, axis=0)  # force and moment of each point
    b = 3 * np.arange(len(blocks))[:, None, None]
    rows = np.broadcast_to(b + np.arange(3)[:, None], blocks.shape).ravel()
    cols = np.broadcast_to(b + np.arange(3), blocks.shape).ravel()
    n = 3 * len(blocks)
    return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(n, n)) @ R


def _reactions(structure, sliders, supports, wanted, chosen) -> Built:
    """What each support exerts on its node: the residual on the dofs it holds, less the
    forces of the joints whose dofs may reach them (their body, the beams of their line)."""
    rows = [s for s in supports if wanted is None or node_label(structure, s) in wanted]
    labels = [node_label(structure, s) for s in rows]
    index = np.full((len(rows), 6), -1)
    for r, support in enumerate(rows):
        held = support.dofs()
        index[r, held] = structure.node_dofs(support.ref)[held]
    index = index[:, chosen]
    blank = index < 0
    held = np.unique(index[~blank])
    touching = [j for j, s in enumerate(sliders) if np.isin(_reach(structure, s), held).any()]
    where = np.where(blank, 0, index)

    def values(state: Snapshot) -> np.ndarray:
        residual = state.residual
        assert residual is not None, "the reactions need the residual"
        if touching and not state.sliders_in_residual:
            residual = residual.copy()
            for j in touching:
                dofs, r_q, _, _ = sliders[j].assemble(structure, state.q, state.unknowns[j])
                np.add.at(residual, dofs, r_q)
        out = residual[where]
        out[blank] = np.nan
        return out

    return labels, blank, values, np.zeros((len(labels), 0))


def _reach(structure: Structure, slider: Slider) -> np.ndarray:
    """The dofs a slider's forces may act on: its body's, and every dof of the beams of its
    line (none on a rigid line)."""
    beams = getattr(slider.line, "indices", ())
    return np.concatenate([slider.body_dofs(structure), *(structure.dof_maps[b] for b in beams)])


def lines(
    values: np.ndarray, blank: np.ndarray | None = None, integers: Sequence[int] = ()
) -> list[str]:
    """A block of numbers as CSV lines (without their ends): floats in full precision (their
    ``repr``, which reads back to the same float), the ``integers`` columns as integers,
    ``blank`` cells empty.  The whole block is turned into text by one ``repr`` of its
    list, as :func:`cell` writes each number."""
    rows, width = values.shape
    if rows == 0 or width == 0:
        return [""] * rows
    table = values.tolist()
    if integers:
        for row in table:
            for c in integers:
                row[c] = int(row[c])
    if blank is not None:
        for r, c in zip(*np.nonzero(blank), strict=True):
            table[r][c] = None
    return repr(table)[2:-2].replace(", ", ",").replace("None", "").split("],[")


def quote(text: str) -> str:
    """``text`` as one CSV cell (quoted if it needs to be, as :mod:`csv` writes it)."""
    buffer = io.StringIO()
    csv.writer(buffer).writerow([text])
    return buffer.getvalue()[:-2]


def cell(value) -> str:
    """A table cell: blank for ``None``, floats in full precision (``repr``)."""
    if value is None:
        return ""
    return repr(float(value)) if isinstance(value, (float, np.floating)) else str(value)
