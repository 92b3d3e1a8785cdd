"""Modes about a solved state with sliders and force elements (sliders.solve.modes).

Tolerance sources:

* ``EIGEN`` (1e-9): a problem whose discrete answer is exact (a rigid body on a linear
  tyre spring: the linearisation of a linear law is exact; one dof): the eigen solvers'
  backward error, ``O(u kappa)`` with a condition number below 1e6 here, ``u = 2.2e-16``.
* Mesh convergence against the exact Timoshenko frequency equations
  (:mod:`fvbeam.closed_forms`): the observed order ``log2(e_n / e_2n)`` on n, 2n, 4n
  elements within 0.5 of the expected one (with the lumped mass: fv2, fv3, galerkin-p1 2,
  galerkin-p2 4, as the bare cantilever in ``tests/test_modes.py``; cubic 2, as the simply
  supported beam with rotary inertia in ``tests/test_simply_supported_modes.py``; the
  slider's body sits on a node, where its constraint is the clamp or pin of the
  reference), and the finest error below ``e_2n / 2^(p - 0.5)``.  A chain of cubic
  elements holds a body between its nodes too, through the line's compliance there (the
  exact response of the element to a point load, condensed by
  :func:`sliders.solve.modes.modes_about`): the same order 2 (measured 1.96 to 2.05 with the
  body at x = 0.61; fv3 and galerkin-p2, whose interpolation cannot kink inside an
  element, lose their order there: measured -0.9 to 4.3).
* The reduction against the bordered pencil it replaces (``[K + E, A; C_y, D]`` with the
  mass and damping on the structure's dofs only, all its finite eigenvalues by
  ``scipy.linalg.eigvals``): both backward stable, so each ``omega^2`` (damped: ``|s|``)
  within ``u cond(J)`` relatively (``u`` the unit roundoff, ``J`` the bordered matrix; 1e-9
  to 1e-8 here, measured differences 5e-13 to 1e-10), a damping ratio within that divided
  by the smallest ratio (measured 2e-11 to 1.4e-9).
* Free decay (generalized-alpha, ``rho_inf = 1``: the trapezoidal rule, which maps a root
  ``s`` to ``s_h = (2 / h) artanh(s h / 2) = s (1 + (s h)^2 / 12 + ...)``; with
  ``s = omega (-zeta + i sqrt(1 - zeta^2))`` that is ``|s_h| = omega (1 - (omega h)^2 / 12)``
  and ``zeta_h = zeta (1 - (omega h)^2 / 6)`` to leading order; with ``omega h = 2 pi / 64``:
  8.0e-4 and 1.6e-3, measured -8.0e-4 and -1.6e-3): each within twice its leading term.
"""

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import curve_fit

from fvbeam import Beam, RigidBody, Section, Structure, Support, closed_forms, formulation, straight
from sliders.forces.elements import Tyre
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics
from sliders.solve.modes import PRELOAD_WARNING, modes_about
from sliders.solve.statics import SliderStatics

EIGEN = 1e-9
#: Bending: EJ = m = 1, s^2 = EJ / (GA L^2) = 0.01, rotary inertia 1e-3 per length; axial and
#: torsional stiffness high enough that their modes lie above the bending ones compared.
EJ, GA, RHO_J = 1.0, 100.0, 1e-3


def section() -> Section:
    return Section.diagonal(
        EA=1e5,
        GAy=GA,
        GAz=GA,
        GJ=1e2,
        EJy=EJ,
        EJz=EJ,
        mass_per_length=1.0,
        inertia=np.diag([2 * RHO_J, RHO_J, RHO_J]),
        name="steel",
    )


def parts(name: str, n: int, a: float, kind: str) -> tuple[Structure, list, list]:
    """A beam of length 1 along x, ``n`` elements, whose node at ``x = a`` carries a fixed
    body held by a ``kind`` slider; clamped at 0 for a spherical slider, else held at 0 in
    ``ux`` and ``rx`` only (the classical slider leaves the sliding and the turn about the
    axis free): the structure, its supports and its slider."""
    mesh = straight((0, 0, 0), (1, 0, 0), n, formulation(name).nodes_per_element)
    b = Beam(mesh, section(), name)
    hub = RigidBody("hub", (a, 0.0, 0.0), mass=1.0)
    structure = Structure([b], bodies=[hub])
    held = Support(0, "start") if kind == "spherical" else Support(0, "start", "ux+rx")
    slider = Slider(kind, BeamChain(structure, 0), "hub", name="S")
    return structure, [held, Support("hub")], [slider]


def slider_beam(name: str, n: int, a: float, kind: str) -> tuple[SliderStatics, int]:
    structure, supports, sliders = parts(name, n, a, kind)
    return SliderStatics(structure, supports, sliders), structure.beams[0].mesh.n_nodes


