"""Large-deflection statics of geometrically exact fv beams (fvbeam.exact_statics) against
closed forms and published solutions, with measured convergence orders.

Tolerances:

* discretisation: the error of the finer of two meshes (``n`` and ``2n`` elements) of a
  scheme of order ``p`` is estimated by Richardson, ``|u_n - u_2n| / (2^p - 1)``, with ``p``
  measured here (2 for fv2, 4 for fv3); the assertions allow twice the estimate (its own
  higher-order terms);
* model: the closed forms are of inextensible, unshearable rods; the beams here have
  ``EA = GA = 1e8 EJ / L^2``, whose flexibility moves the tip by about ``P L / GA`` and
  ``P L / EA``;
* round-off: a converged state is off by the next Newton correction (computed) plus the
  rounding of the positions' sums, ``16 eps`` per element length.
"""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from fvbeam import rotations
from fvbeam.elastica import rolled_cantilever, tip_loaded_cantilever, twisted_cantilever
from fvbeam.exact_beam import ExactBeam
from fvbeam.exact_statics import solve_static
from studies.bench_exact import BEND_PUBLISHED, bend, nodes_per_element, rod, solve_tip

EPS = np.finfo(float).eps
#: Mattiasson, IJNME 17 (1981) 145, Table I: tip shortening u/L and deflection v/L of the
#: elastica at P L^2 / EJ = 1, 2, 5, 10, five decimals.
MATTIASSON = {
    1.0: (0.05643, 0.30172),
    2.0: (0.16064, 0.49346),
    5.0: (0.38763, 0.71379),
    10.0: (0.55500, 0.81061),
}


def next_correction(exact: ExactBeam, result, load) -> float:
    """The largest entry of the Newton correction from the converged state."""
    fixed = exact.beam.node_dofs("start")
    free = np.setdiff1d(np.arange(exact.n_dofs), fixed)
    K = exact.tangent(result.state)[free][:, free].tocsc()
    return float(np.abs(spla.spsolve(K, (load - exact.residual(result.state))[free])).max())


def elastica_tip(exact: ExactBeam, load: float) -> np.ndarray:
    """(shortening, deflection, rotation) of the rod's tip under the tip force ``load``."""
    result, _ = solve_tip(exact, force=(0.0, -load, 0.0))
    d = exact.displacements(result.state)[exact.beam.node_index("end")]
    return np.array([-d[0], -d[1], -d[5]])


def order(e1: np.ndarray, e2: np.ndarray) -> float:
    """Observed order of a halving of the element size."""
    return float(np.log2(np.abs(e1).max() / np.abs(e2).max()))


def test_elastica_closed_form_matches_mattiasson_table():
    """The shortening is ``1 - sqrt(2 sin theta0 / load)``: the table checks the tip rotation
    ``theta0`` through it."""
    for load, row in MATTIASSON.items():
        tip = tip_loaded_cantilever(load)
        got = (tip.shortening, tip.deflection)
        np.testing.assert_allclose(got, row, atol=0.5e-5)  # half a unit of the 5th decimal


@pytest.mark.parametrize("load", list(MATTIASSON))
def test_elastica_fv3(load):
    """The tip-loaded elastica at P L^2 / EJ = 1, 2, 5, 10 with 4 and 8 fv3 elements."""
    tip = tip_loaded_cantilever(load)
    exact = np.array([tip.shortening, tip.deflection, tip.rotation])
    coarse, fine = elastica_tip(rod("fv3", 4), load), elastica_tip(rod("fv3", 8), load)
    richardson = np.abs(coarse - fine) / 15
    model = 2 * load / 1e8  # P L / GA + P L / EA
    assert np.all(np.abs(fine - exact) <= 2 * richardson + model)


