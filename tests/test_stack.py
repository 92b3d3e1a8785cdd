"""ChainStack: the compiled line state of many chains against its numpy reference.

:mod:`sliders.lines.batched_reference` states, for one chain at one ``xi``, what
:func:`sliders.lines.batched_kernel.line_state` computes for a stack of them.  The chains
here have one to three beams (fv2, fv3, galerkin-p1 and galerkin-p2, mixed in a chain where
their elements have the same number of nodes; straight and circular-arc beams, each with its
own section), their members moved rigidly by random shifts and deformed by random nodal
displacements, queried at random abscissae and at the places where the rules change: the
chain's ends, beam junctions, element vertices, mid nodes, and evaluation points (on them,
within :data:`fvbeam.pointwise.TIE` of them, and just off them).

Tolerances (derived).  Every compared entry is a sum ``sum_j c_j y_j`` over the at most
``3 npe`` nodes read, of coefficients ``c_j`` that are polynomials of degree at most 2 in
``X`` (shape functions and their derivatives, and the recovered tangent's combination of at
most three of them with weights in [0, 1] and ``1/h``), or such a coefficient itself.  Kernel
and reference evaluate it in different orders (expanded monomials against Horner's rule, one
product order against another); each is within ``gamma_n`` times the sum of the magnitudes
of its terms of the exact value (Higham, Accuracy and Stability of Numerical Algorithms,
Sec. 3.1), ``n <= 16`` rounded operations along any entry (9 products, 3 monomials of 3
factors, the tangent's combination), so the two differ by at most ``2 gamma_16`` times that
sum.  The sum of the magnitudes of the monomial terms of a shape function or derivative on
[0, 1] is at most :data:`TERMS` ``= 12`` (``|4 - 8 X|``'s ``4 + 8`` at ``X = 1``, P2), times
``1 / h^k`` for a ``k``-th derivative in ``xi``; the recovered tangent adds two half-weighted
one-sided tangents, at most doubling it.  With ``h`` the shortest of the elements read and
``Y`` the largest coordinate of the nodes read (reference or deformed; at least 1, for the
Galerkin ``G`` which is the coefficients themselves): a coefficient of
order ``k`` within ``2 gamma_16 2 TERMS / h^k``; a line quantity within that times
``3 (3 npe + m) Y``, the reference line's sum over the nodes read and the displacement's
over its ``m`` dofs (``Y`` then also bounds the dofs read).  The integers (dofs, beam,
element) are equal exactly, and so is ``X`` (both take ``xi`` off the same breaks by the same
operations).

On cubic elements (chains with cubic beams, alone or beside galerkin-p1 ones) the
coefficients are the element's functions (eq. T11) and its compliance (eq. T13): the bounds
of ``tests/test_pointwise.py`` (the reference's 4x4 and 6x6 solves, ``(128 kappa + 64) EPS``
and ``(192 kappa + 64) EPS`` of four times the largest entry), doubled for the recovered
tangent's combination, plus the difference of the two sides' element frames (the stack's
from the reference line at the element's middle, the reference's from the mesh), which
moves each entry by at most ``2 dR`` of the largest, ``dR`` the frame's bound below.

The frame ``R0``, its curvature ``k0`` and ``k0_/xi`` are functions of the reference line's
``l0`` and ``l0_/xi`` (the same numpy functions on both sides, on ``l0`` from the kernel or
from the reference, at ``X``, or at the element's middle when the stack reads its stored
frames of straight elements, where ``l0`` is constant): they differ to first order by their
derivatives times the difference of ``l0``, ``l0_/xi`` (bounded as above).  The frame is
``t = l0 / |l0|``, ``e3 = n / |n|`` with ``n = up - (up . t) t``, ``e2 = e3 x t``: a change
``dl`` moves ``t`` by at most ``2 |dl| / |l0|``, ``e3`` by ``4 |dt| / |n|`` and ``e2`` by
the sum, so ``|dR0| <= 10 |dl| / (|l0| |n|)`` plus the frame's own rounding
(``2 gamma_16``); ``k0 = ax(R0_/xi R0^T)`` has the same sensitivity to ``l0_/xi`` and
``|l0_/xi| / |l0|`` times it to ``l0``; the compliance ``R0 C R0^T`` (9 terms) moves by
``9 max|C| (2 |dR0| + 2 gamma_16)``, ``max|C|`` at most the trace of the compliance (``C``
is positive definite, the trace invariant).  ``k0_/xi`` is a central difference over
``+-d = 1e-4 / |l0_/xi|`` of ``k0`` (:func:`sliders.lines.rigid.curvature_rate`): to the
first order it moves with ``k0``'s sensitivity times ``|l0_/xi| / |l0|``, and the rounding
of its two ends, ``2 gamma_16 |k0|`` each, is divided by ``2 d``.

With smearing, the load transfer is the kernel form's integral compiled
(:func:`sliders.lines.batched_kernel.smeared_transfer`): the same rule on the same pieces by
other operations, compared with the reference's (the form) on the structure's dofs within the
roundoff bound of :meth:`Bounds.smeared`, and exactly zero on the other dofs it lists.
"""

