"""The time integrator (sliders.solve.integrator, sliders.solve.dynamics) against closed forms.

Tolerance sources:

* Scheme constants: Chung & Hulbert (1993) closed forms at rho_inf = 1 and 0, to roundoff.
* ``SCHEME``: a linear structure started in a mode stays in it, and the modal amplitude then
  follows the scheme's single-dof recursion exactly (the same arithmetic on a projected
  system); the bound is the roundoff of O(10^3) steps, each ~1e-15 relative, with margin 10,
  plus the phase error the eigensolver's own error in ``omega^2`` (its relative backward
  error ``e``) makes over ``N`` steps, ``N omega h e / 2``, with margin 20.
* The first mode's amplitude after 100 periods at ``rho_inf = 0.8`` (the issue's 1 %): the
  scheme's spectral radius at ``omega h = 2 pi / 40`` gives a decay of 0.17 %; measured by the
  recursion above.
* Energy at ``rho_inf = 1`` (trapezoidal rule, exactly conservative on linear symmetric
  systems): over ``N`` steps roundoff can accumulate at most ``N eps cond(K')`` relative.
* Time order: the bead on a circular wire under gravity is a pendulum with the elliptic-function
  solution (e.g. Lawden, "Elliptic Functions and Applications", Sec. 5.2):
  ``theta = 2 arcsin(k sn(omega_n t, k))``, ``k = v0 / (2 sqrt(g R))``, normal force
  ``m g (3 cos theta - 2 cos theta_max)``.  The observed order of the abscissa and of the
  reaction on h = T/100, T/200 must be 2 within 0.35: the first neglected term is
  ``O(omega h)`` = 0.06 relative, a shift of the observed order below 0.1, plus the
  pre-asymptotic spread measured at rho_inf = 0 (0.33 at T/50).
* Static drive: the fv3 cantilever's tip stiffness ``1 / (L^3/3EJ + L/GA)`` is exact (the
  moment is linear), so the drive's reaction matches it to roundoff.
"""

import numpy as np
import pytest
from scipy.special import ellipj, ellipk

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from fvbeam.modes import natural_frequencies
from sliders.app.history import Recorder
from sliders.joints.drives import DofDrive, Linear, Ramp, Tabulated
from sliders.joints.slider import Slider
from sliders.lines.rigid import CircularArc
from sliders.solve.dynamics import Adaptive, Dynamics, DynamicsError
from sliders.solve.integrator import GeneralizedAlpha, State

EPS = np.finfo(float).eps
SCHEME = 1e-11
SECTION = Section.diagonal(
    EA=1e3,
    GAy=100,
    GAz=100,
    GJ=1.0,
    EJy=1.0,
    EJz=1.0,
    mass_per_length=1.0,
    inertia=np.diag([1e-3] * 3),
    name="s",
)


def cantilever(name: str = "fv3", n: int = 2) -> tuple[Structure, list[Support]]:
    return Structure([Beam(straight((0, 0, 0), (1, 0, 0), n, 3), SECTION, name)]), [
        Support(0, 0, "clamp")
    ]


def amplification(scheme: GeneralizedAlpha, omega: float, h: float) -> np.ndarray:
    """The scheme's step on ``qdd + omega^2 q = 0``, state ``(q, v, a, qdd)``: the
    recursion of :mod:`sliders.solve.integrator` written for one dof."""
    b, g, am, af = scheme.beta, scheme.gamma, scheme.alpha_m, scheme.alpha_f
    w2 = omega * omega
    # unknowns (q1, v1, a1, qdd1); rows: the three updates and the equation of motion
    A = np.array(
        [[1, 0, -b * h * h, 0], [0, 1, -g * h, 0], [0, 0, 1 - am, -(1 - af)], [w2, 0, 0, 1]]
    )
    B = np.array(
        [[1, h, h * h * (0.5 - b), 0], [0, 1, h * (1 - g), 0], [0, 0, -am, af], [0, 0, 0, 0]]
    )
    return np.linalg.solve(A, B)


