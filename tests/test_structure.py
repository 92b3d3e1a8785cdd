"""Structures of several beams and supports (closed forms by Castigliano; exact for fv3 since
the moments are linear along each member, see tests/test_fv_closed_forms.py)."""

import meshio
import numpy as np
import pytest

from fvbeam import Beam, LinearStatics, Section, Structure, Support, read_beams

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
    np.testing.assert_allclose(reactions[2], -P, rtol=ROUNDOFF)   # force balance


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
    np.testing.assert_allclose(structure.residual(q), K @ q,
                               atol=ROUNDOFF * np.abs(K).max() * np.abs(q).sum())
