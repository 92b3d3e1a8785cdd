"""Sliders on lines of exact beams (sliders.joints.exact_sliders, sliders.lines.exact_line,
sliders.joints.exact_slider_model) against finite differences and the linear slider.

Tolerances:

* finite differences: central differences of step ``h`` on the manifold (``x + du``,
  ``exp(dphi) R``, ``xi + dxi``, ``y + dy``), their truncation estimated from a second step
  ``2 h`` (``|D(2h) - D(h)| / 3``, Richardson for an ``h^2`` error) and their rounding
  ``2 eps |r| / h`` (``|r|`` the residual's terms, bounded by its round-off floor); the
  assertions allow twice the sum;
* the linear limit: the same rows and derivatives in the reference configuration, evaluated
  by different sums: a few ``eps`` of the entries' sizes (``FLOOR_FACTOR``).
"""

import numpy as np
import pytest
import scipy.linalg

from fvbeam import rotations
from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.exact_beam import ExactBeam, ExactState
from fvbeam.exact_statics import FLOOR_FACTOR, solve_static
from fvbeam.mesh import straight
from fvbeam.section import Section
from fvbeam.structure import Structure
from fvbeam.support import Support
from sliders.joints.exact_model import ExactModel, JointedState
from sliders.joints.exact_slider_model import ExactSlider, SlidingModel, SlidingState
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.statics import SliderStatics
from studies.bench_exact_sliders import bearing, configurational
from tests.test_exact_joints import is_stationary

EPS = np.finfo(float).eps
RNG = np.random.default_rng(2025)
SECTION = Section.diagonal(EA=100.0, GAy=50.0, GAz=40.0, GJ=3.0, EJy=2.0, EJz=1.5)
OFFSET = np.array([0.01, 0.02, -0.01])


def structure(formulation: str, n: int = 3) -> Structure:
    """A rod from the origin along ``x`` (``n`` elements) and a ring at ``x = 0.43``."""
    npe = 2 if formulation in ("fv2", "galerkin-p1") else 3
    rod = Beam(straight([0, 0, 0], [1, 0, 0], n, npe, name="rod"), SECTION, formulation)
    return Structure([rod], (), [RigidBody("ring", [0.43, 0.0, 0.0])])


def random_frame() -> np.ndarray:
    return rotations.exp_map(RNG.uniform(-2, 2, 3))


def sliding(kind: str, formulation: str, smearing: float, frame: np.ndarray) -> SlidingModel:
    model = ExactModel.on(structure(formulation), [])
    slider = ExactSlider(kind, "rod", "ring", OFFSET, frame, smearing)
    return SlidingModel(model, [slider])


def slider_residual(model: SlidingModel, state: SlidingState) -> np.ndarray:
    """The sliders' share of the residual (the model's own taken off)."""
    r = model.residual(state)
    r[: model.model.n_dofs] -= model.model.residual(state.model)
    return r


def slider_part(model: SlidingModel, state: SlidingState) -> tuple[np.ndarray, np.ndarray]:
    """The sliders' share of the residual and the tangent."""
    n = model.model.n_dofs
    r = slider_residual(model, state)
    K = model.tangent(state).toarray()
    K[:n, :n] -= model.model.tangent(state.model).toarray()
    return r, K


CASES = [
    ("spherical", "fv3", 0.1),
    ("classical", "fv3", 0.1),
    ("spline", "fv3", 0.0),
    ("classical", "galerkin-p2", 0.0),
    ("spline", "fv2", 0.1),
]


