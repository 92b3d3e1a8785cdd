"""ChainStack: the queries of many chains of one topology at once equal each chain's own.

The members are one chain of three beams (corners, a junction, fv2/fv3) moved rigidly by
different offsets, queried at different abscissae (inside elements, on a beam junction, on a
vertex, at the ends).  A member's stacked result and its chain's single-point query (the
``B = 1`` case) evaluate the same expressions on the same numbers, in vectorised order:
they agree to a few units of roundoff of the largest entry, ``16 eps max|value|``.
"""

import numpy as np
import pytest
from test_chain import SECTION, chain_of_three

from fvbeam import Beam, Structure, straight
from fvbeam.mesh import arc
from sliders.lines.batched import ChainStack
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import frame_and_curvature

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
    points = np.array([c.geometry(x, qq)[0] for c, x, qq in zip(chains, xi, q, strict=True)]) + 1e-3
    projected = stack.project(points, q)
    for b, (chain, x) in enumerate(zip(chains, xi, strict=True)):
        one = chain.interpolation(x)
        for name in one.__dataclass_fields__:
            close(getattr(interp, name)[b], getattr(one, name))
        for mine, theirs in zip(geometry, one.geometry(q[b]), strict=True):
            close(mine[b], theirs)
        for mine, theirs in zip(tangent, one.tangent(q[b]), strict=True):
            close(mine[b], theirs)
        single = chain.rotation(x)
        for name in single.__dataclass_fields__:
            close(getattr(rotation, name)[b], getattr(single, name))
        d, g, dg = chain.transfer(x, smearing)
        assert np.array_equal(dofs[b, : len(d)], d)
        close(G[b, : len(d)], g)
        close(dG[b, : len(d)], dg)
        assert not np.any(G[b, len(d) :]) and not np.any(dG[b, len(d) :])
        assert projected[b] == pytest.approx(
            chain.project(points[b], q[b]), abs=1e-12 * chain.length
        )


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
    close(rotation.compliance, R0 @ np.stack(stack.compliance)[beam] @ np.swapaxes(R0, 1, 2))
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