import numpy as np
import pytest
from test_chain import SECTION, chain_of_three
from test_pointwise import nodal_matrix

from fvbeam import Beam, Section, Structure, formulation, straight
from fvbeam.elements import evaluation_points
from fvbeam.mesh import arc
from fvbeam.pointwise import CUBIC, TIE, cantilever_flexibility_reference, cubic_reference
from sliders.lines import batched_reference as reference
from sliders.lines.batched import ChainStack
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import frame_and_curvature

EPS = np.finfo(float).eps
#: Twice ``gamma_16`` (module docstring).
ROUNDING = 2 * 16 * EPS / (1 - 16 * EPS)
#: Bound on the sum of the magnitudes of the monomial terms of a shape function or one of
#: its derivatives in ``X`` on [0, 1] (module docstring).
TERMS = 12


def moved_chains(npe, offsets):
    """``chain_of_three`` with every beam translated by each offset (shared stiffness)."""
    chain, _ = chain_of_three(npe)
    chains = []
    for offset in offsets:
        beams = [beam.translated(offset) for beam in chain.beams]
        structure = Structure(beams, ties=[(0, "end", 1, "start"), (1, "end", 2, "start")])
        chains.append(BeamChain(structure, [0, 1, 2]))
    return chains


def close(a, b):
    np.testing.assert_allclose(a, b, rtol=0, atol=16 * EPS * max(np.abs(b).max(), 1.0))


#: Test chains: each beam's formulation and shape, one after the other.
CHAINS = {
    "fv2": [("fv2", "straight")],
    "galerkin-p1, fv2 arc": [("galerkin-p1", "straight"), ("fv2", "arc")],
    "fv3, galerkin-p2 arc, fv3": [("fv3", "straight"), ("galerkin-p2", "arc"), ("fv3", "straight")],
    "galerkin-p2 arc, galerkin-p2": [("galerkin-p2", "arc"), ("galerkin-p2", "straight")],
    "fv3 arc": [("fv3", "arc")],
    "cubic": [("cubic", "straight")],
    "cubic, galerkin-p1 arc, cubic arc": [
        ("cubic", "straight"),
        ("galerkin-p1", "arc"),
        ("cubic", "arc"),
    ],
}


def random_beams(spec, rng):
    """Beams joined end to start, one per ``(formulation, shape)`` of ``spec``: straight
    (random direction and length) or a circular arc in a plane z = const (random radius,
    start angle and sweep), 1 to 3 elements each, each with its own random section."""
    npe = formulation(spec[0][0]).nodes_per_element
    start, beams = rng.uniform(-1, 1, 3), []
    for name, shape in spec:
        n = int(rng.integers(1, 4))
        if shape == "straight":
            direction = rng.standard_normal(3)
            end = start + rng.uniform(0.3, 1.0) * direction / np.linalg.norm(direction)
            mesh = straight(start, end, n, npe)
        else:
            radius, a0 = rng.uniform(0.5, 2.0), rng.uniform(0, 2 * np.pi)
            a1 = a0 + rng.choice([-1, 1]) * rng.uniform(0.5, 2.0)
            center = start - radius * np.array([np.cos(a0), np.sin(a0), 0.0])
            mesh = arc(center, radius, a0, a1, n, npe)
            end = mesh.points[n]
        section = Section.diagonal(*(10 ** rng.uniform(-1, 1, 6)))
        beams.append(Beam(mesh, section, name))
        start = end
    return beams


def chained(beams):
    """The beams tied end to start, as one chain."""
    ties = [(i, "end", i + 1, "start") for i in range(len(beams) - 1)]
    return BeamChain(Structure(beams, ties=ties), list(range(len(beams))))


def special_abscissae(chain, rng):
    """The chain's ends, beam junctions, element vertices, mid nodes and evaluation points
    (on them, within half of :data:`TIE` of them, 1e-9 of the element off them), and random
    abscissae."""
    npe = chain.beams[0].mesh.nodes_per_element
    xi = [0.0, chain.length, *chain.offsets[1:-1]]
    for offset, beam in zip(chain.offsets[:-1], chain.beams, strict=True):
        mesh = beam.mesh
        for start, h in zip(offset + mesh.vertex_s[:-1], mesh.element_length, strict=True):
            xi += [start, start + 0.5 * h] if npe == 3 else [start]
            xi += [
                start + (p + d) * h
                for p in evaluation_points(npe)
                for d in (0.0, 0.5 * TIE, -0.5 * TIE, 1e-9, -1e-9)
            ]
    return np.concatenate([xi, rng.uniform(0, chain.length, 8)])


