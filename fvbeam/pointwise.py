"""A beam's interpolation and test functions at one point, compiled (numba).

The functions of one point write into arrays the caller owns (no temporaries), so that the
compiled kernels of :mod:`sliders.lines.batched_kernel` call them per member; the ``*_many``
functions loop them over flat arrays of points for the numpy-facing wrappers of
:mod:`fvbeam.mesh` (:func:`~fvbeam.mesh.shape_functions`), :mod:`fvbeam.elements`
(:func:`~fvbeam.elements.indicator`, :func:`~fvbeam.elements.rigid_motions_at`) and
:mod:`fvbeam.formulations` (``transfer_at``).  Reference coordinates ``X`` run over the
element [0, 1], local nodes in meshio's order: end 0, end 1, then the mid node.

Each kernel has a plain numpy reference at the end of the module (``*_reference``: the
Lagrange shape functions, the region indicators with their half-and-half rule, the rigid
motions of eq. T4 and the load-transfer block of eq. T6, written as the equations read); the
tests hold kernels and references equal to roundoff.  They are for reading and testing: the
code runs the kernels.

A smeared load has its definition elsewhere: the kernels :func:`fvbeam.smearing.density` and
:func:`~fvbeam.smearing.slope`, integrated against the test functions by the scikit-fem form
of :meth:`fvbeam.beam.Beam.kernel_transfer`.  :func:`kernel_at` and :func:`smeared_element`
are their compiled twins for the hot path (the smeared line state of
:func:`sliders.lines.batched_kernel.smeared_transfer`): the kernel at one offset, and its
integral against one element's test functions on the form's pieces by the form's rule
(``tests/test_smeared_transfer.py`` holds them to the form).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.polynomial import Polynomial

from fvbeam.geometry import skew_matrices

#: Distance (reference coordinate) within which a point counts as on a region boundary.
TIE = 1e-12


@numba.njit(cache=True, inline="never")
def shape_at(X: float, npe: int, N: np.ndarray, dN: np.ndarray, d2N: np.ndarray) -> None:
    """Lagrange shape functions ``N``, ``dN/dX`` and ``d^2N/dX^2`` (npe,) at ``X``
    (``docs/theory.md``, the trial interpolation of the six nodal fields)."""
    if npe == 2:
        N[0], N[1] = 1 - X, X
        dN[0], dN[1] = -1.0, 1.0
        d2N[0], d2N[1] = 0.0, 0.0
    else:
        N[0] = 1 - 3 * X + 2 * (X * X)
        N[1] = -X + 2 * (X * X)
        N[2] = 4 * X - 4 * (X * X)
        dN[0], dN[1], dN[2] = -3 + 4 * X, -1 + 4 * X, 4 - 8 * X
        d2N[0], d2N[1], d2N[2] = 4.0, 4.0, -8.0


@numba.njit(cache=True, inline="never")
def indicator_at(X: float, regions: np.ndarray, chi: np.ndarray) -> None:
    """Influence-region indicators ``chi_a(X)`` (npe,) of the fv test functions (eq. T4) for
    the regions' bounds ``regions`` (npe, 2) (:func:`fvbeam.elements.influence_regions`).

    A point within :data:`TIE` of an evaluation point belongs half to each neighbouring
    region, the limit of a symmetric smearing of vanishing width; the element's ends count
    whole."""
    for a in range(regions.shape[0]):
        lo, hi = regions[a, 0], regions[a, 1]
        near_lo, near_hi = abs(X - lo) <= TIE, abs(X - hi) <= TIE
        value = 1.0 if (X > lo and X < hi and not near_lo and not near_hi) else 0.0
        if near_lo:
            value += 1.0 if lo == 0 else 0.5
        if near_hi:
            value += 1.0 if hi == 1 else 0.5
        chi[a] = value


@numba.njit(cache=True, inline="never")
def rigid_blocks_at(
    nodes: np.ndarray,
    h: float,
    N: np.ndarray,
    dN: np.ndarray,
    chi: np.ndarray,
    dchi: np.ndarray,
    G: np.ndarray,
    dG: np.ndarray,
) -> None:
    """The fv test functions (eq. T4) at a point of an element with node positions ``nodes``
    (npe, 3) and length ``h``, from the shape functions ``N``, ``dN/dX`` there, into ``G``
    and ``dG`` (6 npe, 6) (:func:`fvbeam.elements.rigid_motions_at`): node ``a``'s block
    ``chi_a [[I, 0], [skew(x - x_a), I]]`` and its ``xi``-derivative
    ``chi_a [[0, 0], [skew(x_/xi), 0]] + dchi_a [[I, 0], [skew(x - x_a), I]]``."""
    G[:] = 0.0
    dG[:] = 0.0
    npe = nodes.shape[0]
    x0 = x1 = x2 = d0 = d1 = d2 = 0.0
    for b in range(npe):
        x0 += N[b] * nodes[b, 0]
        x1 += N[b] * nodes[b, 1]
        x2 += N[b] * nodes[b, 2]
        d0 += dN[b] * nodes[b, 0]
        d1 += dN[b] * nodes[b, 1]
        d2 += dN[b] * nodes[b, 2]
    d0, d1, d2 = d0 / h, d1 / h, d2 / h
    for a in range(npe):
        r = 6 * a
        c, dc = chi[a], dchi[a]
        v0, v1, v2 = x0 - nodes[a, 0], x1 - nodes[a, 1], x2 - nodes[a, 2]
        for k in range(3):
            G[r + k, k] = c
            G[r + 3 + k, 3 + k] = c
            dG[r + k, k] = dc
            dG[r + 3 + k, 3 + k] = dc
        G[r + 3, 1], G[r + 3, 2] = -v2 * c, v1 * c
        G[r + 4, 0], G[r + 4, 2] = v2 * c, -v0 * c
        G[r + 5, 0], G[r + 5, 1] = -v1 * c, v0 * c
        dG[r + 3, 1], dG[r + 3, 2] = -d2 * c + -v2 * dc, d1 * c + v1 * dc
        dG[r + 4, 0], dG[r + 4, 2] = d2 * c + v2 * dc, -d0 * c + -v0 * dc
        dG[r + 5, 0], dG[r + 5, 1] = -d1 * c + -v1 * dc, d0 * c + v0 * dc


@numba.njit(cache=True, inline="never")
def shape_blocks_at(h: float, N: np.ndarray, dN: np.ndarray, G: np.ndarray, dG: np.ndarray) -> None:
    """The Galerkin test functions at a point as load-transfer blocks ``N_a I`` (6 npe, 6)
    into ``G`` and their ``xi``-derivatives ``dN_a/dX / h I`` into ``dG``."""
    G[:] = 0.0
    dG[:] = 0.0
    for a in range(N.shape[0]):
        slope = dN[a] / h
        for c in range(6):
            G[6 * a + c, c] = N[a]
            dG[6 * a + c, c] = slope


@numba.njit(cache=True, inline="never")
def transfer_at(
    fv: bool,
    regions: np.ndarray,
    nodes: np.ndarray,
    h: float,
    X: float,
    N: np.ndarray,
    dN: np.ndarray,
    d2N: np.ndarray,
    chi: np.ndarray,
    dchi: np.ndarray,
    G: np.ndarray,
    dG: np.ndarray,
) -> None:
    """The test functions at ``X`` as load-transfer matrices ``G`` and ``dG/dxi``
    (6 npe, 6), eq. T6: fv (``fv``, region bounds ``regions``) or Galerkin; ``N``, ``dN``,
    ``d2N``, ``chi``, ``dchi`` (npe,) are scratch."""
    shape_at(X, nodes.shape[0], N, dN, d2N)
    if fv:
        indicator_at(X, regions, chi)
        dchi[:] = 0.0
        rigid_blocks_at(nodes, h, N, dN, chi, dchi, G, dG)
    else:
        shape_blocks_at(h, N, dN, G, dG)


@numba.njit(cache=True, inline="never")
def kernel_at(r: float, smearing: float, box: bool) -> tuple[float, float]:
    """The smearing kernel ``K(r)`` of half-width ``smearing > 0`` at the offset ``r = s - xi``
    and ``dK/dr`` away from its steps (:func:`fvbeam.smearing.density` and
    :func:`~fvbeam.smearing.slope`, eq. T6): the box ``1 / (2 smearing)`` (``box``) or the
    hat ``(1 - |r| / smearing) / smearing`` with slope ``-sign(r) / smearing^2`` inside
    ``|r| < smearing``, 0 outside."""
    if not abs(r) < smearing:
        return 0.0, 0.0
    if box:
        return 1 / (2 * smearing), 0.0
    return (1 - abs(r) / smearing) / smearing, -np.sign(r) / smearing**2


@numba.njit(cache=True, inline="never")
def smeared_element(
    fv: bool,
    regions: np.ndarray,
    nodes: np.ndarray,
    start: float,
    h: float,
    lo: float,
    hi: float,
    xi: float,
    smearing: float,
    box: bool,
    rule_x: np.ndarray,
    rule_w: np.ndarray,
    breaks: np.ndarray,
    N: np.ndarray,
    dN: np.ndarray,
    d2N: np.ndarray,
    chi: np.ndarray,
    dchi: np.ndarray,
    H: np.ndarray,
    dH: np.ndarray,
    A: np.ndarray,
    dA: np.ndarray,
) -> tuple[float, float]:
    """A smearing kernel integrated against the test functions (eq. T6) over the part
    ``[lo, hi]`` of one element, as :meth:`fvbeam.beam.Beam.kernel_transfer` integrates it.

    The element has node positions ``nodes`` (npe, 3), starts at the abscissa ``start`` and
    has length ``h``; the kernel :func:`kernel_at` sits at ``xi`` with half-width
    ``smearing``.  ``[lo, hi]`` is split at the fv evaluation points (bounds of ``regions``,
    when ``fv``) and the kernel's break points ``xi``, ``xi -+ smearing``; on each piece the
    kernel times the test functions is a polynomial of degree at most 3 in the abscissa,
    integrated exactly by the rule ``rule_x``, ``rule_w`` on [0, 1] (3-point Gauss).  Adds
    ``int K(s - xi) H(s) ds`` to ``A`` and ``-int K'(s - xi) H(s) ds`` to ``dA``
    (6 npe, 6), ``H`` the compiled transfer :func:`transfer_at`; returns ``int K ds`` and
    ``-int K' ds``.  ``breaks`` (at least ``2 npe + 5``), ``N``, ``dN``, ``d2N``, ``chi``,
    ``dchi`` (npe,), ``H`` and ``dH`` (6 npe, 6) are scratch."""
    n = 0
    for value in (lo, hi, xi - smearing, xi, xi + smearing):
        breaks[n] = value
        n += 1
    if fv:
        for a in range(regions.shape[0]):
            for side in range(2):
                breaks[n] = start + h * regions[a, side]
                n += 1
    for i in range(n):  # clip to [lo, hi] and sort (insertion: a handful of points)
        value = min(max(breaks[i], lo), hi)
        j = i
        while j > 0 and breaks[j - 1] > value:
            breaks[j] = breaks[j - 1]
            j -= 1
        breaks[j] = value
    mass = dmass = 0.0
    for i in range(n - 1):
        a, length = breaks[i], breaks[i + 1] - breaks[i]
        if length <= 0:
            continue
        for g in range(len(rule_x)):
            s, w = a + length * rule_x[g], length * rule_w[g]
            K, dK = kernel_at(s - xi, smearing, box)
            X = min(max((s - start) / h, 0.0), 1.0)
            transfer_at(fv, regions, nodes, h, X, N, dN, d2N, chi, dchi, H, dH)
            for r in range(H.shape[0]):
                for c in range(6):
                    A[r, c] += (w * K) * H[r, c]
                    dA[r, c] -= (w * dK) * H[r, c]
            mass += w * K
            dmass -= w * dK
    return mass, dmass


@numba.njit(cache=True)
def shape_functions_many(X: np.ndarray, npe: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`shape_at` at the points ``X`` (P,): ``N`` and ``dN/dX``, (npe, P)."""
    N, dN = np.empty((npe, len(X))), np.empty((npe, len(X)))
    n, dn, d2n = np.empty(npe), np.empty(npe), np.empty(npe)
    for p in range(len(X)):
        shape_at(X[p], npe, n, dn, d2n)
        N[:, p], dN[:, p] = n, dn
    return N, dN


