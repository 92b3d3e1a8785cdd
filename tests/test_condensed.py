"""The condensed Newton back end against the bordered one; rigid modes; load stepping.

Agreement tolerance (derived, per solve): two converged Newton states ``z_a``, ``z_b`` of the
same equations differ by ``J^{-1} (r_a - r_b)`` to first order.  Each back end stops with a
residual below ``rho scale`` in every component (``rho``: its last recorded scaled residual,
``scale``: the largest load), and the residual itself is evaluated with a rounding error of at
most ``n_row eps (|K| |q|)`` (dot products of at most ``n_row`` terms, Higham's ``gamma_n``).
Hence ``|z_a - z_b|_i <= (|J^{-1}| 1)_i ((rho_a + rho_b) scale + 2 n_row eps max(|K| |q|))``,
with ``J`` the bordered Newton matrix at the solution (:meth:`SliderStatics.jacobian`).
The rounding term (about 1e-7 N here) also covers the rounding of the joints' own equations
(of order ``eps |lambda|`` and ``eps |x|``).  The bound is rigorous to first order and loose
(measured differences are about 1e-5 of it) because every component is given the largest
residual; it still sits 4-5 orders below the solution.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from test_sliders import SECTION, L, sliding_beams_model

from fvbeam import Beam, RigidBody, Structure, Support, straight
from fvbeam.mechanism import node_positions, rigid_modes
from sliders.joints.slider import Slider
from sliders.lines.rigid import CircularArc
from sliders.solve.statics import NUMERICALLY_SINGULAR, SliderStatics, rcond_estimate

EPS = np.finfo(float).eps


def agreement_bound(statics, a, b, f):
    """Componentwise bound on ``[q_free; y]`` between solutions ``a`` and ``b`` (module doc)."""
    J = statics.jacobian(a.q, a.unknowns).toarray()
    K = abs(statics.K)
    n_row = int(np.diff(statics.K.indptr).max())
    rounding = n_row * EPS * max((K @ abs(a.q)).max(), (K @ abs(b.q)).max())
    scale = np.abs(f).max()
    return np.abs(np.linalg.inv(J)).sum(axis=1) * (
        (a.residuals[-1] + b.residuals[-1]) * scale + 2 * rounding
    )


def state(statics, solution):
    return np.concatenate([solution.q[statics.free]] + list(solution.unknowns))


@pytest.mark.parametrize("kind", ["spherical", "classical"])
@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
@pytest.mark.parametrize("s", [0.0, 0.3, 0.77])
def test_condensed_equals_bordered_on_sliding_beams(kind, name, s):
    """The piston is held only by its sliders (4 free rigid modes): same solution to the
    derived roundoff bound, same Newton iteration count."""
    structure, supports, sliders, P = sliding_beams_model(s * L, 3, kind, name)
    f = structure.gather(1, P.nodal_load("end", (0, 1.0e3, 0)))
    bordered = SliderStatics(structure, supports, sliders)
    a = bordered.solve(f)
    b = SliderStatics(structure, supports, sliders, method="condensed").solve(f)
    assert b.iterations == a.iterations
    difference = np.abs(state(bordered, a) - state(bordered, b))
    assert np.all(difference <= agreement_bound(bordered, a, b, f))


def tip_on_an_arc(kind):
    """A beam clamped at its start, its tip sliding on a rigid arc; the tip load."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, 3), SECTION, "fv3")
    structure = Structure([beam])
    frame = np.column_stack([[-1.0, 0, 0], [0, 1.0, 0], [0, 0, -1.0]])
    slider = Slider(
        kind,
        CircularArc((1, -2, 0), 2.0, np.pi / 2 - 0.3, np.pi / 2 + 0.3),
        (0, "end"),
        frame=frame,
        name="tip",
    )
    return structure, slider, structure.gather(0, beam.nodal_load("end", force=(3.0, 1.0e3, 2.0e2)))


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_condensed_equals_bordered_without_free_parts(kind):
    """A clamped beam's tip on a rigid arc: K is regular (no rigid modes), C_TT = K^-1_TT."""
    structure, slider, f = tip_on_an_arc(kind)
    bordered = SliderStatics(structure, [Support(0, "start")], [slider])
    condensed = SliderStatics(structure, [Support(0, "start")], [slider], method="condensed")
    assert condensed._condensed.n_rigid == 0
    a, b = bordered.solve(f), condensed.solve(f)
    assert b.iterations == a.iterations
    difference = np.abs(state(bordered, a) - state(bordered, b))
    assert np.all(difference <= agreement_bound(bordered, a, b, f))


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p1", "galerkin-p2"])
def test_rigid_modes_span_both_null_spaces(name):
    """The piston keeps 6 - 2 rigid motions (ux, rx held); the cylinder is clamped.
    K Phi = 0 and Phi^T K = 0 up to rounding (|Phi| <= 1): a row product of n_row terms
    rounds by n_row eps max|K| (gamma_n), and each entry carries the rounding of its
    assembly, at most 2 n_q terms (two elements share a node, n_q = 3 stiffness points per
    element at most: fv3's evaluation points): n_row (1 + 2 n_q) eps max|K|.  Phi comes from
    Householder QR, orthonormal to c n eps (Higham, Accuracy and Stability, Sec. 19.3;
    c = 10 taken for the small constant there)."""
    structure, supports, _, _ = sliding_beams_model(0.3 * L, 3, "spherical", name)
    statics = SliderStatics(structure, supports, [])
    phi = rigid_modes(structure, statics.free).phi
    assert phi.shape == (len(statics.free), 4)
    np.testing.assert_allclose(phi.T @ phi, np.eye(4), atol=10 * len(statics.free) * EPS)
    K = statics.K[statics.free][:, statics.free]
    n_row = int(np.diff(K.tocsr().indptr).max())
    bound = n_row * (1 + 2 * 3) * EPS * abs(K).max()
    assert np.abs(K @ phi).max() <= bound
    assert np.abs(K.T @ phi).max() <= bound


