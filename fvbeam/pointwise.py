"""A beam's interpolation and test functions at one point, compiled (numba).

The functions of one point write into arrays the caller owns (no temporaries), so that the
compiled kernels of :mod:`sliders.lines.batched_kernel` call them per member; the ``*_many``
functions loop them over flat arrays of points for the numpy-facing wrappers of
:mod:`fvbeam.mesh` (:func:`~fvbeam.mesh.shape_functions`), :mod:`fvbeam.elements`
(:func:`~fvbeam.elements.indicator`, :func:`~fvbeam.elements.rigid_motions_at`) and
:mod:`fvbeam.formulations` (``transfer_at``).  Reference coordinates ``X`` run over the
element [0, 1], local nodes in meshio's order: end 0, end 1, then the mid node.

The cubic element (``docs/theory.md`` Sec. 9, the interdependent interpolation) has trial
and test functions of its own, which depend on the element's frame and section:
:func:`cubic_local_at` (section axes) and :func:`cubic_blocks_at` (global axes, the
load-transfer blocks), and the compliance of the element at an interior point under a load
there (:func:`cubic_flex_at`, eq. T13).  :func:`transfer_at` reads an element of any
:data:`LAGRANGE`, :data:`FINITE_VOLUME` or :data:`CUBIC` kind.

Each kernel has a plain numpy reference at the end of the module (``*_reference``: the
Lagrange shape functions, the region indicators with their half-and-half rule, the rigid
motions of eq. T4, the load-transfer block of eq. T6, the cubic element's functions as the
homogeneous solutions of the Timoshenko beam and its compliance as two cantilevers in
parallel, written as the equations read); the tests hold kernels and references equal to
roundoff.  They are for reading and testing: the code runs the kernels.

A smeared load has its definition elsewhere: the kernels :func:`fvbeam.smearing.density` and
:func:`~fvbeam.smearing.slope`, integrated against the test functions by the scikit-fem form
of :meth:`fvbeam.beam.Beam.kernel_transfer`.  :func:`kernel_at` and :func:`smeared_element`
are their compiled twins for the hot path (the smeared line state of
:func:`sliders.lines.batched_kernel.smeared_transfer`): the kernel at one offset, and its
integral against one element's test functions on the form's pieces by the form's rule
(``tests/test_smeared_transfer.py`` holds them to the form).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np
from numpy.polynomial import Polynomial

from fvbeam.geometry import skew_matrices
from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: Distance (reference coordinate) within which a point counts as on a region boundary.
TIE = 1e-12
#: Kinds of element of :func:`transfer_at`: Lagrange shape functions as test functions
#: (Galerkin), rigid motions of the influence regions (finite volume, eq. T4), and the cubic
#: element's own functions (eq. T11).
LAGRANGE, FINITE_VOLUME, CUBIC = 0, 1, 2


class Element(NamedTuple):
    """One element as :func:`transfer_at` reads it."""

    #: :data:`LAGRANGE`, :data:`FINITE_VOLUME` (with the region bounds ``regions`` (npe, 2))
    #: or :data:`CUBIC` (with its section ``frame`` (3, 3) and the diagonal of its section
    #: stiffness ``stiffness`` (6,), which the others ignore).
    kind: int
    regions: np.ndarray
    #: The node positions (npe, 3) and the length.
    nodes: np.ndarray
    frame: np.ndarray
    stiffness: np.ndarray
    h: float


class Shapes(NamedTuple):
    """Scratch for the shape functions ``N``, ``dN``, ``d2N`` and the region indicators
    ``chi``, ``dchi`` at a point (npe,)."""

    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    chi: np.ndarray
    dchi: np.ndarray


class Smearing(NamedTuple):
    """A smeared load's kernel as :func:`smeared_element` integrates it."""

    #: The kernel's half-width (> 0) and shape (box if ``box``, else hat).
    half_width: float
    box: bool
    #: The jumps ``step_jump`` of its derivative at the offsets ``step_r``
    #: (:func:`fvbeam.smearing.steps`), and the composite rule ``rule_x``, ``rule_w`` on
    #: [0, 1].
    step_r: np.ndarray
    step_jump: np.ndarray
    rule_x: np.ndarray
    rule_w: np.ndarray


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
def cubic_plane_at(
    X: float, h: float, EJ: float, GA: float, order: int
) -> tuple[float, float, float, float, float, float, float, float]:
    """The cubic element's functions of one bending plane (eq. T11), or their ``order``-th
    derivative in the abscissa (``order`` 0 to 3), at ``X`` of an element of length ``h``:
    the deflection ``v`` and the rotation ``psi`` (``v' - psi`` the shear strain) of the nodal
    values ``v_0, psi_0, v_1, psi_1`` in turn, ``(v of v_0, psi of v_0, v of psi_0, psi of
    psi_0, ...)``, with ``phi = 12 EJ / (GA h^2)`` and ``mu = 1 / (1 + phi)``::

        v:   mu (1 - 3X^2 + 2X^3 + phi (1 - X)),  mu h (X - 2X^2 + X^3 + phi (X - X^2) / 2),
             mu (3X^2 - 2X^3 + phi X),           mu h (-X^2 + X^3 - phi (X - X^2) / 2)
        psi: 6 mu (X^2 - X) / h,                 mu (1 - 4X + 3X^2 + phi (1 - X)),
             6 mu (X - X^2) / h,                 mu (-2X + 3X^2 + phi X)
    """
    phi = 12 * EJ / (GA * h * h)
    mu = 1 / (1 + phi)
    X2 = X * X
    if order == 0:
        v = (
            1 - 3 * X2 + 2 * X2 * X + phi * (1 - X),
            h * (X - 2 * X2 + X2 * X + 0.5 * phi * (X - X2)),
            3 * X2 - 2 * X2 * X + phi * X,
            h * (-X2 + X2 * X - 0.5 * phi * (X - X2)),
        )
        p = (6 * (X2 - X) / h, 1 - 4 * X + 3 * X2 + phi * (1 - X), 6 * (X - X2) / h)
        p4 = -2 * X + 3 * X2 + phi * X
    elif order == 1:
        v = (
            -6 * X + 6 * X2 - phi,
            h * (1 - 4 * X + 3 * X2 + 0.5 * phi * (1 - 2 * X)),
            6 * X - 6 * X2 + phi,
            h * (-2 * X + 3 * X2 - 0.5 * phi * (1 - 2 * X)),
        )
        p = (6 * (2 * X - 1) / h, -4 + 6 * X - phi, 6 * (1 - 2 * X) / h)
        p4 = -2 + 6 * X + phi
    elif order == 2:
        v = (-6 + 12 * X, h * (-4 + 6 * X - phi), 6 - 12 * X, h * (-2 + 6 * X + phi))
        p = (12 / h, 6.0, -12 / h)
        p4 = 6.0
    else:
        v = (12.0, 6 * h, -12.0, 6 * h)
        p = (0.0, 0.0, 0.0)
        p4 = 0.0
    scale = mu / h**order
    return (
        scale * v[0],
        scale * p[0],
        scale * v[1],
        scale * p[1],
        scale * v[2],
        scale * p[2],
        scale * v[3],
        scale * p4,
    )


