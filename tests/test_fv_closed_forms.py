"""Finite-volume cantilevers against the paper's closed forms (Secs. 5.1-5.3, docs/theory.md).

Tolerances: the fv responses below are exact identities of the discrete scheme, so the only
error is roundoff in a solve whose condition number is at most ~1e4 for these stiffness
ratios: 1e-10 relative leaves a margin of ~1e2 over 1e4 x 2.2e-16.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fvbeam import Beam, LinearStatics, Section, Support, closed_forms, straight
from fvbeam.elements import evaluation_points

ROUNDOFF = 1e-10


def cantilever(name: str, n: int, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0):
    npe = 2 if name in ("fv2", "galerkin-p1") else 3
    section = Section.diagonal(EA=1e3 * GA, GAy=GA, GAz=GA, GJ=EJ, EJy=EJ, EJz=EJ)
    beam = Beam(straight((0, 0, 0), (L, 0, 0), n, npe), section, name)
    return beam, LinearStatics(beam, [Support(0, "start")])


def tip(beam, statics, xi, L, force=(0.0, 1.0, 0.0), moment=(0.0, 0.0, 0.0)):
    q = statics.solve(beam.point_load(xi, force=force, moment=moment))
    return q, beam.displacements(q, L)[0]


def close(actual, expected, rtol=ROUNDOFF, scale=1.0):
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * scale)


@pytest.mark.parametrize(
    "name,closed_form", [("fv2", closed_forms.cantilever_fv2), ("fv3", closed_forms.cantilever_fv3)]
)
@settings(max_examples=60, deadline=None)
@given(
    fraction=st.floats(0.0, 1.0),
    L=st.floats(0.2, 5.0),
    EJ=st.floats(0.5, 20.0),
    GA=st.floats(0.5, 20.0),
)
def test_one_element_matches_paper_sections_5_2_5_3_and_eq_T9(
    name, closed_form, fraction, L, EJ, GA
):
    beam, statics = cantilever(name, 1, L, EJ, GA)
    _, u = tip(beam, statics, fraction * L, L)
    flex, shear, phi = closed_form(fraction * L, L, EJ, GA)
    close(u[1], flex + shear, scale=L**3 / EJ + L / GA)
    close(u[5], phi, scale=L**2 / EJ)


@pytest.mark.parametrize("fraction", [0.3, 0.5, 0.7])
def test_three_node_between_evaluation_points_eq_T9(fraction):
    """The case the paper leaves out, a < xi < b, against the derivation in docs/theory.md."""
    a, b = evaluation_points(3)
    assert a < fraction < b
    beam, statics = cantilever("fv3", 1)
    _, u = tip(beam, statics, fraction, 1.0)
    close(u[1], b * (fraction - a) / 2 + 0.5)
    close(u[5], (fraction - a) / 2)


@pytest.mark.parametrize("name", ["fv2", "fv3"])
@pytest.mark.parametrize("n", [1, 3, 7])
@pytest.mark.parametrize("fraction", [0.137, 0.5, 0.861, 1.0])
def test_internal_forces_at_evaluation_points_are_exact(name, n, fraction):
    """Paper Sec. 5.4: 'always recovered exactly', for any number of elements."""
    beam, statics = cantilever(name, n)
    q, _ = tip(beam, statics, fraction, 1.0)
    forces = beam.internal_forces(q)
    shear, moment = closed_forms.cantilever_internal_forces(forces.xi, fraction)
    close(forces.force[:, 1], shear)
    close(forces.moment[:, 2], moment)
    close(forces.force[:, [0, 2]], 0.0)


@pytest.mark.parametrize("name", ["fv2", "fv3"])
def test_shear_part_is_carried_in_steps_of_the_evaluation_points(name):
    """Exact discrete identity: v_shear = F/GA * sum of the Gauss weights of the evaluation
    points upstream of the load (each carries S = F, paper Sec. 5.4)."""
    n = 5
    points = evaluation_points(2 if name == "fv2" else 3)
    weight = 1.0 / (n * len(points))
    for fraction in (0.05, 0.33, 0.62, 0.97):
        v = [tip(*cantilever(name, n, GA=GA), fraction, 1.0)[1][1] for GA in (1.0, 2.0)]
        shear = 2 * (v[0] - v[1])
        upstream = ((np.arange(n)[:, None] + points) / n < fraction).sum()
        close(shear, upstream * weight)


@pytest.mark.parametrize("n", [1, 3, 6])
def test_three_node_is_exact_for_tip_nodal_and_uniform_loads(n):
    """fv3: curvature is linear between the 2-point Gauss evaluation points, which integrate
    the tip response of a piecewise-linear or quadratic moment exactly (docs/theory.md)."""
    beam, statics = cantilever("fv3", n)
    for xi in np.arange(1, n + 1) / n:
        _, u = tip(beam, statics, xi, 1.0)
        flex, shear, phi = closed_forms.cantilever_exact(xi)
        close(u[[1, 5]], [flex + shear, phi])
    u = beam.displacements(statics.solve(beam.distributed_load(force=(0, 1, 0))), 1.0)[0]
    close(u[[1, 5]], [1 / 8 + 1 / 2, 1 / 6])


def observed_order(errors, ns):
    return -np.polyfit(np.log(ns), np.log(errors), 1)[0]


@pytest.mark.parametrize("name,flexural_order", [("fv2", 2), ("fv3", 2)])
def test_convergence_to_the_exact_timoshenko_cantilever(name, flexural_order):
    """Paper Sec. 5.1 closed form; the load sits at a fixed relative position (0.3) inside
    an element near 0.7 L.  Observed orders are asserted to the nearest integer (|p - p0| <
    0.5): flexural part 2, shear part 1 (steps of the evaluation-point spacing)."""
    ns = np.array([8, 16, 32, 64])
    flex_err, shear_err = [], []
    for n in ns:
        xi = (round(0.7 * n) + 0.3) / n
        v = [tip(*cantilever(name, n, GA=GA), xi, 1.0)[1][1] for GA in (1.0, 2.0)]
        shear = 2 * (v[0] - v[1])
        exact_flex, exact_shear, _ = closed_forms.cantilever_exact(xi)
        flex_err.append(abs(v[0] - shear - exact_flex) / exact_flex)
        shear_err.append(abs(shear - exact_shear) / exact_shear)
    assert abs(observed_order(flex_err, ns) - flexural_order) < 0.5
    assert abs(observed_order(shear_err, ns) - 1) < 0.5
    assert flex_err[-1] < flex_err[0] and shear_err[-1] < shear_err[0]


@pytest.mark.parametrize("name", ["galerkin-p1", "galerkin-p2"])
def test_reduced_galerkin_converges_with_consistent_loads(name):
    """Reduced Galerkin with consistent loads: shear part exact; flexural part order 2
    (P1, one-point rule) and at least 2 (P2, 2-point rule; measured 3 on average)."""
    ns = np.array([8, 16, 32, 64])
    errors = []
    for n in ns:
        xi = (round(0.7 * n) + 0.3) / n
        v = [tip(*cantilever(name, n, GA=GA), xi, 1.0)[1][1] for GA in (1.0, 2.0)]
        exact_flex, exact_shear, _ = closed_forms.cantilever_exact(xi)
        close(2 * (v[0] - v[1]), exact_shear, rtol=1e-9)
        errors.append(abs(v[0] - 2 * (v[0] - v[1]) - exact_flex) / exact_flex)
    assert observed_order(errors, ns) > 2 - 0.5
