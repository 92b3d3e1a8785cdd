"""The Python API as a user meets it: ``import fvbeam`` and ``import sliders`` only, parts named
as in scenes, a scene's study of any kind through ``run``, VTU in one call.

Sources of the asserted numbers:

* the Figure 4 setup built by a user script and by
  :class:`sliders.sliding_beams.model.SlidingBeams` is the same arithmetic on the same numbers
  (the piston is the cylinder's beam translated in both; the script only names what the
  library indexes), so the tip stiffnesses agree to a few roundings of the final
  normalisation ``F L^3 / (EJ v)`` (``4 eps``);
* a name and an index that denote the same node give the same dofs: exact equality;
* a section's inertia given as three principal values is the diagonal matrix, as a scene's:
  exact equality (no arithmetic);
* the dynamic route: the drive's formula ``xi = 0.6 + 0.035 t`` to the Newton tolerance, the
  number of fixed steps ``t_end / h``, and byte-for-byte equal files from the command and from
  Python, and from a recorder streaming to disk and one written from memory;
* the one-call VTU and the frame route store the same arrays: exact equality (VTU stores
  float64 in binary).
"""

from __future__ import annotations

import filecmp
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
from test_scenes import ROOT, SCENES

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from sliders import (
    BeamChain,
    DofDrive,
    DynamicRun,
    Dynamics,
    Frame,
    Linear,
    Model,
    Recorder,
    Slider,
    SliderStatics,
    load_scene,
    run,
    solve_translated,
    to_meshio,
    write_dynamic,
    write_series,
    write_vtu,
)
from sliders.app.cli import main
from sliders.app.state_tables import node_label
from sliders.sliding_beams.model import PAPER, SlidingBeams

EPS = np.finfo(float).eps
#: The Newton tolerance of the scenes' studies (their default ``tol``).
TOL = 1e-8
L = PAPER.length
HEAVY = ("matplotlib", "pyvista", "vtk", "vtkmodules")


# -- a user script: the paper's Figure 4 setup --------------------------------------------------
def figure4(kind: str, s_over_L: float, n_elements: int = 4):
    """The sliding beams as a user writes them: cylinder C clamped at its start, piston P
    (the cylinder moved by s) held in ux and rx at its start, P's start sliding on C, C's end
    sliding on P, a unit transverse force at P's end."""
    section = Section.diagonal(EA=1.1e9, GAy=1.1e8, GAz=1.1e8, GJ=4.1e4, EJy=4.1e4, EJz=4.1e4)
    cylinder = Beam(straight((0, 0, 0), (L, 0, 0), n_elements, name="C"), section, "fv3")
    piston = cylinder.translated((s_over_L * L, 0, 0), name="P")
    structure = Structure([cylinder, piston])
    joints = [
        Slider(kind, BeamChain(structure, "C"), "P.start", name="A"),
        Slider(kind, BeamChain(structure, "P"), "C.end", name="B"),
    ]
    supports = [Support("C.start"), Support("P.start", kind="ux+rx")]
    statics = SliderStatics(structure, supports, joints, method="condensed")
    return statics, structure.nodal_load("P.end", force=(0, 1.0, 0))


def tip_stiffness(statics: SliderStatics, q: np.ndarray) -> float:
    """``F L^3 / (EJ v)`` with ``v`` the piston tip's ``uy``, read by name."""
    tip = q[statics.structure.node_dofs("P.end")[1]]
    return PAPER.force / tip * L**3 / PAPER.EJ


@pytest.mark.parametrize("kind", ["spherical", "classical"])
@pytest.mark.parametrize("s_over_L", [0.1, 0.5, 0.9])
def test_a_user_script_solves_figure_4_as_the_library_does(kind, s_over_L):
    statics, f = figure4(kind, s_over_L)
    k = tip_stiffness(statics, statics.solve(f).q)
    assert k == pytest.approx(SlidingBeams("fv3", 4, kind).stiffness(s_over_L), rel=4 * EPS)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_named_sliders_move_with_their_beams_in_a_translated_batch(kind):
    """``solve_translated`` moves a slider whose body is named ``"P.start"`` with beam P:
    the batch of the user's template gives the library's stiffnesses at every station."""
    stations = np.array([0.1, 0.5, 0.9])
    statics, f = figure4(kind, 0.0)
    shifts = np.zeros((len(stations), 2, 3))
    shifts[:, statics.structure.beam_index("P"), 0] = stations * L
    mine = solve_translated(statics, shifts, np.tile(f, (len(stations), 1)))
    model = SlidingBeams("fv3", 4, kind)
    theirs = model.solve(stations)
    for a, b in zip(mine, theirs, strict=True):
        assert tip_stiffness(statics, a.q) == pytest.approx(
            model.tip_stiffness(model.template[0], b), rel=4 * EPS
        )