@numba.njit(cache=True)
def indicator_many(X: np.ndarray, regions: np.ndarray) -> np.ndarray:
    """:func:`indicator_at` at the points ``X`` (P,): (npe, P)."""
    chi, one = np.empty((regions.shape[0], len(X))), np.empty(regions.shape[0])
    for p in range(len(X)):
        indicator_at(X[p], regions, one)
        chi[:, p] = one
    return chi


@numba.njit(cache=True)
def rigid_motions_many(
    nodes: np.ndarray, h: np.ndarray, X: np.ndarray, chi: np.ndarray, dchi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`rigid_blocks_at` at the points ``X`` (P,) of elements ``nodes`` (P, npe, 3),
    ``h`` (P,), indicators ``chi``, ``dchi`` (P, npe): (P, 6 npe, 6) each."""
    P, npe = nodes.shape[0], nodes.shape[1]
    G, dG = np.empty((P, 6 * npe, 6)), np.empty((P, 6 * npe, 6))
    N, dN, d2N = np.empty(npe), np.empty(npe), np.empty(npe)
    for p in range(P):
        shape_at(X[p], npe, N, dN, d2N)
        rigid_blocks_at(nodes[p], h[p], N, dN, chi[p], dchi[p], G[p], dG[p])
    return G, dG


@numba.njit(cache=True)
def transfer_many(
    fv: bool, regions: np.ndarray, nodes: np.ndarray, h: np.ndarray, X: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`transfer_at` at the points ``X`` (P,) of elements ``nodes`` (P, npe, 3),
    ``h`` (P,): (P, 6 npe, 6) each."""
    P, npe = nodes.shape[0], nodes.shape[1]
    G, dG = np.empty((P, 6 * npe, 6)), np.empty((P, 6 * npe, 6))
    N, dN, d2N = np.empty(npe), np.empty(npe), np.empty(npe)
    chi, dchi = np.empty(npe), np.empty(npe)
    for p in range(P):
        transfer_at(fv, regions, nodes[p], h[p], X[p], N, dN, d2N, chi, dchi, G[p], dG[p])
    return G, dG


# -- numpy reference of the kernels above ----------------------------------------------------

#: Local node positions in the reference element: end 0, end 1, mid node.
LOCAL_NODES = np.array([0.0, 1.0, 0.5])


def shape_reference(X: float, npe: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`shape_at` as the Lagrange polynomials on the local nodes ``X_b``:
    ``N_a = prod_(b != a) (X - X_b) / (X_a - X_b)``, with their first and second derivatives."""
    nodes = LOCAL_NODES[:npe]
    N = [
        Polynomial.fromroots(np.delete(nodes, a)) / np.prod(nodes[a] - np.delete(nodes, a))
        for a in range(npe)
    ]
    value, first, second = (np.array([p.deriv(k)(X) for p in N]) for k in range(3))
    return value, first, second


def indicator_reference(X: float, regions: np.ndarray) -> np.ndarray:
    """:func:`indicator_at`: ``chi_a(X)`` is 1 inside node ``a``'s region ``[lo, hi]`` and 0
    outside (eq. T4); on a bound (within :data:`TIE`) it is 1/2 where the bound is an
    evaluation point, shared half and half with the next region (``docs/theory.md`` Sec. 4, "A
    load on an evaluation point"), and 1 where it is the element's end."""
    chi = np.zeros(len(regions))
    for a, (lo, hi) in enumerate(regions):
        if abs(X - lo) <= TIE:
            chi[a] = 1.0 if lo == 0 else 0.5
        elif abs(X - hi) <= TIE:
            chi[a] = 1.0 if hi == 1 else 0.5
        elif lo < X < hi:
            chi[a] = 1.0
    return chi


def rigid_blocks_reference(
    nodes: np.ndarray, h: float, N: np.ndarray, dN: np.ndarray, chi: np.ndarray, dchi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`rigid_blocks_at`: the fv test functions of eq. T4 at ``x = sum N_b x_b``.

    Node ``a``'s block (rows ``6a .. 6a + 5``) is ``chi_a [[I, 0], [skew(x - x_a), I]]``
    (``skew(v) F = v x F``, :func:`fvbeam.geometry.skew_matrices`): the
    translations ``e_c chi_a`` and rotations ``(e_k x (x - x_a) chi_a, e_k chi_a)`` as rows,
    or the matrix carrying ``[F; M]`` at ``x`` to the node (eq. T6).  Its derivative in the
    abscissa is ``dchi_a [[I, 0], [skew(x - x_a), I]] + chi_a [[0, 0], [skew(x_/xi), 0]]``
    with ``x_/xi = sum dN_b x_b / h``.
    """
    x, x_xi = N @ nodes, dN @ nodes / h
    eye, zero = np.eye(3), np.zeros((3, 3))
    G = [
        c * np.block([[eye, zero], [skew_matrices(x - xa), eye]])
        for c, xa in zip(chi, nodes, strict=True)
    ]
    dG = [
        dc * np.block([[eye, zero], [skew_matrices(x - xa), eye]])
        + c * np.block([[zero, zero], [skew_matrices(x_xi), zero]])
        for c, dc, xa in zip(chi, dchi, nodes, strict=True)
    ]
    return np.vstack(G), np.vstack(dG)


def shape_blocks_reference(
    h: float, N: np.ndarray, dN: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`shape_blocks_at`: the Galerkin test functions ``N_a I`` (6 x 6 blocks) and their
    derivatives in the abscissa ``dN_a/dX / h I``."""
    return np.kron(N[:, None], np.eye(6)), np.kron(dN[:, None] / h, np.eye(6))


def transfer_reference(
    fv: bool, regions: np.ndarray, nodes: np.ndarray, h: float, X: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`transfer_at`: the load-transfer matrix ``H`` (6 npe, 6) of a unit force and
    couple at ``X`` (eq. T6) and ``dH/dxi``, for fv (rigid motions of the regions, with the
    indicators' derivative 0 away from the jumps) or Galerkin (shape functions)."""
    N, dN, _ = shape_reference(X, len(nodes))
    if fv:
        chi = indicator_reference(X, regions)
        return rigid_blocks_reference(nodes, h, N, dN, chi, np.zeros_like(chi))
    return shape_blocks_reference(h, N, dN)
