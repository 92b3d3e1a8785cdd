"""Beam meshes: meshio round trips, chain ordering in ``read_beams``, arc length, bad input."""

from __future__ import annotations

import meshio
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fvbeam import Beam, BeamMesh, Section, arc, from_curve, read_beams, straight

# A fixed, "arbitrary" orientation: nothing in these tests may depend on the global axes.
Q = Rotation.random(random_state=20240611).as_matrix()
DIRECTION = Q @ np.array([1.0, 0.0, 0.0])
ORIGIN = np.array([0.3, -1.2, 0.7])


def _rotated_arc(n_elements: int, nodes_per_element: int) -> BeamMesh:
    """Arc of radius 1.4 over 2 rad in the plane spanned by Q e_x, Q e_y."""

    def curve(u):
        a = 0.4 + 2.0 * u
        local = 1.4 * np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
        return ORIGIN + local @ Q.T

    return from_curve(curve, n_elements, nodes_per_element, up=Q @ np.array([0.0, 0.0, 1.0]))


MESHES = {
    "straight-line": lambda: straight(ORIGIN, ORIGIN + 2.3 * DIRECTION, 5, 2),
    "straight-line3": lambda: straight(ORIGIN, ORIGIN + 2.3 * DIRECTION, 5, 3),
    "arc-line": lambda: arc((0.5, -0.25, 1.5), 1.7, 0.3, 2.9, 6, 2),
    "arc-line3": lambda: arc((0.5, -0.25, 1.5), 1.7, 0.3, 2.9, 6, 3),
    "rotated-arc-line": lambda: _rotated_arc(7, 2),
    "rotated-arc-line3": lambda: _rotated_arc(7, 3),
}


def _write(mesh: BeamMesh, path, how: str) -> None:
    if how == "gmsh22-ascii":
        # An ASCII file as Gmsh itself writes it: nodes and elements only.  (meshio 5.3.5
        # cannot read back the NodeData section it writes in ASCII -- a meshio issue.)
        m = mesh.to_meshio()
        meshio.write(path, meshio.Mesh(m.points, m.cells), file_format="gmsh22", binary=False)
    else:
        mesh.write(path)


# ---------------------------------------------------------------------------------------
# meshio round trips
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", sorted(MESHES))
@pytest.mark.parametrize(
    "suffix, how", [("vtu", "write"), ("msh", "write"), ("msh", "gmsh22-ascii")]
)
def test_round_trip_is_exact(tmp_path, kind, suffix, how):
    mesh = MESHES[kind]()
    path = tmp_path / f"beam.{suffix}"
    _write(mesh, path, how)
    back = BeamMesh.read(path, up=mesh.up)
    # VTU and binary Gmsh store the float64 bits; ASCII Gmsh writes '.16e' (17 significant
    # digits), which round-trips every float64 exactly.  So: bitwise equality.
    assert back.nodes_per_element == mesh.nodes_per_element
    np.testing.assert_array_equal(back.cells, mesh.cells)
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.vertex_s, mesh.vertex_s)
    np.testing.assert_array_equal(back.point_ids, np.arange(mesh.n_nodes))


def test_to_meshio_carries_the_beam():
    mesh = MESHES["rotated-arc-line3"]()
    m = mesh.to_meshio()
    assert [b.type for b in m.cells] == ["line3"]
    np.testing.assert_array_equal(m.cells[0].data, mesh.cells)
    np.testing.assert_array_equal(m.points, mesh.points)
    np.testing.assert_array_equal(m.point_data["xi"], mesh.node_abscissae())