def stack_of(spec, seed):
    """A stack of translated copies of random beams, one member per special abscissa, each
    on its own random shift and nodal displacements (rotations included, 1e-2)."""
    rng = np.random.default_rng(seed)
    beams = random_beams(spec, rng)
    xi = special_abscissae(chained(beams), rng)
    shifts = rng.uniform(-3, 3, (len(xi), 3))
    chains = [chained([beam.translated(s) for beam in beams]) for s in shifts]
    q = 1e-2 * rng.standard_normal((len(xi), chains[0].structure.n_dofs))
    return ChainStack(chains), chains, xi, q


class Bounds:
    """The kernel-against-reference tolerances of one member at ``xi`` (module docstring)."""

    def __init__(self, chain, xi, q):
        self.chain, self.xi = chain, xi
        _, element, X = reference.locate(chain, xi)
        elements = reference.recovered_tangent(chain, element, X)[0]
        self.h = min(reference.element_length(chain, e) for e in elements)
        line = reference.interpolation(chain, xi)
        self.npe, self.m = chain.beams[0].mesh.nodes_per_element, line.N.shape[1]
        positions = np.concatenate([reference.element_nodes(chain, e)[1] for e in elements])
        self.Y0 = max(np.abs(positions).max(), 1.0)
        self.Y = self.Y0 + np.abs(q[line.tangent_dofs]).max()
        self.l0, self.l0_xi = (np.linalg.norm(v) for v in line.reference[1:])
        # the frames come from the reference line, a Lagrange interpolation of the nodes
        self.cubic: list = []
        self.dR = 10 * self.line(1, self.Y0) / (self.l0 * self._n(element)) + ROUNDING
        self.cubic = [cubic_scales(chain, e, X) for e in elements if is_cubic(chain, e)]

    def _n(self, element):
        """``|n|``, ``n = up - (up . t) t`` of the element's frame (module docstring)."""
        k, _ = reference.beam_element(self.chain, element)
        up, t = self.chain.beams[k].mesh.up, reference.element_frame(self.chain, element)[:, 0]
        return np.linalg.norm(up - (up @ t) * t)

    def coefficient(self, k):
        """A coefficient of order ``k`` in ``1 / h``: Lagrange, and on cubic elements the
        bound of ``tests/test_pointwise.py`` (doubled by the recovered tangent's
        combination) plus the frames' difference on both sides, ``2 dR`` of the scale."""
        lagrange = ROUNDING * 2 * TERMS / self.h**k
        cubic = [
            2 * (128 * kappa + 64) * EPS * 4 * scale[k] + 2 * self.dR * scale[k]
            for kappa, scale in self.cubic
        ]
        return max([lagrange, *cubic])

    def line(self, k, Y):
        """A line quantity of order ``k`` on nodes of coordinates (and dofs) up to ``Y``: the
        reference line's sum over the nodes read and the displacement's over the dofs."""
        return self.coefficient(k) * 3 * (3 * self.npe + self.m) * Y

    def smeared(self, smearing, kernel):
        """Bounds on ``|G - G_form|`` and ``|G' - G'_form|`` (entrywise) of the compiled smeared
        transfer (:func:`sliders.lines.batched_kernel.smeared_transfer`) against the kernel
        form (:meth:`sliders.lines.chain.BeamChain.transfer`), and on each one's distance
        from the exact integral.

        Both integrate ``A = int K(s - xi) H(s) ds`` and ``m = int K ds`` over the chain by
        the same 3-point Gauss rule on the same pieces (split at the vertices, the fv
        evaluation points and the kernel's breaks ``xi``, ``xi -+ smearing``), computed by
        different operations, and ``G = A / m``.  Sizes, with ``h_min``, ``h_max`` the
        chain's element lengths: ``|H| <= Hmax = max(1, 8 h_max)`` (``|N_a| <= 1`` on
        [0, 1]; an fv moment arm is at most the arc length, ``max |x_/X| <= 8`` times the
        spread of the nodes, which is at most ``h``), ``|H'| <= H1 = max(8, 4 / h_min)``
        (``|dN/dX| <= 4``), ``K <= K0`` and ``|K'| <= K1`` (box ``1 / (2 smearing)`` and 0,
        hat ``1 / smearing`` and ``1 / smearing^2``), ``int K = m <= 1`` (``m`` in closed
        form), and ``int |K'|`` plus the box's edge jumps at most ``S = 2 / smearing``.

        * Placement: every Gauss point and offset comes out of at most 16 roundings of
          abscissae at most ``L`` (the chain's length) in either computation, so the two
          read a point at most ``delta = 8 EPS L`` apart.  Where the integrand ``f`` is
          smooth that moves it by ``delta max|f'|``, ``2 smearing delta max|f'|`` over the
          rule (weights sum to at most ``2 smearing``).  A piece shorter than ``9 delta``
          (the rule's points lie 0.11 of a piece inside it) beside a jump of ``f`` may be
          read on the other side: at most ``2 max|f|`` over at most ``10 delta`` in each,
          ``40 delta max|f|`` per such jump (``J`` of them: jumps with another break, or
          the same one twice, within ``9 delta``).  Jumps of ``K H``: fv evaluation
          points, the box's edges; of ``K' H``: fv evaluation points, the hat's peak and
          edges.
        * Sums: each of ``n`` terms (``n`` Gauss points and the box's two edge terms)
          carries at most 8 roundings (the weight scaled by ``h`` and back, products), so
          each sum is within ``gamma_(n+8)`` of its magnitudes' sum (Higham, Sec. 3.1), for
          both ``2 gamma_(n+8)``; the Galerkin test functions (scikit-fem's against
          :func:`fvbeam.pointwise.shape_at`) differ by ``128 EPS`` per value
          (``tests/test_pointwise.py``), the fv ones are the same compiled code.

        Then ``|dA| <= 2 gamma Hmax + 128 EPS Hmax + 2 smearing delta (K1 Hmax + K0 H1) +
        40 delta J K0 Hmax``, ``|dm|`` the same with ``H = 1``, ``H1 = 0``, and
        ``|dG| <= (|dA| + Hmax |dm|) / m + EPS Hmax``.  For the derivative
        ``A' = -int K' H - sum jump H(xi + r)``: ``|dA'| <= 2 gamma S Hmax + S (128 EPS
        Hmax + delta H1) + 40 delta J' K1 Hmax`` (``K'`` is constant on each piece, the
        edge terms are the same compiled point transfer at the same abscissae), ``|dm'|``
        the same with ``H = 1``, ``H1 = 0``, and ``G' = (A' - G m') / m`` within
        ``(|dA'| + |dG| S + Hmax |dm'|) / m`` plus its own 3 roundings of
        ``(S Hmax + Hmax S) / m``.
        """
        chain, xi = self.chain, self.xi
        lengths = np.concatenate([beam.mesh.element_length for beam in chain.beams])
        H0, H1 = max(1.0, 8 * lengths.max()), max(8.0, 4 / lengths.min())
        box = kernel == "box"
        K0, K1 = (1 / (2 * smearing), 0.0) if box else (1 / smearing, 1 / smearing**2)
        S, L = 2 / smearing, chain.length
        delta = 8 * EPS * L
        lo, hi = max(xi - smearing, 0.0), min(xi + smearing, L)
        vertices, jumps = [], []
        for offset, beam in zip(chain.offsets[:-1], chain.beams, strict=True):
            mesh = beam.mesh
            vertices.append(offset + mesh.vertex_s)
            if beam.formulation.rigid_test:
                p = evaluation_points(mesh.nodes_per_element)
                jumps.append(offset + mesh.abscissae(np.arange(mesh.n_elements)[:, None], p))
        jumps = np.concatenate([j.ravel() for j in jumps] + [np.zeros(0)])
        peak = xi + smearing * np.array([-1.0, 0.0, 1.0])
        candidates = np.concatenate([*vertices, jumps, peak, [lo, hi]])
        candidates = candidates[(candidates >= lo) & (candidates <= hi)]
        n = 3 * (len(np.unique(candidates)) - 1) + 2
        gamma = (n + 8) * EPS / (1 - (n + 8) * EPS)

        def near(points):
            """How many of ``points`` on the kernel's part have another break (or the same
            one twice) within ``9 delta``; the part's ends, where the kernel's edge is cut,
            count once."""
            inside = points[(points >= lo) & (points <= hi)]
            ends = np.isin(inside, [lo, hi])
            return sum(
                np.sum(np.abs(candidates - p) < 9 * delta) >= 2 + end
                for p, end in zip(inside, ends, strict=True)
            )

        J = near(np.concatenate([jumps, peak[[0, 2]]]) if box else jumps)
        J1 = 0 if box else near(np.concatenate([jumps, peak]))
        mass = kernel_mass(kernel, smearing, lo - xi, hi - xi)
        dA = 2 * gamma * H0 + 128 * EPS * H0 + 2 * smearing * delta * (K1 * H0 + K0 * H1)
        dA += 40 * delta * J * K0 * H0
        dm = 2 * gamma + 2 * smearing * delta * K1 + 40 * delta * J * K0
        tol_G = (dA + H0 * dm) / mass + EPS * H0
        dA1 = 2 * gamma * S * H0 + S * (128 * EPS * H0 + delta * H1) + 40 * delta * J1 * K1 * H0
        dm1 = 2 * gamma * S + 40 * delta * J1 * K1
        tol_dG = (dA1 + tol_G * S + H0 * dm1) / mass + 3 * EPS * 2 * S * H0 / mass
        return tol_G, tol_dG

    def frame(self, rotation, up):
        """``R0``, ``k0`` and ``k0_/xi`` of the reference's ``rotation``."""
        t = rotation.R0[:, 0]
        n = np.linalg.norm(up - (up @ t) * t)
        dl, dl_xi = self.line(1, self.Y0), self.line(2, self.Y0)
        dR = 10 * dl / (self.l0 * n) + ROUNDING
        k0 = np.linalg.norm(rotation.k0)
        dk = 10 * (dl_xi + self.l0_xi / self.l0 * dl) / (self.l0 * n) + ROUNDING * k0
        dk_xi = dk * self.l0_xi / self.l0 + ROUNDING * k0 * self.l0_xi * 1e4
        return {"R0": dR, "k0": dk, "k0_xi": dk_xi}

    def flex(self, beam, kink):
        """``flex`` and ``flex_xi``: Lagrange ``kink C``, ``C = R0 C_s R0^T`` (9 terms), which
        moves by ``9 max|C| (2 |dR0| + 2 gamma_16)``, ``max|C|`` at most the trace of the
        compliance (positive definite, the trace invariant), and ``kink`` by its coefficient
        bound; cubic: the bound of ``tests/test_pointwise.py`` on the compliance plus the
        frames' ``2 dR``."""
        if beam.formulation.kind == CUBIC:
            kappa, scale = contact_scale(self.chain, self.xi)
            tol = (192 * kappa + 64) * EPS * 4 * scale + 2 * self.dR * scale
            return tol, 4 * tol / self.h
        C = np.trace(np.linalg.inv(beam.section.stiffness)[3:, 3:])
        dC = 9 * C * (2 * self.dR + ROUNDING)
        return (
            self.coefficient(-1) * C + abs(kink[0]) * dC,
            self.coefficient(0) * C + abs(kink[1]) * dC,
        )


