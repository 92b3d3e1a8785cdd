"""Beam formulations: finite-volume (fv2, fv3) and Galerkin (galerkin-p1, galerkin-p2).

All of them interpolate the six nodal fields (3 displacements, 3 rotations) with Lagrange
polynomials in the arc length (the *trial* side) and assemble the same internal-work form
(:func:`fvbeam.forms.internal_work`); they differ only in the *test* side and its quadrature:

============  =============================  ===========================================
name          test functions                 stiffness quadrature
============  =============================  ===========================================
fv2, fv3      rigid motions of each node's   the evaluation points (mid-point;
              influence region (paper Sec.5) s = -+1/sqrt(3))
galerkin-p1   P1 shape functions             reduced: 1 Gauss point; full: 2
galerkin-p2   P2 shape functions             reduced: 2 Gauss points; full: 3
============  =============================  ===========================================
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import ClassVar, Literal, get_args

import numpy as np
from skfem.element import Element, ElementLineP1, ElementLineP2, ElementVector

from fvbeam.elements import ElementBeamFV, influence_regions
from fvbeam.mesh import BeamMesh
from fvbeam.pointwise import transfer_many


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
    #: Whether the test functions are the rigid motions of the nodes' influence regions (fv,
    #: eq. T4) rather than the trial shape functions (Galerkin).
    rigid_test: ClassVar[bool] = False

    def trial_element(self) -> Element:
        """Lagrange interpolation of the six nodal fields."""
        scalar = ElementLineP1() if self.nodes_per_element == 2 else ElementLineP2()
        return ElementVector(scalar, 6)

    def test_element(self, mesh: BeamMesh) -> Element:
        raise NotImplementedError

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def transfer(
        self, mesh: BeamMesh, e: np.ndarray, X: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Test functions at points and their derivatives in ``xi``, shape ``P + (6 npe, 6)``.

        Row ``6a + c`` is test function ``c`` of local node ``a`` as the 6-vector
        ``(w, psi)``; read as a matrix, it carries a force and couple ``[F; M]`` applied at the
        point to the element's nodes (eq. T6).  :meth:`transfer_at` on the node positions of
        the elements ``e``.
        """
        e, X = np.broadcast_arrays(np.asarray(e), np.asarray(X, dtype=float))
        return self.transfer_at(mesh.points[mesh.cells[e]], mesh.element_length[e], X)

    def transfer_at(
        self, nodes: np.ndarray, h: np.ndarray, X: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`transfer` in elements given by their node positions ``P + (npe, 3)`` and
        lengths ``P``, at reference coordinates ``X`` (shape ``P``): elements of several
        meshes at once (:func:`fvbeam.pointwise.transfer_at` at each point)."""
        nodes = np.asarray(nodes, dtype=float)
        npe, points = self.nodes_per_element, np.shape(X)
        G, dG = transfer_many(
            self.rigid_test,
            influence_regions(npe),
            np.ascontiguousarray(nodes.reshape(-1, npe, 3)),
            np.ascontiguousarray(np.broadcast_to(h, points), dtype=float).ravel(),
            np.ascontiguousarray(X, dtype=float).ravel(),
        )
        shape = points + (6 * npe, 6)
        return G.reshape(shape), dG.reshape(shape)

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

    rigid_test: ClassVar[bool] = True

    def test_element(self, mesh: BeamMesh) -> Element:
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

    def test_element(self, mesh: BeamMesh) -> Element:
        return self.trial_element()

    def stiffness_quadrature(self, test: Element) -> tuple[np.ndarray, np.ndarray]:
        n = self.nodes_per_element - (1 if self.integration == "reduced" else 0)
        X, W = gauss(n)
        return X[None, :], W

    def load_quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        X, W = gauss(4)
        return X[None, :], W


#: The formulations by name (the scenes' ``formulation`` takes one of them).
FormulationName = Literal["fv2", "fv3", "galerkin-p1", "galerkin-p2"]
FORMULATIONS: tuple[str, ...] = get_args(FormulationName)


def formulation(name: str, integration: str = "reduced") -> Formulation:
    """Formulation by name: ``fv2``, ``fv3``, ``galerkin-p1`` or ``galerkin-p2``.

    ``integration`` ('reduced' or 'full') applies to the Galerkin formulations only.
    """
    if name == "fv2":
        return FiniteVolume("fv2", 2)
    if name == "fv3":
        return FiniteVolume("fv3", 3)
    if name in ("galerkin-p1", "galerkin-p2"):
        return Galerkin(name, 2 if name.endswith("p1") else 3, integration)
    raise ValueError(f"unknown formulation {name!r}; choose one of {', '.join(FORMULATIONS)}")
