"""Benchmark of ``fvslider campaign``'s throughput, merged into ``results/bench.json`` under
``campaign``.

The landing-gear campaign (``studies/campaigns/landing_gear.toml``) as a seeded random sample
of :data:`CASES` drops (the sink speed drawn from the range of its values, each other axis
from its values), run by :func:`sliders.app.campaign.
run_campaign` on a local Dask cluster of one worker, then of two: per cluster size the wall
time of the campaign, the cases per second and the per-case overhead, the worker time not
spent in a case (``workers`` times the wall time, the cluster's start included, less the
sum of the cases' own ``seconds``) over that sum.
Targets: two workers give at least :data:`SPEED_UP` times the throughput of one, and the
overhead is under :data:`OVERHEAD` of a case.

Run as ``python -m studies.bench_campaign --out results/bench.json`` (``make bench``);
``--quick``: four drops.
"""

from __future__ import annotations

import tempfile
import time
import tomllib
from pathlib import Path
from typing import Any

from sliders.app.campaign import run_campaign
from sliders.app.campaign_spec import Campaign, parse_campaign

from .bench import bench_arguments, environment, write_merged

KEY = "campaign"
CAMPAIGN = Path(__file__).parent / "campaigns" / "landing_gear.toml"
CASES, SEED = 200, 28
#: Targets: throughput of two workers over one; overhead per case over a case's time.
SPEED_UP, OVERHEAD = 1.8, 0.05


def sample(size: int) -> Campaign:
    """The landing-gear campaign as a seeded sample of ``size`` drops."""
    data = tomllib.loads(CAMPAIGN.read_text())
    sink = data["axis"][0]
    sink["range"] = [min(sink["values"]), max(sink["values"])]
    del sink["values"]
    data["sample"] = {"size": size, "seed": SEED}
    return parse_campaign(data, CAMPAIGN.parent, str(CAMPAIGN))


def measure(campaign: Campaign, workers: int) -> dict[str, Any]:
    """Wall time, throughput and per-case overhead of ``campaign`` on ``workers``."""
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        outcome = run_campaign(campaign, Path(tmp) / "out", workers=workers, progress=False)
        seconds = time.perf_counter() - start
    table = outcome.table
    if outcome.failed:
        raise RuntimeError(f"{outcome.failed} cases failed: {table['message'].dropna().iloc[0]}")
    busy = float(table["seconds"].sum())
    return {
        "workers": workers,
        "cases": len(table),
        "seconds": seconds,
        "case_seconds": busy,
        "cases_per_second": len(table) / seconds,
        "overhead": (workers * seconds - busy) / busy,
    }


def main(argv: list[str] | None = None) -> None:
    """Run the benchmark, merge it into ``--out`` (``--quick``: four drops)."""
    args = bench_arguments("studies.bench_campaign", __doc__ or "", "four drops (smoke test)", argv)
    campaign = sample(4 if args.quick else CASES)
    runs = [measure(campaign, workers) for workers in (1, 2)]
    speed_up = runs[1]["cases_per_second"] / runs[0]["cases_per_second"]
    overhead = max(run["overhead"] for run in runs)
    for run in runs:
        print(
            f"campaign of {run['cases']} drops on {run['workers']} worker(s): "
            f"{run['seconds']:.1f} s, {run['cases_per_second']:.2f} cases/s, overhead "
            f"{100 * run['overhead']:.1f} % of a case",
            flush=True,
        )
    print(f"two workers: {speed_up:.2f} x the throughput of one (target {SPEED_UP})")
    result = {
        "runs": runs,
        "speed_up": speed_up,
        "speed_up_target": SPEED_UP,
        "overhead_target": OVERHEAD,
        "met": speed_up >= SPEED_UP and overhead < OVERHEAD,
    }
    write_merged(args.out, {"environment": environment(), KEY: result})


if __name__ == "__main__":
    main()