@pytest.mark.parametrize(("kind", "formulation", "smearing"), CASES)
def test_slider_tangent_matches_finite_differences(kind, formulation, smearing):
    """The derived tangent of a slider's loads and rows (geometric stiffness, the line's
    interpolation, the ``xi`` rates of the test functions, of the section frame and of the
    kink correction) agrees with central differences along random directions of all its
    columns at random finite rotations (up to about 2 rad) and positions of every node and
    random multipliers."""
    model = sliding(kind, formulation, smearing, random_frame())
    reference = model.reference()
    n = 6 * model.n_nodes
    dq = np.concatenate([0.3 * RNG.standard_normal(n), RNG.standard_normal(model.n_dofs - n)])
    dq[3:n:6], dq[4:n:6], dq[5:n:6] = RNG.uniform(-1.2, 1.2, (3, model.n_nodes))
    dq[n] = 0.02  # xi, inside its element
    state = reference.updated(dq)
    r, K = slider_part(model, state)
    derived = model.points(state).sliders[0]
    columns = model._dofs(0, derived)

    directions = RNG.standard_normal((len(columns), 4))  # every column, mixed at random

    def differences(h: float) -> np.ndarray:
        out = []
        for v in directions.T:
            e = np.zeros(model.n_dofs)
            e[columns] = h * v
            plus = slider_residual(model, state.updated(e))
            out.append((plus - slider_residual(model, state.updated(-e))) / (2 * h))
        return np.column_stack(out)

    h = 1e-5
    D1, D2 = differences(h), differences(2 * h)
    floor = model.residual_floor(state)
    scale = np.abs(directions).sum(axis=0)  # the rounding of the residuals' differences
    allowed = 2 * (np.abs(D2 - D1) / 3 + 2 * EPS * floor[:, None] * scale / h) + 1e-300
    error = np.abs(D1 - K[:, columns] @ directions)
    bad = np.argwhere(error > allowed)
    assert np.all(error <= allowed), (bad[:8], (error / allowed).max())


@pytest.mark.parametrize("formulation", ["fv3", "fv2", "galerkin-p2"])
@pytest.mark.parametrize("kind", ["spherical", "classical", "spline"])
def test_linear_slider_is_the_first_order_case(kind, formulation):
    """In the reference configuration with zero multipliers, at a random abscissa, offset and
    frame (the spline slider's the line's, about which the linear spline law is
    linearised), the exact slider's residual and tangent are the linear slider's
    (``section`` orientation, the kink correction's compliance in the (mu, mu) block
    included): the exact law to first order in the displacements and the multipliers is
    the linear law."""
    st = structure(formulation)
    frame = np.eye(3) if kind == "spline" else random_frame()
    xi = RNG.uniform(0.1, 0.9)
    linear = Slider(kind, BeamChain(st, "rod"), "ring", OFFSET, frame, smearing=0.05)
    model = SlidingModel(
        ExactModel.on(st, []), [ExactSlider(kind, "rod", "ring", OFFSET, frame, 0.05, xi=xi)]
    )
    state = model.reference()
    r, K = slider_part(model, state)
    dofs, r_q, r_y, J = linear.assemble(st, np.zeros(st.n_dofs), state.unknowns)
    n = model.model.n_dofs
    r_lin = np.zeros(model.n_dofs)
    r_lin[dofs], r_lin[n:] = r_q, r_y
    K_lin = np.zeros_like(K)
    at = np.concatenate([dofs, np.arange(n, model.n_dofs)])
    K_lin[np.ix_(at, at)] = J
    size = FLOOR_FACTOR * EPS * max(np.abs(K).max(), 1.0)
    assert np.abs(r - r_lin).max() <= size
    assert np.abs(K - K_lin).max() <= size


def pulled(formulation: str, n: int) -> tuple[float, float, float]:
    """The rod through the bearing (:func:`studies.bench_exact_sliders.bearing`: ``L = 1``,
    ``EJ = 1``, ``GA = 1e3``, the bearing at 0.4, a tip load of 1 N) on ``n`` elements: the
    axial force its far end's support carries, the closed form and the element length over
    the overhang."""
    model, fixed, load = bearing(formulation, n)
    start, tip = (model.model._node(ref, ref) for ref in ("rod.start", "rod.end"))
    state = solve_static(model, load, fixed).state
    pull = -model.residual(state)[6 * start]
    exact, _ = configurational(model, state.x[tip, 0], pull)
    return pull, exact, (1.0 / n) / 0.6


