"""Smoke test of ``studies.bench``: output structure and merge behaviour, never speed."""

from __future__ import annotations

import json

import numpy as np
import pytest

from studies.bench import main

STAGES = ("assembly_s", "factorisation_s", "solve_s", "per_load_case_s")


def test_quick_run_writes_rows_and_keeps_other_keys(tmp_path, capsys):
    out = tmp_path / "b.json"
    out.write_text(json.dumps({"other_benchmark": {"kept": True}, "environment": "stale"}))

    main(["--out", str(out), "--quick"])

    data = json.loads(out.read_text())
    assert data["other_benchmark"] == {"kept": True}
    env = data["environment"]
    for key in ("python", "numpy", "scipy", "scikit-fem", "cpu_count", "date"):
        assert key in env
    rows = data["fv3_cantilever"]
    assert [r["n_elements"] for r in rows] == [10, 100]
    for row in rows:
        for stage in STAGES:
            assert row[stage]["median"] > 0
            assert 0 < row[stage]["min"] <= row[stage]["median"]
        assert row["rel_error_xi_0.7"] >= 0
        assert row["per_load_case_max_rel_error"] >= 0
    assert "n = 100" in capsys.readouterr().out


def test_second_run_replaces_only_its_own_keys(tmp_path):
    out = tmp_path / "b.json"
    main(["--out", str(out), "--quick"])
    data = json.loads(out.read_text())
    data["later_benchmark"] = [1, 2, 3]
    out.write_text(json.dumps(data))

    main(["--out", str(out), "--quick"])

    again = json.loads(out.read_text())
    assert again["later_benchmark"] == [1, 2, 3]
    assert len(again["fv3_cantilever"]) == 2


def test_sweep_benchmark_reports_time_iterations_and_error():
    """Shape of the sweep benchmark (no timing threshold: speed is never asserted here).  The
    scene rows solve the sliding beams of the other rows from the scene file: the same worst
    errors, to the 2e-4 of the batched rows (below)."""
    from studies.bench_sweep import bench

    result = bench(elements=(1,), progress=False)
    assert len(result["rows"]) == 6 and not result["interrupted"]
    assert all(result["total_seconds"][mode] > 0 for mode in ("continuation", "cold", "scene"))
    for row in result["rows"]:
        assert row["positions"] == 96 and row["mean_newton_iterations"] >= 1
        assert row["max_abs_rel_error"] < 1.0
    scene = [r for r in result["rows"] if r["mode"] == "scene"]
    per_point = [r for r in result["rows"] if r["mode"] == "continuation"]
    for a, b in zip(scene, per_point, strict=True):
        assert a["setup_seconds"] > 0 and a["singular_positions"] == b["singular_positions"] == 0
        assert abs(a["max_abs_rel_error"] - b["max_abs_rel_error"]) <= 2e-4
    general = result["general_path"]
    assert general["seconds"] == result["total_seconds"]["continuation"]
    assert general["positions"] == 192 and general["cpu_seconds"] > 0


def test_fig2_benchmark_reports_step_times_with_and_without_recording():
    """Shape of the Figure 2 benchmark on the 10-period crossing: per level the recorded and
    the bare time per step (wall and CPU) beside the end errors (never a speed threshold)."""
    from studies.bench_dynamics import fig2_dynamics

    result = fig2_dynamics("fast", levels=(0.01,))
    (row,) = result["rows"]
    assert not result["interrupted"] and row["steps"] == 400
    for key in ("", "cpu_", "bare_", "bare_cpu_"):
        assert row[f"{key}seconds_per_step"] > 0
    assert row["end_tip_error"] >= 0 and row["mean_iterations"] >= 1


def test_batched_sweep_benchmark_reports_the_main_sweep():
    """The batched mode: one row per kind, its untimed setup (the template) apart, the same
    worst errors as the per-position solves: their states agree within the bound of
    tests/test_condensed.py, at most 1e-4 of the solution, so ``k`` to 1e-4 relative and the
    relative errors (below 1) to 2e-4.  ``main_sweep`` sums the batched rows."""
    from studies.bench_sweep import ALL_MODES, bench

    result = bench(elements=(1,), modes=ALL_MODES[:2], progress=False)
    batched = [r for r in result["rows"] if r["mode"] == "batched"]
    per_point = [r for r in result["rows"] if r["mode"] == "continuation"]
    assert len(batched) == 2
    for a, b in zip(batched, per_point, strict=True):
        assert a["seconds"] > 0 and a["setup_seconds"] > 0
        assert a["singular_positions"] == b["singular_positions"] == 0
        assert abs(a["max_abs_rel_error"] - b["max_abs_rel_error"]) <= 2e-4
    main = result["main_sweep"]
    assert main["seconds"] == result["total_seconds"]["batched"]
    assert main["setup_seconds"] == sum(r["setup_seconds"] for r in batched)
    assert main["positions"] == 192 and main["mean_newton_iterations"] >= 1