@numba.njit(cache=True, inline="never")
def cubic_local_at(stiffness: np.ndarray, h: float, X: float, order: int, L: np.ndarray) -> None:
    """The cubic element's functions (eq. T11) in its section axes ``(t, e2, e3)``, or their
    ``order``-th derivative in the abscissa, at ``X``, into ``L`` (12, 6): row ``6a + k`` is
    the field ``(u, theta)`` of a unit value of node ``a``'s dof ``k``.

    ``stiffness`` (6,) holds ``EA, GAy, GAz, GJ, EJy, EJz`` (the diagonal of the section
    stiffness).  The axial displacement and the twist are linear; ``u2`` and ``theta3``
    follow :func:`cubic_plane_at` with ``EJz, GAy`` (``psi = theta3``), ``u3`` and ``theta2``
    with ``EJy, GAz`` and ``psi = -theta2`` (the shear strain ``u3' + theta2``)."""
    L[:] = 0.0
    ends = (1 - X, X) if order == 0 else ((-1 / h, 1 / h) if order == 1 else (0.0, 0.0))
    y = cubic_plane_at(X, h, stiffness[5], stiffness[1], order)
    z = cubic_plane_at(X, h, stiffness[4], stiffness[2], order)
    for a in range(2):
        r, j = 6 * a, 4 * a
        L[r, 0] = ends[a]
        L[r + 3, 3] = ends[a]
        L[r + 1, 1], L[r + 1, 5] = y[j], y[j + 1]
        L[r + 5, 1], L[r + 5, 5] = y[j + 2], y[j + 3]
        L[r + 2, 2], L[r + 2, 4] = z[j], -z[j + 1]
        L[r + 4, 2], L[r + 4, 4] = -z[j + 2], z[j + 3]