@pytest.mark.parametrize("formulation", ["fv3", "galerkin-p1"])
def test_configurational_force_of_a_rod_pushed_through_a_bearing(formulation):
    """The far end's support pulls the rod back into the bearing with the configurational
    force of the couple's work through the line's curvature (the xi row's ``m . k``).  Closed
    form, by energy: at equilibrium ``dPi / dxi`` is the strain energy per length just
    outside the bearing (inside it the rod is straight and unstressed; Eshelby's
    energy-momentum of a rod, Bigoni et al., Proc. R. Soc. A 471 (2015) 20140542, for the
    unshearable elastica), ``M^2 / 2 EJ + V^2 / 2 GA`` with the moment ``M = P (x_tip -
    x_bearing)`` of the deflected rod and the shear ``V = P`` (the axial force is zero
    there).  The line at ``xi`` reads the curvature over one node span: a first-order
    error, the curvature's relative change over an element, ``h / a`` (``a`` the overhang);
    it shrinks with the mesh (on 8 and 32 elements, the contact at other places in its
    span)."""
    errors = []
    for n in (8, 32):
        axial, exact, bound = pulled(formulation, n)
        errors.append(abs(axial - exact) / exact)
        assert errors[-1] <= bound, (n, axial, exact)
    assert errors[1] < errors[0]


def test_small_load_approaches_the_linear_solution_at_second_order():
    """The rod through the bearing under tip loads of 1e-2, 5e-3 and 2.5e-3 N: the exact
    solution's displacements differ from the linear model's (``SliderStatics``, the same
    structure, slider and supports) by the neglected terms, of second order in the load:
    the measured slope of the difference against the load, log2 of the ratio of successive
    differences, is 2 within the next order's share (the load halves: ``1 +- 1/2`` on a
    ratio of 4 gives a ratio within ``4 +- 2``, a slope from 1 to 2.58)."""
    model, fixed, load = bearing("fv3", 8)
    tip = model.model._node("rod.end", "rod.end")
    st = model.model.structure
    linear = SliderStatics(
        st,
        [Support("bearing", kind="clamp"), Support("rod.start", kind="ux+rx")],
        [Slider("classical", BeamChain(st, "rod"), "bearing")],
    )
    X = st.node_position("rod.end")
    differences = []
    for P in (1e-2, 5e-3, 2.5e-3):
        exact = solve_static(model, P * load, fixed).state
        q = linear.solve(P * load[: st.n_dofs]).q
        differences.append(np.abs(exact.x[tip] - X - q[6 * tip : 6 * tip + 3]).max())
    slopes = np.log2(np.array(differences[:-1]) / differences[1:])
    assert np.all((slopes > np.log2(2.0)) & (slopes < np.log2(6.0))), slopes


