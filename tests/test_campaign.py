"""Campaigns: one scene over many cases on Dask (``sliders.app.campaign``).

Sources of the asserted numbers: ``fvslider run`` of each resolved scene (a campaign's case is
the same computation, so its tables and peaks equal the command's bit for bit), the campaign
file's own values (the cases are their product, zip or seeded sample), and counting the
cases a resumed campaign runs.
"""

import csv
import importlib
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tomli_w
from test_scenes import data

from sliders.app import campaign as campaign_module
from sliders.app.campaign import reduce, run_campaign
from sliders.app.campaign_spec import ResultSpec, read_campaign
from sliders.app.cli import main
from sliders.app.errors import SceneError
from sliders.app.scene import load_scene
from sliders.app.scene_keys import KeyPathError, get_value, with_values

#: The tiny scene: the pushed body of Figure 2 for 0.5 s (10 steps), the tip's deflection and
#: the cart's reaction as probes.
PROBES = [
    {"name": "tip", "node": "cantilever.end", "value": "uy"},
    {"name": "root_shear", "beam": "cantilever", "at": 0.0, "value": "V2"},
]
RESULTS = [
    {"name": "tip", "column": "tip", "reduce": "max", "concurrent": ["root_shear"]},
    {"name": "shear", "column": "root_shear", "reduce": "absmax"},
    {"name": "final", "column": "tip", "reduce": "last"},
]


def tiny(tmp_path, axes, results=RESULTS, **extra):
    """A campaign file over the tiny scene in ``tmp_path``; its path."""
    scene = data("pushed_body")
    scene["study"].update(t_end=0.5, step=0.05)
    scene["output"] = {"csv": [], "probe": PROBES}
    (tmp_path / "scene.toml").write_text(tomli_w.dumps(scene))
    spec = {"scene": "scene.toml", "axis": axes, "result": results, **extra}
    path = tmp_path / "campaign.toml"
    path.write_text(tomli_w.dumps(spec))
    return path


MATRIX = [
    {"key": "drive[0].motion.velocity", "values": [0.02, 0.035]},
    {"key": "section[unit].mass_per_length", "values": [1.0, 2.0]},
]


