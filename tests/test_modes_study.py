"""The modes study of a scene (studies/scenes/sliding_beams_modes.toml): the first frequency
along the stroke against the Figure 4 stiffness and the tip mass, the tables, the mode
shapes' VTU series, MAC following, and the checks.

Tolerance sources:

* The tip mass ``M = 10 kg`` on the tip stiffness ``k``: the tubes weigh ``m = 1.2e-3 kg``
  in all and the tip's rotary inertia is ``J = 1e-6 kg m^2``, so the first frequency is
  ``sqrt(k / M)`` to within ``(m + J (3 / 2L)^2) / M`` relative in ``omega^2`` (Rayleigh's
  quotient: the tubes' share of the modal mass is below their mass, and the tip turns by at
  most ``3 v / 2L``, a cantilever's of length ``L``, the shortest the setup gets),
  1.2e-4; ``k`` the static tip stiffness of the same model.
* Against the paper's closed form (:func:`sliders.sliding_beams.exact.sliding_beams`), the
  model's ``k`` is within the paper's Figure 5 bound for 5 fv3 elements on [0, 0.95 L]
  (2 %, ``studies.fig4_stiffness.BOUNDS``), so ``omega^2`` is within 2 % plus 1.2e-4.
* MAC: 1 up to the eigenvectors' round-off for a shape and itself (1e-12), and exactly the
  squared cosine for two shapes (closed form).
"""

import csv
import tomllib
from pathlib import Path

import numpy as np
import pytest

from sliders.app.cli import main
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import parse_scene
from sliders.sliding_beams.exact import sliding_beams
from sliders.solve.modes import follow, mac

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "studies" / "scenes"
SCENE = SCENES / "sliding_beams_modes.toml"
#: The scene's tip mass, the tubes' total mass, EJ, GA and L.
M_TIP, M_TUBES, J_TIP, EJ, GA, L = 10.0, 1.2e-3, 1e-6, 4.1e4, 1.1e8, 0.6
FIG5_BOUND = 0.02
#: The relative bound on omega^2 M / k - 1 (module docstring).
MASS_SHARE = (M_TUBES + J_TIP * (1.5 / L) ** 2) / M_TIP


def scene(**study) -> dict:
    data = tomllib.loads(SCENE.read_text())
    data["study"].update(study)
    return data


def test_the_first_frequency_is_the_tip_mass_on_the_figure_4_stiffness():
    values = np.linspace(0.0, 0.57, 5)  # s = 0 ... 0.95 L
    data = scene(range={"start": 0.0, "stop": 0.57, "num": len(values)})
    results = run(Model(parse_scene(data, SCENES, "modes.toml")), progress=False)
    assert results.modes is not None and len(results.modes) == len(values)
    for entry, s in zip(results.modes, values, strict=True):
        statics, modes = entry.sample.statics, entry.modes
        tip = statics.structure.node_dofs("P.end")[1]
        f = statics.structure.nodal_load("P.end", (0.0, 1.0, 0.0))
        k = 1.0 / statics.solve(f).q[tip]
        omega2 = modes.omega[:2] ** 2  # the two bending planes
        np.testing.assert_allclose(omega2, k / M_TIP, rtol=MASS_SHARE)
        k_exact = sliding_beams(s, L, EJ, GA, "spherical")["k_norm"] * EJ / L**3
        np.testing.assert_allclose(omega2, k_exact / M_TIP, rtol=FIG5_BOUND + MASS_SHARE)
        assert np.all(modes.damping_ratio == 0) and not modes.complex


