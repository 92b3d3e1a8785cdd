"""Finite-volume test functions, and the cubic element's functions, as custom scikit-fem
elements.

Each node owns an *influence region* bounded by the evaluation points (or a beam end).  Its six
test functions are the rigid motions of that region (``docs/theory.md``, eq. T4):

* translation ``c``:  ``w = e_c chi``,                 ``psi = 0``
* rotation ``k``:     ``w = e_k x (x - x_a) chi``,       ``psi = e_k chi``

with ``chi`` the indicator of the region.  A rigid motion has zero generalised strain inside
the region, so the internal virtual work reduces to the Dirac spikes of ``chi'`` at the
evaluation points: the region's force and moment balance about its node, with the lever arm
``x(evaluation point) - x_a`` of the internal shear.  The element reproduces those spikes on a
quadrature made of the evaluation points alone: there ``chi' = jump / (W detJ)``, so that the
scikit-fem sum ``sum f chi' W detJ`` returns ``jump * f`` exactly.

:class:`ElementBeamCubic` is the cubic element's (``docs/theory.md`` Sec. 9): its trial and
test functions are the interdependent interpolation of eq. T11, which depends on the element's
section frame and length and on the section, so the element holds the mesh and the section.
"""

from __future__ import annotations

import numpy as np
from skfem.element import DiscreteField, Element
from skfem.mapping import Mapping
from skfem.refdom import RefLine

from fvbeam.mesh import BeamMesh
from fvbeam.pointwise import cubic_many, indicator_many, rigid_motions_many
from fvbeam.section import Section


def evaluation_points(nodes_per_element: int) -> np.ndarray:
    """Evaluation points on the reference element [0, 1] (paper Sec. 5).

    Mid-point for 2-node elements; ``s = -+1/sqrt(3)`` on [-1, 1], the 2-point Gauss points,
    for 3-node elements.
    """
    if nodes_per_element == 2:
        return np.array([0.5])
    return np.array([(1 - 1 / np.sqrt(3)) / 2, (1 + 1 / np.sqrt(3)) / 2])


def influence_regions(nodes_per_element: int) -> np.ndarray:
    """Part of each local node's influence region inside the element, ``(npe, 2)`` bounds.

    Local node order: end 0, end 1, mid node.
    """
    p = evaluation_points(nodes_per_element)
    if nodes_per_element == 2:
        return np.array([[0.0, p[0]], [p[0], 1.0]])
    return np.array([[0.0, p[0]], [p[1], 1.0], [p[0], p[1]]])


def indicator(X: np.ndarray, nodes_per_element: int) -> np.ndarray:
    """Region indicators ``chi_a(X)``, shape ``(npe,) + X.shape``
    (:func:`fvbeam.pointwise.indicator_at` at each point).

    A point exactly on an evaluation point belongs half to each neighbouring region, the limit
    of a symmetric smearing of vanishing width.
    """
    X = np.asarray(X, dtype=float)
    chi = indicator_many(np.ascontiguousarray(X).ravel(), influence_regions(nodes_per_element))
    return chi.reshape((nodes_per_element,) + X.shape)


def jumps(nodes_per_element: int) -> np.ndarray:
    """``chi_a(p+) - chi_a(p-)`` at each evaluation point ``p``, shape ``(npe, n_points)``."""
    p = evaluation_points(nodes_per_element)
    bounds = influence_regions(nodes_per_element)
    return (bounds[:, :1] == p).astype(float) - (bounds[:, 1:] == p)


