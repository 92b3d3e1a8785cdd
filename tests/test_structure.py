"""Structures of several beams, rigid bodies and supports (closed forms by Castigliano; exact for
fv3 since the moments are linear along each member, see tests/test_fv_closed_forms.py)."""

import meshio
import numpy as np
import pytest

from fvbeam import Beam, LinearStatics, RigidBody, Section, Structure, Support, read_beams, straight

ROUNDOFF = 1e-10  # condition number ~1e4 here; see tests/test_fv_closed_forms.py
EJ, GA, GJ = 2.0, 5.0, 1.5
SECTION = Section.diagonal(EA=1e3, GAy=GA, GAz=GA, GJ=GJ, EJy=EJ, EJz=EJ)


def l_frame(a=1.0, b=0.7, n=2, blocks=2):
    """An L of 3-node elements, x from 0 to a, then y: two cell blocks sharing the corner point
    (two beams), or one block (one beam with a kink at the corner node)."""
    corner = np.array([a, 0.0, 0.0])
    s = np.linspace(0, 1, 2 * n + 1)[:, None]
    first = s * corner
    second = corner + s[1:] * np.array([0.0, b, 0.0])
    points = np.vstack([first, second])
    cells = [[2 * k, 2 * k + 2, 2 * k + 1] for k in range(n)]
    m = len(first) - 1
    cells += [[m + 2 * k, m + 2 * k + 2, m + 2 * k + 1] for k in range(n)]
    if blocks == 1:
        return meshio.Mesh(points, [("line3", np.array(cells))])
    return meshio.Mesh(points, [("line3", np.array(cells[:n])), ("line3", np.array(cells[n:]))])


def test_l_frame_out_of_plane_tip_load():
    """delta = P [(a^3 + b^3) / (3 EJ) + (a + b) / GA + a b^2 / GJ]: both members bend and
    shear, the first also twists under the torque P b."""
    a, b, P = 1.0, 0.7, 3.0
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame(a, b))]
    structure = Structure.from_shared_points(beams)
    assert structure.n_nodes == sum(beam.mesh.n_nodes for beam in beams) - 1
    statics = LinearStatics(structure, [Support(0, "start")])
    tip = beams[1].mesh.length
    q = statics.solve(structure.gather(1, beams[1].point_load(tip, force=(0, 0, P))))
    w = beams[1].displacements(structure.local(1, q), tip)[0, 2]
    expected = P * ((a**3 + b**3) / (3 * EJ) + (a + b) / GA + a * b**2 / GJ)
    assert w == pytest.approx(expected, rel=ROUNDOFF)
    kinked = Beam(read_beams(l_frame(a, b, blocks=1))[0], SECTION, "fv3")
    one = LinearStatics(kinked, [Support(0, "start")])
    length = kinked.mesh.length
    q1 = one.solve(kinked.point_load(length, force=(0, 0, P)))
    assert kinked.displacements(q1, length)[0, 2] == pytest.approx(expected, rel=ROUNDOFF)
    reactions = statics.reactions(q, structure.gather(1, beams[1].point_load(tip, (0, 0, P))))
    np.testing.assert_allclose(reactions[2], -P, rtol=ROUNDOFF)  # force balance


def test_unconnected_beams_are_independent_and_singular_without_support():
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame())]
    with pytest.raises(ValueError, match="rigid-body motion"):
        LinearStatics(Structure(beams), [Support(0, "start")])


def test_bad_structure_input_names_the_item():
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame())]
    with pytest.raises(ValueError, match="beam 5"):
        Structure(beams, ties=[(0, "end", 5, "start")])
    with pytest.raises(ValueError, match="node 'middle'"):
        LinearStatics(beams[0], [Support(0, "middle")])
    with pytest.raises(ValueError, match="support kind"):
        Support(0, "start", "roller")


def test_residual_is_the_tangent_times_the_displacements():
    """Linear beams: r(q) = K q, gathered over the beams (the residual + tangent interface)."""
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame())]
    structure = Structure.from_shared_points(beams)
    q = np.random.default_rng(1).standard_normal(structure.n_dofs)
    K = structure.tangent(q)
    np.testing.assert_allclose(
        structure.residual(q), K @ q, atol=ROUNDOFF * np.abs(K).max() * np.abs(q).sum()
    )


