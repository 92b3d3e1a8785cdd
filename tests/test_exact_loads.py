"""Dead loads between nodes on geometrically exact beams (fvbeam.exact_loads): the linear
load vector in the reference configuration, the load stiffness against finite differences,
the heavy cantilever against its elastica, a point load between nodes against the same load
at a node, and the linear limit.

Tolerances:

* round-off: sums of a few hundred terms of size ``|F| |x|``, ``64 eps`` relative;
* finite differences: central, step ``e = 1e-6``; the load is affine in the positions (no
  truncation error there), quadratic-plus in a body's rotation (``e^2 |F| |c|``); rounding
  ``eps |f| / e`` (about ``2e-10`` relative); ``1e-8`` relative bounds both;
* discretisation: as ``tests/test_exact_statics.py``, twice the Richardson estimate of the
  finer mesh at the scheme's order (2 for fv2 and galerkin-p1, 4 for fv3 and galerkin-p2),
  plus the model's share (``EA = GA = 1e8 EJ / L^2``: ``w L^2 / GA`` and ``w L^2 / EA``).
"""

import numpy as np
import pytest
from test_exact_statics import linear_limit_slopes

from fvbeam import Beam, RigidBody, Section, rotations
from fvbeam.elastica import heavy_cantilever
from fvbeam.exact_beam import ExactBeam, ExactState
from fvbeam.exact_loads import BodyForce, DeadLoad, LoadPoints, distributed, point, weight
from fvbeam.exact_statics import solve_static
from fvbeam.mesh import arc
from studies.bench_exact import nodes_per_element, rod

EPS = np.finfo(float).eps
NAMES = ["fv2", "fv3", "galerkin-p1", "galerkin-p2"]
ORDER = {"fv2": 2, "fv3": 4, "galerkin-p1": 2, "galerkin-p2": 4}


def on_beam(beam: Beam, *parts: LoadPoints, bodies=()) -> DeadLoad:
    """The points ``parts`` on a lone beam (its own node numbering)."""
    nodes = np.arange(beam.mesh.n_nodes)
    return DeadLoad(beam.n_dofs, beams=[(beam, nodes, LoadPoints.join(parts))], bodies=list(bodies))


def curved(name: str, n: int = 3) -> Beam:
    """A quarter circle of radius 1 (a curved beam), mass 2.5 per length."""
    mesh = arc((0.0, 0.0, 0.0), 1.0, 0.0, np.pi / 2, n, nodes_per_element(name))
    section = Section.diagonal(
        EA=10.0, GAy=8.0, GAz=7.0, GJ=2.0, EJy=3.0, EJz=4.0, mass_per_length=2.5
    )
    return Beam(mesh, section, name)


def central_differences(function, state, e: float) -> np.ndarray:
    """``d function / d q`` at ``state`` by central differences of step ``e`` in the spatial
    increments ``[du, dphi]`` of every node (:meth:`ExactState.updated`)."""
    n = 6 * len(state.x)
    columns = []
    for j in range(n):
        dq = np.zeros(n)
        dq[j] = e
        columns.append((function(state.updated(dq)) - function(state.updated(-dq))) / (2 * e))
    return np.column_stack(columns)


def random_state(n: int, rng: np.random.Generator, X: np.ndarray) -> ExactState:
    """Positions ``X`` moved by up to 0.3 and rotations of about a radian."""
    x = X + 0.3 * rng.standard_normal(X.shape)
    return ExactState(x, rotations.exp_map(rng.standard_normal((n, 3))))


@pytest.mark.parametrize("name", NAMES)
def test_reference_configuration_gives_the_linear_load(name):
    """On the reference positions the test functions are the linear beam's: distributed
    loads (constant and varying, force and couple), weight, a point load between nodes and
    smeared ones (box and hat kernels) give the linear load vectors to round-off."""
    beam = curved(name)
    L = beam.mesh.length
    field = lambda xi: np.column_stack([np.sin(xi), xi**2, np.ones_like(xi)])  # noqa: E731
    cases = [
        (distributed(beam, field, (0.1, 0.2, 0.3)), beam.distributed_load(field, (0.1, 0.2, 0.3))),
        (weight(beam, (0.0, 0.0, -9.81)), beam.distributed_load((0.0, 0.0, -2.5 * 9.81))),
        (
            point(beam, 0.37 * L, (1, 2, 3), (4, 5, 6)),
            beam.point_load(0.37 * L, (1, 2, 3), (4, 5, 6)),
        ),
        (
            point(beam, 0.5 * L, (1, -2, 3), smearing=0.2 * L),
            beam.point_load(0.5 * L, (1, -2, 3), smearing=0.2 * L),
        ),
        (
            point(beam, 0.05 * L, (1, 2, -3), (1, 0, 0), 0.1 * L, "hat"),
            beam.point_load(0.05 * L, (1, 2, -3), (1, 0, 0), 0.1 * L, "hat"),
        ),
    ]
    reference = ExactBeam(beam).reference()
    for points, linear in cases:
        got = on_beam(beam, points).vector(reference)
        np.testing.assert_allclose(got, linear, rtol=0, atol=64 * EPS * np.abs(linear).max() * L)


