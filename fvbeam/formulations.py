"""Beam formulations: finite-volume (fv2, fv3), Galerkin (galerkin-p1, galerkin-p2) and the
cubic element (cubic).

The fv and Galerkin formulations interpolate the six nodal fields (3 displacements, 3
rotations) with Lagrange polynomials in the arc length (the *trial* side); the cubic one
with the interdependent interpolation of ``docs/theory.md`` Sec. 9 (eq. T11: cubic
deflection, quadratic rotation, coupled through the shear parameter).  All assemble the same
internal-work form (:func:`fvbeam.forms.internal_work`); they differ in their trial and test
sides and the quadrature:

============  =============================  ===========================================
name          test functions                 stiffness quadrature
============  =============================  ===========================================
fv2, fv3      rigid motions of each node's   the evaluation points (mid-point;
              influence region (paper Sec.5) s = -+1/sqrt(3))
galerkin-p1   P1 shape functions             reduced: 1 Gauss point; full: 2
galerkin-p2   P2 shape functions             reduced: 2 Gauss points; full: 3
cubic         its trial functions (eq. T11)  2 Gauss points (exact: constant shear,
                                             linear curvature)
============  =============================  ===========================================
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import ClassVar

import numpy as np
from skfem.element import Element, ElementLineP1, ElementLineP2, ElementVector

from fvbeam.elements import ElementBeamCubic, ElementBeamFV, influence_regions
from fvbeam.formulation_names import FORMULATIONS
from fvbeam.mesh import BeamMesh, shape_functions
from fvbeam.pointwise import CUBIC, FINITE_VOLUME, LAGRANGE, transfer_many
from fvbeam.section import Section


@cache
def _legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """n-point Gauss-Legendre rule on [-1, 1], computed once per ``n``."""
    return np.polynomial.legendre.leggauss(n)


def gauss(n: int, a: float = 0.0, b: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """n-point Gauss-Legendre rule on [a, b]."""
    x, w = _legendre(n)
    return a + (b - a) * (x + 1) / 2, w * (b - a) / 2


def composite_gauss(breaks: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n-point Gauss rule on each interval between consecutive increasing ``breaks``
    (points and weights in order; empty intervals are skipped)."""
    x, w = gauss(n)
    a, h = breaks[:-1], np.diff(breaks)
    a, h = a[h > 0, None], h[h > 0, None]
    return (a + h * x).ravel(), (h * w).ravel()


