"""The arc-length option of the exact static solver (fvbeam.exact_statics) through a limit
point with a closed form: the snap-through of a shallow two-bar (von Mises) truss.

The truss: feet pinned at ``(-a, 0)`` and ``(a, 0)``, apex at ``(0, h)``, a dead load ``P``
down at the apex, bars of ``EA`` with ``EA L0^2 / EJ = 1e8`` (slender members, on the
round-off floor).  Each bar is one fv2 element of one beam with its kink at the apex.  With
the apex at height ``y`` a bar's length is ``L = sqrt(a^2 + y^2)``, its axial force
``N = EA (L / L0 - 1)`` (the strain ``nu = Lambda^T x' - x0'`` of a straight element along its
chord) and the apex balance::

    P(y) = 2 EA y (1 / L - 1 / L0),

whose maximum, where ``(a^2 + y^2)^(3/2) = a^2 L0``, is the limit load
``P_lim = 2 EA y* (1 / L* - 1 / L0)``, ``L* = (a^2 L0)^(1/3)``.  Past it the apex snaps
through to the inverted branch.  A shallow truss snaps symmetrically: the sideways mode's
stiffness ``2 EA a^2 / L^3`` exceeds the compression's ``2 |N| / L`` there
(``a^2 / L*^2 = 0.93 > 1 - L* / L0 = 0.07`` for the truss below).

Tolerance: the bars' bending.  By symmetry the apex does not turn; a bar's mid section
follows its chord (``GA = EA``), turned by ``dalpha`` from the reference, so the pinned foot
turns by ``2 dalpha`` and the element carries ``M = 2 EJ dalpha / L0``; the foot's moment
balance makes it a shear ``V = 2 M / L`` across the bar.  The two bars' shears add at most
``8 EJ |dalpha| / (L0 L)`` to the apex load (their vertical share, times ``cos alpha <= 1``).
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from fvbeam import Beam, Section, from_curve
from fvbeam.exact_beam import ExactBeam
from fvbeam.exact_statics import NotConverged, solve_static
from studies.bench_exact import rod
from tests.test_exact_statics import next_correction

A, H, EA = 1.0, 0.5, 1.0
L0 = float(np.hypot(A, H))
EJ = EA * L0**2 / 1e8


def truss_load(y: np.ndarray | float) -> np.ndarray:
    """``P(y)`` of the module docstring."""
    return 2 * EA * np.asarray(y) * (1 / np.hypot(A, y) - 1 / L0)


def limit() -> tuple[float, float]:
    """``y*`` and ``P_lim`` (module docstring)."""
    L_star = (A * A * L0) ** (1 / 3)
    y_star = float(np.sqrt(L_star**2 - A * A))
    return y_star, float(truss_load(y_star))


def bending_share(y: np.ndarray) -> np.ndarray:
    """The bound on the bars' bending share of the apex load (module docstring)."""
    turn = np.abs(np.arctan2(H, A) - np.arctan2(y, A))
    return 8 * EJ * turn / (L0 * np.hypot(A, y))


@pytest.fixture(scope="module")
def truss():
    """The truss as one fv2 beam of two elements, planar: every node held out of the plane
    (z and the turns about x and y), the feet pinned; the apex load's dof."""

    def polyline(u: np.ndarray) -> np.ndarray:
        x = np.where(u <= 0.5, -A + 2 * A * u, A * (2 * u - 1))
        y = np.where(u <= 0.5, 2 * H * u, 2 * H * (1 - u))
        return np.column_stack([x, y, 0 * u])

    section = Section.diagonal(EA=EA, GAy=EA, GAz=EA, GJ=EJ, EJy=EJ, EJz=EJ)
    exact = ExactBeam(Beam(from_curve(polyline, 2, 2), section, "fv2"))
    assert np.allclose(exact.beam.mesh.points[1], [0.0, H, 0.0])  # the apex is node 1
    fixed = [0, 1, 2, 12, 13, 14] + [6 * node + k for node in range(3) for k in (2, 3, 4)]
    return exact, np.unique(fixed)


def apex_load(exact: ExactBeam, P: float) -> np.ndarray:
    load = np.zeros(exact.n_dofs)
    load[6 * 1 + 1] = -P
    return load


