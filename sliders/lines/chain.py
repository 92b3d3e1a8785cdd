"""A chain of deformable beams as one line with a continuous arc-length abscissa ``xi``.

The beams of a :class:`~fvbeam.structure.Structure` listed in order, each beam's end vertex being
the next beam's start vertex (the same structure node).  ``xi`` runs from 0 at the first
beam's start to the sum of the beam lengths; the chain finds the beam and element, so the user
never keeps offsets or indices.  Deformed geometry (paper Sec. 4): with ``X_i`` the node
positions and ``u_i`` their displacements, ``x(xi) = sum N_i (X_i + u_i)``,
``l = x_/xi`` and ``l_xi = l_/xi`` in the element's arc-length coordinate.

The interpolated centreline is only C0 at the element vertices: its one-sided tangents differ
there by the discretisation error of the slope (much more on shear-soft beams).  The
frictionless condition ``l . lambda = 0`` then has no root for body positions in a band
around the vertex, and Newton fails there.  The joint reads it on a *recovered* tangent
instead, continuous along the chain (:meth:`sliders.lines.batched.ChainStack.interpolation`); the
position, the load transfer and the constraints keep the interpolation itself.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cached_property, partial, wraps
from itertools import pairwise

import numpy as np

from fvbeam.copies import shallow_copy
from fvbeam.geometry import locate_abscissa
from fvbeam.smearing import check_smearing, density, slope, steps
from fvbeam.structure import Structure
from sliders.lines.batched import ChainStack, Interpolation, LineRotation


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


class BeamChain:
    """Beams ``beams`` of ``structure`` joined end to start, as one line: a beam's name (as a
    scene's ``line``), a list of names or indices (:meth:`fvbeam.structure.Structure.
    beam_index`).  ``name`` (for messages) defaults to the beams' names joined by ``+``.

    Raises ``ValueError`` naming the pair of beams that are not joined.
    """

    def __init__(
        self,
        structure: Structure,
        beams: str | int | Sequence[str | int],
        name: str | None = None,
    ) -> None:
        given = [beams] if isinstance(beams, (str, int, np.integer)) else list(beams)
        self.structure, self.indices = structure, [structure.beam_index(b) for b in given]
        self.beams = [structure.beams[i] for i in self.indices]
        self.name = "+".join(b.mesh.name for b in self.beams) if name is None else name
        if not self.indices:
            raise ValueError(f"{self.name or 'chain'}: a chain needs at least one beam")
        joined = zip(given, self.indices, self.beams, strict=True)
        for (a, i, beam_a), (b, j, beam_b) in pairwise(joined):
            end = structure.dof_maps[i][6 * beam_a.node_index("end")]
            start = structure.dof_maps[j][6 * beam_b.node_index("start")]
            if end != start:
                raise ValueError(
                    f"{self.name}: beam {a!r} does not end where beam {b!r} starts "
                    "(tie its end node to the next beam's start node)"
                )
        self.offsets = np.concatenate([[0.0], np.cumsum([b.mesh.length for b in self.beams])])
        self.length = float(self.offsets[-1])
        self._memo: dict = {}

    def moved(self, structure: Structure) -> BeamChain:
        """This chain on ``structure``, a moved copy of its structure
        (:meth:`fvbeam.structure.Structure.moved`: the same numbering, each beam a translated
        copy, of the same lengths): the same beams by index, abscissae and name, not checked
        again; on another structure, the chain of the same beams built and checked anew."""
        if structure.dof_maps is not self.structure.dof_maps:
            return BeamChain(structure, self.indices, self.name)
        out = shallow_copy(self)
        out.structure, out.beams = structure, [structure.beams[i] for i in self.indices]
        out._memo = {}
        out.__dict__.pop("_stack", None)  # the cached stack reads the beams' nodes
        return out

    def locate(self, xi: float) -> tuple[int, float]:
        """Position in the chain of the beam holding ``xi``, and ``xi`` along that beam."""
        k, offset = locate_abscissa(float(xi), self.offsets, self.name, "the chain")
        return int(k), float(offset)

    @cached_property
    def _stack(self) -> ChainStack:
        """This chain alone as a stack: its point queries are the ``B = 1`` case."""
        return ChainStack([self])

    @memoised
    def interpolation(self, xi: float) -> Interpolation:
        """Where ``xi`` sits and how the line interpolates the beam there, with the
        recovered tangent (module docstring; :meth:`ChainStack.interpolation`)."""
        return self._stack.interpolation(np.array([float(xi)])).member(0)

    def geometry(self, xi: float, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l = x_/xi`` and ``l_/xi`` of the deformed chain (global dofs ``q``)."""
        return self.interpolation(xi).geometry(q)

    def project(self, point: np.ndarray, q: np.ndarray) -> float:
        """Abscissa of the point of the deformed chain closest to ``point``."""
        return float(self._stack.project(np.asarray(point, dtype=float)[None], q[None])[0])

    @memoised
    def rotation(self, xi: float) -> LineRotation:
        """The section rotation of the chain at ``xi`` and its reference frame
        (:meth:`ChainStack.rotation`)."""
        return self._stack.rotation(np.array([float(xi)])).member(0)

    @memoised
    def transfer(
        self, xi: float, smearing: float = 0.0, kernel: str = "box"
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """How a force and couple ``[F; M]`` at ``xi`` loads the chain (eq. T6).

        Returns global ``dofs`` (k,), ``G`` (k, 6) -- the nodal loads of a unit force and
        couple -- and ``dG / dxi`` (k, 6).  Without smearing, :meth:`ChainStack.transfer`
        (compiled).  With ``smearing > 0`` the load is spread by the kernel ``K`` over
        ``[xi - smearing, xi + smearing]``, across element and beam junctions, and rescaled
        where the chain ends cut it: ``G = A / m`` with ``A = int K(s - xi) H(s) ds`` and
        ``m = int K(s - xi) ds`` over the chain ``[0, L]``, each beam's part integrated by
        its kernel form (:meth:`fvbeam.beam.Beam.kernel_transfer`).  The derivative is
        exact: the chain ``[0, L]`` does not move with ``xi``, so
        ``A' = -int K'(s - xi) H(s) ds``, with ``K'`` the kernel's
        :func:`~fvbeam.smearing.slope` (the same form, in the same assembly) and the Dirac
        parts of its :func:`~fvbeam.smearing.steps` (``H`` read at the kernel's edges inside
        the chain, compiled as without smearing), likewise ``m'``, and
        ``G' = (A' - G m') / m``.
        """
        smearing = check_smearing(smearing, kernel)
        if smearing == 0:
            touched, G, dG = self._stack.transfer(np.array([float(xi)]))
            return touched[0], G[0], dG[0]
        self.locate(xi)
        kernels = [partial(f, smearing=smearing, kernel=kernel) for f in (density, slope)]
        dofs, A, dA, mass, dmass = [], [], [], 0.0, 0.0
        for k, beam in enumerate(self.beams):
            lo, hi = max(xi - smearing, self.offsets[k]), min(xi + smearing, self.offsets[k + 1])
            if hi <= lo:
                continue
            offset = self.offsets[k]
            local, H, m = beam.kernel_transfer(
                xi - offset, smearing, kernels, (lo - offset, hi - offset)
            )
            dofs.append(self.structure.dof_maps[self.indices[k]][local])
            A.append(H[0])
            dA.append(-H[1])
            mass += m[0]
            dmass -= m[1]
        for r, jump in zip(*steps(smearing, kernel), strict=True):
            if 0 < xi + r < self.length:
                edge, H_edge, _ = self._stack.transfer(np.array([xi + r]))
                dofs.append(edge[0])
                A.append(np.zeros_like(H_edge[0]))
                dA.append(-jump * H_edge[0])
                dmass -= jump
        unique, where = np.unique(np.concatenate(dofs), return_inverse=True)
        G, dG = np.zeros((len(unique), 6)), np.zeros((len(unique), 6))
        np.add.at(G, where, np.concatenate(A))
        np.add.at(dG, where, np.concatenate(dA))
        G /= mass
        return unique, G, (dG - G * dmass) / mass
