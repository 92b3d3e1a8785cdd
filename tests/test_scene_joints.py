"""Joints in scenes (``[[joint]]``, exact kinematics only) through ``fvslider run`` and
``fvslider check``: a pendulum on a hinge and a hinged toggle of tied beams and a body
against their closed forms (``tests/test_exact_joints.py`` solves the same models from
Python), ``joints.csv``, and the refusals naming the key.

Tolerances, as there: a converged state is off by the next Newton correction, the residual's
round-off floor (``FLOOR_FACTOR`` eps times its terms) over the smallest stiffness; the CSV
cells hold every digit (``repr``).
"""

import csv

import numpy as np
import pytest

from fvbeam.body import RigidBody
from fvbeam.exact_statics import FLOOR_FACTOR
from sliders.app.cli import main
from sliders.joints.exact_model import ExactModel, Joint

EPS = np.finfo(float).eps


def run_scene(tmp_path, text: str, capsys, command: str = "run") -> tuple[int, str, str]:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    args = ["run", "--out", str(tmp_path / "out")] if command == "run" else [command]
    code = main([*args, str(path)])
    out, err = capsys.readouterr()
    return code, out, err


def read(path) -> list[dict]:
    with open(path, newline="") as file:
        return list(csv.DictReader(file))


def current(row: dict) -> np.ndarray:
    """A ``nodes.csv`` row's current position."""
    return np.array([float(row[c]) + float(row["u" + c]) for c in "xyz"])


def pendulum(length: float, weight: float, angle: float, head: str = "") -> str:
    """A bob ``length`` below a hinge at the origin (axis z), its weight and the dead couple
    ``W L sin(angle)`` about the hinge's axis."""
    couple = float(weight * length * np.sin(angle))
    return f"""{head}title = "pendulum"
[[body]]
name = "bob"
position = [0.0, {-length!r}, 0.0]
mass = 1.0
[[joint]]
kind = "revolute"
a = "ground"
b = "bob"
position = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
[[load]]
kind = "nodal"
node = "bob"
force = [0.0, {-weight!r}, 0.0]
moment = [0.0, 0.0, {couple!r}]
[study]
kind = "static"
"""


@pytest.mark.parametrize("angle", [np.pi / 6, 1.4])
def test_a_pendulum_scene_meets_the_moment_balance(tmp_path, capsys, angle):
    """``M = W L sin(theta)``: the bob turned by ``theta`` about the hinge's axis, at
    ``L (sin, -cos)``; the hinge holds the bob up with ``W`` and, about the bob, with the
    couple of that force, ``-W L sin(theta)``.  ``auto`` takes the exact path and says why."""
    L, W = 1.5, 2.0
    code, out, err = run_scene(tmp_path, pendulum(L, W, angle), capsys)
    assert code == 0, out + err
    assert "kinematics: exact (auto: the scene has joints" in out
    tol = FLOOR_FACTOR * EPS * 4 / np.cos(angle)  # the floor over the stiffness W L cos
    (bob,) = read(tmp_path / "out" / "nodes.csv")
    np.testing.assert_allclose(
        current(bob), L * np.array([np.sin(angle), -np.cos(angle), 0.0]), rtol=0, atol=tol * L
    )
    rotation = [float(bob[c]) for c in ("rx", "ry", "rz")]
    np.testing.assert_allclose(rotation, [0.0, 0.0, angle], rtol=0, atol=tol)
    (hinge,) = read(tmp_path / "out" / "joints.csv")
    assert (hinge["joint"], hinge["node"]) == ("0", "bob")
    force = [float(hinge[c]) for c in ("fx", "fy", "fz")]
    couple = [float(hinge[c]) for c in ("mx", "my", "mz")]
    np.testing.assert_allclose(force, [0.0, W, 0.0], rtol=0, atol=tol * W)
    np.testing.assert_allclose(couple, [0.0, 0.0, -W * L * np.sin(angle)], rtol=0, atol=tol * W * L)


TOGGLE = """title = "toggle"
formulation = "fv2"
[[section]]
name = "bar"
EA = 100.0
GAy = 100.0
GAz = 100.0
GJ = 100.0
EJy = 100.0
EJz = 100.0
[[beam]]
name = "lower"
section = "bar"
straight = { start = [-1.0, 0.0, 0.0], end = [-0.5, 0.5, 0.0], elements = 1 }
[[beam]]
name = "upper"
section = "bar"
straight = { start = [-0.5, 0.5, 0.0], end = [0.0, 1.0, 0.0], elements = 1 }
[[beam]]
name = "right"
section = "bar"
straight = { start = [1.0, 0.0, 0.0], end = [0.0, 1.0, 0.0], elements = 2 }
[[body]]
name = "apex"
position = [0.0, 1.0, 0.0]
[[tie]]
nodes = ["lower.end", "upper.start"]
[[tie]]
nodes = ["upper.end", "apex"]
JOINTS
[[load]]
kind = "nodal"
node = "apex"
force = [0.0, LOAD, 0.0]
[study]
kind = "static"
"""


