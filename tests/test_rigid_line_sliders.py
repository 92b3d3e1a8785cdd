"""A rigid body held by a spherical slider on a rigid circular arc and on a helix.

Two setups with closed-form equilibria (the line is rigid, so the only nonlinearity is the
line's geometry and Newton must find the point the closed form names):

* **spring**: the body is tied to the tip of a cantilever whose tip compliance is the same
  ``c`` in every direction (``EA`` chosen so that ``L / EA = L^3 / (3 EJ) + L / GA``), so the
  body sits on a linear isotropic spring ``k = 1 / c`` about its reference point ``X0``.
  Under a load ``F`` the body's potential is ``k / 2 |x - P|^2`` up to a constant, with
  ``P = X0 + F / k``: equilibrium is at the point ``x*`` of the line closest to ``P``, and
  the reaction on the line is ``lambda = k (P - x*)``, the normal-plane projection of the
  total force on the body (load plus spring), whose tangential part vanishes.
* **bead**: the body alone (no beam), its rotations supported, a constant load ``F``: the body
  rows read ``lambda = F`` and eq. (3) ``l . lambda = 0`` puts the bead where the line is
  normal to ``F``, at the stable point (the bead hangs from the line in the load's direction).

Tolerances: the bordered Newton matrix has a condition number of about 5e4 (the spring's
stiffness, about 1e3, beside the unit constraint entries), so converged quantities carry
relative roundoff ~5e4 x 2.2e-16 ~ 1e-11; Newton stops on increments of 1e-8 relative and
converges quadratically, so its last step leaves an error ~(1e-8)^2 below that.  1e-10 of the
quantity's scale is the bound (ten times the roundoff estimate).
"""

import numpy as np
import pytest

from fvbeam import Beam, LinearStatics, RigidBody, Section, Structure, Support, straight
from sliders.joints.slider import Slider
from sliders.lines.rigid import CircularArc, Helix
from sliders.solve.statics import SliderStatics

ROUNDOFF = 1e-10
EJ, GA, LS = 2.0, 50.0, 0.5
COMPLIANCE = LS**3 / (3 * EJ) + LS / GA
SPRING = Section.diagonal(EA=LS / COMPLIANCE, GAy=GA, GAz=GA, GJ=1.0, EJy=EJ, EJz=EJ)
K_SPRING = 1.0 / COMPLIANCE
ARC = CircularArc((0.2, -0.1, 0.3), 1.5, -0.4, 1.6, name="arc")
HELIX = Helix((0.1, 0.2, -0.3), 0.8, 0.5, 1.5, name="helix")
LOAD = np.array([2.0, 1.0, 0.5])