def rigid_motions(
    mesh: BeamMesh, e: np.ndarray, X: np.ndarray, chi: np.ndarray, dchi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Values and derivatives of the fv test functions (eq. T4) in elements ``e`` of
    ``mesh``: :func:`rigid_motions_at` on their node positions."""
    return rigid_motions_at(mesh.points[mesh.cells[e]], mesh.element_length[e], X, chi, dchi)


def rigid_motions_at(
    nodes: np.ndarray, h: np.ndarray, X: np.ndarray, chi: np.ndarray, dchi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Values and derivatives of the fv test functions (eq. T4), shape ``P + (6 npe, 6)``.

    Row ``6a + c`` is test function ``c`` of local node ``a`` as the 6-vector ``(w, psi)``:
    node ``a``'s block is ``chi_a [[I, 0], [skew(x - x_a), I]]``, which is also the matrix that
    carries a force and couple ``[F; M]`` at ``x`` to the node (force ``F``, moment
    ``M + (x - x_a) x F``).  The derivative, in the affine element coordinate (the abscissa
    ``xi``), is ``dchi_a [[I, 0], [skew(x - x_a), I]] + chi_a [[0, 0], [skew(x_/xi), 0]]``.

    Parameters
    ----------
    nodes
        Node positions of the element holding each point, ``P + (npe, 3)``.
    h
        Element lengths, shape ``P``.
    X
        Reference coordinates, shape ``P``.
    chi, dchi
        Indicator values and their derivatives in ``xi``, shape ``(npe,) + P``.
    """
    nodes = np.asarray(nodes, dtype=float)
    npe, points = nodes.shape[-2], nodes.shape[:-2]
    G, dG = rigid_motions_many(
        np.ascontiguousarray(nodes.reshape(-1, npe, 3)),
        np.ascontiguousarray(np.broadcast_to(h, points), dtype=float).ravel(),
        np.ascontiguousarray(np.broadcast_to(X, points), dtype=float).ravel(),
        *(
            np.ascontiguousarray(
                np.moveaxis(np.broadcast_to(f, (npe,) + points), 0, -1), dtype=float
            ).reshape(-1, npe)
            for f in (chi, dchi)
        ),
    )
    shape = points + (6 * npe, 6)
    return G.reshape(shape), dG.reshape(shape)


class AllAtOnce(Element):
    """A beam element of six dofs per node whose functions are evaluated all at once:
    scikit-fem asks for them one by one (``gbasis``) at the same points, so the first request
    evaluates all of them (``_all_functions``: values and derivatives in the abscissa,
    ``P + (n_functions, 6)`` each) and the next ones read them."""

    refdom = RefLine

    def __init__(self, n_functions: int) -> None:
        self.n_functions = n_functions
        self.nodal_dofs = 6
        self.dofnames = ["u"] * 6
        self._cache: tuple | None = None

    def gbasis(
        self, mapping: Mapping, X: np.ndarray, i: int, tind: np.ndarray | None = None
    ) -> tuple[DiscreteField]:
        if not 0 <= i < self.n_functions:
            self._index_error()
        if tind is None:
            tind = np.arange(mapping.mesh.t.shape[1])
        tind = np.asarray(tind)
        key = (id(mapping), X.shape, X.tobytes(), tind.tobytes())
        if self._cache is None or self._cache[0] != key:
            value, grad = self._all_functions(mapping, X, tind)
            self._cache = (
                key,
                np.moveaxis(value, (-2, -1), (0, 1)),
                np.moveaxis(grad, (-2, -1), (0, 1)),
            )
        _, value, grad = self._cache
        return (DiscreteField(value=value[i], grad=grad[i][:, None]),)

    def _all_functions(
        self, mapping: Mapping, X: np.ndarray, tind: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError


class ElementBeamFV(AllAtOnce):
    """Finite-volume beam test functions on one :class:`~fvbeam.mesh.BeamMesh`.

    Six dofs per node, numbered as ``ElementVector(ElementLineP1|P2(), 6)`` numbers them, so
    that the trial and test bases share the global dof numbering (a square Petrov-Galerkin
    system).  Evaluated on :meth:`stiffness_quadrature` it yields the spikes of the region
    boundaries; on any other points, the region indicators.
    """

    maxdeg = 0

    def __init__(self, mesh: BeamMesh) -> None:
        npe = mesh.nodes_per_element
        super().__init__(6 * npe)
        self.mesh = mesh
        self.interior_dofs = 6 if npe == 3 else 0
        self.points = evaluation_points(npe)
        self.weight = 1.0 / len(self.points)
        self.jumps = jumps(npe)

    def stiffness_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        """The evaluation points as a quadrature rule (weights cancel in the spikes)."""
        return self.points[None, :], np.full(len(self.points), self.weight)

    def _all_functions(
        self, mapping: Mapping, X: np.ndarray, tind: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """All 6 npe test functions at once (:class:`AllAtOnce`)."""
        npe = self.mesh.nodes_per_element
        Xe = np.broadcast_to(X[0], (len(tind),) + X.shape[-1:]) if X.ndim == 2 else X[0]
        e = np.broadcast_to(tind[:, None], Xe.shape)
        chi = indicator(Xe, npe)
        dchi = np.zeros_like(chi)
        detJ = np.abs(mapping.detDF(X, tind))
        for k, p in enumerate(self.points):
            on = np.isclose(Xe, p, rtol=0, atol=1e-14)
            dchi[:, on] = self.jumps[:, k : k + 1] / (self.weight * detJ[on])
        return rigid_motions(self.mesh, e, Xe, chi, dchi)


class ElementBeamCubic(AllAtOnce):
    """The cubic beam element's functions (eq. T11) on one :class:`~fvbeam.mesh.BeamMesh` of
    2-node (straight) elements with one :class:`~fvbeam.section.Section`: trial and test
    basis alike (a Galerkin element).

    Six dofs per node, numbered as ``ElementVector(ElementLineP1(), 6)`` numbers them (local
    dof ``6a + c``, node ``a``'s component ``c``).  Each function is a 6-component field
    ``(u, theta)`` in global axes; its gradient is the derivative in the abscissa (the affine
    coordinate scikit-fem sees: the elements are straight, metric 1).
    """

    maxdeg = 3

    def __init__(self, mesh: BeamMesh, section: Section) -> None:
        super().__init__(12)
        self.mesh, self.section = mesh, section
        self.frames = mesh.frames(np.arange(mesh.n_elements), np.full(mesh.n_elements, 0.5))
        self.stiffness = np.ascontiguousarray(np.diag(section.stiffness))

    def _all_functions(
        self, mapping: Mapping, X: np.ndarray, tind: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """All twelve functions and their derivatives (:func:`fvbeam.pointwise.cubic_many`)."""
        Xe = np.broadcast_to(X[0], (len(tind),) + X.shape[-1:]) if X.ndim == 2 else X[0]
        e = np.broadcast_to(tind[:, None], Xe.shape).ravel()
        frames = np.ascontiguousarray(self.frames[e])
        h = np.ascontiguousarray(self.mesh.element_length[e])
        points = np.ascontiguousarray(Xe, dtype=float).ravel()
        value, grad = (
            cubic_many(frames, self.stiffness, h, points, order).reshape(Xe.shape + (12, 6))
            for order in (0, 1)
        )
        return value, grad
