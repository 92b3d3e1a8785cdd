"""Exact structures (fvbeam.exact_structure): the beams of a Structure gathered on its global
dofs, solved by fvbeam.exact_statics.solve_static.

Tolerances:

* gathering: a cantilever cut in two beams tied at the cut has the same discrete equations as
  the whole beam; the tied node's entries are sums of the same two terms added in another
  order, so they agree to a few ``eps`` (64) times the sum of the terms' magnitudes
  (:meth:`~fvbeam.exact_beam.ExactBeam.residual_floor`, and the tangent's largest entry);
* solves: two converged states of the same equations differ by at most the sum of their next
  Newton corrections (computed) and the rounding of the positions' sums, ``16 eps`` per
  element length.
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from fvbeam import Beam, Section, Structure, straight
from fvbeam.body import RigidBody
from fvbeam.exact_beam import ExactState
from fvbeam.exact_statics import solve_static
from fvbeam.exact_structure import ExactStructure

EPS = np.finfo(float).eps
SECTION = Section.diagonal(EA=1e4, GAy=1e4, GAz=1e4, GJ=1.0, EJy=1.0, EJz=2.0)


def whole_and_halves(name: str, n: int = 8) -> tuple[ExactStructure, ExactStructure]:
    """A unit cantilever along x of ``n`` elements, and the same cut at its middle into two
    beams of ``n / 2`` elements tied there."""
    npe = 3 if name in ("fv3", "galerkin-p2") else 2
    whole = Beam(straight((0, 0, 0), (1, 0, 0), n, npe, name="W"), SECTION, name)
    a = Beam(straight((0, 0, 0), (0.5, 0, 0), n // 2, npe, name="A"), SECTION, name)
    b = Beam(straight((0.5, 0, 0), (1, 0, 0), n // 2, npe, name="B"), SECTION, name)
    halves = Structure([a, b], [("A.end", "B.start")])
    return ExactStructure(Structure([whole])), ExactStructure(halves)


def halves_order(whole: ExactStructure, halves: ExactStructure) -> np.ndarray:
    """The halves' global node of each of the whole beam's nodes (by position)."""
    X = halves.reference().x
    return np.array([int(np.argmin(np.linalg.norm(X - p, axis=1))) for p in whole.reference().x])


def random_state(exact: ExactStructure, seed: int) -> ExactState:
    """Displacements of 0.1 and nodal rotations of about a radian."""
    rng = np.random.default_rng(seed)
    n = exact.n_dofs // 6
    dq = np.hstack([0.1 * rng.standard_normal((n, 3)), rng.standard_normal((n, 3))])
    return exact.reference().updated(dq.ravel())


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p2"])
def test_tied_halves_gather_the_whole_beams_equations(name):
    whole, halves = whole_and_halves(name)
    order = halves_order(whole, halves)
    state = random_state(whole, 3)
    # the same configuration on the halves' numbering
    x = np.empty_like(halves.reference().x)
    R = np.empty((len(x), 3, 3))
    x[order], R[order] = state.x, state.R
    split = ExactState(x, R)
    dofs = (6 * order[:, None] + np.arange(6)).ravel()
    r_whole, r_split = whole.residual(state), halves.residual(split)[dofs]
    floor = whole.residual_floor(state)
    np.testing.assert_array_less(np.abs(r_split - r_whole), 64 * EPS * floor + 1e-300)
    np.testing.assert_allclose(halves.residual_floor(split)[dofs], floor, rtol=64 * EPS)
    K_whole = whole.tangent(state).toarray()
    K_split = halves.tangent(split).toarray()[np.ix_(dofs, dofs)]
    np.testing.assert_allclose(K_split, K_whole, rtol=0, atol=64 * EPS * np.abs(K_whole).max())
    free = np.arange(6, whole.n_dofs)
    kept = whole.tangent(state, keep=free).toarray()
    np.testing.assert_array_equal(kept, K_whole[np.ix_(free, free)])


def next_correction(exact: ExactStructure, state: ExactState, load, fixed) -> float:
    """The largest entry of the Newton correction from ``state``."""
    free = np.setdiff1d(np.arange(exact.n_dofs), fixed)
    K = exact.tangent(state, keep=free)
    return float(np.abs(spla.spsolve(K, (load - exact.residual(state))[free])).max())


def test_tied_halves_solve_to_the_whole_beams_large_deflection():
    """A tip force of P L^2 / EJ = 5 about the weak axis and a twisting couple, a 3-D
    large deflection: the tied halves reach the whole beam's equilibrium."""
    whole, halves = whole_and_halves("fv3")
    order = halves_order(whole, halves)
    results = []
    for exact in (whole, halves):
        tip = int(np.argmin(np.linalg.norm(exact.reference().x - [1, 0, 0], axis=1)))
        root = int(np.argmin(np.linalg.norm(exact.reference().x, axis=1)))
        load = np.zeros(exact.n_dofs)
        load[6 * tip : 6 * tip + 6] = [0, 0, 5.0, 0.5, 0, 0]
        fixed = 6 * root + np.arange(6)
        result = solve_static(exact, load, fixed)
        results.append((result.state, next_correction(exact, result.state, load, fixed)))
    (s_whole, c_whole), (s_split, c_split) = results
    assert np.abs(s_whole.x[-1] - [1, 0, 0]).max() > 0.3  # a large deflection
    bound = c_whole + c_split + 16 * EPS * 8
    np.testing.assert_allclose(s_split.x[order], s_whole.x, rtol=0, atol=bound)
    np.testing.assert_allclose(s_split.R[order], s_whole.R, rtol=0, atol=bound)


def test_a_tied_body_is_its_beam_node_and_a_free_one_a_node_of_its_own():
    """Bodies are nodes on the structure's numbering: one tied to a beam's end is that node
    (its rows the beam's alone), one tied to nothing a node at its position with zero rows
    (a body has no internal forces)."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 2, name="A"), SECTION, "fv2")
    hub = RigidBody("hub", position=np.array([1.0, 0.0, 0.0]), mass=1.0)
    free = RigidBody("free", position=np.array([3.0, 2.0, 1.0]), mass=1.0)
    structure = Structure([beam], [("A.end", "hub")], [hub, free])
    exact = ExactStructure(structure)
    whole = ExactStructure(Structure([beam]))
    assert exact.n_dofs == whole.n_dofs + 6
    np.testing.assert_array_equal(exact.body_nodes, [2, 3])
    state = exact.reference()
    np.testing.assert_array_equal(state.x[3], [3.0, 2.0, 1.0])
    turned = state.updated(np.linspace(-0.2, 0.3, exact.n_dofs))
    r, K = exact.residual(turned), exact.tangent(turned).toarray()
    part = ExactState(turned.x[:3], turned.R[:3])
    np.testing.assert_array_equal(r[:18], whole.residual(part))
    np.testing.assert_array_equal(r[18:], 0.0)
    np.testing.assert_array_equal(K[:18, :18], whole.tangent(part).toarray())
    np.testing.assert_array_equal(K[18:], 0.0)


def test_a_tie_of_nodes_apart_is_refused_naming_the_node():
    a = Beam(straight((0, 0, 0), (1, 0, 0), 2, 2, name="A"), SECTION, "fv2")
    b = Beam(straight((1, 0.1, 0), (2, 0.1, 0), 2, 2, name="B"), SECTION, "fv2")
    with pytest.raises(ValueError, match="node 'A.end' is tied to a node 0.1 away"):
        ExactStructure(Structure([a, b], [("A.end", "B.start")]))
