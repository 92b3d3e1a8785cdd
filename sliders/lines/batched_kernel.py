"""The line state of ``B`` chains at their abscissae, compiled (numba).

One call of :func:`line_state` answers every query of :class:`sliders.lines.batched.ChainStack` for
``B`` members at once, member by member without temporaries: where ``xi`` lies
(:func:`locate_one`), the element interpolation and the recovered tangent
(``docs/sliders.md``, :func:`interpolation_one`), the deformed line (:func:`weighted`,
:func:`displaced`), the load transfer (eq. T6, :func:`fvbeam.pointwise.transfer_at`), the
section rotation with its compliance at the contact (:func:`rotation_one`) and, on a chain of
cubic elements, the compliance of the line's position under a load at the contact (eq. T13,
:func:`fvbeam.pointwise.cubic_flex_at`).

The deformed line is ``x(xi) = x0(xi) + N(xi) q[dofs]``: the reference line ``x0`` (the
Lagrange interpolation of the node positions) plus the displacement the element interpolates
from its nodes' dofs, ``N`` a (3, m) matrix on ``m = width npe`` dofs, ``width`` of each
node: its 3 translations for the Lagrange elements (``N = [N_a I]``), its 6 dofs on a chain
with cubic elements (eq. T11: the deflection reads the nodal rotations too).

A smeared load transfer is one call of :func:`smeared_transfer`: the kernel form of
:meth:`sliders.lines.chain.BeamChain.transfer` integrated by the same rule on the same pieces,
compiled.  The stack's arrays are described in
:class:`sliders.lines.batched.ChainStack`; the kernels expect them C-contiguous, float64 and int64.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.pointwise import (
    CUBIC,
    Element,
    Shapes,
    Smearing,
    cubic_flex_at,
    cubic_local_at,
    shape_at,
    smeared_element,
    to_global,
    transfer_at,
)
from fvbeam.scratch import stack_empty, stack_zeros

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: The most nodes of an element the kernels' scratch arrays hold (three-node elements).
MAX_NPE = 3


class Chains(NamedTuple):
    """A stack of ``B`` chains as the kernels read them (:class:`sliders.lines.batched.ChainStack`).

    ``M`` distinct dof maps, ``E`` elements of ``npe`` nodes over ``n_beams`` beams.
    """

    #: Each member's dof map (B,), into ``maps`` (M, E, npe, 6); the element ``cells`` (E, npe).
    member_map: np.ndarray
    maps: np.ndarray
    cells: np.ndarray
    #: Node positions (B, n_nodes, 3), beam ``breaks`` (B, n_beams + 1), vertex abscissae
    #: ``vertex_s`` (B, E + n_beams), each beam's ``first_element`` (n_beams + 1,), element
    #: lengths ``h`` (B, E).
    points: np.ndarray
    breaks: np.ndarray
    vertex_s: np.ndarray
    first_element: np.ndarray
    h: np.ndarray
    #: Each element's rotation lag (E,), each beam's kind of element (n_beams,)
    #: (:data:`fvbeam.pointwise.LAGRANGE`, ...), the fv influence ``regions`` (npe, 2),
    #: ``ends`` (2, npe) ``dN/dX`` at the element ends, ``stiffness`` (E, 6) the diagonal of
    #: each element's section stiffness.
    lag: np.ndarray
    kinds: np.ndarray
    regions: np.ndarray
    ends: np.ndarray
    stiffness: np.ndarray
    #: The dofs of a node the displacement reads (3, or 6 on a chain with cubic elements;
    #: module docstring).
    width: int
    #: The element frames (B, E, 3, 3) and compliances ``R0 C R0^T`` (B, E, 3, 3).
    R0_of: np.ndarray
    compliance_of: np.ndarray


class LineArrays(NamedTuple):
    """What :func:`line_state` gives of each member (leading axis B; ``m = width npe``).

    The arrays of what is not asked have a zero size.
    """

    #: Where ``xi`` lies: beam (position in the chain), element and reference coordinate.
    beam: np.ndarray
    element: np.ndarray
    X: np.ndarray
    #: The interpolated dofs (B, m), the reference line ``x0, l0, l0_xi`` (B, 3, 3), the
    #: interpolation matrix and its ``xi``-derivatives (B, 3, m).
    dofs: np.ndarray
    reference: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    #: The recovered tangent: its dofs (B, 3 m), reference ``l~0, l~0_xi`` (B, 2, 3) and
    #: matrices ``T``, ``T_xi`` (B, 3, 3 m).
    tangent_dofs: np.ndarray
    tangent_reference: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray
    #: The deformed line ``x, l, l_xi, l_xixi, l~, l~_xi`` (B, 6, 3); the position's
    #: compliance rows ``[G_uu, G_u theta]`` (B, c, 6) and their derivative (eq. T13).
    geometry: np.ndarray
    contact: np.ndarray
    contact_xi: np.ndarray
    #: The load transfer: dofs (B, 6 npe), ``G`` and ``dG`` (B, 6 npe, 6) (eq. T6).
    load_dofs: np.ndarray
    G: np.ndarray
    dG: np.ndarray
    #: The section rotation: its dofs (B, r), ``W`` and its ``xi``-derivatives (B, 3, r), the
    #: kink and its derivative (B,), the compliance at a couple and its derivative
    #: (B, 3, 3), the stored frame (B, 3, 3).
    rotation_dofs: np.ndarray
    W: np.ndarray
    W_xi: np.ndarray
    W_xixi: np.ndarray
    kink: np.ndarray
    kink_xi: np.ndarray
    flex: np.ndarray
    flex_xi: np.ndarray
    R0: np.ndarray


@numba.njit(cache=True, inline="never")
def interval(breaks: np.ndarray, start: int, n: int, value: float) -> int:
    """The interval of ``breaks[start:start + n + 1]`` (increasing) holding ``value``:
    ``searchsorted(side="right") - 1`` clipped to ``0 .. n - 1``."""
    count = 0
    for i in range(n + 1):
        if breaks[start + i] <= value:
            count += 1
    return min(max(count - 1, 0), n - 1)


@numba.njit(cache=True, inline="never")
def locate_one(
    xi: float, breaks: np.ndarray, vertex_s: np.ndarray, first_element: np.ndarray, h: np.ndarray
) -> tuple[int, int, float]:
    """Beam ``k`` of the chain, element (chain index) and reference coordinate ``X`` of the
    abscissa ``xi`` (on the chain, checked by the caller) of one member: its beam breaks
    ``breaks`` (n_beams + 1,), vertex abscissae ``vertex_s`` (each beam's from 0, one after
    the other) and element lengths ``h``."""
    k = interval(breaks, 0, len(breaks) - 1, xi)
    local = min(max(xi - breaks[k], 0.0), breaks[k + 1] - breaks[k])
    start = first_element[k] + k
    e = interval(vertex_s, start, first_element[k + 1] - first_element[k], local)
    offset = min(
        max(local - vertex_s[start + e], 0.0), vertex_s[start + e + 1] - vertex_s[start + e]
    )
    element = first_element[k] + e
    return k, element, min(max(offset / h[element], 0.0), 1.0)


@numba.njit(cache=True, inline="never")
def element_shape(X: float, he: float, N: np.ndarray, dN: np.ndarray, d2N: np.ndarray) -> None:
    """The shape functions ``N`` (npe,) at ``X`` of an element of length ``he``, and their
    derivatives ``dN``, ``d2N`` in the abscissa ``xi`` (``X`` affine in it)."""
    shape_at(X, len(N), N, dN, d2N)
    for a in range(len(N)):
        dN[a] = dN[a] / he
        d2N[a] = d2N[a] / (he * he)


@numba.njit(cache=True, inline="never")
def element_line(
    kind: int,
    frame: np.ndarray,
    stiffness: np.ndarray,
    he: float,
    X: float,
    order: int,
    out: np.ndarray,
    shape: np.ndarray,
    block: np.ndarray,
) -> None:
    """The ``order``-th ``xi``-derivative of the displacement an element of ``kind`` and
    length ``he`` interpolates at ``X``, as its matrix ``out`` (3, width npe) on its nodes'
    first ``width`` dofs (module docstring): Lagrange ``N_a I`` on the translations
    (:func:`element_shape`); cubic the translation rows of the element's functions
    (:func:`fvbeam.pointwise.cubic_local_at` in global axes, section ``frame`` and
    ``stiffness``).  ``shape`` (3, npe) and ``block`` (12, 6) are scratch."""
    out[:] = 0.0
    width = out.shape[1] // shape.shape[1]
    if kind == CUBIC:
        cubic_local_at(stiffness, he, X, order, block)
        to_global(frame, block)
        for j in range(12):
            for c in range(3):
                out[c, j] = block[j, c]
        return
    if order > 2:  # Lagrange elements of degree at most 2
        return
    element_shape(X, he, shape[0], shape[1], shape[2])
    for a in range(shape.shape[1]):
        for c in range(3):
            out[c, width * a + c] = shape[order, a]


@numba.njit(cache=True, inline="never")
def interpolation_one(
    element: int,
    X: float,
    h: np.ndarray,
    N: np.ndarray,
    dN: np.ndarray,
    d2N: np.ndarray,
    ends: np.ndarray,
    T: np.ndarray,
    T_xi: np.ndarray,
    neighbours: np.ndarray,
) -> None:
    """The shape functions ``N``, ``dN``, ``d2N`` (npe,) in ``xi`` of ``element`` at ``X``,
    and the recovered tangent's coefficients ``T``, ``T_xi`` (3 npe,) (``docs/sliders.md``):
    ``l~ = l + (1 - X) (l_a - l(a)) + X (l_b - l(b))`` with ``l_a``, ``l_b`` the tangents of
    the elements before and after at the shared vertices, averaged (weights 1/2), zero where
    there is none; ``neighbours`` (2,) receives those elements (``element`` itself where
    there is none).  ``ends`` (2, npe): ``dN/dX`` at ``X = 0`` and ``1``; ``h``: the
    member's element lengths (E,).  The reference line's coefficients on the node positions
    (the displacement's are :func:`displacement_one`'s)."""
    npe = len(N)
    he = h[element]
    element_shape(X, he, N, dN, d2N)
    for a in range(npe):
        T[a], T_xi[a] = dN[a], d2N[a]
    for side in range(2):
        other = element - 1 if side == 0 else element + 1
        there = 0 <= other < len(h)
        weight = 0.5 * (1 - X) if side == 0 else 0.5 * X
        weight_xi = 0.5 * (-1 / he) if side == 0 else 0.5 * (1 / he)
        if not there:
            other, weight, weight_xi = element, 0.0, 0.0
        neighbours[side] = other
        own, theirs = ends[side], ends[1 - side]
        ho = h[other]
        for a in range(npe):
            T[a] = T[a] - weight * (own[a] / he)
            T_xi[a] = T_xi[a] - weight_xi * (own[a] / he)
            T[(side + 1) * npe + a] = weight * (theirs[a] / ho)
            T_xi[(side + 1) * npe + a] = weight_xi * (theirs[a] / ho)


@numba.njit(cache=True, inline="never")
def displacement_one(
    elements: np.ndarray,
    X: float,
    chains: Chains,
    b: int,
    out: LineArrays,
    scratch: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> None:
    """Member ``b``'s displacement interpolation at ``X`` of ``elements[0]`` (its neighbours
    before and after in ``elements[1:]``, itself where there is none) as matrices on the
    nodes' dofs (:func:`element_line`), into ``out``'s row ``b``: ``N``, ``dN``, ``d2N``
    (3, m) and the recovered tangent's ``T``, ``T_xi`` (3, 3 m) on the three elements' dofs
    in turn, the same combination of one-sided tangents as :func:`interpolation_one`'s.
    ``scratch``: ``end`` (3, m), ``shape`` and ``block``."""
    frames, h = chains.R0_of[b], chains.h[b]
    N, dN, d2N, T, T_xi = out.N[b], out.dN[b], out.d2N[b], out.T[b], out.T_xi[b]
    end, shape, block = scratch
    element = elements[0]
    m = N.shape[1]
    he = h[element]
    kind, frame = chains.kinds[beam_of(chains.first_element, element)], frames[element]
    for order, out in ((0, N), (1, dN), (2, d2N)):
        element_line(kind, frame, chains.stiffness[element], he, X, order, out, shape, block)
    T[:] = 0.0
    T_xi[:] = 0.0
    for c in range(3):
        for j in range(m):
            T[c, j], T_xi[c, j] = dN[c, j], d2N[c, j]
    for side in range(2):
        other = elements[1 + side]
        if other == element:
            continue
        weight = 0.5 * (1 - X) if side == 0 else 0.5 * X
        weight_xi = 0.5 * (-1 / he) if side == 0 else 0.5 * (1 / he)
        at = 0.0 if side == 0 else 1.0
        element_line(kind, frame, chains.stiffness[element], he, at, 1, end, shape, block)
        for c in range(3):
            for j in range(m):
                T[c, j] -= weight * end[c, j]
                T_xi[c, j] -= weight_xi * end[c, j]
        k = chains.kinds[beam_of(chains.first_element, other)]
        element_line(
            k, frames[other], chains.stiffness[other], h[other], 1.0 - at, 1, end, shape, block
        )
        for c in range(3):
            for j in range(m):
                T[c, (side + 1) * m + j] = weight * end[c, j]
                T_xi[c, (side + 1) * m + j] = weight_xi * end[c, j]


@numba.njit(cache=True, inline="never")
def lagrange_matrices(
    shape: np.ndarray,
    T_scalar: np.ndarray,
    T_scalar_xi: np.ndarray,
    N: np.ndarray,
    dN: np.ndarray,
    d2N: np.ndarray,
    T: np.ndarray,
    T_xi: np.ndarray,
) -> None:
    """On a chain of Lagrange elements (``width`` 3), the displacement's matrices from the
    shape functions ``shape`` (3, npe) and the recovered tangent's coefficients ``T_scalar``,
    ``T_scalar_xi`` (3 npe,) of :func:`interpolation_one`: ``N_a I`` on each node's
    translations (:func:`displacement_one`'s matrices for these elements, without
    evaluating them again), written into zero matrices on their nonzero entries."""
    for a in range(shape.shape[1]):
        for c in range(3):
            N[c, 3 * a + c] = shape[0, a]
            dN[c, 3 * a + c] = shape[1, a]
            d2N[c, 3 * a + c] = shape[2, a]
    for a in range(len(T_scalar)):
        for c in range(3):
            T[c, 3 * a + c] = T_scalar[a]
            T_xi[c, 3 * a + c] = T_scalar_xi[a]


@numba.njit(cache=True, inline="never")
def current(nodes: np.ndarray, q: np.ndarray, dofs: np.ndarray, out: np.ndarray) -> None:
    """Deformed node positions ``nodes + q[dofs]`` (m, 3) into ``out``."""
    for a in range(nodes.shape[0]):
        for c in range(3):
            out[a, c] = nodes[a, c] + q[dofs[a, c]]


@numba.njit(cache=True, inline="never")
def weighted(f: np.ndarray, points: np.ndarray, out: np.ndarray) -> None:
    """``sum_a f_a points_a`` (3,) into ``out``: the reference line interpolated from its
    nodes ``x0 = sum N_a x_a`` (paper Sec. 4) and its derivatives, or the recovered
    tangent."""
    out[:] = 0.0
    for a in range(len(f)):
        for c in range(3):
            out[c] += f[a] * points[a, c]


@numba.njit(cache=True, inline="never")
def displaced(
    reference: np.ndarray, f: np.ndarray, q: np.ndarray, dofs: np.ndarray, out: np.ndarray
) -> None:
    """``reference + f q[dofs]`` (3,) into ``out``: the deformed line, its derivatives or the
    recovered tangent, from the reference one and the displacement's matrix ``f`` (3, m) on
    the dofs ``dofs`` (m,) (module docstring)."""
    for c in range(3):
        value = reference[c]
        for j in range(f.shape[1]):
            value += f[c, j] * q[dofs[j]]
        out[c] = value


@numba.njit(cache=True, inline="never")
def rotation_one(
    X: float, he: float, lag: float, npe: int, pair: np.ndarray, w: np.ndarray, w_xi: np.ndarray
) -> tuple[float, float]:
    """The section rotation's interpolation at ``X`` of a Lagrange element of length ``he``
    (:meth:`sliders.lines.batched.ChainStack.rotation`): the two consecutive nodes around
    ``X`` (``pair``, local indices, along the element: end 0, mid node, end 1), their
    weights ``w`` and ``w_xi``; returns ``kink = t (1 - t) span + lag h w_mid^2`` and its
    derivative in ``xi``."""
    if npe == 2:
        pair[0], pair[1], a0, a1 = 0, 1, 0.0, 1.0
    elif X < 0.5:
        pair[0], pair[1], a0, a1 = 0, 2, 0.0, 0.5
    else:
        pair[0], pair[1], a0, a1 = 2, 1, 0.5, 1.0
    span = (a1 - a0) * he
    t = (X - a0) * he / span
    w[0], w[1] = 1 - t, t
    w_xi[0], w_xi[1] = -1 / span, 1 / span
    shift = lag * he
    mid0, mid1 = (1.0 if pair[0] == 2 else 0.0), (1.0 if pair[1] == 2 else 0.0)
    w_mid = w[0] * mid0 + w[1] * mid1
    kink = t * (1 - t) * span + shift * (w_mid * w_mid)
    kink_xi = 1 - 2 * t + 2 * shift * w_mid * (mid1 - mid0) / span
    return kink, kink_xi


@numba.njit(cache=True)
def locate(
    xi: np.ndarray,
    breaks: np.ndarray,
    vertex_s: np.ndarray,
    first_element: np.ndarray,
    h: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`locate_one` for each member (rows of ``breaks``, ``vertex_s``, ``h``)."""
    B = len(xi)
    beam, element, X = np.empty(B, np.int64), np.empty(B, np.int64), np.empty(B)
    for b in range(B):
        beam[b], element[b], X[b] = locate_one(xi[b], breaks[b], vertex_s[b], first_element, h[b])
    return beam, element, X


