"""The landing gear's force laws (sliders.forces): partials, closed values, bad input.

Sources of truth:
* every partial derivative against central differences (``central_difference``: order-8
  stencil, tolerance derived in ``sliders/forces/differences.py``) at points hypothesis draws
  over the physical ranges of issue 14 and docs/landing_gear.md, away from the laws' kinks by
  more than the stencil (the check refuses to judge across a kink);
* the closed values quoted by issue 14 and /work/shared/notes/landing-gear-parameters.md, to
  the digits they quote: gas preload at S = 0 (494 N), gas force at S_max = 0.16 m (15.8 kN),
  isothermal static stroke under 2.45 kN (131 mm), friction peak 0.8 at kappa 0.14, locked
  wheel mu(1) = 0.52, slope BCD = 13.2, tyre deflection 52 mm under 13 kN;
* closed forms of the laws' limits (the slip ratio against the issue's (u - w R0)/u, tanh
  against the sign function) to bounds derived from their series.
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from sliders.forces import (
    Strut,
    UserLaw,
    coulomb_friction,
    end_stops,
    friction_curve,
    gas_spring,
    orifice_damper,
    slip_ratio,
    stribeck_friction,
    tyre_longitudinal,
    tyre_radial,
)
from sliders.forces.differences import central_difference
from sliders.forces.laws import P_ATM, end_stops_energy, gas_spring_energy, tyre_energy

EPS = float(np.finfo(float).eps)
#: Issue 14's strut, tyre and friction curve.
GAS = dict(area=1.6e-3, pressure=4.1e5, volume=2.8e-4, exponent=1.3)
STRUT = Strut(**GAS, compression=5000.0, rebound=20000.0, stop_stiffness=1e8, stroke_max=0.16)
TYRE = dict(stiffness=2.5e5, damping=250.0)
CURVE = dict(B=10.0, C=1.65, D=0.8)
RADIUS = 0.22
SETTINGS = settings(max_examples=40, deadline=None)


def assert_partials(law, states, steps, scale=0.0, **parameters):
    """Each partial of ``law(*states, **parameters)`` against central differences in that
    state, the others held, with the stencil's largest offset ``steps[i]`` (``scale``: of
    the law's rounding, :func:`sliders.forces.differences.central_difference`)."""
    value, *partials = law(*states, **parameters)
    assert len(partials) == len(states)
    for i, (partial, step) in enumerate(zip(partials, steps, strict=True)):

        def along(xi, *others, i=i):
            return law(*others[:i], xi, *others[i:], **parameters)[0]

        others = tuple(s for j, s in enumerate(states) if j != i)
        estimate, tolerance = central_difference(along, states[i], step, others, scale)
        assert abs(partial - estimate) <= tolerance, (i, partial, estimate, tolerance)


# ---- the finite-difference check itself -------------------------------------------------


@pytest.mark.parametrize(
    "f, df, x",
    [(np.exp, np.exp, 1.3), (np.sin, np.cos, 0.7), (lambda x: x**3, lambda x: 3 * x**2, 0.0)],
)
def test_central_difference_is_tight_on_smooth_functions(f, df, x):
    """The estimate is within its tolerance of the closed-form derivative, and the tolerance
    is small enough to catch a wrong derivative (below 1e-9 of the function's scale)."""
    estimate, tolerance = central_difference(f, x, 1e-2)
    assert abs(estimate - df(x)) <= tolerance
    assert tolerance < 1e-9 * max(abs(df(x)), abs(f(x)), 1.0)


def test_central_difference_refuses_a_jump():
    """A step function has no derivative at 1e-9 from its jump, closer than the smallest
    stencil (1e-2 / 2^12): the estimates grow as the step shrinks, and the check says so."""
    with pytest.raises(ValueError, match="not smooth within the step"):
        central_difference(np.sign, 1e-9, 1e-2)


# ---- partials against central differences (hypothesis over the physical ranges) ---------


