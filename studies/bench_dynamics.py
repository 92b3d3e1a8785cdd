"""Benchmarks of time integration, merged into ``results/bench.json``.

``moving_load``
    The 16-element simply supported beam crossed by a moving force
    (:mod:`studies.moving_load`: ``EJ = m = 1``, ``GA = 1e5``, half the critical speed), 2000
    fixed generalized-alpha steps (``rho_inf = 0.8``) across the crossing, fv3 (lumped mass)
    and galerkin-p2 (consistent mass).  A step is one triangular solve plus the moving load
    vector (``Beam.point_load`` and ``Structure.gather``).  Reported: seconds per step (median
    and minimum of the repeats), steps per second, and beside them the relative max-norm error
    of the mid-span deflection against the closed form
    (:func:`fvbeam.closed_forms.moving_load_simply_supported`), split into its spatial part (the
    exact semi-discrete solution against the closed form) and its time part (the steps
    against the exact semi-discrete solution), all three on the scale of the closed form's
    largest mid-span deflection (so the parts bound the total).
``fig2_dynamics``
    The Figure 2 scene (:mod:`studies.fig2_smearing`: one fv3 element, a body pushed across
    the evaluation point ``b`` in 100 first-mode periods, ``zeta = 2 %``, step ``T_1 / 40``)
    at smearing 0 and 1 %.  Timed: :meth:`studies.fig2_smearing.Crossing.run` (the static
    start, the step operator's build and the study's recording inside; building the model
    is not), and the same steps without a recorder (``bare``); each the least of
    :data:`FIG2_REPEATS` runs on models built anew, after one untimed run (the compiled
    kernels loaded from their cache), in wall-clock (:func:`time.perf_counter`) and the
    process's CPU seconds (:func:`time.process_time`, less inflated by other jobs on the
    shared cores).  Reported per level: seconds, steps, time per step, steps per second,
    mean Newton iterations per step, and beside them the errors of the end state against the
    static closed forms (:func:`studies.fig2_smearing.static_shear_and_tip`: shear at ``b``
    and tip displacement, the damped transient's remainder included).  ``whole_study``: the
    whole Figure 2 study as ``make demo`` runs it (:func:`studies.fig2_smearing.reproduce`:
    three variants x five smearing levels, CSVs and PNGs into a temporary directory), once.
    ``--quick`` runs the 10-period crossing instead, and no whole study.

Run as ``python -m studies.bench_dynamics --out results/bench.json`` (``make bench``).  Ctrl-C
keeps and writes the rows completed so far, marked ``interrupted``.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

from . import fig2_smearing as fig2
from . import moving_load as ml
from .bench import environment, least_time, read_existing, summary, write_merged

KEY = "moving_load"
ELEMENTS, STEPS, RHO_INF, REPEATS = 16, 2000, 0.8, 3
FORMULATIONS = ("fv3", "galerkin-p2")


def moving_load_bench(
    formulations: tuple[str, ...] = FORMULATIONS,
    repeats: int = REPEATS,
    steps: int = STEPS,
    progress: bool = True,
) -> dict[str, Any]:
    """Time per step and errors of each formulation's crossing (module docstring)."""
    from tqdm import tqdm

    rows, interrupted = [], False
    try:
        for formulation in tqdm(
            formulations, disable=None if progress else True, desc="moving load"
        ):
            m = ml.model(formulation, ELEMENTS)
            seconds = []
            for _ in range(repeats):
                start = time.perf_counter()
                t, w = ml.simulate(m, steps, RHO_INF)
                seconds.append((time.perf_counter() - start) / steps)
            exact, semi = ml.exact_midspan(t), ml.semi_discrete(m, t)
            per_step = summary(seconds)
            rows.append(
                {
                    "formulation": formulation,
                    "mass": ml.MASS[formulation],
                    "n_elements": ELEMENTS,
                    "n_dofs": m.structure.n_dofs,
                    "steps": steps,
                    "rho_inf": RHO_INF,
                    "repeats": repeats,
                    "seconds_per_step": per_step,
                    "steps_per_second": 1.0 / per_step["median"],
                    "rel_error": ml.relative_error(w, exact),
                    "rel_error_space": ml.relative_error(semi, exact),
                    "rel_error_time": ml.relative_error(w, semi, scale=exact),
                }
            )
            r = rows[-1]
            print(
                f"{formulation:12s} {1e3 * per_step['median']:.3f} ms/step "
                f"({r['steps_per_second']:.0f} steps/s), error {r['rel_error']:.2e} "
                f"(space {r['rel_error_space']:.2e}, time {r['rel_error_time']:.2e})",
                flush=True,
            )
    except KeyboardInterrupt:
        interrupted = True
    return {
        "rows": rows,
        "setup": {
            "L": ml.L,
            "EJ": ml.EJ,
            "GA": ml.GA,
            "mass_per_length": ml.M_PER_LENGTH,
            "F": ml.F,
            "speed": ml.SPEED,
            "crossing_time": ml.CROSSING,
            "error": "max_t |w_mid - w_ref| / max_t |w_ref|",
            "timer": "time.perf_counter per crossing / steps; median and min over repeats",
        },
        "interrupted": interrupted,
    }