def test_a_conservative_slider_problem_is_a_stationary_point_of_its_potential():
    """A spherical slider on a ``galerkin-p2`` cantilever (a line whose load transfer is the
    constraint's own virtual work: a conservative problem): a ring held along ``x`` and in
    its rotations, pushed across the rod by a dead force (``P L^2 / EJ = 1``: the rod turns
    by 0.26 rad, the contact slides to ``xi = 0.713``, its force leans by 0.27 rad).  Its
    equilibrium is a stationary point of the potential ``U - f . x``
    (``U = sum_p w_p [nu; kappa]^T C [nu; kappa] / 2``) on the constraint's manifold in the
    nodes' dofs and ``xi``: perturbations along random directions of the rows' null space,
    projected back onto ``c = 0`` (Gauss-Newton, to round-off); the central slope vanishes to
    its truncation (a doubled step) and rounding, and does not at the equilibrium of a load
    10 % smaller (the same potential)."""
    section = Section.diagonal(EA=1e3, GAy=1e3, GAz=1e3, GJ=1.0, EJy=1.0, EJz=1.0)
    rod = Beam(straight([0, 0, 0], [1, 0, 0], 4, 3, name="rod"), section, "galerkin-p2")
    st = Structure([rod], (), [RigidBody("ring", [0.7, 0.0, 0.0])])
    model = SlidingModel(ExactModel.on(st, []), [ExactSlider("spherical", "rod", "ring")])
    ring, start = model.model._node("ring", "ring"), model.model._node("rod.start", "rod")
    n, at = 6 * model.n_nodes, model.model.n_dofs  # the nodes' dofs, xi
    fixed = np.concatenate([6 * start + np.arange(6), [6 * ring], 6 * ring + np.arange(3, 6)])
    moving = np.append(np.setdiff1d(np.arange(n), fixed), at)
    rows = np.arange(at + 1, at + 4)
    load = np.zeros(model.n_dofs)
    load[6 * ring + 1] = -1.0

    def potential(state: SlidingState) -> float:
        exact = model.model.exact
        energy = 0.0
        for i, beam in enumerate(exact.beams):
            strain = beam.points(exact.local(state.model.nodes, i)).strain
            energy += 0.5 * float(np.einsum("p,pi,pij,pj->", beam.weight, strain, beam.C, strain))
        return energy - float(load[:n].reshape(-1, 6)[:, :3].ravel() @ state.x.ravel())

    def moved(state: SlidingState, d: np.ndarray) -> SlidingState:
        dq = np.zeros(model.n_dofs)
        dq[moving] = d
        return state.updated(dq)

    def projected(state: SlidingState, d: np.ndarray) -> SlidingState:
        state = moved(state, d)
        for _ in range(20):
            c = model.residual(state)[rows]
            if np.abs(c).max() <= 16 * EPS:
                return state
            B = model.tangent(state).toarray()[np.ix_(rows, moving)]
            state = moved(state, -np.linalg.lstsq(B, c, rcond=None)[0])
        raise AssertionError("the projection onto the slider's rows did not converge")

    for factor, stationary in ((1.0, True), (0.9, False)):
        state = solve_static(model, factor * load, fixed).state
        B = model.tangent(state).toarray()[np.ix_(rows, moving)]
        free = scipy.linalg.null_space(B)
        directions = (free @ RNG.standard_normal((free.shape[1], 2))).T
        directions /= np.linalg.norm(directions, axis=1)[:, None]
        size = abs(potential(state)) + 1e3  # terms of size EA = 1e3
        assert is_stationary(potential, projected, state, directions, size) == stationary


def test_spline_slider_transmits_a_torque_on_a_line_turned_by_a_large_angle():
    """A shaft (``EJ = GJ = 1``) rolled by a tip couple ``pi EJ / 2 L`` towards a quarter
    circle, a collar on it by a spline slider (held along ``x``, so that it cannot slide
    off), a couple ``C`` on the collar: the collar's moment balance is the torque balance
    of the slider, ``C = mu_1 e_b1 + mu_3 e_b2 - mu_2 e_b3`` in the collar's current axes
    (the spline row's couple about ``e_b1 = t``, the classical rows' about ``e_bj x t``),
    with the collar turned by about 0.9 rad.  Tolerance: the collar's rows' round-off floor
    (the residual of a converged state)."""
    section = Section.diagonal(EA=1e3, GAy=1e3, GAz=1e3, GJ=1.0, EJy=1.0, EJz=1.0)
    shaft = Beam(straight([0, 0, 0], [1, 0, 0], 8, 3, name="shaft"), section, "fv3")
    st = Structure([shaft], (), [RigidBody("collar", [0.5, 0.0, 0.0])])
    model = SlidingModel(ExactModel.on(st, []), [ExactSlider("spline", "shaft", "collar")])
    collar, start, tip = (model.model._node(r, r) for r in ("collar", "shaft.start", "shaft.end"))
    fixed = np.concatenate([6 * start + np.arange(6), [6 * collar]])
    load = np.zeros(model.n_dofs)
    load[6 * tip + 5] = np.pi / 2
    C = 0.3 * np.array([np.cos(np.pi / 4), np.sin(np.pi / 4), 0.0])
    load[6 * collar + 3 : 6 * collar + 6] = C
    state = solve_static(model, load, fixed).state
    E = state.R[collar]
    assert np.linalg.norm(rotations.log_map(E)) > 0.8
    _, _, _, _, mu_2, mu_3, mu_1 = state.unknowns
    turn = slice(6 * collar + 3, 6 * collar + 6)
    floor = FLOOR_FACTOR * EPS * model.residual_floor(state)[turn].sum()
    np.testing.assert_allclose([mu_1, mu_3, -mu_2], C @ E, rtol=0, atol=floor)


