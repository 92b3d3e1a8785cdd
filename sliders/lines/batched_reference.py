"""The line state of one chain at one abscissa, in plain numpy: the reference of the kernel.

:mod:`sliders.lines.batched_kernel` computes, compiled and for ``B`` chains at once, what a
joint needs of its line at ``xi``; this module states the same quantities for one chain
(:class:`sliders.lines.chain.BeamChain`) as the equations they are, one function per
quantity, from the beams themselves (meshes, formulations, sections and the structure's
dof maps) rather than from the arrays :class:`~sliders.lines.batched.ChainStack` builds of
them.  It is slow and is not used by the solvers: it is what the kernel is tested against
(``tests/test_stack.py``), and where to read what the kernel computes.

* :func:`locate`: the beam, element and reference coordinate ``X`` of ``xi``;
* :func:`shape_functions`: the Lagrange interpolation of the element and its derivatives in
  ``xi`` (``docs/theory.md``, the trial interpolation);
* :func:`interpolation`: the deformed line ``x = sum N_a (X_a + u_a)``, ``l = x_/xi`` and
  ``l_/xi`` (paper Sec. 4) and the recovered tangent (:func:`recovered_tangent`,
  ``docs/sliders.md``, "Corners of the interpolated chain");
* :func:`transfer`: the test functions at ``xi`` read as load-transfer matrices ``G`` and
  ``dG/dxi`` (eqs. T4, T6 without smearing);
* :func:`rotation`: the section rotation between the two nodes around ``xi``, the kink
  correction and the reference frame (``docs/sliders.md``, "The orientation constraints");
* :func:`line_state`: all of them at once, as :meth:`ChainStack.line_state` gives them for
  one member.

Where the kernel pads (the recovered tangent's neighbours at the chain's ends), the
reference pads the same way, so that the two compare entry by entry.
"""

from __future__ import annotations

import numpy as np

from fvbeam.elements import influence_regions
from fvbeam.formulations import FiniteVolume
from fvbeam.geometry import locate_abscissa
from fvbeam.pointwise import LOCAL_NODES, shape_reference, transfer_reference
from sliders.lines.batched import (
    MID_NODE_LAG,
    Chain,
    Interpolation,
    LineRotation,
    LineState,
)
from sliders.lines.rigid import curvature_rate, frame_and_curvature


def _first_elements(chain: Chain) -> np.ndarray:
    """The chain index of each beam's first element, and the number of elements last."""
    return np.concatenate([[0], np.cumsum([beam.mesh.n_elements for beam in chain.beams])])


def beam_element(chain: Chain, element: int) -> tuple[int, int]:
    """The beam (position in the chain) and its own element of the chain's ``element``
    (elements numbered along the chain, beam after beam)."""
    first = _first_elements(chain)
    k = int(np.searchsorted(first, element, side="right") - 1)
    return k, element - int(first[k])


def element_length(chain: Chain, element: int) -> float:
    """The length ``h`` of the chain's ``element`` (the difference of its vertex abscissae)."""
    k, e = beam_element(chain, element)
    return float(chain.beams[k].mesh.element_length[e])


def element_nodes(chain: Chain, element: int) -> tuple[np.ndarray, np.ndarray]:
    """The structure dofs (npe, 6) and reference positions (npe, 3) of the nodes of the
    chain's ``element``: node ``a`` of beam ``i`` owns the beam's dofs ``6 a .. 6 a + 5``,
    which the structure's dof map of the beam numbers globally."""
    k, e = beam_element(chain, element)
    beam, cells = chain.beams[k], chain.beams[k].mesh.cells[e]
    dof_map = chain.structure.dof_maps[chain.indices[k]]
    return dof_map[6 * cells[:, None] + np.arange(6)], beam.mesh.points[cells]


def locate(chain: Chain, xi: float) -> tuple[int, int, float]:
    """The beam ``k`` holding ``xi`` (its position in the chain), the element (numbered along
    the chain) and the reference coordinate ``X`` in [0, 1] there.

    ``xi`` is placed on a beam by the chain's offsets (:func:`fvbeam.geometry.locate_abscissa`),
    then on an element by the beam's vertex abscissae (:meth:`fvbeam.mesh.BeamMesh.locate`): a
    point on a junction or a vertex belongs to the beam or element that starts there, the
    chain's end to the last ones.
    """
    k, along = locate_abscissa(float(xi), chain.offsets, chain.name, "the chain")
    e, X = chain.beams[int(k)].mesh.locate(along)
    return int(k), int(_first_elements(chain)[k] + e), float(X)