def is_cubic(chain, element):
    """Whether the chain's ``element`` is a cubic one."""
    k, _ = reference.beam_element(chain, element)
    return chain.beams[k].formulation.kind == CUBIC


def cubic_scales(chain, element, X):
    """The condition of the reference's nodal systems of a cubic ``element`` (both bending
    planes) and the largest entry of its functions' derivatives of each order (0 to 3) at
    ``X`` and its ends (the points the recovered tangent reads)."""
    k, _ = reference.beam_element(chain, element)
    beam, h = chain.beams[k], reference.element_length(chain, element)
    stiffness, frame = np.diag(beam.section.stiffness), reference.element_frame(chain, element)
    kappa = max(
        np.linalg.cond(nodal_matrix(h, EJ, GA))
        for EJ, GA in ((stiffness[5], stiffness[1]), (stiffness[4], stiffness[2]))
    )
    scale = [
        max(np.abs(cubic_reference(frame, stiffness, h, x, order)).max() for x in (X, 0.0, 1.0))
        for order in range(4)
    ]
    return kappa, scale


def contact_scale(chain, xi):
    """The condition of ``S = F_a + F_b`` of the cubic element holding ``xi`` and ``max|S|``
    (``tests/test_pointwise.py``)."""
    k, element, X = reference.locate(chain, xi)
    beam, h = chain.beams[k], reference.element_length(chain, element)
    stiffness = np.diag(beam.section.stiffness)
    S = cantilever_flexibility_reference(X * h, 1.0, stiffness)
    S = S + cantilever_flexibility_reference(h - X * h, -1.0, stiffness)
    return np.linalg.cond(S), np.abs(S).max()


