"""Dead loads on geometrically exact beams and bodies: their virtual work on the current
configuration, and its load stiffness.

A *dead* load keeps its size and direction in global axes whatever the structure does
(gravity, a weight hung on a cable, a force a test rig applies along a fixed axis): no
follower terms.  What does change with the configuration is *where* it acts, and with it
the work it does through the beam's test functions (``docs/exact_beams.md``, "Loads"):

- **Finite volume** (``fv2``, ``fv3``): the test functions are the rigid motions of the
  nodes' influence regions (eq. T4), on the current configuration.  A force ``F`` at the
  material point ``X`` of an element, now at ``x(X) = sum_b N_b(X) x_b``, gives node ``a``
  (whose region holds the point) the force ``F`` and the moment ``(x(X) - x_a) x F``; a
  force density ``q(s)`` gives ``int q ds`` and ``int (x(s) - x_a) x q ds`` over the region:
  the region's balance on the current configuration (:mod:`fvbeam.exact_beam`) is then
  the exact equilibrium of the region of the interpolated beam.  The moments are affine in
  the positions; their load stiffness is
  ``d m_a / d x_b = -chi_a skew(F) (N_b(X) - delta_ab)``.  A dead couple does no work on the
  spatial rotation increments' tangent: it adds to its node's moment and nothing to the
  stiffness.
- **Galerkin** (``galerkin-p1``, ``galerkin-p2``): the positions are interpolated with the
  same shape functions as the test functions' translations, so the work of ``F`` at ``X``
  is ``sum_a N_a(X) F . du_a``: the nodal forces ``N_a(X) F`` on any configuration, with no
  load stiffness.
- **Bodies**: a force ``F`` at the offset ``c`` (global axes, the reference configuration)
  from a body's node acts at ``x + R c`` and gives the node ``F`` and ``(R c) x F``, with
  the load stiffness ``d m / d phi = skew(F) skew(R c)`` on the spatial rotation increment.

In the reference configuration the fv lever arms are the linear beam's
(:meth:`fvbeam.beam.Beam.transfer` reads the same test functions on the reference node
positions), so :meth:`DeadLoad.vector` there is the linear load vector
(:meth:`~fvbeam.beam.Beam.distributed_load`, :meth:`~fvbeam.beam.Beam.point_load`, smeared
or not) to round-off: the two kinematics differ only in the lever arms' change, second order
in the load (``tests/test_exact_loads.py``).

:func:`distributed`, :func:`point` and :func:`weight` turn a beam's loads into
:class:`LoadPoints` (the quadratures of the linear beam's loads); :class:`DeadLoad` gathers
them, the bodies' offset forces and any nodal loads on a structure's global dofs, the load
:func:`fvbeam.exact_statics.solve_static` takes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from fvbeam.beam import Beam, Field, sample_field
from fvbeam.formulations import FiniteVolume
from fvbeam.geometry import skew_matrices, vector3
from fvbeam.mesh import shape_functions
from fvbeam.smearing import check_smearing, density


@dataclass(frozen=True)
class LoadPoints:
    """Dead forces and couples ``wrench`` (K, 6; ``[F; M]``, global axes) at material points
    of one beam: the element of each (K,) and its reference coordinate ``X`` (K,)."""

    element: np.ndarray
    X: np.ndarray
    wrench: np.ndarray

    @staticmethod
    def join(parts: Sequence[LoadPoints]) -> LoadPoints:
        """The points of ``parts`` together."""
        return LoadPoints(
            np.concatenate([p.element for p in parts]).astype(np.int64),
            np.concatenate([p.X for p in parts]),
            np.concatenate([p.wrench for p in parts]).reshape(-1, 6),
        )


def distributed(
    beam: Beam, force: Field = (0.0, 0.0, 0.0), moment: Field = (0.0, 0.0, 0.0)
) -> LoadPoints:
    """A force and couple per unit length (constants or functions of the abscissa, as
    :meth:`fvbeam.beam.Beam.distributed_load` takes them) as the points of its load
    quadrature, each carrying its density times its weight in arc length."""
    X, W = beam.formulation.load_quadrature()
    n_el = beam.mesh.n_elements
    elements = np.repeat(np.arange(n_el), X.shape[1])
    _, metric = beam.centreline(X)
    ds = (W[None, :] * beam.mesh.element_length[:, None] * metric).ravel()
    xi = beam.mesh.abscissae(np.arange(n_el)[:, None], X)
    sampled = [sample_field(v, xi, name) for name, v in (("f", force), ("m", moment))]
    density_ = np.concatenate([np.moveaxis(f, 0, -1).reshape(-1, 3) for f in sampled], axis=1)
    return LoadPoints(elements, np.tile(X[0], n_el), density_ * ds[:, None])


def point(
    beam: Beam,
    xi: float,
    force: ArrayLike = (0.0, 0.0, 0.0),
    moment: ArrayLike = (0.0, 0.0, 0.0),
    smearing: float = 0.0,
    kernel: str = "box",
) -> LoadPoints:
    """A force and couple at the abscissa ``xi`` (:meth:`fvbeam.beam.Beam.point_load`): the
    point itself, or spread by the kernel of half-width ``smearing`` over the quadrature
    points that integrate it exactly (:meth:`~fvbeam.beam.Beam.kernel_points`), rescaled so
    that the whole load stays on the beam."""
    name = f"beam {beam.mesh.name!r}"
    smearing = check_smearing(smearing, kernel, beam.mesh.length, name)
    load = np.concatenate([vector3(force, "force"), vector3(moment, "moment")])
    beam.mesh.locate(xi)  # on the beam, else ValueError
    s, w = beam.kernel_points(float(xi), smearing)
    if smearing > 0:
        w = w * density(s - xi, smearing, kernel)
    e, X = beam.mesh.locate(s)
    return LoadPoints(e, X, np.outer(w / w.sum(), load))


def weight(beam: Beam, gravity: ArrayLike) -> LoadPoints:
    """The weight ``m g`` of a beam of mass ``m`` per length under the acceleration of
    gravity ``gravity``, a dead distributed force (:func:`distributed`)."""
    return distributed(beam, beam.section.mass_per_length * vector3(gravity, "gravity"))


@dataclass(frozen=True)
class BodyForce:
    """A dead ``force`` at ``offset`` (global axes, the reference configuration) from the
    node ``node`` of a rigid body (its weight at its centre of mass)."""

    node: int
    force: np.ndarray
    offset: np.ndarray


@dataclass
class DeadLoad:
    """Dead loads on the global dofs of a structure (module docstring): ``nodal`` forces and
    couples (n_dofs,), beam loads as :class:`LoadPoints` on each beam with its global node
    numbers (``node_map``: one per mesh node), and forces at offsets from bodies' nodes.

    ``n_dofs`` may exceed the nodes' ``6 n`` (the multipliers of an exact model follow
    them; no load acts on those).
    """

    n_dofs: int
    nodal: np.ndarray = field(default_factory=lambda: np.zeros(0))
    beams: list[tuple[Beam, np.ndarray, LoadPoints]] = field(default_factory=list)
    bodies: list[BodyForce] = field(default_factory=list)

    def __post_init__(self) -> None:
        nodal = np.zeros(self.n_dofs)
        nodal[: len(self.nodal)] = self.nodal
        self.nodal = nodal
        #: Per beam: its points' element nodes (K, npe, global), element lengths and section
        #: frames (what the test functions read besides the positions).
        self._elements = [
            (
                node_map[beam.mesh.cells[pts.element]],
                beam.mesh.element_length[pts.element],
                beam.mesh.frames(pts.element, np.full(len(pts.X), 0.5)),
            )
            for beam, node_map, pts in self.beams
        ]

    def _beam_terms(self, state: Any) -> list[tuple[Beam, LoadPoints, np.ndarray, np.ndarray]]:
        """For each beam: its points, their element nodes (K, npe, global) and the test
        functions at them on the current node positions (K, 6 npe, 6)."""
        out = []
        for (beam, _, pts), (nodes, h, frames) in zip(self.beams, self._elements, strict=True):
            G, _ = beam.formulation.transfer_at(state.x[nodes], h, pts.X, frames, beam.section)
            out.append((beam, pts, nodes, G))
        return out

    def vector(self, state: Any) -> np.ndarray:
        """The load's virtual work on the dofs at ``state`` (any state with node positions
        ``x`` and rotations ``R``): the nodal loads, each beam's points through its test
        functions on the current positions, each body force with its moment about the
        node's current position."""
        f = self.nodal.copy()
        for _, pts, nodes, G in self._beam_terms(state):
            dofs = 6 * nodes[:, :, None] + np.arange(6)
            f += np.bincount(
                dofs.ravel(), np.einsum("kij,kj->ki", G, pts.wrench).ravel(), minlength=self.n_dofs
            )
        for body in self.bodies:
            arm = state.R[body.node] @ body.offset
            f[6 * body.node : 6 * body.node + 3] += body.force
            f[6 * body.node + 3 : 6 * body.node + 6] += np.cross(arm, body.force)
        return f

    def stiffness(self, state: Any) -> sp.csr_matrix:
        """``d vector / d q`` at ``state`` for the spatial increments ``[du, dphi]`` (module
        docstring): fv beams' ``-chi_a skew(F) (N_b - delta_ab)`` from the moment rows of
        node ``a`` to the positions of node ``b``, bodies' ``skew(F) skew(R c)`` on their
        rotations; Galerkin beams add nothing."""
        rows, cols, vals = [], [], []
        for beam, pts, nodes, G in self._beam_terms(state):
            if not isinstance(beam.formulation, FiniteVolume):
                continue
            npe = nodes.shape[1]
            chi = G[:, 6 * np.arange(npe), 0]  # (K, npe)
            N = shape_functions(pts.X, npe)[0].T  # (K, npe)
            lever = N[:, None, :] - np.eye(npe)[None]  # (K, a, b)
            block = -np.einsum("ka,kab,kij->kabij", chi, lever, skew_matrices(pts.wrench[:, :3]))
            r = 6 * nodes[:, :, None, None, None] + 3 + np.arange(3)[:, None]
            c = 6 * nodes[:, None, :, None, None] + np.arange(3)[None, :]
            rows.append(np.broadcast_to(r, block.shape).ravel())
            cols.append(np.broadcast_to(c, block.shape).ravel())
            vals.append(block.ravel())
        for body in self.bodies:
            arm = state.R[body.node] @ body.offset
            block = skew_matrices(body.force) @ skew_matrices(arm)
            i = 6 * body.node + 3 + np.arange(3)
            rows.append(np.repeat(i, 3))
            cols.append(np.tile(i, 3))
            vals.append(block.ravel())
        if not vals:
            return sp.csr_matrix((self.n_dofs, self.n_dofs))
        return sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.n_dofs, self.n_dofs),
        )

    def padded(self, n_dofs: int) -> DeadLoad:
        """The same load on ``n_dofs`` dofs (a model's multipliers after its nodes)."""
        return DeadLoad(n_dofs, self.nodal, self.beams, self.bodies)