# ---------------------------------------------------------------------------------------
# read_beams: ordering of shuffled / reversed cells, several chains
# ---------------------------------------------------------------------------------------
def _shuffled_line(nodes_per_element: int, first_reversed: bool, seed: int = 3):
    """A straight chain of 6 elements along DIRECTION stored with permuted point ids,
    cells in random order and about half of them reversed.

    Returns the meshio mesh, the arc-length position of every file point (nan if unused)
    and the sign (+1 / -1) of the direction of the first cell in the file.
    """
    rng = np.random.default_rng(seed)
    n = 6
    s_vertex = np.linspace(0.0, 3.0, n + 1)
    s_all = np.concatenate(
        [s_vertex, (s_vertex[:-1] + s_vertex[1:]) / 2] if nodes_per_element == 3 else [s_vertex]
    )
    local = np.column_stack([np.arange(n), np.arange(1, n + 1)])
    if nodes_per_element == 3:
        local = np.column_stack([local, np.arange(n + 1, 2 * n + 1)])
    n_file = len(s_all) + 2  # two unused points in the file
    file_id = rng.permutation(n_file)[: len(s_all)]  # file id of every local node
    points = rng.normal(size=(n_file, 3)) * 10  # unused points anywhere
    s_file = np.full(n_file, np.nan)
    points[file_id] = ORIGIN + np.outer(s_all, DIRECTION)
    s_file[file_id] = s_all
    order = rng.permutation(n)
    cells = file_id[local][order]
    flip = rng.random(n) < 0.5
    flip[0] = first_reversed
    # the fixture must really shuffle and reverse some (not all) of the other cells
    assert np.any(order != np.arange(n)) and flip[1:].any() and not flip[1:].all()
    cells[flip, :2] = cells[flip, 1::-1]
    sign = -1.0 if first_reversed else 1.0
    return (
        meshio.Mesh(points, [("line" if nodes_per_element == 2 else "line3", cells)]),
        s_file,
        sign,
    )


@pytest.mark.parametrize("nodes_per_element", [2, 3])
@pytest.mark.parametrize("first_reversed", [False, True])
def test_read_beams_orders_a_shuffled_chain(nodes_per_element, first_reversed):
    m, s_file, sign = _shuffled_line(nodes_per_element, first_reversed)
    (beam,) = read_beams(m)
    n = beam.n_elements
    assert n == 6 and beam.nodes_per_element == nodes_per_element
    ids = beam.point_ids
    # the beam's nodes are the file's points, identified by point_ids
    np.testing.assert_array_equal(beam.points, m.points[ids])
    # vertices run monotonically, in the direction of the first cell of the file
    s = sign * s_file[ids[: n + 1]]
    assert np.all(np.diff(s) > 0)
    first = m.cells[0].data[0]
    vertices = list(ids[: n + 1])
    assert vertices.index(first[1]) == vertices.index(first[0]) + 1
    # mid nodes sit between the ends of their element
    if nodes_per_element == 3:
        s_mid = sign * s_file[ids[n + 1 :]]
        assert np.all((s[:-1] < s_mid) & (s_mid < s[1:]))
    # arc length from the first vertex: |s - s0| (roundoff: one subtraction, 8-point
    # Gauss sum of a constant speed, ~1e2 eps on lengths of order 3)
    np.testing.assert_allclose(beam.vertex_s, s - s[0], rtol=0, atol=1e2 * np.finfo(float).eps * 3)


def test_read_beams_two_disjoint_chains(tmp_path):
    a = straight((0, 0, 0), (1, 2, 0.5), 3, 3)
    b = arc((5, 5, 1), 1.0, 0.0, 1.5, 4, 3)
    points = np.vstack([a.points, b.points])
    cells = np.vstack([a.cells, b.cells + a.n_nodes])
    path = tmp_path / "two.vtu"
    meshio.write(path, meshio.Mesh(points, [("line3", cells)]))
    beams = read_beams(path)
    assert len(beams) == 2
    for beam, ref, offset in zip(beams, (a, b), (0, a.n_nodes), strict=True):
        assert beam.n_elements == ref.n_elements
        np.testing.assert_array_equal(beam.point_ids, np.arange(ref.n_nodes) + offset)
        np.testing.assert_array_equal(beam.points, ref.points)
        np.testing.assert_array_equal(beam.vertex_s, ref.vertex_s)
    with pytest.raises(ValueError, match="2 separate beams"):
        BeamMesh.read(path)


JUNCTION_POINTS = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0], [1, 2, 0]], float)


@pytest.mark.parametrize(
    "blocks",
    [
        # T junction at point 1, every branch in its own cell block (as the branching error
        # message advises)
        [np.array([[0, 1]]), np.array([[1, 2]]), np.array([[1, 3], [3, 4]])],
        # corner: two blocks meeting end to end at point 1
        [np.array([[0, 1]]), np.array([[4, 3], [3, 1]])],
    ],
    ids=["tee", "corner"],
)
def test_read_beams_chains_sharing_a_point_keep_its_id(blocks):
    m = meshio.Mesh(JUNCTION_POINTS, [("line", b) for b in blocks])
    beams = read_beams(m)
    assert len(beams) == len(blocks)
    for beam, block in zip(beams, blocks, strict=True):
        assert beam.n_elements == len(block)
        assert set(beam.point_ids.tolist()) == set(block.ravel().tolist())
        # the shared point 1 is an end vertex of every beam, with its coordinates
        end = [k for k in (0, beam.n_elements) if beam.point_ids[k] == 1]
        assert len(end) == 1
        np.testing.assert_array_equal(beam.points[end[0]], JUNCTION_POINTS[1])