def test_a_toggle_of_tied_beams_and_a_body_meets_its_closed_form(tmp_path, capsys):
    """Two bars hinged to the ground and to each other at an apex (the left one two beams
    tied at its middle, the apex a body tied to its end): the apex load ``P = 2 N h / l``
    with ``N = EA (l / L_0 - 1)``, ``l = sqrt(1 + h^2)`` brings the apex to ``h = 0.6``;
    each ground hinge pushes its bar along the bar with ``N``.  Straight bars in uniform
    strain are exact in fv2: round-off, the floor of terms of size EA over about EA / 8."""
    EA, L0, h = 100.0, np.sqrt(2.0), 0.6
    length = np.hypot(1.0, h)
    force = EA * (length / L0 - 1.0)
    hinges = [("ground", "lower.start"), ("ground", "right.start"), ("apex", "right.end")]
    joints = "".join(
        f'[[joint]]\nkind = "revolute"\na = "{a}"\nb = "{b}"\naxis = [0.0, 0.0, 1.0]\n'
        for a, b in hinges
    )
    text = TOGGLE.replace("JOINTS\n", joints).replace("LOAD", repr(float(2 * force * h / length)))
    code, out, err = run_scene(tmp_path, text, capsys)
    assert code == 0, out + err
    tol = FLOOR_FACTOR * EPS * EA * 8
    nodes = {(r["part"], r["xi"]): r for r in read(tmp_path / "out" / "nodes.csv")}
    np.testing.assert_allclose(current(nodes["apex", ""]), [0.0, h, 0.0], rtol=0, atol=tol)
    rows = read(tmp_path / "out" / "joints.csv")
    assert [(r["joint"], r["node"]) for r in rows] == [
        ("0", "lower.start"),
        ("1", "right.start"),
        ("2", "apex"),
        ("2", "right.end"),
    ]
    for row, root in zip(rows[:2], ([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]), strict=True):
        along = (np.array([0.0, h, 0.0]) - root) / length  # from the root to the apex
        pushed = [float(row[c]) for c in ("fx", "fy", "fz")]
        np.testing.assert_allclose(pushed, -force * along, rtol=0, atol=tol * EA)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            ('title = "pendulum"', 'kinematics = "linear"\ntitle = "pendulum"'),
            "kinematics = 'linear': joints need kinematics = 'exact'",
        ),
        (
            ('kind = "revolute"', 'kind = "hinge"'),
            "joint[0].kind = 'hinge': joint[0]: 'hinge' is neither a kind of joint",
        ),
        (('b = "bob"', 'b = "bib"'), "joint[0].b = 'bib': no body named 'bib'"),
        (
            ('kind = "static"', 'kind = "dynamic"\nt_end = 1.0\nstep = 0.1'),
            "study.kind: a dynamic study: exact kinematics, which joints need, does not carry it",
        ),
        (
            ('b = "bob"', 'b = "ground"'),
            "joint[0] = ['ground', 'ground']: both ends are the ground",
        ),
        (
            ("axis = [0.0, 0.0, 1.0]", "axis = [0.0, 0.0, 0.0]"),
            "joint[0].axis = (0.0, 0.0, 0.0): the axis must be a non-zero",
        ),
        (
            ('kind = "static"', 'kind = "static"\n[output]\nvtu = true'),
            "output.vtu = True: draws the beams, the lines and what rides on them",
        ),
        (
            ('kind = "static"', 'kind = "static"\n[output]\npng = "last"'),
            "output.png = 'last': draws the beams, the lines and what rides on them",
        ),
    ],
)
def test_bad_joints_are_refused_naming_the_key(tmp_path, capsys, change, message):
    code, out, err = run_scene(tmp_path, pendulum(1.0, 1.0, 0.5).replace(*change), capsys, "check")
    assert code == 2
    assert message in err
    assert "Traceback" not in err


def test_a_free_motion_is_named_not_left_to_newton(tmp_path, capsys):
    """A body on a prismatic joint along x with no load along x: the joint's one free
    motion, the body's ``ux``, is what nothing resists; the sample fails naming it and the
    joint (its tangent is singular at the start, whatever the load across the axis)."""
    text = (
        pendulum(1.0, 1.0, 0.0)
        .replace('"revolute"', '"prismatic"')
        .replace("axis = [0.0, 0.0, 1.0]", "axis = [1.0, 0.0, 0.0]")
    )
    run_scene(tmp_path, text, capsys)
    (sample,) = read(tmp_path / "out" / "samples.csv")
    assert sample["converged"] == "false"
    assert sample["error"] == (
        "exact kinematics: at the start, a free motion nothing resists (a singular tangent): "
        "mostly body 'bob' ux, left free by joint[0] (prismatic)"
    )


def test_redundant_rows_are_named():
    """Two fixed joints holding one body to the ground: the body is held, but the second
    joint's rows repeat the first's (their multipliers are the null vector)."""
    bob = RigidBody("bob", [0.0, -1.0, 0.0])
    model = ExactModel(bodies=[bob], joints=[Joint("fixed", "ground", "bob")] * 2)
    free = np.arange(model.n_dofs)
    motion = model.free_motion(model.reference(), free)
    assert motion is not None and "(fixed) repeat what other joints or supports hold" in motion
    single = ExactModel(bodies=[bob], joints=[Joint("fixed", "ground", "bob")])
    assert single.free_motion(single.reference(), np.arange(single.n_dofs)) is None


def test_a_joint_of_two_tied_nodes_is_refused(tmp_path, capsys):
    """The toggle's apex hinge put between the apex and the node it is tied to."""
    hinge = '[[joint]]\nkind = "revolute"\na = "apex"\nb = "upper.end"\n'
    text = TOGGLE.replace("JOINTS\n", hinge).replace("LOAD", "-1.0")
    code, _, err = run_scene(tmp_path, text, capsys, "check")
    assert code == 2
    assert "joint[0].b = 'upper.end': is tied to 'apex': one node, nothing to join" in err
