"""The rigid and the elastic part of a solved structure's motion, for pictures.

A body pushed 0.3 m along a beam, or a piston driven along its cylinder, moves much more
than any beam bends: a picture that magnifies the whole displacement draws them far from
where they are.  :func:`rigid_motion` splits the displacements ``q`` into a rigid part
``q_R``, drawn at its true size, and the elastic part ``q - q_R``, which a picture magnifies.

The rigid part is one rigid motion per *group*: the beams and bodies joined by ties (they
share nodes, so they move together).  With the beams' small-rotation kinematics a rigid
motion is ``u(X) = c + theta x (X - X_0)``, ``r = theta`` (``X_0`` the mean of the group's
nodes), six numbers per group.  They solve three sets of equations in turn, each in the
least-squares sense and only within the freedom the sets before it leave (lexicographic least
squares):

1. **held dofs**: on every dof a support or a dof drive holds, the rigid motion is the
   motion ``q`` has there.  A clamped group has no rigid part (its drawn clamp stays at the
   clamp, however the rest is magnified); a driven one moves rigidly with its drive.
2. **joints**: every slider's sliding point ``X_b + offset`` is carried by its group's
   rigid motion to the point of the *reference* line at the slider's current ``xi``, moved
   by the line's rigid motion (paper eq. 1, with the rigid motions in place of the
   displacements); the rotations the orientation constraints hold (classical: about the
   slider axes ``e2, e3``; spline: all three) turn with the line's group.  Sliding along
   the line is thus rigid travel, and a sliding body's elastic part is the line's elastic
   displacement at the contact: the magnified body sits on the magnified line.
3. **fit**: whatever is still free fits the group's nodal motion, translations and
   rotations times the structure's size (so that both are lengths).  A free group's rigid
   part is its mean motion, and a motion that is rigid is recovered whole: its elastic part
   is zero.

A direction counts as free when its singular value is below ``sqrt(eps)`` of the largest
(:data:`RANK`): the equations are built from coordinates relative to the structure's size,
O(1) numbers.  The joints only see the state, so the split is the same for a static sample
and a time step.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.csgraph import connected_components

from fvbeam.structure import Structure
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain

#: Relative singular value below which a direction of the rigid motions counts as free.
RANK = float(np.sqrt(np.finfo(float).eps))
#: The rotation axes (columns of the slider frame) each kind of slider holds.
HELD_AXES = {"spherical": [], "classical": [1, 2], "spline": [0, 1, 2]}


def _skew(a: np.ndarray) -> np.ndarray:
    """``skew(a) @ b = a x b`` for ``a`` (..., 3): (..., 3, 3)."""
    x, y, z = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    zero = np.zeros_like(x)
    return np.stack(
        [np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)],
        -2,
    )


class _Groups:
    """The structure's groups of tied parts and the map from their rigid motions to the dofs.

    The unknowns are, per group ``g``, ``c`` and ``ell theta`` (``ell`` the structure's
    size); :attr:`basis` maps them to the weighted dofs ``W q`` (translations, rotations
    times ``ell``)."""

    def __init__(self, structure: Structure) -> None:
        n = structure.n_nodes
        position = np.zeros((n, 3))
        links = []
        for beam, dofs in zip(structure.beams, structure.dof_maps, strict=True):
            nodes = dofs[::6] // 6
            position[nodes] = beam.mesh.points
            links.append(np.column_stack([nodes, np.full(len(nodes), nodes[0])]))
        for body in structure.bodies:
            position[structure.node_dofs(body.name)[0] // 6] = body.position
        edges = np.vstack(links) if links else np.zeros((0, 2), dtype=int)
        graph = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
        self.count, self.of_node = connected_components(graph, directed=False)
        self.ell = float(np.linalg.norm(np.ptp(position, axis=0))) or 1.0
        self.origin = np.array(
            [position[self.of_node == g].mean(axis=0) for g in range(self.count)]
        )
        basis = np.zeros((n, 6, self.count, 6))
        basis[np.arange(n), :, self.of_node, :] = self.at(self.of_node, position, rotations=True)
        self.basis = basis.reshape(6 * n, 6 * self.count)

    def columns(self, group: int) -> slice:
        return slice(6 * group, 6 * group + 6)

    def at(self, group, point: np.ndarray, rotations: bool = False) -> np.ndarray:
        """The map ``(..., 3, 6)`` from a group's unknowns to its rigid displacement
        ``c + theta x (point - X_0)`` at ``point`` (..., 3); ``(..., 6, 6)`` with the
        weighted rotation ``ell theta`` below it."""
        lever = -_skew(point - self.origin[group]) / self.ell
        eye = np.broadcast_to(np.eye(3), lever.shape)
        translation = np.concatenate([eye, lever], axis=-1)
        if not rotations:
            return translation
        turn = np.concatenate([np.zeros_like(eye), eye], axis=-1)
        return np.concatenate([translation, turn], axis=-2)

    def weights(self, dofs: np.ndarray) -> np.ndarray:
        """1 on translation dofs, ``ell`` on rotation dofs."""
        return np.where(dofs % 6 < 3, 1.0, self.ell)


def _joint_equations(
    groups: _Groups,
    structure: Structure,
    sliders: Sequence[Slider],
    unknowns: Sequence[np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """Rows and right-hand side of the joints' equations (module docstring, 2)."""
    rows, rhs = [], []
    for slider, y in zip(sliders, unknowns, strict=True):
        xi = float(y[0])
        body = slider.body_dofs(structure)[0] // 6
        g_body = groups.of_node[body]
        point = slider.reference_point(structure)
        position = np.zeros((3, groups.basis.shape[1]))
        position[:, groups.columns(g_body)] = groups.at(g_body, point)
        turn = np.zeros((3, groups.basis.shape[1]))
        turn[:, groups.columns(g_body)] = groups.at(g_body, point, rotations=True)[3:]
        if isinstance(slider.line, BeamChain):
            interp = slider.line.interpolation(xi)
            on_line = interp.reference[0]
            position -= interp.N @ groups.basis[interp.dofs]
            turn -= groups.basis[interp.dofs[:3] + 3]  # the first node's rotations
        else:
            on_line = slider.line.at(xi).x
        axes = slider.frame[:, HELD_AXES[slider.kind]].T
        rows += [position, axes @ turn]
        rhs += [on_line - point, np.zeros(len(axes))]
    width = groups.basis.shape[1]
    return np.vstack([np.zeros((0, width)), *rows]), np.concatenate([np.zeros(0), *rhs])


