"""What a chain gives at ``xi`` for many chains of one topology at once (paper Sec. 4, T6).

A sweep solves many independent problems of the same shape: the same beams moved rigidly
(:meth:`fvbeam.beam.Beam.translated`), with the same dof maps, connectivity, element lengths,
formulations and sections, differing only in the reference node positions.  A
:class:`ChainStack` holds ``B`` such :class:`~sliders.lines.chain.BeamChain` members and answers
their queries at abscissae ``xi`` of shape ``(B,)`` (one per member) with arrays of leading
dimension ``B``:

* :meth:`ChainStack.interpolation`: the element holding ``xi`` and how it interpolates the
  line, ``x(xi) = x0(xi) + N q[dofs]`` (the reference line ``x0 = sum N_i X_i`` and the
  displacement of the nodes' dofs: ``N = [N_i I]`` on the translations for the Lagrange
  elements; on a chain with cubic elements, on all six dofs of each node, eq. T11), and the
  recovered tangent ``l~ = l + (1 - X) (l_a - l(a)) + X (l_b - l(b))``
  (``docs/sliders.md``), its neighbours padded with zero coefficients at the chain's ends
  (fixed ``3 m`` entries);
* :meth:`ChainStack.rotation`: the section rotation at ``xi`` (interpolated between the two
  nodes around it; the cubic element's own), its compliance under a couple there (the kink
  correction ``kappa C``, ``kappa = w0 w1 l + lag h w_mid^2``; the cubic element's, eq. T13)
  and the reference frame;
* :meth:`ChainStack.transfer`: the test functions at ``xi`` read as load-transfer matrices
  ``G(xi)`` (eq. T6) and ``dG/dxi``; with smearing, the kernel integrated against them as
  :meth:`~sliders.lines.chain.BeamChain.transfer` integrates it by the kernel form
  (:func:`sliders.lines.batched_kernel.smeared_transfer`), padded to a common size with zero
  rows;
* :meth:`ChainStack.project`: the initial ``xi`` by projection;
* :meth:`ChainStack.line_state`: all a joint needs at once on the states ``q`` (the deformed
  line, the recovered tangent, the position's compliance under a load at ``xi`` on a cubic
  chain, the load transfer and the section rotation).

Every query is one call of the compiled kernel :func:`sliders.lines.batched_kernel.line_state`
(and, for a smeared load, one of :func:`~sliders.lines.batched_kernel.smeared_transfer`).
The single-point queries of :class:`~sliders.lines.chain.BeamChain` are the ``B = 1`` case.  The
chain's beams must all have the same number of nodes per element (fixed-size slots).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np

from fvbeam.beam import Beam
from fvbeam.elements import influence_regions
from fvbeam.formulations import FiniteVolume, gauss
from fvbeam.geometry import locate_abscissa
from fvbeam.mesh import shape_functions
from fvbeam.pointwise import CUBIC, Smearing
from fvbeam.smearing import KERNEL_GAUSS_POINTS, check_smearing, steps
from fvbeam.structure import Structure
from sliders.lines import batched_kernel as stack_kernel
from sliders.lines.rigid import curvature_rate, frame_and_curvature, project


class Chain(Protocol):
    """What a batch reads of each member chain (:class:`sliders.lines.chain.BeamChain` is one)."""

    name: str
    structure: Structure
    indices: list[int]
    beams: list[Beam]
    offsets: np.ndarray
    length: float

    def transfer(
        self, xi: float, smearing: float = 0.0, kernel: str = "box"
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


#: Lag of a 3-node element's mid-node rotation under a couple ``M`` at the mid-node, per
#: ``h C M`` (the exact rotation steps its rate by ``C M`` there, the elements cannot):
#: fv3, ``1/4 - sqrt(3)/8``: the curvature, linear in the element and exact at the
#: evaluation points, integrates from a vertex to the mid-node to ``(1/4 + sqrt(3)/8) h C M``
#: where the exact step gives ``h C M / 2``; Galerkin P2, ``1/16``: the quadratic minimising
#: the energy with the couple at the mid-node reaches ``7/16 h C M`` there.
MID_NODE_LAG = {"fv": 0.25 - np.sqrt(3.0) / 8, "galerkin": 1.0 / 16}

#: The rule on [0, 1] by which a smeared transfer integrates each piece of a kernel's support
#: (:meth:`ChainStack.transfer`), the kernel form's (:meth:`fvbeam.beam.Beam.kernel_transfer`).
KERNEL_RULE = gauss(KERNEL_GAUSS_POINTS)

#: Relative tolerance on the element lengths of the members: a rigid move recomputes them
#: from the moved nodes (8-point Gauss rule on ``|dx/dX|``), with a roundoff of some ``eps``.
LENGTH_TIE = 1e-12


def gather(q: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """``q[dofs]`` for one state ``q`` (n,), or each member's own for states ``(B, n)`` and
    dofs ``(B, ...)``."""
    if q.ndim == 1:
        return q[dofs]
    return q[np.arange(len(q)).reshape((-1,) + (1,) * (dofs.ndim - 1)), dofs]


@dataclass(frozen=True)
class ElementInterpolation:
    """The line near ``xi``: ``x = x0 + N q[dofs]``, the dofs ``dofs`` (..., m) that the
    element holding it interpolates (its nodes' first ``width`` dofs, node after node), the
    reference line's ``x0``, ``l0``, ``l0_/xi`` at ``xi`` (``reference`` (..., 3, 3)), and
    the displacement's matrices ``N``, ``dN``, ``d2N`` (..., 3, m) and their first and
    second derivatives in ``xi``.  The leading axis, if any, runs over the members of a
    :class:`ChainStack`."""

    dofs: np.ndarray
    reference: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray

    def geometry(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l`` and ``l_/xi`` of the deformed line."""
        x, l, l_xi = _weighted(
            np.stack([self.N, self.dN, self.d2N], axis=-3), self.reference, q, self.dofs
        )
        return x, l, l_xi


@dataclass(frozen=True)
class Interpolation(ElementInterpolation):
    """:class:`ElementInterpolation` with the recovered tangent's dofs (..., 3 m), its
    reference values ``l~0``, ``l~0_/xi`` (``tangent_reference`` (..., 2, 3)) and its
    displacement's matrices ``T``, ``T_xi`` (..., 3, 3 m) (the element, the one before and
    the one after; zero columns where there is none): the first ``m`` dofs are the
    element's."""

    tangent_dofs: np.ndarray
    tangent_reference: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray

    def tangent(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The recovered tangent ``l~`` and ``l~_/xi`` of the deformed line."""
        l, l_xi = _weighted(
            np.stack([self.T, self.T_xi], axis=-3), self.tangent_reference, q, self.tangent_dofs
        )
        return l, l_xi

    def member(self, b: int) -> Interpolation:
        """Member ``b`` of a stacked interpolation."""
        return Interpolation(*(getattr(self, f)[b] for f in self.__dataclass_fields__))


@dataclass(frozen=True)
class LineRotation:
    """Section rotation of the line at ``xi``: ``theta = W q[dofs]``, with ``dofs`` (r,) the
    dofs it reads (the two nodes around ``xi``: their rotations, or on a cubic chain their
    six dofs), ``W`` (3, r) and ``W_xi``, ``W_xixi`` its derivatives (the second zero but
    on cubic elements); ``flex`` (3, 3), the rotation a
    unit couple at ``xi`` adds there to it (the kink correction ``kappa C``, ``C`` the
    section's bending-and-torsion compliance, or the cubic element's, eq. T13;
    :class:`sliders.joints.slider.Slider`) and ``flex_xi``; the reference frame ``R0``, its
    curvature vector ``k0`` and ``k0_xi``.  Stacked: a leading member axis on every
    field."""

    dofs: np.ndarray
    W: np.ndarray
    W_xi: np.ndarray
    W_xixi: np.ndarray
    flex: np.ndarray
    flex_xi: np.ndarray
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


class LineState(NamedTuple):
    """All a joint needs of its chains at ``xi`` on the states ``q``, per member (leading
    axis B, :meth:`ChainStack.line_state`): the interpolation with the recovered tangent,
    the deformed line ``x``, ``l``, ``l_/xi``, ``l_/xixi`` (zero but on cubic elements), the
    recovered tangent ``l~`` and ``l~_/xi`` (3,), the position's compliance under a force
    and couple at ``xi`` (``contact`` (c, 6): the rows ``[G_uu, G_u theta]`` of eq. T13 with
    ``c = 3`` on a chain with cubic elements, none (``c = 0``) otherwise) and
    ``contact_xi``, the load transfer
    (``load_dofs``, ``G``, ``dG``, :meth:`ChainStack.transfer`) and the section rotation
    (None unless asked)."""

    interpolation: Interpolation
    x: np.ndarray
    l: np.ndarray
    l_xi: np.ndarray
    l_xixi: np.ndarray
    tangent: np.ndarray
    tangent_xi: np.ndarray
    contact: np.ndarray
    contact_xi: np.ndarray
    load_dofs: np.ndarray
    G: np.ndarray
    dG: np.ndarray
    rotation: LineRotation | None


class ChainStack:
    """``B`` chains of one topology (module docstring), queried together; each
    member keeps its own element lengths and abscissae (equal to :data:`LENGTH_TIE`).

    Raises ``ValueError`` naming the first member that differs from the first chain in
    anything but its node positions, or a chain mixing element sizes.
    """

    def __init__(self, chains: Sequence[Chain]) -> None:
        self.chains = list(chains)
        first = self.chains[0]
        self.name, self.beams, self.offsets = first.name, first.beams, first.offsets
        self.length = first.length
        npe = {beam.mesh.nodes_per_element for beam in first.beams}
        if len(npe) != 1:
            raise ValueError(
                f"{first.name}: the beams of a chain must have the same number of "
                f"nodes per element, got {sorted(npe)}"
            )
        self.npe = npe.pop()
        for b, chain in enumerate(self.chains[1:], start=1):
            if not _same_topology(first, chain):
                raise ValueError(
                    f"{chain.name}: member {b} of the batch differs from member 0 "
                    "in more than its node positions (beams, dof maps, element "
                    "lengths, formulations, sections)"
                )
        counts = [beam.mesh.n_elements for beam in self.beams]
        self.first_element = np.concatenate([[0], np.cumsum(counts)])
        nodes = np.concatenate([[0], np.cumsum([beam.mesh.n_nodes for beam in self.beams])])
        self.cells = np.concatenate(
            [beam.mesh.cells + n for beam, n in zip(self.beams, nodes[:-1], strict=True)]
        )
        # the dofs of each element's nodes, (maps, elements, npe, 6), and each member's map
        # (one here; a joined stack holds one per chain of the structure, :meth:`joined`)
        self.maps = np.concatenate(
            [
                first.structure.dof_maps[i][6 * beam.mesh.cells[:, :, None] + np.arange(6)]
                for i, beam in zip(first.indices, self.beams, strict=True)
            ]
        )[None].astype(np.int64)
        self.map = np.zeros(len(self.chains), dtype=np.int64)
        self.breaks = np.stack([chain.offsets for chain in self.chains])
        # each member's beams' vertex abscissae, one beam after the other (B, E + n_beams)
        self.vertex_s = np.stack(
            [np.concatenate([beam.mesh.vertex_s for beam in chain.beams]) for chain in self.chains]
        )
        self.h = np.concatenate(
            [
                np.diff(self.vertex_s[:, f + j : f + j + n + 1], axis=1)
                for j, (f, n) in enumerate(zip(self.first_element[:-1], counts, strict=True))
            ],
            axis=1,
        )
        self.up = np.concatenate(
            [np.tile(beam.mesh.up, (n, 1)) for beam, n in zip(self.beams, counts, strict=True)]
        )
        self.lag = np.concatenate(
            [
                np.full(
                    n,
                    MID_NODE_LAG[
                        "fv" if isinstance(beam.formulation, FiniteVolume) else "galerkin"
                    ],
                )
                for beam, n in zip(self.beams, counts, strict=True)
            ]
        )
        self.points = np.stack(
            [np.concatenate([beam.mesh.points for beam in chain.beams]) for chain in self.chains]
        )
        # the rotational block of each beam's inverse section stiffness, in section axes
        # (in global axes: R C R^T, the section stiffness rotating by blockdiag(R, R))
        self.compliance = [np.linalg.inv(beam.section.stiffness)[3:, 3:] for beam in self.beams]
        self.kinds = np.array([beam.formulation.kind for beam in self.beams], dtype=np.int64)
        #: The dofs of a node the line's displacement reads: its translations, or all six on
        #: a chain with cubic elements (eq. T11).
        self.width = 6 if np.any(self.kinds == CUBIC) else 3
        # the diagonal of each element's section stiffness (the cubic element's, eq. T11)
        self.stiffness = np.concatenate(
            [
                np.tile(np.diag(beam.section.stiffness), (n, 1))
                for beam, n in zip(self.beams, counts, strict=True)
            ]
        )
        self.regions = influence_regions(self.npe)
        self.members = np.arange(len(self.chains))
        self._ends = np.ascontiguousarray(shape_functions(np.array([0.0, 1.0]), self.npe)[1].T)
        self._frames: ElementFrames | None = None
        self._node_map: np.ndarray | None = None

    def subset(self, members: np.ndarray) -> ChainStack:
        """The stack of the given members only (their topology already checked)."""
        out = copy.copy(self)
        out.chains = [self.chains[b] for b in members]
        out.breaks, out.h, out.points = self.breaks[members], self.h[members], self.points[members]
        out.vertex_s, out.map = self.vertex_s[members], self.map[members]
        out.members = np.arange(len(out.chains))
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
            if not (
                stack.npe == first.npe
                and _same_topology(first.chains[0], stack.chains[0], maps=False)
            ):
                raise ValueError(
                    f"{stack.name}: its chains differ from {first.name}'s in more "
                    "than their node positions and dof maps"
                )
        out = copy.copy(first)
        out.chains = [c for stack in stacks for c in stack.chains]
        out.breaks, out.h, out.points, out.vertex_s = (
            np.concatenate([getattr(stack, f) for stack in stacks])
            for f in ("breaks", "h", "points", "vertex_s")
        )
        out.maps = np.concatenate([stack.maps for stack in stacks])
        out._node_map = None
        out.map = np.concatenate(
            [stack.map + sum(len(s.maps) for s in stacks[:i]) for i, stack in enumerate(stacks)]
        )
        out.members = np.arange(len(out.chains))
        out._frames = (
            None
            if any(stack._frames is None for stack in stacks)
            else ElementFrames(
                *(np.concatenate(f) for f in zip(*(stack._frames for stack in stacks), strict=True))
            )
        )
        return out

    def _dofs(self, element: np.ndarray) -> np.ndarray:
        """The dofs (B, ..., npe, 6) of each member's ``element`` (B, ...), on its own map."""
        return self.maps[self.map.reshape((-1,) + (1,) * (element.ndim - 1)), element]

    def translated(self, shifts: np.ndarray) -> ChainStack:
        """``B`` copies of this one-member stack, copy ``b`` with the structure's beams moved
        rigidly by ``shifts[b]`` ((B, n_beams, 3), one shift per beam of the structure), as
        :meth:`fvbeam.beam.Beam.translated` would move them (the node positions are this
        chain's plus the shift), without building the moved chains.  A translation changes
        nothing but the node positions, so every member keeps this chain (its beams, offsets
        and dof maps); every query reads the moved positions."""
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
        which report an abscissa off the chain; :func:`sliders.lines.batched_kernel.locate_one`)."""
        xi = self._checked(xi)
        return stack_kernel.locate(xi, self.breaks, self.vertex_s, self.first_element, self.h)

    @property
    def kernel_chains(self) -> stack_kernel.Chains:
        """The chains' layout as the compiled kernels read it
        (:class:`sliders.lines.batched_kernel.Chains`)."""
        frames = self.element_frames()
        return stack_kernel.Chains(
            self.map,
            self.maps,
            self.cells,
            self.points,
            self.breaks,
            self.vertex_s,
            self.first_element,
            self.h,
            self.lag,
            self.kinds,
            self.regions,
            self._ends,
            self.stiffness,
            self.width,
            frames.R0,
            frames.compliance,
        )

    def _checked(self, xi: np.ndarray) -> np.ndarray:
        """``xi`` (B,) as contiguous floats; raises ``ValueError`` for an abscissa off the
        chain (:func:`fvbeam.geometry.locate_abscissa`)."""
        xi = np.ascontiguousarray(xi, dtype=float)
        if not (0.0 <= xi.min() and xi.max() <= self.length):  # NaN fails too
            locate_abscissa(xi, self.offsets, self.name, "the chain")  # raises if off it
        return xi

    def _query(
        self, xi: np.ndarray, q: np.ndarray | None, transfer: bool, rotation: bool
    ) -> stack_kernel.LineArrays:
        """:func:`sliders.lines.batched_kernel.line_state` at ``xi`` (B,): the deformed line on the
        states ``q`` (B, n) unless None, the load transfer and the rotation if asked."""
        xi = self._checked(xi)
        return stack_kernel.line_state(
            xi,
            np.zeros((len(xi), 0)) if q is None else np.ascontiguousarray(q, dtype=float),
            self.kernel_chains,
            q is not None,
            transfer,
            rotation,
        )

    def line_state(
        self,
        xi: np.ndarray,
        q: np.ndarray,
        rotation: bool,
        smearing: float = 0.0,
        kernel: str = "box",
    ) -> LineState:
        """What a joint needs of each member at ``xi`` (B,) on its state ``q`` (B, n), in one
        kernel call (:class:`LineState`): with ``smearing > 0`` the load transfer is each
        member's smeared one (:meth:`transfer`); ``rotation``: the section rotation too."""
        a = self._query(xi, q, smearing == 0, rotation)
        load = (a.load_dofs, a.G, a.dG) if smearing == 0 else self.transfer(xi, smearing, kernel)
        g = a.geometry
        return LineState(
            self._interpolation(a),
            g[:, 0],
            g[:, 1],
            g[:, 2],
            g[:, 3],
            g[:, 4],
            g[:, 5],
            a.contact,
            a.contact_xi,
            *load,
            self._rotation(a) if rotation else None,
        )

    @staticmethod
    def _interpolation(a: stack_kernel.LineArrays) -> Interpolation:
        """The interpolation of a kernel answer."""
        return Interpolation(
            a.dofs,
            a.reference,
            a.N,
            a.dN,
            a.d2N,
            a.tangent_dofs,
            a.tangent_reference,
            a.T,
            a.T_xi,
        )

    def _nodes(self, element: np.ndarray) -> np.ndarray:
        """Reference node positions ``(B, ..., npe, 3)`` of each member's ``element``
        (B, ...)."""
        return self.points[self.members.reshape((-1,) + (1,) * element.ndim), self.cells[element]]

    def interpolation(self, xi: np.ndarray) -> Interpolation:
        """Where each member's ``xi`` sits, how its element interpolates the line there, and
        the recovered tangent (module docstring)."""
        return self._interpolation(self._query(xi, None, False, False))

    def rotation(self, xi: np.ndarray) -> LineRotation:
        """The section rotation at ``xi`` and its reference frame, per member.

        On a Lagrange element (fv, Galerkin) the rotation is interpolated linearly between the
        two consecutive nodes that bracket ``xi`` (the element's vertices, and its mid-node
        for 3-node elements): the weights are continuous along the chain, so a couple carried
        by them never jumps.  Its compliance ``flex = kink C``: ``kink`` is how far the exact
        rotation at a couple ``M`` lies off that interpolation, per unit ``C M``:
        ``w0 w1 span`` for exact nodal rotations, plus ``MID_NODE_LAG h w_mid^2`` on a 3-node
        element, whose mid-node rotation lags by that much under the share ``w_mid M`` it
        carries (``docs/sliders.md``); ``C`` is the section's bending-and-torsion compliance
        (the rotational block of the inverse section stiffness) in global axes, taken in the
        element's reference frame at ``xi``.  On a cubic element the rotation is the
        element's own (eq. T11, on its nodes' six dofs) and ``flex`` the rotational block of
        its compliance (eq. T13), exact.  The reference frame ``R0``, its curvature ``k0``
        and ``k0_/xi`` come from the element's reference interpolation and the mesh's
        ``up``.  When every member's element is straight, ``R0`` and ``C`` are read from
        :meth:`element_frames` (``k0 = k0_/xi = 0``).
        """
        return self._rotation(self._query(xi, None, False, True))

    def _rotation(self, a: stack_kernel.LineArrays) -> LineRotation:
        """The rotation of a kernel answer; off straight elements, the frame, curvature and
        compliance computed at ``xi`` (:meth:`rotation`)."""
        beam, element, X = a.beam, a.element, a.X
        R0, flex, flex_xi = a.R0, a.flex, a.flex_xi
        k0 = k0_xi = np.zeros((len(X), 3))
        if not self.element_frames().straight[self.members, element].all():
            # curved: Lagrange 3-node elements only (a cubic element is straight)
            l0, l0_xi = self._reference_line(element, X)
            R0, k0 = frame_and_curvature(l0, l0_xi, self.up[element])
            k0_xi = curvature_rate(l0, l0_xi, np.zeros(3), self.up[element])
            compliance = np.zeros((len(X), 3, 3))
            for b in np.unique(beam):
                on = beam == b
                compliance[on] = R0[on] @ self.compliance[b] @ np.swapaxes(R0[on], 1, 2)
            flex = a.kink[:, None, None] * compliance
            flex_xi = a.kink_xi[:, None, None] * compliance
        return LineRotation(a.rotation_dofs, a.W, a.W_xi, a.W_xixi, flex, flex_xi, R0, k0, k0_xi)

    def _reference_line(self, element: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The reference line's ``l0`` and ``l0_/xi`` at the reference coordinates ``X``
        (...) of the members' ``element`` (...)."""
        nodes = self._nodes(element)
        h = self.h[self.members.reshape((-1,) + (1,) * (element.ndim - 1)), element]
        l0, l0_xi = stack_kernel.reference_line(
            np.ascontiguousarray(nodes.reshape(-1, self.npe, 3)),
            h.ravel(),
            np.ascontiguousarray(X, dtype=float).ravel(),
        )
        return l0.reshape(X.shape + (3,)), l0_xi.reshape(X.shape + (3,))

    def element_frames(self) -> ElementFrames:
        """Per member and element, whether the element is straight in the reference
        configuration (``|l0_/xi| <= 1e-12 |l0|``, the test by which
        :func:`sliders.lines.rigid.curvature_rate` takes ``k0_/xi`` as zero; ``k0`` is then zero
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
                R0,
                R0 @ sections @ np.swapaxes(R0, -1, -2),
            )
        return self._frames

    def transfer(
        self, xi: np.ndarray, smearing: float = 0.0, kernel: str = "box"
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """How a force and couple ``[F; M]`` at each member's ``xi`` loads its chain (T6).

        Returns global ``dofs`` (B, k), ``G`` (B, k, 6) and ``dG/dxi`` (B, k, 6) as
        :meth:`sliders.lines.chain.BeamChain.transfer` gives them, compiled: without smearing
        the test functions at ``xi`` (:func:`sliders.lines.batched_kernel.line_state`); with
        ``smearing > 0`` the kernel integrated against them over the chain and normalised by
        its mass there, with the exact derivative
        (:func:`sliders.lines.batched_kernel.smeared_transfer`, the kernel form's quadrature
        :data:`KERNEL_RULE` on the same pieces): the dofs of the nodes of the elements the
        kernel reaches, padded to a common ``k`` with zero rows on the member's last dof.
        """
        smearing = check_smearing(smearing, kernel)
        if smearing > 0:
            return stack_kernel.smeared_transfer(
                self._checked(xi),
                Smearing(smearing, kernel == "box", *steps(smearing, kernel), *KERNEL_RULE),
                self.kernel_chains,
            )
        a = self._query(xi, None, True, False)
        return a.load_dofs, a.G, a.dG

    def project(self, points: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Abscissae of the points of the deformed chains (states ``q``, (B, n)) closest to
        ``points`` (B, 3), Newton started from the closest node
        (:func:`sliders.lines.rigid.project`)."""
        grid, node = self._node_grid()
        sampled = self.points[:, node] + gather(q, self._node_dofs()[self.map[:, None], node])

        def curve(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            x = self._query(xi, q, False, False).geometry
            return x[:, 0], x[:, 1], x[:, 2]

        return project(curve, grid, points, sampled)

    def _node_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The distinct node abscissae of the chain, increasing (tied for all members), and
        a node (of :attr:`points`) at each: the beams' nodes are their vertices along the
        beam, then their mid nodes (:class:`fvbeam.mesh.BeamMesh`)."""
        return np.unique(
            np.concatenate(
                [
                    offset + beam.mesh.node_abscissae()
                    for offset, beam in zip(self.offsets[:-1], self.beams, strict=True)
                ]
            ),
            return_index=True,
        )

    def _node_dofs(self) -> np.ndarray:
        """The translational dofs (maps, nodes, 3) of every node of :attr:`points`, per dof
        map, computed once."""
        if self._node_map is None:
            self._node_map = np.zeros((len(self.maps), self.points.shape[1], 3), dtype=np.int64)
            self._node_map[:, self.cells] = self.maps[..., :3]
        return self._node_map


def _same_topology(a: Chain, b: Chain, maps: bool = True) -> bool:
    """Whether chains ``a`` and ``b`` differ at most in their node positions (and, without
    ``maps``, their dof maps).  Beams sharing
    their arc lengths (moved copies, :meth:`fvbeam.mesh.BeamMesh.translated`) have equal
    lengths and chain offsets without comparing them."""
    return (
        len(a.beams) == len(b.beams)
        and (
            all(x.mesh.vertex_s is y.mesh.vertex_s for x, y in zip(a.beams, b.beams, strict=True))
            or _tied(a.offsets, b.offsets)
        )
        and (
            not maps
            or all(
                np.array_equal(a.structure.dof_maps[i], b.structure.dof_maps[j])
                for i, j in zip(a.indices, b.indices, strict=True)
            )
        )
        and all(
            x.formulation == y.formulation
            and x.section is y.section
            and (x.mesh.cells is y.mesh.cells or np.array_equal(x.mesh.cells, y.mesh.cells))
            and (
                x.mesh.vertex_s is y.mesh.vertex_s
                or _tied(x.mesh.element_length, y.mesh.element_length)
            )
            and (x.mesh.up is y.mesh.up or np.array_equal(x.mesh.up, y.mesh.up))
            for x, y in zip(a.beams, b.beams, strict=True)
        )
    )


def _tied(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the lengths ``a`` equal ``b`` to :data:`LENGTH_TIE` (relative to ``b``;
    ``np.allclose(a, b, rtol=LENGTH_TIE, atol=0)`` without its overhead)."""
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= LENGTH_TIE * np.abs(b)))


def _weighted(
    f: np.ndarray, reference: np.ndarray, q: np.ndarray, dofs: np.ndarray
) -> tuple[np.ndarray, ...]:
    """``reference_j + f_j q[dofs]`` for each ``j`` of matrices ``f`` (..., k, 3, m),
    reference values (..., k, 3) and dofs (..., m): on one state ``q`` (n,), or on each
    member's own (``q`` (B, n), leading axis of ``f`` B)
    (:func:`sliders.lines.batched_kernel.weighted_current`).  Returns ``k`` arrays
    (..., 3)."""
    lead, (k, m) = f.shape[:-3], (f.shape[-3], f.shape[-1])
    P = int(np.prod(lead))
    rows = np.arange(P) if q.ndim == 2 else np.zeros(P, dtype=np.int64)
    out = stack_kernel.weighted_current(
        np.ascontiguousarray(f, dtype=float).reshape(P, k, 3, m),
        np.ascontiguousarray(reference, dtype=float).reshape(P, k, 3),
        np.ascontiguousarray(np.atleast_2d(q), dtype=float),
        rows,
        np.ascontiguousarray(dofs, dtype=np.int64).reshape(P, m),
    ).reshape(lead + (k, 3))
    return tuple(out[..., j, :] for j in range(k))