@numba.njit(cache=True, inline="never")
def to_global(frame: np.ndarray, B: np.ndarray) -> None:
    """``B`` (n 6, 6) made global in place, block by block: ``Q B_a Q^T`` with
    ``Q = blockdiag(R, R)``, ``R`` the section ``frame`` (3, 3), for each 6x6 block
    ``B_a``."""
    for a in range(B.shape[0] // 6):
        r = 6 * a
        for k in range(6):  # B_a Q^T, row by row
            for half in range(2):
                c = 3 * half
                x0, x1, x2 = B[r + k, c], B[r + k, c + 1], B[r + k, c + 2]
                for i in range(3):
                    B[r + k, c + i] = frame[i, 0] * x0 + frame[i, 1] * x1 + frame[i, 2] * x2
        for j in range(6):  # Q (B_a Q^T), column by column
            for half in range(2):
                c = r + 3 * half
                x0, x1, x2 = B[c, j], B[c + 1, j], B[c + 2, j]
                for i in range(3):
                    B[c + i, j] = frame[i, 0] * x0 + frame[i, 1] * x1 + frame[i, 2] * x2


@numba.njit(cache=True, inline="never")
def cubic_blocks_at(
    frame: np.ndarray, stiffness: np.ndarray, h: float, X: float, G: np.ndarray, dG: np.ndarray
) -> None:
    """The cubic element's test functions at ``X`` as load-transfer blocks ``G`` (12, 6) and
    their ``xi``-derivatives ``dG`` (eqs. T6, T11): :func:`cubic_local_at` in global axes
    (:func:`to_global`, ``frame`` the element's section frame).  Row ``6a + c`` is test
    function ``c`` of node ``a`` as the 6-vector ``(w, psi)``, as for the other kinds; the
    element is a Galerkin one, so these are its trial functions too."""
    cubic_local_at(stiffness, h, X, 0, G)
    cubic_local_at(stiffness, h, X, 1, dG)
    to_global(frame, G)
    to_global(frame, dG)


@numba.njit(cache=True, inline="never")
def _cantilever(
    length: float, sign: float, EJ: float, GA: float, rate: bool
) -> tuple[float, float, float]:
    """Tip flexibility ``[[f_vv, f_vp], [f_vp, f_pp]]`` of a Timoshenko cantilever of
    ``length`` in one bending plane (deflection and rotation ``psi`` under a tip force and
    couple), ``sign`` -1 for one clamped at its far end (its tip looks back), or its
    derivative in ``length`` (``rate``)."""
    if rate:
        return length * length / EJ + 1 / GA, sign * length / EJ, 1 / EJ
    return (
        length**3 / (3 * EJ) + length / GA,
        sign * length * length / (2 * EJ),
        length / EJ,
    )


@numba.njit(cache=True, inline="never")
def _triple(
    x: tuple[float, float, float], y: tuple[float, float, float], z: tuple[float, float, float]
) -> tuple[float, float, float, float]:
    """The product ``X Y Z`` of three symmetric 2x2 matrices given by their entries
    ``(00, 01, 11)``: its entries ``00, 01, 10, 11``."""
    p00, p01 = x[0] * y[0] + x[1] * y[1], x[0] * y[1] + x[1] * y[2]
    p10, p11 = x[1] * y[0] + x[2] * y[1], x[1] * y[1] + x[2] * y[2]
    return (
        p00 * z[0] + p01 * z[1],
        p00 * z[1] + p01 * z[2],
        p10 * z[0] + p11 * z[1],
        p10 * z[1] + p11 * z[2],
    )


@numba.njit(cache=True, inline="never")
def _parallel(
    a: float, b: float, EJ: float, GA: float
) -> tuple[float, float, float, float, float, float, float, float]:
    """One bending plane's compliance ``G = F_a (F_a + F_b)^-1 F_b`` at a point ``a`` from
    one end and ``b`` from the other of a Timoshenko beam clamped at both (two cantilevers
    joined at their tips, in parallel; eq. T13), ``F`` the cantilevers' tip flexibilities
    (:func:`_cantilever`), and its derivative in ``a`` (``b = h - a``): the entries ``00,
    01, 10, 11`` of each, ``G' = F_a' S^-1 F_b - F_a S^-1 S' S^-1 F_b + F_a S^-1 dF_b/da``
    with ``S = F_a + F_b``.  Both vanish with ``a`` or ``b``: there is no division by
    either."""
    Fa, Fb = _cantilever(a, 1.0, EJ, GA, False), _cantilever(b, -1.0, EJ, GA, False)
    dFa = _cantilever(a, 1.0, EJ, GA, True)
    rate = _cantilever(b, -1.0, EJ, GA, True)
    dFb = (-rate[0], -rate[1], -rate[2])
    det = (Fa[0] + Fb[0]) * (Fa[2] + Fb[2]) - (Fa[1] + Fb[1]) ** 2
    Si = ((Fa[2] + Fb[2]) / det, -(Fa[1] + Fb[1]) / det, (Fa[0] + Fb[0]) / det)
    dS = (dFa[0] + dFb[0], dFa[1] + dFb[1], dFa[2] + dFb[2])
    t = _triple(Si, dS, Si)  # symmetric: S^-1 dS S^-1
    dSi = (-t[0], -t[1], -t[3])
    g = _triple(Fa, Si, Fb)
    d1, d2, d3 = _triple(dFa, Si, Fb), _triple(Fa, dSi, Fb), _triple(Fa, Si, dFb)
    return (
        g[0],
        g[1],
        g[2],
        g[3],
        d1[0] + d2[0] + d3[0],
        d1[1] + d2[1] + d3[1],
        d1[2] + d2[2] + d3[2],
        d1[3] + d2[3] + d3[3],
    )


@numba.njit(cache=True, inline="never")
def cubic_flex_at(
    frame: np.ndarray,
    stiffness: np.ndarray,
    h: float,
    X: float,
    flex: np.ndarray,
    flex_xi: np.ndarray,
) -> None:
    """The cubic element's compliance at ``X`` (eq. T13) into ``flex`` (6, 6) and its
    ``xi``-derivative into ``flex_xi``, global axes: the displacement and rotation that a
    force and couple ``[F; M]`` at the point add there to the element's interpolation of the
    nodal values, the element's clamped-clamped Green's function at the load point.  The
    axial and torsional parts are ``a b / (h EA)`` and ``a b / (h GJ)``, the bending ones
    :func:`_parallel`, in the planes of :func:`cubic_local_at` (``stiffness`` (6,) as
    there, ``a = X h``, ``b = h - a``)."""
    a, b = X * h, (1 - X) * h
    flex[:] = 0.0
    flex_xi[:] = 0.0
    for k, EJ in ((0, stiffness[0]), (3, stiffness[3])):
        flex[k, k] = a * b / (h * EJ)
        flex_xi[k, k] = (b - a) / (h * EJ)
    y = _parallel(a, b, stiffness[5], stiffness[1])
    z = _parallel(a, b, stiffness[4], stiffness[2])
    for out, j in ((flex, 0), (flex_xi, 4)):
        out[1, 1], out[1, 5], out[5, 1], out[5, 5] = y[j], y[j + 1], y[j + 2], y[j + 3]
        out[2, 2], out[2, 4], out[4, 2], out[4, 4] = z[j], -z[j + 1], -z[j + 2], z[j + 3]
    to_global(frame, flex)
    to_global(frame, flex_xi)


@numba.njit(cache=True, inline="never")
def transfer_at(element: Element, X: float, shapes: Shapes, G: np.ndarray, dG: np.ndarray) -> None:
    """The test functions of ``element`` at ``X`` as load-transfer matrices ``G`` and
    ``dG/dxi`` (6 npe, 6), eq. T6; ``shapes`` is scratch."""
    if element.kind == CUBIC:
        cubic_blocks_at(element.frame, element.stiffness, element.h, X, G, dG)
        return
    shape_at(X, element.nodes.shape[0], shapes.N, shapes.dN, shapes.d2N)
    if element.kind == FINITE_VOLUME:
        indicator_at(X, element.regions, shapes.chi)
        shapes.dchi[:] = 0.0
        rigid_blocks_at(
            element.nodes, element.h, shapes.N, shapes.dN, shapes.chi, shapes.dchi, G, dG
        )
    else:
        shape_blocks_at(element.h, shapes.N, shapes.dN, G, dG)


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
    element: Element,
    start: float,
    lo: float,
    hi: float,
    xi: float,
    kernel: Smearing,
    shapes: Shapes,
    scratch: tuple[np.ndarray, np.ndarray, np.ndarray],
    out: tuple[np.ndarray, np.ndarray],
) -> tuple[float, float]:
    """A smearing kernel integrated against the test functions (eq. T6) over the part
    ``[lo, hi]`` of one element, as :meth:`fvbeam.beam.Beam.kernel_transfer` integrates it.

    The ``element`` (:func:`transfer_at`) starts at the abscissa ``start``; the ``kernel``
    (:func:`kernel_at`) sits at ``xi`` with half-width ``smearing``.
    ``[lo, hi]`` is split at the fv evaluation points (bounds of ``regions``, for
    :data:`FINITE_VOLUME`) and the kernel's break points ``xi``, ``xi -+ smearing``; on each
    piece the kernel times the test functions is a polynomial of degree at most 3 (4 for
    the cubic element under the hat) in the abscissa, integrated exactly by the rule
    ``rule_x``, ``rule_w`` on [0, 1] (3-point Gauss, exact to degree 5).  Adds
    ``int K(s - xi) H(s) ds`` to ``A`` and ``-int K'(s - xi) H(s) ds`` to ``dA`` of
    ``out = (A, dA)`` (6 npe, 6), ``H`` the compiled transfer :func:`transfer_at`; returns
    ``int K ds`` and ``-int K' ds``.  ``shapes`` and ``scratch = (breaks, H, dH)``
    (at least ``2 npe + 5``; (6 npe, 6) each) are scratch."""
    smearing = kernel.half_width
    breaks, H, dH = scratch
    A, dA = out
    n = 0
    for value in (lo, hi, xi - smearing, xi, xi + smearing):
        breaks[n] = value
        n += 1
    if element.kind == FINITE_VOLUME:
        for a in range(element.regions.shape[0]):
            for side in range(2):
                breaks[n] = start + element.h * element.regions[a, side]
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
        for g in range(len(kernel.rule_x)):
            s, w = a + length * kernel.rule_x[g], length * kernel.rule_w[g]
            K, dK = kernel_at(s - xi, smearing, kernel.box)
            X = min(max((s - start) / element.h, 0.0), 1.0)
            transfer_at(element, X, shapes, H, dH)
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
    kind: int,
    regions: np.ndarray,
    nodes: np.ndarray,
    frames: np.ndarray,
    stiffness: np.ndarray,
    h: np.ndarray,
    X: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`transfer_at` at the points ``X`` (P,) of elements ``nodes`` (P, npe, 3),
    section ``frames`` (P, 3, 3) and lengths ``h`` (P,): (P, 6 npe, 6) each."""
    P, npe = nodes.shape[0], nodes.shape[1]
    G, dG = np.empty((P, 6 * npe, 6)), np.empty((P, 6 * npe, 6))
    shapes = Shapes(np.empty(npe), np.empty(npe), np.empty(npe), np.empty(npe), np.empty(npe))
    for p in range(P):
        element = Element(kind, regions, nodes[p], frames[p], stiffness, h[p])
        transfer_at(element, X[p], shapes, G[p], dG[p])
    return G, dG


@numba.njit(cache=True)
def cubic_many(
    frames: np.ndarray, stiffness: np.ndarray, h: np.ndarray, X: np.ndarray, order: int
) -> np.ndarray:
    """The cubic element's functions (or their ``order``-th ``xi``-derivative) in global
    axes at the points ``X`` (P,) of elements of section ``frames`` (P, 3, 3) and lengths
    ``h`` (P,): (P, 12, 6), :func:`cubic_local_at` made global (:func:`to_global`)."""
    out = np.empty((len(X), 12, 6))
    for p in range(len(X)):
        cubic_local_at(stiffness, h[p], X[p], order, out[p])
        to_global(frames[p], out[p])
    return out


@numba.njit(cache=True)
def cubic_flex_many(
    frames: np.ndarray, stiffness: np.ndarray, h: np.ndarray, X: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cubic_flex_at` at the points ``X`` (P,): (P, 6, 6) each."""
    flex, flex_xi = np.empty((len(X), 6, 6)), np.empty((len(X), 6, 6))
    for p in range(len(X)):
        cubic_flex_at(frames[p], stiffness, h[p], X[p], flex[p], flex_xi[p])
    return flex, flex_xi


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