@SETTINGS
@given(
    fraction=st.floats(-0.05, 0.95),
    area=st.floats(9.6e-4, 2.8e-3),  # 35 to 60 mm pistons
    pressure=st.floats(2e5, 1e6),
    volume=st.floats(1.5e-4, 5e-4),
    exponent=st.floats(1.0, 1.4),
)
def test_gas_spring_partial(fraction, area, pressure, volume, exponent):
    """Up to 95 % of the gas column's length; the stencil is 1 % of the distance to it."""
    length = volume / area
    stroke = fraction * length
    parameters = dict(area=area, pressure=pressure, volume=volume, exponent=exponent)
    assert_partials(gas_spring, (stroke,), (0.01 * (length - stroke),), **parameters)


@SETTINGS
@given(fraction=st.floats(-0.05, 0.95), exponent=st.sampled_from([1.0, 1.1, 1.3, 1.4]))
def test_gas_spring_energy_is_the_force_integral(fraction, exponent):
    """d E_gas / dS = F_gas (the isothermal n = 1 branch included), E_gas(0) = 0."""
    gas = dict(GAS, exponent=exponent)
    length = GAS["volume"] / GAS["area"]
    stroke = fraction * length

    def energy(s):
        return gas_spring_energy(s, **gas)

    estimate, tolerance = central_difference(energy, stroke, 0.01 * (length - stroke))
    force, _ = gas_spring(stroke, **gas)
    assert abs(force - estimate) <= tolerance
    assert gas_spring_energy(0.0, **gas) == 0.0


@SETTINGS
@given(rate=st.floats(-5.0, 5.0), compression=st.floats(100.0, 2e4), ratio=st.floats(1.0, 10.0))
def test_orifice_damper_partial(rate, compression, ratio):
    """Rebound 1 to 10 times compression (docs/landing_gear.md); away from S' = 0, where the
    coefficient switches (the second derivative jumps), by more than the stencil."""
    assume(abs(rate) > 1e-3)
    parameters = dict(compression=compression, rebound=ratio * compression)
    assert_partials(orifice_damper, (rate,), (0.01 * abs(rate),), **parameters)


@SETTINGS
@given(stroke=st.floats(-0.02, 0.2))
def test_end_stops_partial_and_energy(stroke):
    """Away from the kinks at S_min = 0 and S_max = 0.16 by more than the 1e-4 m stencil."""
    assume(min(abs(stroke), abs(stroke - 0.16)) > 2e-4)
    stops = dict(stiffness=1e8, lower=0.0, upper=0.16)
    assert_partials(end_stops, (stroke,), (1e-4,), **stops)
    estimate, tolerance = central_difference(lambda s: end_stops_energy(s, **stops), stroke, 1e-4)
    assert abs(end_stops(stroke, **stops)[0] - estimate) <= tolerance


@SETTINGS
@given(stroke=st.floats(-1e-3, 0.17), rate=st.floats(-5.0, 5.0))
def test_strut_partials_and_sum(stroke, rate):
    """The strut law is the sum of its three laws, its partials hold against differences,
    and its energy's derivative is its force at rest."""
    assume(min(abs(stroke), abs(stroke - 0.16)) > 2e-6 and abs(rate) > 1e-3)
    force, d_stroke, d_rate = STRUT(stroke, rate)
    parts = (
        gas_spring(stroke, **GAS)[0]
        + end_stops(stroke, stiffness=1e8, lower=0.0, upper=0.16)[0]
        + orifice_damper(rate, compression=5000.0, rebound=20000.0)[0]
    )
    assert force == parts
    assert_partials(lambda s, v: STRUT(s, v), (stroke, rate), (1e-6, 0.01 * abs(rate)))
    estimate, tolerance = central_difference(STRUT.energy, stroke, 1e-6)
    assert abs(STRUT(stroke, 0.0)[0] - estimate) <= tolerance


