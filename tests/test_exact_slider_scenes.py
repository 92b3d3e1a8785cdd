"""Sliders in scenes with ``kinematics = "exact"`` (``docs/scenes.md``, "Kinematics";
``docs/exact_sliders.md``): the tables and what the exact path refuses, at its key.

Tolerance of the bearing: the configurational force's discretisation error, at most the
curvature's relative change over an element, ``h / a`` (``tests/test_exact_sliders.py``);
the ``sliders`` table's ``lambda_x`` and the far end's reaction are the same balance, equal to
the residual's round-off floor (``16 eps`` times the axial stiffness' terms, ``EA = 1e5``).
"""

import csv
from pathlib import Path

import numpy as np
import pytest

from sliders.app.cli import main

EPS = np.finfo(float).eps
SCENES = Path(__file__).resolve().parents[1] / "studies" / "scenes"
BEARING = """title = "bearing"
kinematics = "exact"
formulation = "fv3"
[[section]]
name = "rod"
EA = 1e5
GAy = 1e3
GAz = 1e3
GJ = 1.0
EJy = 1.0
EJz = 1.0
[[beam]]
name = "rod"
section = "rod"
straight = { start = [0.0, 0.0, 0.0], end = [1.0, 0.0, 0.0], elements = 8 }
[[body]]
name = "bearing"
position = [0.4, 0.0, 0.0]
[[support]]
node = "bearing"
[[support]]
node = "rod.start"
kind = "ux+rx"
[[slider]]
name = "ring"
kind = "classical"
line = "rod"
body = "bearing"
[[load]]
kind = "nodal"
node = "rod.end"
force = [0.0, 1.0, 0.0]
[study]
kind = "static"
[output]
csv = ["nodes", "sliders", "reactions"]
"""


def rows(path) -> list[dict]:
    with open(path, newline="") as file:
        return list(csv.DictReader(file))


def test_a_rod_pushed_through_a_bearing_as_a_scene(tmp_path, capsys):
    """The rod of ``tests/test_exact_sliders.py`` pushed through a bearing, as a scene: the
    sliders table has the linear path's columns (``mu_1`` blank for a classical slider);
    the far end's support holds the rod with the configurational force,
    ``M^2 / 2 EJ + V^2 / 2 GA`` (``M`` from the tip's current place), which is the
    slider's ``lambda_x`` (the rod's axial balance)."""
    path = tmp_path / "bearing.toml"
    path.write_text(BEARING)
    assert main(["run", "--out", str(tmp_path / "out"), str(path)]) == 0
    assert "kinematics: exact (asked)" in capsys.readouterr().out
    slider = rows(tmp_path / "out" / "sliders.csv")
    assert list(slider[0]) == [
        "sample", "value", "slider", "xi", "x", "y", "z",
        "lambda_x", "lambda_y", "lambda_z", "mu_2", "mu_3", "mu_1",
    ]  # fmt: skip
    assert slider[0]["mu_1"] == ""  # a classical slider's: blank
    tip = next(r for r in rows(tmp_path / "out" / "nodes.csv") if float(r["xi"]) == 1.0)
    M = 1.0 * (float(tip["x"]) + float(tip["ux"]) - 0.4)
    closed = M**2 / 2 + 1.0 / (2 * 1e3)
    reaction = next(r for r in rows(tmp_path / "out" / "reactions.csv") if r["node"] == "rod.start")
    pull = -float(reaction["fx"])
    assert abs(pull - closed) <= (1 / 8) / 0.6 * closed
    assert abs(float(slider[0]["lambda_x"]) - pull) <= 16 * EPS * 1e5


@pytest.mark.parametrize(
    ("change", "key", "what"),
    [
        (
            'body = "bearing"\nfriction = { mu = 0.1 }\n',
            "slider[0].friction",
            "a slider's friction",
        ),
        ('body = "bearing"\norientation = "slope"\n', "slider[0].orientation", "'slope'"),
    ],
)
def test_exact_refuses_what_its_sliders_do_not_carry(tmp_path, capsys, change, key, what):
    """Friction and the ``slope`` orientation: one error naming the key."""
    path = tmp_path / "scene.toml"
    path.write_text(BEARING.replace('body = "bearing"\n', change))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{key}: " in err and what in err and "exact kinematics does not carry it" in err


