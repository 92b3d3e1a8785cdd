"""Beam centrelines in 3-D space: nodes, elements, arc length and section frames.

A :class:`BeamMesh` is one beam: an ordered chain of 2-node (``line``) or 3-node (``line3``)
elements.  Nodes are stored in the order scikit-fem numbers its degrees of freedom on a
``MeshLine1``: the element end nodes (vertices) along the beam first, then, for 3-node elements,
one mid node per element.  The 3-D centreline stays here; scikit-fem only sees the arc-length
coordinate (``vertex_s``), see ``docs/architecture.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from numbers import Real
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from fvbeam.copies import shallow_copy
from fvbeam.geometry import (
    check_up,
    closest_to_up,
    direction,
    locate_abscissa,
    norm,
    number,
    section_frames,
    vector3,
)
from fvbeam.io import write_atomic
from fvbeam.pointwise import shape_functions_many

if TYPE_CHECKING:  # meshio is imported where a mesh is read or written
    import meshio

_GAUSS8 = np.polynomial.legendre.leggauss(8)
_CELL_TYPES = {"line": 2, "line3": 3}


def shape_functions(X: np.ndarray, nodes_per_element: int) -> tuple[np.ndarray, np.ndarray]:
    """Lagrange shape functions and their derivatives on the reference element [0, 1]
    (:func:`fvbeam.pointwise.shape_at` at each point).

    Local node order is meshio's and scikit-fem's: end 0, end 1, then the mid node.

    Returns
    -------
    N, dN : arrays of shape ``(nodes_per_element,) + X.shape``
    """
    X = np.asarray(X, dtype=float)
    N, dN = shape_functions_many(np.ascontiguousarray(X).ravel(), nodes_per_element)
    shape = (nodes_per_element,) + X.shape
    return N.reshape(shape), dN.reshape(shape)


@dataclass(frozen=True, eq=False)
class BeamMesh:
    """One beam: nodes, element connectivity, arc length and section frames.

    Parameters
    ----------
    points
        ``(n_nodes, 3)`` node coordinates: vertices along the beam, then mid nodes.
    cells
        ``(n_elements, nodes_per_element)`` node indices in meshio order ``[end0, end1, mid]``.
    up
        Reference vector fixing the section frame: the section axis ``e3`` is ``up`` made
        orthogonal to the tangent, ``e2 = e3 x t`` (see :func:`fvbeam.geometry.section_frames`).
    point_ids
        Identifier of every node in the mesh it was read from (shared nodes between beams
        carry the same identifier); defaults to ``arange(n_nodes)``.
    name
        Label used in error messages and outputs.
    """

    points: np.ndarray
    cells: np.ndarray
    up: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    point_ids: np.ndarray | None = None
    name: str = "beam"
    #: Arc length of each vertex from the first (computed from the nodes).
    vertex_s: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        points = np.array(self.points, dtype=float)
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise ValueError(f"{self.name}: points must have shape (n, 3), got {points.shape}")
        if points.shape[1] == 2:
            points = np.column_stack([points, np.zeros(len(points))])
        ids = np.arange(len(points)) if self.point_ids is None else np.asarray(self.point_ids)
        if not np.all(np.isfinite(points)):
            bad = int(np.argwhere(~np.isfinite(points))[0, 0])
            raise ValueError(
                f"{self.name}: point {ids[bad]} has a non-finite coordinate {points[bad]}"
            )
        cells = np.array(self.cells, dtype=np.int64)
        if cells.ndim != 2 or cells.shape[1] not in (2, 3) or len(cells) == 0:
            raise ValueError(
                f"{self.name}: cells must have shape (n_elements, 2 or 3), got {cells.shape}"
            )
        if cells.min() < 0 or cells.max() >= len(points):
            raise ValueError(f"{self.name}: a cell refers to a node outside 0..{len(points) - 1}")
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "cells", cells)
        object.__setattr__(self, "point_ids", ids)
        self._check_chain()
        lengths = self._element_lengths()
        scale = max(float(np.ptp(points, axis=0).max()), 1.0)
        short = np.flatnonzero(lengths <= 1e-12 * scale)
        if short.size:
            raise ValueError(
                f"{self.name}: element {int(short[0])} has zero length "
                f"(points {ids[cells[short[0]]].tolist()})"
            )
        if self.nodes_per_element == 3:
            speeds = norm(self.element_tangents(np.array([0.0, 0.5, 1.0])))
            folded = np.flatnonzero(speeds.min(axis=1) <= 1e-9 * lengths)
            if folded.size:
                raise ValueError(
                    f"{self.name}: element {int(folded[0])} folds back on itself "
                    "(mid node outside its end nodes)"
                )
        object.__setattr__(self, "vertex_s", np.concatenate([[0.0], np.cumsum(lengths)]))
        object.__setattr__(self, "up", self._check_up())

    def _check_up(self) -> np.ndarray:
        """``up`` made a unit vector, checked to cross the centreline everywhere
        (:func:`fvbeam.geometry.check_up`) at the points where it may come closest
        (:func:`fvbeam.geometry.closest_to_up`: the tangent of an element is linear in its
        reference coordinate)."""
        up = direction(self.up, f"{self.name}: up")
        n = self.n_elements
        start = self.tangent_vectors(np.arange(n), np.zeros(n))
        slope = self.tangent_vectors(np.arange(n), np.ones(n)) - start
        s = closest_to_up(np.stack([slope, start]), np.arange(n + 1.0), up)
        e = np.minimum(s.astype(np.int64), n - 1)
        check_up(up, self.tangent_vectors(e, s - e), self.abscissae(e, s - e), self.name)
        return up

    def _check_chain(self) -> None:
        n_el = len(self.cells)
        expected = np.column_stack([np.arange(n_el), np.arange(1, n_el + 1)])
        if not np.array_equal(self.cells[:, :2], expected):
            raise ValueError(
                f"{self.name}: cells must run along the beam, element e joining "
                "vertices e and e + 1 (use BeamMesh.from_meshio to order a mesh)"
            )
        if self.cells.shape[1] == 3 and not np.array_equal(
            self.cells[:, 2], np.arange(n_el + 1, 2 * n_el + 1)
        ):
            raise ValueError(f"{self.name}: mid nodes must follow the vertices in element order")
        if len(self.points) != n_el + 1 + (n_el if self.cells.shape[1] == 3 else 0):
            raise ValueError(
                f"{self.name}: {len(self.points)} points do not match "
                f"{n_el} elements of {self.cells.shape[1]} nodes"
            )

    def translated(self, offset: np.ndarray, name: str | None = None) -> "BeamMesh":
        """The mesh moved rigidly by ``offset`` (a finite 3-vector), sharing its connectivity,
        ``up``, identifiers and arc lengths; named ``name`` (default: this mesh's name).

        A translation passes every check the mesh passed and keeps its element lengths, so
        neither is run again: the lengths are the original ones exactly (recomputed from the
        moved nodes they would differ by roundoff).
        """
        moved = shallow_copy(self)
        object.__setattr__(moved, "points", self.points + offset)
        if name is not None:
            object.__setattr__(moved, "name", name)
        return moved

    # -- sizes -------------------------------------------------------------------------
    @property
    def nodes_per_element(self) -> int:
        return int(self.cells.shape[1])

    @property
    def n_elements(self) -> int:
        return int(len(self.cells))

    @property
    def n_nodes(self) -> int:
        return int(len(self.points))

    @property
    def length(self) -> float:
        return float(self.vertex_s[-1])

    @property
    def element_length(self) -> np.ndarray:
        return np.diff(self.vertex_s)

    # -- geometry of the interpolated centreline --------------------------------------
    def _element_lengths(self) -> np.ndarray:
        X, W = _GAUSS8
        speed = norm(self.element_tangents((X + 1) / 2))
        return (speed * W / 2).sum(axis=1)

    def positions(self, e: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Centreline points x(X) in elements ``e`` at reference coordinates ``X`` in [0, 1]."""
        N, _ = shape_functions(X, self.nodes_per_element)
        return np.einsum("a...,...ak->...k", N, self.points[self.cells[e]])

    def element_tangents(self, X: np.ndarray) -> np.ndarray:
        """Centreline derivative dx/dX at the reference coordinates ``X`` (nq,) of every
        element, (n_elements, nq, 3): :meth:`tangent_vectors` at the same points of all
        elements, reading each element's nodes once."""
        _, dN = shape_functions(X, self.nodes_per_element)
        return np.einsum("aq,eak->eqk", dN, self.points[self.cells])

    def tangent_vectors(self, e: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Centreline derivative dx/dX in elements ``e`` at reference coordinates ``X``."""
        _, dN = shape_functions(X, self.nodes_per_element)
        return np.einsum("a...,...ak->...k", dN, self.points[self.cells[e]])

    def metric(self, e: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Ratio of true arc length to the element's affine coordinate, |dx/dX| / h_e."""
        return norm(self.tangent_vectors(e, X)) / self.element_length[np.asarray(e)]

    def frames(self, e: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Section frames ``R = [t, e2, e3]`` (columns) at the given points, shape (..., 3, 3)."""
        return section_frames(self.tangent_vectors(e, X), self.up)

    def locate(self, xi: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Element index and reference coordinate of the abscissa ``xi`` (arc length from node 0).

        Inside an element the abscissa is the affine coordinate scaled to the element's arc
        length, exact at the nodes.  ``xi`` outside ``[0, length]`` raises ``ValueError``.
        """
        e, offset = locate_abscissa(xi, self.vertex_s, self.name, "the beam")
        return e, np.clip(offset / self.element_length[e], 0.0, 1.0)

    def abscissae(self, e: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Abscissa ``xi`` of reference coordinates ``X`` in elements ``e`` (inverse of
        :meth:`locate`)."""
        return self.vertex_s[e] + self.element_length[e] * X

    def node_abscissae(self) -> np.ndarray:
        """Abscissa ``xi`` of every node (vertices, then mid nodes)."""
        if self.nodes_per_element == 2:
            return self.vertex_s.copy()
        return np.concatenate([self.vertex_s, self.vertex_s[:-1] + self.element_length / 2])

    # -- meshio ----------------------------------------------------------------------
    def to_meshio(self) -> meshio.Mesh:
        """The beam as a meshio mesh with one ``line`` or ``line3`` cell block (points N x 3)."""
        import meshio

        kind = "line" if self.nodes_per_element == 2 else "line3"
        return meshio.Mesh(
            self.points.copy(),
            [(kind, self.cells.copy())],
            point_data={"xi": self.node_abscissae()},
        )

    def write(self, path: str | Path, file_format: str | None = None) -> None:
        """Write with meshio (any format it knows; ``.msh`` is written as Gmsh 2.2)."""
        import meshio

        path = Path(path)
        if file_format is None and path.suffix == ".msh":
            file_format = "gmsh22"
        write_atomic(path, lambda tmp: meshio.write(tmp, self.to_meshio(), file_format=file_format))

    @classmethod
    def read(cls, path: str | Path, **kwargs: Any) -> "BeamMesh":
        """Read a file holding exactly one beam (see :func:`read_beams` for several)."""
        return cls.from_meshio(_read_meshio(path), **kwargs)

    @classmethod
    def from_meshio(cls, mesh: meshio.Mesh, **kwargs: Any) -> "BeamMesh":
        """Build the beam from a meshio mesh whose line cells form exactly one chain."""
        beams = read_beams(mesh, **kwargs)
        if len(beams) != 1:
            raise ValueError(f"the mesh holds {len(beams)} separate beams; use read_beams")
        return beams[0]


def _read_meshio(path: str | Path) -> meshio.Mesh:
    import meshio

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"mesh file {path} does not exist")
    try:
        return meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types, or exits
        raise ValueError(f"meshio cannot read {path}: {exc}") from exc


def read_beams(
    mesh: meshio.Mesh | str | Path, up: Sequence[float] = (0.0, 0.0, 1.0), name: str = "beam"
) -> list[BeamMesh]:
    """Split the line cells of a meshio mesh into beams: one per connected chain of each cell
    block (a Gmsh physical group, say, is a block).

    All line cells must be of one kind (``line`` or ``line3``).  Nodes shared by two beams keep
    the same ``point_ids``; :meth:`fvbeam.structure.Structure.from_shared_points` joins them.  A
    chain keeps the direction of its first cell in the file.
    """
    if isinstance(mesh, (str, Path)):
        mesh = _read_meshio(mesh)
    blocks = [b for b in mesh.cells if b.type in _CELL_TYPES]
    if not blocks:
        found = sorted({b.type for b in mesh.cells}) or ["none"]
        raise ValueError(f"the mesh has no line or line3 cells (cell types: {', '.join(found)})")
    kinds = {b.type for b in blocks}
    if len(kinds) > 1:
        raise ValueError(f"the mesh mixes {' and '.join(sorted(kinds))} cells; use one kind")
    points = np.asarray(mesh.points, dtype=float)
    chains = [
        (block.data.astype(np.int64), chain)
        for block in blocks
        for chain in _chains(block.data[:, :2].astype(np.int64), name)
    ]
    beams = []
    for k, (cells, chain) in enumerate(chains):
        vertices = [cells[chain[0][0], 0 if chain[0][1] else 1]]
        vertices += [cells[c, 1 if forward else 0] for c, forward in chain]
        ids = list(vertices)
        if cells.shape[1] == 3:
            ids += [cells[c, 2] for c, _ in chain]
        n = len(chain)
        local = np.column_stack([np.arange(n), np.arange(1, n + 1)])
        if cells.shape[1] == 3:
            local = np.column_stack([local, np.arange(n + 1, 2 * n + 1)])
        label = name if len(chains) == 1 else f"{name}[{k}]"
        beams.append(
            BeamMesh(
                points[ids], local, up=np.asarray(up, float), point_ids=np.asarray(ids), name=label
            )
        )
    return beams


def _chains(ends: np.ndarray, name: str) -> list[list[tuple[int, bool]]]:
    """Order 2-vertex cells into simple chains: lists of (cell, traversed forward)."""
    incident: dict[int, list[int]] = {}
    for c, (a, b) in enumerate(ends):
        if a == b:
            raise ValueError(f"{name}: cell {c} has zero length (both ends are node {a})")
        incident.setdefault(int(a), []).append(c)
        incident.setdefault(int(b), []).append(c)
    branching = [v for v, cs in incident.items() if len(cs) > 2]
    if branching:
        raise ValueError(
            f"{name}: node {branching[0]} joins {len(incident[branching[0]])} "
            "cells; a beam is a chain (split branches into separate beams)"
        )
    used = np.zeros(len(ends), bool)
    chains = []
    for first in range(len(ends)):
        if used[first]:
            continue
        start = _chain_start(first, ends, incident)
        chain, vertex, cell = [], start, None
        while True:
            nxt = [c for c in incident[vertex] if c != cell and not used[c]]
            if not nxt:
                break
            cell = nxt[0]
            forward = bool(ends[cell, 0] == vertex)
            chain.append((cell, forward))
            used[cell] = True
            vertex = int(ends[cell, 1] if forward else ends[cell, 0])
        if vertex == start:
            raise ValueError(
                f"{name}: cells {chain[0][0]}..{chain[-1][0]} form a closed loop; "
                "a beam must have two free ends"
            )
        if not dict(chain)[first]:
            chain = [(c, not f) for c, f in reversed(chain)]
        chains.append(chain)
    return chains


def _chain_start(cell: int, ends: np.ndarray, incident: dict[int, list[int]]) -> int:
    """Walk backwards from ``cell`` to an end vertex of its chain (or back to ``cell``)."""
    vertex, current = int(ends[cell, 0]), cell
    while True:
        others = [c for c in incident[vertex] if c != current]
        if not others:
            return vertex
        current = others[0]
        vertex = int(ends[current, 0] if ends[current, 1] == vertex else ends[current, 1])
        if current == cell:
            return int(ends[cell, 0])


def from_curve(
    curve: Callable[[np.ndarray], np.ndarray],
    n_elements: int,
    nodes_per_element: int = 3,
    up: Sequence[float] = (0.0, 0.0, 1.0),
    name: str = "beam",
) -> BeamMesh:
    """Beam along a parametrised curve ``curve(u)`` (u in [0, 1], returns (n, 3)), uniform in u.

    ``n_elements`` is a positive integer (an integral float too) and ``nodes_per_element`` 2 or
    3, or ``ValueError`` naming them."""
    whole = isinstance(n_elements, Real) and not isinstance(n_elements, bool)
    if not (whole and float(n_elements).is_integer() and n_elements >= 1):
        raise ValueError(f"{name}: n_elements must be a positive integer, got {n_elements!r}")
    if nodes_per_element not in (2, 3) or isinstance(nodes_per_element, bool):
        raise ValueError(f"{name}: nodes_per_element must be 2 or 3, got {nodes_per_element!r}")
    n = int(n_elements)
    u = np.linspace(0.0, 1.0, n + 1)
    if nodes_per_element == 3:
        u = np.concatenate([u, (u[:-1] + u[1:]) / 2])
    cells = np.column_stack([np.arange(n), np.arange(1, n + 1)])
    if nodes_per_element == 3:
        cells = np.column_stack([cells, np.arange(n + 1, 2 * n + 1)])
    return BeamMesh(np.asarray(curve(u), dtype=float), cells, up=np.asarray(up, float), name=name)


def straight(
    start: Sequence[float],
    end: Sequence[float],
    n_elements: int,
    nodes_per_element: int = 3,
    up: Sequence[float] | None = None,
    name: str = "beam",
) -> BeamMesh:
    """Straight beam from ``start`` to ``end`` with equal elements.

    ``up`` defaults to the global z axis, or the y axis for a beam along z.  ``start`` and
    ``end`` are finite 3-vectors, or ``ValueError`` naming them.
    """
    a, b = vector3(start, f"{name}: start"), vector3(end, f"{name}: end")
    if up is None:
        d = b - a
        up = (0.0, 1.0, 0.0) if abs(d[2]) > 0.9 * norm(d) else (0.0, 0.0, 1.0)
    return from_curve(lambda u: a + np.outer(u, b - a), n_elements, nodes_per_element, up, name)


def arc(
    center: Sequence[float],
    radius: float,
    angle0: float,
    angle1: float,
    n_elements: int,
    nodes_per_element: int = 3,
    name: str = "beam",
) -> BeamMesh:
    """Circular arc in the plane z = center[2], from ``angle0`` to ``angle1`` (radians).

    ``center`` a finite 3-vector, ``radius`` > 0, the angles finite and distinct, or
    ``ValueError`` naming them."""
    c = vector3(center, f"{name}: center")
    radius = number(radius, f"{name}: radius", "> 0")
    angle0, angle1 = number(angle0, f"{name}: angle0"), number(angle1, f"{name}: angle1")
    if angle0 == angle1:
        raise ValueError(f"{name}: angle0 and angle1 are both {angle0}: the arc has no length")

    def circle(u: np.ndarray) -> np.ndarray:
        a = angle0 + (angle1 - angle0) * u
        return c + radius * np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])

    return from_curve(circle, n_elements, nodes_per_element, (0.0, 0.0, 1.0), name)
