"""Smoke test of ``studies.bench_exact``: output structure, time beside error, never speed."""

from __future__ import annotations

import json

from studies.bench_exact import main


def test_quick_run_writes_time_beside_error_and_keeps_other_keys(tmp_path, capsys):
    out = tmp_path / "b.json"
    out.write_text(json.dumps({"other_benchmark": {"kept": True}}))
    main(["--out", str(out), "--quick"])
    data = json.loads(out.read_text())
    assert data["other_benchmark"] == {"kept": True}
    section = data["exact_statics"]
    assert not section["interrupted"]
    for rows in section["elastica"].values():
        errors = [row["error"] for row in rows]
        assert errors == sorted(errors, reverse=True)  # refined until the target or the cap
        assert all(row["seconds"]["min"] > 0 and row["newton_iterations"] > 0 for row in rows)
    for rows in section.get("peer", {}).values():  # with the peer extra, per setting
        assert all(row["seconds"]["min"] > 0 and row["error"] > 0 for row in rows)
    for name, pair in section.get("side_by_side", {}).items():  # where both reach the target
        assert pair["error"] <= section["target"]
        if name != "peer":
            assert pair["ratio_to_peer"] > 0
    for name in ("fv2", "fv3"):
        assert all(d > 0 for d in section["bend"][name]["distance_to_published"].values())
    for row in section["heavy"].values():  # exact beside linear, each with its error
        assert row["exact"]["error"] < row["linear"]["error"]
        assert row["exact"]["seconds"]["min"] > 0 and row["linear"]["seconds"]["min"] > 0
    assert "45-degree bend" in capsys.readouterr().out