@SETTINGS
@given(deflection=st.floats(-0.05, 0.15), rate=st.floats(-5.0, 5.0))
def test_tyre_radial_partials_and_never_pulls(deflection, rate):
    """F_z >= 0, zero out of contact; partials away from d = 0 and the unloading kink."""
    force, _, _ = tyre_radial(deflection, rate, **TYRE)
    assert force >= 0.0
    if deflection <= 0:
        assert force == 0.0
    step = 1e-5
    push = TYRE["stiffness"] * deflection + TYRE["damping"] * rate
    assume(abs(deflection) > 2 * step)
    assume(abs(push) > 2 * step * (TYRE["stiffness"] + TYRE["damping"]))
    assert_partials(tyre_radial, (deflection, rate), (step, step), **TYRE)
    estimate, tolerance = central_difference(
        lambda d: tyre_energy(d, stiffness=TYRE["stiffness"]), deflection, step
    )
    assert abs(max(TYRE["stiffness"] * deflection, 0.0) - estimate) <= tolerance


@SETTINGS
@given(
    speed=st.floats(-50.0, 50.0),
    spin=st.floats(-300.0, 300.0),
    speed_eps=st.floats(0.01, 1.0),
)
def test_slip_ratio_partials(speed, spin, speed_eps):
    """Smooth everywhere: the stencil is 1 % of sqrt(u^2 + u_eps^2), the slip's scale."""
    scale = math.hypot(speed, speed_eps)
    parameters = dict(radius=RADIUS, speed_eps=speed_eps)
    assert_partials(slip_ratio, (speed, spin), (0.01 * scale, 1.0), **parameters)


@SETTINGS
@given(kappa=st.floats(-2.0, 2.0), B=st.floats(5.0, 15.0), C=st.floats(1.3, 1.9))
def test_friction_curve_partial(kappa, B, C):
    """The stencil is 1 % of 1 / B, the scale of the curve's rise."""
    assert_partials(friction_curve, (kappa,), (0.01 / B,), B=B, C=C, D=0.8)


@SETTINGS
@given(
    speed=st.floats(1.0, 50.0),
    fraction=st.floats(0.0, 1.2),
    normal=st.floats(100.0, 2e4),
)
def test_tyre_longitudinal_partials(speed, fraction, normal):
    """From a locked wheel (fraction 0) past rolling speed (fraction 1.2 of u / R0)."""
    spin = fraction * speed / RADIUS
    parameters = dict(radius=RADIUS, speed_eps=0.1, **CURVE)
    # the slip changes by 1e-3 over the steps, 1 % of the curve's scale 1 / B
    steps = (1e-3 * speed, 1e-3 * speed / RADIUS, 0.01 * normal)
    # near rolling the slip is a difference of the speeds over the forward one: it carries
    # ulps of 1 + omega R / u (at most 1.001 + fraction over the stencil), which the curve's
    # largest slope B C D and the normal force turn into the force's
    scale = normal * CURVE["B"] * CURVE["C"] * CURVE["D"] * (1.001 + fraction)
    assert_partials(tyre_longitudinal, (speed, spin, normal), steps, scale, **parameters)


@SETTINGS
@given(
    velocity=st.floats(-1.0, 1.0),
    normal=st.floats(100.0, 2e4),
    v_eps=st.floats(1e-4, 1e-2),
    mu_static=st.floats(0.01, 0.3),
    drop=st.floats(0.0, 1.0),
)
def test_friction_partials_and_dissipation(velocity, normal, v_eps, mu_static, drop):
    """Both friction laws: partials (stencil 1 % of v_eps), power F v <= 0, and Stribeck's
    law with mu_s = mu_k is Coulomb's (to a few ulps)."""
    mu_kinetic = (1.0 - drop) * mu_static
    coulomb = dict(mu=mu_static, v_eps=v_eps)
    stribeck = dict(mu_static=mu_static, mu_kinetic=mu_kinetic, v_stribeck=0.05, v_eps=v_eps)
    steps = (0.01 * v_eps, 0.01 * normal)
    assert_partials(coulomb_friction, (velocity, normal), steps, **coulomb)
    assert_partials(stribeck_friction, (velocity, normal), steps, **stribeck)
    for law, parameters in ((coulomb_friction, coulomb), (stribeck_friction, stribeck)):
        force = law(velocity, normal, **parameters)[0]
        assert force * velocity <= 0.0
    # to a few ulps: the two expressions associate their products differently
    same = dict(stribeck, mu_kinetic=mu_static)
    np.testing.assert_allclose(
        stribeck_friction(velocity, normal, **same),
        coulomb_friction(velocity, normal, **coulomb),
        rtol=4 * EPS,
    )


