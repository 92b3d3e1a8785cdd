"""VTU snapshots and PVD series (:mod:`sliders.app.vtu`): every field read back with meshio
against the arrays it came from, cell counts, the PVD index, atomic writes, bad input.

Exactness: VTU stores float64 in binary, so a value copied from an array must come back
bit for bit (``array_equal``).  Values the writer *computes* are compared with their
definition to roundoff: a point ``sum_a N_a X_a`` of a 2- or 3-node element carries at most
``3 eps`` relative rounding per term and the abscissa round trip ``X = (xi - s_e) / h_e`` one
more, so ``8 eps`` times the coordinates' scale bounds the difference (``POSITION``).  The
rigid part of a motion (:mod:`sliders.app.motion`) is the solution of least-squares
problems through the SVD: backward stable, it is off by at most ``m n eps`` times the size
of the right-hand side (``m`` rows, ``n`` unknowns; Higham, *Accuracy and Stability of
Numerical Algorithms*, Thm. 20.3; ``SPLIT``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from fvbeam import Beam, RigidBody, Section, Structure, straight
from fvbeam.io import OUTPUT_MARKER
from sliders.app.shapes import tube_sizes
from sliders.app.vtu import (
    PARTS,
    Frame,
    structure_size,
    to_meshio,
    write_pvd,
    write_series,
    write_vtu,
)
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import StraightLine
from sliders.sliding_beams.model import SlidingBeams

EPS = np.finfo(float).eps
POSITION = 8 * EPS
S_OVER_L, L = 0.3, 0.6
SECTION = Section.diagonal(EA=1e3, GAy=2e2, GAz=2e2, GJ=5.0, EJy=7.0, EJz=7.0)


@pytest.fixture(scope="module")
def sliding():
    """The sliding-beams setup (classical sliders, fv3, 5 elements) solved at s/L = 0.3."""
    statics, load = SlidingBeams("fv3", 5, "classical").problem(S_OVER_L)
    return statics, statics.solve(load)


def split_bound(structure: Structure, q: np.ndarray) -> float:
    """``m n eps`` times the largest entry of the fit's right-hand side (module docstring):
    ``m`` the structure's dofs, ``n`` six unknowns per beam or body (at most one group
    each), rotations weighted by the structure's size."""
    n = 6 * (len(structure.beams) + len(structure.bodies))
    ell = structure_size(structure)
    weighted = np.abs(q.reshape(-1, 6) * [1, 1, 1, ell, ell, ell]).max()
    return structure.n_dofs * n * EPS * weighted


def driven_piston(kind: str = "classical"):
    """The sliding-beams setup solved with the piston at ``s = 0.3 L`` (``q3``, the
    unknowns), written on the model whose reference places the piston at ``s = 0.1 L``:
    the same configuration, the piston's nodes displaced by its travel ``d = 0.2 L`` along
    x on top of ``q3``, its bottom ``ux`` held at ``d`` as a drive would hold it.

    Returns ``structure, q, sliders, unknowns, held`` of that model, ``q3`` and ``d``."""
    solved, load = SlidingBeams("fv3", 5, kind).problem(0.3)
    solution = solved.solve(load)
    statics, _ = SlidingBeams("fv3", 5, kind).problem(0.1)
    structure, d = statics.structure, 0.2 * L
    q = solution.q.copy()
    q[structure.dof_maps[1][::6]] += d
    held = np.setdiff1d(np.arange(structure.n_dofs), statics.free)
    return structure, q, statics.sliders, solution.unknowns, held, solution.q, d


def mixed():
    """A ``line`` beam (galerkin-p1) tied to a ``line3`` beam (fv3), a rigid body, a
    spherical slider of the body on a rigid line and a classical slider of a beam node on
    the line3 beam; random ``q`` and unknowns (the writer maps arrays, solved or not)."""
    a = Beam(straight((0, 0, 0), (1.0, 0.5, 0), 4, 2), SECTION, "galerkin-p1")
    b = Beam(straight((1.0, 0.5, 0), (1.0, 0.5, 1.2), 3, 3), SECTION, "fv3")
    hub = RigidBody("hub", (0.3, -0.4, 0.2))
    structure = Structure([a, b], [(0, "end", 1, "start")], [hub])
    rail = StraightLine((0, -0.4, 0.2), (1.0, -0.4, 0.2), name="rail")
    sliders = [
        Slider("spherical", rail, "hub", name="S"),
        Slider("classical", BeamChain(structure, [1], "B"), (0, 2), name="C"),
    ]
    rng = np.random.default_rng(7)
    q = rng.normal(size=structure.n_dofs)
    unknowns = [np.array([0.35, *rng.normal(size=3)]), np.array([0.8, *rng.normal(size=5)])]
    return structure, q, sliders, unknowns