def solve_modes(statics: SliderStatics, count: int, **options):
    return modes_about(statics, statics.solve(np.zeros(statics.structure.n_dofs)), count, **options)


def pairs(omega: np.ndarray) -> np.ndarray:
    """Bending frequencies come in equal pairs (the two planes): one of each."""
    np.testing.assert_allclose(omega[0::2], omega[1::2], rtol=1e-8)
    return omega[0::2]


#: The slider's body: at x = 0.6, a node of every mesh of 10, 20, 40 elements.
A = 0.6
#: Expected orders with the lumped mass (module docstring).
ORDERS = {"fv2": 2, "fv3": 2, "galerkin-p1": 2, "galerkin-p2": 4, "cubic": 2}
#: A body between the nodes of every mesh of 10, 20, 40 elements.
BETWEEN = 0.61


def assert_order(name: str, errors: list[np.ndarray]) -> None:
    order = ORDERS[name]
    for coarse, fine in zip(errors, errors[1:], strict=False):
        observed = np.log2(coarse / fine)
        assert np.all(np.abs(observed - order) < 0.5), observed
    assert np.all(errors[2] < errors[1] / 2 ** (order - 0.5))


ON_NODES = [(name, A) for name in ORDERS] + [("cubic", BETWEEN)]


@pytest.mark.parametrize("name,a", ON_NODES)
def test_a_classical_slider_held_inside_a_beam_makes_two_cantilevers(name, a):
    exact = np.sort(
        np.concatenate(
            [
                closed_forms.timoshenko_cantilever_frequencies(
                    2, L=length, EJ=EJ, GA=GA, rhoJ=RHO_J
                )
                for length in (a, 1 - a)
            ]
        )
    )
    errors = []
    for n in (10, 20, 40):
        statics, _ = slider_beam(name, n, a, "classical")
        errors.append(np.abs(pairs(solve_modes(statics, 8).omega) / exact - 1))
    assert_order(name, errors)


@pytest.mark.parametrize("name,a", ON_NODES)
def test_a_spherical_slider_is_a_pinned_intermediate_support(name, a):
    step = 3.5160 * np.sqrt(EJ) / 200  # the grid of the cantilever's frequency equation
    exact = closed_forms.frequency_roots(
        closed_forms.timoshenko_pinned_cantilever_determinant, 3, step, (a, 1.0, EJ, GA, 1.0, RHO_J)
    )
    errors = []
    for n in (10, 20, 40):
        statics, _ = slider_beam(name, n, a, "spherical")
        errors.append(np.abs(pairs(solve_modes(statics, 6).omega) / exact - 1))
    assert_order(name, errors)


@pytest.mark.filterwarnings("ignore:modes about a loaded state")
@pytest.mark.parametrize("damping", [0.0, 4e-3])
@pytest.mark.parametrize("a", [A, BETWEEN])
@pytest.mark.parametrize("kind", ["classical", "spherical"])
@pytest.mark.parametrize("name", ["fv3", "galerkin-p1", "cubic"])
def test_the_reduction_has_the_bordered_pencils_roots_about_a_loaded_state(name, kind, a, damping):
    """About a state loaded at the free end (the sliders' terms in their multipliers, a
    cubic line's compliance between nodes, the kink correction of a classical slider), the
    six lowest roots are the bordered pencil's lowest finite ones (module docstring):
    undamped ``omega^2``; with the beams' damping (not proportional once the sliders add
    stiffness: complex modes) the roots ``s`` of the first-order form, ``|s|`` and the
    damping ratio ``-Re s / |s|``, which carries the error of ``Re s`` divided by itself."""
    statics, _ = slider_beam(name, 6, a, kind)
    solution = statics.solve(statics.structure.nodal_load("beam.end", (0.0, 1.0, 0.3)))
    J = statics.jacobian(solution.q, solution.unknowns).toarray()
    free, N = statics.free, J.shape[0]
    M, C = np.zeros_like(J), np.zeros_like(J)
    M[: len(free), : len(free)] = statics.structure.mass("lumped")[free][:, free].toarray()
    C[: len(free), : len(free)] = damping * statics.K_free.toarray()
    modes = modes_about(statics, solution, 6, damping=damping)
    tol = np.finfo(float).eps / 2 * np.linalg.cond(J)
    if damping == 0:
        s = sla.eigvals(J, M)
        s = np.sort(s[np.isfinite(s)].real)
        np.testing.assert_allclose(modes.omega**2, s[s > 0][:6], rtol=tol)
        return
    Z, eye = np.zeros((N, N)), np.eye(N)
    s = sla.eigvals(np.block([[Z, eye], [-J, -C]]), np.block([[eye, Z], [Z, M]]))
    s = s[np.isfinite(s) & (s.imag > 0)]
    s = s[np.argsort(np.abs(s))][:6]
    zeta = -s.real / np.abs(s)
    assert modes.complex
    np.testing.assert_allclose(modes.omega, np.abs(s), rtol=tol)
    np.testing.assert_allclose(modes.damping_ratio, zeta, rtol=tol / zeta.min())


