"""The spline slider (paper eq. 5, Sec. 4): Jacobian, the torque about the line, the twist test.

Finite differences as in ``tests/test_sliders.py``: central, step 1e-7, agreement to 1e-6.
"""

import numpy as np
import pytest
from test_sliders import SECTION, check_jacobian

from fvbeam import Beam, Section, Structure, Support, formulation, straight
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import Helix, StraightLine
from sliders.solve.statics import SliderStatics

GJ = 2.0e4
TWIST_SECTION = Section.diagonal(EA=1e9, GAy=1e8, GAz=1e8, GJ=GJ, EJy=4e4, EJz=4e4)


def line_with_body(name, n, a, T, formulation_body="fv3"):
    """Line beam on [0, 1] along x, clamped at 0; a body beam along y from (a, 0, 0), its
    start node sliding on the line with a spline slider, its axial position held (``ux``) so
    that it does not slide; a torque ``T`` about x at the body beam's free end."""
    npe = formulation(name).nodes_per_element
    line = Beam(straight((0, 0, 0), (1, 0, 0), n, npe), TWIST_SECTION, name)
    body = Beam(straight((a, 0, 0), (a, 0.1, 0), 1, 3), TWIST_SECTION, formulation_body)
    structure = Structure([line, body])
    slider = Slider("spline", BeamChain(structure, [0], "line"), (1, "start"), name="S")
    supports = [Support(0, "start"), Support(1, "start", "ux")]
    f = structure.gather(1, body.nodal_load("end", moment=(T, 0, 0)))
    return structure, supports, slider, f


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p2", "cubic"])
@pytest.mark.parametrize("smearing", [0.0, 0.03])
@pytest.mark.parametrize("a", [0.37, 0.5, 0.625])
def test_spline_jacobian_matches_finite_differences(name, smearing, a):
    """Deformed state, random multipliers; xi inside an element, on a vertex (0.5) and on an
    fv3 mid-node (0.625 with 4 elements)."""
    structure, _, slider, _ = line_with_body(name, 4, a, 1.0)
    slider.smearing = smearing
    check_jacobian(slider, structure, 2)


@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p2", "cubic"])
@pytest.mark.parametrize("a", [0.37, 0.5, 0.625])
def test_twist_at_the_body_is_T_a_over_GJ(name, a):
    """The issue's twist test: the line's twist at the contact is T a / GJ (closed form of a
    shaft clamped at 0 under a torque at a), the body turns with the section, the clamp
    returns the torque.  Exact for every formulation: the torque is shared by the two nodes
    around a, the nodal twists are exact for nodal torques, and the kink correction (the
    cubic element's compliance, ``a b / (h GJ)`` in twist) restores the exact twist between
    them (relative tolerance 1e-9: roundoff of K ~ 1e10 against
    rotations ~1e-5)."""
    T = 100.0
    structure, supports, slider, f = line_with_body(name, 4, a, T)
    solution = SliderStatics(structure, supports, [slider]).solve(f)
    body_turn = solution.q[slider.body_dofs(structure)[3]]
    assert body_turn == pytest.approx(T * a / GJ, rel=1e-9)
    mu_1 = solution.unknowns[0][6]  # the body beam hands T to the joint: m = mu_1 t = T
    assert mu_1 == pytest.approx(T, rel=1e-9)
    line = structure.beams[0]
    clamp = structure.dof_maps[0][3]
    reaction = (structure.tangent(solution.q) @ solution.q)[clamp]
    assert reaction == pytest.approx(-T, rel=1e-9)
    assert np.isclose(line.section.stiffness[3, 3], GJ)


@pytest.mark.parametrize("kind", ["classical", "spline"])
def test_spline_slider_transmits_the_torque_about_a_rigid_line(kind):
    """A beam along y clamped at (0, -1, 0), its tip on a rigid straight line along x, a torque
    T about x at the tip.  The spline slider takes all of it (mu_1 = T, the tip does not
    turn about the line, to roundoff); the classical slider leaves that turn free, so the
    beam, propped at its tip by the line, bends under T: Timoshenko propped cantilever, tip
    reaction R = -(T L^2 / 2EJ) / (L^3 / 3EJ + L / GA), tip turn R L^2 / 2EJ + T L / EJ
    (fv3 is exact for end loads: tolerance 1e-9, roundoff)."""
    EJ, GA, L, T = 4e4, 1e8, 1.0, 10.0
    beam = Beam(straight((0, -1, 0), (0, 0, 0), 4, 3), TWIST_SECTION, "fv3")
    structure = Structure([beam])
    line = StraightLine((-1, 0, 0), (1, 0, 0))
    R0 = line.at(1.0).R
    slider = Slider(kind, line, (0, "end"), frame=R0, name="S")
    supports = [Support(0, "start"), Support(0, "end", "ux")]
    f = structure.gather(0, beam.nodal_load("end", moment=(T, 0, 0)))
    solution = SliderStatics(structure, supports, [slider]).solve(f)
    tip_turn = solution.q[structure.dof_maps[0][6 * beam.node_index("end") + 3]]
    if kind == "spline":
        assert solution.unknowns[0][6] == pytest.approx(T, rel=1e-12)
        assert abs(tip_turn) <= 1e-12
    else:
        R = -(T * L**2 / (2 * EJ)) / (L**3 / (3 * EJ) + L / GA)
        assert tip_turn == pytest.approx(R * L**2 / (2 * EJ) + T * L / EJ, rel=1e-9)


def test_spline_jacobian_on_a_helix():
    """A beam tip on a rigid helix, the slider frame the helix's frame at the projection:
    Jacobian against differences (the frame's curvature and its rate enter the xi row)."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")
    structure = Structure([beam])
    helix = Helix((1, -1, 0), 1.0, 0.5, 0.5)
    xi = helix.project(np.array([1.0, 0.0, 0.0]))
    slider = Slider("spline", helix, (0, "end"), frame=helix.at(xi).R, name="S")
    check_jacobian(slider, structure, 3)


def test_misaligned_spline_frame_is_refused():
    structure, _, slider, _ = line_with_body("fv3", 4, 0.37, 1.0)
    slider.frame = np.diag([1.0, -1.0, -1.0])
    with pytest.raises(ValueError, match="S: a spline slider's frame must match"):
        slider.initial_unknowns(structure, np.zeros(structure.n_dofs))
