"""BeamChain: continuous abscissa over several beams, deformed geometry, junction errors.

Tolerances: positions are sums of a few products of order one (1e-14 absolute); derivatives
against central differences with h = 1e-6 on quadratics carry only roundoff, eps/h ~ 1e-10.
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, Structure, straight
from sliders.lines.chain import BeamChain

SECTION = Section.diagonal(EA=10.0, GAy=2.0, GAz=3.0, GJ=1.0, EJy=1.5, EJz=0.8)


def chain_of_three(npe=3):
    corners = np.array([[0, 0, 0], [0.4, 0.1, 0], [1.0, 0.3, 0.2], [1.5, 0.3, 0.6]], float)
    beams = [
        Beam(straight(a, b, n, npe), SECTION, f"fv{npe}")
        for a, b, n in zip(corners[:-1], corners[1:], (2, 3, 1), strict=True)
    ]
    structure = Structure(beams, ties=[(0, "end", 1, "start"), (1, "end", 2, "start")])
    return BeamChain(structure, [0, 1, 2]), corners


@pytest.mark.parametrize("npe", [2, 3])
def test_undeformed_chain_is_the_polyline_in_arc_length(npe):
    chain, corners = chain_of_three(npe)
    lengths = np.linalg.norm(np.diff(corners, axis=0), axis=1)
    assert chain.length == pytest.approx(lengths.sum(), rel=1e-14)
    q = np.zeros(chain.structure.n_dofs)
    for k, (a, b) in enumerate(zip(corners[:-1], corners[1:], strict=True)):
        for s in (0.1, 0.5, 0.9):
            xi = lengths[:k].sum() + s * lengths[k]
            x, l, l_xi = chain.geometry(xi, q)
            np.testing.assert_allclose(x, a + s * (b - a), atol=1e-14)
            np.testing.assert_allclose(l, (b - a) / lengths[k], atol=1e-14)
            np.testing.assert_allclose(l_xi, 0.0, atol=1e-13)


def test_deformed_chain_is_continuous_at_junctions_and_derivatives_match():
    chain, _ = chain_of_three()
    q = np.random.default_rng(3).standard_normal(chain.structure.n_dofs) * 0.01
    for junction in chain.offsets[1:-1]:
        below = chain.geometry(junction - 1e-13, q)[0]
        above = chain.geometry(junction + 1e-13, q)[0]
        np.testing.assert_allclose(below, above, atol=1e-12)
    h = 1e-6
    for xi in (0.2, 0.61, 1.3):
        x, l, l_xi = chain.geometry(xi, q)
        np.testing.assert_allclose(
            l, (chain.geometry(xi + h, q)[0] - chain.geometry(xi - h, q)[0]) / (2 * h), atol=1e-8
        )
        np.testing.assert_allclose(
            l_xi, (chain.geometry(xi + h, q)[1] - chain.geometry(xi - h, q)[1]) / (2 * h), atol=1e-6
        )


def test_bad_chains_name_the_item():
    chain, _ = chain_of_three()
    with pytest.raises(ValueError, match="outside the chain"):
        chain.geometry(chain.length * 1.01, np.zeros(chain.structure.n_dofs))
    with pytest.raises(ValueError, match="beam 0 does not end where beam 2 starts"):
        BeamChain(chain.structure, [0, 2])
    with pytest.raises(ValueError, match="beam 7"):
        BeamChain(chain.structure, [0, 7])


def chain_load(chain, xi, smearing, kernel, W):
    dofs, G, dG = chain.transfer(xi, smearing, kernel)
    f, df = np.zeros(chain.structure.n_dofs), np.zeros(chain.structure.n_dofs)
    np.add.at(f, dofs, G @ W)
    np.add.at(df, dofs, dG @ W)
    return f, df


@pytest.mark.parametrize("npe", [2, 3])
@pytest.mark.parametrize("smearing,kernel", [(0.0, "box"), (0.03, "box"), (0.03, "hat")])
def test_transfer_derivative_and_continuity_across_junctions(npe, smearing, kernel):
    """d G / d xi against central differences (h = 1e-6 on piecewise polynomials: roundoff
    ~eps/h, 1e-8 bound) at points whose kernel covers beam junctions, evaluation points and
    the chain ends; with smearing the load is continuous across a junction (Lipschitz, slope
    bounded by the derivative), without it the shared junction node makes it continuous too."""
    chain, _ = chain_of_three(npe)
    W = np.array([0.3, -1.0, 0.5, 0.2, 0.1, -0.4])
    h = 1e-6
    for xi in (
        0.01,
        chain.offsets[1] - 0.011,
        chain.offsets[1] + 0.007,
        0.77,
        chain.length - 0.013,
    ):
        _, df = chain_load(chain, xi, smearing, kernel, W)
        fd = (
            chain_load(chain, xi + h, smearing, kernel, W)[0]
            - chain_load(chain, xi - h, smearing, kernel, W)[0]
        ) / (2 * h)
        np.testing.assert_allclose(df, fd, atol=1e-8)
    for junction in chain.offsets[1:-1]:
        below = chain_load(chain, junction - 1e-9, smearing, kernel, W)
        above = chain_load(chain, junction + 1e-9, smearing, kernel, W)
        slope = max(np.abs(below[1]).max(), np.abs(above[1]).max(), 1.0)
        assert np.abs(below[0] - above[0]).max() <= 2e-9 * slope * 10