@numba.njit(cache=True)
def line_state(
    xi: np.ndarray,
    q: np.ndarray,
    chains: Chains,
    state: bool,
    transfer: bool,
    rotation: bool,
) -> LineArrays:
    """The line state of each member at ``xi`` (B,) on its states ``q`` (B, n), on the
    stack's arrays ``chains``.

    ``state``: the deformed line ``x``, ``l``, ``l_/xi`` and the recovered tangent with its
    derivative (with ``width`` 6, the position's compliance at the contact too);
    ``transfer``: the load dofs, ``G`` and ``dG`` (eq. T6); ``rotation``: the rotation's
    dofs ``(6 - width) .. 5`` of the two nodes around ``xi`` and the matrices ``W``,
    ``W_xi`` (3, 2 width) that read it of them, its compliance ``flex`` at a couple there and
    ``flex_xi`` (a Lagrange element's: the weights of :func:`rotation_one` and ``kink C``;
    a cubic element's: its own rotation, eq. T11, and the rotational block of eq. T13), the
    kink and the stored frame.  The arrays of what is not asked have a zero size.

    Returns the arrays (:class:`LineArrays`).
    """
    B, npe, width = len(xi), chains.cells.shape[1], chains.width
    m = width * npe
    nb, nt, nr = (B if state else 0), (B if transfer else 0), (B if rotation else 0)
    nc = 3 if width == 6 else 0  # contact rows
    r = 2 * width
    out = LineArrays(
        np.empty(B, np.int64),
        np.empty(B, np.int64),
        np.empty(B),
        np.empty((B, m), np.int64),
        np.empty((B, 3, 3)),
        np.empty((B, 3, m)),
        np.empty((B, 3, m)),
        np.empty((B, 3, m)),
        np.empty((B, 3 * m), np.int64),
        np.empty((B, 2, 3)),
        np.empty((B, 3, 3 * m)),
        np.empty((B, 3, 3 * m)),
        np.empty((nb, 6, 3)),
        np.empty((nb, nc, 6)),
        np.empty((nb, nc, 6)),
        np.empty((nt, 6 * npe), np.int64),
        np.empty((nt, 6 * npe, 6)),
        np.empty((nt, 6 * npe, 6)),
        np.empty((nr, r), np.int64),
        np.empty((nr, 3, r)),
        np.empty((nr, 3, r)),
        np.empty((nr, 3, r)),
        np.empty(nr),
        np.empty(nr),
        np.empty((nr, 3, 3)),
        np.empty((nr, 3, 3)),
        np.empty((nr, 3, 3)),
    )
    line_state_into(
        xi,
        q,
        chains,
        state,
        transfer,
        rotation,
        out,
    )
    return out