# ---- closed values ----------------------------------------------------------------------


def test_gas_spring_closed_values():
    """Preload A (p0 - p_atm) at S = 0 (the notes: 494 N), the force at S_max = 0.16 m (the
    notes: 15.8 kN), and the isothermal static stroke under a 2.45 kN nose load (131 mm)."""
    A, p0, V0, n = GAS["area"], GAS["pressure"], GAS["volume"], GAS["exponent"]
    preload = float(gas_spring(0.0, **GAS)[0])
    assert preload == pytest.approx(A * (p0 - P_ATM), rel=4 * EPS)
    assert round(preload) == 494
    at_max = float(gas_spring(0.16, **GAS)[0])
    assert at_max == pytest.approx(A * (p0 * (V0 / (V0 - A * 0.16)) ** n - P_ATM), rel=8 * EPS)
    assert round(at_max / 1e3, 1) == 15.8
    # n = 1: A (p0 V0 / (V0 - A S) - p_atm) = W  gives  S = (V0 - p0 V0 / (W / A + p_atm)) / A
    static = (V0 - p0 * V0 / (2450.0 / A + P_ATM)) / A
    assert round(static * 1e3) == 131
    isothermal = dict(GAS, exponent=1.0)
    assert float(gas_spring(static, **isothermal)[0]) == pytest.approx(2450.0, rel=1e-12)


def test_friction_curve_closed_values():
    """Peak D at kappa = tan(pi / (2 C)) / B (the notes: 0.8 at 0.14), locked wheel
    mu(1) = D sin(C atan B) (0.52), slope B C D (13.2) at zero slip."""
    B, C, D = CURVE["B"], CURVE["C"], CURVE["D"]
    peak = math.tan(math.pi / (2 * C)) / B
    mu, slope = friction_curve(peak, **CURVE)
    assert float(mu) == pytest.approx(D, rel=4 * EPS)
    assert abs(float(slope)) <= 16 * EPS * B * C * D
    assert round(peak, 2) == 0.14
    locked = float(friction_curve(1.0, **CURVE)[0])
    assert locked == pytest.approx(D * math.sin(C * math.atan(B)), rel=4 * EPS)
    assert round(locked, 2) == 0.52
    assert float(friction_curve(0.0, **CURVE)[1]) == pytest.approx(13.2, rel=4 * EPS)


def test_tyre_deflection_under_13_kN():
    """k_t d = 13 kN at d = 52 mm (the notes), at rest; a tyre being compressed adds c_t d'."""
    assert float(tyre_radial(0.052, 0.0, **TYRE)[0]) == pytest.approx(13e3, rel=4 * EPS)
    assert float(tyre_radial(0.052, 2.8, **TYRE)[0]) == pytest.approx(13e3 + 700.0, rel=4 * EPS)


def test_tyre_jumps_at_first_contact():
    """At d = 0+ with the axle sinking, the damper's c_t d' acts at once (the law's jump)."""
    assert float(tyre_radial(0.0, 2.8, **TYRE)[0]) == 0.0
    assert float(tyre_radial(1e-12, 2.8, **TYRE)[0]) == pytest.approx(700.0, rel=1e-6)


@SETTINGS
@given(speed=st.floats(1.0, 50.0), fraction=st.floats(0.0, 1.2))
def test_slip_ratio_is_the_issues_for_positive_speed(speed, fraction):
    """kappa = (u - w R0) / u to the regularisation's relative u_eps^2 / (2 u^2) (the
    series of 1 / sqrt(1 + x), first term; the next is 3/8 x^2, below it)."""
    eps = 0.1
    spin = fraction * speed / RADIUS
    kappa = float(slip_ratio(speed, spin, radius=RADIUS, speed_eps=eps)[0])
    exact = (speed - spin * RADIUS) / speed
    assert abs(kappa - exact) <= abs(exact) * (eps / speed) ** 2 / 2 + 4 * EPS