# -- names and indices ---------------------------------------------------------------------------
SECTION = Section.diagonal(EA=1e3, GAy=2e2, GAz=2e2, GJ=5.0, EJy=7.0, EJz=7.0, mass_per_length=1.0)


def named_structure() -> Structure:
    """Beams C then P joined end to start, and a body ``hub`` at P's end."""
    c = Beam(straight((0, 0, 0), (1, 0, 0), 3, name="C"), SECTION)
    p = Beam(straight((1, 0, 0), (1, 1, 0), 2, name="P"), SECTION)
    return Structure(
        [c, p], [("C.end", "P.start"), ("P.end", "hub")], [RigidBody("hub", (1, 1, 0))]
    )


def test_a_support_is_labelled_as_a_scene_names_its_node():
    """The reactions table names a support's node the scene's way whichever form the
    support was given in (a node index of an end is the end's name; an inner node its
    index, 1 of C's 3 elements being its first inner vertex)."""
    structure = named_structure()
    labels = {
        "C.start": ["C.start", ("C", "start"), (0, "start"), ("C", 0), (0, 0)],
        "P.end": ["P.end", ("P", 2), (1, "end")],
        "C.1": [("C", 1), (0, 1)],
        "hub": ["hub"],
    }
    for label, refs in labels.items():
        for ref in refs:
            support = Support(ref) if isinstance(ref, str) else Support(*ref)
            assert node_label(structure, support) == label, ref


def test_names_and_indices_give_the_same_dofs():
    structure = named_structure()
    same = [
        ["C.start", (0, "start"), ("C", "start"), ("C", 0), (0, 0)],
        ["C.end", (0, "end"), ("C", 3), "P.start", (1, 0)],
        ["P.end", (1, "end"), ("P", 2), "hub"],
    ]
    for refs in same:
        dofs = [structure.node_dofs(ref) for ref in refs]
        assert all(np.array_equal(d, dofs[0]) for d in dofs), refs
        positions = [structure.node_position(ref) for ref in refs]
        assert all(np.array_equal(x, positions[0]) for x in positions), refs
    q = np.arange(structure.n_dofs, dtype=float)
    assert np.array_equal(structure.local("P", q), structure.local(1, q))
    f = np.ones(structure.beams[1].n_dofs)
    assert np.array_equal(structure.gather("P", f), structure.gather(1, f))
    assert np.array_equal(
        structure.nodal_load("P.end", (1, 2, 3)), structure.nodal_load((1, "end"), (1, 2, 3))
    )
    supports = [Support("C.start"), Support("P.end", kind="pin"), Support("C", "end", "ux")]
    by_index = [Support(0, "start"), Support(1, "end", "pin"), Support(0, "end", "ux")]
    assert np.array_equal(structure.support_dofs(supports), structure.support_dofs(by_index))
    chain = BeamChain(structure, ["C", "P"])
    assert chain.indices == BeamChain(structure, [0, 1]).indices == [0, 1]
    assert chain.name == "C+P" and BeamChain(structure, "P").indices == [1]
    rail = BeamChain(structure, "C")
    for body in ("hub", "P.end"):
        slider = Slider("spherical", rail, body)
        assert np.array_equal(slider.body_dofs(structure), structure.node_dofs((1, "end")))
    hold = Dynamics(structure, [Support("C.start")], drives=[DofDrive("P.end", "uy", Linear(0, 1))])
    assert hold.driven.tolist() == [structure.node_dofs((1, 2))[1]]


def test_the_scene_model_resolves_names_as_indices_would():
    """The fig4 scene's supports, sliders and load, resolved by the structure, are the
    user's integer references (C is beam 0, P beam 1 in the scene)."""
    model = Model(load_scene(SCENES / "fig4_sliding_beams.toml"))
    structure = model.structure
    assert np.array_equal(
        structure.support_dofs(model.supports),
        structure.support_dofs([Support(0, "start"), Support(1, "start", "ux+rx")]),
    )
    for slider, body, beam in zip(model.sliders, [(1, "start"), (0, "end")], [0, 1], strict=True):
        assert np.array_equal(slider.body_dofs(structure), structure.node_dofs(body))
        assert slider.line.indices == [beam]
    np.testing.assert_array_equal(
        model.load_vector(structure, None), structure.nodal_load((1, "end"), (0, 1.0, 0))
    )


