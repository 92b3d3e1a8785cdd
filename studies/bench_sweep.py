"""Benchmark of the main sliding-beams sweep (Figures 4-5), merged into ``results/bench.json``.

Times the main sweep: both slider kinds, fv3 with 1, 3 and 5 elements per beam,
96 piston positions s/L = 0, 0.01, ..., 0.95, no smearing, on the condensed back end.  Three
ways of running the positions:

``batched`` (the main sweep, whose total is compared with the 0.1 s target)
    :meth:`SlidingBeams.solve`, what the Figures 4-5 study runs: all 96 positions of a sweep
    at once, each from its projected abscissae, as translations of one template problem
    (:func:`sliders.solve.statics.solve_translated`).  ``seconds`` is that call: building the 96
    positions' joint batches from the template and the shifts, the projections, every joint
    evaluation and every Newton step.  Not in it: imports, the beams, and the template
    (``setup_seconds``: the piston at s = 0, the stiffness assembled by scikit-fem and the
    condensed operator factorised with its dense inverse, and the sliders' template batches,
    once per mesh and kind), and the tip stiffness read from each solution afterwards.
    Run :data:`REPEATS` times, each pass on models built anew: the row of a sweep is its
    fastest pass (the run least slowed by other jobs on the shared cores), with the median
    and every pass beside it; ``main_sweep`` also gives each whole pass's CPU time.
``continuation``
    :func:`sliders.solve.sweep.sweep`, each position from the secant prediction of the last two
    (the general path: run :data:`REPEATS` times like ``batched``, each row its fastest pass),
    each position's statics moved from the last.  Its setup, apart like the batched
    template's (``setup_seconds``): the first position's statics (the stiffness assembled,
    the condensed operator factorised) and its compiled Newton loop (the joints packed);
``cold``
    :meth:`SlidingBeams.stiffness` per position, Newton from the projected abscissae.
    These two build every position's statics (:meth:`SlidingBeams.problem`) inside the time.
``scene``
    The scene ``studies/scenes/fig4_sliding_beams.toml`` with the same meshes, slider kinds
    and stations, run as ``fvslider run`` runs a sweep (:func:`sliders.app.run.run` on its
    :class:`~sliders.app.model.Model`: every position's statics built from the scene, solved
    in continuation).  ``seconds`` is the run; ``setup_seconds`` building the model (which
    checks every position's sliders on their lines).

The compiled kernels (numba) are compiled, or loaded from their cache, before any timing
(:func:`warm_up`, ``warmup_seconds``: :func:`sliders.sliding_beams.model.compile_kernels` and
two positions of each kind through the general path), like the imports the timing leaves
out.
Reported beside each time: the microseconds per position, the mean Newton iterations per
converged position, the singular positions, and the largest error against the analytic
two-beam stiffness; times are wall clock (``seconds``) and this process's CPU time
(``cpu_seconds``: less inflated than the wall clock by other jobs on the cores).
``main_sweep`` sums the batched rows (with and without the setup); ``general_path`` sums the
continuation rows, the same 576 positions through the general path (its target:
0.1 s).
``--profile N`` prints the N most expensive functions (cProfile, cumulative time) of the
main sweep.  An interruption (Ctrl-C) keeps and writes the rows completed so far, marked
``interrupted``.  Run with ``OPENBLAS_NUM_THREADS=1`` (``docs/sliders.md``, "Cost").

Run as ``python -m studies.bench_sweep --out results/bench.json``.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
from pathlib import Path
from typing import Any

import numpy as np

from sliders.app.model import Model
from sliders.app.run import Results
from sliders.app.run import run as run_scene
from sliders.app.scene import load_scene, parse_scene
from sliders.sliding_beams.exact import sliding_beams
from sliders.sliding_beams.model import KINDS, SlidingBeams, compile_kernels
from sliders.solve.sweep import sweep

from .bench import environment, least_time, write_merged
from .fig4_stiffness import EJ, GA, STATIONS, L

#: The scene's tip force (``[[load]]`` of :data:`SCENE`).
SETUP_FORCE = 1.0

KEY = "fig4_sweep"
#: The Figures 4-5 sweep as a scene (the ``scene`` mode).
SCENE = Path(__file__).parent / "scenes" / "fig4_sliding_beams.toml"
#: The per-position modes (the default of :func:`bench`); ``main`` runs ``batched`` first.
MODES = ("continuation", "cold", "scene")
ALL_MODES = ("batched",) + MODES
#: The modes whose sweeps are run ``repeats`` times, each row its fastest pass.
REPEATED = ("batched", "continuation")
#: Passes of the batched sweeps in ``main`` (the machine's other jobs slow some of them).
REPEATS = 7


def run(kind: str, n: int, mode: str) -> tuple[float, float, float | None, np.ndarray, list[int]]:
    """One timed sweep: wall-clock and CPU seconds, the untimed setup seconds (batched mode:
    the template; else None), ``k_norm`` per station (NaN where singular) and the Newton
    iterations of the converged positions.  Raises ``KeyboardInterrupt`` if interrupted."""
    model = SlidingBeams("fv3", n, kind)
    k = np.full(len(STATIONS), np.nan)
    if mode == "batched":
        (statics, _), setup, _ = least_time(lambda: model.template)
        outcomes, elapsed, cpu = least_time(lambda: model.solve(STATIONS))
        solved = [(i, o) for i, o in enumerate(outcomes) if not isinstance(o, str)]
        for i, solution in solved:
            k[i] = model.tip_stiffness(statics, solution)
        return elapsed, cpu, setup, k, [o.iterations for _, o in solved]
    if mode == "continuation":
        # the setup, as the batched template's: the first position's statics (stiffness
        # assembled, condensed operator factorised) and its compiled loop (the joints packed)
        _, setup, _ = least_time(lambda: model.problem(float(STATIONS[0]))[0].compiled)
        result, elapsed, cpu = least_time(lambda: sweep(STATIONS, model.problem, progress=False))
        if result.interrupted:
            raise KeyboardInterrupt
        solutions = result.solutions
        for i, solution in enumerate(solutions):
            if solution is not None:
                k[i] = model.tip_stiffness(model._previous, solution)
        return elapsed, cpu, setup, k, [s.iterations for s in solutions if s is not None]
    if mode == "scene":
        return scene(kind, n, k)
    _, elapsed, cpu = least_time(lambda: cold(model, k))
    return elapsed, cpu, None, k, model.iterations


def scene(kind: str, n: int, k: np.ndarray) -> tuple[float, float, float, np.ndarray, list[int]]:
    """The ``scene`` mode (module docstring): :data:`SCENE` with ``n`` elements per beam,
    sliders of ``kind``, a piston position per station, no output tables."""
    data = load_scene(SCENE).model_dump(mode="python", exclude_none=True)
    for beam in data["beam"]:
        beam["straight"]["elements"] = n
    for slider in data["slider"]:
        slider["kind"] = kind
    data["study"]["range"] = None
    data["study"]["values"] = tuple(float(s * L) for s in STATIONS)
    data["output"] = {}
    spec = parse_scene(data)
    model, setup, _ = least_time(lambda: Model(spec))
    result, elapsed, cpu = least_time(lambda: run_scene(model, progress=False))
    assert isinstance(result, Results)  # a sweep
    if result.interrupted:
        raise KeyboardInterrupt
    iterations = []
    for i, sample in enumerate(result.samples):
        if sample.solution is not None and sample.statics is not None:
            structure = sample.statics.structure
            tip = structure.beams[1].displacements(structure.local(1, sample.solution.q), L)
            k[i] = SETUP_FORCE / tip[0, 1] * L**3 / EJ
            iterations.append(sample.solution.iterations)
    return elapsed, cpu, setup, k, iterations


def cold(model: SlidingBeams, k: np.ndarray) -> None:
    """Every station's ``k_norm`` into ``k``, one cold solve each (NaN where singular)."""
    for i, s in enumerate(STATIONS):
        try:
            k[i] = model.stiffness(s)
        except ValueError:
            model._previous = None