# ---------------------------------------------------------------------------------------
# arc length of circular arcs
# ---------------------------------------------------------------------------------------
R_ARC, A0, A1 = 1.3, 0.2, 2.5


def test_arc_length_of_chords_is_exact():
    # 2-node elements are chords: length 2 R sin(dphi / 2) each, an exact identity
    for n in (1, 3, 8, 32):
        mesh = arc((0.3, 0.1, 0.2), R_ARC, A0, A1, n, 2)
        chord = 2 * R_ARC * np.sin((A1 - A0) / (2 * n))
        # roundoff: 8-point Gauss sum of a constant speed + cumsum of n terms: ~(8 + n) eps
        np.testing.assert_allclose(mesh.element_length, chord, rtol=(8 + n) * 2.3e-16)
        np.testing.assert_allclose(mesh.length, n * chord, rtol=(8 + n) * 2.3e-16)


def test_arc_length_of_quadratic_elements_converges_at_order_4():
    exact = R_ARC * (A1 - A0)
    ns = np.array([2, 4, 8, 16, 32])
    err = np.array(
        [abs(arc((0.3, 0.1, 0.2), R_ARC, A0, A1, n, 3).length - exact) / exact for n in ns]
    )
    order = np.log2(err[:-1] / err[1:])
    # quadratic interpolation of a circle: length error O(h^4); smallest error 3e-8 is far
    # above roundoff, so the observed order must approach 4
    assert np.all(np.abs(order - 4) < 0.5), order


# ---------------------------------------------------------------------------------------
# bad input: one ValueError naming the offending item
# ---------------------------------------------------------------------------------------
LINE = np.array([[i, 0.5 * i, 0.0] for i in range(6)], float)


def test_no_line_cells():
    m = meshio.Mesh(LINE, [("triangle", np.array([[0, 1, 2]]))])
    with pytest.raises(ValueError, match=r"no line or line3 cells \(cell types: triangle\)"):
        read_beams(m)


def test_zero_length_cell_same_node():
    m = meshio.Mesh(LINE, [("line", np.array([[0, 1], [1, 1], [1, 2]]))])
    with pytest.raises(ValueError, match=r"cell 1 has zero length \(both ends are node 1\)"):
        read_beams(m)


def test_zero_length_element_coincident_nodes():
    pts = LINE[:5].copy()
    pts[3] = pts[2]
    cells = np.column_stack([np.arange(4), np.arange(1, 5)])
    with pytest.raises(ValueError, match=r"element 2 has zero length \((nodes|points) \[2, 3\]\)"):
        BeamMesh(pts, cells)
    with pytest.raises(ValueError, match="element 0 has zero length"):
        straight((1, 2, 3), (1, 2, 3), 2)


def test_zero_length_element_from_file_names_file_points():
    # the message must name the file's point ids (0 and 5), not the beam-local numbers (2, 3)
    perm = np.array([3, 7, 0, 5, 2, 6])  # file id of chain vertex k
    pts = np.full((8, 3), 9.0)
    pts[perm] = np.outer(1.5 * np.arange(6) + 0.25, [1.0, 0.0, 0.0])
    pts[5] = pts[0]  # chain vertices 2 and 3 coincide
    cells = np.column_stack([perm[:-1], perm[1:]])[[3, 1, 0, 4, 2]][:, ::-1]
    with pytest.raises(ValueError, match=r"(?s)(?=.*\b0\b)(?=.*\b5\b)"):
        read_beams(meshio.Mesh(pts, [("line", cells)]))


def test_branching_mesh():
    m = meshio.Mesh(LINE, [("line", np.array([[0, 1], [1, 2], [1, 3], [3, 4]]))])
    with pytest.raises(ValueError, match=r"node 1 joins 3 cells"):
        read_beams(m)


def test_closed_loop():
    m = meshio.Mesh(LINE, [("line", np.array([[2, 3], [0, 1], [3, 0], [1, 2]]))])
    with pytest.raises(ValueError, match=r"closed loop"):
        read_beams(m)