def flat(mesh: meshio.Mesh) -> tuple[list[np.ndarray], np.ndarray, dict[str, np.ndarray]]:
    """Per cell: connectivity, cell type, and every cell field, over all blocks."""
    conn = [row for block in mesh.cells for row in block.data]
    types = np.array([block.type for block in mesh.cells for _ in block.data])
    data = {name: np.concatenate(blocks) for name, blocks in mesh.cell_data.items()}
    return conn, types, data


def pick(mesh: meshio.Mesh, part: str, index: int):
    """Cell positions, connectivities and cell types of one beam / slider / body."""
    conn, types, data = flat(mesh)
    where = np.flatnonzero((data["part"] == PARTS[part]) & (data["id"] == index))
    return where, np.array([conn[k] for k in where]), types[where], data


def assert_beams(mesh: meshio.Mesh, structure: Structure, q: np.ndarray, *kinds: str) -> None:
    """Every beam's cells, nodal motion and evaluation points against the arrays they come
    from (straight beams: an evaluation point lies at ``start + xi t``)."""
    _, _, data = flat(mesh)
    for b, (beam, kind) in enumerate(zip(structure.beams, kinds, strict=True)):
        q_beam = structure.local(b, q)
        where, cells, types, _ = pick(mesh, "beam", b)
        assert set(types) == {kind}
        assert data["element"][where].tolist() == list(range(beam.mesh.n_elements))
        nodal = q_beam.reshape(-1, 6)[beam.mesh.cells]
        assert np.array_equal(mesh.points[cells], beam.mesh.points[beam.mesh.cells])
        assert np.array_equal(mesh.point_data["displacement"][cells], nodal[..., :3])
        assert np.array_equal(mesh.point_data["rotation"][cells], nodal[..., 3:])
        assert np.isnan(data["force"][where]).all() and np.isnan(data["xi"][where]).all()
        forces = beam.internal_forces(q_beam)
        where, cells, _, _ = pick(mesh, "evaluation point", b)
        for name in ("xi", "force", "moment", "force_global", "moment_global"):
            assert np.array_equal(data[name][where], getattr(forces, name))
        points = cells[:, 0]
        start, end = beam.mesh.points[0], beam.mesh.points[beam.mesh.n_elements]
        expected = start + np.outer(forces.xi, (end - start) / beam.mesh.length)
        scale = np.abs(beam.mesh.points).max()
        assert np.abs(mesh.points[points] - expected).max() <= POSITION * scale
        motion = beam.displacements(q_beam, forces.xi)
        assert np.array_equal(mesh.point_data["displacement"][points], motion[:, :3])
        assert np.array_equal(mesh.point_data["rotation"][points], motion[:, 3:])
        assert np.isnan(data["reaction"][where]).all()