def test_a_drive_holds_the_rod_in_its_bearing():
    """The rod through the bearing held by a drive of the slider's abscissa
    (``ExactSlider.drive``) instead of its far end's support: ``xi`` stays where the drive
    holds it, the rod's axial balance leaves the bearing's force no axial part
    (``lambda_x``: zero to the round-off floor of the rod's axial force balances), and the
    drive carries the configurational force: the frictionless row's value
    ``f_L . l + m_L . k`` (the force along the line the drive holds the contact with) is the
    closed form within the discretisation bound ``h / a``
    (:func:`test_configurational_force_of_a_rod_pushed_through_a_bearing`)."""
    model, fixed, load = bearing("fv3", 8)
    model = SlidingModel(model.model, [ExactSlider("classical", "rod", "bearing", drive=0.4)])
    start = model.model._node("rod.start", "rod.start")
    fixed = fixed[fixed != 6 * start]  # the rod free along its axis
    state = solve_static(model, load, fixed).state
    xi, lambda_x = state.unknowns[:2]
    floor = FLOOR_FACTOR * EPS * model.residual_floor(state)[0 : 6 * model.n_nodes : 6].sum()
    assert xi == 0.4
    assert abs(lambda_x) <= floor
    tip = model.model._node("rod.end", "rod.end")
    along = model.points(state).sliders[0].along
    _, error = configurational(model, state.x[tip, 0], along)
    assert error <= (1 / 8) / 0.6


@pytest.mark.parametrize("formulation", ["fv3", "galerkin-p1"])
def test_spherical_slider_loads_a_bent_cantilever_as_a_point_force(formulation):
    """A ring (held along ``x`` and in its rotations) pushed across a cantilever by a dead
    force (``P L^2 / EJ = 1``, the rod turning by about 0.26 rad): the loads the slider puts
    on the rod's nodes are a point force ``lambda`` at the contact ``x(xi)`` (the joint
    pushes the line with ``+lambda``, the body with ``-lambda``: ``docs/scenes.md``; their
    resultant, and their moment about the contact zero: the fv regions' arms on the current
    configuration), and the rod alone under those loads, dead, is in equilibrium at the
    slider's state (its residual on the round-off floor).  Tolerance: the floor of the rows
    summed (16 eps times their terms)."""
    section = Section.diagonal(EA=1e3, GAy=1e3, GAz=1e3, GJ=1.0, EJy=1.0, EJz=1.0)
    npe = 2 if formulation == "galerkin-p1" else 3
    rod = Beam(straight([0, 0, 0], [1, 0, 0], 8, npe, name="rod"), section, formulation)
    st = Structure([rod], (), [RigidBody("ring", [0.7, 0.0, 0.0])])
    model = SlidingModel(ExactModel.on(st, []), [ExactSlider("spherical", "rod", "ring")])
    ring, start = model.model._node("ring", "ring"), model.model._node("rod.start", "rod")
    fixed = np.concatenate([6 * start + np.arange(6), [6 * ring], 6 * ring + np.arange(3, 6)])
    load = np.zeros(model.n_dofs)
    load[6 * ring + 1] = -1.0
    state = solve_static(model, load, fixed).state
    n_rod = 6 * st.beams[0].mesh.n_nodes  # the rod's nodes come first
    on_rod = -slider_residual(model, state)[:n_rod].reshape(-1, 6)  # what the slider puts there
    lam = state.unknowns[1:4]
    x_L = state.x[ring]  # the ring's point is the contact (no offset)
    floor = FLOOR_FACTOR * EPS * model.residual_floor(state)[:n_rod].sum()
    np.testing.assert_allclose(on_rod[:, :3].sum(axis=0), lam, rtol=0, atol=floor)
    arms = np.cross(state.x[: len(on_rod)] - x_L, on_rod[:, :3])
    np.testing.assert_allclose((on_rod[:, 3:] + arms).sum(axis=0), 0.0, rtol=0, atol=floor)
    alone = ExactModel(beams=[ExactBeam(rod)])
    nodes = JointedState(ExactState(state.x[: len(on_rod)], state.R[: len(on_rod)]), np.zeros(0))
    residual = alone.residual(nodes) - on_rod.ravel()
    held = np.arange(6)  # the clamp
    residual[held] = 0.0
    assert np.abs(residual).max() <= FLOOR_FACTOR * EPS * alone.residual_floor(nodes).max() + floor


