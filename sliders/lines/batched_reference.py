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
  ``xi`` (``docs/theory.md``, the trial interpolation), which interpolates the reference
  line;
* :func:`displacement`: the displacement the element interpolates from its nodes' dofs, as a
  matrix (the Lagrange ``N_a I`` on the translations; the cubic element's functions,
  eq. T11, on all six dofs);
* :func:`interpolation`: the deformed line ``x = sum N_a X_a + N q[dofs]``, ``l = x_/xi``
  and ``l_/xi`` (paper Sec. 4) and the recovered tangent (:func:`recovered_tangent`,
  ``docs/sliders.md``, "Corners of the interpolated chain");
* :func:`contact`: on a chain with cubic elements, the position's compliance under a load at
  ``xi`` (eq. T13);
* :func:`transfer`: the test functions at ``xi`` read as load-transfer matrices ``G`` and
  ``dG/dxi`` (eqs. T4, T6 without smearing);
* :func:`rotation`: the section rotation at ``xi`` (between the two nodes around it; the cubic
  element's own), its compliance under a couple there (the kink correction; eq. T13) and the
  reference frame (``docs/sliders.md``, "The orientation constraints");
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
from fvbeam.pointwise import (
    CUBIC,
    LOCAL_NODES,
    cubic_flex_reference,
    cubic_reference,
    shape_reference,
    transfer_reference,
)
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


def width(chain: Chain) -> int:
    """The dofs of a node the line's displacement reads: its three translations, or its six
    dofs on a chain with a cubic beam (eq. T11: the deflection reads the rotations)."""
    return 6 if any(beam.formulation.kind == CUBIC for beam in chain.beams) else 3


def element_frame(chain: Chain, element: int) -> np.ndarray:
    """The section frame of the chain's ``element`` at its middle
    (:meth:`fvbeam.mesh.BeamMesh.frames`): a cubic element's (straight) frame."""
    k, e = beam_element(chain, element)
    return chain.beams[k].mesh.frames(np.array(e), np.array(0.5))


def displacement(chain: Chain, element: int, X: float, order: int) -> np.ndarray:
    """The ``order``-th ``xi``-derivative of the displacement the chain's ``element``
    interpolates at ``X``, as its matrix (3, width npe) on its nodes' first :func:`width`
    dofs, node after node: ``N_a I`` on the translations of a Lagrange element
    (:func:`shape_functions`), the translation rows of a cubic element's functions
    (:func:`fvbeam.pointwise.cubic_reference`)."""
    k, _ = beam_element(chain, element)
    beam, w = chain.beams[k], width(chain)
    npe, h = beam.mesh.nodes_per_element, element_length(chain, element)
    if beam.formulation.kind == CUBIC:
        stiffness = np.diag(beam.section.stiffness)
        return cubic_reference(element_frame(chain, element), stiffness, h, X, order)[:, :3].T
    out = np.zeros((3, npe, w))
    if order < 3:  # Lagrange elements of degree at most 2
        out[:, :, :3] = np.einsum("a,cd->cad", shape_functions(X, h, npe)[order], np.eye(3))
    return out.reshape(3, -1)


def tangent_coefficients(chain: Chain, element: int, X: float) -> np.ndarray:
    """The coefficients on the element's nodes of ``l0 = x0_/xi`` at ``X`` (the one-sided
    tangent of that element there): ``dN_a/dxi`` (npe,)."""
    npe = chain.beams[0].mesh.nodes_per_element
    return shape_functions(X, element_length(chain, element), npe)[1]


def recovered_tangent(
    chain: Chain, element: int, X: float
) -> tuple[list[int], np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The recovered tangent of ``docs/sliders.md`` at ``X`` of ``element``:

        l~ = l + (1 - X) (l_a - l(0)) + X (l_b - l(1)),

    ``l`` the element's tangent, ``l_a = (l(0) + l_before(1)) / 2`` and
    ``l_b = (l(1) + l_after(0)) / 2`` the means of the one-sided tangents at its vertices,
    shared with the elements before and after it along the chain (across beam junctions
    too); at the chain's ends there is no other side and ``l_a = l(0)`` (``l_b = l(1)``).

    Returns the three elements whose nodes it reads (the element, the one before and the
    one after, the element itself in place of a missing one), the coefficients ``T`` and
    ``T_xi`` (3 npe,) of the reference ``l~0`` and ``l~0_/xi`` on their node positions, and
    the matrices (3, 3 m) of the displacement's on their nodes' dofs (:func:`displacement`),
    in that order (zero on a missing one's).  ``X`` is affine in ``xi``: ``dX/dxi = 1 / h``.
    """
    h = element_length(chain, element)
    n_elements = int(_first_elements(chain)[-1])

    def one_sided(e: int, at: float) -> tuple[np.ndarray, np.ndarray]:
        return tangent_coefficients(chain, e, at), displacement(chain, e, at, 1)

    npe = chain.beams[0].mesh.nodes_per_element
    T, T_xi = np.zeros((3, npe)), np.zeros((3, npe))
    m = 3 * npe if width(chain) == 3 else 6 * npe
    D, D_xi = np.zeros((3, 3, m)), np.zeros((3, 3, m))
    T[0], D[0] = one_sided(element, X)
    T_xi[0] = shape_functions(X, h, npe)[2]
    D_xi[0] = displacement(chain, element, X, 2)
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
        for coefficients, rate, index in ((T, T_xi, 0), (D, D_xi, 1)):
            own = -0.5 * one_sided(element, end)[index]
            theirs = 0.5 * one_sided(other, other_end)[index]
            coefficients[0] += weight * own
            coefficients[slot] += weight * theirs
            rate[0] += weight_xi * own
            rate[slot] += weight_xi * theirs
    matrices = (np.concatenate(list(D), axis=1), np.concatenate(list(D_xi), axis=1))
    return elements, T.ravel(), T_xi.ravel(), *matrices


def element_dofs(chain: Chain, element: int) -> np.ndarray:
    """The dofs the displacement of the chain's ``element`` reads (:func:`displacement`): its
    nodes' first :func:`width` dofs, node after node."""
    return element_nodes(chain, element)[0][:, : width(chain)].ravel()


def interpolation(chain: Chain, xi: float) -> Interpolation:
    """Where ``xi`` sits and how the line interpolates there (:class:`Interpolation`): the
    element's dofs (:func:`element_dofs`), the reference line ``x0 = sum N_a X_a`` and its
    derivatives (:func:`shape_functions`), the displacement's matrices
    (:func:`displacement`), and the :func:`recovered_tangent` with the dofs of the nodes it
    reads and its reference values."""
    _, element, X = locate(chain, xi)
    npe = chain.beams[0].mesh.nodes_per_element
    N, dN, d2N = shape_functions(X, element_length(chain, element), npe)
    _, points = element_nodes(chain, element)
    elements, T, T_xi, D, D_xi = recovered_tangent(chain, element, X)
    positions = np.concatenate([element_nodes(chain, e)[1] for e in elements])
    matrix, rate, curvature = (displacement(chain, element, X, k) for k in range(3))
    return Interpolation(
        element_dofs(chain, element),
        np.stack([N @ points, dN @ points, d2N @ points]),
        matrix,
        rate,
        curvature,
        np.concatenate([element_dofs(chain, e) for e in elements]),
        np.stack([T @ positions, T_xi @ positions]),
        D,
        D_xi,
    )


def deformed(reference: np.ndarray, f: np.ndarray, dofs: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``reference + f q[dofs]``: the line (or a derivative, or the recovered tangent) from its
    reference value and the displacement's matrix ``f`` (3, m) on the dofs ``dofs`` (m,)
    (paper Sec. 4)."""
    return reference + f @ q[dofs]


def contact(chain: Chain, xi: float) -> tuple[np.ndarray, np.ndarray]:
    """The position's compliance at ``xi`` under a force and couple there, on a chain with
    cubic elements: the rows ``[G_uu, G_u theta]`` (3, 6) of the cubic element's
    clamped-clamped compliance (eq. T13, :func:`fvbeam.pointwise.cubic_flex_reference`) and
    their ``xi``-derivative; zero on a Lagrange element of such a chain; none (0, 6) on a
    chain without cubic elements."""
    if width(chain) == 3:
        return np.zeros((0, 6)), np.zeros((0, 6))
    k, element, X = locate(chain, xi)
    beam = chain.beams[k]
    if beam.formulation.kind != CUBIC:
        return np.zeros((3, 6)), np.zeros((3, 6))
    flex, flex_xi = cubic_flex_reference(
        element_frame(chain, element),
        np.diag(beam.section.stiffness),
        element_length(chain, element),
        X,
    )
    return flex[:3], flex_xi[:3]


def transfer(chain: Chain, xi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How a force and couple ``[F; M]`` at ``xi`` loads the element holding it (eq. T6 with
    no smearing: the test functions at ``xi``).

    fv (eq. T4): node ``a`` takes ``chi_a(X) [[I, 0], [skew(x - x_a), I]]``, the force and
    its moment about the node, ``x`` the reference line at ``xi``; Galerkin: ``N_a I6``;
    cubic: its functions (eq. T11).  Returns the element's dofs (6 npe,), ``G`` (6 npe, 6)
    and ``dG/dxi`` (``chi_a`` is piecewise constant: ``chi_a [[0, 0], [skew(x_/xi), 0]]``;
    Galerkin ``dN_a/dxi I6``): :func:`fvbeam.pointwise.transfer_reference` on the element.
    """
    k, element, X = locate(chain, xi)
    beam = chain.beams[k]
    npe = beam.mesh.nodes_per_element
    dofs, points = element_nodes(chain, element)
    G, dG = transfer_reference(
        beam.formulation.kind,
        influence_regions(npe),
        points,
        element_frame(chain, element),
        np.diag(beam.section.stiffness),
        element_length(chain, element),
        X,
    )
    return dofs.ravel(), G, dG


def rotation(chain: Chain, xi: float) -> LineRotation:
    """The section rotation at ``xi``, its compliance and the reference frame
    (:class:`LineRotation`).

    Lagrange elements: ``theta = w_0 theta_0 + w_1 theta_1`` between the two consecutive
    nodes along the element (end 0, mid node, end 1) around ``X``, ``w = (1 - t, t)`` with
    ``t`` the position between them, read on the nodes' last :func:`width` dofs; the
    compliance is the kink correction ``kappa C`` with ``kappa = w_0 w_1 span + lag h
    w_mid^2`` (``span`` their distance, ``w_mid`` the mid node's weight, ``lag``
    :data:`MID_NODE_LAG` of the formulation; ``docs/sliders.md``, "The kink correction")
    and ``C = R0 C_s R0^T`` the section's bending-and-torsion compliance (the rotational
    block of the inverse section stiffness) in the reference frame.  Cubic elements: the
    rotation rows of its functions on its nodes' six dofs (eq. T11) and the rotational block
    of its compliance (eq. T13).  The reference frame ``R0`` of the reference line
    ``l0 = sum dN_a X_a`` and the beam's ``up``, its curvature ``k0 = ax(R0_/xi R0^T)`` and
    ``k0_/xi`` (:func:`sliders.lines.rigid.frame_and_curvature`,
    :func:`~sliders.lines.rigid.curvature_rate`).
    """
    k, element, X = locate(chain, xi)
    beam, w = chain.beams[k], width(chain)
    npe, h = beam.mesh.nodes_per_element, element_length(chain, element)
    dofs, points = element_nodes(chain, element)
    _, dN, d2N = shape_functions(X, h, npe)
    l0, l0_xi = dN @ points, d2N @ points
    R0, k0 = frame_and_curvature(l0, l0_xi, beam.mesh.up)
    k0_xi = curvature_rate(l0, l0_xi, np.zeros(3), beam.mesh.up)
    if beam.formulation.kind == CUBIC:
        stiffness, frame = np.diag(beam.section.stiffness), element_frame(chain, element)
        W, W_xi, W_xixi = (cubic_reference(frame, stiffness, h, X, k)[:, 3:].T for k in range(3))
        flex, flex_xi = (f[3:, 3:] for f in cubic_flex_reference(frame, stiffness, h, X))
        return LineRotation(dofs.ravel(), W, W_xi, W_xixi, flex, flex_xi, R0, k0, k0_xi)
    along = [0, 1] if npe == 2 else [0, 2, 1]  # local nodes in order along the element
    at = LOCAL_NODES[along]
    i = int(np.clip(np.searchsorted(at, X, side="right") - 1, 0, len(at) - 2))
    pair, span = [along[i], along[i + 1]], (at[i + 1] - at[i]) * h
    t = (X - at[i]) / (at[i + 1] - at[i])
    weights, weights_xi = np.array([1 - t, t]), np.array([-1 / span, 1 / span])
    is_mid = np.array([a == 2 for a in pair], dtype=float)
    w_mid, w_mid_xi = weights @ is_mid, weights_xi @ is_mid
    lag = MID_NODE_LAG["fv" if isinstance(beam.formulation, FiniteVolume) else "galerkin"]
    kink = weights[0] * weights[1] * span + lag * h * w_mid**2
    kink_xi = (weights_xi[0] * weights[1] + weights[0] * weights_xi[1]) * span
    kink_xi += 2 * lag * h * w_mid * w_mid_xi
    # theta = sum_s w_s theta_s, on the last `w` dofs of each of the two nodes
    read = np.zeros((2, w, 3))
    read[:, w - 3 :, :] = np.eye(3)
    W, W_xi = (np.einsum("s,skc->csk", v, read).reshape(3, -1) for v in (weights, weights_xi))
    C = R0 @ np.linalg.inv(beam.section.stiffness)[3:, 3:] @ R0.T
    return LineRotation(
        dofs[pair, 6 - w :].ravel(), W, W_xi, np.zeros_like(W), kink * C, kink_xi * C, R0, k0, k0_xi
    )


def line_state(
    chain: Chain,
    xi: float,
    q: np.ndarray,
    smearing: float = 0.0,
    kernel: str = "box",
) -> LineState:
    """All a joint needs of the chain at ``xi`` on the state ``q`` (:class:`LineState` of one
    member, as :meth:`sliders.lines.batched.ChainStack.line_state` with ``rotation``): the
    :func:`interpolation`, the deformed line ``x``, ``l``, ``l_/xi``, ``l_/xixi`` (the
    reference line's is zero: degree at most 2) and the recovered tangent ``l~``, ``l~_/xi``
    (:func:`deformed`), the position's compliance (:func:`contact`), the
    load transfer (:func:`transfer`; with ``smearing > 0`` the smeared one,
    :meth:`sliders.lines.chain.BeamChain.transfer`, which the stack reads too: a quadrature
    outside the kernel) and the :func:`rotation`."""
    line = interpolation(chain, xi)
    x, l, l_xi = (
        deformed(r, f, line.dofs, q)
        for r, f in zip(line.reference, (line.N, line.dN, line.d2N), strict=True)
    )
    _, element, X = locate(chain, xi)
    l_xixi = deformed(np.zeros(3), displacement(chain, element, X, 3), line.dofs, q)
    tangent, tangent_xi = (
        deformed(r, f, line.tangent_dofs, q)
        for r, f in zip(line.tangent_reference, (line.T, line.T_xi), strict=True)
    )
    load = transfer(chain, xi) if smearing == 0 else chain.transfer(xi, smearing, kernel)
    return LineState(
        line,
        x,
        l,
        l_xi,
        l_xixi,
        tangent,
        tangent_xi,
        *contact(chain, xi),
        *load,
        rotation(chain, xi),
    )
