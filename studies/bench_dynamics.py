"""Wall-clock benchmarks of the dynamics, merged into ``results/bench.json``.

``moving_load``
    The 16-element simply supported beam crossed by a moving force
    (:mod:`studies.moving_load`: ``EJ = m = 1``, ``GA = 1e5``, half the critical speed), 2000
    fixed generalized-alpha steps (``rho_inf = 0.8``) across the crossing, fv3 (lumped mass)
    and galerkin-p2 (consistent mass).  A step is one triangular solve plus the moving load
    vector (``Beam.point_load`` and ``Structure.gather``).  Reported: seconds per step (median
    and minimum of the repeats), steps per second, and beside them the relative max-norm error
    of the mid-span deflection against the closed form
    (:func:`fvbeam.analytic.moving_load_simply_supported`), split into its spatial part (the
    exact semi-discrete solution against the closed form) and its time part (the steps
    against the exact semi-discrete solution), all three on the scale of the closed form's
    largest mid-span deflection (so the parts bound the total).

Run as ``python -m studies.bench_dynamics --out results/bench.json`` (``make bench``).  An
interruption (Ctrl-C) keeps and writes the rows completed so far, marked ``interrupted``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from studies import moving_load as ml
from studies.bench import environment, summary, write_merged

KEY = "moving_load"
ELEMENTS, STEPS, RHO_INF, REPEATS = 16, 2000, 0.8, 3
FORMULATIONS = ("fv3", "galerkin-p2")


def moving_load_bench(formulations: tuple[str, ...] = FORMULATIONS, repeats: int = REPEATS,
                      steps: int = STEPS, progress: bool = True) -> dict[str, Any]:
    """Time per step and errors of each formulation's crossing (module docstring)."""
    from tqdm import tqdm

    rows, interrupted = [], False
    try:
        for formulation in tqdm(formulations, disable=None if progress else True,
                                desc="moving load"):
            m = ml.model(formulation, ELEMENTS)
            seconds = []
            for _ in range(repeats):
                start = time.perf_counter()
                t, w = ml.simulate(m, steps, RHO_INF)
                seconds.append((time.perf_counter() - start) / steps)
            exact, semi = ml.exact_midspan(t), ml.semi_discrete(m, t)
            per_step = summary(seconds)
            rows.append({"formulation": formulation, "mass": ml.MASS[formulation],
                         "n_elements": ELEMENTS, "n_dofs": m.structure.n_dofs,
                         "steps": steps, "rho_inf": RHO_INF, "repeats": repeats,
                         "seconds_per_step": per_step,
                         "steps_per_second": 1.0 / per_step["median"],
                         "rel_error": ml.relative_error(w, exact),
                         "rel_error_space": ml.relative_error(semi, exact),
                         "rel_error_time": ml.relative_error(w, semi, scale=exact)})
            r = rows[-1]
            print(f"{formulation:12s} {1e3 * per_step['median']:.3f} ms/step "
                  f"({r['steps_per_second']:.0f} steps/s), error {r['rel_error']:.2e} "
                  f"(space {r['rel_error_space']:.2e}, time {r['rel_error_time']:.2e})",
                  flush=True)
    except KeyboardInterrupt:
        interrupted = True
    return {"rows": rows, "setup": {"L": ml.L, "EJ": ml.EJ, "GA": ml.GA,
                                    "mass_per_length": ml.M_PER_LENGTH, "F": ml.F,
                                    "speed": ml.SPEED, "crossing_time": ml.CROSSING,
                                    "error": "max_t |w_mid - w_ref| / max_t |w_ref|",
                                    "timer": "time.perf_counter per crossing / steps; "
                                             "median and min over repeats"},
            "interrupted": interrupted}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    args = parser.parse_args(argv)
    result = moving_load_bench()
    write_merged(args.out, {"environment": environment(), KEY: result})
    print(f"written to {args.out}{' (interrupted)' if result['interrupted'] else ''}")


if __name__ == "__main__":
    main()