def test_sliding_beams_fields_read_back(sliding, tmp_path):
    statics, solution = sliding
    structure, q = statics.structure, solution.q
    path = tmp_path / "state.vtu"
    write_vtu(path, structure, q, statics.sliders, solution.unknowns)
    mesh = meshio.read(path)
    conn, types, data = flat(mesh)
    # fv3: two evaluation points per element (docs/theory.md), 5 elements per beam
    assert (types == "line3").sum() == 10 and (types == "vertex").sum() == 2 * 2 * 5 + 2
    assert np.bincount(data["part"]).tolist() == [10, 20, 2]
    size = S_OVER_L * L + L
    # the radii a render draws (tests/test_tube_sizes.py), the largest on the sliders
    radii = tube_sizes(structure, statics.sliders, size).radii
    for b, r in enumerate(radii):
        _, cells, _, _ = pick(mesh, "beam", b)
        assert np.all(mesh.point_data["radius"][cells] == r)
    assert_beams(mesh, structure, q, "line3", "line3")
    # without the held dofs there is no rigid part: the whole displacement is elastic
    assert np.all(mesh.point_data["rigid_displacement"] == 0)
    assert np.array_equal(mesh.point_data["elastic_displacement"], mesh.point_data["displacement"])
    for i, (slider, y) in enumerate(zip(statics.sliders, solution.unknowns, strict=True)):
        where, cells, kinds, _ = pick(mesh, "slider", i)
        assert kinds.tolist() == ["vertex"] and data["element"][where].tolist() == [-1]
        assert data["xi"][where][0] == y[0]
        assert np.array_equal(data["reaction"][where][0], y[1:4])
        # straight line along x, slider axes = global axes: m = mu_2 e2 x t + mu_3 e3 x t
        mu_2, mu_3 = y[4:]
        couple = np.array([0.0, mu_3, -mu_2])
        assert np.abs(data["couple"][where][0] - couple).max() <= 4 * EPS * np.abs(y[4:]).max()
        point = cells[0, 0]
        x, _, _ = slider.line.geometry(y[0], q)
        warped = mesh.points[point] + mesh.point_data["displacement"][point]
        assert np.abs(warped - x).max() <= POSITION * size
        assert np.array_equal(
            mesh.point_data["rotation"][point], q[slider.body_dofs(structure)[3:]]
        )


def test_mixed_structure_body_and_rigid_line(tmp_path):
    structure, q, sliders, unknowns = mixed()
    path = tmp_path / "mixed.vtu"
    write_vtu(path, structure, q, sliders, unknowns, radius=[0.02, 0.01])
    mesh = meshio.read(path)
    conn, types, data = flat(mesh)
    assert (types == "line").sum() == 4 and (types == "line3").sum() == 3
    # galerkin-p1 reduced: one Gauss point per element; fv3: two evaluation points
    assert (data["part"] == PARTS["evaluation point"]).sum() == 4 * 1 + 3 * 2
    assert_beams(mesh, structure, q, "line", "line3")
    radius = mesh.point_data["radius"]
    for b, r in enumerate((0.02, 0.01)):
        _, cells, _, _ = pick(mesh, "beam", b)
        assert np.all(radius[cells] == r)
    # the tied node: written once per beam, the same dofs
    _, cells_a, _, _ = pick(mesh, "beam", 0)
    _, cells_b, _, _ = pick(mesh, "beam", 1)
    tip, root = cells_a[-1, 1], cells_b[0, 0]
    assert np.array_equal(mesh.points[tip], mesh.points[root])
    tied = q[structure.node_dofs((0, "end"))]
    assert np.array_equal(mesh.point_data["displacement"][[tip, root]], [tied[:3]] * 2)
    where, cells, _, _ = pick(mesh, "body", 0)
    hub = structure.bodies[0]
    assert np.array_equal(mesh.points[cells[0, 0]], hub.position)
    dofs = structure.node_dofs("hub")
    assert np.array_equal(mesh.point_data["displacement"][cells[0, 0]], q[dofs[:3]])
    assert np.array_equal(mesh.point_data["rotation"][cells[0, 0]], q[dofs[3:]])
    assert radius[cells[0, 0]] == 0.02 and np.isnan(data["reaction"][where]).all()
    where, cells, _, _ = pick(mesh, "slider", 0)
    assert np.array_equal(mesh.points[cells[0, 0]], sliders[0].line.at(0.35).x)
    assert np.array_equal(mesh.point_data["displacement"][cells[0, 0]], np.zeros(3))
    assert np.array_equal(data["couple"][where][0], np.zeros(3))
    where, cells, _, _ = pick(mesh, "slider", 1)
    x, _, _ = sliders[1].line.geometry(0.8, q)
    warped = mesh.points[cells[0, 0]] + mesh.point_data["displacement"][cells[0, 0]]
    assert np.abs(warped - x).max() <= POSITION * np.abs(x).max()