def test_scheme_constants_match_chung_hulbert():
    one, zero = GeneralizedAlpha(1.0), GeneralizedAlpha(0.0)
    assert (one.alpha_m, one.alpha_f, one.gamma, one.beta) == (0.5, 0.5, 0.5, 0.25)
    assert (zero.alpha_m, zero.alpha_f, zero.gamma, zero.beta) == (-1.0, 0.0, 1.5, 1.0)
    # the spectral radius tends to rho_inf as omega h grows, like (omega h)^-1/2 at worst (at
    # rho_inf = 0 a double eigenvalue splits like the root of an O((omega h)^-1) perturbation)
    wh = 1e8
    for rho in (0.0, 0.5, 0.8, 1.0):
        step = amplification(GeneralizedAlpha(rho), 1.0, wh)
        assert np.abs(np.linalg.eigvals(step)).max() == pytest.approx(rho, abs=wh**-0.5)
    with pytest.raises(ValueError, match="rho_inf"):
        GeneralizedAlpha(1.5)


@pytest.mark.parametrize("name,mass", [("fv3", "lumped"), ("galerkin-p2", "consistent")])
def test_modes_follow_the_scheme_and_rho_08_keeps_the_first_mode(name, mass):
    structure, supports = cantilever(name)
    modes = natural_frequencies(structure, supports, 8, mass=mass)
    omega, shapes = modes.omega, modes.shapes[:, [0, 7]]
    T1 = 2 * np.pi / omega[0]
    h, steps = T1 / 40, 4000
    d = Dynamics(structure, supports, mass=mass, rho_inf=0.8)
    amplitude = np.array([1e-2, 1e-3])
    start = d.state(shapes @ amplitude)
    final = d.run(start, steps * h, h, progress=False)
    measured = np.linalg.lstsq(shapes, final.q, rcond=None)[0]
    for j, w in enumerate(omega[[0, 7]]):
        x = np.array([amplitude[j], 0.0, -w * w * amplitude[j], -w * w * amplitude[j]])
        x = np.linalg.matrix_power(amplification(d.scheme, w, h), steps) @ x
        phi = shapes[:, j]
        backward = np.linalg.norm((d.K @ phi - w * w * (d.M @ phi))[d.free]) / np.linalg.norm(
            (d.K @ phi)[d.free]
        )
        # a relative error e in omega^2 shifts the phase by steps * omega h * e / 2
        phase = steps * w * h * backward
        assert measured[j] == pytest.approx(x[0], abs=(SCHEME + 10 * phase) * amplitude[j])
    v_first = np.linalg.lstsq(shapes, final.v, rcond=None)[0][0]
    first = np.hypot(measured[0], v_first / omega[0]) / amplitude[0]
    assert abs(first - 1) < 0.01
    assert abs(measured[1]) < 1e-6 * amplitude[1]