@numba.njit(cache=True, inline="always")
def one_point_state(npe: int, width: int, state: bool, transfer: bool, rotation: bool) -> tuple:
    """The arrays :func:`line_state_into` fills for one member (``B = 1``), uninitialised, on
    the stack of the kernel this is inlined into (:mod:`fvbeam.scratch`; elements of at most
    :data:`MAX_NPE` nodes of six dofs)."""
    m = width * npe
    nb, nt, nr = (1 if state else 0), (1 if transfer else 0), (1 if rotation else 0)
    nc = 3 if width == 6 else 0
    r = 2 * width
    f8, i8 = np.float64, np.int64
    return LineArrays(
        stack_empty(1, (1,), i8),
        stack_empty(1, (1,), i8),
        stack_empty(1, (1,), f8),
        stack_empty(18, (1, m), i8),
        stack_empty(9, (1, 3, 3), f8),
        stack_empty(54, (1, 3, m), f8),
        stack_empty(54, (1, 3, m), f8),
        stack_empty(54, (1, 3, m), f8),
        stack_empty(54, (1, 3 * m), i8),
        stack_empty(6, (1, 2, 3), f8),
        stack_empty(162, (1, 3, 3 * m), f8),
        stack_empty(162, (1, 3, 3 * m), f8),
        stack_empty(18, (nb, 6, 3), f8),
        stack_empty(18, (nb, nc, 6), f8),
        stack_empty(18, (nb, nc, 6), f8),
        stack_empty(18, (nt, 6 * npe), i8),
        stack_empty(108, (nt, 6 * npe, 6), f8),
        stack_empty(108, (nt, 6 * npe, 6), f8),
        stack_empty(12, (nr, r), i8),
        stack_empty(36, (nr, 3, r), f8),
        stack_empty(36, (nr, 3, r), f8),
        stack_empty(36, (nr, 3, r), f8),
        stack_empty(1, (nr,), f8),
        stack_empty(1, (nr,), f8),
        stack_empty(9, (nr, 3, 3), f8),
        stack_empty(9, (nr, 3, 3), f8),
        stack_empty(9, (nr, 3, 3), f8),
    )