def cubic_plane_reference(h: float, EJ: float, GA: float) -> tuple[list, list]:
    """:func:`cubic_plane_at` as the homogeneous solutions of the Timoshenko beam that take
    unit nodal values: deflection ``v`` and rotation ``psi`` polynomials in the abscissa
    ``s`` from the element's start (two lists of four, for ``v_0, psi_0, v_1, psi_1``).

    Without loads, ``GA (v' - psi)`` is constant and ``EJ psi'' + GA (v' - psi) = 0``
    (``docs/theory.md``, eq. T11): ``psi = c_1 + c_2 s + c_3 s^2`` and
    ``v = c_0 + c_1 s + c_2 s^2 / 2 + c_3 (s^3 / 3 - 2 EJ s / GA)``.  The four ``c`` of each
    shape function are those matching its nodal values (``v, psi`` at 0 and ``h``)."""
    v = [
        Polynomial([1.0]),
        Polynomial([0.0, 1.0]),
        Polynomial([0.0, 0.0, 0.5]),
        Polynomial([0.0, -2 * EJ / GA, 0.0, 1 / 3]),
    ]
    psi = [
        Polynomial([0.0]),
        Polynomial([1.0]),
        Polynomial([0.0, 1.0]),
        Polynomial([0.0, 0.0, 1.0]),
    ]
    nodal = np.array([[f(0), g(0), f(h), g(h)] for f, g in zip(v, psi, strict=True)]).T
    c = np.linalg.inv(nodal)  # column i: the coefficients of the function of nodal value i
    deflection = [sum((c[j, i] * v[j] for j in range(4)), Polynomial([0.0])) for i in range(4)]
    rotation = [sum((c[j, i] * psi[j] for j in range(4)), Polynomial([0.0])) for i in range(4)]
    return deflection, rotation


