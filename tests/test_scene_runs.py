"""Running the shipped scenes: the paper's setups against their closed forms and against the
studies' own models, and the tables a run writes."""

import csv
import re
import tomllib

import numpy as np
import pytest
from test_condensed import agreement_bound, state
from test_scenes import ROOT, SCENES, data

from fvbeam import closed_forms
from fvbeam.io import replace_directory
from sliders.app.history import ENERGIES
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene, parse_scene
from sliders.app.state_tables import STEP_COLUMNS
from sliders.app.tables import COLUMNS, MARKER, write_results
from sliders.app.vtu import to_meshio
from sliders.sliding_beams.exact import sliding_beams
from studies.fig4_stiffness import EJ, GA, L, SlidingBeams

EPS = np.finfo(float).eps
#: Largest |relative error| of k with 5 fv3 elements over s/L = 0, 0.01, ..., 0.95, measured
#: in docs/sliders.md (0.88 % spherical, 0.46 % classical section), rounded up at the last
#: printed digit; the scene's stations s/L = 0, 0.05, ..., 0.95 are among those.
MEASURED = {"spherical": 0.00885, "classical": 0.00465}


def results_of(scene: dict):
    return run(Model(parse_scene(scene, SCENES)), progress=False)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_sliding_beams_scene_is_the_fig4_model(kind):
    """studies/scenes/fig4_sliding_beams.toml is the setup of studies/fig4_stiffness.py: at
    every station the same state as SlidingBeams within the derived agreement bound of two
    converged Newton solutions (tests/test_condensed.py; the scene's sweep starts warm, the
    study cold), and k within the measured accuracy of docs/sliders.md of the analytic
    two-beam solution."""
    scene = data("fig4_sliding_beams")
    for slider in scene["slider"]:
        slider["kind"] = kind
    results = results_of(scene)
    study = SlidingBeams("fv3", 5, kind)
    assert not results.failures and len(results.samples) == 20
    for sample in results.samples:
        statics, f = study.problem(sample.value / L)
        reference = statics.solve(f)
        mine = sample.solution
        assert np.all(
            np.abs(state(statics, mine) - state(statics, reference))
            <= agreement_bound(statics, mine, reference, f)
        )
        structure = sample.statics.structure
        tip = structure.beams[1].displacements(structure.local(1, mine.q), L)[0, 1]
        exact = sliding_beams(sample.value, L, EJ, GA, kind)["k_norm"]
        assert abs((1.0 / tip * L**3 / EJ) / exact - 1) <= MEASURED[kind]


def test_fig1_scene_is_the_paper_closed_form():
    """Tip deflection and rotation of the one-element fv3 cantilever equal
    fvbeam.closed_forms.cantilever_fv3 (paper Sec. 5.3; exact for one element) to the roundoff
    bound of the solve (agreement_bound of a solution with itself bounds its distance from
    the exact discrete solution twice over) plus the closed form's own rounding (4 eps)."""
    results = run(Model(load_scene(SCENES / "fig1_cantilever.toml")), progress=False)
    values = np.array([s.value for s in results.samples])
    v_flex, v_shear, phi = closed_forms.cantilever_fv3(values, L=1.0, EJ=1.0, GA=1.0, F=1.0)
    for sample, v, rz in zip(results.samples, v_flex + v_shear, phi, strict=True):
        statics, sol = sample.statics, sample.solution
        bound = agreement_bound(statics, sol, sol, sample.load)
        tip = statics.structure.node_dofs((0, "end"))[[1, 5]]
        where = np.searchsorted(statics.free, tip)
        got = sol.q[tip]
        assert np.all(np.abs(got - [v, rz]) <= bound[where] + 4 * EPS * np.abs([v, rz]))


def test_end_stops_scene(tmp_path):
    """tests/test_end_stops.py's closed forms: pulled inwards the tip slides by the end
    deflection F L^3 / 3EJ + F L / GA (relative 1e-9, roundoff); pushed, it rests at the
    end and the stop takes the force (relative 1e-12).  The clamp's reactions in
    reactions.csv balance what the stop does not take: the force and its moment about the
    clamp, 1 m away along y (relative 1e-9; the stop's share is 0 or all of it)."""
    results = run(Model(load_scene(SCENES / "end_stops.toml")), progress=False)
    EJ_arm, GA_arm, F = 4e4, 1e8, 50.0
    for sample in results.samples:
        force = sample.value * F
        xi, lam = sample.solution.unknowns[0][0], sample.solution.unknowns[0][1:4]
        if force < 0:
            assert xi == pytest.approx(1 + force / (3 * EJ_arm) + force / GA_arm, rel=1e-9)
        else:
            assert xi == 1.0 and lam[0] == pytest.approx(force, rel=1e-12)
    write_results(results, tmp_path / "out")
    for row in read_csv(tmp_path / "out" / "reactions.csv")[1:]:
        row = dict(zip(COLUMNS["reactions"], row, strict=True))
        force = float(row["value"]) * F
        held = -force if force < 0 else 0.0
        assert float(row["fx"]) == pytest.approx(held, rel=1e-9, abs=1e-9 * F)
        assert float(row["mz"]) == pytest.approx(-held, rel=1e-9, abs=1e-9 * F)


