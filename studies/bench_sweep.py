"""Benchmark of the main sliding-beams sweep (Figures 4-5), merged into ``results/bench.json``.

Times the sweep the issue names: both slider kinds, fv3 with 1, 3 and 5 elements per beam,
96 piston positions s/L = 0, 0.01, ..., 0.95, no smearing, on the condensed back end.  The
beams are built once per mesh (outside the timing, like imports); the stiffness
factorisation and its cached columns are inside.  Two ways of running the positions:

``continuation``
    :func:`sliders.sweep.sweep`, each position from the secant prediction of the last two
    (the main sweep, whose total is compared with the target);
``cold``
    :meth:`SlidingBeams.stiffness` per position, Newton from the projected abscissae (what
    the Figures 4-5 study does).

Reported beside each time: the mean Newton iterations per converged position, the singular
positions, and the largest error against the analytic two-beam stiffness.  ``--profile N``
prints the N most expensive functions (cProfile, cumulative time) of the main sweep.  An
interruption (Ctrl-C) keeps and writes the rows completed so far, marked ``interrupted``.

Run as ``python -m studies.bench_sweep --out results/bench.json``.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import time
from pathlib import Path
from typing import Any

import numpy as np

from sliders.analytic import sliding_beams
from sliders.sweep import sweep
from studies.bench import environment, write_merged
from studies.fig4_stiffness import EJ, GA, KINDS, L, STATIONS, SlidingBeams, tip_stiffness

KEY = "fig4_sweep"
MODES = ("continuation", "cold")


def run(kind: str, n: int, mode: str) -> tuple[float, np.ndarray, list[int]]:
    """One timed sweep: seconds, ``k_norm`` per station (NaN where singular) and the Newton
    iterations of the converged positions.  Raises ``KeyboardInterrupt`` if interrupted."""
    model = SlidingBeams("fv3", n, kind)
    k = np.full(len(STATIONS), np.nan)
    if mode == "continuation":
        start = time.perf_counter()
        result = sweep(STATIONS, model.problem, progress=False)
        elapsed = time.perf_counter() - start
        if result.interrupted:
            raise KeyboardInterrupt
        solutions = result.solutions
        for i, solution in enumerate(solutions):
            if solution is not None:
                k[i] = tip_stiffness(model._previous, solution)
        return elapsed, k, [s.iterations for s in solutions if s is not None]
    start = time.perf_counter()
    for i, s in enumerate(STATIONS):
        try:
            k[i] = model.stiffness(s)
        except ValueError:
            model._previous = None
    return time.perf_counter() - start, k, model.iterations


def bench(elements: tuple[int, ...] = (1, 3, 5), modes: tuple[str, ...] = MODES,
          progress: bool = True) -> dict[str, Any]:
    """Time, iterations and worst error of each (mode, kind, elements) sweep.

    ``total_seconds`` maps each mode to the sum of its sweeps; ``interrupted`` is set when
    Ctrl-C ended the benchmark (the rows completed so far are kept).
    """
    from tqdm import tqdm

    exact = {kind: np.array([sliding_beams(s * L, L, EJ, GA, kind)["k_norm"]
                             for s in STATIONS]) for kind in KINDS}
    rows, interrupted = [], False
    jobs = [(mode, kind, n) for mode in modes for kind in KINDS for n in elements]
    try:
        for mode, kind, n in tqdm(jobs, disable=None if progress else True, desc="sweeps"):
            elapsed, k, iterations = run(kind, n, mode)
            rows.append({"mode": mode, "slider": kind, "n_elements": n,
                         "positions": len(STATIONS), "seconds": elapsed,
                         "us_per_position": 1e6 * elapsed / len(STATIONS),
                         "mean_newton_iterations": float(np.mean(iterations)),
                         "singular_positions": int(np.isnan(k).sum()),
                         "max_abs_rel_error": float(np.nanmax(np.abs(k / exact[kind] - 1)))})
            row = rows[-1]
            print(f"{mode:12s} {kind:9s} n={n}: {elapsed:.3f} s, {row['us_per_position']:.0f} "
                  f"us per position, {row['mean_newton_iterations']:.2f} iterations, max error "
                  f"{row['max_abs_rel_error']:.4f}", flush=True)
    except KeyboardInterrupt:
        interrupted = True
    total = {mode: sum(r["seconds"] for r in rows if r["mode"] == mode) for mode in modes}
    return {"rows": rows, "total_seconds": total, "target_seconds": 0.1,
            "solver": "condensed", "interrupted": interrupted}


def profile(top: int) -> None:
    """cProfile of the main sweep (continuation, all kinds and meshes), cumulative time."""
    profiler = cProfile.Profile()
    profiler.runcall(bench, modes=("continuation",), progress=False)
    pstats.Stats(profiler).sort_stats("cumulative").print_stats(top)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--profile", type=int, default=0, metavar="N",
                        help="print the N most expensive functions instead of benchmarking")
    args = parser.parse_args(argv)
    if args.profile:
        profile(args.profile)
        return
    result = bench()
    write_merged(args.out, {"environment": environment(), KEY: result})
    totals = ", ".join(f"{mode} {t:.2f} s" for mode, t in result["total_seconds"].items())
    print(f"whole sweep: {totals} (target {result['target_seconds']} s)"
          f"{' (interrupted)' if result['interrupted'] else ''}; written to {args.out}")


if __name__ == "__main__":
    main()