@pytest.mark.parametrize("name", NAMES)
def test_load_stiffness_matches_finite_differences(name):
    """``d vector / d q`` (positions and spatial rotation increments) against central
    differences at a random finite configuration: fv beams' lever arms, Galerkin beams'
    none, and a body's offset weight turning with it."""
    rng = np.random.default_rng(7)
    beam = curved(name)
    n = beam.mesh.n_nodes
    body = BodyForce(1, np.array([0.3, -1.0, 2.0]), np.array([0.2, 0.5, -0.4]))
    load = on_beam(
        beam,
        distributed(beam, (1.0, -2.0, 0.5), (0.3, 0.0, 0.1)),
        point(beam, 0.3, (0.0, 0.0, 5.0)),
        point(beam, 0.9, (2.0, 1.0, 0.0), smearing=0.2, kernel="hat"),
        bodies=[body],
    )
    state = random_state(n, rng, beam.mesh.points)
    S = load.stiffness(state).toarray()
    fd = central_differences(load.vector, state, 1e-6)
    np.testing.assert_allclose(S, fd, rtol=0, atol=1e-8 * np.abs(fd).max())
    body_rows = slice(6 * body.node + 3, 6 * body.node + 6)
    S[body_rows, body_rows] = 0.0  # the body's own block, checked above
    if name.startswith("fv"):  # the lever arms act: moments on positions
        assert np.abs(S).max() > 0.1 * np.abs(fd).max()
    else:  # Galerkin beams: no load stiffness
        assert np.all(S == 0.0)


def heavy_tip(name: str, n: int, load: float) -> np.ndarray:
    """(shortening, deflection, rotation) of the tip of a unit rod clamped at its start
    under the dead uniform load ``load`` per length along -y."""
    exact = rod(name, n)
    beam = exact.beam
    dead = on_beam(beam, distributed(beam, (0.0, -load, 0.0)))
    result = solve_static(exact, dead, beam.node_dofs("start"))
    d = exact.displacements(result.state)[beam.node_index("end")]
    return np.array([-d[0], -d[1], -d[5]])


@pytest.mark.parametrize(
    "name,meshes",
    [
        ("fv2", (8, 16, 32)),
        ("fv3", (4, 8, 16)),
        ("galerkin-p1", (8, 16, 32)),
        ("galerkin-p2", (4, 8, 16)),
    ],
)
def test_heavy_cantilever_against_its_elastica(name, meshes):
    """Self-weight ``w L^3 / EJ = 10`` (the tip turns by a radian) against the elastica
    (:func:`fvbeam.elastica.heavy_cantilever`): the error falls at the scheme's order on two
    halvings, and the finest mesh lies within twice its Richardson estimate."""
    tip = heavy_cantilever(10.0)
    exact = np.array([tip.shortening, tip.deflection, tip.rotation])
    values = [heavy_tip(name, n, 10.0) for n in meshes]
    errors = [v - exact for v in values]
    p = ORDER[name]
    orders = [
        np.log2(np.abs(a).max() / np.abs(b).max())
        for a, b in zip(errors[:-1], errors[1:], strict=True)
    ]
    assert [round(o) for o in orders] == [p, p]
    richardson = np.abs(values[-2] - values[-1]) / (2**p - 1)
    model = 2 * 10.0 / 1e8  # w L^2 / GA + w L^2 / EA
    assert np.all(np.abs(errors[-1]) <= 2 * richardson + model)


def test_heavy_cantilever_elastica_small_load_is_linear():
    """The reference's own check: at ``w L^3 / EJ = 1e-3`` its tip is the linear beam's,
    ``w L^4 / 8 EJ`` and ``w L^3 / 6 EJ``, to the neglected second order (``w^2``)."""
    tip = heavy_cantilever(1e-3)
    np.testing.assert_allclose([tip.deflection, tip.rotation], [1e-3 / 8, 1e-3 / 6], rtol=1e-5)


def tip_under_force_at(exact: ExactBeam, a: float, force, between: bool) -> np.ndarray:
    """(x, y displacement, rotation about z) of the tip of a rod clamped at its start under
    a dead force at ``a``: a point load between nodes, or the nodal load at the node there."""
    beam = exact.beam
    if between:
        load = on_beam(beam, point(beam, a, force))
    else:
        node = int(np.argmin(np.abs(beam.mesh.points[:, 0] - a)))
        assert abs(beam.mesh.points[node, 0] - a) < 1e-15
        load = beam.nodal_load(node, force=force)
    result = solve_static(exact, load, beam.node_dofs("start"))
    d = exact.displacements(result.state)[beam.node_index("end")]
    return np.array([d[0], d[1], d[5]])