def test_energy_is_conserved_over_1e5_steps_at_rho_1():
    """The trapezoidal rule (rho_inf = 1) keeps ``v M v / 2 + q K q / 2`` of a linear system
    with symmetric ``M`` and ``K`` to roundoff.  A Galerkin beam: the fv stiffness is
    unsymmetric (a Petrov-Galerkin form), and ``q K q`` is then no invariant of the flow, exact
    or discrete (a superposition of its modes exchanges ``q (K - K^T) q`` between them: a
    bounded oscillation, measured at 2-3 % on the fv3 cantilever, whose size follows the
    modes' relative amplitudes, which the eigensolver's normalisation decides)."""
    structure, supports = cantilever("galerkin-p2")
    modes = natural_frequencies(structure, supports, 3)
    h = 2 * np.pi / modes.omega[0] / 40
    d = Dynamics(structure, supports, rho_inf=1.0)
    state = d.state(modes.shapes[:, 0] * 1e-2 + modes.shapes[:, 2] * 1e-3)

    def energy(s: State) -> float:
        return s.v @ (d.M @ s.v) / 2 + s.q @ (d.K @ s.q) / 2

    e0, drift, steps = energy(state), [], 100_000
    for _ in range(10):
        state = d.run(state, state.t + steps // 10 * h, h, progress=False)
        drift.append(abs(energy(state) - e0) / e0)
    K = d.operator(h)[d.free][:, d.free].toarray()
    assert max(drift) < steps * EPS * np.linalg.cond(K)


R, G, MASS, V0 = 1.0, 1.0, 2.0, 1.2
WIRE = CircularArc((0, 0, 0), R, -np.pi / 2 - 2.0, -np.pi / 2 + 2.0, name="wire")
BOTTOM = 2.0 * R


def bead() -> tuple[Structure, Slider, list[Support]]:
    structure = Structure([], bodies=[RigidBody("bead", (0, -R, 0), mass=MASS, inertia=np.eye(3))])
    return (
        structure,
        Slider("spherical", WIRE, "bead", name="bead_on_wire"),
        [Support("bead", kind="rx+ry+rz")],
    )


def pendulum(t: float) -> tuple[float, float]:
    """Abscissa and normal force of the bead released at the bottom with speed V0."""
    k = V0 / (2 * np.sqrt(G * R))
    sn = ellipj(np.sqrt(G / R) * t, k * k)[0]
    theta = 2 * np.arcsin(k * sn)
    return BOTTOM + R * theta, MASS * G * (3 * np.cos(theta) - 2 * (1 - 2 * k * k))


def bead_start(n_dofs: int) -> State:
    """At the bottom with speed V0 along x: centripetal acceleration V0^2/R, and the wire
    pulls with m (g + V0^2/R) (the body's residual carries ``+ lambda``)."""
    q, v, qdd = np.zeros(n_dofs), np.zeros(n_dofs), np.zeros(n_dofs)
    v[0], qdd[1] = V0, V0**2 / R
    return State(0.0, q, v, qdd.copy(), qdd, [np.array([BOTTOM, 0, -MASS * (G + V0**2 / R), 0])])


@pytest.mark.parametrize("rho", [1.0, 0.8, 0.5])
def test_bead_on_a_wire_converges_at_order_2_in_time(rho):
    structure, slider, supports = bead()
    period = 4 * ellipk((V0 / 2) ** 2) / np.sqrt(G / R)
    errors = []
    for n in (50, 100, 200):
        d = Dynamics(structure, supports, [slider], gravity=(0, -G, 0), rho_inf=rho)
        s = d.run(bead_start(structure.n_dofs), 0.7 * period, period / n, progress=False)
        xi, normal = pendulum(s.t)
        errors.append((abs(s.unknowns[0][0] - xi), abs(np.linalg.norm(s.unknowns[0][1:]) - normal)))
    e = np.array(errors)
    order = np.log2(e[-2] / e[-1])
    assert np.all(np.abs(order - 2) < 0.35), order


def test_restart_from_a_saved_state_is_bitwise_identical(tmp_path):
    structure, slider, supports = bead()
    d = Dynamics(structure, supports, [slider], gravity=(0, -G, 0))
    whole = d.run(bead_start(structure.n_dofs), 1.0, 0.05, progress=False)
    half = d.run(bead_start(structure.n_dofs), 0.5, 0.05, progress=False)
    half.save(tmp_path / "state.npz")
    resumed = d.run(State.load(tmp_path / "state.npz"), 1.0, 0.05, progress=False)
    np.testing.assert_array_equal(resumed.q, whole.q)
    np.testing.assert_array_equal(resumed.unknowns[0], whole.unknowns[0])
    (tmp_path / "bad.npz").write_text("not a state")
    with pytest.raises(ValueError, match="bad.npz"):
        State.load(tmp_path / "bad.npz")


def test_scaled_steps_converge_alike_over_four_decades():
    """At rest at the bottom the wire carries the weight: ``lambda = -m g`` whatever the
    step, and the scaled Newton needs the same few iterations (the unscaled matrix's
    condition grows like h^-4)."""
    structure, slider, supports = bead()
    d = Dynamics(structure, supports, [slider], gravity=(0, -G, 0))
    zero = np.zeros(structure.n_dofs)
    rest = State(0.0, zero, zero, zero, zero, [np.array([BOTTOM, 0, -MASS * G, 0])])
    for h in (1e-1, 1e-3, 1e-5):
        s = d.step(rest, h)
        assert s.iterations <= 2
        np.testing.assert_allclose(s.unknowns[0][1:], [0, -MASS * G, 0], atol=1e-12)


def test_adaptive_steps_are_powers_of_two_and_meet_the_error_bound():
    structure, slider, supports = bead()
    d = Dynamics(structure, supports, [slider], gravity=(0, -G, 0))
    control = Adaptive(rtol=1e-5, atol=1e-8, h_min=1e-6, h_max=0.4)
    states = []
    rec = Recorder(probes={"capture": lambda s, dyn: states.append(s) or 0.0})
    d.run(bead_start(structure.n_dofs), 3.0, 0.1, adaptive=control, recorder=rec, progress=False)
    h = np.array([s.h for s in states[1:]])
    k = np.log2(h[:-1] / 0.1)
    np.testing.assert_allclose(k, np.round(k), atol=1e-12)
    assert len(set(np.round(k))) > 1
    for old, new in zip(states[:-1], states[1:], strict=True):
        bound = control.atol + control.rtol * np.abs(new.q).max()
        assert np.abs(d.scheme.local_error(old, new)[d.free]).max() <= bound
    with pytest.raises(DynamicsError, match="below its minimum"):
        d.run(
            bead_start(structure.n_dofs),
            3.0,
            0.1,
            progress=False,
            adaptive=Adaptive(rtol=1e-12, atol=0.0, h_min=0.05),
        )


def test_leaving_the_wire_stops_with_the_state_and_whole_rows_on_disk(tmp_path):
    structure, _, supports = bead()
    slider = Slider("spherical", WIRE, "bead", name="bead_on_wire", drive=Linear(BOTTOM, 1.0))
    d = Dynamics(structure, supports, [slider], gravity=(0, -G, 0))
    with pytest.raises(DynamicsError, match="wire") as failure:
        d.run(d.static_state(), 5.0, 0.1, recorder=Recorder(tmp_path), progress=False)
    rows = (tmp_path / "history.csv").read_text().splitlines()
    assert float(rows[-1].split(",")[1]) == pytest.approx(failure.value.state.t)
    assert failure.value.state.t <= BOTTOM + 1e-9
    assert not list(tmp_path.glob("*.part"))


def test_dof_drive_holds_the_tip_with_the_timoshenko_reaction():
    L, delta = 1.0, 0.01
    structure, supports = cantilever("fv3", 3)
    ramp = Ramp(0.0, delta, 0.0, 1.0)
    d = Dynamics(structure, supports, drives=[DofDrive((0, "end"), "uy", ramp)])
    state = d.static_state(t=2.0)
    tip = structure.node_dofs((0, "end"))[1]
    assert state.q[tip] == delta
    stiffness = 1 / (L**3 / 3 + L / 100)  # EJ = 1, GA = 100 (SECTION)
    assert d.constraint_forces(state)[tip] == pytest.approx(stiffness * delta, rel=1e-10)
    moving = d.run(state, 2.5, 0.05, progress=False)
    assert moving.q[tip] == delta
    with pytest.raises(ValueError, match="driven twice"):
        Dynamics(structure, supports, drives=[DofDrive((0, "start"), "uy", ramp)])


@pytest.mark.parametrize(
    "motion",
    [
        Linear(0.2, 0.3, 1.0),
        Ramp(0.0, 2.0, 1.0, 3.0),
        Ramp(1.0, 0.0, 0.0, 2.0, "linear"),
        Tabulated([0, 1, 2, 4], [0, 1, 0.5, 2], order=3),
        Tabulated([0, 1, 2], [0, 1, 0.5]),
    ],
)
def test_motions_rates_are_their_derivatives(motion):
    """Central differences of step ``d``: error ``d^2 |f'''| / 6``; the bound uses
    ``|f'''| <= 1e2`` (the largest third derivative of these motions is pi^3 / 4 < 8)."""
    d = 1e-5
    for t in (0.5, 1.5, 2.5):
        value, rate, accel = motion(t)
        assert rate == pytest.approx(
            (motion(t + d)[0] - motion(t - d)[0]) / (2 * d), abs=1e2 * d * d + 1e-8
        )
        assert accel == pytest.approx(
            (motion(t + d)[1] - motion(t - d)[1]) / (2 * d), abs=1e2 * d * d + 1e-8
        )


def test_motion_errors_name_the_problem():
    with pytest.raises(ValueError, match="t1 must be after t0"):
        Ramp(0, 1, 2.0, 1.0)
    with pytest.raises(ValueError, match="increase strictly"):
        Tabulated([0, 0], [1, 2])
    with pytest.raises(ValueError, match="finite"):
        Linear(np.nan, 1.0)
    with pytest.raises(ValueError, match="dof must be one of"):
        DofDrive((0, 0), "uw", Linear(0, 1))


def test_a_body_centre_off_its_node_couples_and_weighs():
    """``T = m |u' + w x c|^2 / 2 + w.J w / 2`` for any velocities, and gravity's moment
    about the node is ``c x m g``."""
    c, J, m = np.array([0.3, -0.2, 0.5]), np.diag([1.0, 2.0, 3.0]), 4.0
    body = RigidBody("b", (1, 2, 3), mass=m, inertia=J, centre=c)
    rng = np.random.default_rng(1)
    u, w = rng.normal(size=3), rng.normal(size=3)
    v = np.concatenate([u, w])
    kinetic = m * np.sum((u + np.cross(w, c)) ** 2) / 2 + w @ J @ w / 2
    assert v @ body.mass_matrix() @ v / 2 == pytest.approx(kinetic, rel=1e-14)
    structure = Structure([], bodies=[body])
    g = np.array([0.0, 0.0, -9.81])
    d = Dynamics(structure, [], gravity=g)
    np.testing.assert_allclose(d.f_gravity, np.concatenate([m * g, np.cross(c, m * g)]), rtol=1e-14)


def test_a_loaded_cantilever_at_rest_stays_and_its_clamp_reacts(tmp_path):
    """From static equilibrium under a constant tip force the exact motion is rest, so the
    clamp's reactions are the statics of the whole beam: ``-F`` on ``uy`` and ``-F L`` on
    ``rz``; every other entry zero (to the solve's roundoff)."""
    structure, supports = cantilever("fv3", 3)
    F, L = 2.5, 1.0
    d = Dynamics(structure, supports, load=structure.nodal_load((0, "end"), (0, F, 0)))
    recorder = Recorder(tmp_path, tables=["reactions"])
    d.run(d.static_state(), 1.0, 0.1, recorder=recorder, progress=False)
    expected = np.array([0, -F, 0, 0, 0, -F * L])
    header, *rows = (tmp_path / "reactions.csv").read_text().splitlines()
    assert len(rows) == len(recorder.rows)
    for row in rows:
        step, t, node, *values = row.split(",")
        assert node == "beam.start"
        np.testing.assert_allclose(np.array(values, dtype=float), expected, atol=1e-12 * F)
    assert header.split(",") == ["step", "t", "node", "fx", "fy", "fz", "mx", "my", "mz"]
