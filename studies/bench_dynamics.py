"""Benchmarks of time integration with sliders, merged into ``results/bench.json``.

``fig2_dynamics``: the Figure 2 scene (:mod:`studies.fig2_smearing`: one fv3 element, a body
pushed across the evaluation point ``b`` in 100 first-mode periods, ``zeta = 2 %``, step
``T_1 / 40``) at smearing 0 and 1 %.  Timed with :func:`time.perf_counter` around
:meth:`sliders.dynamics.Dynamics.run` (the static start and the step operator's build are
inside; building the model is not).  Reported per level: seconds, steps, time per step, steps
per second, mean Newton iterations per step, and beside them the errors of the end state
against the static closed forms (:func:`studies.fig2_smearing.static_shear_and_tip`: shear at
``b`` and tip displacement, the damped transient's remainder included).  ``--quick`` runs the
10-period crossing instead.  Ctrl-C writes the levels completed, marked ``interrupted``.

Run as ``python -m studies.bench_dynamics --out results/bench.json`` (``make bench``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from studies import fig2_smearing as fig2
from studies.bench import environment, read_existing, write_merged

FIG2_KEY = "fig2_dynamics"
FIG2_LEVELS = (0.0, 0.01)


def fig2_dynamics(variant: str = "damped", levels: tuple[float, ...] = FIG2_LEVELS,
                  steps_per_period: int = fig2.STEPS_PER_PERIOD) -> dict[str, Any]:
    """Time the Figure 2 scene's ``variant`` (a key of :data:`studies.fig2_smearing.VARIANTS`)
    at each smearing level; one row per level.  Ctrl-C returns the rows completed, with
    ``interrupted`` set."""
    spec = fig2.VARIANTS[variant]
    result: dict[str, Any] = {"scene": "studies/fig2_smearing.py", "variant": variant,
                              "zeta": spec.zeta, "periods": spec.periods,
                              "steps_per_period": steps_per_period, "rho_inf": fig2.RHO_INF,
                              "method": "condensed", "rows": [], "interrupted": False}
    for level in levels:
        crossing = fig2.Crossing(level, spec.zeta, spec.periods)
        try:
            start = time.perf_counter()
            run = crossing.run(steps_per_period)
            seconds = time.perf_counter() - start
        except KeyboardInterrupt:
            result["interrupted"] = True
            break
        steps = len(run["t"]) - 1
        shear, tip = fig2.static_shear_and_tip(float(run["xi"][-1]), level)
        result["rows"].append({
            "smearing": level, "seconds": seconds, "steps": steps,
            "seconds_per_step": seconds / steps, "steps_per_second": steps / seconds,
            "mean_iterations": float(run["iterations"][1:].mean()),
            "overshoot": fig2.overshoot(run),
            "end_shear_error": abs(float(run["shear"][-1]) - shear),
            "end_tip_error": abs(float(run["tip"][-1]) - tip)})
        row = result["rows"][-1]
        print(f"fig2 smearing {100 * level:g} %: {steps} steps in {seconds:.1f} s "
              f"({1e3 * row['seconds_per_step']:.2f} ms/step, {row['steps_per_second']:.0f} "
              f"steps/s); end errors V(b) {row['end_shear_error']:.1e}, v(L) "
              f"{row['end_tip_error']:.1e}", flush=True)
    return result


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks, merge them into ``--out``."""
    parser = argparse.ArgumentParser(prog="python -m studies.bench_dynamics",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--quick", action="store_true", help="the 10-period crossing")
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    result = fig2_dynamics("fast" if args.quick else "damped")
    write_merged(args.out, {"environment": environment(), FIG2_KEY: result})
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