def test_slip_ratio_at_zero_speed():
    """A wheel spinning over still ground slides fully (-w R0 / u_eps); a still one does not."""
    kappa = slip_ratio(0.0, [10.0, 0.0], radius=RADIUS, speed_eps=0.1)[0]
    np.testing.assert_allclose(kappa, [-10.0 * RADIUS / 0.1, 0.0], rtol=4 * EPS)


@SETTINGS
@given(velocity=st.floats(1e-3, 1.0), normal=st.floats(1.0, 2e4))
def test_coulomb_limit(velocity, normal):
    """Beyond a few v_eps the force is -mu N sign(v) to the relative 2 exp(-2 |v| / v_eps)
    (1 - tanh x = 2 e^-2x / (1 + e^-2x))."""
    v_eps = 1e-4
    for v in (velocity, -velocity):
        force = float(coulomb_friction(v, normal, mu=0.02, v_eps=v_eps)[0])
        bound = 2 * math.exp(-2 * velocity / v_eps) + 4 * EPS
        assert abs(force + 0.02 * normal * math.copysign(1, v)) <= 0.02 * normal * bound


def test_laws_are_vectorised():
    """Arrays in, arrays of the broadcast shape out, each element the scalar law's."""
    strokes = np.linspace(-1e-4, 0.17, 7)
    force, d_stroke, d_rate = STRUT(strokes[:, None], np.array([-1.0, 0.0, 2.0]))
    assert force.shape == d_stroke.shape == d_rate.shape == (7, 3)
    assert force[4, 2] == STRUT(strokes[4], 2.0)[0]