def test_the_driven_piston_is_split_into_its_travel_and_its_bending(tmp_path):
    """The piston driven ``d`` along x (:func:`driven_piston`): every point of the piston
    (nodes, evaluation points, slider B's contact) has the rigid displacement ``(d, 0, 0)``
    and the elastic displacement the piston has with its reference at ``s = 0.3 L``, to the
    forming of ``q`` (one rounding, ``eps |q|``) plus the split's bound; the clamped
    cylinder (and slider A's contact on it) has no rigid part, to the bit.  Everywhere
    ``displacement = rigid_displacement + elastic_displacement`` to one rounding."""
    structure, q, sliders, unknowns, held, q3, d = driven_piston()
    path = tmp_path / "piston.vtu"
    write_vtu(path, structure, q, sliders, unknowns, held=held)
    mesh = meshio.read(path)
    total, rigid, elastic = (
        mesh.point_data[name]
        for name in ("displacement", "rigid_displacement", "elastic_displacement")
    )
    bound = EPS * np.abs(q).max() + split_bound(structure, q)
    travel = np.array([d, 0.0, 0.0])
    piston, q3_piston = structure.beams[1], structure.local(1, q3)
    _, cells, _, _ = pick(mesh, "beam", 1)
    nodes = np.unique(cells)
    assert np.abs(rigid[nodes] - travel).max() <= bound
    nodal = q3_piston.reshape(-1, 6)[:, :3]
    assert np.abs(elastic[nodes] - nodal[nodes - nodes.min()]).max() <= bound
    _, cells, _, _ = pick(mesh, "evaluation point", 1)
    points = cells[:, 0]
    assert np.abs(rigid[points] - travel).max() <= bound
    xi = piston.internal_forces(q3_piston).xi
    assert np.abs(elastic[points] - piston.displacements(q3_piston, xi)[:, :3]).max() <= bound
    for part in ("beam", "evaluation point"):
        _, cells, _, _ = pick(mesh, part, 0)
        assert np.all(rigid[np.unique(cells)] == 0)
    (a,), (b,) = (pick(mesh, "slider", i)[1][:, 0] for i in range(2))
    assert np.all(rigid[a] == 0) and np.abs(rigid[b] - travel).max() <= bound
    # slider B's contact drawn at its true place: the deformed point of the s = 0.3 L model
    x3, _, _ = sliders[1].line.geometry(unknowns[1][0], q3)
    placed = mesh.points[b] + rigid[b] + elastic[b]
    assert np.abs(placed - x3 - travel).max() <= POSITION * L + 2 * bound
    assert np.abs(rigid + elastic - total).max() <= EPS * np.abs(total).max()


def test_pyvista_reads_line3_as_quadratic_edges(sliding, tmp_path):
    pv = pytest.importorskip("pyvista")
    statics, solution = sliding
    path = tmp_path / "state.vtu"
    write_vtu(path, statics.structure, solution.q, statics.sliders, solution.unknowns)
    grid = pv.read(path)
    kinds = np.asarray(grid.celltypes)
    assert (kinds == pv.CellType.QUADRATIC_EDGE).sum() == 10
    assert (kinds == pv.CellType.VERTEX).sum() == 22
    assert {"displacement", "rotation", "radius"} <= set(grid.point_data)
    warped = grid.warp_by_vector("displacement")
    assert np.array_equal(warped.points, grid.points + grid.point_data["displacement"])


def test_bad_input_names_the_item(sliding, tmp_path):
    statics, solution = sliding
    structure, sliders, ys = statics.structure, statics.sliders, solution.unknowns
    with pytest.raises(ValueError, match=rf"q must be {structure.n_dofs} finite values"):
        to_meshio(structure, solution.q[:-1], sliders, ys)
    with pytest.raises(ValueError, match=r"unknowns: 1 arrays for 2 sliders"):
        to_meshio(structure, solution.q, sliders, ys[:1])
    with pytest.raises(
        ValueError,
        match=r"unknowns\[1\] \(slider 'B'\): expected 6 finite "
        r"values \(xi, lambda_x",
    ):
        to_meshio(structure, solution.q, sliders, [ys[0], ys[1][:4]])
    with pytest.raises(
        ValueError,
        match=r"radius must be one positive number or one per "
        r"beam \(2\)",
    ):
        to_meshio(structure, solution.q, sliders, ys, radius=[0.1, -0.1])
    with pytest.raises(ValueError, match=r"must end in \.vtu"):
        write_vtu(tmp_path / "x.vtk", structure, solution.q, sliders, ys)
    with pytest.raises(ValueError, match=r"unknowns\[0\] \(slider 'A'\): .* got 'xi'"):
        to_meshio(structure, solution.q, sliders, ["xi", ys[1]])
    structure, q, sliders, unknowns = mixed()
    itself = Slider("classical", sliders[1].line, (1, 1), name="itself")
    with pytest.raises(
        ValueError,
        match=r"slider 'itself': its body is a node of its own "
        r"line 'B'",
    ):
        to_meshio(structure, q, [itself], [unknowns[1]])