def test_bad_names_raise_one_clear_error():
    structure = named_structure()
    with pytest.raises(ValueError, match=r"no beam named 'Pp'.*'C', 'P'.*did you mean 'P'"):
        structure.node_dofs("Pp.end")
    with pytest.raises(ValueError, match=r"no rigid body named 'hbu'.*did you mean 'hub'"):
        structure.node_dofs("hbu")
    with pytest.raises(ValueError, match=r"'C' is a beam, not a node: .*'C.start' or 'C.end'"):
        structure.node_dofs("C")
    with pytest.raises(ValueError, match=r"'hub' is a rigid body, not a beam"):
        BeamChain(structure, "hub")
    with pytest.raises(ValueError, match=r"node reference 'C.middle' must be 'BEAM.start'"):
        structure.node_position("C.middle")
    with pytest.raises(ValueError, match=r"P: node 7 is not 'start', 'end' or an index in 0..4"):
        structure.node_dofs(("P", 7))
    with pytest.raises(ValueError, match=r"A: body: node reference 'C.mid'"):
        Slider("spherical", BeamChain(structure, "C"), "C.mid", name="A")
    with pytest.raises(ValueError, match=r"drive: node reference 3"):
        DofDrive(3, "uy", Linear(0, 1))
    with pytest.raises(ValueError, match=r"node 'C.start'.*named already.*kind='pin'"):
        Support("C.start", "pin")
    with pytest.raises(ValueError, match=r"beam 'C' does not end where beam 'C' starts"):
        BeamChain(structure, ["C", "C"])
    twins = [Beam(straight((0, 0, 0), (1, 0, 0), 2), SECTION)] * 2
    with pytest.raises(ValueError, match=r"beam name 'beam' is shared by beams 0, 1"):
        Structure(twins).node_dofs("beam.start")
    with pytest.raises(ValueError, match=r"rigid body name 'x.end' has the form of a beam's node"):
        Structure(twins, bodies=[RigidBody("x.end", (0, 0, 0))])


# -- sections as in scenes ----------------------------------------------------------------------
STIFF = dict(EA=1.0, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)


def test_section_inertia_as_three_numbers_is_the_scenes():
    """pushed_body.toml: ``inertia = [1e-4, 1e-4, 1e-4]``, ``mass_per_length = 1``;
    carriage_on_chain.toml's body: ``inertia = [1e-3, 1e-3, 2e-3]``."""
    scene = Model(load_scene(SCENES / "pushed_body.toml"))
    section = scene.beams[0].section
    mine = Section.diagonal(**STIFF, mass_per_length=1.0, inertia=[1e-4, 1e-4, 1e-4], name="tube")
    assert np.array_equal(mine.inertia, section.inertia)
    assert np.array_equal(mine.inertia, np.diag([1e-4] * 3))
    assert mine.mass_per_length == section.mass_per_length == 1.0
    carriage = Model(load_scene(SCENES / "carriage_on_chain.toml")).bodies[0]
    body = RigidBody("carriage", carriage.position, carriage.mass, [1e-3, 1e-3, 2e-3])
    assert np.array_equal(body.inertia, carriage.inertia)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("EA", "1e9", r"tube: EA must be finite and > 0, got '1e9'"),
        ("GJ", True, r"tube: GJ must be finite and > 0, got True"),
        ("EJz", -2.0, r"tube: EJz must be finite and > 0, got -2.0"),
        ("mass_per_length", "heavy", r"tube: mass_per_length must be finite and >= 0, got 'heavy'"),
        ("mass_per_length", np.nan, r"tube: mass_per_length must be finite and >= 0, got nan"),
        ("inertia", "abc", r"tube: inertia must be a finite 3x3 matrix or 3 numbers, got 'abc'"),
        ("inertia", [1.0, np.nan, 1.0], r"tube: inertia must be a finite 3x3 matrix"),
        ("inertia", [1.0, -1.0, 1.0], r"tube: inertia must be positive semi-definite"),
        ("inertia", [1.0, 2.0], r"tube: inertia must be a finite 3x3 matrix"),
    ],
)
def test_bad_section_input_names_the_field(field, value, message):
    with pytest.raises(ValueError, match=message):
        Section.diagonal(**dict(STIFF, **{field: value}), name="tube")


