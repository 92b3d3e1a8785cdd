"""Force elements, initial velocities and the dynamic start from a given state in scenes
(studies/scenes/landing_gear.toml): validation messages, ``fvslider check`` and ``run``.

Sources of the asserted numbers: the Python model of the same gear (sliders.gear.model,
fv3-3), which the scene differs from by its static start only: the scene's tyre takes part in
it, and the axle, hanging on the strut's extension stop below R0 by |S0| (the ODE study's
stroke) and the piston's stretch (9 % of it), presses it by less than 2 k_t |S0| = 3 N; the
touchdown speeds, given exactly.
"""

import csv

import numpy as np
import pytest
from test_scenes import SCENES, data, problems

from sliders.app.cli import main
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import parse_scene
from sliders.gear.model import GearModel
from studies import landing_gear_ode as ode

SCENE = SCENES / "landing_gear.toml"


def gear(**study) -> dict:
    scene = data("landing_gear")
    scene["study"].update(study)
    return scene


def test_check_and_a_short_run_through_the_command(tmp_path, capsys):
    assert main(["check", str(SCENE)]) == 0
    assert "valid (2 beams, 3 bodies, 2 sliders; dynamic" in capsys.readouterr().out
    scene = tmp_path / "short.toml"
    scene.write_text(SCENE.read_text().replace("t_end = 0.3", "t_end = 0.02"))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 0
    with open(tmp_path / "out" / "history.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 101 and float(rows[-1]["t"]) == pytest.approx(0.02)
    first = rows[0]
    assert (float(first["airframe_vx"]), float(first["airframe_vz"])) == (40.0, -2.8)
    assert float(first["wheel_spin"]) == 0.0
    g = GearModel("fv3-3").gear
    S0 = ode.initial_stroke(g)
    # the tyre's preload (below 2 k_t |S0|) compresses the extension stop a little further
    assert abs(float(first["stroke"]) - S0) <= 2 * g.tyre_stiffness * abs(S0) / 1e8


@pytest.mark.parametrize("friction", [False, True])
def test_the_scene_is_the_python_models_gear(friction):
    """The scene's run against ``GearModel("fv3-3")`` at the scene's step: the tyre's force
    within twice the start's preload k_t |S0|, the stroke within 2 |S0|, the spin and the
    airframe's speed within ten times that preload relative to the peak vertical load; with
    the bearing friction on both sliders (``friction = {mu, v_eps}`` in the scene) too."""
    g = GearModel("fv3-3").gear
    scene = gear(t_end=0.06)
    if friction:
        for slider in scene["slider"]:
            slider["friction"] = {"mu": g.bearing_mu, "v_eps": g.bearing_v_eps}
    outcome = run(Model(parse_scene(scene, SCENES, "landing_gear.toml")), False)
    table = outcome.recorder.table()
    ours = GearModel("fv3-3", friction=friction).simulate(0.06, 2e-4).outputs
    S0 = abs(ode.initial_stroke(g))
    preload = g.tyre_stiffness * S0
    assert np.abs(table["F_z"] - ours["ground_vertical"])[1:].max() <= 2 * preload
    assert np.abs(table["stroke"] - ours["strut_stroke"]).max() <= 2 * S0
    relative = 10 * preload / ours["ground_vertical"].max()
    for column, name in (("wheel_spin", "wheel_speed"), ("airframe_vx", "airframe_forward_speed")):
        scale = np.abs(ours[name]).max()
        assert np.abs(table[column] - ours[name]).max() <= relative * scale, column


def test_force_problems_are_named():
    scene = data("landing_gear")
    scene["force"][0]["nodes"] = ["C.start", "C.start"]
    scene["force"][1]["wheel"] = "weel"
    paths = {p.path: p.message for p in problems(scene)}
    assert "other node too" in paths["force[0].nodes[1]"]
    assert "no body named 'weel'" in paths["force[1].wheel"]
    scene = data("landing_gear")
    scene["force"][1]["normal"] = [1.0, 0.0, 0.0]  # along forward
    scene["force"][0]["law"]["stroke_max"] = -0.1
    paths = {p.path: p.message for p in problems(scene)}
    assert "forward must be normal" in paths["force[1]"]
    assert "lower (0.0) must be below upper (-0.1)" in paths["force[0].law"]
    scene = data("landing_gear")
    scene["force"].append({"kind": "spring", "name": "s"})
    scene["force"][0]["law"]["pressur"] = 4.1e5
    paths = {p.path: p.message for p in problems(scene)}
    assert "force[2]" in str(paths) and "force[0].law.pressur" in paths, paths


def test_friction_problems_are_named():
    scene = data("landing_gear")
    scene["slider"][0]["friction"] = {"mu": -0.02}
    scene["slider"][1]["friction"] = {"mu": 0.02, "v_esp": 1e-3}
    paths = {p.path: p.message for p in problems(scene)}
    assert ">= 0" in paths["slider[0].friction.mu"]
    assert "unknown key" in paths["slider[1].friction.v_esp"]


def test_start_and_velocity_problems_are_named():
    scene = data("landing_gear")
    scene["study"]["start"]["hold"] = ["airframe", "airframe", "wing"]
    scene["study"]["restart"] = "state.npz"
    scene["body"][0]["velocity"] = [40.0, 0.0, -2.8]
    paths = {}
    for p in problems(scene):
        paths.setdefault(p.path, []).append(p.message)
    assert any("no body named 'wing'" in m for m in paths["study.start.hold[2]"])
    assert any("more than once" in m for m in paths["study.start.hold"])
    assert any("either study.restart or initial velocities" in m for m in paths["study.start"])
    assert any("either study.restart" in m for m in paths["body[0].velocity"])
    static = data("fig4_sliding_beams")
    static["body"] = [{"name": "b", "position": [0, 0, 0], "velocity": [1.0, 0.0, 0.0]}]
    (problem,) = [p for p in problems(static) if p.path.startswith("body")]
    assert problem.path == "body[0].velocity" and "study.kind = 'dynamic'" in problem.message


def test_probe_problems_are_named():
    scene = data("landing_gear")
    scene["output"]["probe"][1]["force"] = "tyer"
    scene["output"]["probe"][5]["beam"] = "C"
    paths = {p.path: p.message for p in problems(scene)}
    assert "no force element named 'tyer'" in paths["output.probe[1].force"]
    assert "exactly one of node, beam, force" in paths["output.probe[5]"]
    scene = data("landing_gear")  # the values, against the built model
    scene["output"]["probe"][0]["value"] = "Fy"
    scene["output"]["probe"][4]["value"] = "vq"
    paths = {p.path: p.message for p in problems(scene)}
    assert "one of 'Fz', 'Fx'" in paths["output.probe[0].value"]
    assert "vx" in paths["output.probe[4].value"]
