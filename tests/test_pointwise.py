"""The compiled test functions at a point (fvbeam/pointwise.py) against their numpy reference
and against the scikit-fem kernel form (``Beam.kernel_transfer``).

Tolerances are roundoff bounds, ``EPS`` the machine epsilon:

* kernel and reference evaluate the same polynomials in different orders (expanded against
  Horner on the Lagrange products, whose coefficients are exact binary fractions).  Each
  shape-function value or derivative is a sum of at most 3 terms of magnitude at most 8 (the
  P2 coefficients: 1, 3, 2 / 1, 4 / 4, 8), each with at most 4 roundings, so the two differ by
  at most ``3 * 8 * 4 EPS < 128 EPS``.  A block entry ``N_b x_b`` summed over at most 3 nodes
  then differs by at most ``128 EPS`` times the sum of ``|x_b|`` (``|N_b| <= 1`` on [0, 1]) plus
  the roundings of the sums, ``256 EPS`` times ``scale = 1 + sum |x_b|`` in all (divided by
  ``h`` for the derivative).  Indicators are exact (0, 1/2 or 1) and compared exactly.
* the cubic element (eq. T11): the kernel writes its functions' polynomials out
  (:func:`fvbeam.pointwise.cubic_plane_at`), the reference solves for them as the homogeneous
  solutions taking unit nodal values (a 4x4 system ``A c = e_i`` per bending plane).  A
  backward-stable solve is within ``4 n kappa(A) EPS`` of the exact coefficients (Higham,
  Accuracy and Stability of Numerical Algorithms, Thm. 9.4 with ``n = 4`` and the growth
  factor of partial pivoting on a 4x4 below 8), which is at most ``128 kappa(A) EPS``; either
  side's evaluation and rotation to global axes adds ``2 gamma_16`` of the magnitudes (at
  most 16 operations per entry), so the two differ by at most ``(128 kappa(A) + 64) EPS``
  times the largest magnitude of the entries' terms, taken as ``4`` times the largest entry
  (at most four terms of a sum, each at most the largest of the unrotated values, rotated
  by an orthogonal frame).  The compliance (eq. T13): the kernel's 2x2 closed form against
  the reference's 6x6 solve of ``S = F_a + F_b`` (the same bound with ``kappa(S)`` and
  ``n = 6``, on terms at most ``|S|``: the compliance lies below ``F_a`` and ``F_b``), and its
  derivative against a complex step (no difference taken; its own error ``delta^2``
  negligible), whose terms are at most ``3 |S| / h`` (cubics in ``a`` and ``b``).
* the form and the compiled transfer integrated by an independent Gauss rule: both rules are
  exact for the piecewise polynomial integrand (degree at most 4 on every piece), so they
  differ by the roundings of their sums: each point's value (``256 EPS`` of the largest
  entry, as above) plus one rounding per term of each sum, ``(256 + n) EPS max|H|`` for ``n``
  terms in the two sums together; the normalisation by the kernel's mass adds a few roundings.
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, arc, straight
from fvbeam.elements import evaluation_points, influence_regions
from fvbeam.geometry import section_frames
from fvbeam.pointwise import (
    CUBIC,
    FINITE_VOLUME,
    LAGRANGE,
    TIE,
    Element,
    Shapes,
    cantilever_flexibility_reference,
    cubic_flex_many,
    cubic_flex_reference,
    cubic_many,
    cubic_reference,
    indicator_at,
    indicator_reference,
    rigid_blocks_at,
    rigid_blocks_reference,
    shape_at,
    shape_blocks_at,
    shape_blocks_reference,
    shape_reference,
    transfer_at,
    transfer_reference,
)
from fvbeam.smearing import density

EPS = np.finfo(float).eps
SECTION = Section.diagonal(EA=10.0, GAy=2.0, GAz=3.0, GJ=1.0, EJy=1.5, EJz=0.8)
FORMULATIONS = [("fv2", 2), ("fv3", 3), ("galerkin-p1", 2), ("galerkin-p2", 3), ("cubic", 2)]


def reference_points(npe: int, rng: np.random.Generator) -> np.ndarray:
    """Random reference coordinates, the element ends, the evaluation points exactly, within
    the tie distance of them (half and half) and just outside it."""
    p = evaluation_points(npe)
    near = np.concatenate([p + d for d in (-0.5 * TIE, 0.5 * TIE, -3 * TIE, 3 * TIE)])
    return np.concatenate([rng.random(40), [0.0, 1.0, 0.5], p, near])


def curved_element(npe: int, rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """Random node positions (the mid node off the chord) and a random element length."""
    nodes = rng.uniform(-2.0, 2.0, (npe, 3))
    return nodes, float(rng.uniform(0.5, 2.0))


@pytest.mark.parametrize("npe", [2, 3])
def test_kernels_equal_their_numpy_reference(npe):
    rng = np.random.default_rng(11 + npe)
    regions = influence_regions(npe)
    buffers = [np.empty(npe) for _ in range(5)]
    N, dN, d2N, chi, dchi = buffers
    shapes = Shapes(*buffers)
    G, dG = np.empty((6 * npe, 6)), np.empty((6 * npe, 6))
    for X in reference_points(npe, rng):
        shape_at(X, npe, N, dN, d2N)
        for kernel, reference in zip((N, dN, d2N), shape_reference(X, npe), strict=True):
            np.testing.assert_allclose(kernel, reference, rtol=0, atol=128 * EPS)
        indicator_at(X, regions, chi)
        assert np.array_equal(chi, indicator_reference(X, regions))

        nodes, h = curved_element(npe, rng)
        scale = 1 + np.abs(nodes).sum(axis=0).max()
        tol = 256 * EPS * scale
        chi_r, dchi_r = rng.random(npe), rng.standard_normal(npe)
        rigid_blocks_at(nodes, h, N, dN, chi_r, dchi_r, G, dG)
        G_ref, dG_ref = rigid_blocks_reference(nodes, h, N, dN, chi_r, dchi_r)
        np.testing.assert_allclose(G, G_ref, rtol=0, atol=tol)
        np.testing.assert_allclose(dG, dG_ref, rtol=0, atol=tol * (1 + np.abs(dchi_r).max()) / h)
        shape_blocks_at(h, N, dN, G, dG)
        for kernel, reference in zip((G, dG), shape_blocks_reference(h, N, dN), strict=True):
            np.testing.assert_array_equal(kernel, reference)

        frame, stiffness = np.eye(3), np.ones(6)  # read by the cubic element only
        for kind in (FINITE_VOLUME, LAGRANGE):
            transfer_at(Element(kind, regions, nodes, frame, stiffness, h), X, shapes, G, dG)
            G_ref, dG_ref = transfer_reference(kind, regions, nodes, frame, stiffness, h, X)
            np.testing.assert_allclose(G, G_ref, rtol=0, atol=tol)
            np.testing.assert_allclose(dG, dG_ref, rtol=0, atol=tol / h)


def random_cubic_element(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, float]:
    """A random section frame, a section whose six stiffnesses span two decades each way
    (shear parameters ``12 EJ / (GA h^2)`` from about 1e-5 to 1e5) and a random length."""
    frame = section_frames(rng.standard_normal(3), rng.standard_normal(3))
    return frame, 10 ** rng.uniform(-2, 2, 6), float(10 ** rng.uniform(-1, 0.5))


def test_cubic_kernels_equal_their_numpy_reference():
    """The cubic element's functions and their first three derivatives (:func:`cubic_many`,
    :func:`transfer_at`) and its compliance with its derivative (:func:`cubic_flex_many`)
    against the references at random and special points of random elements, within the
    bounds of the module docstring."""
    rng = np.random.default_rng(3)
    regions, nodes = influence_regions(2), np.zeros((2, 3))
    shapes = Shapes(*(np.empty(2) for _ in range(5)))
    G, dG = np.empty((12, 6)), np.empty((12, 6))
    for _ in range(20):
        frame, stiffness, h = random_cubic_element(rng)
        kappa = max(
            np.linalg.cond(nodal_matrix(h, EJ, GA))
            for EJ, GA in ((stiffness[5], stiffness[1]), (stiffness[4], stiffness[2]))
        )
        for X in np.concatenate([[0.0, 1.0, 0.5], rng.random(5)]):
            values = []
            for order in range(4):
                mine = cubic_many(frame[None], stiffness, np.array([h]), np.array([X]), order)[0]
                theirs = cubic_reference(frame, stiffness, h, X, order)
                tol = (128 * kappa + 64) * EPS * 4 * np.abs(theirs).max()
                np.testing.assert_allclose(mine, theirs, rtol=0, atol=tol)
                values.append(mine)
            transfer_at(Element(CUBIC, regions, nodes, frame, stiffness, h), X, shapes, G, dG)
            np.testing.assert_array_equal(G, values[0])
            np.testing.assert_array_equal(dG, values[1])
            flex, flex_xi = cubic_flex_many(frame[None], stiffness, np.array([h]), np.array([X]))
            a = X * h
            S = cantilever_flexibility_reference(a, 1.0, stiffness) + (
                cantilever_flexibility_reference(h - a, -1.0, stiffness)
            )
            # the compliance is at most min(F_a, F_b) <= S (positive definite order); its
            # a-derivative's terms at most |S| / h over the cubics' three powers of a and b
            tol = (192 * np.linalg.cond(S) + 64) * EPS * 4 * np.abs(S).max()
            theirs = cubic_flex_reference(frame, stiffness, h, X)
            np.testing.assert_allclose(flex[0], theirs[0], rtol=0, atol=tol)
            np.testing.assert_allclose(flex_xi[0], theirs[1], rtol=0, atol=4 * tol / h)


def nodal_matrix(h: float, EJ: float, GA: float) -> np.ndarray:
    """The system the reference solves (:func:`fvbeam.pointwise.cubic_plane_reference`): the
    nodal values ``v(0), psi(0), v(h), psi(h)`` (rows) of the homogeneous solutions
    ``v = 1, s, s^2 / 2, s^3 / 3 - 2 EJ s / GA`` with ``psi = 0, 1, s, s^2`` (columns)."""
    deflection = (
        lambda s: 1.0,
        lambda s: s,
        lambda s: s * s / 2,
        lambda s: s**3 / 3 - 2 * EJ * s / GA,
    )
    rotation = (lambda s: 0.0, lambda s: 1.0, lambda s: s, lambda s: s * s)
    return np.array(
        [[v(0.0), p(0.0), v(h), p(h)] for v, p in zip(deflection, rotation, strict=True)]
    ).T


def test_the_reference_reads_the_half_and_half_rule():
    """On an evaluation point the two neighbouring regions share the point half and half; the
    element ends belong whole to their node; indicators are a partition of unity."""
    for npe in (2, 3):
        regions = influence_regions(npe)
        for p in evaluation_points(npe):
            chi = indicator_reference(p, regions)
            assert sorted(chi) == [0.0] * (npe - 2) + [0.5, 0.5]
        for X in (0.0, 1.0, 0.3, 0.7):
            assert indicator_reference(X, regions).sum() == 1.0
        np.testing.assert_array_equal(indicator_reference(0.0, regions)[:2], [1.0, 0.0])


def beams(name: str, npe: int) -> list[Beam]:
    """A straight oblique beam and a curved one (quarter circle), four elements each."""
    return [
        Beam(straight((0.5, -1.0, 2.0), (1.5, 1.0, 1.5), 4, npe), SECTION, name),
        Beam(arc((0.2, 0.1, -0.3), 1.3, 0.1, 1.7, 4, npe), SECTION, name),
    ]


def compiled_integral(
    beam: Beam, xi: float, smearing: float, kernel: str
) -> tuple[np.ndarray, int]:
    """The kernel average of the compiled transfer (n_dofs, 6), by a 4-point Gauss rule (exact
    to degree 7) on pieces split at every vertex, every evaluation point and the kernel's
    peak and ends, built here independently of the beam's own rule; and its number of
    points."""
    mesh = beam.mesh
    p = evaluation_points(mesh.nodes_per_element)
    inner = mesh.vertex_s[:-1, None] + mesh.element_length[:, None] * p
    lo, hi = max(xi - smearing, 0.0), min(xi + smearing, mesh.length)
    breaks = np.concatenate([mesh.vertex_s, inner.ravel(), [xi - smearing, xi, xi + smearing]])
    breaks = np.unique(breaks[(breaks >= lo) & (breaks <= hi)])
    x, w = np.polynomial.legendre.leggauss(4)
    a, h = breaks[:-1, None], np.diff(breaks)[:, None]
    s, w = (a + h * (x + 1) / 2).ravel(), (h * w / 2).ravel()
    w = w * density(s - xi, smearing, kernel)
    dofs, H, _ = beam.transfer(s)
    out = np.zeros((beam.n_dofs, 6))
    np.add.at(out, dofs, w[:, None, None] * H)
    return out / w.sum(), len(s)


@pytest.mark.parametrize("name,npe", FORMULATIONS)
@pytest.mark.parametrize("curved", [False, True])
@pytest.mark.parametrize("kernel", ["dirac", "box", "hat"])
def test_compiled_transfer_equals_the_kernel_form(name, npe, curved, kernel):
    """At random abscissae (and on vertices, evaluation points and the ends) and random
    half-widths from a tenth of an element to one and a half: without smearing the compiled
    transfer equals the form's Dirac limit (the one-point rule); with smearing the compiled
    transfer integrated against the kernel equals the form."""
    beam = beams(name, npe)[curved]
    mesh = beam.mesh
    rng = np.random.default_rng([npe, curved, ["dirac", "box", "hat"].index(kernel), len(name)])
    p = evaluation_points(npe)
    special = np.concatenate([mesh.vertex_s, mesh.vertex_s[1] + mesh.element_length[1] * p])
    h = mesh.element_length.min()
    for xi in np.concatenate([rng.uniform(0, mesh.length, 12), special]):
        form = np.zeros((beam.n_dofs, 6))
        if kernel == "dirac":
            dofs, (H,), (mass,) = beam.kernel_transfer(float(xi))
            assert mass == pytest.approx(1.0, abs=4 * EPS)
            form[dofs] = H / mass
            compiled = np.zeros((beam.n_dofs, 6))
            d, G, _ = beam.transfer(xi)
            compiled[d[0]] = G[0]
            terms = 2
        else:
            smearing = float(rng.uniform(0.1, 1.5) * h)
            dofs, (H,), (mass,) = beam.kernel_transfer(
                float(xi), smearing, (lambda r, e=smearing: density(r, e, kernel),)
            )
            form[dofs] = H / mass
            compiled, n = compiled_integral(beam, float(xi), smearing, kernel)
            terms = 2 * n  # the form's rule has fewer points than this one
        scale = np.abs(compiled).max()
        np.testing.assert_allclose(form, compiled, rtol=0, atol=(256 + terms + 8) * EPS * scale)


def test_a_kernel_off_its_window_names_the_beam():
    beam = beams("fv3", 3)[0]
    with pytest.raises(ValueError, match="does not reach"):
        beam.kernel_transfer(0.5, 0.1, (np.ones_like,), (1.0, 1.5))
