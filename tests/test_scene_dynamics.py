"""Dynamic studies and drives in scenes: validation messages, runs, restarts and the command.

Sources of the asserted numbers: the drive's own formula (a driven abscissa equals it to the
Newton tolerance), the massless body's equilibrium (its reaction equals the load it carries,
exactly: the body has no inertia), and determinism (a restart repeats the same arithmetic,
up to the roundoff of its step times).
"""

import csv

import meshio
import numpy as np
import pytest
from test_output import split_bound
from test_scenes import SCENES, data, problems

from sliders.app.cli import main
from sliders.app.history import Recorder
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.run_dynamic import DynamicRun, write_dynamic
from sliders.app.scene import parse_scene
from sliders.app.tables import COLUMNS, write_results
from sliders.app.vtu import PARTS

TOL = 1e-8


def read_csv(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return {name: np.array([float(r[i]) for r in rows[1:]]) for i, name in enumerate(rows[0])}


def run_into(model: Model, out) -> DynamicRun:
    """The Python route of a dynamic study: ``run`` in memory, then written into ``out``."""
    outcome = run(model, progress=False)
    write_dynamic(outcome, out)
    return outcome


def read_table(path) -> list[dict[str, str]]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def pushed(t_end: float = 1.0, **study) -> dict:
    scene = data("pushed_body")
    scene["study"].update(t_end=t_end, **study)
    return scene


def test_drive_problems_are_named():
    scene = data("fig1_cantilever")
    scene["drive"] = [
        {
            "kind": "dof",
            "node": "cantilever.end",
            "dof": "uy",
            "motion": {"kind": "linear", "start": 0.0, "velocity": 1.0},
        }
    ]
    (problem,) = problems(scene)
    assert problem.path == "drive" and "study.kind = 'dynamic'" in problem.message
    scene = pushed()
    scene["drive"][0]["slider"] = "psuh"
    scene["drive"].append(
        {
            "kind": "dof",
            "node": "cantilever.start",
            "dof": "uy",
            "motion": {"kind": "ramp", "start": 0, "end": 1, "t0": 2, "t1": 1},
        }
    )
    scene["drive"].append(
        {
            "kind": "dof",
            "node": "cart",
            "dof": "uz",
            "motion": {"kind": "tabulated", "times": [0, 1, 1], "values": [0, 1]},
        }
    )
    found = {p.path: p.message for p in problems(scene)}
    assert "did you mean 'push'" in found["drive[0].slider"]
    assert "which drive[1] drives" in found["support[0].kind"]
    assert "must be after t0" in found["drive[1].motion.t1"]
    assert "2 values for 3 times" in found["drive[2].motion.values"]
    assert "increase strictly" in found["drive[2].motion.times"]


def test_dynamic_study_problems_are_named():
    scene = pushed(t_end=0.01)
    found = {p.path: p.message for p in problems(scene)}
    assert "longer than t_end" in found["study.step"]
    scene = pushed(rho_inf=1.5)
    (problem,) = problems(scene)
    assert problem.path == "study.rho_inf"
    scene = pushed(load_steps=2)
    (problem,) = problems(scene)
    assert problem.path == "study.load_steps"
    scene = pushed()
    del scene["section"][0]["mass_per_length"]
    (problem,) = problems(scene)
    assert problem.path == "section[0].mass_per_length" and "dynamic" in problem.message


def test_pushed_body_follows_its_drive_and_restarts(tmp_path):
    model = Model(parse_scene(pushed(t_end=1.0), SCENES, "pushed"), "pushed")
    first = run_into(model, tmp_path / "first")
    assert first.error is None and first.state.t == pytest.approx(1.0)
    history = read_csv(tmp_path / "first" / "history.csv")
    np.testing.assert_allclose(history["push.xi"], 0.6 + 0.035 * history["t"], atol=TOL)
    np.testing.assert_allclose(history["push.lambda_y"], 1.0, atol=1e-12)
    assert np.all(history["push.residual"] <= TOL)
    # tidy per-step tables: the cantilever's 3 nodes and the cart at every step of history
    nodes = read_table(tmp_path / "first" / "nodes.csv")
    assert [(r["step"], r["t"]) for r in nodes[::4]] == list(
        zip(map(str, range(len(history["t"]))), map(repr, history["t"].tolist()), strict=True)
    )
    assert [r["part"] for r in nodes[:4]] == ["cantilever"] * 3 + ["cart"]
    assert (tmp_path / "first" / "internal_forces.csv").is_file()
    reactions = read_table(tmp_path / "first" / "reactions.csv")
    assert len(reactions) == 2 * len(history["t"])
    assert [r["node"] for r in reactions[:2]] == ["cantilever.start", "cart"]
    assert all(r["mz"] != "" for r in reactions) and reactions[1]["fx"] == ""
    scene = pushed(t_end=2.0, restart=str(tmp_path / "first" / "state.npz"))
    resumed = run_into(Model(parse_scene(scene, SCENES, "r"), "r"), tmp_path / "second")
    whole = run_into(Model(parse_scene(pushed(t_end=2.0), SCENES, "w"), "w"), tmp_path / "whole")
    # the restart's steps end at 1 + k h, the whole run's at (20 + k) h: equal to roundoff
    np.testing.assert_allclose(
        resumed.state.q, whole.state.q, rtol=0, atol=1e-12 * np.abs(whole.state.q).max()
    )
    assert read_csv(tmp_path / "second" / "history.csv")["t"][0] == pytest.approx(1.0)


def test_the_command_runs_a_dynamic_scene_and_keeps_the_steps_of_a_failure(tmp_path, capsys):
    path = tmp_path / "push.toml"
    text = (SCENES / "pushed_body.toml").read_text()
    path.write_text(text.replace("t_end = 10.0", "t_end = 0.5"))
    assert main(["run", str(path), "--out", str(tmp_path / "ok")]) == 0
    assert "10 steps to t = 0.5 s" in capsys.readouterr().out
    # the cart's ux driven instead of its abscissa, from 0 to 1 m in 2 s: it leaves the beam
    # (0.4 m from its start) at t = 0.87 s, which only the integration finds (check cannot
    # follow a slider that a dof drive moves; an abscissa drive off its line fails check)
    path.write_text(
        text.replace(
            'kind = "abscissa"\nslider = "push"\n'
            'motion = { kind = "linear", start = 0.6, velocity = 0.035 }',
            'kind = "dof"\nnode = "cart"\ndof = "ux"\n'
            'motion = { kind = "ramp", start = 0.0, end = 1.0, t0 = 0.0, t1 = 2.0 }',
        )
    )
    assert main(["run", str(path), "--out", str(tmp_path / "fails")]) == 1
    message = capsys.readouterr().err
    assert "failed: t = " in message and "push" in message
    history = read_csv(tmp_path / "fails" / "history.csv")
    assert history["push.xi"][-1] <= 1.0 and len(history["t"]) > 10
    assert (tmp_path / "fails" / "state.npz").is_file()
    assert main(["check", str(path)]) == 0
    assert "dynamic to t = 10 s" in capsys.readouterr().out


TABLES = ["nodes", "sliders", "internal_forces", "reactions"]


@pytest.fixture(scope="module")
def both_runs(tmp_path_factory):
    """A static sweep (end_stops) and a dynamic run (pushed_body, 0.5 s), every table and
    the VTU states asked for."""
    out = tmp_path_factory.mktemp("runs")
    static = data("end_stops")
    static["output"] = {"csv": ["samples", *TABLES], "vtu": True}
    results = run(Model(parse_scene(static, SCENES, "static"), "static"), progress=False)
    write_results(results, out / "static")
    dynamic = pushed(t_end=0.5)
    dynamic["output"] = {"csv": ["samples", *TABLES], "vtu": True}
    model = Model(parse_scene(dynamic, SCENES, "dynamic"), "dynamic")
    outcome = run_into(model, out / "dynamic")
    assert outcome.error is None
    return out, model, outcome


def test_static_and_dynamic_runs_write_the_same_columns_and_fields(both_runs):
    """One definition of the tables: a dynamic run's per-step table has the static one's
    columns with ``step, t`` in place of ``sample, value``; and both runs' VTUs carry the
    same point and cell fields."""
    out, _, _ = both_runs
    for name in TABLES:
        static, dynamic = (
            (out / kind / f"{name}.csv").read_text().splitlines()[0].split(",")
            for kind in ("static", "dynamic")
        )
        assert static == list(COLUMNS[name]) and static[:2] == ["sample", "value"]
        assert dynamic == ["step", "t"] + static[2:]
    assert not (out / "dynamic" / "samples.csv").exists()
    meshes = [
        meshio.read(out / kind / "states" / "step_000000.vtu") for kind in ("static", "dynamic")
    ]
    assert [set(m.point_data) for m in meshes] == [
        {
            "displacement",
            "rigid_displacement",
            "elastic_displacement",
            "rotation",
            "rotation_matrix",
            "radius",
        }
    ] * 2
    assert set(meshes[0].cell_data) == set(meshes[1].cell_data)


def test_the_pushed_cart_is_drawn_on_its_line(both_runs):
    """In every VTU state of the pushed body, the cart's rigid displacement is its travel
    along the cantilever, ``(xi - 0.6, 0, 0)`` (its rotations held, its sliding point on
    the reference line at ``xi``), to a few roundings of numbers of order 1 (the split's
    bound, tests/test_output.py); its elastic displacement is the cantilever's at the
    contact, to the constraint's residual (history ``push.residual``) plus that bound (the
    largest over the states).  So a magnified picture draws the cart on the magnified
    line."""
    out, model, outcome = both_runs
    history = read_csv(out / "dynamic" / "history.csv")
    bound = max(split_bound(model.structure, s.q) for s in outcome.recorder.states)
    for k, (xi, residual) in enumerate(
        zip(history["push.xi"], history["push.residual"], strict=True)
    ):
        mesh = meshio.read(out / "dynamic" / "states" / f"step_{k:06d}.vtu")
        part = np.concatenate(mesh.cell_data["part"])
        conn = np.concatenate([block.data[:, 0] for block in mesh.cells])
        (cart,), (contact,) = (conn[part == PARTS[p]] for p in ("body", "slider"))
        rigid, elastic = (
            mesh.point_data["rigid_displacement"],
            mesh.point_data["elastic_displacement"],
        )
        assert np.abs(rigid[cart] - [xi - 0.6, 0, 0]).max() <= bound
        assert np.all(rigid[contact] == 0)
        assert np.abs(elastic[cart] - elastic[contact]).max() <= residual + 2 * bound


def test_a_dynamic_run_reports_what_the_supports_exert(tmp_path):
    """A cart carried ``0.1`` above its sliding point (offset ``(0, 0, -0.1)``): the
    frictionless contact force ``lambda = (0, 1, 0)`` (the unit load it carries; the cart
    is massless) acts ``0.1`` below the cart, so the supports holding the cart's rotations
    exert ``offset x lambda = (0.1, 0, 0)`` on it at every step, as statics reports it (the
    joints' share counted); ``lambda_y`` is 1 to 1e-12 (the test above), so is ``mx / 0.1``."""
    scene = pushed(t_end=0.25)
    scene["body"][0]["position"] = [0.6, 0.0, 0.1]
    scene["slider"][0]["offset"] = [0.0, 0.0, -0.1]
    run_into(Model(parse_scene(scene, SCENES, "offset"), "offset"), tmp_path)
    cart = [r for r in read_table(tmp_path / "reactions.csv") if r["node"] == "cart"]
    assert len(cart) == len(read_csv(tmp_path / "history.csv")["t"])
    for row in cart:
        np.testing.assert_allclose(
            [float(row[c]) for c in ("mx", "my", "mz")], [0.1, 0.0, 0.0], atol=1e-12 * 0.1
        )


def test_recorder_tables_are_checked(tmp_path):
    with pytest.raises(ValueError, match=r"tables\[1\] must be one of nodes, sliders, "):
        Recorder(tmp_path, tables=["nodes", "displacements"])