def shape_functions(X: float, h: float, npe: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The Lagrange shape functions ``N_a`` (npe,) of an element of length ``h`` at ``X``
    and their first and second derivatives in ``xi = xi_0 + h X``:

        N_a(X) = prod_{b != a} (X - X_b) / (X_a - X_b),   dN_a/dxi = N_a'(X) / h,
        d2N_a/dxi^2 = N_a''(X) / h^2,

    ``X_b`` the nodes' reference coordinates (:data:`fvbeam.pointwise.LOCAL_NODES`;
    :func:`fvbeam.pointwise.shape_reference`)."""
    N, dN, d2N = shape_reference(X, npe)
    return N, dN / h, d2N / h**2


def tangent_coefficients(chain: Chain, element: int, X: float) -> np.ndarray:
    """The coefficients on the element's nodes of ``l = x_/xi`` at ``X`` (the one-sided
    tangent of that element there): ``dN_a/dxi`` (npe,)."""
    npe = chain.beams[0].mesh.nodes_per_element
    return shape_functions(X, element_length(chain, element), npe)[1]


def recovered_tangent(
    chain: Chain, element: int, X: float
) -> tuple[list[int], np.ndarray, np.ndarray]:
    """The recovered tangent of ``docs/sliders.md`` at ``X`` of ``element``:

        l~ = l + (1 - X) (l_a - l(0)) + X (l_b - l(1)),

    ``l`` the element's tangent, ``l_a = (l(0) + l_before(1)) / 2`` and
    ``l_b = (l(1) + l_after(0)) / 2`` the means of the one-sided tangents at its vertices,
    shared with the elements before and after it along the chain (across beam junctions
    too); at the chain's ends there is no other side and ``l_a = l(0)`` (``l_b = l(1)``).

    Returns the three elements whose nodes it reads (the element, the one before and the
    one after, the element itself in place of a missing one) and the coefficients ``T`` and
    ``T_xi`` (3 npe,) of ``l~`` and ``l~_/xi`` on their nodes, in that order (zero on a
    missing one's).  ``X`` is affine in ``xi``: ``dX/dxi = 1 / h``.
    """
    npe, h = chain.beams[0].mesh.nodes_per_element, element_length(chain, element)
    n_elements = int(_first_elements(chain)[-1])
    T, T_xi = np.zeros((3, npe)), np.zeros((3, npe))
    T[0] = tangent_coefficients(chain, element, X)
    T_xi[0] = shape_functions(X, h, npe)[2]
    elements = [element, element, element]
    # the vertex at X = 0 with the element before, weight 1 - X; at X = 1, after, weight X
    for slot, other, end, other_end, weight, weight_xi in (
        (1, element - 1, 0.0, 1.0, 1 - X, -1 / h),
        (2, element + 1, 1.0, 0.0, X, 1 / h),
    ):
        if not 0 <= other < n_elements:
            continue
        elements[slot] = other
        # l_mean - l(end) = (l_other(other_end) - l(end)) / 2
        own = -0.5 * tangent_coefficients(chain, element, end)
        theirs = 0.5 * tangent_coefficients(chain, other, other_end)
        T[0] += weight * own
        T[slot] += weight * theirs
        T_xi[0] += weight_xi * own
        T_xi[slot] += weight_xi * theirs
    return elements, T.ravel(), T_xi.ravel()


def interpolation(chain: Chain, xi: float) -> Interpolation:
    """Where ``xi`` sits and how the line interpolates there (:class:`Interpolation`): the
    element's translational dofs and reference node positions, :func:`shape_functions`, and
    the :func:`recovered_tangent` with the dofs and positions of the nodes it reads."""
    _, element, X = locate(chain, xi)
    npe = chain.beams[0].mesh.nodes_per_element
    N, dN, d2N = shape_functions(X, element_length(chain, element), npe)
    dofs, points = element_nodes(chain, element)
    elements, T, T_xi = recovered_tangent(chain, element, X)
    read = [element_nodes(chain, e) for e in elements]
    return Interpolation(
        dofs[:, :3],
        points,
        N,
        dN,
        d2N,
        np.concatenate([d[:, :3] for d, _ in read]),
        np.concatenate([p for _, p in read]),
        T,
        T_xi,
    )


def deformed(f: np.ndarray, points: np.ndarray, dofs: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``sum_a f_a (X_a + u_a)``: the line's interpolation with coefficients ``f`` (m,) on
    nodes at ``points`` (m, 3) displaced by ``u_a = q[dofs_a]`` (translational dofs (m, 3))
    (paper Sec. 4)."""
    return f @ (points + q[dofs])


def transfer(chain: Chain, xi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How a force and couple ``[F; M]`` at ``xi`` loads the element holding it (eq. T6 with
    no smearing: the test functions at ``xi``).

    fv (eq. T4): node ``a`` takes ``chi_a(X) [[I, 0], [skew(x - x_a), I]]``, the force and
    its moment about the node, ``x`` the reference line at ``xi``; Galerkin: ``N_a I6``.
    Returns the element's dofs (6 npe,), ``G`` (6 npe, 6) and ``dG/dxi`` (``chi_a`` is
    piecewise constant: ``chi_a [[0, 0], [skew(x_/xi), 0]]``; Galerkin ``dN_a/dxi I6``):
    :func:`fvbeam.pointwise.transfer_reference` on the element's nodes.
    """
    k, element, X = locate(chain, xi)
    beam = chain.beams[k]
    npe = beam.mesh.nodes_per_element
    dofs, points = element_nodes(chain, element)
    G, dG = transfer_reference(
        beam.formulation.rigid_test,
        influence_regions(npe),
        points,
        element_length(chain, element),
        X,
    )
    return dofs.ravel(), G, dG


def rotation(chain: Chain, xi: float) -> LineRotation:
    """The section rotation at ``xi`` and its reference frame (:class:`LineRotation`).

    ``theta = w_0 theta_0 + w_1 theta_1`` between the two consecutive nodes along the element
    (end 0, mid node, end 1) around ``X``, ``w = (1 - t, t)`` with ``t`` the position between
    them; the kink correction ``kappa = w_0 w_1 span + lag h w_mid^2`` (``span`` their
    distance, ``w_mid`` the mid node's weight, ``lag`` :data:`MID_NODE_LAG` of the
    formulation; ``docs/sliders.md``, "The kink correction") and ``kappa_/xi``.  The reference
    frame ``R0`` of the reference line ``l0 = sum dN_a X_a`` and the beam's ``up``, its
    curvature ``k0 = ax(R0_/xi R0^T)`` and ``k0_/xi`` (:func:`sliders.lines.rigid.
    frame_and_curvature`, :func:`~sliders.lines.rigid.curvature_rate`), and the section's
    bending-and-torsion compliance ``R0 C R0^T`` (``C``: the rotational block of the
    inverse section stiffness).
    """
    k, element, X = locate(chain, xi)
    beam = chain.beams[k]
    npe, h = beam.mesh.nodes_per_element, element_length(chain, element)
    along = [0, 1] if npe == 2 else [0, 2, 1]  # local nodes in order along the element
    at = LOCAL_NODES[along]
    i = int(np.clip(np.searchsorted(at, X, side="right") - 1, 0, len(at) - 2))
    pair, span = [along[i], along[i + 1]], (at[i + 1] - at[i]) * h
    t = (X - at[i]) / (at[i + 1] - at[i])
    w, w_xi = np.array([1 - t, t]), np.array([-1 / span, 1 / span])
    is_mid = np.array([a == 2 for a in pair], dtype=float)
    w_mid, w_mid_xi = w @ is_mid, w_xi @ is_mid
    lag = MID_NODE_LAG["fv" if isinstance(beam.formulation, FiniteVolume) else "galerkin"]
    kink = w[0] * w[1] * span + lag * h * w_mid**2
    kink_xi = (w_xi[0] * w[1] + w[0] * w_xi[1]) * span + 2 * lag * h * w_mid * w_mid_xi
    dofs, points = element_nodes(chain, element)
    _, dN, d2N = shape_functions(X, h, npe)
    l0, l0_xi = dN @ points, d2N @ points
    R0, k0 = frame_and_curvature(l0, l0_xi, beam.mesh.up)
    k0_xi = curvature_rate(l0, l0_xi, np.zeros(3), beam.mesh.up)
    C = np.linalg.inv(beam.section.stiffness)[3:, 3:]
    return LineRotation(dofs[pair, 3:], w, w_xi, kink, kink_xi, R0 @ C @ R0.T, R0, k0, k0_xi)


def line_state(
    chain: Chain,
    xi: float,
    q: np.ndarray,
    smearing: float = 0.0,
    kernel: str = "box",
) -> LineState:
    """All a joint needs of the chain at ``xi`` on the state ``q`` (:class:`LineState` of one
    member, as :meth:`sliders.lines.batched.ChainStack.line_state` with ``rotation``): the
    :func:`interpolation`, the deformed line ``x``, ``l``, ``l_/xi`` and the recovered tangent
    ``l~``, ``l~_/xi`` (:func:`deformed`), the load transfer (:func:`transfer`; with
    ``smearing > 0`` the smeared one, :meth:`sliders.lines.chain.BeamChain.transfer`, which
    the stack reads too: a quadrature outside the kernel) and the :func:`rotation`."""
    line = interpolation(chain, xi)
    x, l, l_xi = (deformed(f, line.X, line.dofs, q) for f in (line.N, line.dN, line.d2N))
    tangent, tangent_xi = (
        deformed(f, line.tangent_X, line.tangent_dofs, q) for f in (line.T, line.T_xi)
    )
    load = transfer(chain, xi) if smearing == 0 else chain.transfer(xi, smearing, kernel)
    return LineState(line, x, l, l_xi, tangent, tangent_xi, *load, rotation(chain, xi))