@numba.njit(cache=True)
def line_state_into(
    xi: np.ndarray,
    q: np.ndarray,
    chains: Chains,
    state: bool,
    transfer: bool,
    rotation: bool,
    out: LineArrays,
) -> None:
    """:func:`line_state` into the arrays ``out``, overwritten (those :func:`line_state`
    returns, or :func:`one_point_state`'s for one member)."""
    width = chains.width
    B, npe = len(xi), chains.cells.shape[1]
    m = width * npe
    nc = 3 if width == 6 else 0  # contact rows
    (
        beam,
        element,
        X,
        dofs,
        reference,
        N,
        dN,
        d2N,
        tangent_dofs,
        tangent_reference,
        T,
        T_xi,
        geometry,
        contact,
        contact_xi,
        load_dofs,
        G,
        dG,
        rotation_dofs,
        W,
        W_xi,
        W_xixi,
        kink,
        kink_xi,
        flex,
        flex_xi,
        R0,
    ) = out
    # zero: the Lagrange elements' matrices are written on their nonzero entries only
    for arr in (N, dN, d2N, T, T_xi, contact, contact_xi, W, W_xi, W_xixi):
        arr[:] = 0.0
    kink[:] = 0.0
    kink_xi[:] = 0.0
    # scratch, on the stack (fvbeam.scratch): bounds for three-node elements of six-dof nodes
    if npe > MAX_NPE:
        raise ValueError("line_state reads elements of at most three nodes")
    f8, i8 = np.float64, np.int64
    three, pair = stack_empty(3, (3,), i8), stack_empty(2, (2,), i8)
    n, dn, d2n = stack_empty(3, (npe,), f8), stack_empty(3, (npe,), f8), stack_empty(3, (npe,), f8)
    chi, dchi = stack_empty(3, (npe,), f8), stack_empty(3, (npe,), f8)
    Ns = stack_empty(9, (3, npe), f8)
    Ts, Ts_xi = stack_empty(9, (3 * npe,), f8), stack_empty(9, (3 * npe,), f8)
    nodes, moved = stack_empty(27, (3 * npe, 3), f8), stack_empty(27, (3 * npe, 3), f8)
    translations = stack_empty(27, (3 * npe, 3), i8)
    end, shape = stack_empty(54, (3, m), f8), stack_empty(9, (3, npe), f8)
    block, G_b = stack_empty(72, (12, 6), f8), stack_empty(72, (12, 6), f8)
    compliance6, compliance6_xi = stack_empty(36, (6, 6), f8), stack_empty(36, (6, 6), f8)
    w, w_xi, zero = stack_empty(2, (2,), f8), stack_empty(2, (2,), f8), stack_zeros(3, (3,), f8)
    for b in range(B):
        k, e, Xb = locate_one(
            xi[b], chains.breaks[b], chains.vertex_s[b], chains.first_element, chains.h[b]
        )
        beam[b], element[b], X[b] = k, e, Xb
        kind, frame = chains.kinds[k], chains.R0_of[b, e]
        interpolation_one(
            e, Xb, chains.h[b], Ns[0], Ns[1], Ns[2], chains.ends, Ts, Ts_xi, three[1:]
        )
        three[0] = e
        dof_map = chains.maps[chains.member_map[b]]
        for slot in range(3):
            el = three[slot]
            for a in range(npe):
                node = chains.cells[el, a]
                for c in range(3):
                    nodes[slot * npe + a, c] = chains.points[b, node, c]
                for c in range(width):
                    tangent_dofs[b, slot * m + width * a + c] = dof_map[el, a, c]
        for j in range(m):
            dofs[b, j] = tangent_dofs[b, j]
        weighted(Ns[0], nodes[:npe], reference[b, 0])
        weighted(Ns[1], nodes[:npe], reference[b, 1])
        weighted(Ns[2], nodes[:npe], reference[b, 2])
        weighted(Ts, nodes, tangent_reference[b, 0])
        weighted(Ts_xi, nodes, tangent_reference[b, 1])
        if width == 3:  # Lagrange elements only: N_a I on the translations
            lagrange_matrices(Ns, Ts, Ts_xi, N[b], dN[b], d2N[b], T[b], T_xi[b])
        else:
            displacement_one(three, Xb, chains, b, out, (end, shape, block))
        if state and width == 3:  # x = sum N_a (X_a + u_a): the scalar coefficients
            for j in range(3 * npe):
                for c in range(3):
                    translations[j, c] = tangent_dofs[b, 3 * j + c]
            current(nodes, q[b], translations, moved)
            weighted(Ns[0], moved[:npe], geometry[b, 0])
            weighted(Ns[1], moved[:npe], geometry[b, 1])
            weighted(Ns[2], moved[:npe], geometry[b, 2])
            geometry[b, 3] = 0.0  # degree at most 2
            weighted(Ts, moved, geometry[b, 4])
            weighted(Ts_xi, moved, geometry[b, 5])
        elif state:
            displaced(reference[b, 0], N[b], q[b], dofs[b], geometry[b, 0])
            displaced(reference[b, 1], dN[b], q[b], dofs[b], geometry[b, 1])
            displaced(reference[b, 2], d2N[b], q[b], dofs[b], geometry[b, 2])
            # l_/xixi: zero on Lagrange elements (degree at most 2), the reference line's too
            element_line(kind, frame, chains.stiffness[e], chains.h[b, e], Xb, 3, end, shape, block)
            displaced(zero, end, q[b], dofs[b], geometry[b, 3])
            displaced(tangent_reference[b, 0], T[b], q[b], tangent_dofs[b], geometry[b, 4])
            displaced(tangent_reference[b, 1], T_xi[b], q[b], tangent_dofs[b], geometry[b, 5])
            if nc and kind == CUBIC:
                cubic_flex_at(
                    frame, chains.stiffness[e], chains.h[b, e], Xb, compliance6, compliance6_xi
                )
                for i in range(3):
                    for c in range(6):
                        contact[b, i, c] = compliance6[i, c]
                        contact_xi[b, i, c] = compliance6_xi[i, c]
        if transfer:
            for a in range(npe):
                for c in range(6):
                    load_dofs[b, 6 * a + c] = dof_map[e, a, c]
            element_e = Element(
                kind, chains.regions, nodes[:npe], frame, chains.stiffness[e], chains.h[b, e]
            )
            transfer_at(element_e, Xb, Shapes(n, dn, d2n, chi, dchi), G[b], dG[b])
        if rotation:
            R0[b] = frame
            if kind == CUBIC:  # the element's own rotation and its compliance (eq. T13)
                pair[0], pair[1] = 0, 1
                for order, rows in ((0, W[b]), (1, W_xi[b]), (2, W_xixi[b])):
                    cubic_local_at(chains.stiffness[e], chains.h[b, e], Xb, order, G_b)
                    to_global(frame, G_b)
                    for j in range(12):
                        for c in range(3):
                            rows[c, j] = G_b[j, 3 + c]
                cubic_flex_at(
                    frame, chains.stiffness[e], chains.h[b, e], Xb, compliance6, compliance6_xi
                )
                for i in range(3):
                    for c in range(3):
                        flex[b, i, c] = compliance6[3 + i, 3 + c]
                        flex_xi[b, i, c] = compliance6_xi[3 + i, 3 + c]
            else:
                kink[b], kink_xi[b] = rotation_one(
                    Xb, chains.h[b, e], chains.lag[e], npe, pair, w, w_xi
                )
                for s in range(2):
                    for c in range(3):
                        W[b, c, width * s + width - 3 + c] = w[s]
                        W_xi[b, c, width * s + width - 3 + c] = w_xi[s]
                for i in range(3):
                    for c in range(3):
                        flex[b, i, c] = kink[b] * chains.compliance_of[b, e, i, c]
                        flex_xi[b, i, c] = kink_xi[b] * chains.compliance_of[b, e, i, c]
            for s in range(2):
                for c in range(width):
                    rotation_dofs[b, width * s + c] = dof_map[e, pair[s], 6 - width + c]