# ---- bad input --------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: gas_spring(0.175, **GAS), r"gas spring: stroke 0.175 m leaves no gas.*V0 / A"),
        (lambda: gas_spring(0.2, **GAS), r"gas spring: stroke 0.2 m leaves no gas"),
        (lambda: gas_spring(0.0, **dict(GAS, area=-1.0)), "gas spring: area must be finite"),
        (lambda: gas_spring(np.nan, **GAS), "gas spring: stroke must be finite"),
        (lambda: gas_spring("a", **GAS), "gas spring: stroke must be finite numbers"),
        (
            lambda: orifice_damper(1.0, compression=-1.0, rebound=1.0),
            "orifice damper: compression",
        ),
        (
            lambda: end_stops(0.0, stiffness=1e8, lower=0.2, upper=0.1),
            r"end stops: lower \(0.2\) must be below upper",
        ),
        (lambda: tyre_radial(0.0, np.inf, **TYRE), "tyre radial force: rate must be finite"),
        (lambda: tyre_radial(0.0, 0.0, stiffness=0.0, damping=1.0), "tyre radial force: stiff"),
        (lambda: slip_ratio(1.0, 1.0, radius=RADIUS, speed_eps=0.0), "slip ratio: speed_eps"),
        (lambda: friction_curve(0.1, B=10, C=-1, D=0.8), "friction curve: C"),
        (
            lambda: tyre_longitudinal(1.0, 0.0, -5.0, radius=RADIUS, speed_eps=0.1, **CURVE),
            "tyre longitudinal force: normal force must be >= 0",
        ),
        (
            lambda: coulomb_friction(0.1, -1.0, mu=0.02, v_eps=1e-3),
            "coulomb friction: normal force must be >= 0",
        ),
        (lambda: coulomb_friction(0.1, 1.0, mu=0.02, v_eps=0.0), "coulomb friction: v_eps"),
        (
            lambda: stribeck_friction(
                0.1, 1.0, mu_static=0.1, mu_kinetic=0.2, v_stribeck=0.1, v_eps=1e-3
            ),
            r"stribeck friction: mu_static \(0.1\) must be >= mu_kinetic",
        ),
        (
            lambda: Strut(**GAS, compression=1.0, rebound=1.0, stop_stiffness=1e8, stroke_max=0.2),
            "gas spring: stroke 0.2 m leaves no gas",
        ),
    ],
)
def test_bad_input_is_refused_by_name(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_strut_refuses_a_stroke_limit_beyond_the_gas_column():
    """Not at construction (the check is at S_min) but at the first stroke past V0 / A."""
    strut = Strut(**GAS, compression=1.0, rebound=1.0, stop_stiffness=1e8, stroke_max=0.16)
    with pytest.raises(ValueError, match="gas spring: stroke 0.18 m"):
        strut(0.18, 0.0)


# ---- user laws --------------------------------------------------------------------------


def spring_damper(stroke, rate):
    return 2e4 * stroke + 1e3 * stroke**3 + 300.0 * rate * np.abs(rate)


def spring_damper_partials(stroke, rate):
    return 2e4 + 3e3 * stroke**2, 600.0 * np.abs(rate)


POINTS = [[0.0, 1.0], [0.05, -2.0], [0.15, 0.5]]


def test_user_law_accepts_a_right_derivative():
    """A strut-like law of (stroke, rate) is checked at three points and then evaluates like
    a built-in law: value and partials broadcast together."""
    law = UserLaw("spring-damper", spring_damper, spring_damper_partials, POINTS, [0.1, 1.0])
    assert law.arity == 2
    force, d_stroke, d_rate = law(np.array([0.0, 0.1]), 2.0)
    np.testing.assert_array_equal(force, spring_damper(np.array([0.0, 0.1]), 2.0))
    np.testing.assert_array_equal(d_rate, [1200.0, 1200.0])
    assert d_stroke.shape == (2,)


@pytest.mark.parametrize("error", [1e-6, -1e-3, 1.0])
def test_user_law_refuses_a_wrong_derivative(error):
    """A partial wrong by a relative 1e-6 (the differences' tolerance is below 1e-9 of the
    law's scale here) or by a factor is refused, naming the law, state and point."""

    def wrong(stroke, rate):
        d_stroke, d_rate = spring_damper_partials(stroke, rate)
        return d_stroke, d_rate * (1 + error)

    with pytest.raises(ValueError, match=r"user law 'sd': the partial in state 2 at \[0.0, 1.0\]"):
        UserLaw("sd", spring_damper, wrong, POINTS, [0.1, 1.0])


def test_user_law_refuses_a_point_at_a_jump():
    """Unregularised Coulomb friction checked at 1e-9 m/s from its jump: the check cannot
    judge there and says so (rather than accept the zero partial)."""
    with pytest.raises(ValueError, match="user law 'dry': cannot check the partial in state 1"):
        UserLaw("dry", lambda v: -100.0 * np.sign(v), lambda v: (0.0 * v,), [[1e-9]], [1.0])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(name=""), "user law: name must be a non-empty string"),
        (dict(scales=[0.1, -1.0]), "user law 'sd': scales must be positive"),
        (dict(points=[[0.0, 1.0, 2.0]]), r"points must be rows of 2 states"),
        (dict(points=[[0.0, np.nan]]), "user law 'sd': points must be finite"),
        (dict(derivative=lambda s, v: (s,)), "derivative must return 2 partials, got 1"),
        (dict(function=lambda s, v: s / 0.0), "user law 'sd': value must be finite"),
    ],
)
def test_user_law_bad_input(kwargs, message):
    arguments = dict(
        name="sd",
        function=spring_damper,
        derivative=spring_damper_partials,
        points=POINTS,
        scales=[0.1, 1.0],
    )
    with np.errstate(divide="ignore", invalid="ignore"), pytest.raises(ValueError, match=message):
        UserLaw(**(arguments | kwargs))


def test_user_law_call_checks_its_arity():
    law = UserLaw("sd", spring_damper, spring_damper_partials, POINTS, [0.1, 1.0])
    with pytest.raises(ValueError, match="user law 'sd': takes 2 states, got 1"):
        law(0.1)