def kernel_mass(kernel, smearing, a, b):
    """``int K(r) dr`` over ``[a, b]`` inside ``[-smearing, smearing]``, in closed form: the
    box's length over ``2 smearing``; the hat's difference of its distribution function
    ``(r + smearing)^2 / (2 smearing^2)`` (``r <= 0``), ``1 - (smearing - r)^2 / (2
    smearing^2)`` (``r >= 0``)."""
    if kernel == "box":
        return (b - a) / (2 * smearing)

    def F(r):
        if r <= 0:
            return (r + smearing) ** 2 / (2 * smearing**2)
        return 1 - (smearing - r) ** 2 / (2 * smearing**2)

    return F(b) - F(a)


def scattered(dofs, G, n):
    """A transfer's rows ``G`` (k, 6) summed onto the ``n`` dofs of the structure."""
    out = np.zeros((n, 6))
    np.add.at(out, dofs, G)
    return out


def agree(kernel, mine, atol):
    np.testing.assert_allclose(kernel, mine, rtol=0, atol=atol)


def check_member(state, interp, rotation, transfer, b, chain, xi, q, smearing, kernel):
    """Member ``b`` of the stack's answers against the reference at ``xi`` on ``q``."""
    mine = reference.line_state(chain, xi, q, smearing, kernel)
    bound = Bounds(chain, xi, q)
    line = mine.interpolation
    for answer in (state.interpolation.member(b), interp.member(b)):
        for name in ("dofs", "tangent_dofs"):
            np.testing.assert_array_equal(getattr(answer, name), getattr(line, name))
        for k in range(3):
            agree(answer.reference[k], line.reference[k], bound.line(k, bound.Y0))
        for k in range(2):
            agree(
                answer.tangent_reference[k], line.tangent_reference[k], bound.line(k + 1, bound.Y0)
            )
        for name, k in (("N", 0), ("dN", 1), ("d2N", 2), ("T", 1), ("T_xi", 2)):
            agree(getattr(answer, name), getattr(line, name), bound.coefficient(k))
    geometry = interp.member(b).geometry(q), interp.member(b).tangent(q)
    for k, name in enumerate(("x", "l", "l_xi")):
        for value in (getattr(state, name)[b], geometry[0][k]):
            agree(value, getattr(mine, name), bound.line(k, bound.Y))
    agree(state.l_xixi[b], mine.l_xixi, bound.line(3, bound.Y))
    for k, name in ((1, "tangent"), (2, "tangent_xi")):
        for value in (getattr(state, name)[b], geometry[1][k - 1]):
            agree(value, getattr(mine, name), bound.line(k, bound.Y))
    k_beam, _, _ = reference.locate(chain, xi)
    beam = chain.beams[k_beam]
    assert state.contact.shape[1:] == mine.contact.shape
    if mine.contact.size:
        tol, tol_xi = bound.flex(beam, None) if beam.formulation.kind == CUBIC else (0.0, 0.0)
        agree(state.contact[b], mine.contact, tol)
        agree(state.contact_xi[b], mine.contact_xi, tol_xi)
    for dofs, G, dG in ((state.load_dofs, state.G, state.dG), transfer):
        if smearing == 0:
            np.testing.assert_array_equal(dofs[b], mine.load_dofs)
            agree(G[b], mine.G, max(bound.line(0, bound.Y0), bound.coefficient(0)))
            agree(dG[b], mine.dG, max(bound.line(1, bound.Y0), bound.coefficient(1)))
        else:  # the kernel form's integral, compiled: on the chain's dofs, zero elsewhere
            tol_G, tol_dG = bound.smeared(smearing, kernel)
            assert np.isin(mine.load_dofs, dofs[b]).all()
            extra = ~np.isin(dofs[b], mine.load_dofs)
            assert not np.any(G[b, extra]) and not np.any(dG[b, extra])
            n = chain.structure.n_dofs
            for compiled, form, tol in ((G, mine.G, tol_G), (dG, mine.dG, tol_dG)):
                agree(scattered(dofs[b], compiled[b], n), scattered(mine.load_dofs, form, n), tol)
    frame = bound.frame(mine.rotation, beam.mesh.up)
    kink = kink_of(chain, xi)
    tol_flex, tol_flex_xi = bound.flex(beam, kink)
    for answer in (state.rotation.member(b), rotation.member(b)):
        np.testing.assert_array_equal(answer.dofs, mine.rotation.dofs)
        for name, k in (("W", 0), ("W_xi", 1), ("W_xixi", 2)):
            agree(getattr(answer, name), getattr(mine.rotation, name), bound.coefficient(k))
        agree(answer.flex, mine.rotation.flex, tol_flex)
        agree(answer.flex_xi, mine.rotation.flex_xi, tol_flex_xi)
        for name, atol in frame.items():
            agree(getattr(answer, name), getattr(mine.rotation, name), atol)


