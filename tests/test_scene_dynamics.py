"""Dynamic studies and drives in scenes: validation messages, runs, restarts and the command.

Sources of the asserted numbers: the drive's own formula (a driven abscissa equals it to the
Newton tolerance), the massless body's equilibrium (its reaction equals the load it carries,
exactly: the body has no inertia), and determinism (a restart repeats the same arithmetic,
up to the roundoff of its step times).
"""

import csv

import numpy as np
import pytest
from test_scenes import SCENES, data, problems

from sliders.app.cli import main
from sliders.app.model import Model
from sliders.app.run_dynamic import run_dynamic
from sliders.app.scene import parse_scene

TOL = 1e-8


def read_csv(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return {name: np.array([float(r[i]) for r in rows[1:]]) for i, name in enumerate(rows[0])}


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
    assert "held by a support" in found["drive[1].dof"]
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
    first = run_dynamic(model, tmp_path / "first", progress=False)
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
    resumed = run_dynamic(
        Model(parse_scene(scene, SCENES, "r"), "r"), tmp_path / "second", progress=False
    )
    whole = run_dynamic(
        Model(parse_scene(pushed(t_end=2.0), SCENES, "w"), "w"), tmp_path / "whole", progress=False
    )
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
    path.write_text(text.replace("velocity = 0.035", "velocity = 0.5"))
    assert main(["run", str(path), "--out", str(tmp_path / "fails")]) == 1
    message = capsys.readouterr().err
    assert "failed: t = " in message and "push" in message
    history = read_csv(tmp_path / "fails" / "history.csv")
    assert history["push.xi"][-1] <= 1.0 and len(history["t"]) > 10
    assert (tmp_path / "fails" / "state.npz").is_file()
    assert main(["check", str(path)]) == 0
    assert "dynamic to t = 10 s" in capsys.readouterr().out
