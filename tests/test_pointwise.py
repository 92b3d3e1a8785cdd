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
* the form and the compiled transfer integrated by an independent Gauss rule: both rules are
  exact for the piecewise polynomial integrand (degree at most 3 on every piece), so they
  differ by the roundings of their sums: each point's value (``256 EPS`` of the largest
  entry, as above) plus one rounding per term of each sum, ``(256 + n) EPS max|H|`` for ``n``
  terms in the two sums together; the normalisation by the kernel's mass adds a few roundings.
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, arc, straight
from fvbeam.elements import evaluation_points, influence_regions
from fvbeam.pointwise import (
    TIE,
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
FORMULATIONS = [("fv2", 2), ("fv3", 3), ("galerkin-p1", 2), ("galerkin-p2", 3)]


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

        for fv in (True, False):
            transfer_at(fv, regions, nodes, h, X, N, dN, d2N, chi, dchi, G, dG)
            G_ref, dG_ref = transfer_reference(fv, regions, nodes, h, X)
            np.testing.assert_allclose(G, G_ref, rtol=0, atol=tol)
            np.testing.assert_allclose(dG, dG_ref, rtol=0, atol=tol / h)


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