def kink_of(chain, xi):
    """The kink correction ``kappa`` and ``kappa_/xi`` of a Lagrange element at ``xi``
    (:func:`sliders.lines.batched_reference.rotation`: its ``flex`` over ``C``)."""
    k, _, _ = reference.locate(chain, xi)
    rotation = reference.rotation(chain, xi)
    C = rotation.R0 @ np.linalg.inv(chain.beams[k].section.stiffness)[3:, 3:] @ rotation.R0.T
    return rotation.flex[0, 0] / C[0, 0], rotation.flex_xi[0, 0] / C[0, 0]


@pytest.mark.parametrize("name", CHAINS)
@pytest.mark.parametrize("smearing,kernel", [(0.0, "box"), (0.03, "box"), (0.03, "hat")])
def test_line_state_equals_the_reference(name, smearing, kernel):
    """Every member of a stack (random shifts, displacements and abscissae, the special
    ones included) against :func:`sliders.lines.batched_reference.line_state` of its chain:
    the kernel's line state, interpolation, rotation and transfer, and the deformed line
    and tangent of its interpolation (:func:`sliders.lines.batched_kernel.weighted_current`),
    to the derived roundoff bounds (module docstring); the location exactly."""
    stack, chains, xi, q = stack_of(CHAINS[name], seed=list(CHAINS).index(name))
    state = stack.line_state(xi, q, rotation=True, smearing=smearing, kernel=kernel)
    interp, rotation = stack.interpolation(xi), stack.rotation(xi)
    transfer = stack.transfer(xi, smearing, kernel)
    located = stack.locate(xi)
    for b, (chain, x) in enumerate(zip(chains, xi, strict=True)):
        assert tuple(v[b] for v in located) == reference.locate(chain, x)
        check_member(state, interp, rotation, transfer, b, chain, x, q[b], smearing, kernel)


