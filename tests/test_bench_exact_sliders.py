"""Smoke test of ``studies.bench_exact_sliders``: output structure, time beside error, never
speed."""

from __future__ import annotations

import json

from studies.bench_exact_sliders import main


def test_quick_run_writes_time_beside_error_and_keeps_other_keys(tmp_path, capsys):
    out = tmp_path / "b.json"
    out.write_text(json.dumps({"other_benchmark": {"kept": True}}))
    main(["--out", str(out), "--quick"])
    data = json.loads(out.read_text())
    assert data["other_benchmark"] == {"kept": True}
    (row,) = data["exact_sliders"]["bearing"]
    assert row["n_elements"] == 8 and row["closed_form_N"] > 0
    for path in ("exact", "linear"):
        assert row[path]["seconds"]["min"] > 0 and row[path]["rel_error"] >= 0
        assert row[path]["newton_iterations"] > 0
    assert "bearing, fv3 x 8: exact" in capsys.readouterr().out