def _rotated(frame: np.ndarray, local: np.ndarray) -> np.ndarray:
    """``Q B Q^T`` of each 6x6 block ``B`` of ``local`` (n 6, 6), ``Q = blockdiag(R, R)``."""
    Q = np.kron(np.eye(2), frame)
    blocks = local.reshape(-1, 6, 6)
    return (Q @ blocks @ Q.T).reshape(local.shape)


def cubic_reference(
    frame: np.ndarray, stiffness: np.ndarray, h: float, X: float, order: int
) -> np.ndarray:
    """:func:`cubic_local_at` made global (:func:`cubic_many`): the ``order``-th
    ``xi``-derivative at ``X`` of the cubic element's functions, rows ``6a + k`` the field
    ``(u, theta)`` of node ``a``'s dof ``k`` (12, 6).  Section axes first: ``u_t`` and
    ``theta_t`` linear, ``(u2, theta3)`` the plane of :func:`cubic_plane_reference` with
    ``EJz, GAy``, ``(u3, -theta2)`` the one with ``EJy, GAz``; then ``Q L Q^T`` per node."""
    s = X * h
    linear = [Polynomial([1.0, -1.0 / h]), Polynomial([0.0, 1.0 / h])]
    read = [f.deriv(order)(s) for f in linear]
    planes = [cubic_plane_reference(h, stiffness[5], stiffness[1])]
    planes.append(cubic_plane_reference(h, stiffness[4], stiffness[2]))
    (vy, py), (vz, pz) = ([[f.deriv(order)(s) for f in fs] for fs in plane] for plane in planes)
    local = np.zeros((12, 6))
    for a in range(2):
        r, j = 6 * a, 2 * a
        local[r, 0] = local[r + 3, 3] = read[a]
        local[r + 1, [1, 5]] = vy[j], py[j]
        local[r + 5, [1, 5]] = vy[j + 1], py[j + 1]
        local[r + 2, [2, 4]] = vz[j], -pz[j]
        local[r + 4, [2, 4]] = -vz[j + 1], pz[j + 1]
    return _rotated(frame, local)


