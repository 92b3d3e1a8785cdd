"""The line at ``xi`` on a chain of geometrically exact beams.

A chain (:class:`~sliders.lines.chain.BeamChain`: beams joined end to start, ``xi`` the
arc length of the reference line, across elements and beams) of exact beams
(:mod:`fvbeam.exact_beam`: each node a position ``x_a`` and a rotation ``R_a``, the identity
in the reference configuration) is a line whose position and frame at ``xi`` follow the
nodes.  :meth:`ExactChain.at` reads what depends on the reference geometry only (which
element and nodes, the weights and their ``xi``-rates; :class:`LineSite`), the same
interpolation, load transfer and smearing the linear chain uses; the functions below make
the current line of it, with arithmetic only, so that they run on dual numbers
(:mod:`sliders.joints.dual`) as well as on floats:

* **position** (:func:`position`): ``x(xi) = sum_a N_a(xi) x_a`` and ``l = x_/xi`` with the
  element's Lagrange functions, the linear chain's ``x_0 + N q`` written on the current
  positions;
* **section frame** (:func:`section_frame`): between the two consecutive nodes ``a``, ``b``
  that bracket ``xi`` (the element's vertices, and its mid-node on 3-node elements: the
  linear chain's ``W``), with the linear weight ``s(xi)`` of ``b``::

      Lambda(xi) = R_a cay(s g),     g = cay^-1(R_a^T R_b),     D = Lambda R_0(xi),

  ``cay(g) = I + d (g x + (g x)^2 / 2)``, ``d = 4 / (4 + g . g)``, the Cayley map of the
  Gibbs-Rodrigues parameters ``g = 2 tan(phi / 2) v`` (the parametrisation of the reference
  implementation's nodes, Ghiringhelli, Masarati and Mantegazza, AIAA J. 38 (2000) 131-138),
  ``cay^-1(Q) = 4 ax(Q) / (1 + tr Q)``.  Interpolating the *relative* rotation of the two
  nodes is objective (a rigid rotation of the whole line turns ``Lambda`` with it and leaves
  ``g`` unchanged: Crisfield and Jelenic, Proc. R. Soc. A 455 (1999) 1125-1147), exact at the
  nodes (``Lambda = R_a`` at ``s = 0``, ``R_b`` at ``s = 1``), and to first order the linear
  chain's ``theta_L = (1 - s) theta_a + s theta_b``.  It holds for relative rotations of the
  two nodes below pi (``1 + tr Q > 0``);
* **curvature** ``k = ax(D_/xi D^T)`` (paper Sec. 4: the section's change of orientation
  along the line): ``k = R_a G(s g) g s_/xi + Lambda k_0`` with ``G(g) = d (I + g x / 2)``
  (``ax(cay(g)_/g[dg] cay(g)^T) = G(g) dg``, and ``G(s g) g = d g``), ``k_0`` the
  reference frame's own.

The load the line takes at ``xi`` (:func:`transfer`) is the linear chain's test functions
(:meth:`~sliders.lines.chain.BeamChain.transfer`, eq. T6, smeared over ``[xi - dL,
xi + dL]`` as the linear chain spreads it) on the current configuration: on a
finite-volume beam the node whose region holds the point takes the force and its moment about
the node's *current* position, ``w_a (x(xi) - x_a) x F`` (the fv regions' balance on the
current configuration, :mod:`fvbeam.exact_beam`); with smearing, the arm's change from the
reference is read at ``xi`` (the spread's own extent, at most 40 % of an element, turns with
the section only to the first order of its rotation).  On a Galerkin beam a force goes to the
nodes by the shape functions, which is its virtual work on any configuration.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from fvbeam.formulations import FiniteVolume
from fvbeam.structure import Structure
from sliders.lines.chain import BeamChain


def skew(v: Any) -> np.ndarray:
    """``skew(v)``, the matrix of ``v x``, for a 3-vector of any number type."""
    zero = 0 * v[0]
    return np.array([[zero, -v[2], v[1]], [v[2], zero, -v[0]], [-v[1], v[0], zero]], dtype=object)


def axial(A: Any) -> np.ndarray:
    """``ax(A)``, the vector of the skew-symmetric part of a 3x3 matrix, any number type."""
    return 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]], dtype=object)


def reciprocal(a: Any) -> Any:
    """``1 / a`` for a number of any type with ``+ * /`` (``(0 a + 1) / a``: a dual divided by
    a dual of the same level)."""
    return (a * 0 + 1) / a


def cayley(g: Any) -> np.ndarray:
    """``cay(g) = I + d (G + G G / 2)``, ``G = skew(g)``, ``d = 4 / (4 + g . g)`` (module
    docstring)."""
    G = skew(g)
    d = 4.0 * reciprocal(4.0 + g @ g)
    return np.eye(3) + d * (G + 0.5 * (G @ G))


def cayley_inverse(Q: Any) -> np.ndarray:
    """The Gibbs-Rodrigues parameters of a rotation, ``4 ax(Q) / (1 + tr Q)``."""
    return 4.0 * axial(Q) * reciprocal(1.0 + Q[0, 0] + Q[1, 1] + Q[2, 2])


@dataclass(frozen=True)
class LineSite:
    """What the line at ``xi`` reads of its chain's reference geometry (module docstring).

    ``nodes`` (m,) the structure nodes the element holding ``xi`` interpolates, ``N``,
    ``dN``, ``d2N`` (m,) their Lagrange functions at ``xi`` and the first two
    ``xi``-derivatives; ``pair`` (2,) the consecutive nodes bracketing ``xi``, ``s`` and
    ``s_xi`` the weight of the second (linear in ``xi``); ``load_dofs`` (k,) the global dofs
    a force and couple at ``xi`` load, ``G``, ``G_xi`` (k, 6) the test functions and their
    ``xi``-rates; ``X`` and ``l0`` the reference line and its tangent at ``xi``; ``R0``,
    ``k0``, ``k0_xi`` the reference frame (columns ``[t_0, ...]``) and its curvature;
    ``flex``, ``flex_xi``, ``flex_xixi`` (3, 3) the linear chain's kink correction
    ``kappa C`` and its first two ``xi``-rates (reference axes:
    :meth:`~sliders.lines.batched.ChainStack.rotation`; ``kappa`` is quadratic in ``xi``
    over the node span, so the second is the difference quotient of the first there);
    ``finite_volume`` whether the beam holding ``xi`` balances regions (the moment arms of
    :func:`transfer`)."""

    xi: float
    nodes: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    pair: np.ndarray
    s: float
    s_xi: float
    load_dofs: np.ndarray
    G: np.ndarray
    G_xi: np.ndarray
    X: np.ndarray
    l0: np.ndarray
    R0: np.ndarray
    k0: np.ndarray
    k0_xi: np.ndarray
    flex: np.ndarray
    flex_xi: np.ndarray
    flex_xixi: np.ndarray
    finite_volume: bool

    @property
    def touched(self) -> np.ndarray:
        """Every structure node the line at ``xi`` reads or loads, sorted."""
        return np.unique(np.concatenate([self.nodes, self.pair, self.load_dofs // 6]))


class ExactChain:
    """The beams ``beams`` of ``structure`` joined end to start (a
    :class:`~sliders.lines.chain.BeamChain`, its errors and abscissa) as a line of exact
    beams, with the load spread over ``smearing`` (``dL``, the linear chain's) by
    ``kernel``."""

    def __init__(
        self,
        structure: Structure,
        beams: str | int | Sequence[str | int],
        smearing: float = 0.0,
        kernel: str = "box",
        name: str | None = None,
    ) -> None:
        self.chain = BeamChain(structure, beams, name)
        self.name, self.length = self.chain.name, self.chain.length
        self.smearing, self.kernel = smearing, kernel

    def at(self, xi: float) -> LineSite:
        """The line's reference data at ``xi`` (``ValueError`` naming the chain off it)."""
        xi = float(xi)
        k, _ = self.chain.locate(xi)
        interp = self.chain.interpolation(xi)
        rotation = self.chain.rotation(xi)
        dofs, G, G_xi = self.chain.transfer(xi, self.smearing, self.kernel)
        s, s_xi = float(rotation.W[0, 3]), float(rotation.W_xi[0, 3])
        # flex_xi is linear over the node span: its difference quotient inside it is exact
        other = xi + 0.5 * (1 - s) / s_xi if s < 0.5 else xi - 0.5 * s / s_xi
        flex_xixi = (self.chain.rotation(other).flex_xi - rotation.flex_xi) / (other - xi)
        width = interp.N.shape[-1] // 3
        columns = 3 * np.arange(width)
        return LineSite(
            xi=xi,
            nodes=interp.dofs[columns] // 6,
            N=interp.N[0, columns],
            dN=interp.dN[0, columns],
            d2N=interp.d2N[0, columns],
            pair=rotation.dofs[[0, 3]] // 6,
            s=s,
            s_xi=s_xi,
            load_dofs=np.asarray(dofs),
            G=np.asarray(G),
            G_xi=np.asarray(G_xi),
            X=interp.reference[0],
            l0=interp.reference[1],
            R0=rotation.R0,
            k0=rotation.k0,
            k0_xi=rotation.k0_xi,
            flex=rotation.flex,
            flex_xi=rotation.flex_xi,
            flex_xixi=flex_xixi,
            finite_volume=isinstance(self.chain.beams[k].formulation, FiniteVolume),
        )

    def project(self, point: np.ndarray) -> float:
        """The abscissa of the reference line's point closest to ``point``."""
        q = np.zeros(self.chain.structure.n_dofs)
        return self.chain.project(point, q)


def position(x: Any, N: Any, dN: Any) -> tuple[Any, Any]:
    """``x(xi) = sum N_a x_a`` and ``l = sum N_a' x_a`` on the positions ``x`` (m, 3) of the
    nodes a site interpolates, with the functions ``N``, ``dN`` given (numbers, or duals
    carrying their ``xi``-rates)."""
    return N @ x, dN @ x


def section_frame(
    R_a: Any, R_b: Any, s: Any, s_xi: Any, R0: Any, k0: Any
) -> tuple[np.ndarray, np.ndarray]:
    """The section frame ``D = Lambda R_0`` at ``xi`` and its curvature
    ``k = ax(D_/xi D^T)`` (module docstring) from the bracketing nodes' rotations."""
    g = cayley_inverse(R_a.T @ R_b)
    Lam = R_a @ cayley(s * g)
    d = 4.0 * reciprocal(4.0 + (s * s) * (g @ g))
    return Lam @ R0, R_a @ (d * s_xi * g) + Lam @ k0


def transfer(
    site: LineSite,
    G: Any,
    load: Any,
    moved: Any,
    x_nodes: dict[int, Any],
    X_nodes: dict[int, np.ndarray],
) -> np.ndarray:
    """The nodal loads (on ``site.load_dofs``) of the force and couple ``load`` (6,) at
    ``xi``: ``G load`` (``G`` given, numbers or duals), plus on a finite-volume beam the
    change of each region's arm from the reference, ``w_a ((x - X) - (x_a - X_a)) x F``
    (module docstring); ``moved`` the line's displacement ``x - X`` at ``xi``, ``x_nodes``
    and ``X_nodes`` the nodes' current and reference positions by node."""
    out = G @ load
    if not site.finite_volume:
        return out
    where = {int(d): i for i, d in enumerate(site.load_dofs)}
    for node in np.unique(site.load_dofs // 6):
        node = int(node)
        w = G[where[6 * node], 0]
        arm = np.cross(moved - (x_nodes[node] - X_nodes[node]), load[:3])
        for k in range(3):
            out[where[6 * node + 3 + k]] = out[where[6 * node + 3 + k]] + w * arm[k]
    return out
