"""The Figure 7 study (studies/fig7_landing_gear.py) on two models: its files, their columns,
and the checks it reports (the rigid model against its ODEs to issue 14's 1e-3)."""

import csv

import numpy as np
import pytest

from sliders.gear.outputs import COLUMNS
from studies import fig7_landing_gear as study


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig7")
    rows = study.reproduce(out, plot_png=True, progress=False, models=("rigid", "fv3-1"))
    return out, rows


def test_files_and_columns(written):
    out, _ = written
    with open(out / "fig7_landing_gear.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    assert tuple(table[0]) == ("model", "t", *COLUMNS)
    steps = round(study.T_END / study.STEP) + 1
    assert [row["model"] for row in table] == ["rigid"] * steps + ["fv3-1"] * steps
    assert float(table[-1]["t"]) == pytest.approx(study.T_END)
    with open(out / "fig7_landing_gear_summary.csv", newline="") as handle:
        summary = list(csv.DictReader(handle))
    assert tuple(summary[0]) == study.SUMMARY and [s["model"] for s in summary] == [
        "rigid",
        "fv3-1",
    ]
    # the rigid leg has no spring-back frequency, the flexible one has
    assert summary[0]["spring_back_frequency"] == "" == summary[0]["spring_back"]
    assert all(float(row["bottoming_penetration"]) == 0.0 for row in summary)
    assert float(summary[1]["spring_back_frequency"]) > 0
    # the friction in the dynamics is mu N tanh <= mu N, N the run's own transverse reaction:
    # the post-processed friction of the frictionless run to the friction's feedback on the
    # loads (the ODEs: 1.6 % on the friction's peak, docs/landing_gear.md), within 5 %
    for row in summary:
        dynamic, post = (float(row[f"friction_{k}_fraction"]) for k in ("dynamic", "post"))
        assert 0 < dynamic and abs(dynamic / post - 1) <= 0.05
    for name in ("fig7_landing_gear.png", "fig7_render.png"):
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_the_checks_hold_the_rigid_model_to_its_odes(written):
    _, rows = written
    rigid = [error for case, error, _ in rows if case.startswith("rigid vs ODE")]
    assert len(rigid) == 4 and max(rigid) <= 1e-3
    assert all(np.isfinite(error) for _, error, _ in rows)