def body_on_tyre(damping: float) -> tuple[SliderStatics, np.ndarray]:
    """A body of mass 2 free only in uz, on a tyre of stiffness 800 pressed 0.01 into the
    ground by a load that balances it at q = 0."""
    radius, deflection, k = 0.3, 0.01, 800.0
    body = RigidBody("hub", (0.0, 0.0, radius - deflection), mass=2.0, inertia=np.eye(3))
    structure = Structure([], bodies=[body])
    tyre = Tyre("hub", "hub", radius, k, damping, B=10.0, C=1.9, D=1.0)
    statics = SliderStatics(structure, [Support("hub", kind="ux+uy+rx+ry+rz")], [], forces=[tyre])
    f = structure.nodal_load("hub", (0.0, 0.0, -k * deflection))
    return statics, f


@pytest.mark.filterwarnings("ignore:modes about a loaded state")  # the tyre's preload
@pytest.mark.parametrize("c", [0.0, 8.0])
def test_a_body_on_a_tyre_spring_has_the_oscillator_frequency_and_damping_ratio(c):
    statics, f = body_on_tyre(c)
    modes = modes_about(statics, statics.solve(f), 1)
    k, m = 800.0, 2.0
    np.testing.assert_allclose(modes.omega, [np.sqrt(k / m)], rtol=EIGEN)
    np.testing.assert_allclose(modes.damping_ratio, [c / (2 * np.sqrt(k * m))], rtol=EIGEN)
    assert modes.complex == (c > 0)


def test_free_decay_of_the_time_integration_gives_the_first_frequency_and_damping_ratio():
    """The two-cantilever beam with stiffness-proportional damping (proportional on the
    motions the slider leaves free too: real modes, ``zeta = damping omega / 2``), started
    on its first mode ``q = Re(eps phi e^{s t})`` at ``t = 0`` and integrated
    (``rho_inf = 1``, 64 steps a period, 6 periods): the modal coordinate's fit
    ``e^{-zeta omega t} (a cos + b sin)(omega sqrt(1 - zeta^2) t)`` gives ``omega`` and
    ``zeta`` (module docstring)."""
    structure, supports, sliders = parts("fv3", 10, A, "classical")
    statics = SliderStatics(structure, supports, sliders)
    damping = 4e-3  # zeta = 0.02 on the first mode, 0.12 on the next distinct one
    modes = solve_modes(statics, 1, damping=damping)
    assert not modes.complex
    omega, zeta = modes.omega[0], modes.damping_ratio[0]
    s = omega * (-zeta + 1j * np.sqrt(1 - zeta**2))
    phi = 1e-6 * modes.shapes[:, 0] / np.abs(modes.shapes[:, 0]).max()
    dynamics = Dynamics(structure, supports, sliders, damping=damping, rho_inf=1.0)
    state = dynamics.state(phi.real, (s * phi).real, qdd=(s * s * phi).real)
    period = 2 * np.pi / s.imag
    h = period / 64
    M = dynamics.M
    weight = M @ phi.real / (phi.real @ M @ phi.real)
    t, a = [0.0], [weight @ state.q]
    for _ in range(6 * 64):
        state = dynamics.step(state, h)
        t.append(state.t)
        a.append(weight @ state.q)

    def decay(t, w, z, p, r):
        wd = w * np.sqrt(1 - z**2)
        return np.exp(-z * w * t) * (p * np.cos(wd * t) + r * np.sin(wd * t))

    (w_fit, z_fit, _, _), _ = curve_fit(decay, np.array(t), np.array(a), p0=(omega, zeta, 1, 0))
    leading = (omega * h) ** 2 / 12  # module docstring
    assert abs(w_fit / omega - 1) < 2 * leading
    assert abs(z_fit / zeta - 1) < 2 * (2 * leading)


def test_modes_about_a_loaded_state_warn_that_the_preload_is_left_out():
    statics, _ = slider_beam("fv3", 4, A, "spherical")
    f = statics.structure.nodal_load("beam.end", (0.0, 1.0, 0.0))
    with pytest.warns(UserWarning, match="geometric stiffness"):
        modes_about(statics, statics.solve(f), 2)
    assert "not included" in PRELOAD_WARNING


def test_bad_arguments_are_named():
    statics, _ = slider_beam("fv3", 4, A, "spherical")
    solution = statics.solve(np.zeros(statics.structure.n_dofs))
    for options, message in (
        (dict(count=0), "count must be an integer >= 1"),
        (dict(count=2, damping=-1.0), "damping must be"),
        (dict(count=2, window=(3.0, 1.0)), "window must be"),
    ):
        with pytest.raises(ValueError, match=message):
            modes_about(statics, solution, **options)