def lexicographic_lstsq(levels: Sequence[tuple[np.ndarray, np.ndarray]], n: int) -> np.ndarray:
    """The ``z`` (n,) that solves each ``A z = b`` of ``levels`` in the least-squares sense
    within the solutions of the levels before it (minimum norm in what none fixes).

    Each level is solved through the singular value decomposition of ``A`` restricted to
    the directions still free; those with a singular value below :data:`RANK` times the
    largest stay free, both in its solve and for the levels after it.
    """
    z, free = np.zeros(n), np.eye(n)
    for A, b in levels:
        if not free.shape[1] or not len(A):
            continue
        reduced = A @ free
        u, s, vh = np.linalg.svd(reduced, full_matrices=len(reduced) < reduced.shape[1])
        rank = int(np.sum(s > RANK * s[0])) if s.size and s[0] > 0 else 0
        w = vh[:rank].T @ ((u[:, :rank].T @ (b - A @ z)) / s[:rank])
        z = z + free @ w
        free = free @ vh[rank:].T
    return z


def rigid_motion(
    structure: Structure,
    q: np.ndarray,
    sliders: Sequence[Slider] = (),
    unknowns: Sequence[np.ndarray] = (),
    held: ArrayLike = (),
) -> np.ndarray:
    """The rigid part ``q_R`` (``(structure.n_dofs,)``) of the displacements ``q``; the
    elastic part is ``q - q_R`` (module docstring).

    Parameters
    ----------
    structure, q
        The structure and its displacements.
    sliders, unknowns
        The sliders and their unknowns ``[xi, lambda, mu...]``, in the same order.
    held
        The global dofs the supports and dof drives hold (``statics`` or ``dynamics``: the
        dofs not in ``.free``).
    """
    groups = _Groups(structure)
    held = _held(structure, held)
    everything = np.arange(structure.n_dofs)
    weight = groups.weights(everything)
    levels = [
        (groups.basis[held], weight[held] * q[held]),
        _joint_equations(groups, structure, sliders, unknowns),
        (groups.basis, weight * q),
    ]
    return groups.basis @ lexicographic_lstsq(levels, groups.basis.shape[1]) / weight


def _held(structure: Structure, held: ArrayLike) -> np.ndarray:
    """``held`` as distinct global dofs; ``ValueError`` for anything else."""
    try:
        dofs = np.unique(np.asarray(held, dtype=float))
    except (TypeError, ValueError):
        dofs = np.array([np.nan])
    if dofs.ndim != 1 or not np.all(
        (dofs == np.round(dofs)) & (0 <= dofs) & (dofs < structure.n_dofs)
    ):
        raise ValueError(
            f"held must be global dofs of the structure (integers in 0..{structure.n_dofs - 1}), "
            f"got {held!r}"
        )
    return dofs.astype(int)