def bench(
    elements: tuple[int, ...] = (1, 3, 5),
    modes: tuple[str, ...] = MODES,
    progress: bool = True,
    repeats: int = 1,
) -> dict[str, Any]:
    """Time, iterations and worst error of each (mode, kind, elements) sweep.

    ``repeats``: passes of the ``batched`` and ``continuation`` sweeps (the main sweep and
    the general path; each on models built anew, the batched setup untimed); such a row
    keeps the smallest time of its passes (``seconds``, ``cpu_seconds``: the run least
    disturbed by other jobs on the machine) and the median and every pass's CPU time
    beside it.  ``total_seconds`` maps each mode to the sum of its
    rows; ``interrupted`` is set when Ctrl-C ended the benchmark (the rows completed so far
    are kept).
    """
    from tqdm import tqdm

    exact = {
        kind: np.array([sliding_beams(s * L, L, EJ, GA, kind)["k_norm"] for s in STATIONS])
        for kind in KINDS
    }
    rows, interrupted = [], False
    _, warmup, _ = least_time(warm_up)
    jobs = [
        (mode, kind, n)
        for mode in modes
        for _ in range(repeats if mode in REPEATED else 1)
        for kind in KINDS
        for n in elements
    ]
    try:
        for mode, kind, n in tqdm(jobs, disable=None if progress else True, desc="sweeps"):
            elapsed, cpu, setup, k, iterations = run(kind, n, mode)
            rows.append(
                {
                    "mode": mode,
                    "slider": kind,
                    "n_elements": n,
                    "positions": len(STATIONS),
                    "seconds": elapsed,
                    "cpu_seconds": cpu,
                    "setup_seconds": setup,
                    "us_per_position": 1e6 * elapsed / len(STATIONS),
                    "mean_newton_iterations": float(np.mean(iterations)),
                    "singular_positions": int(np.isnan(k).sum()),
                    "max_abs_rel_error": float(np.nanmax(np.abs(k / exact[kind] - 1))),
                }
            )
            row = rows[-1]
            print(
                f"{mode:12s} {kind:9s} n={n}: {elapsed:.3f} s, {row['us_per_position']:.0f} "
                f"us per position, {row['mean_newton_iterations']:.2f} iterations, max error "
                f"{row['max_abs_rel_error']:.4f}",
                flush=True,
            )
    except KeyboardInterrupt:
        interrupted = True
    per_pass = len(KINDS) * len(elements)
    passes = _passes([r for r in rows if r["mode"] == "batched"], per_pass)
    general = _passes([r for r in rows if r["mode"] == "continuation"], per_pass)
    rows = (
        _fastest(passes)
        + (_fastest(general) if general else [])
        + [r for r in rows if r["mode"] not in REPEATED]
    )
    total = {mode: sum(r["seconds"] for r in rows if r["mode"] == mode) for mode in modes}
    return {
        "rows": rows,
        "total_seconds": total,
        "main_sweep": main_sweep(rows, passes),
        "general_path": general_path(rows),
        "warmup_seconds": warmup,
        "target_seconds": 0.1,
        "solver": "condensed",
        "interrupted": interrupted,
    }


