"""The rigid motions that a structure's supports leave free, and their names in words.

Every connected *part* of a structure (beams joined at shared nodes and the bodies tied to
them; a body tied to nothing is a part of one node) moves rigidly without straining: with the
beams' small-rotation kinematics, ``u(X) = t + w x (X - X_0)`` and ``r = w`` on all its nodes
(``X_0`` the mean of its nodes).  A part's stiffness is positive definite on every other
motion (its sections are, :class:`fvbeam.section.Section`), so the null space of the
stiffness on the free dofs is exactly the rigid motions that vanish on the supported dofs:
:func:`rigid_modes` builds an orthonormal basis of them, without assembling anything.  A
structure is held by its supports alone when that basis is empty; a solve with a free motion
has no unique answer, and :class:`fvbeam.linear_statics.LinearStatics` (like the slider
statics of :mod:`sliders`, which add the sliders that may hold them) refuses it with the
message of :func:`free_motion_message`, which names the motions: ``beam 'arch' translating
along x``, ``body 'hub' rotating about z through (0, 0, 0)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from fvbeam.structure import Structure

#: Below this fraction of a vector's largest entry, an entry of a free motion counts as zero
#: when it is named: the basis is orthonormal to roundoff (1e-16), far below.
NEGLIGIBLE = 1e-9
#: Free motions named in one message; the rest are counted.
NAMED = 8


def node_positions(structure: Structure) -> np.ndarray:
    """Reference position of every structure node, beam nodes and rigid bodies,
    ``(n_nodes, 3)``."""
    x = np.zeros((structure.n_nodes, 3))
    for beam, dofs in zip(structure.beams, structure.dof_maps, strict=True):
        x[dofs[::6] // 6] = beam.mesh.points
    for body in structure.bodies:
        x[structure.node_dofs(body.name)[0] // 6] = body.position
    return x


@dataclass(frozen=True)
class RigidModes:
    """An orthonormal basis ``phi`` (n_free, k) of free rigid motions and what they are.

    ``coords`` (6 P, k): each basis vector as, per part ``p``, the translation ``t`` of the
    part's centre ``centres[p]`` and its rotation ``w`` times the part's size ``sizes[p]``
    (``phi = modes[free] @ coords``, the modes of :func:`rigid_modes`); ``labels[p]``
    names the part (its beams and bodies).
    """

    phi: np.ndarray
    coords: np.ndarray
    centres: np.ndarray
    sizes: np.ndarray
    labels: list[str]

    @property
    def k(self) -> int:
        """How many independent free motions."""
        return int(self.phi.shape[1])

    def combined(self, V: np.ndarray) -> RigidModes:
        """The motions ``phi @ V`` (``V`` with orthonormal columns keeps ``phi``
        orthonormal)."""
        return RigidModes(
            np.ascontiguousarray(self.phi @ V),
            self.coords @ V,
            self.centres,
            self.sizes,
            self.labels,
        )


def _parts(structure: Structure) -> tuple[int, np.ndarray]:
    """The number of connected parts and the part of each node: the nodes of a beam's
    elements are joined, tied nodes are one node already."""
    return connected_components(structure.node_graph(), directed=False)


def _labels(structure: Structure, part: np.ndarray, count: int) -> list[str]:
    """Each part named by its beams (by name, or by index where names repeat) and bodies."""
    names = [beam.mesh.name for beam in structure.beams]
    members: list[list[str]] = [[] for _ in range(count)]
    for i, (name, dofs) in enumerate(zip(names, structure.dof_maps, strict=True)):
        members[part[dofs[0] // 6]].append(
            f"beam '{name}'" if names.count(name) == 1 else f"beam {i}"
        )
    for body in structure.bodies:
        members[part[structure.node_dofs(body.name)[0] // 6]].append(f"body '{body.name}'")
    return [" with ".join([m[0], ", ".join(m[1:])]) if len(m) > 1 else m[0] for m in members]


def rigid_modes(structure: Structure, free: np.ndarray) -> RigidModes:
    """Orthonormal basis of the rigid motions that leave the supported dofs (all but
    ``free``) at rest.

    Every part moves with a translation and a rotation about its centre (rotations scaled by
    the part's size, so that both are lengths; a part of one node has size 1); per part, the
    combinations that vanish on its supported dofs are kept (module docstring).  Parts share
    no dof, so their motions are orthogonal to one another.
    """
    free = np.asarray(free, dtype=np.int64)
    count, part = _parts(structure)
    x = node_positions(structure)
    position = np.full(structure.n_dofs, -1)
    position[free] = np.arange(len(free))
    centres, sizes = np.zeros((count, 3)), np.ones(count)
    columns, blocks = [], []
    for p in range(count):
        nodes = np.flatnonzero(part == p)
        centres[p] = x[nodes].mean(axis=0)
        lever = x[nodes] - centres[p]
        sizes[p] = float(np.linalg.norm(lever, axis=1).max()) or 1.0
        nodal = np.zeros((len(nodes), 6, 6))  # per node, its six dofs in the part's motions
        nodal[:, :3, :3] = np.eye(3)
        for i in range(3):
            nodal[:, :3, 3 + i] = np.cross(np.eye(3)[i], lever) / sizes[p]
            nodal[:, 3 + i, 3 + i] = 1.0 / sizes[p]
        modes = nodal.reshape(-1, 6)
        at = position[(6 * nodes[:, None] + np.arange(6)).ravel()]
        held = at < 0
        combos = _null_combinations(modes[held]) if held.any() else np.eye(6)
        if combos.shape[1] == 0:
            continue
        Q, R = np.linalg.qr(modes[~held] @ combos)
        column = np.zeros((len(free), Q.shape[1]))
        column[at[~held]] = Q
        block = np.zeros((6 * count, Q.shape[1]))
        block[6 * p : 6 * p + 6] = combos @ la.inv(R)
        columns.append(column)
        blocks.append(block)
    labels = _labels(structure, part, count)
    if not columns:
        return RigidModes(
            np.zeros((len(free), 0)), np.zeros((6 * count, 0)), centres, sizes, labels
        )
    return RigidModes(np.hstack(columns), np.hstack(blocks), centres, sizes, labels)


def _null_combinations(held: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the null space of ``held`` (m, 6): the combinations of a
    part's six motions that vanish on its held dofs.  Its rows are reduced to the triangle
    ``R`` of their QR decomposition (at most 6 x 6; the null spaces are equal), so that the
    cost is linear in ``m``, whatever the number of held dofs (a planar solve holds half of
    a long beam's); the rank threshold is ``scipy.linalg.null_space``'s on ``held``."""
    R = np.linalg.qr(held, mode="r")
    return la.null_space(R, rcond=np.finfo(float).eps * max(held.shape))


def unresisted(modes: RigidModes, operator_free: sp.spmatrix) -> RigidModes:
    """The combinations of ``modes`` that ``operator_free`` (on the free dofs) does not
    resist (``|A phi a| <= 1e-8 max|A|`` for unit ``a``).  A stiffness keeps them all; the
    time integrator's operator ``M + c K`` keeps only those of the massless parts."""
    if modes.k == 0:
        return modes
    # the singular values and right vectors of A = Q R are those of the small R (k x k)
    R = np.linalg.qr(operator_free @ modes.phi, mode="r")
    _, sigma, Vt = np.linalg.svd(R, full_matrices=True)
    sigma = np.concatenate([sigma, np.zeros(modes.k - len(sigma))])
    return modes.combined(Vt[sigma <= 1e-8 * abs(operator_free).max()].T)


def _direction(v: np.ndarray) -> str:
    """A direction in words: ``x``, ``y``, ``z``, or its unit vector (signs as found)."""
    u = v / np.linalg.norm(v)
    axis = int(np.argmax(np.abs(u)))
    if abs(u[axis]) >= 1 - NEGLIGIBLE:
        return "xyz"[axis]
    u = np.where(np.abs(u) < NEGLIGIBLE, 0.0, u)
    return "(" + ", ".join(f"{c:.3g}" for c in u) + ")"


def _point(p: np.ndarray, size: float) -> str:
    p = np.where(np.abs(p) < NEGLIGIBLE * size, 0.0, p)
    return "(" + ", ".join(f"{c:.4g}" for c in p) + ")"


def _reduced(rows: np.ndarray) -> np.ndarray:
    """The reduced row echelon form of ``rows`` (d, n) with independent rows: one basis of
    their span in which each vector has a leading coordinate of its own."""
    A = np.array(rows, dtype=float)
    tol = NEGLIGIBLE * max(float(np.abs(A).max(initial=0.0)), 1e-300)
    r = 0
    for j in range(A.shape[1]):
        if r == len(A):
            break
        pivot = r + int(np.argmax(np.abs(A[r:, j])))
        if abs(A[pivot, j]) <= tol:
            continue
        A[[r, pivot]] = A[[pivot, r]]
        A[r] /= A[r, j]
        others = np.arange(len(A)) != r
        A[others] -= np.outer(A[others, j], A[r])
        r += 1
    A[np.abs(A) <= tol] = 0.0
    return A[:r]


def motion_phrases(modes: RigidModes, null: np.ndarray, extras: Sequence[str] = ()) -> list[str]:
    """The free motions spanned by the columns of ``null``, in words.

    ``null`` (k + e, d): combinations of the ``k`` rigid motions of ``modes``, then of ``e``
    other unknowns that move with them, named by ``extras`` (e.g. a slider's abscissa:
    ``"slider 'key' sliding along its line"``).  The span is written in a basis of its own
    (reduced row echelon form, rotations first, so that a rotation comes with the least
    translation), each vector as its parts' motions: a translation ``beam 'arch'
    translating along x``, a rotation ``beam 'arch' rotating about z through (0, 0, 0)``
    (the point of the axis closest to the part's centre).  The vectors that move one part
    alone are gathered in one phrase per part.
    """
    k, count = modes.k, len(modes.sizes)
    c = (modes.coords @ null[:k]).reshape(count, 2, 3, -1)[:, ::-1].reshape(6 * count, -1)
    alone: dict[int, list[_Motion]] = {}
    phrases = []
    for vector in _reduced(np.vstack([c, null[k:]]).T):
        moving = [
            (p, _Motion.of(modes, p, vector[6 * p + 3 : 6 * p + 6], vector[6 * p : 6 * p + 3]))
            for p in range(count)
            if np.any(vector[6 * p : 6 * p + 6])
        ]
        carried = [extras[i] for i in np.flatnonzero(vector[6 * count :]).tolist()]
        if len(moving) == 1 and not carried:
            alone.setdefault(moving[0][0], []).append(moving[0][1])
            continue
        phrases.append(
            ", ".join([f"{modes.labels[p]} {_Motion.words([m])}" for p, m in moving] + carried)
        )
    return [f"{modes.labels[p]} {_Motion.words(motions)}" for p, motions in alone.items()] + phrases


@dataclass(frozen=True)
class _Motion:
    """One rigid motion of a part: a translation along ``direction`` (``turning`` False), or
    a rotation about ``direction`` through the point ``through``, with a ``slip`` along the
    axis per radian (a screw); ``size``: the part's, for rounding."""

    direction: np.ndarray
    size: float
    turning: bool = False
    through: np.ndarray = field(default_factory=lambda: np.zeros(3))
    slip: float = 0.0

    @classmethod
    def of(cls, modes: RigidModes, p: int, t: np.ndarray, scaled: np.ndarray) -> _Motion:
        """The motion of part ``p`` that translates its centre by ``t`` and turns it by
        ``scaled`` over its size: a rotation is named by the point of its axis closest to
        the centre."""
        size = float(modes.sizes[p])
        if np.linalg.norm(scaled) <= NEGLIGIBLE * np.linalg.norm(t):
            return cls(t, size)
        w = scaled / size
        slip = float(t @ w) / float(w @ w)
        if abs(slip) * np.linalg.norm(w) <= NEGLIGIBLE * np.linalg.norm(t):
            slip = 0.0
        return cls(w, size, True, modes.centres[p] + np.cross(w, t) / (w @ w), slip)

    @staticmethod
    def words(motions: Sequence[_Motion]) -> str:
        """Motions of one part in one phrase: ``translating along x and z and rotating
        about x and y through (0, 0.849, 0)``; rotations whose axes meet at one point are
        named through that point."""
        along = [_direction(m.direction) for m in motions if not m.turning]
        turns = [m for m in motions if m.turning and m.slip == 0.0]
        common = _meeting_point(turns)
        about: dict[str, list[str]] = {}
        for m in turns:
            point = _point(m.through if common is None else common, m.size)
            about.setdefault(point, []).append(_direction(m.direction))
        out = [f"translating along {_and(along)}"] if along else []
        out += [f"rotating about {_and(axes)} through {point}" for point, axes in about.items()]
        out += [
            f"rotating about {_direction(m.direction)} through {_point(m.through, m.size)} "
            f"while translating along it ({m.slip:.3g} m per rad)"
            for m in motions
            if m.turning and m.slip != 0.0
        ]
        return _and(out)


def _meeting_point(turns: Sequence[_Motion]) -> np.ndarray | None:
    """The point where the axes of two or more rotations meet (least squares, then checked
    on every axis), or None."""
    if len(turns) < 2:
        return None
    projectors = [
        np.eye(3) - np.outer(m.direction, m.direction) / (m.direction @ m.direction) for m in turns
    ]
    A = np.vstack(projectors)
    b = np.concatenate([P @ m.through for P, m in zip(projectors, turns, strict=True)])
    point = np.linalg.lstsq(A, b, rcond=None)[0]
    size = max(m.size for m in turns)
    return point if np.abs(A @ point - b).max() <= NEGLIGIBLE * size else None


def _and(items: list[str]) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def free_motion_message(held_by: str, phrases: Sequence[str], remedy: str) -> str:
    """The message of a singular configuration: ``held_by`` (``"supports"``, ``"supports and
    sliders"``) leave the motions ``phrases`` free (at most :data:`NAMED` of them named);
    ``remedy`` says what would hold them."""
    named = list(phrases[:NAMED])
    if len(phrases) > NAMED:
        named.append(f"{len(phrases) - NAMED} more")
    return (
        f"singular configuration: the {held_by} leave a rigid-body motion free: "
        f"{'; '.join(named)} ({remedy})"
    )
