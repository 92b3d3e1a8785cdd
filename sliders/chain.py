"""A chain of deformable beams as one line with a continuous arc-length abscissa ``xi``.

The beams of a :class:`~fvbeam.statics.Structure` listed in order, each beam's end vertex being
the next beam's start vertex (the same structure node).  ``xi`` runs from 0 at the first
beam's start to the sum of the beam lengths; the chain finds the beam and element, so the user
never keeps offsets or indices.  Deformed geometry (paper Sec. 4): with ``X_i`` the node
positions and ``u_i`` their displacements, ``x(xi) = sum N_i (X_i + u_i)``,
``l = x_/xi`` and ``l_xi = l_/xi`` in the element's arc-length coordinate.

The interpolated centreline is only C0 at the element vertices: its one-sided tangents differ
there by the discretisation error of the slope (much more on shear-soft beams).  The
frictionless condition ``l . lambda = 0`` then has no root for body positions in a band
around the vertex, and Newton fails there.  The joint reads it on a *recovered* tangent
instead, continuous along the chain (:meth:`BeamChain._tangent_recovery`); the position, the
load transfer and the constraints keep the interpolation itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import wraps
from typing import Callable, Sequence

import numpy as np

from fvbeam.formulations import FiniteVolume, composite_gauss
from fvbeam.geometry import locate_abscissa
from fvbeam.mesh import shape_functions
from fvbeam.smearing import check_smearing, density
from fvbeam.statics import Structure
from sliders.lines import curvature_rate, frame_and_curvature, project


#: Lag of a 3-node element's mid-node rotation under a couple ``M`` at the mid-node, per
#: ``h C M`` (the exact rotation steps its rate by ``C M`` there, the elements cannot):
#: fv3, ``1/4 - sqrt(3)/8``: the curvature, linear in the element and exact at the
#: evaluation points, integrates from a vertex to the mid-node to ``(1/4 + sqrt(3)/8) h C M``
#: where the exact step gives ``h C M / 2``; Galerkin P2, ``1/16``: the quadratic minimising
#: the energy with the couple at the mid-node reaches ``7/16 h C M`` there.
MID_NODE_LAG = {"fv": 0.25 - np.sqrt(3.0) / 8, "galerkin": 1.0 / 16}


def memoised(method: Callable) -> Callable:
    """Keep a chain method's results by its (positional) arguments: what the chain gives at
    ``xi`` depends on the reference geometry only, and a Newton step asks for it several
    times (the joint, its residual check).  The store is emptied when it reaches 512
    entries.  Results are shared: callers must not modify them."""
    @wraps(method)
    def wrapper(self, *args):
        key = (method.__name__,) + args
        store = self._memo
        if key not in store:
            if len(store) >= 512:
                store.clear()
            store[key] = method(self, *args)
        return store[key]
    return wrapper


def second_derivatives(nodes_per_element: int) -> np.ndarray:
    """d^2 N / dX^2 of the Lagrange shape functions on [0, 1] (constant)."""
    return np.zeros(2) if nodes_per_element == 2 else np.array([4.0, 4.0, -8.0])


class BeamChain:
    """Beams ``beams`` (indices into ``structure``) joined end to start, as one line.

    Raises ``ValueError`` naming the pair of beams that are not joined.
    """

    def __init__(self, structure: Structure, beams: Sequence[int], name: str = "chain") -> None:
        self.structure, self.indices, self.name = structure, list(beams), name
        if not self.indices:
            raise ValueError(f"{name}: a chain needs at least one beam")
        self.beams = [structure.beams[structure.beam_index(b)] for b in self.indices]
        for (a, beam_a), (b, beam_b) in zip(zip(self.indices, self.beams),
                                            zip(self.indices[1:], self.beams[1:])):
            end = structure.dof_maps[a][6 * beam_a.node_index("end")]
            start = structure.dof_maps[b][6 * beam_b.node_index("start")]
            if end != start:
                raise ValueError(f"{name}: beam {a} does not end where beam {b} starts "
                                 "(tie its end node to the next beam's start node)")
        self.offsets = np.concatenate([[0.0], np.cumsum([b.mesh.length for b in self.beams])])
        self.length = float(self.offsets[-1])
        self._memo: dict = {}

    def locate(self, xi: float) -> tuple[int, float]:
        """Position in the chain of the beam holding ``xi``, and ``xi`` along that beam."""
        k, offset = locate_abscissa(float(xi), self.offsets, self.name, "the chain")
        return int(k), float(offset)

    @memoised
    def interpolation(self, xi: float) -> Interpolation:
        """Where ``xi`` sits and how the line interpolates the beam there."""
        k, local = self.locate(xi)
        mesh = self.beams[k].mesh
        e, X = mesh.locate(local)
        e, X = int(e), float(X)
        h = mesh.element_length[e]
        dofs, points = self._element(k, e)
        N, dN = shape_functions(np.array(X), mesh.nodes_per_element)
        return Interpolation(dofs, points, N, dN / h,
                             second_derivatives(mesh.nodes_per_element) / h**2,
                             *self._tangent_recovery(k, e, X, dN / h))

    def _element(self, k: int, e: int) -> tuple[np.ndarray, np.ndarray]:
        """Translational dofs (npe, 3) and reference node positions of element ``e`` of the
        chain's beam ``k``."""
        beam = self.beams[k]
        nodes = beam.mesh.cells[e]
        dofs = self.structure.dof_maps[self.indices[k]][6 * nodes[:, None] + np.arange(3)]
        return dofs, beam.mesh.points[nodes]

    def _end_slope(self, k: int, e: int, end: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dofs, node positions and ``dN/dxi`` at the start (``end = 0``) or the end
        (``end = 1``) of element ``e`` of beam ``k``."""
        mesh = self.beams[k].mesh
        dN = shape_functions(np.array(float(end)), mesh.nodes_per_element)[1]
        return (*self._element(k, e), dN / mesh.element_length[e])

    def _neighbour(self, k: int, e: int, side: int) -> tuple[int, int] | None:
        """The element before (``side = -1``) or after (``+1``) element ``e`` of beam ``k``
        along the chain, across beam junctions; None at the chain's ends."""
        e += side
        if 0 <= e < self.beams[k].mesh.n_elements:
            return k, e
        k += side
        if not 0 <= k < len(self.beams):
            return None
        return k, (self.beams[k].mesh.n_elements - 1 if side < 0 else 0)

    def _tangent_recovery(self, k: int, e: int, X: float, dN: np.ndarray) -> tuple:
        """Coefficients of the recovered tangent ``l~`` in element ``e`` (module docstring).

        ``l~ = l + (1 - X) (l_a - l(a)) + X (l_b - l(b))`` where ``l_a, l_b`` are the means
        of the one-sided tangents at the element's vertices (unchanged at the chain's ends):
        continuous along the chain, equal to ``l`` where the interpolated centreline has no
        corner.  Returns the dofs (m, 3), node positions (m, 3) and the coefficients of
        ``l~`` and of ``l~_/xi`` (m,) on them."""
        h = self.beams[k].mesh.element_length[e]
        dofs, points = self._element(k, e)
        blocks = [(dofs, points, dN.copy(), np.zeros_like(dN) + self._own_curvature(k, e))]
        for side, weight, weight_xi, end in ((-1, 1 - X, -1 / h, 0), (1, X, 1 / h, 1)):
            other = self._neighbour(k, e, side)
            if other is None:
                continue
            _, _, own = self._end_slope(k, e, end)
            d, p, theirs = self._end_slope(*other, 1 - end)
            blocks[0][2][:] -= 0.5 * weight * own
            blocks[0][3][:] -= 0.5 * weight_xi * own
            blocks.append((d, p, 0.5 * weight * theirs, 0.5 * weight_xi * theirs))
        return tuple(np.concatenate(part) for part in zip(*blocks))

    def _own_curvature(self, k: int, e: int) -> np.ndarray:
        """``d^2 N / dxi^2`` of element ``e`` of beam ``k`` (constant in the element)."""
        mesh = self.beams[k].mesh
        return second_derivatives(mesh.nodes_per_element) / mesh.element_length[e] ** 2

    def geometry(self, xi: float, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l = x_/xi`` and ``l_/xi`` of the deformed chain (global dofs ``q``)."""
        return self.interpolation(xi).geometry(q)

    def project(self, point: np.ndarray, q: np.ndarray) -> float:
        """Abscissa of the point of the deformed chain closest to ``point``."""
        grid = np.unique(np.concatenate([offset + beam.mesh.node_abscissae()
                                         for offset, beam in zip(self.offsets, self.beams)]))
        return project(lambda xi: self.geometry(xi, q), grid, point)

    @memoised
    def rotation(self, xi: float) -> LineRotation:
        """The section rotation of the chain at ``xi`` and its reference frame.

        The rotation is interpolated linearly between the two consecutive nodes that bracket
        ``xi`` (the element's vertices, and its mid-node for 3-node elements), whatever the
        beam formulation: the weights are continuous along the chain, so a couple carried by
        them never jumps.  ``kink`` is how far the exact rotation at a couple ``M`` lies off
        that interpolation, per unit ``C M``: ``w0 w1 span`` for exact nodal rotations, plus
        ``MID_NODE_LAG h w_mid^2`` on a 3-node element, whose mid-node rotation lags by that
        much under the share ``w_mid M`` it carries (``docs/sliders.md``).  The reference frame ``R0``, its curvature
        ``k0`` and ``k0_/xi`` come from the element's reference interpolation and the mesh's
        ``up``.  ``C`` is the section's bending-and-torsion compliance (the rotational block
        of the inverse section stiffness) in global axes, taken in the element's reference
        frame at ``xi``.
        """
        k, local = self.locate(xi)
        beam = self.beams[k]
        mesh = beam.mesh
        e, X = mesh.locate(local)
        h, X, nodes = float(mesh.element_length[e]), float(X), mesh.cells[e]
        along = np.array([0.0, 1.0, 0.5])[:len(nodes)]
        order = np.argsort(along)
        j = min(int(np.searchsorted(along[order], X, side="right")) - 1, len(nodes) - 2)
        pair = order[j:j + 2]
        span = (along[pair[1]] - along[pair[0]]) * h
        t = (X - along[pair[0]]) * h / span
        w = np.array([1 - t, t])
        mid = np.flatnonzero(pair == 2)
        family = "fv" if isinstance(beam.formulation, FiniteVolume) else "galerkin"
        shift = MID_NODE_LAG[family] * h
        kink, kink_xi = t * (1 - t) * span, 1 - 2 * t
        if mid.size:
            kink += shift * w[mid[0]] ** 2
            kink_xi += 2 * shift * w[mid[0]] * (1 if mid[0] else -1) / span
        interp = self.interpolation(xi)
        l0, l0_xi = interp.dN @ interp.X, interp.d2N @ interp.X
        R0, k0 = frame_and_curvature(l0, l0_xi, mesh.up)
        k0_xi = curvature_rate(l0, l0_xi, np.zeros(3), mesh.up)
        compliance = np.linalg.inv(beam.section.global_stiffness(R0[None])[0])[3:, 3:]
        dofs = self.structure.dof_maps[self.indices[k]][6 * nodes[pair][:, None] + np.arange(3, 6)]
        return LineRotation(dofs, w, np.array([-1.0, 1.0]) / span, kink, kink_xi, compliance,
                            R0, k0, k0_xi)

    @memoised
    def transfer(self, xi: float, smearing: float = 0.0,
                 kernel: str = "box") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """How a force and couple ``[F; M]`` at ``xi`` loads the chain (eq. T6).

        Returns global ``dofs`` (k,), ``G`` (k, 6) -- the nodal loads of a unit force and
        couple -- and ``dG / dxi`` (k, 6).  With ``smearing > 0`` the load is spread by the
        kernel over ``[xi - smearing, xi + smearing]``, across element and beam junctions, and
        rescaled where the chain ends cut it.  The derivative is exact: writing
        ``G = int K(r) H(xi + r) dr / int K(r) dr`` over the part of the kernel on the chain,
        it is the kernel average of ``H'`` plus ``K(b - xi) [H](b)`` at every jump ``b`` of
        the test functions (fv evaluation points, chain ends), minus ``G`` times the same
        end terms of the normalisation.
        """
        smearing = check_smearing(smearing, kernel)
        if smearing == 0:
            k, local = self.locate(xi)
            dofs, H, dH = self.beams[k].transfer(np.array([local]))
            return self.structure.dof_maps[self.indices[k]][dofs[0]], H[0], dH[0]
        self.locate(xi)
        lo, hi = max(xi - smearing, 0.0), min(xi + smearing, self.length)
        dofs, N, dN, weight = [], [], [], 0.0
        for k, beam in enumerate(self.beams):
            a, b = max(lo, self.offsets[k]), min(hi, self.offsets[k + 1])
            if b <= a:
                continue
            s, w = composite_gauss(self._breaks(k, a, b, xi), 3)
            w = w * density(s - xi, smearing, kernel)
            weight += w.sum()
            local, H, dH = beam.transfer(s - self.offsets[k])
            jump_xi, jump_dofs, J = beam.transfer_jumps()
            jump_xi = jump_xi + self.offsets[k]
            inside = (jump_xi > a) & (jump_xi < b)
            to_global = self.structure.dof_maps[self.indices[k]]
            dofs += [to_global[local], to_global[jump_dofs[inside]]]
            N += [w[:, None, None] * H, np.zeros_like(J[inside])]
            dN += [w[:, None, None] * dH,
                   density(jump_xi[inside] - xi, smearing, kernel)[:, None, None] * J[inside]]
        dweight = 0.0
        for end, sign, k in ((0.0, 1.0, 0), (self.length, -1.0, len(self.beams) - 1)):
            if abs(end - xi) < smearing:
                cut = sign * density(np.array([end - xi]), smearing, kernel)
                local, H, _ = self.beams[k].transfer(np.array([end - self.offsets[k]]))
                dofs.append(self.structure.dof_maps[self.indices[k]][local])
                N.append(np.zeros_like(H))
                dN.append(cut[:, None, None] * H)
                dweight += cut[0]
        unique, where = np.unique(np.concatenate([d.ravel() for d in dofs]),
                                  return_inverse=True)
        G, dG = np.zeros((len(unique), 6)), np.zeros((len(unique), 6))
        np.add.at(G, where, np.concatenate([n.reshape(-1, 6) for n in N]))
        np.add.at(dG, where, np.concatenate([n.reshape(-1, 6) for n in dN]))
        return unique, G / weight, dG / weight - G * dweight / weight**2

    def _breaks(self, k: int, a: float, b: float, xi: float) -> np.ndarray:
        """Points in [a, b] of beam ``k`` (chain abscissae) where the integrand is not smooth:
        element ends, fv region boundaries, the kernel's peak."""
        mesh = self.beams[k].mesh
        local = self.beams[k].formulation.breakpoints()
        inner = self.offsets[k] + mesh.abscissae(np.arange(mesh.n_elements)[:, None], local)
        points = np.concatenate([[a, b, xi], inner.ravel()])
        return np.unique(points[(points >= a) & (points <= b)])


@dataclass(frozen=True)
class Interpolation:
    """The line near ``xi``: translational ``dofs`` (npe, 3) of the element holding it, node
    positions ``X`` (npe, 3), and the shape functions ``N`` with their first and second
    derivatives in ``xi``; the recovered tangent's dofs (m, 3), node positions (m, 3) and
    coefficients ``T``, ``T_xi`` (m,) (:meth:`BeamChain._tangent_recovery`)."""

    dofs: np.ndarray
    X: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    tangent_dofs: np.ndarray
    tangent_X: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray

    def tangent(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The recovered tangent ``l~`` and ``l~_/xi`` of the deformed line."""
        current = self.tangent_X + q[self.tangent_dofs]
        return self.T @ current, self.T_xi @ current

    def geometry(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l`` and ``l_/xi`` of the deformed line."""
        current = self.X + q[self.dofs]
        return self.N @ current, self.dN @ current, self.d2N @ current


@dataclass(frozen=True)
class LineRotation:
    """Section rotation of the line at ``xi``: ``theta = w @ q[dofs]``, with ``dofs`` (2, 3)
    the rotation dofs of the bracketing nodes, ``w`` their weights and ``w_xi`` their
    derivatives; ``kink = w0 w1 span`` and ``kink_xi`` its derivative (the correction for a
    couple at ``xi``, :class:`sliders.joint.Slider`); the section ``compliance`` (3, 3); the
    reference frame ``R0``, its curvature vector ``k0`` and ``k0_xi``."""

    dofs: np.ndarray
    w: np.ndarray
    w_xi: np.ndarray
    kink: float
    kink_xi: float
    compliance: np.ndarray
    R0: np.ndarray
    k0: np.ndarray
    k0_xi: np.ndarray