def test_bodies_are_numbered_after_the_beam_nodes_and_add_no_stiffness():
    """Two beams of five nodes sharing the corner: nine beam nodes, then one node per body."""
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame())]
    bodies = [RigidBody("hub", (1.0, 0.0, 0.0)), RigidBody("free", (3.0, 0.0, 0.0), mass=2.0)]
    structure = Structure.from_shared_points(beams, bodies)
    assert structure.n_nodes == 9 + 2
    np.testing.assert_array_equal(structure.node_dofs((0, "start")), structure.dof_maps[0][:6])
    end = 6 * beams[1].node_index("end")
    np.testing.assert_array_equal(
        structure.node_dofs((1, "end")), structure.dof_maps[1][end : end + 6]
    )
    np.testing.assert_array_equal(structure.node_dofs("hub"), 6 * 9 + np.arange(6))
    np.testing.assert_array_equal(structure.node_dofs("free"), 6 * 10 + np.arange(6))
    np.testing.assert_array_equal(structure.node_position("free"), [3.0, 0.0, 0.0])
    np.testing.assert_array_equal(structure.node_position((1, "end")), [1.0, 0.7, 0.0])
    assert structure.dof_name(6 * 10 + 4) == "body 'free' ry"
    assert structure.dof_name(structure.node_dofs((1, "end"))[1]) == "beam 1 node 2 uy"
    K = structure.tangent(np.zeros(structure.n_dofs)).tocsr()
    assert K[6 * 9 :].count_nonzero() == 0 and K[:, 6 * 9 :].count_nonzero() == 0


def test_members_tied_to_a_hub_body_are_the_shared_point_frame():
    """The L frame of test_l_frame_out_of_plane_tip_load with both members tied to a rigid body
    at the corner instead of to each other (both tie forms): the hub takes the corner's dofs
    and the tip deflection is the same closed form; a force on the hub itself bends only the
    first member, as a cantilever: P (a^3 / (3 EJ) + a / GA)."""
    a, b, P = 1.0, 0.7, 3.0
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame(a, b))]
    hub = RigidBody("hub", (a, 0.0, 0.0), mass=2.0, inertia=np.diag([1.0, 2.0, 2.5]))
    structure = Structure(
        beams, ties=[((0, "end"), "hub"), (1, "start", "hub", None)], bodies=[hub]
    )
    assert structure.n_nodes == sum(beam.mesh.n_nodes for beam in beams) - 1
    np.testing.assert_array_equal(structure.node_dofs("hub"), structure.node_dofs((0, "end")))
    np.testing.assert_array_equal(structure.node_dofs("hub"), structure.node_dofs((1, "start")))
    statics = LinearStatics(structure, [Support(0, "start")])
    tip = beams[1].mesh.length
    q = statics.solve(structure.gather(1, beams[1].point_load(tip, force=(0, 0, P))))
    expected = P * ((a**3 + b**3) / (3 * EJ) + (a + b) / GA + a * b**2 / GJ)
    assert beams[1].displacements(structure.local(1, q), tip)[0, 2] == pytest.approx(
        expected, rel=ROUNDOFF
    )
    q = statics.solve(structure.nodal_load("hub", force=(0, 0, P)))
    assert q[structure.node_dofs("hub")[2]] == pytest.approx(
        P * (a**3 / (3 * EJ) + a / GA), rel=ROUNDOFF
    )


def cantilever_with_bodies(a=1.0):
    """A beam along x tied to a body ``root`` at its start and a body ``tip`` at its end."""
    beam = Beam(straight((0, 0, 0), (a, 0, 0), 2), SECTION, "fv3")
    bodies = [RigidBody("root", (0, 0, 0)), RigidBody("tip", (a, 0, 0))]
    return Structure([beam], ties=[((0, "start"), "root"), ((0, "end"), "tip")], bodies=bodies)


