"""ChainStack: the queries of many chains of one topology at once equal each chain's own.

The members are one chain of three beams (corners, a junction, fv2/fv3) moved rigidly by
different offsets, queried at different abscissae (inside elements, on a beam junction, on a
vertex, at the ends).  A member's stacked result and its chain's single-point query (the
``B = 1`` case) evaluate the same expressions on the same numbers, in vectorised order:
they agree to a few units of roundoff of the largest entry, ``16 eps max|value|``.
"""

import numpy as np
import pytest

from fvbeam import Beam, Structure, straight
from sliders.chain import BeamChain
from sliders.stack import ChainStack
from test_chain import SECTION, chain_of_three

EPS = np.finfo(float).eps


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


@pytest.mark.parametrize("npe", [2, 3])
@pytest.mark.parametrize("smearing", [0.0, 0.03])
def test_stacked_queries_equal_single_queries(npe, smearing):
    offsets = [(0, 0, 0), (0.3, -0.2, 0.1), (5.0, 1.0, -2.0), (0.01, 0, 0), (-1, -1, -1)]
    chains = moved_chains(npe, offsets)
    xi = np.array([0.0, 0.2, chains[0].offsets[1], chains[0].offsets[2], chains[0].length])
    stack = ChainStack(chains)
    rng = np.random.default_rng(4)
    q = rng.standard_normal((len(chains), chains[0].structure.n_dofs)) * 1e-2
    interp, rotation = stack.interpolation(xi), stack.rotation(xi)
    dofs, G, dG = stack.transfer(xi, smearing)
    geometry, tangent = interp.geometry(q), interp.tangent(q)
    points = np.array([c.geometry(x, qq)[0] for c, x, qq in zip(chains, xi, q)]) + 1e-3
    projected = stack.project(points, q)
    for b, (chain, x) in enumerate(zip(chains, xi)):
        one = chain.interpolation(x)
        for name in one.__dataclass_fields__:
            close(getattr(interp, name)[b], getattr(one, name))
        for mine, theirs in zip(geometry, one.geometry(q[b])):
            close(mine[b], theirs)
        for mine, theirs in zip(tangent, one.tangent(q[b])):
            close(mine[b], theirs)
        single = chain.rotation(x)
        for name in single.__dataclass_fields__:
            close(getattr(rotation, name)[b], getattr(single, name))
        d, g, dg = chain.transfer(x, smearing)
        assert np.array_equal(dofs[b, :len(d)], d)
        close(G[b, :len(d)], g)
        close(dG[b, :len(d)], dg)
        assert not np.any(G[b, len(d):]) and not np.any(dG[b, len(d):])
        assert projected[b] == pytest.approx(chain.project(points[b], q[b]),
                                             abs=1e-12 * chain.length)


def test_members_must_share_the_topology():
    a, = moved_chains(3, [(0, 0, 0)])
    other = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")])
    with pytest.raises(ValueError, match="member 1 of the batch differs"):
        ChainStack([a, BeamChain(other, [0])])
    mixed = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3"),
                       Beam(straight((1, 0, 0), (2, 0, 0), 2, 2), SECTION, "fv2")],
                      ties=[(0, "end", 1, "start")])
    with pytest.raises(ValueError, match="same number of nodes per element"):
        ChainStack([BeamChain(mixed, [0, 1])])


def test_subset_answers_as_a_stack_of_its_members():
    """A subset (no topology checks again) gives the stack of its members' answers."""
    chains = moved_chains(3, [(0, 0, 0), (0.3, -0.2, 0.1), (5.0, 1.0, -2.0), (0.01, 0, 0)])
    pick = np.array([3, 1])
    xi = np.array([0.2, chains[0].offsets[1]])
    part, direct = ChainStack(chains).subset(pick), ChainStack([chains[b] for b in pick])
    for mine, theirs in ((part.interpolation(xi), direct.interpolation(xi)),
                         (part.rotation(xi), direct.rotation(xi))):
        for name in mine.__dataclass_fields__:
            np.testing.assert_array_equal(getattr(mine, name), getattr(theirs, name))
    for mine, theirs in zip(part.transfer(xi), direct.transfer(xi)):
        np.testing.assert_array_equal(mine, theirs)
