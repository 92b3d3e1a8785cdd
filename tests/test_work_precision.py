"""The work-precision study's quick grid (``studies/work_precision.py``), and its peer's.

Timings are never asserted, only that they are there.  The errors' sources:

* **Moving load, meshes.**  At 800 steps per crossing the time error is below the spatial
  one (``tests/test_moving_load.py``: the step error at 800 steps is about ``1e-4`` on two
  elements and falls with the mesh's loaded frequencies), so the error falls with the mesh at
  the formulation's order over 1.5 crossing times: fv3 **2** (``n = 4, 8, 16``), galerkin-p2
  **3** on the last doubling (``docs/dynamics.md``: the P2 order reaches 3 from 8 elements
  on; 4 to 8 is pre-asymptotic, 2.5 on the verification scene), within the order tolerance
  of ``tests/test_moving_load.py``.
* **Statics.**  The sliding-beams tip-stiffness error falls as the mesh is refined
  (``docs/sliders.md``, "Under refinement"); no rate is claimed, since the largest error
  over the stations converges erratically (orders 1.6 to 2).  The cubic element's is at
  round-off on every mesh: its nodal statics are exact for end loads, and the two-beam
  solution is made of end-loaded beams (``docs/theory.md`` Sec. 9; the bound of
  ``tests/test_cubic.py``, ``test_sliding_beams_tip_stiffness_is_the_closed_form``).
* **Figure 2 scene.**  The overshoot of the shear at the evaluation point is fv3's (the
  cubic element has no evaluation point: its rows leave it empty).
* **Peer** (skipped without Exudyn): the cubic Hermite shape functions are a partition of
  unity and reproduce cubics (their defining property), and the peer's rows have our columns.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from studies import work_precision as wp

ORDER_TOLERANCE = 0.5


@pytest.fixture(scope="module")
def rows():
    rows, interrupted = wp.compute(wp.QUICK, progress=False)
    assert not interrupted
    return rows


def pick(rows, **match):
    return [r for r in rows if all(r[k] == v for k, v in match.items())]


def test_every_job_gives_one_row_with_times(rows):
    assert len(rows) == len(wp.Study(wp.QUICK).jobs())
    for r in rows:
        assert tuple(r) == wp.COLUMNS
        assert r["wall_seconds"] > 0 and r["cpu_seconds"] > 0
        assert math.isfinite(r["error"]) and r["error"] > 0
    assert {r["study"] for r in rows} == {"statics", "moving_load", "fig2"}
    for r in pick(rows, study="fig2", formulation="fv3"):
        assert math.isfinite(r["overshoot"])
    (cubic,) = pick(rows, study="fig2", formulation="cubic")
    assert cubic["smearing"] == 0.0 and cubic["overshoot"] == ""
    assert {r["formulation"] for r in pick(rows, study="moving_load")} == set(wp.QUICK.formulations)


@pytest.mark.parametrize("formulation, order, doublings", [("fv3", 2, 2), ("galerkin-p2", 3, 1)])
def test_moving_load_error_falls_at_the_mesh_order(rows, formulation, order, doublings):
    mine = sorted(
        pick(rows, study="moving_load", formulation=formulation), key=lambda r: r["n_elements"]
    )
    assert [r["n_elements"] for r in mine] == list(wp.QUICK.moving_elements)
    errors = np.array([r["error"] for r in mine])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(orders > 0), errors
    assert np.all(np.abs(orders[-doublings:] - order) <= ORDER_TOLERANCE), errors


def test_statics_error_falls_with_the_mesh(rows):
    for formulation in set(wp.QUICK.formulations) - {"cubic"}:
        mine = sorted(
            pick(rows, study="statics", formulation=formulation), key=lambda r: r["n_elements"]
        )
        errors = [r["error"] for r in mine]
        assert np.all(np.diff(errors) < 0), (formulation, errors)


def test_cubic_statics_error_is_roundoff(rows):
    mine = pick(rows, study="statics", formulation="cubic")
    assert [r["n_elements"] for r in mine] == list(wp.QUICK.statics_elements)
    assert max(r["error"] for r in mine) < 1e-8


def test_pareto_front_keeps_only_unbeaten_rows():
    rows = [
        {"cpu_seconds": 1.0, "error": 1e-2},
        {"cpu_seconds": 2.0, "error": 5e-2},  # slower and worse: beaten
        {"cpu_seconds": 3.0, "error": 1e-3},
        {"cpu_seconds": 0.5, "error": 1e-1},
    ]
    assert [r["cpu_seconds"] for r in wp.pareto(rows)] == [0.5, 1.0, 3.0]


def test_outputs_and_docs_block(rows, tmp_path, monkeypatch):
    docs = tmp_path / "performance.md"
    docs.write_text(f"# P\n\nbefore\n{wp.MARKERS[0]}\nold\n{wp.MARKERS[1]}\nafter\n")
    monkeypatch.setattr(wp, "compute", lambda grid, progress: (rows, False))
    out = tmp_path / "out"
    assert wp.main(["--quick", "--out", str(out), "--docs", str(docs), "--no-progress"]) == 0
    read = wp.read_csv(out / "work_precision.csv")
    assert len(read) == len(rows)
    assert float(read[0]["error"]) == rows[0]["error"]  # full precision
    for study in ("statics", "moving_load", "fig2"):
        assert (out / f"work_precision_{study}.png").stat().st_size > 0
    table = (out / "work_precision.md").read_text()
    text = docs.read_text()
    assert "old" not in text and table in text and text.endswith("after\n")
    assert "moving_load, euler-bernoulli" in table
    assert wp.main(["--replot", "--out", str(out), "--no-plot", "--no-progress"]) == 0
    assert (out / "work_precision.md").read_text() == table


def test_ctrl_c_keeps_the_rows_done(tmp_path, monkeypatch):
    done = []

    def run(self, study, parameters):
        if len(done) == 3:  # the first job's untimed warm-up, the first job, the second
            raise KeyboardInterrupt
        done.append(study)
        return wp.row(study=study, case="x", formulation="fv3", cpu_seconds=1.0, error=0.1)

    monkeypatch.setattr(wp.Study, "run", run)
    assert wp.main(["--quick", "--out", str(tmp_path), "--no-plot", "--no-progress"]) == 130
    with open(tmp_path / "work_precision.csv", newline="") as handle:
        assert len(list(csv.DictReader(handle))) == 2


def test_foreign_csv_is_named(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="bad.csv"):
        wp.read_csv(path)


def test_peer_shape_functions_and_rows():
    pytest.importorskip("exudyn")
    from studies import peer_moving_load as peer

    h = 0.3
    xi = np.linspace(0, 1, 7)
    N = np.array([peer.hermite(x, h) for x in xi])
    assert np.allclose(N[:, 0] + N[:, 2], 1, rtol=0, atol=1e-15)
    y = lambda s: 1 + 2 * s - s**2 + 0.5 * s**3  # noqa: E731  a cubic on [0, h]
    dy = lambda s: 2 - 2 * s + 1.5 * s**2  # noqa: E731
    nodal = np.array([y(0), dy(0), y(h), dy(h)])
    assert np.allclose(N @ nodal, y(xi * h), rtol=0, atol=1e-14)
    rows, interrupted = peer.compute(peer.QUICK, progress=False)
    assert not interrupted and len(rows) == 4
    assert all(tuple(r) == wp.COLUMNS and math.isfinite(r["error"]) for r in rows)