def test_joined_stack_equals_the_reference():
    """A joined stack (chains of one structure on different beams, so different dof maps:
    :meth:`ChainStack.joined`) against the reference of each member's chain."""
    rng = np.random.default_rng(7)
    beams = random_beams(CHAINS["fv3, galerkin-p2 arc, fv3"], rng)
    moved = [beam.translated((0.5, -2.0, 1.0)) for beam in beams]
    n = len(beams)
    ties = [(i, "end", i + 1, "start") for i in range(n - 1)]
    ties += [(n + i, "end", n + i + 1, "start") for i in range(n - 1)]
    structure = Structure(beams + moved, ties=ties)
    first, second = BeamChain(structure, range(n)), BeamChain(structure, range(n, 2 * n))
    xi_first = special_abscissae(first, rng)
    xi = np.concatenate([xi_first, xi_first[::-1]])
    chains = [first] * len(xi_first) + [second] * len(xi_first)
    stack = ChainStack.joined(
        [ChainStack([first] * len(xi_first)), ChainStack([second] * len(xi_first))]
    )
    q = 1e-2 * rng.standard_normal((len(xi), structure.n_dofs))
    state = stack.line_state(xi, q, rotation=True)
    interp, rotation, transfer = stack.interpolation(xi), stack.rotation(xi), stack.transfer(xi)
    for b, (chain, x) in enumerate(zip(chains, xi, strict=True)):
        check_member(state, interp, rotation, transfer, b, chain, x, q[b], 0.0, "box")


@pytest.mark.parametrize("name", CHAINS)
def test_projection_is_a_foot_of_the_perpendicular(name):
    """The stacked projection of points 1e-4 off the deformed lines (along a normal at a
    random ``xi0`` inside an element) is a foot of the perpendicular on the reference's
    line: ``g = (x - p) . l = 0`` there (a stationary point of the distance, not
    necessarily ``xi0``: Newton starts from the nearest node, which may lie on the next
    element).  Newton stops on a step below ``s = 1e-14 max(L, 1)``, so ``|g| <= g' s``
    with ``g' = |l|^2 + l_/xi . (x - p)``; evaluating ``g`` on the reference adds the line
    bounds of ``x`` and ``l`` times ``|l|`` and ``|x - p|``."""
    stack, chains, _, q = stack_of(CHAINS[name], seed=list(CHAINS).index(name))
    rng = np.random.default_rng(5)
    xi0, points = np.empty(len(chains)), np.empty((len(chains), 3))
    for b, chain in enumerate(chains):
        k = int(rng.integers(len(chain.beams)))
        mesh = chain.beams[k].mesh
        e = int(rng.integers(mesh.n_elements))
        xi0[b] = chain.offsets[k] + mesh.abscissae(e, rng.uniform(0.05, 0.95))
        mine = reference.line_state(chain, xi0[b], q[b])
        normal = np.cross(mine.l, rng.standard_normal(3))
        points[b] = mine.x + 1e-4 * normal / np.linalg.norm(normal)
    projected = stack.project(points, q)
    for b, (chain, xi) in enumerate(zip(chains, projected, strict=True)):
        assert 0 < xi < chain.length
        mine, bound = reference.line_state(chain, xi, q[b]), Bounds(chain, xi, q[b])
        gap = mine.x - points[b]
        slope = mine.l @ mine.l + abs(mine.l_xi @ gap)
        tol = slope * 1e-14 * max(chain.length, 1.0) + (
            bound.line(0, bound.Y) * np.linalg.norm(mine.l)
            + bound.line(1, bound.Y) * np.linalg.norm(gap)
        )
        assert abs(gap @ mine.l) <= tol