def test_failed_write_keeps_the_old_file(sliding, tmp_path, monkeypatch):
    statics, solution = sliding
    path = tmp_path / "state.vtu"
    write_vtu(path, statics.structure, solution.q, statics.sliders, solution.unknowns)
    before = path.read_bytes()

    def broken(target, *args, **kwargs):
        Path(target).write_bytes(b"<VTKFile truncated")
        raise OSError("disk full")

    monkeypatch.setattr(meshio, "write", broken)
    with pytest.raises(OSError, match="disk full"):
        write_vtu(path, statics.structure, 2 * solution.q, statics.sliders, solution.unknowns)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["state.vtu"]


def frames(times, structure, q, sliders, unknowns):
    return [Frame(t, structure, (1 + k) * q, sliders, unknowns) for k, t in enumerate(times)]


def test_pvd_lists_the_steps(tmp_path):
    structure, q, sliders, unknowns = mixed()
    times = [0.0, 0.1, 0.30000000000000004]
    index = write_series(tmp_path / "run", frames(times, structure, q, sliders, unknowns))
    assert index == tmp_path / "run" / "run.pvd"
    root = ET.parse(index).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    sets = root.findall("./Collection/DataSet")
    assert [float(s.get("timestep")) for s in sets] == times
    names = [s.get("file") for s in sets]
    assert names == [f"step_{k:06d}.vtu" for k in range(3)]
    for k, name in enumerate(names):
        mesh = meshio.read(index.parent / name)
        _, cells, _, _ = pick(mesh, "body", 0)
        dofs = structure.node_dofs("hub")
        assert np.array_equal(mesh.point_data["displacement"][cells[0, 0]], (1 + k) * q[dofs[:3]])
    other = tmp_path / "elsewhere" / "index.pvd"
    write_pvd(other, [(1.5, index.parent / names[0])])
    dataset = ET.parse(other).getroot().find("./Collection/DataSet")
    assert dataset.get("file") == "../run/step_000000.vtu" and dataset.get("timestep") == "1.5"


def test_pvd_bad_input(tmp_path):
    structure, q, sliders, unknowns = mixed()
    vtu = tmp_path / "a.vtu"
    write_vtu(vtu, structure, q, sliders, unknowns)
    with pytest.raises(ValueError, match=r"steps\[1\]: time 0.5 repeats steps\[0\]"):
        write_pvd(tmp_path / "a.pvd", [(0.5, vtu), (0.5, vtu)])
    with pytest.raises(ValueError, match=r"steps\[0\]: time must be a finite number"):
        write_pvd(tmp_path / "a.pvd", [(float("nan"), vtu)])
    with pytest.raises(ValueError, match=r"steps\[0\]: file .*missing.vtu' does not exist"):
        write_pvd(tmp_path / "a.pvd", [(0.0, tmp_path / "missing.vtu")])
    with pytest.raises(ValueError, match=r"frames\[1\] must be a Frame"):
        write_series(tmp_path / "run", [frames([0.0], structure, q, sliders, unknowns)[0], 3])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.vtu"]


def test_series_is_replaced_as_a_whole(tmp_path):
    structure, q, sliders, unknowns = mixed()
    run = tmp_path / "run"
    write_series(run, frames([0.0, 1.0, 2.0], structure, q, sliders, unknowns))
    old = {p.name: p.read_bytes() for p in run.iterdir()}

    def interrupted():
        yield from frames([0.0, 1.0], structure, -q, sliders, unknowns)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_series(run, interrupted())
    assert {p.name: p.read_bytes() for p in run.iterdir()} == old
    assert [p.name for p in tmp_path.iterdir()] == ["run"]
    write_series(run, frames([5.0, 6.0], structure, -q, sliders, unknowns))
    assert sorted(p.name for p in run.iterdir()) == sorted(
        [OUTPUT_MARKER, "run.pvd", "step_000000.vtu", "step_000001.vtu"]
    )
    assert [p.name for p in tmp_path.iterdir()] == ["run"]