def test_end_stops_hold_a_sliding_point_that_pushes_and_release_one_that_pulls():
    """A cantilever arm along ``y`` whose tip slides (spherical slider with end stops) on a
    rail beam along ``x`` clamped at both ends, the tip at the rail's far end, a force ``F``
    along ``x`` at the tip (the linear end-stop scene's problem on an exact line).  Pushed
    outwards, the stop holds the tip at the end: ``xi = L`` exactly, ``lambda = (F, 0, 0)``
    and the stop's force ``-along = F |l|`` with the rail's end unstrained (``|l| = 1``), to
    the round-off floor.  Pulled inwards, the stop lets go: the frictionless row holds
    (``along = 0``), the slider carries nothing along the rail, and the tip slides in by the
    cantilever's deflection ``F L^3 / 3 EJ + F L / GA``, stiffened by the tension ``N`` the
    rail's hold on the shortening arm puts in it: by at most the geometric over the elastic
    stiffness, ``(6 N / 5 L) / (3 EJ / L^3) = 0.4 N L^2 / EJ`` (twice allowed)."""
    EJ, GA = 4e4, 1e8
    section = Section.diagonal(EA=1e9, GAy=GA, GAz=GA, GJ=4e4, EJy=EJ, EJz=EJ)
    arm = Beam(straight([0, -1, 0], [0, 0, 0], 4, 3, name="arm"), section, "fv3")
    rail = Beam(straight([-1, 0, 0], [0, 0, 0], 4, 3, name="rail"), section, "fv3")
    slider = ExactSlider("spherical", "rail", "arm.end", end_stops=True)
    model = SlidingModel(ExactModel.on(Structure([arm, rail]), []), [slider])
    ends = [model.model._node(r, r) for r in ("arm.start", "rail.start", "rail.end")]
    fixed = (6 * np.array(ends)[:, None] + np.arange(6)).ravel()
    tip = model.model._node("arm.end", "arm.end")
    F = 50.0
    for sign in (1.0, -1.0):
        load = np.zeros(model.n_dofs)
        load[6 * tip] = sign * F
        state = solve_static(model, load, fixed).state
        xi, lam = state.unknowns[0], state.unknowns[1:4]
        along = model.points(state).sliders[0].along
        floor = FLOOR_FACTOR * EPS * model.residual_floor(state).max()
        if sign > 0:
            assert xi == 1.0
            np.testing.assert_allclose(lam, [F, 0.0, 0.0], rtol=0, atol=floor)
            assert abs(along + F) <= floor
            continue
        assert abs(along) <= floor and abs(lam[0]) <= floor
        linear = F / (3 * EJ) + F / GA
        tension = abs(lam[1])
        assert abs((1.0 - xi) - linear) <= 2 * 0.4 * tension / EJ * linear