def test_run_writes_the_modes_table_the_shapes_and_the_campbell_plot(tmp_path):
    path = tmp_path / "modes.toml"
    path.write_text(SCENE.read_text().replace("num = 20", "num = 3"))
    assert main(["check", str(path)]) == 0
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    out = tmp_path / "out"
    with open(out / "modes.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0]) == ["sample", "value", "mode", "frequency_hz", "damping_ratio", "mac"]
    assert len(rows) == 3 * 4
    assert [int(r["mode"]) for r in rows[:4]] == [1, 2, 3, 4]
    assert all(r["mac"] == "" for r in rows[:4])
    assert all(0 <= float(r["mac"]) <= 1 + 1e-12 for r in rows[4:])
    for k in range(3):
        pvd = out / f"modes_{k:06d}" / f"modes_{k:06d}.pvd"
        assert pvd.is_file() and len(list(pvd.parent.glob("step_*.vtu"))) == 4
    assert (out / "campbell.png").is_file() == _has("matplotlib")


def _has(module: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(module) is not None


def test_mac_of_shapes_is_their_squared_cosine_and_follow_keeps_numbers_across_a_swap():
    a = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    b = np.array([[1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(mac(a, b), [[0.5, 1.0], [0.5, 0.0]], atol=1e-15)
    # two modes whose frequencies crossed: the current shapes come in the other order
    number, values = follow(a, a[:, ::-1] * [[2.0, -3.0]])
    assert list(number) == [1, 0]
    np.testing.assert_allclose(values, 1.0, atol=1e-12)


def test_check_names_the_modes_table_of_another_study_and_values_without_a_parameter(capsys):
    data = tomllib.loads((SCENES / "fig4_sliding_beams.toml").read_text())
    data["output"]["csv"] = ["samples", "modes"]
    from test_scenes import problems

    paths = {p.path: p.message for p in problems(data)}
    assert "modes.csv is a modes study's, not a sweep study's" in paths["output.csv"]
    data = scene()
    del data["study"]["parameter"]
    paths = {p.path: p.message for p in problems(data)}
    assert "values and range sweep a parameter" in paths["study"]


def test_a_bad_count_and_window_are_named():
    from test_scenes import problems

    assert "study.count" in {p.path for p in problems(scene(count=0))}
    assert "study.window" in {p.path for p in problems(scene(window=[5.0, 1.0]))}


def test_modes_benchmark_reports_times_and_the_tip_mass_consistency():
    """Shape of the benchmark's rows, on small sizes (speed is never asserted here)."""
    from studies.bench_modes import bench

    result = bench(elements=20, points=3, repeats=1)
    assert result["large"]["modes"] == 20 and result["large"]["elements"] == 40
    assert result["stroke"]["converged"] == 3
    assert result["stroke"]["tip_mass_consistency"] < MASS_SHARE
    assert all(row["seconds"] > 0 for row in result.values())


def test_planar_is_reported_as_ignored_by_a_modes_study():
    from sliders.app.ignored import ignored_options

    found = ignored_options(parse_scene(scene(planar=True), SCENES, "modes.toml"))
    assert [p.path for p in found] == ["study.planar"]
    assert ignored_options(parse_scene(scene(), SCENES, "modes.toml")) == []


def test_a_modes_frames_are_one_period_of_the_shape_about_the_state():
    """A real mode swings as ``a phi cos(2 pi k / N)`` about the state ``q`` at ``t = k /
    (N f)`` (``a`` its drawing scale): the first frame is ``q + a phi``, the middle one
    ``q - a phi`` (exactly: ``e^{i pi} = -1`` to round-off), and the frames span one
    period."""
    from sliders.app.run_modes import MODE_FRAMES, mode_frames, mode_scale

    data = scene(range={"start": 0.0, "stop": 0.0, "num": 1})
    found = run(Model(parse_scene(data, SCENES, "modes.toml")), progress=False).modes
    assert found is not None and found[0].modes is not None
    frames = mode_frames(found[0], 0)
    phi, hertz = found[0].modes.shapes[:, 0].real, found[0].modes.hertz[0]
    q = found[0].sample.solution.q
    a = mode_scale(found[0].sample.statics.structure, phi)
    assert len(frames) == MODE_FRAMES
    np.testing.assert_array_equal(frames[0].q, q + a * phi)
    half = frames[MODE_FRAMES // 2]
    atol = 4 * np.finfo(float).eps * (np.abs(q).max() + a * np.abs(phi).max())
    np.testing.assert_allclose(half.q, q - a * phi, atol=atol)
    np.testing.assert_allclose(
        [f.time for f in frames], np.arange(MODE_FRAMES) / (MODE_FRAMES * hertz), rtol=1e-15
    )


def test_a_modes_study_animates_each_mode_of_its_first_sample(tmp_path):
    """``animation = "gif"`` on a modes study writes ``mode_NN.gif`` per mode of the first
    sample, one period each (``MODE_FRAMES`` frames)."""
    imageio = pytest.importorskip("imageio")
    pytest.importorskip("pyvista")
    from sliders.app.run_modes import MODE_FRAMES

    path = tmp_path / "modes.toml"
    text = SCENE.read_text().replace("num = 20", "num = 2").replace("count = 4", "count = 2")
    path.write_text(
        text.replace('csv = ["samples", "modes"]', 'csv = ["modes"]\nanimation = "gif"')
    )
    assert main(["check", str(path)]) == 0
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    written = sorted(p.name for p in (tmp_path / "out").glob("mode_*.gif"))
    assert written == ["mode_01.gif", "mode_02.gif"]
    for name in written:
        assert len(imageio.mimread(tmp_path / "out" / name)) == MODE_FRAMES


def test_a_modes_study_renders_each_mode_of_the_last_sample(tmp_path):
    """``png = "last"`` on a modes study renders, beside the last sample's state, each of its
    modes at its peak as ``render_NNNNNN_mode_NN.png``; the two bending planes' modes are
    different pictures (beside their titles)."""
    imageio = pytest.importorskip("imageio")
    pytest.importorskip("pyvista")

    path = tmp_path / "modes.toml"
    text = SCENE.read_text().replace("num = 20", "num = 2").replace("count = 4", "count = 2")
    path.write_text(text.replace('csv = ["samples", "modes"]', 'csv = ["modes"]\npng = "last"'))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    written = sorted(p.name for p in (tmp_path / "out").glob("render_*.png"))
    assert written == [
        "render_000001.png",
        "render_000001_mode_01.png",
        "render_000001_mode_02.png",
    ]
    first, second = (imageio.v3.imread(tmp_path / "out" / name) for name in written[1:])
    band = slice(first.shape[0] // 10, 9 * first.shape[0] // 10)  # without the texts
    assert first.shape == second.shape and np.any(first[band] != second[band])
