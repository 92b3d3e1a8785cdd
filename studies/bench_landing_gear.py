"""Benchmark of the landing-gear drop, merged into ``results/bench.json``.

``landing_gear``
    The ``fv3-5`` model of the Figure 7 study (:mod:`sliders.gear.model`: classical sliders,
    0.3 s from touchdown) at fixed steps from 0.8 ms down, each against a reference run at
    ``REFERENCE`` (its peaks' relative errors: the peak loads of :data:`LOADS`, the spin-up
    time), and the largest of them, the *bench step*, whose peak loads are within 1 % of the
    reference: there it is timed (``time.perf_counter`` around
    :meth:`sliders.solve.dynamics.Dynamics.run`, recorder included; the model's build, its
    mode and its touchdown state apart, as ``setup_s``), median and minimum of the repeats
    against its target of 1 s.  Then the mesh: ``fv3-1`` to ``fv3-20`` at the bench
    step against ``fv3-20``.

Run as ``python -m studies.bench_landing_gear --out results/bench.json`` (``make bench``;
``--quick``: 0.05 s, two steps, one repeat).  Ctrl-C keeps and writes what was measured,
marked ``interrupted``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from sliders.gear.model import GearModel
from sliders.gear.outputs import GearRun

from .bench import environment, read_existing, summary, write_merged

KEY = "landing_gear"
MODEL = "fv3-5"
#: The target for the 0.3 s run of ``fv3-5`` [s].
TARGET = 1.0
#: The peak loads that the bench step must converge to 1 %, and the events reported beside.
LOADS = (
    "ground_vertical",
    "ground_longitudinal",
    "attachment_longitudinal_spin_up",
    "spring_back",
    "top_slider",
    "bottom_slider",
)
EVENTS = ("stroke", "spin_up_time", "spring_back_frequency")
STEPS = (8e-4, 4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5)
REFERENCE = 1.25e-5
MESHES = ("fv3-1", "fv3-3", "fv3-5", "fv3-10", "fv3-20")


def errors(run: GearRun, reference: dict[str, Any]) -> dict[str, float]:
    """Relative errors of ``run``'s peaks and events against ``reference``'s."""
    ours = run.summary()
    return {name: abs(float(ours[name]) / float(reference[name]) - 1) for name in LOADS + EVENTS}


def bench(t_end: float = 0.3, steps=STEPS, reference=REFERENCE, meshes=MESHES, repeats: int = 3):
    """The benchmark's JSON section (module docstring)."""
    result: dict[str, Any] = {
        "model": MODEL,
        "slider": "classical",
        "t_end": t_end,
        "target_s": TARGET,
        "reference_step": reference,
        "interrupted": False,
    }
    try:
        clock = time.perf_counter()
        model = GearModel(MODEL)
        model.touchdown()
        result["setup_s"] = time.perf_counter() - clock
        truth = model.simulate(t_end, reference).summary()
        result["convergence"] = []
        for h in steps:
            run = model.simulate(t_end, h)
            found = errors(run, truth)
            result["convergence"].append(
                {
                    "step": h,
                    "seconds": run.seconds,
                    "iterations": float(run.iterations[1:].mean()),
                    "rel_errors": found,
                    "max_load_error": max(found[n] for n in LOADS),
                }
            )
        good = [row for row in result["convergence"] if row["max_load_error"] <= 0.01]
        step = max(row["step"] for row in good) if good else min(steps)
        times = [model.simulate(t_end, step).seconds for _ in range(repeats)]
        result["bench"] = {
            "step": step,
            "steps": round(t_end / step),
            "seconds": summary(times),
            "seconds_per_step": summary([t / round(t_end / step) for t in times]),
            "max_load_error": next(
                r["max_load_error"] for r in result["convergence"] if r["step"] == step
            ),
            "within_target": min(times) <= TARGET,
        }
        finest = GearModel(meshes[-1]).simulate(t_end, step).summary()
        result["mesh"] = [
            {"model": name, **errors(GearModel(name).simulate(t_end, step), finest)}
            for name in meshes[:-1]
        ]
    except KeyboardInterrupt:
        result["interrupted"] = True
    return result


def main(argv: list[str] | None = None) -> None:
    """Run the benchmark, merge it into ``--out``."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench_landing_gear", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--quick", action="store_true", help="0.05 s, two steps, one repeat")
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    if args.quick:
        result = bench(0.05, (4e-4, 2e-4), 1e-4, ("fv3-1", "fv3-3"), 1)
    else:
        result = bench()
    write_merged(args.out, {"environment": environment(), KEY: result})
    for row in result.get("convergence", []):
        print(
            f"h = {row['step']:.3g} s: {row['seconds']:.2f} s, largest peak-load error "
            f"{row['max_load_error']:.2e}"
        )
    if "bench" in result:
        b = result["bench"]
        print(
            f"{MODEL}, {result['t_end']} s at h = {b['step']:.3g} s: {b['seconds']['min']:.2f} s "
            f"(median {b['seconds']['median']:.2f}; target {TARGET} s), peak loads within "
            f"{b['max_load_error']:.1e}; setup {result['setup_s']:.2f} s"
        )
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
