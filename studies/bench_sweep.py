"""Benchmark of the main sliding-beams sweep (Figures 4-5), merged into ``results/bench.json``.

Times the sweep the issue names: both slider kinds, fv3 with 1, 3 and 5 elements per beam,
96 piston positions s/L = 0, 0.01, ..., 0.95, no smearing.  The beams are built once per mesh
(outside the timing, like imports); each position moves the piston, builds its sliders and
runs Newton from the projected abscissae.  Reported beside each time: the mean Newton
iterations and the largest error against the analytic two-beam stiffness.

Run as ``python -m studies.bench_sweep --out results/bench.json``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from sliders.analytic import sliding_beams
from studies.bench import environment, write_merged
from studies.fig4_stiffness import EJ, GA, KINDS, L, STATIONS, SlidingBeams

KEY = "fig4_sweep"


def bench(elements: tuple[int, ...] = (1, 3, 5)) -> dict[str, Any]:
    """Compute time, iterations and worst error of each (kind, elements) sweep."""
    rows, total = [], 0.0
    for kind in KINDS:
        exact = np.array([sliding_beams(s * L, L, EJ, GA, kind)["k_norm"] for s in STATIONS])
        for n in elements:
            model = SlidingBeams("fv3", n, kind)
            k = np.full(len(STATIONS), np.nan)
            start = time.perf_counter()
            for i, s in enumerate(STATIONS):
                try:
                    k[i] = model.stiffness(s)
                except ValueError:
                    model._previous = None
            elapsed = time.perf_counter() - start
            total += elapsed
            rows.append({"slider": kind, "n_elements": n, "positions": len(STATIONS),
                         "seconds": elapsed, "us_per_position": 1e6 * elapsed / len(STATIONS),
                         "mean_newton_iterations": float(np.mean(model.iterations)),
                         "singular_positions": int(np.isnan(k).sum()),
                         "max_abs_rel_error": float(np.nanmax(np.abs(k / exact - 1)))})
            print(f"{kind:9s} n={n}: {elapsed:.2f} s, {rows[-1]['us_per_position']:.0f} us per "
                  f"position, {rows[-1]['mean_newton_iterations']:.2f} iterations, max error "
                  f"{rows[-1]['max_abs_rel_error']:.4f}", flush=True)
    return {"rows": rows, "total_seconds": total, "target_seconds": 0.1}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    args = parser.parse_args(argv)
    result = bench()
    write_merged(args.out, {"environment": environment(), KEY: result})
    print(f"whole sweep {result['total_seconds']:.2f} s (target {result['target_seconds']} s); "
          f"written to {args.out}")


if __name__ == "__main__":
    main()