def test_spline_slider_scene_twists_by_T_a_over_GJ():
    """tests/test_spline_slider.py's twist test: the arm's root turns by T a / GJ (relative
    1e-9: roundoff of K ~ 1e10 against rotations ~ 1e-5) with linear kinematics (the
    scene's ``auto`` takes the exact path, whose second-order terms are above that)."""
    model = Model(load_scene(SCENES / "spline_slider.toml"))
    results = run(model, progress=False, kinematics="linear")
    (sample,) = results.samples
    structure = sample.statics.structure
    turn = sample.solution.q[structure.node_dofs((1, "start"))[3]]
    assert turn == pytest.approx(100.0 * 0.37 / 2e4, rel=1e-9)


def test_tip_on_a_straight_rail_along_the_load_is_free():
    """rigid_lines.toml: the rail through tip a runs along the load, so the tip moves as a free
    cantilever's, F L^3 / 3EJ + F L / GA (fv3 is exact for an end load; relative 1e-9 as in
    tests/test_end_stops.py) and the rail's reaction vanishes (1e-9 F)."""
    results = run(Model(load_scene(SCENES / "rigid_lines.toml")), progress=False)
    (sample,) = results.samples
    structure = sample.statics.structure
    uy = sample.solution.q[structure.node_dofs((0, "end"))[1]]
    assert uy == pytest.approx(10.0 / (3 * 1e2) + 10.0 / 8e6, rel=1e-9)
    assert np.abs(sample.solution.unknowns[0][1:4]).max() <= 1e-9 * 10.0


def test_arch_from_a_mesh_file_is_the_generated_arch():
    """meshes/arch.msh holds exactly the nodes of fvbeam.arc, so both scenes are one model and
    give the same numbers bit for bit.  The supports' vertical reactions balance the
    distributed load (the sum of its nodal loads; the internal forces of the fv regions
    cancel in pairs): the y rows of ``K q - f`` sum to zero but for the Newton residual left on the
    free rows (each below ``rho max|f|``) and the rounding of ``K`` and of ``K q`` on every
    row (``n_row eps (|K| |q|)_i`` each, tests/test_condensed.py; twice, for the entries of
    ``K`` and the product)."""
    generated, read = (
        run(Model(load_scene(SCENES / f"{n}.toml")), progress=False).samples[0]
        for n in ("arch", "arch_mesh")
    )
    np.testing.assert_array_equal(generated.solution.q, read.solution.q)
    statics, q, f = generated.statics, generated.solution.q, generated.load
    residual = statics.K @ q - f
    rows = np.arange(1, statics.structure.n_dofs, 6)
    free = np.intersect1d(rows, statics.free)
    n_row = int(np.diff(statics.K.indptr).max())
    bound = (
        len(free) * generated.solution.residuals[-1] * np.abs(f).max()
        + 2 * n_row * EPS * (abs(statics.K) @ abs(q))[rows].sum()
    )
    supports = np.setdiff1d(rows, statics.free)
    assert abs(residual[supports].sum() + f[rows].sum()) <= bound


def test_carriage_sweep_places_the_sliding_point_on_the_chain():
    """The abscissa sweep moves the carriage (and its spring) so that its sliding point sits
    at x = value on the straight chain: the body node at (value, 0, 0.05), to the rounding
    of the offset's additions (4 eps of the chain's length)."""
    results = run(Model(load_scene(SCENES / "carriage_on_chain.toml")), progress=False)
    assert not results.failures
    for sample in results.samples:
        body = sample.statics.structure.bodies[0]
        np.testing.assert_allclose(
            body.position, [sample.value, 0.0, 0.05], rtol=0, atol=4 * EPS * 1.8
        )