def test_singular_configuration_gives_the_same_diagnostic():
    """The singular classical pair of the slope form (tests/test_sliders.py): the small system
    is singular and the condensed back end names the same free motion as the bordered one."""
    structure, supports, sliders, P = sliding_beams_model(
        0.9 * L, 1, "classical", orientation="slope"
    )
    f = structure.gather(1, P.nodal_load("end", (0, 1.0, 0)))
    messages = []
    for method in ("bordered", "condensed"):
        with pytest.raises(ValueError, match="singular configuration") as info:
            SliderStatics(structure, supports, sliders, method=method).solve(f)
        messages.append(str(info.value))
    assert messages[0] == messages[1]


@pytest.mark.parametrize("method", ["bordered", "condensed"])
@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_load_steps_reach_the_one_step_solution(method, kind):
    """Static equilibrium has no path dependence (linear beams, frictionless sliders): 4 load
    increments end at the one-step solution, within the same derived agreement bound."""
    structure, supports, sliders, P = sliding_beams_model(0.43 * L, 3, kind)
    f = structure.gather(1, P.nodal_load("end", (0, 1.0e3, 0)))
    statics = SliderStatics(structure, supports, sliders, method=method)
    one, stepped = statics.solve(f), statics.solve(f, load_steps=4)
    assert len(stepped.step_iterations) == 4
    assert stepped.iterations == sum(stepped.step_iterations)
    difference = np.abs(state(statics, one) - state(statics, stepped))
    assert np.all(difference <= agreement_bound(statics, one, stepped, f))


def test_bad_input():
    structure, supports, sliders, P = sliding_beams_model(0.3 * L, 1, "spherical")
    with pytest.raises(ValueError, match="method must be one of"):
        SliderStatics(structure, supports, sliders, method="dense")
    statics = SliderStatics(structure, supports, sliders, method="condensed")
    f = structure.gather(1, P.nodal_load("end", (0, 1.0, 0)))
    for steps in (0, 2.5, -1):
        with pytest.raises(ValueError, match="load_steps must be a positive integer"):
            statics.solve(f, load_steps=steps)
    with pytest.raises(ValueError, match="load vector must be finite"):
        statics.solve(f[:-1])


def test_unsupported_beam_keeps_six_rigid_modes():
    """No support at all: the six rigid motions of the beam, and B is regular."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")
    statics = SliderStatics(Structure([beam]), [], [], method="condensed")
    assert statics._condensed.n_rigid == 6


def test_node_positions_hold_the_rigid_bodies():
    """Beam nodes at their mesh points, a body tied to a beam node at that (coincident)
    point, a lone body at its own position: exact copies."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")
    structure = Structure(
        [beam],
        ties=[((0, "end"), "tip")],
        bodies=[RigidBody("tip", (1.0, 0, 0)), RigidBody("hub", (3, 4, 5))],
    )
    x = node_positions(structure)
    np.testing.assert_array_equal(x[structure.node_dofs((0, "start"))[0] // 6], [0, 0, 0])
    np.testing.assert_array_equal(x[structure.node_dofs("tip")[0] // 6], [1, 0, 0])
    np.testing.assert_array_equal(x[structure.node_dofs("hub")[0] // 6], [3, 4, 5])


def test_the_bordered_condition_estimate_tells_singular_from_ill_scaled():
    """:func:`sliders.solve.statics.rcond_estimate`: on a regular matrix with rows scaled
    1e9 : 1 (a stiffness bordered by unit constraint rows) it is the equilibrated matrix's
    reciprocal 1-norm condition number from above (Hager's estimate of ``|A^-1|_1`` is a
    lower bound) and within a factor 10 of it (the estimator is typically within 3, Higham,
    Sec. 15.3); on a matrix whose last row is the sum of the others (exactly singular, made
    nonsingular by the rounding of that sum) it is below the unit roundoff, the threshold of
    the bordered step (a matrix singular to working precision)."""
    rng = np.random.default_rng(4)
    n = 30
    A = rng.standard_normal((n, n)) + 5 * np.eye(n)
    A[: n // 2] *= 1e9
    S = sp.csc_matrix(A)
    rows = np.abs(A).max(axis=1, keepdims=True)
    E = A / rows
    E = E / np.abs(E).max(axis=0)
    exact = 1.0 / np.linalg.cond(E, 1)
    estimate = rcond_estimate(S, spla.splu(S))
    assert exact * (1 - 1e-9) <= estimate <= 10 * exact
    B = rng.standard_normal((n, n))
    B[-1] = B[:-1].sum(axis=0)
    lu = spla.splu(sp.csc_matrix(B))  # a pivot of roundoff's size, not zero
    assert np.abs(lu.U.diagonal()).min() > 0
    assert rcond_estimate(sp.csc_matrix(B), lu) < NUMERICALLY_SINGULAR