def test_exact_refuses_a_slider_on_a_rigid_line(tmp_path, capsys):
    """A slider on a rigid line: one error naming its line."""
    line = '[[line]]\nkind = "straight"\nname = "rail"\nstart = [0.0, 0.0, 0.0]\n'
    line += "end = [1.0, 0.0, 0.0]\n"
    path = tmp_path / "scene.toml"
    path.write_text(BEARING.replace('line = "rod"', 'line = "rail"') + line)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "slider[0].line: a slider on a rigid line: exact kinematics does not carry it" in err


def test_auto_takes_a_bent_rod_through_its_bearing_exact(tmp_path, capsys):
    """``auto``: the bearing's rod under its 1 N tip load turns by about 0.2 rad, whose
    neglected terms exceed the study's tolerance: auto solves again on the exact path and
    says why; its answer is the exact path's."""
    scenes = {"auto": BEARING.replace('kinematics = "exact"\n', ""), "exact": BEARING}
    said = {}
    for name, text in scenes.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(text)
        assert main(["run", "--out", str(tmp_path / name), str(path)]) == 0
        said[name] = capsys.readouterr().out
    assert "kinematics: exact (auto: the linear answer's largest rotation" in said["auto"]
    assert rows(tmp_path / "auto" / "sliders.csv") == rows(tmp_path / "exact" / "sliders.csv")


def test_an_end_stop_holds_a_tip_pushed_off_its_rail(tmp_path, capsys):
    """studies/scenes/end_stops.toml's problem on an exact rail beam (clamped at both ends)
    with ``kinematics = "exact"``: the tip pushed outwards rests on the stop, ``xi`` at the
    rail's end and the slider's ``lambda_x`` the force ``F`` (to the round-off floor of the
    arm's force balance, ``16 eps`` times ``EA = 1e9`` and its terms)."""
    text = (SCENES / "end_stops.toml").read_text()
    text = text.replace('title = "end stops"', 'title = "end stops"\nkinematics = "exact"')
    text = text.replace(
        '[[line]]\nkind = "straight"\nname = "rail"\nstart = [-1.0, 0.0, 0.0]\n'
        "end = [0.0, 0.0, 0.0]\n",
        '[[beam]]\nname = "rail"\nsection = "rod"\n'
        "straight = { start = [-1.0, 0.0, 0.0], end = [0.0, 0.0, 0.0], elements = 4 }\n"
        '[[support]]\nnode = "rail.start"\n[[support]]\nnode = "rail.end"\n',
    )
    text = text.split("[study]")[0] + '[study]\nkind = "static"\n[output]\ncsv = ["sliders"]\n'
    path = tmp_path / "stops.toml"
    path.write_text(text)
    assert main(["run", "--out", str(tmp_path / "out"), str(path)]) == 0, capsys.readouterr()
    (slider,) = rows(tmp_path / "out" / "sliders.csv")
    assert float(slider["xi"]) == 1.0
    assert abs(float(slider["lambda_x"]) - 50.0) <= 16 * EPS * 1e9


def test_modes_about_an_exact_sliding_state_warn_they_take_the_linear_stiffness(tmp_path):
    """A modes study about the bearing's rod on the exact path: the sliding model's tangent
    is not yet handed to the modes' reduction, so the modes take the linear, unloaded
    stiffness about the state, with the preload warning (:data:`sliders.solve.modes.
    PRELOAD_WARNING`), and the study still gives its modes."""
    from sliders.solve.modes import PRELOAD_WARNING

    text = BEARING.replace(
        "EJz = 1.0\n", "EJz = 1.0\nmass_per_length = 1.0\ninertia = [1e-3, 1e-3, 1e-3]\n", 1
    )
    text = text.replace('[study]\nkind = "static"\n', '[study]\nkind = "modes"\ncount = 3\n')
    text = text.replace('csv = ["nodes", "sliders", "reactions"]', 'csv = ["modes"]')
    path, out = tmp_path / "modes.toml", tmp_path / "out"
    path.write_text(text)
    with pytest.warns(UserWarning, match=PRELOAD_WARNING.split(":")[0]):
        assert main(["run", str(path), "--out", str(out)]) == 0
    frequencies = [float(row["frequency_hz"]) for row in rows(out / "modes.csv")]
    assert len(frequencies) == 3
    assert all(np.isfinite(f) and f > 0 for f in frequencies)