def read_csv(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def test_tables_columns_and_rows(tmp_path):
    """Every table has its documented header; one row per sample and node (5 fv3 elements:
    11 nodes per beam), slider, recovery point (2 per fv3 element) or support."""
    scene = data("fig4_sliding_beams")
    scene["output"]["csv"] = list(COLUMNS)
    results = results_of(scene)
    write_results(results, tmp_path / "out")
    n = len(results.samples)
    rows = {name: read_csv(tmp_path / "out" / f"{name}.csv") for name in COLUMNS}
    for name, table in rows.items():
        assert tuple(table[0]) == COLUMNS[name]
    counts = {
        "samples": n,
        "nodes": n * 2 * 11,
        "sliders": n * 2,
        "internal_forces": n * 2 * 10,
        "reactions": n * 2,
    }
    assert {name: len(table) - 1 for name, table in rows.items()} == counts
    assert tomllib.loads((tmp_path / "out" / "scene.toml").read_text())["title"]


def test_a_rerun_replaces_the_whole_directory(tmp_path):
    out = tmp_path / "out"
    write_results(run(Model(load_scene(SCENES / "fig1_cantilever.toml")), progress=False), out)
    write_results(run(Model(load_scene(SCENES / "end_stops.toml")), progress=False), out)
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [MARKER, "scene.toml", "samples.csv", "sliders.csv", "reactions.csv"]
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_replace_directory_refuses_foreign_directories_and_keeps_the_old_on_error(tmp_path):
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("keep")
    with pytest.raises(ValueError, match="not written by this program"):
        replace_directory(foreign, lambda d: None, MARKER)
    assert (foreign / "notes.txt").read_text() == "keep"
    out = tmp_path / "out"
    replace_directory(out, lambda d: (d / "a.csv").write_text("old"), MARKER)

    def fail(directory):
        (directory / "a.csv").write_text("new")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        replace_directory(out, fail, MARKER)
    assert (out / "a.csv").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine", "out"]


def test_interrupted_sweep_keeps_the_completed_samples(monkeypatch):
    model = Model(load_scene(SCENES / "fig1_cantilever.toml"))
    build = model.problem
    calls = []

    def interrupt(value=None):
        calls.append(value)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return build(value)

    monkeypatch.setattr(model, "problem", interrupt)
    results = run(model, progress=False)
    assert results.interrupted and len(results.samples) == 3 and results.planned == 21


def test_states_and_render_of_the_carriage_sweep(tmp_path):
    """``vtu = true``: the .pvd lists one VTU per converged sample, its time the sample's
    value, and each VTU holds the slider's abscissa and reaction exactly as the solution
    (binary float64, copied); ``png = "last"``: one render, of the last sample, not blank
    (a blank render has zero spread)."""
    import xml.etree.ElementTree as ET

    import meshio
    from PIL import Image

    results = run(Model(load_scene(SCENES / "carriage_on_chain.toml")), progress=False)
    out = tmp_path / "carriage"
    write_results(results, out)
    datasets = ET.parse(out / "states" / "states.pvd").getroot().iter("DataSet")
    listed = [(float(d.get("timestep")), d.get("file")) for d in datasets]
    assert [t for t, _ in listed] == [s.value for s in results.samples]
    for (_, name), sample in zip(listed, results.samples, strict=True):
        mesh = meshio.read(out / "states" / name)
        part = np.concatenate(mesh.cell_data["part"])  # readers merge blocks of one type
        slider = np.flatnonzero(part == 2)
        assert len(slider) == 1
        y = sample.solution.unknowns[0]
        assert np.concatenate(mesh.cell_data["xi"])[slider[0]] == y[0]
        np.testing.assert_array_equal(np.concatenate(mesh.cell_data["reaction"])[slider[0]], y[1:4])
    renders = sorted(p.name for p in out.glob("render_*.png"))
    assert renders == [f"render_{results.samples[-1].index:06d}.png"]
    assert np.asarray(Image.open(out / renders[0])).std() > 0


def test_every_output_column_and_field_is_documented():
    """docs/scenes.md, section Outputs, has a table row (name, unit, meaning) for every
    column of every table (static and per-step), of ``history.csv`` (the slider columns as
    ``NAME.xi`` ...) and for every VTU point and cell field."""
    text = (ROOT / "docs" / "scenes.md").read_text()
    section = text[text.index("## Outputs") : text.index("## Validation")]
    documented = {
        name
        for line in section.splitlines()
        if line.startswith("| `")
        for name in re.findall(r"`([^`]+)`", line.split("|")[1])
    }
    columns = {c for table in (*COLUMNS.values(), *STEP_COLUMNS.values()) for c in table}
    history = {"step", "t", "h", "iterations", *ENERGIES, "NAME.xi", "NAME.residual"}
    statics, load = SlidingBeams("fv3", 1, "classical").problem(0.3)
    solution = statics.solve(load)
    mesh = to_meshio(statics.structure, solution.q, statics.sliders, solution.unknowns)
    fields = set(mesh.point_data) | set(mesh.cell_data)
    assert columns | history | fields <= documented, (columns | history | fields) - documented
