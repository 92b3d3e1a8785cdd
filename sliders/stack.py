"""What a chain gives at ``xi`` for many chains of one topology at once (paper Sec. 4, T6).

A sweep solves many independent problems of the same shape: the same beams moved rigidly
(:meth:`fvbeam.beam.Beam.translated`), with the same dof maps, connectivity, element lengths,
formulations and sections, differing only in the reference node positions.  A
:class:`ChainStack` holds ``B`` such :class:`~sliders.chain.BeamChain` members and answers
their queries at abscissae ``xi`` of shape ``(B,)`` (one per member) with arrays of leading
dimension ``B``:

* :meth:`ChainStack.interpolation`: the element holding ``xi``, its shape functions
  ``x(xi) = sum N_i (X_i + u_i)`` and the recovered tangent
  ``l~ = l + (1 - X) (l_a - l(a)) + X (l_b - l(b))`` (``docs/sliders.md``), its neighbours
  padded with zero coefficients at the chain's ends (fixed ``3 npe`` entries);
* :meth:`ChainStack.rotation`: the section rotation interpolated between the two nodes around
  ``xi``, the kink correction ``kappa = w0 w1 l + lag h w_mid^2`` and the reference frame;
* :meth:`ChainStack.transfer`: the test functions at ``xi`` read as load-transfer matrices
  ``G(xi)`` (eq. T6) and ``dG/dxi``; with smearing, each member's
  :meth:`~sliders.chain.BeamChain.transfer` padded to a common size with zero rows;
* :meth:`ChainStack.project`: the initial ``xi`` by projection.

The single-point queries of :class:`~sliders.chain.BeamChain` are the ``B = 1`` case.  The
chain's beams must all have the same number of nodes per element (fixed-size slots).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple, Sequence

import numpy as np

from fvbeam.formulations import FiniteVolume
from fvbeam.geometry import locate_abscissa
from fvbeam.mesh import shape_functions
from sliders.lines import curvature_rate, frame_and_curvature, project

if TYPE_CHECKING:
    from sliders.chain import BeamChain

#: Lag of a 3-node element's mid-node rotation under a couple ``M`` at the mid-node, per
#: ``h C M`` (the exact rotation steps its rate by ``C M`` there, the elements cannot):
#: fv3, ``1/4 - sqrt(3)/8``: the curvature, linear in the element and exact at the
#: evaluation points, integrates from a vertex to the mid-node to ``(1/4 + sqrt(3)/8) h C M``
#: where the exact step gives ``h C M / 2``; Galerkin P2, ``1/16``: the quadratic minimising
#: the energy with the couple at the mid-node reaches ``7/16 h C M`` there.
MID_NODE_LAG = {"fv": 0.25 - np.sqrt(3.0) / 8, "galerkin": 1.0 / 16}

#: Relative tolerance on the element lengths of the members: a rigid move recomputes them
#: from the moved nodes (8-point Gauss rule on ``|dx/dX|``), with a roundoff of some ``eps``.
LENGTH_TIE = 1e-12


def second_derivatives(nodes_per_element: int) -> np.ndarray:
    """d^2 N / dX^2 of the Lagrange shape functions on [0, 1] (constant)."""
    return np.zeros(2) if nodes_per_element == 2 else np.array([4.0, 4.0, -8.0])


def gather(q: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """``q[dofs]`` for one state ``q`` (n,), or each member's own for states ``(B, n)`` and
    dofs ``(B, ...)``."""
    if q.ndim == 1:
        return q[dofs]
    return q[np.arange(len(q)).reshape((-1,) + (1,) * (dofs.ndim - 1)), dofs]


@dataclass(frozen=True)
class ElementInterpolation:
    """The line near ``xi``: translational ``dofs`` (..., npe, 3) of the element holding it,
    node positions ``X`` (..., npe, 3), and the shape functions ``N`` with their first and
    second derivatives in ``xi`` (..., npe).  The leading axis, if any, runs over the members
    of a :class:`ChainStack`."""

    dofs: np.ndarray
    X: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray

    def geometry(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l`` and ``l_/xi`` of the deformed line."""
        current = self.X + gather(q, self.dofs)
        return tuple(np.einsum("...a,...ak->...k", f, current)
                     for f in (self.N, self.dN, self.d2N))


