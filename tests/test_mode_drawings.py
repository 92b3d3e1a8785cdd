"""Mode shapes drawn over the state they are taken about (sliders.app.run_modes.over_state,
mode_scale, the modes study's VTU series read back with meshio).

A cantilever under a tip force of ``P L^2 / EJ = 2`` bends to a tip rotation of about 0.6
rad with exact kinematics; its modes are drawn at the node positions ``x + a du`` and
rotations ``exp(a dphi) R``.  The VTU is written in double precision (meshio's binary
``float64``), its points the reference ones and ``displacement`` the rest, so the points read
back warped by ``displacement`` are the drawn positions to the round-off of one addition and
subtraction of coordinates of size 1 (``4 u``); the rotation matrix is written from the
rotation vector, exact to the rotation maps' round-off (1e-14).
"""

import tomllib

import numpy as np
import pytest

from fvbeam.rotations import exp_map
from sliders.app.kinematics import ExactSolution
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.run_modes import (
    MODE_FRACTION,
    mode_frames,
    mode_scale,
    over_state,
    write_modes,
)
from sliders.app.scene import parse_scene
from sliders.app.vtu import structure_size
from tests.test_preloaded_modes import SCENE

EPS = np.finfo(float).eps


def solved(tmp_path):
    """The hinged column's scene of ``tests/test_preloaded_modes.py`` as a cantilever of 8
    elements under a tip force ``P L^2 / EJ = 2`` across it, its modes solved."""
    data = tomllib.loads(SCENE)
    data["support"] = [{"node": "rod.start", "kind": "clamp"}]
    data["load"][0]["force"] = [0.0, 2.0, 0.0]
    data["beam"][0]["straight"]["elements"] = 8
    data["study"]["load_steps"] = 4
    results = run(Model(parse_scene(data, tmp_path, "bent.toml")), progress=False)
    assert results.modes is not None
    entry = results.modes[0]
    assert entry.modes is not None and isinstance(entry.sample.solution, ExactSolution)
    return results.modes


def test_a_mode_is_drawn_over_the_exact_state_in_the_vtu(tmp_path):
    meshio = pytest.importorskip("meshio")
    found = solved(tmp_path)
    entry = found[0]
    solution, structure = entry.sample.solution, entry.sample.statics.structure
    state = solution.state
    assert np.linalg.norm(solution.q.reshape(-1, 6)[-1, 3:]) > 0.5  # a large rotation
    write_modes(found, tmp_path, table=False, sweep=False)
    n = len(state.x)
    for k, j in enumerate(np.argsort(entry.number)):  # the series by mode number
        shape = entry.modes.shapes[:, j].reshape(-1, 6)
        a = mode_scale(structure, entry.modes.shapes[:, j])
        # the scale's definition: the largest translation or rotation at MODE_FRACTION
        reached = max(
            np.abs(a * shape[:, :3]).max() / structure_size(structure),
            np.abs(a * shape[:, 3:]).max(),
        )
        assert abs(reached - MODE_FRACTION) < 4 * EPS
        step = tmp_path / "modes_000000" / f"step_{k:06d}.vtu"
        mesh = meshio.read(step)
        drawn = mesh.points[:n] + mesh.point_data["displacement"][:n]
        np.testing.assert_allclose(drawn, state.x + a * shape[:, :3], rtol=0, atol=4 * EPS)
        turned = mesh.point_data["rotation_matrix"][:n].reshape(-1, 3, 3)
        np.testing.assert_allclose(turned, exp_map(a * shape[:, 3:]) @ state.R, atol=1e-14)
        # not the mode over the reference: the state is there
        assert np.abs(mesh.point_data["displacement"][:n] - a * shape[:, :3]).max() > 0.2


def test_a_modes_frames_swing_about_the_state(tmp_path):
    """Frame ``k`` of a real mode is the state moved by ``a phi cos(2 pi k / N)``: the
    middle frame is the state moved by ``-a phi``, and the two average to the state's
    positions (to round-off) while their rotations are the state's turned both ways."""
    entry = solved(tmp_path)[0]
    frames = mode_frames(entry, 0)
    structure, solution = entry.sample.statics.structure, entry.sample.solution
    phi = entry.modes.shapes[:, 0].real
    a = mode_scale(structure, phi)
    np.testing.assert_array_equal(frames[0].q, over_state(solution, a * phi))
    half = frames[len(frames) // 2].q.reshape(-1, 6)
    first = frames[0].q.reshape(-1, 6)
    mean = (first[:, :3] + half[:, :3]) / 2
    np.testing.assert_allclose(mean, solution.q.reshape(-1, 6)[:, :3], atol=8 * EPS)
    turned = exp_map(-a * phi.reshape(-1, 6)[:, 3:]) @ solution.state.R
    np.testing.assert_allclose(exp_map(half[:, 3:]), turned, atol=1e-14)