# -- every study kind through run ---------------------------------------------------------------
@pytest.fixture(scope="module")
def pushed(tmp_path_factory):
    """pushed_body.toml to t = 1 s (20 steps of 0.05 s), keeping one state in 3 for VTU."""
    text = (SCENES / "pushed_body.toml").read_text()
    text = text.replace("t_end = 10.0", "t_end = 1.0").replace(
        "step = 0.05", "step = 0.05\nevery = 3"
    )
    text = text.replace(
        'csv = ["nodes", "internal_forces", "reactions"]', 'csv = ["nodes"]\nvtu = true'
    )
    path = tmp_path_factory.mktemp("scene") / "pushed.toml"
    path.write_text(text)
    return path


def test_run_integrates_a_dynamic_study_in_memory_and_writes_it_as_the_command(
    pushed, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)
    outcome = run(Model(load_scene(pushed)), progress=False)
    assert isinstance(outcome, DynamicRun) and list(tmp_path.iterdir()) == []
    assert outcome.error is None and outcome.state.t == pytest.approx(1.0)
    history = outcome.recorder.table()
    assert len(history["t"]) == 20 + 1
    np.testing.assert_allclose(history["push.xi"], 0.6 + 0.035 * history["t"], atol=TOL)
    write_dynamic(outcome, tmp_path / "python")
    assert main(["run", str(pushed), "--out", str(tmp_path / "command")]) == 0
    python = sorted(p.relative_to(tmp_path / "python") for p in (tmp_path / "python").rglob("*"))
    command = sorted(p.relative_to(tmp_path / "command") for p in (tmp_path / "command").rglob("*"))
    assert python == command and len(python) > 5
    for name in python:
        if (tmp_path / "python" / name).is_file():
            assert filecmp.cmp(tmp_path / "python" / name, tmp_path / "command" / name, False), name


def test_a_recorder_written_from_memory_equals_one_streamed(tmp_path):
    """The same integration recorded twice, streamed to files and kept in memory then
    written: the same files byte for byte (one definition of the rows and their cells)."""
    structure = named_structure()
    dynamics = Dynamics(
        structure,
        [Support("C.start")],
        load=structure.nodal_load("hub", (0, 0, 1.0)),
        drives=[DofDrive("P.start", "ux", Linear(0, 0.01))],
    )
    tables = ["nodes", "sliders", "internal_forces", "reactions"]
    streamed = Recorder(tmp_path / "streamed", tables)
    dynamics.run(dynamics.static_state(), 0.5, 0.05, recorder=streamed, progress=False)
    memory = Recorder(None, tables)
    dynamics.run(dynamics.static_state(), 0.5, 0.05, recorder=memory, progress=False)
    assert not (tmp_path / "memory").exists()
    (tmp_path / "memory").mkdir()
    memory.write(tmp_path / "memory")
    names = [f"{name}.csv" for name in ["history", *tables]]
    assert sorted(p.name for p in (tmp_path / "memory").iterdir()) == sorted(names)
    match, mismatch, errors = filecmp.cmpfiles(
        tmp_path / "streamed", tmp_path / "memory", names, shallow=False
    )
    assert match == names and not mismatch and not errors


# -- VTU in one call -----------------------------------------------------------------------------
def same_vtu(a, b) -> None:
    """Two VTU files hold the same points, cells and data, bit for bit."""
    ma, mb = meshio.read(a), meshio.read(b)
    assert np.array_equal(ma.points, mb.points)
    assert [(c.type, c.data.tolist()) for c in ma.cells] == [
        (c.type, c.data.tolist()) for c in mb.cells
    ]
    assert ma.point_data.keys() == mb.point_data.keys()
    assert ma.cell_data.keys() == mb.cell_data.keys()
    for name in ma.point_data:
        assert np.array_equal(ma.point_data[name], mb.point_data[name], equal_nan=True)
    for name in ma.cell_data:
        for x, y in zip(ma.cell_data[name], mb.cell_data[name], strict=True):
            assert np.array_equal(x, y, equal_nan=True)