FIG2_KEY = "fig2_dynamics"
FIG2_LEVELS = (0.0, 0.01)
FIG2_REPEATS = 7


def bare_run(crossing: fig2.Crossing, steps_per_period: int) -> None:
    """The crossing's steps without a recorder (what the recording costs is left out)."""
    d = crossing.dynamics
    d.run(d.static_state(), crossing.t_end, crossing.period / steps_per_period, progress=False)


def whole_study() -> dict[str, Any]:
    """Wall and CPU seconds of :func:`studies.fig2_smearing.reproduce` (every variant and
    level, CSVs and PNGs written into a temporary directory)."""
    with tempfile.TemporaryDirectory() as out:
        _, wall, cpu = least_time(lambda: fig2.reproduce(Path(out), progress=False))
    return {
        "variants": list(fig2.VARIANTS),
        "levels": list(fig2.LEVELS),
        "seconds": wall,
        "cpu_seconds": cpu,
        "timed": "fig2_smearing.reproduce: models, integration, recording, CSVs, PNGs",
    }


def fig2_dynamics(
    variant: str = "damped",
    levels: tuple[float, ...] = FIG2_LEVELS,
    steps_per_period: int = fig2.STEPS_PER_PERIOD,
) -> dict[str, Any]:
    """Time the Figure 2 scene's ``variant`` (a key of :data:`studies.fig2_smearing.VARIANTS`)
    at each smearing level; one row per level.  Ctrl-C returns the rows completed, with
    ``interrupted`` set."""
    spec = fig2.VARIANTS[variant]
    result: dict[str, Any] = {
        "scene": "studies/fig2_smearing.py",
        "variant": variant,
        "zeta": spec.zeta,
        "periods": spec.periods,
        "steps_per_period": steps_per_period,
        "rho_inf": fig2.RHO_INF,
        "method": "condensed",
        "rows": [],
        "interrupted": False,
    }

    def crossing(level: float) -> fig2.Crossing:
        return fig2.Crossing(level, spec.zeta, spec.periods)

    for level in levels:
        try:
            crossing(level).run(steps_per_period)  # untimed: the kernels loaded
            run, seconds, cpu = least_time(
                lambda level=level: crossing(level).run(steps_per_period), FIG2_REPEATS
            )
            _, bare, bare_cpu = least_time(
                lambda level=level: bare_run(crossing(level), steps_per_period), FIG2_REPEATS
            )
        except KeyboardInterrupt:
            result["interrupted"] = True
            break
        steps = len(run["t"]) - 1
        shear, tip = fig2.static_shear_and_tip(float(run["xi"][-1]), level)
        result["rows"].append(
            {
                "smearing": level,
                "seconds": seconds,
                "cpu_seconds": cpu,
                "steps": steps,
                "seconds_per_step": seconds / steps,
                "cpu_seconds_per_step": cpu / steps,
                "bare_seconds_per_step": bare / steps,
                "bare_cpu_seconds_per_step": bare_cpu / steps,
                "steps_per_second": steps / seconds,
                "mean_iterations": float(run["iterations"][1:].mean()),
                "overshoot": fig2.overshoot(run),
                "end_shear_error": abs(float(run["shear"][-1]) - shear),
                "end_tip_error": abs(float(run["tip"][-1]) - tip),
            }
        )
        row = result["rows"][-1]
        print(
            f"fig2 smearing {100 * level:g} %: {steps} steps in {seconds:.2f} s "
            f"({1e6 * row['cpu_seconds_per_step']:.0f} us/step CPU, "
            f"{1e6 * row['bare_cpu_seconds_per_step']:.0f} without recording); "
            f"end errors V(b) {row['end_shear_error']:.1e}, v(L) "
            f"{row['end_tip_error']:.1e}",
            flush=True,
        )
    return result


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks, merge them into ``--out``."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench_dynamics", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--quick", action="store_true", help="Figure 2: the 10-period crossing")
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    moving = moving_load_bench()
    write_merged(args.out, {"environment": environment(), KEY: moving})
    if not moving["interrupted"]:
        result = fig2_dynamics("fast" if args.quick else "damped")
        if not (args.quick or result["interrupted"]):
            result["whole_study"] = study = whole_study()
            print(
                f"the whole Figure 2 study: {study['seconds']:.1f} s "
                f"({study['cpu_seconds']:.1f} s CPU)",
                flush=True,
            )
        write_merged(args.out, {FIG2_KEY: result})
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