def spring_model(line, X0, direction=(0.3, -1.0, 0.4)):
    """Body ``carriage`` at ``X0`` tied to the tip of the isotropic spring, a cantilever along
    ``direction`` (any: the compliance is isotropic) clamped at its other end."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    beam = Beam(straight(X0 + LS * d, X0, 2), SPRING, "fv3")
    structure = Structure(
        [beam], ties=[((0, "end"), "carriage")], bodies=[RigidBody("carriage", X0, mass=1.0)]
    )
    slider = Slider("spherical", line, "carriage", name="carriage slider")
    return structure, SliderStatics(structure, [Support(0, "start")], [slider])


def closest_point_target(line):
    """A point ``P`` and the abscissa ``xi*`` of the line's point closest to it.

    Arc: ``P`` off the arc's plane at angle 0.7, inside the circle; the closest point has the
    same angle, ``xi* = r (0.7 - angle0)``.  Helix: ``P`` on the ray from the axis through the
    helix point at parameter ``a* = 5``, at height ``h a*`` and radius 0.3: its squared
    distance ``r^2 + rho^2 - 2 r rho cos(a - a*) + h^2 (a - a*)^2`` is least at ``a*``, so
    ``xi* = a* / w``.
    """
    if line is ARC:
        angle = 0.7
        P = ARC.center + np.array([1.2 * np.cos(angle), 1.2 * np.sin(angle), 0.2])
        return P, ARC.radius * (angle - ARC.angle0)
    a = 5.0
    P = HELIX.center + np.array([0.3 * np.cos(a), 0.3 * np.sin(a), HELIX.rise * a])
    return P, a / HELIX.w


def test_the_spring_is_isotropic():
    """Tip compliance of the fv3 cantilever (exact for a tip load, the moment being linear):
    ``L^3 / (3 EJ) + L / GA`` transversely and ``L / EA`` axially, equal by the choice of EA."""
    structure, _ = spring_model(ARC, np.array([0.3, 0.2, 0.1]), (1.0, 2.0, 3.0))
    statics = LinearStatics(structure, [Support(0, "start")])
    u = structure.node_dofs("carriage")[:3]
    C = np.column_stack(
        [statics.solve(structure.nodal_load("carriage", force=e))[u] for e in np.eye(3)]
    )
    np.testing.assert_allclose(C, COMPLIANCE * np.eye(3), atol=ROUNDOFF * COMPLIANCE)


@pytest.mark.parametrize("line", [ARC, HELIX], ids=["arc", "helix"])
def test_spring_pulls_the_body_to_the_closest_point(line):
    """Closed form (module docstring): xi = xi*, the body on the line, lambda = k (P - x*),
    l . lambda = 0, and lambda is the normal-plane projection of the total force on the body
    (the load minus the spring force ``K q`` on the body's rows), whose tangential part is 0.
    Newton starts from the projection of the body's reference point, with zero multipliers."""
    P, xi_star = closest_point_target(line)
    X0 = P - LOAD / K_SPRING
    structure, statics = spring_model(line, X0)
    f = structure.nodal_load("carriage", force=LOAD)
    solution = statics.solve(f)
    xi, lam = solution.unknowns[0][0], solution.unknowns[0][1:]
    point = line.at(xi)
    assert xi == pytest.approx(xi_star, abs=ROUNDOFF * line.length)
    u = structure.node_dofs("carriage")[:3]
    np.testing.assert_allclose(X0 + solution.q[u], point.x, atol=ROUNDOFF * line.length)
    scale = np.abs(lam).max()
    np.testing.assert_allclose(lam, K_SPRING * (P - point.x), atol=ROUNDOFF * scale)
    assert abs(point.l @ lam) <= ROUNDOFF * scale
    total = f[u] - (statics.K @ solution.q)[u]
    t = point.l / np.linalg.norm(point.l)
    np.testing.assert_allclose(lam, total - (t @ total) * t, atol=ROUNDOFF * scale)
    assert abs(t @ total) <= ROUNDOFF * scale
    assert solution.residuals[-1] <= ROUNDOFF


@pytest.mark.parametrize("line", [ARC, HELIX], ids=["arc", "helix"])
def test_newton_converges_quadratically_on_a_rigid_line(line):
    """Newton from the solution with xi moved by eps: the first residual is proportional to
    eps and the one after one step to eps^2 (quadratic convergence), with relative corrections
    of order eps / r (r the radius, the scale of the line's curvature).  From eps = 1e-3 r and
    eps / 10 the observed order log10(r_1(eps) / r_1(eps / 10)) is 2 to within ~1e-3 times an
    order-one curvature ratio; 0.05 allows that ratio up to ~50 and still rejects orders 1
    (linear) and 3.  Both r_1 lie far above the roundoff floor (~1e-14)."""
    P, _ = closest_point_target(line)
    structure, statics = spring_model(line, P - LOAD / K_SPRING)
    f = structure.nodal_load("carriage", force=LOAD)
    solution = statics.solve(f)
    first = []
    for eps in (1e-3 * line.radius, 1e-4 * line.radius):
        start = solution.unknowns[0].copy()
        start[0] += eps
        residuals = statics.solve(f, start=(solution.q, [start])).residuals
        assert residuals[1] > 1e4 * 1e-14
        first.append(residuals[1])
    assert abs(np.log10(first[0] / first[1]) - 2) < 0.05


def bead_model(line, X0):
    """The body ``bead`` alone at ``X0``, its rotations supported, on ``line``."""
    structure = Structure([], bodies=[RigidBody("bead", X0)])
    slider = Slider("spherical", line, "bead", name="bead slider")
    return structure, SliderStatics(structure, [Support("bead", kind="rx+ry+rz")], [slider])


def bead_abscissa(line, F):
    """Stable equilibrium of a bead under ``F``: minimum of ``-F . x(xi)``.

    Arc (in its plane): where ``F``'s in-plane direction points radially out, angle
    ``atan2(F_y, F_x)``.  Helix ``x = c + (r cos a, r sin a, h a)``: ``l . F = 0`` reads
    ``r |F_xy| sin(phi - a) = -h F_z`` (``phi`` the direction of ``F_xy``); the root with
    ``cos(a - phi) > 0`` (positive second derivative of the potential) is
    ``a = phi + asin(h F_z / (r |F_xy|))``, ``xi = a / w``.
    """
    phi = np.arctan2(F[1], F[0])
    if line is ARC:
        return ARC.radius * (phi - ARC.angle0)
    a = phi + 2 * np.pi + np.arcsin(HELIX.rise * F[2] / (HELIX.radius * np.hypot(F[0], F[1])))
    return a / HELIX.w


@pytest.mark.parametrize("line", [ARC, HELIX], ids=["arc", "helix"])
def test_bead_settles_where_the_load_is_normal_to_the_line(line):
    """The body rows give lambda = F; eq. (3) puts the bead at the closed-form abscissa, on
    the line.  At lambda = 0 the bead has no stiffness along the line (the xi row's
    ``-l_/xi . lambda`` vanishes and the body rows hold no stiffness), so the first Newton
    matrix would be singular: Newton starts from lambda = F, the body rows' own solution, and
    from the projection of the bead's reference point (0.1 off the line, 0.05 before the
    equilibrium along it)."""
    F = LOAD
    xi_star = bead_abscissa(line, F)
    p = line.at(xi_star - 0.05)
    X0 = p.x + 0.1 * p.R[:, 1]
    structure, statics = bead_model(line, X0)
    y0 = np.concatenate([[line.project(X0)], F])
    solution = statics.solve(
        structure.nodal_load("bead", force=F), start=(np.zeros(structure.n_dofs), [y0])
    )
    xi, lam = solution.unknowns[0][0], solution.unknowns[0][1:]
    assert xi == pytest.approx(xi_star, abs=ROUNDOFF * line.length)
    np.testing.assert_allclose(lam, F, atol=ROUNDOFF * np.abs(F).max())
    point = line.at(xi)
    assert abs(point.l @ lam) <= ROUNDOFF * np.abs(F).max()
    np.testing.assert_allclose(
        X0 + solution.q[structure.node_dofs("bead")[:3]], point.x, atol=ROUNDOFF * line.length
    )


def test_slider_on_an_unknown_body_names_the_bodies():
    structure, _ = bead_model(ARC, ARC.at(1.0).x)
    slider = Slider("spherical", ARC, "baed")
    with pytest.raises(ValueError, match="no rigid body named 'baed'.*'bead'"):
        SliderStatics(structure, [], [slider]).solve(np.zeros(structure.n_dofs))