@numba.njit(cache=True)
def weighted_current(
    f: np.ndarray, reference: np.ndarray, q: np.ndarray, rows: np.ndarray, dofs: np.ndarray
) -> np.ndarray:
    """``reference_j + f_j q[dofs]`` (P, k, 3) for matrices ``f`` (P, k, 3, m) at points with
    reference values ``reference`` (P, k, 3) and dofs ``dofs`` (P, m), on the states
    ``q[rows]`` (``q`` (R, n), ``rows`` (P,)): :func:`displaced` at each."""
    P, k = f.shape[0], f.shape[1]
    out = np.empty((P, k, 3))
    for p in range(P):
        for j in range(k):
            displaced(reference[p, j], f[p, j], q[rows[p]], dofs[p], out[p, j])
    return out


@numba.njit(cache=True)
def reference_line(
    nodes: np.ndarray, h: np.ndarray, X: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The reference line's ``l0`` and ``l0_/xi`` (P, 3) at ``X`` (P,) of elements with node
    positions ``nodes`` (P, npe, 3) and lengths ``h`` (P,) (:func:`element_shape`,
    :func:`weighted`)."""
    P, npe = nodes.shape[0], nodes.shape[1]
    l0, l0_xi = np.empty((P, 3)), np.empty((P, 3))
    N, dN, d2N = np.empty(npe), np.empty(npe), np.empty(npe)
    for p in range(P):
        element_shape(X[p], h[p], N, dN, d2N)
        weighted(dN, nodes[p], l0[p])
        weighted(d2N, nodes[p], l0_xi[p])
    return l0, l0_xi


@numba.njit(cache=True, inline="never")
def beam_of(first_element: np.ndarray, element: int) -> int:
    """The beam (position in the chain) holding the chain's ``element``."""
    k = 0
    while first_element[k + 1] <= element:
        k += 1
    return k


@numba.njit(cache=True, inline="never")
def node_slot(element: int, a: int, npe: int) -> int:
    """The slot of local node ``a`` of the ``element``-th element of a run of consecutive
    elements: the run's nodes in order along the chain, each element's start vertex, its mid
    node, then the next vertex (shared with the next element, across beam junctions too)."""
    base = element * (npe - 1)
    if a == 0:
        return base
    if a == 1:
        return base + npe - 1
    return base + 1


@numba.njit(cache=True, inline="never")
def element_nodes(points: np.ndarray, cell: np.ndarray, nodes: np.ndarray) -> None:
    """The positions (npe, 3) of an element's nodes ``cell`` (npe,) among ``points`` into
    ``nodes``."""
    for a in range(len(cell)):
        for c in range(3):
            nodes[a, c] = points[cell[a], c]


@numba.njit(cache=True, inline="never")
def add_block(block: np.ndarray, scale: float, element: int, out: np.ndarray) -> None:
    """Add ``scale`` times an element's ``block`` (6 npe, 6), node by node, to the rows of its
    nodes' slots in ``out`` (:func:`node_slot`)."""
    npe = block.shape[0] // 6
    for a in range(npe):
        slot = 6 * node_slot(element, a, npe)
        for r in range(6):
            for c in range(6):
                out[slot + r, c] += scale * block[6 * a + r, c]


@numba.njit(cache=True)
def smeared_transfer(
    xi: np.ndarray, kernel: Smearing, chains: Chains
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The smeared load transfer of each member at ``xi`` (B,) on the stack's arrays
    ``chains``, as :meth:`sliders.lines.chain.BeamChain.transfer` gives it from the kernel form:
    ``G = A / m`` and ``G' = (A' - G m') / m`` with ``A = int K(s - xi) H(s) ds`` and
    ``m = int K(s - xi) ds`` over the chain ``[0, L]``, ``A' = -int K' H ds`` (eq. T6).

    The ``kernel`` (box if ``box``, else hat; half-width ``smearing > 0``) is integrated on each
    element of each beam it touches, over its part inside the beam and the kernel
    (:func:`fvbeam.pointwise.smeared_element`, composite rule ``rule_x``, ``rule_w``); the
    Dirac parts of ``K'`` (the jumps ``step_jump`` at the offsets ``step_r``,
    :func:`fvbeam.smearing.steps`) add ``-jump H`` at ``xi + r`` inside the chain to ``A'``
    (and ``-jump`` to ``m'``), ``H`` the point transfer there (:func:`locate_one`,
    :func:`fvbeam.pointwise.transfer_at`).

    Returns ``dofs`` (B, k), ``G`` and ``dG/dxi`` (B, k, 6): the dofs of the nodes of the
    elements from the one holding ``max(xi - smearing, 0)`` to the one holding
    ``min(xi + smearing, L)`` (:func:`node_slot`), padded to the common ``k`` with the
    member's last dof and zero rows.
    """
    smearing, step_r, step_jump = kernel.half_width, kernel.step_r, kernel.step_jump
    B, npe = len(xi), chains.cells.shape[1]
    span = np.empty((B, 2), np.int64)
    slots = 1
    for b in range(B):
        length = chains.breaks[b, -1]
        span[b, 0] = locate_one(
            max(xi[b] - smearing, 0.0),
            chains.breaks[b],
            chains.vertex_s[b],
            chains.first_element,
            chains.h[b],
        )[1]
        span[b, 1] = locate_one(
            min(xi[b] + smearing, length),
            chains.breaks[b],
            chains.vertex_s[b],
            chains.first_element,
            chains.h[b],
        )[1]
        slots = max(slots, (span[b, 1] - span[b, 0] + 1) * (npe - 1) + 1)
    dofs = np.empty((B, 6 * slots), np.int64)
    G, dG = np.zeros((B, 6 * slots, 6)), np.zeros((B, 6 * slots, 6))
    shapes = Shapes(np.empty(npe), np.empty(npe), np.empty(npe), np.empty(npe), np.empty(npe))
    H, dH = np.empty((6 * npe, 6)), np.empty((6 * npe, 6))
    A, dA = np.empty((6 * npe, 6)), np.empty((6 * npe, 6))
    nodes, scratch = np.empty((npe, 3)), np.empty(2 * npe + 5)
    for b in range(B):
        x, dof_map, first = xi[b], chains.maps[chains.member_map[b]], span[b, 0]
        mass = dmass = 0.0
        for e in range(first, span[b, 1] + 1):
            for a in range(npe):
                slot = 6 * node_slot(e - first, a, npe)
                for c in range(6):
                    dofs[b, slot + c] = dof_map[e, a, c]
            k = beam_of(chains.first_element, e)
            offset = chains.breaks[b, k]
            lo, hi = max(x - smearing, offset), min(x + smearing, chains.breaks[b, k + 1])
            if hi <= lo:
                continue
            local = x - offset  # the beam's own abscissae, as the beam's form reads them
            lo, hi = max(lo - offset, local - smearing), min(hi - offset, local + smearing)
            # beam k's vertices
            start, end = chains.vertex_s[b, e + k], chains.vertex_s[b, e + k + 1]
            if not (start < hi and end > lo):
                continue
            element_nodes(chains.points[b], chains.cells[e], nodes)
            A[:] = 0.0
            dA[:] = 0.0
            element = Element(
                chains.kinds[k],
                chains.regions,
                nodes,
                chains.R0_of[b, e],
                chains.stiffness[e],
                chains.h[b, e],
            )
            m, dm = smeared_element(
                element,
                start,
                max(lo, start),
                min(hi, end),
                local,
                kernel,
                shapes,
                (scratch, H, dH),
                (A, dA),
            )
            mass += m
            dmass += dm
            add_block(A, 1.0, e - first, G[b])
            add_block(dA, 1.0, e - first, dG[b])
        for i in range(len(step_r)):
            at = x + step_r[i]
            if 0 < at < chains.breaks[b, -1]:
                k, e, X = locate_one(
                    at, chains.breaks[b], chains.vertex_s[b], chains.first_element, chains.h[b]
                )
                element_nodes(chains.points[b], chains.cells[e], nodes)
                element = Element(
                    chains.kinds[k],
                    chains.regions,
                    nodes,
                    chains.R0_of[b, e],
                    chains.stiffness[e],
                    chains.h[b, e],
                )
                transfer_at(element, X, shapes, H, dH)
                add_block(H, -step_jump[i], e - first, dG[b])
                dmass -= step_jump[i]
        used = 6 * ((span[b, 1] - first + 1) * (npe - 1) + 1)
        dofs[b, used:] = dofs[b, used - 1]
        for r in range(used):
            for c in range(6):
                G[b, r, c] = G[b, r, c] / mass
                dG[b, r, c] = (dG[b, r, c] - G[b, r, c] * dmass) / mass
    return dofs, G, dG