def warm_up() -> None:
    """Compile the kernels of every timed path, or load them from their cache: the batched
    template's (:func:`compile_kernels`) and the general path's (two positions of each kind
    through :func:`sliders.solve.sweep.sweep` and one cold solve)."""
    compile_kernels()
    for kind in KINDS:
        model = SlidingBeams("fv3", 1, kind)
        sweep(STATIONS[:2], model.problem, progress=False)
        model.stiffness(float(STATIONS[2]))


def general_path(rows: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The continuation rows summed: the main sweep's positions through the general path
    (each position's statics built, Newton from the secant prediction); None without them."""
    mine = [r for r in rows if r["mode"] == "continuation"]
    if not mine:
        return None
    seconds, positions = sum(r["seconds"] for r in mine), sum(r["positions"] for r in mine)
    setup = sum(r["setup_seconds"] for r in mine)
    return {
        "seconds": seconds,
        "cpu_seconds": sum(r["cpu_seconds"] for r in mine),
        "setup_seconds": setup,
        "with_setup_seconds": seconds + setup,
        "positions": positions,
        "us_per_position": 1e6 * seconds / positions,
        "cpu_us_per_position": 1e6 * sum(r["cpu_seconds"] for r in mine) / positions,
        "timed": "sliders.solve.sweep.sweep: each position's statics built (moved from the "
        "last), the compiled Newton loop from the secant prediction; not imports, kernel "
        "compilation, nor the setup (setup_seconds, as the batched template's: the first "
        "position's statics, its stiffness assembled and factorised, and its compiled loop)",
    }


def _passes(rows: list[dict[str, Any]], per_pass: int) -> list[list[dict[str, Any]]]:
    """One mode's rows cut into complete passes (an interrupted pass is dropped)."""
    return [rows[i : i + per_pass] for i in range(0, len(rows) - per_pass + 1, per_pass)]


def _fastest(passes: list[list[dict[str, Any]]]) -> list[dict[str, Any]]:
    """Per sweep, its row of the pass with the least CPU time, with the median and every
    pass's CPU time."""
    out = []
    for same in zip(*passes, strict=True):
        cpu = [r["cpu_seconds"] for r in same]
        out.append(
            dict(
                min(same, key=lambda r: r["cpu_seconds"]),
                cpu_seconds_median=float(np.median(cpu)),
                cpu_seconds_passes=cpu,
            )
        )
    return out


def main_sweep(
    rows: list[dict[str, Any]], passes: list[list[dict[str, Any]]]
) -> dict[str, Any] | None:
    """The batched rows summed (module docstring): wall-clock and CPU seconds (each sweep's
    fastest pass), untimed setup, positions, microseconds per position (wall clock) and
    mean Newton iterations; beside them, the CPU time of each whole pass and its smallest
    and median.  None without batched rows."""
    batched = [r for r in rows if r["mode"] == "batched"]
    if not batched:
        return None
    seconds = sum(r["seconds"] for r in batched)
    setup = sum(r["setup_seconds"] for r in batched)
    positions = sum(r["positions"] for r in batched)
    whole = [sum(r["cpu_seconds"] for r in p) for p in passes]
    return {
        "seconds": seconds,
        "cpu_seconds": sum(r["cpu_seconds"] for r in batched),
        "pass_cpu_seconds": whole,
        "pass_cpu_seconds_min": min(whole),
        "pass_cpu_seconds_median": float(np.median(whole)),
        "setup_seconds": setup,
        "with_setup_seconds": seconds + setup,
        "positions": positions,
        "us_per_position": 1e6 * seconds / positions,
        "mean_newton_iterations": float(np.mean([r["mean_newton_iterations"] for r in batched])),
        "timed": "per-position batches from the template, projections, joint "
        "evaluations, Newton steps; not imports, kernel compilation, beams, "
        "template setup",
    }


def profile(top: int) -> None:
    """cProfile of the main sweep (batched, all kinds and meshes), cumulative time."""
    profiler = cProfile.Profile()
    profiler.runcall(bench, modes=ALL_MODES[:1], progress=False)
    pstats.Stats(profiler).sort_stats("cumulative").print_stats(top)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument(
        "--profile",
        type=int,
        default=0,
        metavar="N",
        help="print the N most expensive functions instead of benchmarking",
    )
    args = parser.parse_args(argv)
    if args.profile:
        profile(args.profile)
        return
    result = bench(modes=ALL_MODES, repeats=REPEATS)
    write_merged(args.out, {"environment": environment(), KEY: result})
    totals = ", ".join(f"{mode} {t:.3f} s" for mode, t in result["total_seconds"].items())
    main = result["main_sweep"]
    if main is not None:
        print(
            f"main sweep (batched): {main['seconds']:.3f} s (CPU {main['cpu_seconds']:.3f} s; "
            f"whole passes {main['pass_cpu_seconds_min']:.3f} s fastest, "
            f"{main['pass_cpu_seconds_median']:.3f} s median of {REPEATS}), "
            f"{main['us_per_position']:.0f} us per position, "
            f"{main['mean_newton_iterations']:.2f} Newton iterations (target "
            f"{result['target_seconds']} s; setup apart {main['setup_seconds']:.3f} s)"
        )
    general = result["general_path"]
    if general is not None:
        print(
            f"main sweep (general path): {general['seconds']:.3f} s "
            f"(CPU {general['cpu_seconds']:.3f} s), {general['cpu_us_per_position']:.0f} us "
            f"CPU per position (target {result['target_seconds']} s; setup apart "
            f"{general['setup_seconds']:.3f} s)"
        )
    print(
        f"whole sweep: {totals}{' (interrupted)' if result['interrupted'] else ''}; "
        f"written to {args.out}"
    )


if __name__ == "__main__":
    main()