def test_load_stepping_stops_at_the_limit_point(truss):
    """Beyond the limit load no equilibrium is near: load stepping gives up (no arc
    length)."""
    exact, fixed = truss
    _, P_lim = limit()
    with pytest.raises(NotConverged, match="did not converge beyond load factor 0.66"):
        solve_static(exact, apex_load(exact, 1.5 * P_lim), fixed)


def test_arc_length_snaps_through_the_limit_point(truss):
    """With ``method="arc-length"`` the solver traces the path over the limit point, through
    negative loads on the way down, to the full load ``1.5 P_lim`` on the inverted branch:
    every converged point lies on the truss's ``P(y)`` within the bending share, the path
    passes ``y*`` with its load at most the limit load and within the path's resolution of
    it, and the final apex height is the closed form's root."""
    exact, fixed = truss
    y_star, P_lim = limit()
    P = 1.5 * P_lim
    result = solve_static(exact, apex_load(exact, P), fixed, method="arc-length", first_step=0.1)
    y = np.array([state.x[1, 1] for state in result.path])
    loads = np.array(result.load_factors) * P
    # every point of the path on the closed form; round-off: the floor's 16 eps of EA
    share = bending_share(y) + 16 * np.finfo(float).eps * EA
    assert np.all(np.abs(loads - truss_load(y)) <= share)
    # over the limit point: from above y* to below -y* (the snap), through negative loads
    assert y[0] > y_star and y[-1] < -y_star and loads.min() < 0
    # the upper branch's top: the load falls after it, and it is the limit load to within
    # the path's resolution, P_lim - P(y_i) <= max|P''| d^2 / 2 within d of y*
    upper = loads[y > 0]
    top = int(np.argmax(upper))
    assert top + 1 < len(upper) and upper[top + 1] < upper[top]
    d = float(np.abs(y - y_star).min())
    around = np.linspace(y_star - d, y_star + d, 101)
    curvature = np.abs(-6 * EA * A * A * around / (A * A + around**2) ** 2.5).max()
    assert upper[top] <= P_lim + share.max()
    assert P_lim - upper[top] <= curvature * d * d / 2 + share.max()
    # the end: P(y) = 1.5 P_lim on the inverted branch; the share over the slope P'(y)
    y_end = brentq(lambda v: truss_load(v) - P, -2 * L0, -y_star)
    slope = abs(2 * EA * (A * A / np.hypot(A, y_end) ** 3 - 1 / L0))
    assert result.load_factors[-1] == 1.0
    assert abs(y[-1] - y_end) <= bending_share(np.array([y_end]))[0] / slope


def test_an_unknown_method_is_refused(truss):
    exact, fixed = truss
    with pytest.raises(ValueError, match="method must be one of load, arc-length, got 'riks'"):
        solve_static(exact, apex_load(exact, 0.01), fixed, method="riks")


@pytest.mark.parametrize(
    "name,slenderness,force,moment",
    [
        ("fv3", 1e8, (0.0, -10.0, 0.0), (0.0, 0.0, 0.0)),  # the elastica, P L^2/EJ = 10
        ("fv2", 1e4, (0.0, 0.0, 0.0), (0.0, 0.0, 2 * np.pi)),  # the roll-up into a circle
    ],
)
def test_arc_length_reaches_load_steppings_equilibrium(name, slenderness, force, moment):
    """Without a limit point both methods end on the same equilibrium (the rotations of a
    node up to a full turn, the arc shortened to keep each step within a radian): to the
    sum of the two states' next Newton corrections plus the positions' rounding."""
    exact = rod(name, 8, slenderness)
    load = exact.beam.nodal_load("end", force=force, moment=moment)
    fixed = exact.beam.node_dofs("start")
    stepped = solve_static(exact, load, fixed)
    traced = solve_static(exact, load, fixed, method="arc-length")
    assert traced.load_factors[-1] == 1.0 and len(traced.path) == len(traced.load_factors)
    bound = (
        next_correction(exact, stepped, load)
        + next_correction(exact, traced, load)
        + 16 * np.finfo(float).eps * 8
    )
    assert np.abs(traced.state.x - stepped.state.x).max() <= bound
    assert np.abs(traced.state.R - stepped.state.R).max() <= bound