@dataclass(frozen=True)
class Interpolation(ElementInterpolation):
    """:class:`ElementInterpolation` with the recovered tangent's dofs (..., m, 3), node
    positions (..., m, 3) and coefficients ``T``, ``T_xi`` (..., m), ``m = 3 npe`` (the
    element, the one before and the one after; zero coefficients where there is none): the
    first ``3 npe`` are the element's."""

    tangent_dofs: np.ndarray
    tangent_X: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray

    def tangent(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The recovered tangent ``l~`` and ``l~_/xi`` of the deformed line."""
        current = self.tangent_X + gather(q, self.tangent_dofs)
        return (np.einsum("...a,...ak->...k", self.T, current),
                np.einsum("...a,...ak->...k", self.T_xi, current))

    def member(self, b: int) -> Interpolation:
        """Member ``b`` of a stacked interpolation."""
        return Interpolation(*(getattr(self, f)[b] for f in self.__dataclass_fields__))


@dataclass(frozen=True)
class LineRotation:
    """Section rotation of the line at ``xi``: ``theta = w @ q[dofs]``, with ``dofs`` (2, 3)
    the rotation dofs of the bracketing nodes, ``w`` their weights and ``w_xi`` their
    derivatives; ``kink = w0 w1 span`` and ``kink_xi`` its derivative (the correction for a
    couple at ``xi``, :class:`sliders.joint.Slider`); the section ``compliance`` (3, 3); the
    reference frame ``R0``, its curvature vector ``k0`` and ``k0_xi``.  Stacked: a leading
    member axis on every field."""

    dofs: np.ndarray
    w: np.ndarray
    w_xi: np.ndarray
    kink: np.ndarray
    kink_xi: np.ndarray
    compliance: np.ndarray
    R0: np.ndarray
    k0: np.ndarray
    k0_xi: np.ndarray

    def member(self, b: int) -> LineRotation:
        """Member ``b`` of a stacked rotation."""
        return LineRotation(*(getattr(self, f)[b] for f in self.__dataclass_fields__))


class ElementFrames(NamedTuple):
    """Per member and element (leading axes (B, E)) of a :class:`ChainStack`: whether the
    element is straight, its reference frame ``R0`` (3, 3) and its section compliance in
    global axes (3, 3) (:meth:`ChainStack.element_frames`)."""

    straight: np.ndarray
    R0: np.ndarray
    compliance: np.ndarray


class ChainStack:
    """``B`` chains of one topology (module docstring), queried together; each
    member keeps its own element lengths and abscissae (equal to :data:`LENGTH_TIE`).

    Raises ``ValueError`` naming the first member that differs from the first chain in
    anything but its node positions, or a chain mixing element sizes.
    """

    def __init__(self, chains: Sequence[BeamChain]) -> None:
        self.chains = list(chains)
        first = self.chains[0]
        self.name, self.beams, self.offsets = first.name, first.beams, first.offsets
        self.length = first.length
        npe = {beam.mesh.nodes_per_element for beam in first.beams}
        if len(npe) != 1:
            raise ValueError(f"{first.name}: the beams of a chain must have the same number of "
                             f"nodes per element, got {sorted(npe)}")
        self.npe = npe.pop()
        for b, chain in enumerate(self.chains[1:], start=1):
            if not _same_topology(first, chain):
                raise ValueError(f"{chain.name}: member {b} of the batch differs from member 0 "
                                 "in more than its node positions (beams, dof maps, element "
                                 "lengths, formulations, sections)")
        counts = [beam.mesh.n_elements for beam in self.beams]
        self.first_element = np.concatenate([[0], np.cumsum(counts)])
        nodes = np.concatenate([[0], np.cumsum([beam.mesh.n_nodes for beam in self.beams])])
        self.cells = np.concatenate([beam.mesh.cells + n for beam, n in zip(self.beams, nodes)])
        # the dofs of each element's nodes, (maps, elements, npe, 6), and each member's map
        # (one here; a joined stack holds one per chain of the structure, :meth:`joined`)
        self.maps = np.concatenate([
            first.structure.dof_maps[i][6 * beam.mesh.cells[:, :, None] + np.arange(6)]
            for i, beam in zip(first.indices, self.beams)])[None]
        self.map = np.zeros(len(self.chains), dtype=int)
        self.breaks = np.stack([chain.offsets for chain in self.chains])
        self.vertices = [np.stack([chain.beams[j].mesh.vertex_s for chain in self.chains])
                         for j in range(len(self.beams))]
        self.h = np.concatenate([np.diff(v, axis=1) for v in self.vertices], axis=1)
        self.up = np.concatenate([np.tile(beam.mesh.up, (n, 1))
                                  for beam, n in zip(self.beams, counts)])
        self.lag = np.concatenate([np.full(n, MID_NODE_LAG[
            "fv" if isinstance(beam.formulation, FiniteVolume) else "galerkin"])
            for beam, n in zip(self.beams, counts)])
        self.points = np.stack([np.concatenate([beam.mesh.points for beam in chain.beams])
                                for chain in self.chains])
        # the rotational block of each beam's inverse section stiffness, in section axes
        # (in global axes: R C R^T, the section stiffness rotating by blockdiag(R, R))
        self.compliance = [np.linalg.inv(beam.section.stiffness)[3:, 3:] for beam in self.beams]
        self.members = np.arange(len(self.chains))
        self._ends = shape_functions(np.array([0.0, 1.0]), self.npe)[1].T
        self._located: tuple[np.ndarray, tuple] | None = None
        self._frames: ElementFrames | None = None

    def subset(self, members: np.ndarray) -> ChainStack:
        """The stack of the given members only (their topology already checked)."""
        out = copy.copy(self)
        out.chains = [self.chains[b] for b in members]
        out.breaks, out.h, out.points = self.breaks[members], self.h[members], self.points[members]
        out.vertices = [v[members] for v in self.vertices]
        out.map = self.map[members]
        out.members, out._located = np.arange(len(out.chains)), None
        if self._frames is not None:
            out._frames = ElementFrames(*(f[members] for f in self._frames))
        return out

    @classmethod
    def joined(cls, stacks: Sequence[ChainStack]) -> ChainStack:
        """One stack of the members of ``stacks``, one after the other: chains of one
        topology but for their dof maps (e.g. the lines of two joints on different beams of
        one structure), so that one query answers them all.  Raises ``ValueError`` naming
        the first stack whose chains differ from the first one's in more than their node
        positions and dof maps."""
        first = stacks[0]
        for stack in stacks[1:]:
            if not (stack.npe == first.npe
                    and _same_topology(first.chains[0], stack.chains[0], maps=False)):
                raise ValueError(f"{stack.name}: its chains differ from {first.name}'s in more "
                                 "than their node positions and dof maps")
        out = copy.copy(first)
        out.chains = [c for stack in stacks for c in stack.chains]
        out.breaks, out.h, out.points = (np.concatenate([getattr(stack, f) for stack in stacks])
                                         for f in ("breaks", "h", "points"))
        out.vertices = [np.concatenate(v) for v in zip(*(stack.vertices for stack in stacks))]
        out.maps = np.concatenate([stack.maps for stack in stacks])
        out.map = np.concatenate([stack.map + sum(len(s.maps) for s in stacks[:i])
                                  for i, stack in enumerate(stacks)])
        out.members, out._located = np.arange(len(out.chains)), None
        out._frames = (None if any(stack._frames is None for stack in stacks) else
                       ElementFrames(*(np.concatenate(f) for f in
                                       zip(*(stack._frames for stack in stacks)))))
        return out

    def _dofs(self, element: np.ndarray) -> np.ndarray:
        """The dofs (B, ..., npe, 6) of each member's ``element`` (B, ...), on its own map."""
        return self.maps[self.map.reshape((-1,) + (1,) * (element.ndim - 1)), element]

    def translated(self, shifts: np.ndarray) -> ChainStack:
        """``B`` copies of this one-member stack, copy ``b`` with the structure's beams moved
        rigidly by ``shifts[b]`` ((B, n_beams, 3), one shift per beam of the structure), as
        :meth:`fvbeam.beam.Beam.translated` would move them (the node positions are this
        chain's plus the shift), without building the moved chains.  A translation changes
        nothing but the node positions, so every member keeps this chain for the queries that
        do not read them (the smeared transfer)."""
        if len(self) != 1:
            raise ValueError(f"{self.name}: only a one-member stack is translated")
        chain = self.chains[0]
        self.element_frames()  # a translation keeps them
        out = self.subset(np.zeros(len(shifts), dtype=int))
        counts = [beam.mesh.n_nodes for beam in self.beams]
        out.points = self.points + np.repeat(shifts[:, chain.indices], counts, axis=1)
        return out

    def __len__(self) -> int:
        return len(self.chains)

    def locate(self, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Beam (position in the chain), element of the chain (global index) and reference
        coordinate ``X`` of each member's abscissa ``xi`` (B,), on the member's own abscissae
        (as :func:`fvbeam.geometry.locate_abscissa` and :meth:`fvbeam.mesh.BeamMesh.locate`,
        which report an abscissa off the chain).  The last answer is kept: a joint
        evaluation asks for the same ``xi`` up to three times (interpolation, load transfer,
        rotation)."""
        last = self._located
        if last is not None and np.array_equal(last[0], xi):
            return last[1]
        located = self._locate(xi)
        self._located = (xi.copy(), located)
        return located

    def _locate(self, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`locate`, computed."""
        if not (0.0 <= xi.min() and xi.max() <= self.length):  # NaN fails too
            locate_abscissa(xi, self.offsets, self.name, "the chain")  # raises if off it
        k = _interval(self.breaks, xi)
        rows = self.members
        local = np.clip(xi - self.breaks[rows, k], 0.0,
                        self.breaks[rows, k + 1] - self.breaks[rows, k])
        element, X = np.zeros(len(xi), dtype=int), np.zeros(len(xi))
        for j in np.unique(k):
            on = k == j
            vertex = self.vertices[j][on]
            e = _interval(vertex, local[on])
            inside = np.arange(len(e))
            offset = np.clip(local[on] - vertex[inside, e], 0.0,
                             vertex[inside, e + 1] - vertex[inside, e])
            element[on] = self.first_element[j] + e
            X[on] = np.clip(offset / self.h[rows[on], element[on]], 0.0, 1.0)
        return k, element, X

    def _nodes(self, element: np.ndarray) -> np.ndarray:
        """Reference node positions ``(B, ..., npe, 3)`` of each member's ``element``
        (B, ...)."""
        return self.points[self.members.reshape((-1,) + (1,) * element.ndim), self.cells[element]]

    def element_interpolation(self, xi: np.ndarray) -> ElementInterpolation:
        """Where each member's ``xi`` sits and how its element interpolates the line there."""
        _, element, X = self.locate(xi)
        h = self.h[self.members, element][:, None]
        N, dN = (f.T for f in shape_functions(X, self.npe))
        return ElementInterpolation(self._dofs(element)[:, :, :3], self._nodes(element), N,
                                    dN / h, second_derivatives(self.npe) / h**2)

    def interpolation(self, xi: np.ndarray) -> Interpolation:
        """:meth:`element_interpolation` with the recovered tangent (module docstring)."""
        _, element, X = self.locate(xi)
        inside = self.element_interpolation(xi)
        h = self.h[self.members, element][:, None]
        dN, d2N = inside.dN, inside.d2N
        T, T_xi = [dN], [d2N.copy()]
        dofs, nodes = [inside.dofs], [inside.X]
        ends = self._ends
        for side, weight, weight_xi, end in ((-1, 1 - X, -1 / h[:, 0], 0),
                                             (1, X, 1 / h[:, 0], 1)):
            other = element + side
            there = (other >= 0) & (other < self.h.shape[1])
            other = np.where(there, other, element)
            weight, weight_xi = 0.5 * weight * there, 0.5 * weight_xi * there
            own = ends[end] / h
            T[0] = T[0] - weight[:, None] * own
            T_xi[0] = T_xi[0] - weight_xi[:, None] * own
            theirs = ends[1 - end] / self.h[self.members, other][:, None]
            T.append(weight[:, None] * theirs)
            T_xi.append(weight_xi[:, None] * theirs)
            dofs.append(self._dofs(other)[:, :, :3])
            nodes.append(self._nodes(other))
        return Interpolation(inside.dofs, inside.X, inside.N, dN, d2N,
                             np.concatenate(dofs, axis=1), np.concatenate(nodes, axis=1),
                             np.concatenate(T, axis=1), np.concatenate(T_xi, axis=1))

    def rotation(self, xi: np.ndarray) -> LineRotation:
        """The section rotation at ``xi`` and its reference frame, per member.

        The rotation is interpolated linearly between the two consecutive nodes that bracket
        ``xi`` (the element's vertices, and its mid-node for 3-node elements), whatever the
        beam formulation: the weights are continuous along the chain, so a couple carried by
        them never jumps.  ``kink`` is how far the exact rotation at a couple ``M`` lies off
        that interpolation, per unit ``C M``: ``w0 w1 span`` for exact nodal rotations, plus
        ``MID_NODE_LAG h w_mid^2`` on a 3-node element, whose mid-node rotation lags by that
        much under the share ``w_mid M`` it carries (``docs/sliders.md``).  The reference
        frame ``R0``, its curvature ``k0`` and ``k0_/xi`` come from the element's reference
        interpolation and the mesh's ``up``.  ``C`` is the section's bending-and-torsion
        compliance (the rotational block of the inverse section stiffness) in global axes,
        taken in the element's reference frame at ``xi``.  When every member's element is
        straight, both are read from :meth:`element_frames` (``k0 = k0_/xi = 0``).
        """
        beam, element, X = self.locate(xi)
        h = self.h[self.members, element]
        along = np.array([0.0, 1.0, 0.5])[:self.npe]
        order = np.argsort(along)
        j = np.minimum(np.searchsorted(along[order], X, side="right") - 1, self.npe - 2)
        pair = np.stack([order[j], order[j + 1]], axis=1)
        span = (along[pair[:, 1]] - along[pair[:, 0]]) * h
        t = (X - along[pair[:, 0]]) * h / span
        w = np.stack([1 - t, t], axis=1)
        mid = pair == 2
        shift = self.lag[element] * h
        w_mid = np.sum(w * mid, axis=1)
        kink = t * (1 - t) * span + shift * w_mid**2
        kink_xi = 1 - 2 * t + 2 * shift * w_mid * (mid[:, 1] * 1.0 - mid[:, 0]) / span
        frames = self.element_frames()
        if frames.straight[self.members, element].all():
            R0, compliance = (f[self.members, element] for f in (frames.R0, frames.compliance))
            k0 = k0_xi = np.zeros((len(xi), 3))
        else:
            l0, l0_xi = self._reference_line(element, X)
            R0, k0 = frame_and_curvature(l0, l0_xi, self.up[element])
            k0_xi = curvature_rate(l0, l0_xi, np.zeros(3), self.up[element])
            compliance = np.zeros((len(xi), 3, 3))
            for b in np.unique(beam):
                on = beam == b
                compliance[on] = R0[on] @ self.compliance[b] @ np.swapaxes(R0[on], 1, 2)
        dofs = self._dofs(element)[self.members[:, None], pair][:, :, 3:]
        return LineRotation(dofs, w, np.stack([-1 / span, 1 / span], axis=1), kink, kink_xi,
                            compliance, R0, k0, k0_xi)

    def _reference_line(self, element: np.ndarray,
                        X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The reference line's ``l0`` and ``l0_/xi`` at the reference coordinates ``X``
        (...) of the members' ``element`` (...)."""
        nodes = self._nodes(element)
        h = self.h[self.members.reshape((-1,) + (1,) * (element.ndim - 1)), element][..., None]
        dN = np.moveaxis(shape_functions(X.ravel(), self.npe)[1], 0, -1).reshape(
            X.shape + (self.npe,)) / h
        return (np.einsum("...a,...ak->...k", dN, nodes),
                np.einsum("a,...ak->...k", second_derivatives(self.npe), nodes) / h ** 2)

    def element_frames(self) -> ElementFrames:
        """Per member and element, whether the element is straight in the reference
        configuration (``|l0_/xi| <= 1e-12 |l0|``, the test by which
        :func:`sliders.lines.curvature_rate` takes ``k0_/xi`` as zero; ``k0`` is then zero
        to roundoff), and its frame ``R0`` and section compliance in global axes
        (:meth:`rotation`), computed once per stack (a translated stack keeps its
        template's, :meth:`translated`)."""
        if self._frames is None:
            E = self.h.shape[1]
            element = np.broadcast_to(np.arange(E), (len(self), E))
            l0, l0_xi = self._reference_line(element, np.full((len(self), E), 0.5))
            R0 = frame_and_curvature(l0, l0_xi, self.up[element])[0]
            beam = np.searchsorted(self.first_element, np.arange(E), side="right") - 1
            sections = np.stack(self.compliance)[beam]
            self._frames = ElementFrames(
                np.linalg.norm(l0_xi, axis=-1) <= 1e-12 * np.linalg.norm(l0, axis=-1),
                R0, R0 @ sections @ np.swapaxes(R0, -1, -2))
        return self._frames

    def transfer(self, xi: np.ndarray, smearing: float = 0.0,
                 kernel: str = "box") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """How a force and couple ``[F; M]`` at each member's ``xi`` loads its chain (T6).

        Returns global ``dofs`` (B, k), ``G`` (B, k, 6) and ``dG/dxi`` (B, k, 6) as
        :meth:`sliders.chain.BeamChain.transfer` (which gives the smeared loads, padded here
        to a common ``k`` with zero rows on the member's first dof).
        """
        if smearing > 0:
            parts = [chain.transfer(float(x), smearing, kernel)
                     for chain, x in zip(self.chains, xi)]
            size = max(len(p[0]) for p in parts)
            dofs = np.array([np.pad(d, (0, size - len(d)), mode="edge") for d, _, _ in parts])
            G, dG = (np.array([np.pad(p[i], ((0, size - len(p[0])), (0, 0))) for p in parts])
                     for i in (1, 2))
            return dofs, G, dG
        beam, element, X = self.locate(xi)
        G = np.zeros((len(xi), 6 * self.npe, 6))
        dG = np.zeros_like(G)
        nodes, h = self._nodes(element), self.h[self.members, element]
        for b in np.unique(beam):
            on = beam == b
            G[on], dG[on] = self.beams[b].formulation.transfer_at(nodes[on], h[on], X[on])
        return self._dofs(element).reshape(len(xi), -1), G, dG

    def project(self, points: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Abscissae of the points of the deformed chains (states ``q``, (B, n)) closest to
        ``points`` (B, 3)."""
        grid = np.unique(np.concatenate([offset + beam.mesh.node_abscissae()
                                         for offset, beam in zip(self.offsets, self.beams)]))
        # the grid located once, on the first member (the members' abscissae are tied)
        _, element, X = self.subset(np.zeros(len(grid), dtype=int)).locate(grid)
        element = np.broadcast_to(element, (len(self), len(grid)))
        current = self._nodes(element) + gather(q, self._dofs(element)[..., :3])
        sampled = np.einsum("ga,bgak->bgk", shape_functions(X, self.npe)[0].T, current)
        return project(lambda xi: self.element_interpolation(xi).geometry(q), grid, points,
                       sampled)


def _same_topology(a: BeamChain, b: BeamChain, maps: bool = True) -> bool:
    """Whether chains ``a`` and ``b`` differ at most in their node positions (and, without
    ``maps``, their dof maps).  Beams sharing
    their arc lengths (moved copies, :meth:`fvbeam.mesh.BeamMesh.translated`) have equal
    lengths and chain offsets without comparing them."""
    return (len(a.beams) == len(b.beams)
            and (all(x.mesh.vertex_s is y.mesh.vertex_s for x, y in zip(a.beams, b.beams))
                 or _tied(a.offsets, b.offsets))
            and (not maps or all(np.array_equal(a.structure.dof_maps[i], b.structure.dof_maps[j])
                                 for i, j in zip(a.indices, b.indices)))
            and all(x.formulation == y.formulation and x.section is y.section
                    and (x.mesh.cells is y.mesh.cells
                         or np.array_equal(x.mesh.cells, y.mesh.cells))
                    and (x.mesh.vertex_s is y.mesh.vertex_s
                         or _tied(x.mesh.element_length, y.mesh.element_length))
                    and (x.mesh.up is y.mesh.up or np.array_equal(x.mesh.up, y.mesh.up))
                    for x, y in zip(a.beams, b.beams)))


def _tied(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the lengths ``a`` equal ``b`` to :data:`LENGTH_TIE` (relative to ``b``;
    ``np.allclose(a, b, rtol=LENGTH_TIE, atol=0)`` without its overhead)."""
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= LENGTH_TIE * np.abs(b)))


def _interval(breaks: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Per row, the interval of ``breaks`` (B, n + 1), increasing, holding ``xi`` (B,):
    ``searchsorted(side="right") - 1`` clipped to ``0 .. n - 1``."""
    return np.clip(np.sum(breaks <= xi[:, None], axis=1) - 1, 0, breaks.shape[1] - 2)