def test_supported_bodies_hold_the_beam():
    """Clamped through the root body: the cantilever P (a^3 / (3 EJ) + a / GA).  With the tip
    body's rotations held as well, the clamped-guided beam P (a^3 / (12 EJ) + a / GA), whose
    guide carries the moment P a / 2 (the moment is linear, zero at mid-span)."""
    a, P = 1.0, 3.0
    structure = cantilever_with_bodies(a)
    load = structure.nodal_load("tip", force=(0, 0, P))
    w = structure.node_dofs("tip")[2]
    q = LinearStatics(structure, [Support("root")]).solve(load)
    assert q[w] == pytest.approx(P * (a**3 / (3 * EJ) + a / GA), rel=ROUNDOFF)
    guided = LinearStatics(structure, [Support("root"), Support("tip", kind="rx+ry+rz")])
    q = guided.solve(load)
    assert q[w] == pytest.approx(P * (a**3 / (12 * EJ) + a / GA), rel=ROUNDOFF)
    moment = guided.reactions(q, load)[structure.node_dofs("tip")[3:]]
    np.testing.assert_allclose(np.abs(moment), [0, P * a / 2, 0], atol=ROUNDOFF * P * a)


def test_an_unsupported_free_body_is_a_free_motion():
    """A body tied to nothing has zero rows: without a support its six dofs are free."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2), SECTION, "fv3")
    structure = Structure([beam], bodies=[RigidBody("loose", (0, 1, 0))])
    with pytest.raises(ValueError, match="rigid-body motion"):
        LinearStatics(structure, [Support(0, "start")])
    statics = LinearStatics(structure, [Support(0, "start"), Support("loose")])
    q = statics.solve(structure.nodal_load((0, "end"), force=(0, 1, 0)))
    assert not q[structure.node_dofs("loose")].any()


def test_bad_body_input_names_the_item():
    beams = [Beam(mesh, SECTION, "fv3") for mesh in read_beams(l_frame())]
    hub = RigidBody("hub", (1.0, 0.0, 0.0))
    structure = Structure(beams, bodies=[hub])
    with pytest.raises(ValueError, match="no rigid body named 'hbu'.*bodies: 'hub'"):
        Structure(beams, ties=[((0, "end"), "hbu")], bodies=[hub])
    with pytest.raises(ValueError, match="no rigid body named 'hbu'"):
        LinearStatics(structure, [Support(0, "start"), Support("hbu")])
    with pytest.raises(ValueError, match="no rigid body named 'x'.*bodies: none"):
        Structure(beams).node_dofs("x")
    with pytest.raises(ValueError, match="repeated: hub"):
        Structure(beams, bodies=[hub, RigidBody("hub", (0, 0, 0))])
    with pytest.raises(ValueError, match=r"bodies\[0\] must be a RigidBody"):
        Structure(beams, bodies=["hub"])
    with pytest.raises(ValueError, match="0.5 apart"):
        Structure(beams, ties=[((0, "start"), "hub")], bodies=[RigidBody("hub", (0.5, 0, 0))])
    with pytest.raises(ValueError, match="tie \\(0, 'end', 'hub'\\)"):
        Structure(beams, ties=[(0, "end", "hub")], bodies=[hub])
    with pytest.raises(ValueError, match="node reference 3"):
        structure.node_position(3)
    with pytest.raises(ValueError, match="body 'hub'.*no node.*kind='pin'"):
        Support("hub", "pin")
    with pytest.raises(ValueError, match="beam 0 needs a node"):
        Support(0)
    with pytest.raises(ValueError, match="body 'hub': mass"):
        RigidBody("hub", (0, 0, 0), mass=-1.0)
    with pytest.raises(ValueError, match="body 'hub': mass"):
        RigidBody("hub", (0, 0, 0), mass="heavy")
    with pytest.raises(ValueError, match="body 'hub': position"):
        RigidBody("hub", (0, np.nan, 0))
    with pytest.raises(ValueError, match="body 'hub': inertia must be symmetric"):
        RigidBody("hub", (0, 0, 0), inertia=[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match="body 'hub': inertia must be positive semi-definite"):
        RigidBody("hub", (0, 0, 0), inertia=np.diag([1.0, -0.5, 1.0]))
    with pytest.raises(ValueError, match="body 'hub': frame must be an orthonormal"):
        RigidBody("hub", (0, 0, 0), frame=np.diag([1.0, 2.0, 1.0]))
    with pytest.raises(ValueError, match="non-empty string"):
        RigidBody("", (0, 0, 0))
    with pytest.raises(ValueError, match="at least one beam or body"):
        Structure([])