@dataclass(frozen=True)
class Formulation:
    """Common interface: trial element, test element, quadratures, test values at points."""

    name: str
    nodes_per_element: int
    #: The test functions' kind (:func:`fvbeam.pointwise.transfer_at`): Lagrange shape
    #: functions, the rigid motions of the nodes' influence regions (fv, eq. T4), or the cubic
    #: element's functions (eq. T11).
    kind: ClassVar[int] = LAGRANGE

    @property
    def degree(self) -> int:
        """The degree of the trial polynomials (a consistent mass integrates their
        products)."""
        return self.nodes_per_element - 1

    @property
    def rigid_test(self) -> bool:
        """Whether the test functions are the rigid motions of the nodes' influence regions
        (fv, eq. T4) rather than shape functions."""
        return self.kind == FINITE_VOLUME

    def trial_element(self, mesh: BeamMesh, section: Section) -> Element:
        """Lagrange interpolation of the six nodal fields."""
        scalar = ElementLineP1() if self.nodes_per_element == 2 else ElementLineP2()
        return ElementVector(scalar, 6)

    def test_element(self, mesh: BeamMesh, section: Section) -> Element:
        raise NotImplementedError

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def transfer(
        self, mesh: BeamMesh, section: Section, e: np.ndarray, X: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Test functions at points and their derivatives in ``xi``, shape ``P + (6 npe, 6)``.

        Row ``6a + c`` is test function ``c`` of local node ``a`` as the 6-vector
        ``(w, psi)``; read as a matrix, it carries a force and couple ``[F; M]`` applied at the
        point to the element's nodes (eq. T6).  :meth:`transfer_at` on the node positions,
        section frames and lengths of the elements ``e`` of a beam of ``section``.
        """
        e, X = np.broadcast_arrays(np.asarray(e), np.asarray(X, dtype=float))
        frames = mesh.frames(e, np.full(e.shape, 0.5))
        return self.transfer_at(
            mesh.points[mesh.cells[e]], mesh.element_length[e], X, frames, section
        )

    def transfer_at(
        self,
        nodes: np.ndarray,
        h: np.ndarray,
        X: np.ndarray,
        frames: np.ndarray,
        section: Section,
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`transfer` in elements given by their node positions ``P + (npe, 3)``,
        lengths ``P`` and section frames ``P + (3, 3)`` (the cubic element's), at reference
        coordinates ``X`` (shape ``P``): elements of several meshes at once
        (:func:`fvbeam.pointwise.transfer_at` at each point)."""
        nodes = np.asarray(nodes, dtype=float)
        npe, points = self.nodes_per_element, np.shape(X)
        G, dG = transfer_many(
            self.kind,
            influence_regions(npe),
            np.ascontiguousarray(nodes.reshape(-1, npe, 3)),
            np.ascontiguousarray(np.broadcast_to(frames, points + (3, 3))).reshape(-1, 3, 3),
            np.ascontiguousarray(np.diag(section.stiffness)),
            np.ascontiguousarray(np.broadcast_to(h, points), dtype=float).ravel(),
            np.ascontiguousarray(X, dtype=float).ravel(),
        )
        shape = points + (6 * npe, 6)
        return G.reshape(shape), dG.reshape(shape)

    def interpolation(
        self, mesh: BeamMesh, section: Section, e: np.ndarray, X: np.ndarray
    ) -> np.ndarray:
        """The trial functions at points of the elements ``e`` of a beam of ``section``,
        shape ``P + (6 npe, 6)``: row ``6a + c`` is the field ``(u, theta)`` of a unit value
        of node ``a``'s dof ``c``, here the Lagrange ``N_a e_c``."""
        N, _ = shape_functions(np.asarray(X, dtype=float), self.nodes_per_element)
        return np.einsum("a...,cd->...acd", N, np.eye(6)).reshape(np.shape(X) + (-1, 6))

    def breakpoints(self) -> np.ndarray:
        """Reference coordinates where the test functions are not smooth (element ends...)."""
        return np.array([0.0, 1.0])

    def check(self, mesh: BeamMesh) -> None:
        if mesh.nodes_per_element != self.nodes_per_element:
            raise ValueError(
                f"{mesh.name}: formulation {self.name} needs "
                f"{self.nodes_per_element}-node elements, the mesh has "
                f"{mesh.nodes_per_element}-node elements"
            )


@dataclass(frozen=True)
class FiniteVolume(Formulation):
    """Finite-volume beam of Ghiringhelli, Masarati and Mantegazza (paper ref. [8], Sec. 5)."""

    kind: ClassVar[int] = FINITE_VOLUME

    def test_element(self, mesh: BeamMesh, section: Section) -> Element:
        return ElementBeamFV(mesh)

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        return test.stiffness_quadrature()

    def breakpoints(self) -> np.ndarray:
        return np.unique(influence_regions(self.nodes_per_element))

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        X, W = composite_gauss(self.breakpoints(), 4)
        return X[None, :], W


@dataclass(frozen=True)
class Galerkin(Formulation):
    """Bubnov-Galerkin Timoshenko beam with full or reduced (uniform) integration."""

    integration: str = "reduced"

    def __post_init__(self) -> None:
        if self.integration not in ("full", "reduced"):
            raise ValueError(
                f"{self.name}: integration must be 'full' or 'reduced', got {self.integration!r}"
            )

    def test_element(self, mesh: BeamMesh, section: Section) -> Element:
        return self.trial_element(mesh, section)

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        n = self.nodes_per_element - (1 if self.integration == "reduced" else 0)
        X, W = gauss(n)
        return X[None, :], W

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        X, W = gauss(4)
        return X[None, :], W


@dataclass(frozen=True)
class Cubic(Formulation):
    """The cubic Timoshenko beam element: 2-node, Galerkin on the interdependent
    interpolation (eq. T11, Reddy's IIE), whose nodal solution is exact for loads at the
    nodes (``docs/theory.md`` Sec. 9)."""

    kind: ClassVar[int] = CUBIC

    @property
    def degree(self) -> int:
        """Cubic deflections."""
        return 3

    def trial_element(self, mesh: BeamMesh, section: Section) -> Element:
        """The interdependent interpolation of the element (eq. T11)."""
        return ElementBeamCubic(mesh, section)

    def test_element(self, mesh: BeamMesh, section: Section) -> Element:
        return self.trial_element(mesh, section)

    def interpolation(
        self, mesh: BeamMesh, section: Section, e: np.ndarray, X: np.ndarray
    ) -> np.ndarray:
        """The element's functions (eq. T11): its test functions (:meth:`transfer`)."""
        return self.transfer(mesh, section, e, X)[0]

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        """Two Gauss points: the strains of the element's functions are a constant shear and
        a linear curvature (and constant stretch and twist), so the integrand is at most
        quadratic and the stiffness exact; the points are where internal forces are
        recovered."""
        X, W = gauss(2)
        return X[None, :], W

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        X, W = gauss(4)
        return X[None, :], W


def formulation(name: str, integration: str = "reduced") -> Formulation:
    """Formulation by name: ``fv2``, ``fv3``, ``galerkin-p1``, ``galerkin-p2`` or ``cubic``.

    ``integration`` ('reduced' or 'full') applies to the Lagrange Galerkin formulations only.
    """
    if name == "fv2":
        return FiniteVolume("fv2", 2)
    if name == "fv3":
        return FiniteVolume("fv3", 3)
    if name in ("galerkin-p1", "galerkin-p2"):
        return Galerkin(name, 2 if name.endswith("p1") else 3, integration)
    if name == "cubic":
        return Cubic("cubic", 2)
    raise ValueError(f"unknown formulation {name!r}; choose one of {', '.join(FORMULATIONS)}")
