"""The linear answer's bound on what it neglects (:func:`sliders.app.kinematics.neglected`)
measures the beams' rotations, not a body's rigid spin.

* closed form: a unit cantilever (EJ = 1, GA = 1e8) under a tip force ``P``, its linear
  Timoshenko answer ``v(x) = P (L x^2 / 2 - x^3 / 6) / EJ + P x / GA``, ``theta(x) = P (L x -
  x^2 / 2) / EJ`` put on its nodes, beside a wheel (a body on no beam) turned 49.3 rad
  about its axle: the bound's rotation is the tip's ``P L^2 / 2 EJ``, its displacement the
  tip's, its strain the shear strain ``P / GA``, and ``eta = L theta (theta / 2 + P / GA) /
  v(L)``.  The strain is the recovered one: a relative error ``delta <= 1`` in it moves
  ``eta`` by at most ``2 P / (GA theta) = 4e-8`` of itself, the tolerance;
* the shipped landing gear over 50 ms, its wheel spun up: the rotation its kinematics line
  states is at least that of the tubes' end nodes, and below a tenth of the wheel's spin
  angle then (before, it was that angle).
"""

from __future__ import annotations

import math

import numpy as np
import tomli_w
from test_cli_properties import small
from test_kinematics import STIFF, cantilever

from sliders.app.kinematics import neglected
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.run_dynamic import DynamicRun
from sliders.app.run_exact import dynamic_choice
from sliders.app.scene import load_scene

WHEEL = """
[[body]]
name = "wheel"
position = [2.0, 0.0, 0.0]
inertia = [0.0, 0.15, 0.0]
[[support]]
node = "wheel"
kind = "ux+uy+uz+rx+rz"
"""


def test_a_spinning_body_on_no_beam_does_not_enter_the_bound(tmp_path):
    P, L, spin = 10.0, 1.0, 49.3
    path = tmp_path / "scene.toml"
    text = (
        cantilever(force=P, extra=WHEEL)  # dynamic: the wheel's spin is free
        .replace("EJz = 1.0\n", "EJz = 1.0\nmass_per_length = 1.0\ninertia = [1e-3, 1e-3, 1e-3]\n")
        .replace(
            'kind = "static"',
            'kind = "dynamic"\nt_end = 0.002\nstep = 0.001\nstart = { hold = ["wheel"] }',
        )
    )
    path.write_text(text)
    structure = Model(load_scene(path)).structure
    q = np.zeros(structure.n_dofs)
    nodes = structure.dof_maps[0].reshape(-1, 6)
    x = structure.beams[0].mesh.node_abscissae()
    assert len(x) == len(nodes)
    q[nodes[:, 1]] = P * (L * x**2 / 2 - x**3 / 6) + P * x / STIFF
    q[nodes[:, 5]] = P * (L * x - x**2 / 2)
    q[structure.node_dofs("wheel")[4]] = spin
    bound = neglected(structure, q)
    theta, tip = P * L**2 / 2, P * L**3 / 3 + P * L / STIFF
    assert bound.rotation == theta
    # the nodal value and the closed form, each a few roundings of a sum of three terms
    assert math.isclose(bound.displacement, tip, rel_tol=4 * np.finfo(float).eps)
    tol = 2 * P / (STIFF * theta)
    assert math.isclose(bound.eta, L * theta * (theta / 2 + P / STIFF) / tip, rel_tol=tol)


def test_the_gears_kinematics_line_states_the_tubes_rotation_not_the_wheels(tmp_path):
    scene = small("landing_gear")
    scene["study"]["t_end"] = 250 * scene["study"]["step"]  # 50 ms: spun up (28 ms)
    path = tmp_path / "gear.toml"
    path.write_text(tomli_w.dumps(scene))
    model = Model(load_scene(path))
    outcome = run(model, progress=False)
    assert isinstance(outcome, DynamicRun) and outcome.state is not None
    q, structure = outcome.state.q, model.structure
    bound = neglected(structure, q)
    ends = max(
        float(np.linalg.norm(q[structure.node_dofs(f"{tube}.{end}")[3:]]))
        for tube in "CP"
        for end in ("start", "end")
    )
    wheel = abs(float(q[structure.node_dofs("wheel")[4]]))
    assert ends > 0 and bound.rotation >= ends
    assert bound.rotation < wheel / 10
    statement = dynamic_choice(model, q).statement
    assert f"largest rotation {bound.rotation:.3g} rad" in statement
