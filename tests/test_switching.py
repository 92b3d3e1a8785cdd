"""A body sliding along a chain of three fv3 beams: what happens as the contact crosses the
beam junctions and the evaluation points.

The chain (one element per beam, along x, 3 x 0.6) is clamped at its start.  The body is a
rigid body node at ``(s, 0, 0)`` tied to the tip of a short vertical cantilever (its spring,
clamped at the top), loaded by a transverse force; a spherical slider puts it on the chain.
Moving ``s`` in steps ``h``, the response ``R(s)`` is the slip ``xi - s``, the reaction
``lambda`` and the chain's tip displacement.

* Without smearing the fv load transfer jumps where the contact ``xi`` crosses an evaluation
  point (the force changes region, so the shear between the two nodes changes by the force):
  ``R`` jumps there.  At a beam junction the region belongs to the shared node on both sides,
  so nothing jumps.
* With a box smearing ``eps`` the transfer is the average of the unsmeared one over
  ``[xi - eps, xi + eps]``: a jump ``J`` of the unsmeared response becomes a ramp of slope
  ``J / (2 eps)`` on top of the smooth slope ``L0`` (to first order in the load's effect on
  the contact), ``L0`` and ``J`` read off the unsmeared response on the same steps: ``L0``
  the largest change of a step whose ``xi``-interval holds no evaluation point, over ``h``;
  ``J`` the change of the step that holds one.  Beyond first order the ramp is not
  straight: across it the share ``t`` of the load on the new region goes from 0 to 1 and the
  reaction varies like ``lambda(t) = c / (m0 + a t)`` (the chain's compliance at the contact
  is linear in ``t``), whose largest slope is ``rho = max |lambda| / min |lambda|`` times
  its mean slope ``J``; slip and tip follow the reaction through the same denominator, and
  so does the smooth part of their slope inside the ramp.  So every step may change ``R`` by
  at most ``rho h (L0 + J / (2 eps))``, with ``rho`` from the unsmeared window (1.0 to 1.05
  here).  With ``h = eps / 4`` this is about ``J / 8``, so a
  jump surviving the smearing fails it.

Roundoff: the bordered matrix, rows and columns equilibrated, has a condition number of
about 6e3, so each solution carries ~6e3 x 2.2e-16 ~ 1.3e-12 of its size; a step change of
two of them is allowed 1e-10 of the response's size on top of the bound (for the slip
``xi - s``, of the size of ``xi``, up to the chain's length).

Why the step holding a junction is bounded by its neighbours: the unsmeared response is
smooth there, and a step in the middle of steps of monotone slope changes ``R`` by no more
than the larger of its neighbours (mean value theorem).
"""

import numpy as np
import pytest
from test_sliders import check_jacobian

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.statics import SliderStatics

EJ, GA, H = 4.1e4, 1.0e5, 0.6  # shear-soft enough for the fv jumps to show
CHAIN_SECTION = Section.diagonal(EA=10 * GA, GAy=GA, GAz=GA, GJ=EJ, EJy=EJ, EJz=EJ)
SPRING_SECTION = Section.diagonal(EA=1e6, GAy=1e6, GAz=1e6, GJ=100.0, EJy=100.0, EJz=100.0)
CHAIN = [
    Beam(straight((k * H, 0, 0), ((k + 1) * H, 0, 0), 1), CHAIN_SECTION, "fv3") for k in range(3)
]
SPRING = Beam(straight((0, 0, 0.2), (0, 0, 0), 2), SPRING_SECTION, "fv3")
FORCE = (0.0, 100.0, 0.0)
#: fv3 evaluation points, (1 -+ 1/sqrt(3)) / 2 of each element, and the beam junctions.
EVALUATION_POINTS = (
    np.arange(3)[:, None] * H + H * (1 + np.array([-1, 1]) / np.sqrt(3)) / 2
).ravel()
JUNCTIONS = np.array([H, 2 * H])
ROUNDOFF = 1e-10
GROUPS = {"slip": slice(0, 1), "lambda": slice(1, 4), "tip": slice(4, 7)}


class SlidingBody:
    """The model at body positions ``s``; the chain stiffness is assembled once (the spring
    beam is translated, sharing its stiffness)."""

    def __init__(self, smearing: float) -> None:
        self.smearing, self.statics = smearing, None

    def model(self, s: float):
        spring = SPRING.translated((s, 0.0, 0.0))
        structure = Structure(
            CHAIN + [spring],
            ties=[(0, "end", 1, "start"), (1, "end", 2, "start"), ((3, "end"), "body")],
            bodies=[RigidBody("body", (s, 0.0, 0.0))],
        )
        slider = Slider(
            "spherical",
            BeamChain(structure, [0, 1, 2], name="rail"),
            "body",
            smearing=self.smearing,
            name="carriage",
        )
        self.statics = SliderStatics(
            structure, [Support(0, "start"), Support(3, "start")], [slider], reuse=self.statics
        )
        return structure

    def response(self, s: float) -> np.ndarray:
        """``[xi - s, lambda (3), tip displacement (3)]``.  Newton starts from rest each time:
        started from a neighbouring solution it cannot stop when the answer is q = 0 (contact
        in the clamped node's region), because SliderStatics measures the q increments
        relative to max |q|."""
        structure = self.model(s)
        solution = self.statics.solve(structure.nodal_load("body", force=FORCE))
        y = solution.unknowns[0]
        tip = solution.q[structure.node_dofs((2, "end"))[:3]]
        return np.concatenate([[y[0] - s], y[1:], tip])


