"""Slider friction's term of the ``xi`` equation (:mod:`sliders.joints.friction`): the
compiled form generated from the statement (:mod:`sliders.joints.generate`) against the
statement run in numpy to roundoff, its partials against central differences of the
statement, the limits (the friction opposes the sliding, is bounded by ``mu N``, and
vanishes without a transverse reaction or without sliding).

Tolerances: the two evaluate the same expressions in another order (``16 eps`` of the largest
term); a central difference of step ``h = 1e-6`` of the inputs' scale errs by ``h^2 f''' / 6``
plus ``eps |f| / h``: below ``1e-7`` of the largest partial for these smooth laws (``v_eps``
is kept above a hundredth of the sliding speeds drawn)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from sliders.forces.laws import stribeck_friction
from sliders.joints.compiled_laws import friction_at
from sliders.joints.friction import friction_term

EPS = np.finfo(float).eps
vectors = st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3).map(np.array)


@settings(max_examples=150, deadline=None, derandomize=True)
@given(
    vectors,
    vectors,
    vectors,
    st.floats(0.01, 0.5),
    st.floats(0.05, 1.0),
    st.floats(0.0, 0.5),
    st.floats(0.1, 1.0),
)
def test_compiled_equals_reference_and_partials_are_derivatives(
    l, w, lam, mu, v_eps, rise, v_stribeck
) -> None:
    """Coulomb's law (``rise = 0``) and the Stribeck curve (``mu_static = mu + rise``)."""
    law = (mu, v_eps, mu + rise, v_stribeck)
    l = l + np.array([1.0, 0.0, 0.0]) * (np.linalg.norm(l) < 0.5)  # a line: |l| away from 0
    across = lam - (lam @ l) * l / (l @ l)
    if np.linalg.norm(across) < 0.1:  # a transverse reaction: |N| away from 0 (its kink)
        perp = max((np.cross(l, e) for e in np.eye(3)), key=np.linalg.norm)
        lam = lam + perp / np.linalg.norm(perp)
    e, F = friction_term(l, w, lam, *law)
    got = [np.zeros(3), np.zeros(3), np.zeros(3)]
    e2, F2 = friction_at(l, w, lam, *law, *got)
    scale = max(abs(e), np.abs(np.concatenate(got)).max(), 1.0)
    assert abs(e2 - e) <= 16 * EPS * scale and abs(F2 - F) <= 16 * EPS * scale
    h = 1e-6
    for index, partial in enumerate(got):
        for c in range(3):
            step = np.zeros(3)
            step[c] = h
            args = [l, w, lam]
            plus = [a + step if i == index else a for i, a in enumerate(args)]
            minus = [a - step if i == index else a for i, a in enumerate(args)]
            fd = (friction_term(*plus, *law)[0] - friction_term(*minus, *law)[0]) / (2 * h)
            assert abs(fd - partial[c]) <= 1e-7 * scale


def test_the_stribeck_curve_is_the_force_laws() -> None:
    """With stick-slip the joint's friction is :func:`sliders.forces.laws.stribeck_friction`
    of the sliding speed along the line and the transverse reaction, to roundoff."""
    l, lam = np.array([0.0, 2.0, 0.0]), np.array([3.0, 0.5, -4.0])  # N = 5
    for slide in (-0.3, -2e-3, 1e-4, 5e-3, 0.05):
        w = np.array([0.4, slide, -0.2])
        F = friction_term(l, w, lam, 0.1, 1e-3, 0.25, 0.02)[1]
        law = stribeck_friction(
            slide, 5.0, mu_static=0.25, mu_kinetic=0.1, v_stribeck=0.02, v_eps=1e-3
        )
        assert abs(F - float(law[0])) <= 16 * EPS * 0.25 * 5.0


def test_the_friction_opposes_the_sliding_and_is_bounded() -> None:
    l, lam = np.array([2.0, 0.0, 0.0]), np.array([0.3, -4.0, 3.0])  # N = 5
    for slide in (-1.0, -1e-3, 1e-3, 1.0):
        F = friction_term(l, np.array([slide, 0.7, 0.0]), lam, 0.02, 1e-2)[1]
        assert F * slide < 0 and abs(F) <= 0.02 * 5.0
    assert friction_term(l, np.array([1.0, 0, 0]), np.array([1.0, 0, 0]), 0.02, 1e-2)[1] == 0.0
    assert friction_term(l, np.array([0.0, 1.0, 0]), lam, 0.02, 1e-2)[1] == 0.0