def test_outputs_benchmark_reports_time_and_error_per_setup():
    """Shape of the outputs benchmark: every recorder set-up timed beside its energies'
    difference from their definitions, the recovery map beside the field path (their
    round-off bounds are tests/test_recorder.py's and tests/test_recovery.py's)."""
    from studies.bench_outputs import recording, recovery

    result = recording(repeats=1, periods=1)
    assert [r["setup"] for r in result["rows"]] == [
        "default",
        "no_residuals",
        "probes",
        "probes_by_function",
        "tables",
    ]
    for row in result["rows"]:
        assert row["seconds_per_step"]["min"] > 0 and row["seconds_per_row_formatted"]["min"] > 0
        assert np.isfinite(row["energy_rel_error"]) and row["energy_rel_error"] >= 0
    rows = recovery(repeats=2)["rows"]
    assert [r["n_elements"] for r in rows] == [1, 100]
    assert all(np.isfinite(r["max_rel_difference"]) and r["speed_up"] > 0 for r in rows)


def test_landing_gear_benchmark_reports_its_step_time_and_errors(tmp_path):
    """Shape of the landing-gear benchmark (``--quick``), never its speed."""
    from studies.bench_landing_gear import LOADS
    from studies.bench_landing_gear import main as gear_main

    out = tmp_path / "b.json"
    gear_main(["--out", str(out), "--quick"])
    result = json.loads(out.read_text())["landing_gear"]
    assert not result["interrupted"] and result["setup_s"] > 0
    assert [row["step"] for row in result["convergence"]] == [4e-4, 2e-4]
    for row in result["convergence"]:
        assert row["max_load_error"] == max(row["rel_errors"][name] for name in LOADS)
    assert result["bench"]["step"] in (4e-4, 2e-4) and result["bench"]["seconds"]["min"] > 0
    assert [row["model"] for row in result["mesh"]] == ["fv3-1"]


def test_command_benchmark_scenes_are_valid():
    """The scenes ``studies.bench_command`` runs through the command validate (their speed is
    measured by ``make bench`` only)."""
    from sliders.app.scene import parse_scene
    from studies.bench_command import cantilever, pushed

    assert parse_scene(cantilever(10)).beam[0].straight.elements == 10
    assert parse_scene(cantilever(10, dynamic=True)).study.kind == "dynamic"
    for record in (True, False):
        scene = parse_scene(pushed(0.1, record))
        assert scene.study.t_end == 0.1
        assert scene.output.csv == (("nodes",) if record else ())
        assert scene.output.history == (None if record else ())


def test_the_moving_load_scene_is_the_in_process_slider_problem():
    """``studies.moving_load.scene`` (what ``studies.bench_command`` runs through the
    command) validates, and builds the model ``Model.dynamics(loading="slider")`` integrates
    in process: the same beam matrices (the same section and mesh), supports (less the
    out-of-plane dofs a planar scene holds) and load."""
    from sliders.app.model import Model
    from sliders.app.scene import parse_scene
    from studies import moving_load as ml

    model = Model(parse_scene(ml.scene("cubic", 4, 50, 0.8, 0.1)))
    reference = ml.model("cubic", 4).dynamics(0.8, "slider")
    dynamics = model.dynamics()
    for ours, theirs in ((dynamics.K, reference.K), (dynamics.M, reference.M)):
        assert (ours != theirs).nnz == 0
    # the scene is solved in its plane: the same free dofs but the out-of-plane ones
    held = np.setdiff1d(reference.free, dynamics.free)
    assert set(dynamics.free) <= set(reference.free) and set(held % 6) <= {2, 3, 4}
    assert np.array_equal(dynamics.load(0.0), reference.load(0.0))
    with pytest.raises(ValueError, match="even"):
        ml.scene("cubic", 3, 50, 0.8, 0.1)


def test_campaign_benchmark_samples_200_drops():
    """The campaign ``studies.bench_campaign`` runs (its speed is measured by ``make bench``
    only): 200 distinct drops (the sink speed drawn from a range), the same on every call
    (seeded)."""
    from studies.bench_campaign import CASES, sample

    keys = [c.key for c in sample(CASES).cases()]
    assert len(set(keys)) == CASES and keys == [c.key for c in sample(CASES).cases()]