def sweep(smearing: float, feature: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Contact abscissae and responses at ``s = feature + h (j + 1/2)``, ``j = -6 .. 5``."""
    body = SlidingBody(smearing)
    R = np.array([body.response(s) for s in feature + h * (np.arange(-6, 6) + 0.5)])
    return R[:, 0] + feature + h * (np.arange(-6, 6) + 0.5), R


def crossing(xi: np.ndarray, point: float) -> np.ndarray:
    """Steps whose contact interval holds ``point``."""
    return (np.minimum(xi[:-1], xi[1:]) < point) & (np.maximum(xi[:-1], xi[1:]) > point)


def group_max(values: np.ndarray) -> dict[str, float]:
    return {g: float(np.abs(values[..., sl]).max()) for g, sl in GROUPS.items()}


@pytest.mark.parametrize("fraction", [0.01, 0.05])
@pytest.mark.parametrize("feature", list(EVALUATION_POINTS) + list(JUNCTIONS))
def test_smeared_response_is_continuous(feature, fraction):
    """Step changes within rho h (L0 + J / (2 eps)) (module docstring), for each of slip,
    lambda and tip displacement, at smearing 1 % and 5 % of an element."""
    eps = fraction * H
    h = eps / 4
    xi0, R0 = sweep(0.0, feature, h)
    _, R = sweep(eps, feature, h)
    steps0 = np.abs(np.diff(R0, axis=0))
    jump_step = crossing(xi0, feature) & np.isin(feature, EVALUATION_POINTS)
    smooth = group_max(steps0[~jump_step]) if jump_step.any() else group_max(steps0)
    jump = group_max(steps0[jump_step]) if jump_step.any() else dict.fromkeys(GROUPS, 0.0)
    reaction = np.linalg.norm(R0[:, GROUPS["lambda"]], axis=1)
    rho = reaction.max() / reaction.min()
    changes = group_max(np.diff(R, axis=0)[None])
    size = group_max(np.vstack([R0, R])) | {"slip": 3 * H}  # slip = xi - s, xi up to 3 H
    for g in GROUPS:
        allowed = rho * (smooth[g] + h * jump[g] / (2 * eps)) + ROUNDOFF * size[g]
        assert changes[g] <= allowed, g


@pytest.mark.parametrize("feature", list(EVALUATION_POINTS) + list(JUNCTIONS))
def test_unsmeared_response_jumps_at_evaluation_points_only(feature):
    """Steps of h = 0.25 % of an element.  The step whose contact interval holds an
    evaluation point changes the tip displacement and lambda by more than any other step
    (a jump); the step holding a junction by no more than its largest neighbour (smooth)."""
    h = 0.0025 * H
    xi, R = sweep(0.0, feature, h)
    steps = np.abs(np.diff(R, axis=0))
    holding = crossing(xi, feature)
    assert holding.sum() == 1
    inside, others = group_max(steps[holding]), group_max(steps[~holding])
    for g in ("lambda", "tip"):
        if feature in EVALUATION_POINTS:
            assert inside[g] > others[g], g
        else:
            k = int(np.flatnonzero(holding)[0])
            assert inside[g] <= group_max(steps[[k - 1, k + 1]])[g], g


def test_body_past_the_chain_end_names_the_chain():
    body = SlidingBody(0.0)
    with pytest.raises(ValueError, match="rail: xi = .* outside the chain"):
        body.response(3 * H + 0.1)


def test_contact_crosses_a_junction_corner_smoothly():
    """The interpolated chain has a corner at the junction (one-sided tangents differ by about
    6e-4 rad here): on the raw tangent the frictionless condition l . lambda = 0 has no root
    in a band of body positions around it, and Newton failed at s = 0.6 - 1e-6.  On the
    recovered tangent (continuous, the mean of the one-sided ones at the vertex) it converges
    everywhere, and the slip has no jump: over steps of 1e-7 .. 1e-5 it changes by at most
    L0 |ds| + ROUNDOFF, L0 the larger slope measured on the outer 1e-5 steps, one on each
    side.  (A body held at the corner, or a jump of the contact, would change it by about
    the band's width, 1e-6.)"""
    body = SlidingBody(0.0)
    positions = 0.6 + np.array([-2e-5, -1e-5, -1e-6, -1e-7, 0.0, 1e-7, 1e-6, 1e-5, 2e-5])
    slip = np.array([body.response(s)[0] for s in positions])
    changes, steps = np.abs(np.diff(slip)), np.diff(positions)
    slope = max(changes[0] / steps[0], changes[-1] / steps[-1])
    assert np.all(changes[1:-1] <= slope * steps[1:-1] + ROUNDOFF)


@pytest.mark.parametrize("xi", [0.6 - 1e-3, 0.6 + 1e-3, 0.6 - 0.15, 1.2 + 0.31])
def test_jacobian_next_to_vertices_and_junctions(xi):
    """The recovered tangent reaches into the neighbouring elements, across junctions: the
    joint's Jacobian against differences there (tests/test_sliders.py)."""
    body = SlidingBody(0.01 * H)
    structure = body.model(xi)
    slider = body.statics.sliders[0]
    check_jacobian(slider, structure, 4)