def test_mixed_line_and_line3():
    m = meshio.Mesh(LINE, [("line", np.array([[0, 1]])), ("line3", np.array([[1, 3, 2]]))])
    with pytest.raises(ValueError, match=r"mixes line and line3"):
        read_beams(m)


def test_nan_coordinate():
    pts = LINE[:4].copy()
    pts[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"(node|point) 2 has a non-finite coordinate"):
        BeamMesh(pts, np.column_stack([np.arange(3), np.arange(1, 4)]))


def test_nan_coordinate_from_file_names_file_point():
    # the message must name the file's point id (0), not the beam-local number (2)
    perm = np.array([3, 7, 0, 5, 2, 6])  # file id of chain vertex k
    pts = np.full((8, 3), 9.0)  # points 1 and 4 are unused
    pts[perm] = np.outer(1.5 * np.arange(6) + 0.25, [1.0, 0.0, 0.0])
    pts[0, 0] = np.nan  # chain vertex 2 is file point 0
    cells = np.column_stack([perm[:-1], perm[1:]])[[3, 1, 0, 4, 2]]
    with pytest.raises(ValueError, match=r"point 0\b|node 0\b"):
        read_beams(meshio.Mesh(pts, [("line", cells)]))


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.vtu"
    with pytest.raises(ValueError, match=r"nowhere\.vtu does not exist"):
        BeamMesh.read(path)
    with pytest.raises(ValueError, match=r"nowhere\.vtu does not exist"):
        read_beams(str(path))


def test_unknown_format(tmp_path):
    path = tmp_path / "beam.notaformat"
    path.write_text("1 2 3\n")
    with pytest.raises(ValueError, match=r"meshio cannot read .*beam\.notaformat"):
        BeamMesh.read(path)


@pytest.mark.parametrize("suffix", ["vtu", "msh"])
def test_unreadable_file(tmp_path, suffix):
    # meshio.read calls sys.exit(1) on an unparsable file with a known suffix
    # (meshio/_helpers.py:_read_file): that must still come out as one ValueError
    path = tmp_path / f"garbage.{suffix}"
    path.write_text("this is not a mesh\n")
    with pytest.raises(ValueError, match=rf"meshio cannot read .*garbage\.{suffix}"):
        BeamMesh.read(path)


def test_xi_outside_the_beam():
    mesh = straight((0, 0, 0), (2, 1, 0), 3)
    beam = Beam(mesh, Section.diagonal(1, 1, 1, 1, 1, 1), "fv3")
    L = mesh.length
    for xi in (-0.25, L + 0.5, np.nan):
        with pytest.raises(ValueError, match=rf"xi = {xi} lies outside the beam"):
            beam.point_load(xi, force=(0, 1, 0))
        with pytest.raises(ValueError, match=rf"xi = {xi} lies outside the beam"):
            mesh.locate(xi)
    with pytest.raises(ValueError, match=r"xi = 3\.5 lies outside the beam"):
        mesh.locate([0.5, 3.5, 1.0])


@pytest.mark.parametrize("n", [0, -2, 2.5])
def test_bad_number_of_elements(n):
    with pytest.raises(ValueError, match=rf"n_elements must be a positive integer, got {n}"):
        straight((0, 0, 0), (1, 0, 0), n)


def test_translated_mesh_moves_points_and_keeps_lengths():
    """A translation keeps the arc lengths exactly (no recomputation) and the original mesh."""
    mesh = arc((0, 0, 0), 1.0, 0.0, 1.5, 4, 3)
    moved = mesh.translated(np.array([0.3, -1.0, 2.0]))
    np.testing.assert_array_equal(moved.points, mesh.points + [0.3, -1.0, 2.0])
    assert moved.vertex_s is mesh.vertex_s and moved.cells is mesh.cells
    rebuilt = BeamMesh(moved.points, moved.cells)
    np.testing.assert_allclose(rebuilt.vertex_s, mesh.vertex_s, rtol=1e-13)


def test_translated_beam_shares_the_stiffness():
    beam = Beam(
        straight((0, 0, 0), (1, 0, 0), 3, 3),
        Section.diagonal(EA=1, GAy=1, GAz=1, GJ=1, EJy=1, EJz=1),
    )
    moved = beam.translated((0.5, 0, 0))
    assert moved.stiffness is beam.stiffness
    np.testing.assert_allclose(moved.mesh.points[:, 0], beam.mesh.points[:, 0] + 0.5)
    with pytest.raises(ValueError, match="offset"):
        beam.translated((np.nan, 0, 0))