def cantilever_flexibility_reference(
    length: complex, sign: float, stiffness: np.ndarray
) -> np.ndarray:
    """The tip flexibility (6, 6), section axes, of a cantilever of ``length`` whose tip looks
    back along the axis (``sign`` -1) or forward (+1): ``int_0^length B^T C^-1 B dr``, ``C``
    the diagonal section stiffness ``stiffness`` and ``B = [[I, 0], [skew(sign r e_1), I]]``
    the internal force and moment at ``r`` from the tip of a unit tip force and couple
    (virtual work).  The integrand is quadratic in ``r``: a 3-point Gauss rule is exact, and
    takes a complex ``length`` (:func:`cubic_flex_reference`)."""
    x, w = np.polynomial.legendre.leggauss(3)
    out = np.zeros((6, 6), dtype=np.result_type(length, float))
    for xg, wg in zip(x, w, strict=True):
        r = length * (xg + 1) / 2
        B = np.eye(6, dtype=out.dtype)
        B[3:, :3] = sign * r * np.array([[0, 0, 0], [0, 0, -1], [0, 1, 0]])
        out = out + wg * length / 2 * (B.T @ np.diag(1 / stiffness) @ B)
    return out


def cubic_flex_reference(
    frame: np.ndarray, stiffness: np.ndarray, h: float, X: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cubic_flex_at` (eq. T13): the clamped-clamped element's compliance at the load
    point ``a = X h``, the two cantilevers ``[0, a]`` and ``[a, h]`` joined at their tips,
    ``F_a (F_a + F_b)^-1 F_b`` (:func:`cantilever_flexibility_reference`), made global
    (``Q G Q^T``), and its ``xi``-derivative by a complex step ``i delta`` in ``a``
    (exact to roundoff: no difference is taken)."""
    delta = 1e-30 * h

    def compliance(a: complex) -> np.ndarray:
        Fa = cantilever_flexibility_reference(a, 1.0, stiffness)
        Fb = cantilever_flexibility_reference(h - a, -1.0, stiffness)
        return Fa @ np.linalg.solve(Fa + Fb, Fb)

    G = compliance(complex(X * h, delta))
    return _rotated(frame, G.real), _rotated(frame, G.imag / delta)


def transfer_reference(
    kind: int,
    regions: np.ndarray,
    nodes: np.ndarray,
    frame: np.ndarray,
    stiffness: np.ndarray,
    h: float,
    X: float,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`transfer_at`: the load-transfer matrix ``H`` (6 npe, 6) of a unit force and
    couple at ``X`` (eq. T6) and ``dH/dxi``, for fv (rigid motions of the regions, with the
    indicators' derivative 0 away from the jumps), Galerkin (shape functions) or the cubic
    element (:func:`cubic_reference`)."""
    if kind == CUBIC:
        return cubic_reference(frame, stiffness, h, X, 0), cubic_reference(
            frame, stiffness, h, X, 1
        )
    N, dN, _ = shape_reference(X, len(nodes))
    if kind == FINITE_VOLUME:
        chi = indicator_reference(X, regions)
        return rigid_blocks_reference(nodes, h, N, dN, chi, np.zeros_like(chi))
    return shape_blocks_reference(h, N, dN)