@pytest.mark.parametrize(
    "name,expected,meshes",
    [
        ("fv2", 2, (8, 16, 32)),
        ("fv3", 4, (2, 4, 8)),
        ("galerkin-p1", 2, (8, 16, 32)),
        ("galerkin-p2", 4, (2, 4, 8)),
    ],
)
def test_elastica_convergence_order(name, expected, meshes):
    """At P L^2 / EJ = 10 the error falls as h^2 (fv2, galerkin-p1) and h^4 (fv3,
    galerkin-p2; reduced integration), measured on two successive halvings."""
    tip = tip_loaded_cantilever(10.0)
    exact = np.array([tip.shortening, tip.deflection, tip.rotation])
    errors = [elastica_tip(rod(name, n), 10.0) - exact for n in meshes]
    orders = [order(errors[0], errors[1]), order(errors[1], errors[2])]
    assert [round(p) for p in orders] == [expected, expected]
    assert np.abs(errors[-1]).max() < 1e-3  # the finest mesh resolves the tip to 0.1 %


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
def test_roll_up(name):
    """An end couple 2 pi EJ / L rolls the rod into a circle: the tip back at the root, the
    middle node at the top, (0, L / pi), converging at the scheme's order (2 with 2-node
    elements, 4 with 3-node ones)."""
    errors = []
    for n in (4, 8):
        exact = rod(name, n, slenderness=1e4)
        result, load = solve_tip(exact, moment=(0.0, 0.0, 2 * np.pi))
        x = result.state.x
        tip_bound = next_correction(exact, result, load) + 16 * EPS * n
        np.testing.assert_allclose(x[n] - [0.0, 0.0, 0.0], 0.0, atol=tip_bound)
        errors.append(x[n // 2] - [0.0, 1 / np.pi, 0.0])
    np.testing.assert_allclose(rolled_cantilever(2 * np.pi), 0.0, atol=16 * EPS)
    assert round(order(errors[0], errors[1])) == (2 if nodes_per_element(name) == 2 else 4)


@pytest.mark.parametrize(
    "name,expected", [("fv2", 2), ("fv3", 4), ("galerkin-p1", 2), ("galerkin-p2", 4)]
)
def test_twisted_rod_bending_torsion_coupling(name, expected):
    """A dead end couple oblique to the rod (GJ = EJ / 2): a helix, the section turning about
    the couple and twisting about itself (bending and torsion coupled), against the closed
    form (tip position and rotation), at the scheme's order."""
    M = np.array([2.0, 1.0, 1.5])
    tip, R = twisted_cantilever(M, 1.0, 1.0, 0.5)
    values = []
    for n in (4, 8):
        exact = rod(name, n, slenderness=1e4, GJ=0.5)
        result, _ = solve_tip(exact, moment=M)
        end = exact.beam.node_index("end")
        turn = rotations.log_map(R.T @ result.state.R[end])
        values.append(np.concatenate([result.state.x[end] - tip, turn]))
    richardson = np.abs(values[0] - values[1]) / (2**expected - 1)
    assert np.all(np.abs(values[1]) <= 2 * richardson)
    assert round(order(values[0], values[1])) == expected


def test_bathe_bolourchi_bend():
    """The 45-degree bend (R = 100, E = 1e7, G = E / 2, unit square section, tip force 600 out
    of plane), 8 fv3 elements, against the published tip positions
    (``studies.bench_exact.BEND_PUBLISHED``: Bathe and Bolourchi's and BeamDyn's, given to
    0.1, and a converged spectral element's).  The published solutions differ from one
    another by up to 0.32 (their own discretisations); each coordinate of the tip must lie
    within their range, widened by half a unit of the coarsest's last digit (0.05)."""
    exact = bend("fv3", 8)
    result, _ = solve_tip(exact, force=(0.0, 0.0, 600.0))
    tip = result.state.x[exact.beam.node_index("end")]
    published = np.array(list(BEND_PUBLISHED.values()))
    assert np.all(tip >= published.min(axis=0) - 0.05)
    assert np.all(tip <= published.max(axis=0) + 0.05)


def linear_limit_slopes(exact: ExactBeam, loads, load_at) -> np.ndarray:
    """The slopes of ``log |exact - linear|`` against ``log P`` over the ``loads`` ``P``,
    the start clamped, ``load_at(P)`` giving the exact path's load and the linear one's
    vector."""
    beam = exact.beam
    fixed = beam.node_dofs("start")
    free = np.setdiff1d(np.arange(beam.n_dofs), fixed)
    K = beam.stiffness[free][:, free].tocsc()
    differences = []
    for P in loads:
        load, f = load_at(P)
        linear = np.zeros(beam.n_dofs)
        linear[free] = spla.spsolve(K, f[free])
        result = solve_static(exact, load, fixed)
        differences.append(np.abs(exact.displacements(result.state).ravel() - linear).max())
    return np.diff(np.log(differences)) / np.diff(np.log(loads))


@pytest.mark.parametrize("name", ["fv2", "fv3"])
def test_linear_limit_is_second_order(name):
    """At small loads the exact solution approaches the linear one with an error of second
    order in the load (the neglected terms are quadratic: the shortening of a deflected
    rod); measured slope on a 3-D load of force and couple."""
    exact = rod(name, 4, slenderness=1e4)

    def load_at(P: float) -> tuple[np.ndarray, np.ndarray]:
        load = exact.beam.nodal_load("end", force=(0.0, P, 0.5 * P), moment=(0.3 * P, 0.0, 0.0))
        return load, load

    slopes = linear_limit_slopes(exact, (1e-3, 2e-3, 4e-3), load_at)
    np.testing.assert_allclose(slopes, 2.0, atol=0.01)  # next term: third order, P ~ 1e-2


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
def test_slender_rod_converges(name):
    """EA L^2 / EJ = 1e8 converges on the residual's round-off floor (no stall, no
    'singular'): the next Newton correction is below that floor, 16 eps EA (the axial
    force's rounding), over the softest stiffness, the tip's 3 EJ / L^3; and the answer is
    the moderately slender rod's within the axial and shear flexibility it drops,
    P L / EA + P L / GA at EA = GA = 1e6."""
    slender, moderate = elastica_tip(rod(name, 10), 10.0), elastica_tip(rod(name, 10, 1e6), 10.0)
    assert np.all(np.abs(slender - moderate) <= 2 * 10.0 / 1e6)
    exact = rod(name, 10)
    result, load = solve_tip(exact, force=(0.0, -10.0, 0.0))
    assert next_correction(exact, result, load) <= 16 * EPS * 1e8 / 3


@pytest.mark.parametrize("name", ["fv2", "fv3"])
def test_internal_forces_balance_the_load_in_the_current_configuration(name):
    """The region balances hold on the deformed beam, on any mesh: at every evaluation point
    of the elastica the internal force is the tip load and the couple its moment about the
    point, ``(x_tip - x_p) x P``, to the solver's round-off floor (summed over the nodes the
    balances chain); in the section frame the load splits into axial force and shear by the
    section's current angle."""
    exact = rod(name, 4)
    P = np.array([0.0, -10.0, 0.0])
    result, _ = solve_tip(exact, force=P)
    forces = exact.internal_forces(result.state)
    pts = exact.points(result.state)
    tip = result.state.x[exact.beam.node_index("end")]
    scale = 16 * EPS * exact.residual_floor(result.state).max() * exact.beam.mesh.n_nodes
    np.testing.assert_allclose(forces.force_global, np.broadcast_to(P, pts.x.shape), atol=scale)
    np.testing.assert_allclose(forces.moment_global, np.cross(tip - pts.x, P), atol=scale)
    tangent = pts.Lambda[:, :, 0]  # the section's axis t, turned
    np.testing.assert_allclose(forces.force[:, 0], tangent @ P, atol=scale)
    np.testing.assert_allclose(np.linalg.norm(forces.force, axis=1), 10.0, atol=scale)