def test_a_static_solution_writes_in_one_call_as_by_its_parts(tmp_path):
    statics, f = figure4("classical", 0.3)
    solution = statics.solve(f)
    parts = (statics.structure, solution.q, statics.sliders, solution.unknowns)
    held = np.setdiff1d(np.arange(statics.structure.n_dofs), statics.free)
    write_vtu(tmp_path / "one.vtu", statics, solution)
    write_vtu(tmp_path / "parts.vtu", *parts, held=held)
    same_vtu(tmp_path / "one.vtu", tmp_path / "parts.vtu")
    write_vtu(tmp_path / "thin.vtu", statics, solution, radius=0.002)
    assert np.all(meshio.read(tmp_path / "thin.vtu").point_data["radius"] == 0.002)
    mesh = to_meshio(statics, solution)
    assert np.array_equal(mesh.points, to_meshio(*parts, held=held).points)
    with pytest.raises(ValueError, match="pass nothing after the solution"):
        write_vtu(tmp_path / "bad.vtu", statics, solution, 0.002)
    with pytest.raises(ValueError, match="the system must have structure and sliders"):
        write_vtu(tmp_path / "bad.vtu", "statics", solution)
    with pytest.raises(ValueError, match="the solution must have q and unknowns"):
        Frame.of(statics, solution.q)
    assert not (tmp_path / "bad.vtu").exists()


def test_a_dynamic_run_writes_its_series_in_one_call_as_by_frames(pushed, tmp_path):
    model = Model(load_scene(pushed))
    outcome = run(model, progress=False)
    states = outcome.recorder.states
    assert [s.t for s in states] == pytest.approx([0.0, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9])
    held = outcome.held
    by_hand = [Frame(s.t, model.structure, s.q, model.sliders, s.unknowns, held) for s in states]
    last = outcome.state
    by_hand.append(Frame(last.t, model.structure, last.q, model.sliders, last.unknowns, held))
    one = write_series(tmp_path / "one", outcome.frames())
    hand = write_series(tmp_path / "hand", by_hand)
    times = [
        [d.get("timestep") for d in ET.parse(index).getroot().iter("DataSet")]
        for index in (one, hand)
    ]
    assert times[0] == times[1] and len(times[0]) == len(states) + 1
    for k in range(len(by_hand)):
        same_vtu(tmp_path / "one" / f"step_{k:06d}.vtu", tmp_path / "hand" / f"step_{k:06d}.vtu")


# -- the documented examples --------------------------------------------------------------------
def python_blocks(doc: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", (ROOT / doc).read_text(), re.S)


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """An empty working directory where the repository's ``studies/`` is at hand."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "studies").symlink_to(ROOT / "studies")
    return tmp_path


def test_the_readme_examples_run_and_solve_figure_4_as_the_library(workdir):
    namespace: dict = {}
    blocks = python_blocks("README.md")
    assert len(blocks) == 3
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)
    statics, solution = namespace["statics"], namespace["solution"]
    assert tip_stiffness(statics, solution.q) == pytest.approx(
        SlidingBeams("fv3", 5, "spherical").stiffness(0.18 / L), rel=4 * EPS
    )
    assert (workdir / "sliding_beams.vtu").is_file()
    assert (workdir / "results" / "sliding_beams" / "samples.csv").is_file()
    assert len(namespace["results"].samples) == 20 and not namespace["results"].failures


def test_the_scenes_python_example_runs_a_dynamic_study(workdir):
    (block,) = python_blocks("docs/scenes.md")
    namespace: dict = {}
    exec(compile(block, "docs/scenes.md", "exec"), namespace)
    outcome = namespace["outcome"]
    assert isinstance(outcome, DynamicRun) and outcome.error is None
    assert outcome.state.t == pytest.approx(10.0)
    history = outcome.recorder.table()
    np.testing.assert_allclose(history["push.xi"], 0.6 + 0.035 * history["t"], atol=TOL)
    assert (workdir / "results" / "pushed_body" / "history.csv").is_file()


# -- the packages' names -------------------------------------------------------------------------
def test_the_packages_expose_their_public_names_without_matplotlib_or_pyvista():
    code = (
        "import sys, fvbeam, sliders\n"
        "missing = [n for p in (fvbeam, sliders) for n in p.__all__ if not hasattr(p, n)]\n"
        f"heavy = sorted(m for m in {HEAVY!r} if m in sys.modules)\n"
        "print(missing, heavy)"
    )
    child = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert child.returncode == 0, child.stderr
    assert child.stdout.strip() == "[] []"