def test_members_must_share_the_topology():
    (a,) = moved_chains(3, [(0, 0, 0)])
    other = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")])
    with pytest.raises(ValueError, match="member 1 of the batch differs"):
        ChainStack([a, BeamChain(other, [0])])
    mixed = Structure(
        [
            Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3"),
            Beam(straight((1, 0, 0), (2, 0, 0), 2, 2), SECTION, "fv2"),
        ],
        ties=[(0, "end", 1, "start")],
    )
    with pytest.raises(ValueError, match="same number of nodes per element"):
        ChainStack([BeamChain(mixed, [0, 1])])


def test_subset_answers_as_a_stack_of_its_members():
    """A subset (no topology checks again) gives the stack of its members' answers."""
    chains = moved_chains(3, [(0, 0, 0), (0.3, -0.2, 0.1), (5.0, 1.0, -2.0), (0.01, 0, 0)])
    pick = np.array([3, 1])
    xi = np.array([0.2, chains[0].offsets[1]])
    part, direct = ChainStack(chains).subset(pick), ChainStack([chains[b] for b in pick])
    for mine, theirs in (
        (part.interpolation(xi), direct.interpolation(xi)),
        (part.rotation(xi), direct.rotation(xi)),
    ):
        for name in mine.__dataclass_fields__:
            np.testing.assert_array_equal(getattr(mine, name), getattr(theirs, name))
    for mine, theirs in zip(part.transfer(xi), direct.transfer(xi), strict=True):
        np.testing.assert_array_equal(mine, theirs)


@pytest.mark.parametrize("npe", [2, 3])
def test_stored_frames_of_straight_elements_equal_the_frames_at_xi(npe):
    """On straight elements the rotation reads the frame and compliance stored per element
    (:meth:`ChainStack.element_frames`): they equal the frame of the reference line at each
    ``xi`` (:func:`sliders.lines.rigid.frame_and_curvature`) and ``R0 C R0^T``, to the roundoff of
    the direction (``16 eps``, as above), with ``k0 = k0_/xi = 0``; a translated stack keeps
    its template's frames, which equal those of the moved chains built afresh (to the same
    roundoff: the moved node positions carry that of the shift)."""
    chains = moved_chains(npe, [(0, 0, 0), (0.3, -0.2, 0.1), (5.0, 1.0, -2.0)])
    stack = ChainStack(chains)
    xi = np.array([0.1, chains[0].offsets[1] + 0.05, chains[0].length - 0.01])
    rotation = stack.rotation(xi)
    assert stack.element_frames().straight.all()
    _, element, X = stack.locate(xi)
    l0, l0_xi = stack._reference_line(element, X)
    R0 = frame_and_curvature(l0, l0_xi, stack.up[element])[0]
    close(rotation.R0, R0)
    assert not np.any(rotation.k0) and not np.any(rotation.k0_xi)
    beam = np.searchsorted(stack.first_element, element, side="right") - 1
    stored = stack.element_frames().compliance[np.arange(len(xi)), element]
    close(stored, R0 @ np.stack(stack.compliance)[beam] @ np.swapaxes(R0, 1, 2))
    shifts = np.array([[(0.3, -0.2, 0.1)] * 3, [(5.0, 1.0, -2.0)] * 3])
    moved = ChainStack(chains[:1]).translated(shifts)
    for mine, theirs in zip(
        moved.element_frames(), ChainStack(chains[1:]).element_frames(), strict=True
    ):
        close(mine, theirs)


def test_curved_elements_take_the_frame_at_xi():
    """On an arc the elements are not straight: the rotation's frame is the reference line's
    at ``xi``, with the curvature ``1 / radius`` about the axis (``e3`` the arc's normal
    ``up``): the fv3 interpolation of the arc is exact to ``O(h^3)`` in the curvature,
    ``(pi/4 / 8)^2 / radius`` with eight elements on a quarter circle, less than 1 %."""
    beam = Beam(arc((0, 0, 0), 2.0, 0.0, np.pi / 2, 8, 3), SECTION, "fv3")
    stack = ChainStack([BeamChain(Structure([beam]), [0])])
    rotation = stack.rotation(np.array([1.3]))
    assert not stack.element_frames().straight.any()
    assert np.linalg.norm(rotation.k0[0]) == pytest.approx(0.5, rel=0.01)