def history(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return {n: np.array([float(r[i]) for r in rows[1:]]) for i, n in enumerate(rows[0])}


def test_key_paths_address_tables_by_index_or_name():
    scene = data("landing_gear")
    assert get_value(scene, "body[airframe].mass") == get_value(scene, "body[0].mass")
    assert get_value(scene, "study.start.velocity[2]") == -2.8
    assert get_value(scene, "force[tyre].D") == 0.8
    changed = with_values(scene, {"study.start.velocity[2]": -3.05, "beam[P].straight.elements": 5})
    assert changed["study"]["start"]["velocity"] == [40.0, 0.0, -3.05]
    assert changed["beam"][1]["straight"]["elements"] == 5
    assert scene["study"]["start"]["velocity"][2] == -2.8  # the document is left as it was
    with pytest.raises(KeyPathError, match="named 'airfrme'.*airframe"):
        get_value(scene, "body[airfrme].mass")
    with pytest.raises(KeyPathError, match="has 3 entries"):
        get_value(scene, "study.start.velocity[3]")
    with pytest.raises(KeyPathError, match=r"tie.*use an index"):
        get_value(scene, "tie[C].nodes")


def test_load_scene_takes_a_document_as_well_as_a_path(tmp_path):
    path = tiny(tmp_path, MATRIX).parent / "scene.toml"
    document = tomllib.loads(path.read_text())
    assert load_scene(document, base=path.parent) == load_scene(path)
    document["section"][0]["EA"] = -1.0
    with pytest.raises(SceneError, match=r"(?s)in memory: invalid scene.*section\[0\]\.EA"):
        load_scene(document, source="in memory")


def test_campaign_problems_are_named(tmp_path):
    path = tiny(tmp_path, [{"key": "body[crat].mass", "values": [1.0]}, {"key": "study.t_end"}])
    with pytest.raises(SceneError) as info:
        read_campaign(path)
    (problem,) = info.value.problems  # the schema first: axis[1] has no values
    assert problem.path == "axis[1]" and "values" in problem.message
    path = tiny(tmp_path, [{"key": "body[crat].mass", "values": [1.0]}])
    with pytest.raises(SceneError) as info:
        read_campaign(path)
    (problem,) = info.value.problems
    assert problem.path == "axis[0].key" and "'cart'" in problem.message


def test_cases_are_the_product_a_zip_or_a_seeded_sample(tmp_path):
    product = read_campaign(tiny(tmp_path, MATRIX)).values()
    assert [tuple(v.values()) for v in product] == [
        (0.02, 1.0),
        (0.02, 2.0),
        (0.035, 1.0),
        (0.035, 2.0),
    ]
    zipped = read_campaign(tiny(tmp_path, MATRIX, combine="zip")).values()
    assert [tuple(v.values()) for v in zipped] == [(0.02, 1.0), (0.035, 2.0)]
    axes = [
        {"key": "drive[0].motion.velocity", "range": [0.01, 0.04]},
        {"key": "beam[0].straight.elements", "range": [1, 3]},
        {"key": "formulation", "values": ["fv3", "galerkin-p2"]},
    ]
    sample = read_campaign(tiny(tmp_path, axes, sample={"size": 50, "seed": 7})).values()
    again = read_campaign(tiny(tmp_path, axes, sample={"size": 50, "seed": 7})).values()
    assert sample == again and len(sample) == 50
    speeds = [v["drive[0].motion.velocity"] for v in sample]
    assert all(0.01 <= s < 0.04 for s in speeds) and len(set(speeds)) == 50
    assert {v["beam[0].straight.elements"] for v in sample} == {1, 2, 3}
    assert {v["formulation"] for v in sample} == {"fv3", "galerkin-p2"}


def test_a_campaign_equals_the_command_case_for_case(tmp_path):
    """Each case's tables are those ``fvslider run`` writes of its resolved scene, byte for
    byte, and its results the peaks of that ``history.csv``."""
    campaign = read_campaign(tiny(tmp_path, MATRIX))
    outcome = run_campaign(campaign, tmp_path / "out", workers=0, keep=True, progress=False)
    table = pd.read_parquet(tmp_path / "out" / "cases.parquet")
    assert outcome.run == 4 and outcome.failed == 0 and list(table["status"]) == ["ok"] * 4
    csv_table = pd.read_csv(tmp_path / "out" / "cases.csv")
    assert table["message"].isna().all() and csv_table["message"].isna().all()
    pd.testing.assert_frame_equal(table.drop(columns="message"), csv_table.drop(columns="message"))
    for case in campaign.cases():
        scene = tmp_path / f"case{case.index}.toml"
        scene.write_text(tomli_w.dumps(case.scene))
        assert main(["run", str(scene), "--out", str(tmp_path / f"run{case.index}")]) == 0
        ours = tmp_path / "out" / "runs" / f"case_{case.index:06d}" / "history.csv"
        theirs = tmp_path / f"run{case.index}" / "history.csv"
        assert ours.read_bytes() == theirs.read_bytes()
        h, row = history(theirs), table.iloc[case.index]
        k = int(np.argmax(h["tip"]))
        assert row["tip"] == h["tip"][k] and row["tip.t"] == h["t"][k]
        assert row["tip.root_shear"] == h["root_shear"][k]
        assert row["shear"] == h["root_shear"][np.argmax(np.abs(h["root_shear"]))]
        assert row["final"] == h["tip"][-1]
        for key, value in case.values.items():
            assert row[key] == value


def test_a_bad_value_fails_its_case_only(tmp_path, capsys):
    axes = [{"key": "section[unit].EA", "values": [1e3, -1.0, 2e3]}]
    out = tmp_path / "out"
    assert main(["campaign", str(tiny(tmp_path, axes)), "--out", str(out), "--workers", "0"]) == 1
    table = pd.read_csv(out / "cases.csv")
    assert list(table["status"]) == ["ok", "failed", "ok"]
    assert "section[0].EA" in table["message"][1] and table["message"].isna()[[0, 2]].all()
    assert np.isnan(table["tip"][1]) and np.isfinite(table["tip"][[0, 2]]).all()
    assert "case 1 failed" in capsys.readouterr().err


def test_resume_after_an_interruption_reruns_nothing_finished(tmp_path, monkeypatch):
    campaign = read_campaign(tiny(tmp_path, MATRIX))
    calls = []
    real = campaign_module.run_case

    def interrupted_after_two(case, *args):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(case.index)
        return real(case, *args)

    monkeypatch.setattr(campaign_module, "run_case", interrupted_after_two)
    first = run_campaign(campaign, tmp_path / "out", workers=0, progress=False)
    assert first.interrupted and calls == [0, 1] and len(first.table) == 2
    kept = pd.read_parquet(tmp_path / "out" / "cases.parquet")
    calls.clear()
    monkeypatch.setattr(
        campaign_module, "run_case", lambda case, *a: calls.append(case.index) or real(case, *a)
    )
    second = run_campaign(campaign, tmp_path / "out", workers=0, resume=True, progress=False)
    assert calls == [2, 3] and second.skipped == 2 and second.run == 2
    table = pd.read_parquet(tmp_path / "out" / "cases.parquet")
    assert list(table["case"]) == [0, 1, 2, 3]
    pd.testing.assert_frame_equal(table.iloc[:2], kept)  # the finished rows as they were
    calls.clear()
    third = run_campaign(campaign, tmp_path / "out", workers=0, resume=True, progress=False)
    assert calls == [] and third.skipped == 4


def test_efficiency_of_a_constant_force_is_one_and_of_a_linear_spring_one_half():
    """A shock absorber's efficiency: work over peak force times peak stroke (1 for a
    constant force, 1/2 for a spring, exactly under the trapezoidal rule)."""
    stroke = np.linspace(0.0, 0.1, 11)
    spec = ResultSpec(name="eta", column="force", reduce="efficiency", over="stroke")
    constant = pd.DataFrame({"t": stroke, "stroke": stroke, "force": np.full(11, 5.0)})
    spring = pd.DataFrame({"t": stroke, "stroke": stroke, "force": 3.0 * stroke})
    assert reduce(constant, spec)["eta"] == pytest.approx(1.0, rel=1e-15)
    assert reduce(spring, spec)["eta"] == pytest.approx(0.5, rel=1e-15)


def test_the_shipped_landing_gear_campaign_resolves_every_case():
    """``studies/campaigns/landing_gear.toml``: its cases are the product of its axes (3 sink
    speeds x 4 weights with their lift x 2 forward speeds x 2 friction peaks x 2 models = 96),
    each setting its axes' keys, and every resolved scene validates."""
    from test_scenes import ROOT

    shipped = read_campaign(ROOT / "studies" / "campaigns" / "landing_gear.toml")
    cases = shipped.cases()
    assert len(cases) == 3 * 4 * 2 * 2 * 2
    for case in cases:
        for key, value in case.values.items():
            assert get_value(case.scene, key) == value
        load_scene(case.scene, base=shipped.base)


def compiled_kernels(root: Path) -> dict[str, int]:
    """Each numba cache index under ``root`` and the time it was last written (ns)."""
    return {str(p): p.stat().st_mtime_ns for p in root.rglob("*.nbi")}


def test_dask_workers_load_the_kernels_from_the_shared_cache(tmp_path, monkeypatch):
    """A local cluster's worker gives the cases the numbers this process gives them (bit for
    bit: the same computation) and compiles nothing: the kernels this process compiled (or
    loaded) are loaded from the cache beside their modules, whose index files the worker
    does not rewrite (numba rewrites a kernel's index when it compiles it).  The workers
    import a copy of the packages with their caches (first on the ``sys.path`` they are
    spawned with), so that no other test process compiling at the same time touches the
    files watched."""
    import fvbeam
    import sliders

    campaign = read_campaign(tiny(tmp_path, MATRIX[:1]))
    here = run_campaign(campaign, tmp_path / "here", workers=0, progress=False)
    copy = tmp_path / "packages"
    for package in (fvbeam, sliders):
        source = Path(package.__file__).parent
        shutil.copytree(source, copy / source.name)  # sources and caches, their times kept
    monkeypatch.syspath_prepend(str(copy))  # a spawned worker starts with this sys.path
    before = compiled_kernels(copy)
    assert before
    with campaign_module.local_client(1) as client:
        imported = client.submit(lambda: importlib.import_module("sliders").__file__).result()
        address = client.scheduler.address
        there = run_campaign(campaign, tmp_path / "there", scheduler=address, progress=False)
    assert Path(imported).is_relative_to(copy)  # the worker imported the copy
    assert there.failed == 0 and there.run == 2
    pd.testing.assert_frame_equal(
        here.table.drop(columns="seconds"), there.table.drop(columns="seconds")
    )
    assert compiled_kernels(copy) == before


def test_the_landing_gear_report_is_its_cases_own_history(tmp_path):
    """The shipped campaign's results and report on two cases of a short drop (0.06 s: the
    spin-up at 25 ms and the vertical peak at 44 ms, ``docs/landing_gear.md``), read against
    each case's own ``history.csv``: every peak is the column's extreme row with that row's
    time and concurrent loads, the load factor the vertical peak over the weight ``(m + 12
    kg) g`` (the airframe's ``m - 6e-5``, the axle's ``12 - 6e-5`` and the tubes' ``1.2e-4``
    kg of the scene, summed in another order: to a few ulps), the efficiency
    its definition, the work of the strut force over the stroke up to the largest stroke
    (``numpy.trapezoid``) over the peak force and stroke there."""
    from test_scenes import ROOT

    shipped = tomllib.loads((ROOT / "studies" / "campaigns" / "landing_gear.toml").read_text())
    scene = data("landing_gear")
    scene["study"]["t_end"] = 0.06
    (tmp_path / "scene.toml").write_text(tomli_w.dumps(scene))
    masses = [299.99994, 239.99994]
    axes = [shipped["axis"][1] | {"values": [[masses[0], 3060.72], [masses[1], 1648.08]]}]
    report = {"plot": ["vertical", "spin_up"], "against": "body[airframe].mass"}
    spec = {"scene": "scene.toml", "axis": axes, "result": shipped["result"], "report": report}
    (tmp_path / "campaign.toml").write_text(tomli_w.dumps(spec))
    campaign = read_campaign(tmp_path / "campaign.toml")
    outcome = run_campaign(campaign, tmp_path / "out", workers=0, keep=True, progress=False)
    assert outcome.failed == 0 and outcome.run == 2
    table = pd.read_csv(tmp_path / "out" / "cases.csv")
    for k, row in table.iterrows():
        h = pd.read_csv(tmp_path / "out" / "runs" / f"case_{k:06d}" / "history.csv")
        for name, column, at in (
            ("vertical", "F_z", h["F_z"].idxmax()),
            ("spin_up", "F_x", h["F_x"].idxmin()),
            ("spring_back", "F_x", h["F_x"].idxmax()),
            ("stroke", "stroke", h["stroke"].idxmax()),
        ):
            assert row[name] == h[column][at] and row[f"{name}.t"] == h["t"][at]
        for name, others in (("vertical", ["F_x", "strut_force", "stroke"]), ("spin_up", ["F_z"])):
            at = row[f"{name}.t"] == h["t"]
            assert all(row[f"{name}.{c}"] == h[c][at].item() for c in others)
        assert row["spin_up"] < 0 <= row["spring_back"]
        weight = (masses[k] + 0.00006 + 12.0) * 9.81
        assert row["load_factor"] == pytest.approx(h["F_z"].max() / weight, rel=8 * 2.2e-16)
        top = int(h["stroke"].idxmax())
        force, stroke = h["strut_force"][: top + 1], h["stroke"][: top + 1]
        work = np.trapezoid(force, stroke)
        assert row["efficiency"] == pytest.approx(work / (force.max() * stroke[top]), rel=1e-12)
        assert 0 < row["efficiency"] <= 1
    assert (outcome.report is not None) == _has_matplotlib()
    if outcome.report is not None:
        assert outcome.report == tmp_path / "out" / "report.png"
        assert outcome.report.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _has_matplotlib() -> bool:
    return importlib.util.find_spec("matplotlib") is not None
