"""Benchmarks of the compiled Newton step on every solve path, merged into
``results/bench.json`` (key ``engine``).

``static_solve``
    The sliding beams (paper Figure 4 setup, fv3, 5 elements per beam, both slider kinds,
    the piston at ``s = 0.43 L``) solved again and again on one set-up statics
    (:class:`sliders.solve.statics.SliderStatics`, ``auto``: the compiled condensed loop):
    from the projected start (``cold``: the projection included) and from the last solution
    (``warm``), each with a new load; the error is the tip stiffness's against the two-beam
    solution (:mod:`sliders.sliding_beams.exact`).  The time per solve is the least over
    :data:`BURSTS` bursts of :data:`BURST` solves: a burst lasts about a millisecond, so
    some of them run undisturbed by the machine's other jobs, where the least of a few
    long runs (this benchmark's first form) still carried their slowdown (up to 1.8x here).
``telescope``
    The scene ``studies/scenes/telescope.toml`` (ten fv3 elements, two classical sliders, a
    piston pushed in while a force bends it) run as ``fvslider run`` runs it
    (:func:`sliders.app.run.run` on its :class:`~sliders.app.model.Model`): the time per step
    is the difference of a run to ``t_end`` and one to ``t_end / 4``, divided by their
    difference in steps (model building, compilation loads and the static start cancel).
``moving_load_scaling``
    The moving-load study (:mod:`studies.moving_load`, fv3, 2000 steps across the crossing)
    on 16 to 1024 elements: time per step, its growth with the element count (log-log slope
    between the ends), and the error against the closed form.

Every time is the minimum over ``REPEATS`` runs (the moving load: ``MOVING_LOAD_REPEATS``;
the static solve: its bursts) of the process's CPU time (the machine is
shared: the wall clock is kept beside it).  Run as ``python -m studies.bench_engine --out
results/bench.json`` (``make bench``).
"""

from __future__ import annotations

import argparse
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene, parse_scene
from sliders.sliding_beams.exact import sliding_beams
from sliders.sliding_beams.model import PAPER, SlidingBeams
from sliders.solve.statics import SliderSolution, SliderStatics

from . import moving_load as ml
from .bench import environment, least_time, read_existing, write_merged

KEY = "engine"
REPEATS = 3
#: Runs of the moving load per element count (a run of 16 elements lasts 30-40 ms, so the
#: least of three still carried the machine's other jobs: 44 against 31-33 ms).
MOVING_LOAD_REPEATS = 7
#: The static solve's bursts: :data:`BURSTS` of :data:`BURST` solves each.
BURST, BURSTS = 10, 200


def static_solve(solves: int = BURST, bursts: int = BURSTS) -> list[dict[str, Any]]:
    """Per-solve time of the sliding beams on one set-up statics (module docstring): the
    least over ``bursts`` bursts of ``solves`` solves."""
    rows = []
    s, L = 0.43, PAPER.length
    for kind in ("spherical", "classical"):
        model = SlidingBeams("fv3", 5, kind)
        statics, f = model.problem(s)
        first = statics.solve(f)  # set up: factorisation, compiled loop, columns
        exact = sliding_beams(s * L, L, PAPER.EJ, PAPER.GA, kind)["k_norm"]
        for start in ("cold", "warm"):
            burst = partial(_solves, statics, f, first, start, solves)
            solution, wall, cpu = least_time(burst, bursts)
            k = model.tip_stiffness(statics, solution) * (1.0 + 1e-3 * solves)
            rows.append(
                {
                    "kind": kind,
                    "start": start,
                    "us_per_solve": 1e6 * cpu / solves,
                    "us_per_solve_wall": 1e6 * wall / solves,
                    "timer": f"least of {bursts} bursts of {solves} solves",
                    "iterations": solution.iterations,
                    "rel_error": abs(k - exact) / exact,
                }
            )
            print(
                f"static solve {kind:9s} {start}: {rows[-1]['us_per_solve']:.0f} us per solve "
                f"(CPU), {solution.iterations} iterations, error {rows[-1]['rel_error']:.2e}",
                flush=True,
            )
    return rows


def _solves(
    statics: SliderStatics, f: np.ndarray, last: SliderSolution, start: str, solves: int
) -> SliderSolution:
    """``solves`` solves of ``statics`` under ``f`` scaled by ``1 + 1e-3 i``, ``i = 1 ..
    solves`` (each a new load), from the projected start (``cold``) or from the last
    solution (``warm``; the first from ``last``, the solution under ``f``); the last
    solution."""
    for i in range(1, solves + 1):
        begin = None if start == "cold" else (last.q, last.unknowns)
        last = statics.solve(f * (1.0 + 1e-3 * i), start=begin)
    return last


def telescope() -> dict[str, Any]:
    """Time per step of the telescope scene (module docstring)."""
    scene = load_scene(Path(__file__).parent / "scenes" / "telescope.toml")
    data = scene.model_dump(mode="python", exclude_none=True)
    t_end, step = scene.study.t_end, scene.study.step
    data["study"]["t_end"] = t_end / 4
    short = parse_scene(data)
    result, wall_long, cpu_long = least_time(lambda: run(Model(scene)), REPEATS)
    _, wall_short, cpu_short = least_time(lambda: run(Model(short)), REPEATS)
    steps = round(t_end * 3 / 4 / step)
    row = {
        "steps": steps,
        "us_per_step": 1e6 * (cpu_long - cpu_short) / steps,
        "us_per_step_wall": 1e6 * (wall_long - wall_short) / steps,
        "final_time": result.state.t if result.state is not None else None,
        "error": result.error,
    }
    print(f"telescope: {row['us_per_step']:.0f} us per step (CPU)", flush=True)
    return row


def moving_load_scaling(
    elements: tuple[int, ...] = (16, 64, 256, 1024), steps: int = 2000
) -> dict[str, Any]:
    """Time per step of the moving load against the element count (module docstring)."""
    rows = []
    for n in elements:
        m = ml.model("fv3", n)
        ml.simulate(m, 10)  # set up: the compiled problem, the factorisation
        (t, w), wall, cpu = least_time(lambda m=m: ml.simulate(m, steps), MOVING_LOAD_REPEATS)
        rows.append(
            {
                "n_elements": n,
                "seconds": cpu,
                "us_per_step": 1e6 * cpu / steps,
                "us_per_step_wall": 1e6 * wall / steps,
                "rel_error": ml.relative_error(w, ml.exact_midspan(t)),
            }
        )
        print(
            f"moving load {n:5d} elements: {rows[-1]['seconds'] * 1e3:.1f} ms for {steps} steps "
            f"({rows[-1]['us_per_step']:.1f} us per step, CPU), error {rows[-1]['rel_error']:.2e}",
            flush=True,
        )
    ends = rows[0], rows[-1]
    slope = np.log(ends[1]["us_per_step"] / ends[0]["us_per_step"]) / np.log(
        ends[1]["n_elements"] / ends[0]["n_elements"]
    )
    return {"steps": steps, "rows": rows, "slope": float(slope)}


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks, merge them into ``--out``."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench_engine", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    result = {
        "static_solve": static_solve(),
        "telescope": telescope(),
        "moving_load_scaling": moving_load_scaling(),
        "timer": "process CPU time, least of the repeats; wall clock beside it",
    }
    write_merged(args.out, {"environment": environment(), KEY: result})
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