@pytest.mark.parametrize("name", NAMES)
def test_point_load_between_nodes_converges_to_the_load_at_a_node_there(name):
    """A dead force ``P = 8 EJ / L^2`` normal to the rod at ``a = 0.3 L``: beyond it the rod
    is straight, so the tip is the tip-loaded elastica of length ``a`` (closed form, at
    ``P a^2 / EJ``) continued straight.  Meshes of 10, 20, 40 elements with a node at ``a``
    (the nodal load) converge to it at the scheme's order; meshes of 4 to 32 elements with
    ``a`` between nodes (the point load through the test functions on the current
    configuration) converge to the same tip: a force inside an element puts a kink (a jump of
    the shear) inside it, which the element's polynomials do not represent, and the force's
    place in its element changes from mesh to mesh, so the errors fall irregularly, at about
    second order (measured over the three halvings 1.5 to 2.9): the 32-element error below
    ``(4 / 32)^1.5`` of the 4-element one."""
    from fvbeam.elastica import tip_loaded_cantilever

    a, P = 0.3, 8.0
    short = tip_loaded_cantilever(P * a * a)
    theta = short.rotation
    closed = np.array(
        [
            a * (1 - short.shortening) + (1 - a) * np.cos(theta) - 1,
            -a * short.deflection - (1 - a) * np.sin(theta),
            -theta,
        ]
    )
    force = (0.0, -P, 0.0)
    at_node = [
        np.abs(tip_under_force_at(rod(name, n), a, force, False) - closed).max()
        for n in (10, 20, 40)
    ]
    orders = np.log2(np.array(at_node[:-1]) / np.array(at_node[1:]))
    assert [round(o) for o in orders] == [ORDER[name]] * 2
    between = [
        np.abs(tip_under_force_at(rod(name, n), a, force, True) - closed).max() for n in (4, 32)
    ]
    assert between[1] <= (4 / 32) ** 1.5 * between[0]


@pytest.mark.parametrize("name", ["fv2", "fv3"])
def test_linear_limit_is_second_order(name):
    """At small loads the exact solution under a distributed load and a point load between
    nodes approaches the linear one (the same loads' linear vectors) at second order in the
    load: measured slope."""
    exact = rod(name, 4, slenderness=1e4)
    beam = exact.beam

    def load_at(P: float) -> tuple[DeadLoad, np.ndarray]:
        q, F = (0.0, P, 0.3 * P), (0.2 * P, 0.0, -P)
        dead = on_beam(beam, distributed(beam, q), point(beam, 0.55, F))
        return dead, beam.distributed_load(q) + beam.point_load(0.55, F)

    slopes = linear_limit_slopes(exact, (1e-3, 2e-3, 4e-3), load_at)
    np.testing.assert_allclose(slopes, 2.0, atol=0.01)  # next term: third order, P ~ 1e-2


def test_body_weight_at_its_centre_turns_with_it():
    """A rigid body's weight at an offset centre of mass: at the reference the linear
    body's weight (``fvbeam.mass.weight``), force and moment about its node; turned by a
    half turn about the vertical, the moment's arm turns with it."""
    g = np.array([0.0, 0.0, -9.81])
    body = RigidBody("b", (0.0, 0.0, 0.0), mass=2.0, centre=(0.5, 0.0, 0.0))
    dead = DeadLoad(6, bodies=[BodyForce(0, body.mass * g, np.asarray(body.centre))])
    reference = ExactState(np.zeros((1, 3)), np.eye(3)[None])
    np.testing.assert_allclose(
        dead.vector(reference), body.mass_matrix() @ np.concatenate([g, np.zeros(3)]), atol=1e-14
    )
    turned = ExactState(np.zeros((1, 3)), rotations.exp_map(np.array([[0.0, 0.0, np.pi]])))
    np.testing.assert_allclose(dead.vector(turned)[3:], [0.0, -9.81, 0.0], atol=1e-14)


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p2"])
def test_a_box_smeared_over_the_whole_beam_is_the_uniform_load(name):
    """A point force ``-10 EJ / L^2`` at ``L / 2`` smeared by the box of half-width ``L / 2``
    is the uniform load ``-10 EJ / L^3`` (the heavy cantilever at ``w L^3 / EJ = 10``): both
    quadratures integrate the lever arms (polynomials of the element's degree) exactly, so
    the two equilibria agree to the solvers' round-off: each converged state is off by its
    next Newton correction (computed, with the load stiffness), plus ``16 eps`` of the unit
    length per element."""
    n = 4
    exact = rod(name, n, slenderness=1e4)
    beam = exact.beam
    fixed = beam.node_dofs("start")
    free = np.setdiff1d(np.arange(beam.n_dofs), fixed)
    tips, bound = [], 16 * EPS * n
    for load in (
        distributed(beam, (0.0, -10.0, 0.0)),
        point(beam, 0.5, (0.0, -10.0, 0.0), smearing=0.5),
    ):
        dead = on_beam(beam, load)
        result = solve_static(exact, dead, fixed)
        state = result.state
        K = (exact.tangent(state) - dead.stiffness(state)).toarray()[np.ix_(free, free)]
        g = (dead.vector(state) - exact.residual(state))[free]
        bound += float(np.abs(np.linalg.solve(K, g)).max())
        tips.append(state.x[beam.node_index("end")])
    np.testing.assert_allclose(tips[0], tips[1], rtol=0, atol=bound)
