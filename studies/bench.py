"""Wall-clock benchmark of the linear-statics pipeline on a straight cantilever, to 1e5 elements.

Run as ``python -m studies.bench --out results/bench.json`` (``make bench``).

For a straight cantilever of length ``L`` clamped at node 0, with ``n`` equal elements of each
formulation (fv3 from 10 to 1e5 elements, fv2, galerkin-p1 and galerkin-p2 from 1e3 to 1e5),
four stages are timed with :func:`time.perf_counter` (and :func:`time.process_time`, the CPU
time of this process, which other work on a shared machine does not inflate):

``assembly``
    ``Beam(straight(...), section, formulation).stiffness`` (mesh and stiffness; a fresh
    beam every repeat, since ``stiffness`` is cached on the beam);
``factorisation``
    ``LinearStatics(beam, [Support(0, "start")])`` (global matrix and ``scipy`` ``splu``);
``solve``
    the first ``statics.solve(f)`` for a tip-ward force at ``xi = 0.7 L``;
``per_load_case``
    ``beam.point_load(xi, ...)`` plus ``statics.solve(f)`` for a batch of further load
    positions on the cached factorisation, reported per case.

Every timing comes with the accuracy of the answer it produced: the relative error of the tip
deflection against the closed-form Timoshenko cantilever
(:func:`fvbeam.closed_forms.cantilever_exact`).  Per formulation, the log-log slope of
assembly + factorisation + first solve against ``n`` from 1e3 to 1e5 elements (least squares
over the sizes, of the medians) says how the pipeline scales: 1 is linear.  The section and
length are the values of the paper's Sec. 6 (``EA = 1e9``, ``GA = 1.1e8``, ``GJ = 3e4``,
``EJ = 4.1e4``, ``L = 0.6``).

The results are merged into the output JSON: top-level keys written by other benchmarks are
kept, the keys written here (:data:`KEYS`) are replaced.
"""

from __future__ import annotations

import argparse
import datetime as dt
import gc
import json
import math
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from fvbeam import Beam, LinearStatics, Section, Support, straight
from fvbeam.closed_forms import cantilever_exact
from fvbeam.io import write_atomic

T = TypeVar("T")

#: Section of the paper's Sec. 6.
SECTION = dict(EA=1e9, GAy=1.1e8, GAz=1.1e8, GJ=3e4, EJy=4.1e4, EJz=4.1e4)
#: Cantilever length of the paper's Sec. 6.
LENGTH = 0.6
#: Load station of the accuracy check, as a fraction of the length.
XI_FRACTION = 0.7
#: Transverse tip-ward force (global y): bending about z (EJz) and shear along y (GAy).
FORCE = (0.0, 1.0, 0.0)
#: Load positions of the per-load-case batch, as fractions of the length.
BATCH_FRACTIONS = tuple(np.round(np.linspace(0.05, 1.0, 20), 10))

#: n_elements: repeats, per formulation (fv3's rows are :data:`RESULT_KEY`'s).
FULL_SIZES = {
    "fv3": {10: 5, 100: 5, 1000: 5, 10000: 3, 100000: 3},
    "fv2": {1000: 3, 10000: 3, 100000: 2},
    "galerkin-p1": {1000: 3, 10000: 3, 100000: 2},
    "galerkin-p2": {1000: 3, 10000: 3, 100000: 2},
}
QUICK_SIZES = {"fv3": {10: 1, 100: 1}, "fv2": {10: 1, 100: 1}}
#: The slope is fitted from this many elements on (over all sizes when fewer than two reach it).
SLOPE_FROM = 1000
#: The stages of one solve from scratch, whose sum the slope is fitted to.
PIPELINE = ("assembly", "factorisation", "solve")

RESULT_KEY = "fv3_cantilever"
OTHERS_KEY = "cantilever_formulations"
SCALING_KEY = "cantilever_scaling"
SETUP_KEY = "fv3_cantilever_setup"
KEYS = ("environment", RESULT_KEY, OTHERS_KEY, SCALING_KEY, SETUP_KEY)


# -- the problem ------------------------------------------------------------------------------
def make_section() -> Section:
    """The paper's Sec. 6 section (uncoupled)."""
    return Section.diagonal(**SECTION)


def build_beam(n_elements: int, section: Section, formulation: str = "fv3") -> Beam:
    """Straight beam along x of length :data:`LENGTH` with its stiffness assembled.

    Parameters
    ----------
    n_elements
        Number of elements (2-node for fv2 and galerkin-p1, 3-node otherwise).
    section
        Section properties.
    formulation
        A formulation name (:data:`fvbeam.FORMULATIONS`).

    Returns
    -------
    Beam
        The beam; ``beam.stiffness`` is already computed (and cached).
    """
    npe = 2 if formulation in ("fv2", "galerkin-p1") else 3
    mesh = straight((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), n_elements, npe)
    beam = Beam(mesh, section, formulation)
    _ = beam.stiffness  # assembled here, outside the timed solves
    return beam


def exact_tip_deflection(xi: float) -> float:
    """Closed-form tip deflection for a unit force at ``xi`` (Timoshenko cantilever).

    Parameters
    ----------
    xi
        Load station, ``0 <= xi <= LENGTH``.

    Returns
    -------
    float
        ``xi^2 (3 L - xi) / (6 EJz) + xi / GAy``.
    """
    flexural, shear, _ = cantilever_exact(xi, LENGTH, SECTION["EJz"], SECTION["GAy"])
    return float(flexural + shear)


def relative_tip_error(beam: Beam, q: np.ndarray, xi: float) -> float:
    """``|v_tip - v_exact| / |v_exact|`` for the solution ``q`` of a unit load at ``xi``."""
    v = float(beam.displacements(q, LENGTH)[0, 1])
    exact = exact_tip_deflection(xi)
    return abs(v - exact) / abs(exact)


# -- timing -----------------------------------------------------------------------------------
def timed(fn: Callable[[], T], cpu: dict[str, float], stage: str) -> tuple[float, T]:
    """Run ``fn()`` once; return (elapsed seconds, its result), and put its CPU seconds in
    ``cpu[stage]``."""
    start, start_cpu = time.perf_counter(), time.process_time()
    result = fn()
    cpu[stage] = time.process_time() - start_cpu
    return time.perf_counter() - start, result


def least_time(
    call: Callable[[], T], repeats: int = 1, long_run: float = math.inf
) -> tuple[T, float, float]:
    """``call()``'s last result and its least wall-clock and CPU seconds over ``repeats``
    calls (the runs least slowed by other jobs on the machine); once a call has taken more
    than ``long_run`` CPU seconds, no more."""
    wall, cpu = math.inf, math.inf
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        result = call()
        wall, cpu = min(wall, time.perf_counter() - w), min(cpu, time.process_time() - c)
        if cpu > long_run:
            break
    return result, wall, cpu


def run_once(n_elements: int, section: Section, formulation: str = "fv3") -> dict[str, float]:
    """One repeat of the four stages for ``n_elements``; times and errors.

    Returns
    -------
    dict
        ``assembly``, ``factorisation``, ``solve``, ``per_load_case`` (seconds; their CPU
        seconds as ``cpu_<stage>``), ``rel_error`` (first solve, load at
        ``XI_FRACTION * L``), ``batch_max_rel_error`` and ``batch_worst_xi`` (over the
        per-load-case batch).
    """
    xi = XI_FRACTION * LENGTH
    gc.collect()
    cpu: dict[str, float] = {}
    t_assembly, beam = timed(lambda: build_beam(n_elements, section, formulation), cpu, "assembly")
    t_factor, statics = timed(
        lambda: LinearStatics(beam, [Support(0, "start")]), cpu, "factorisation"
    )
    f = beam.point_load(xi, force=FORCE)
    t_solve, q = timed(lambda: statics.solve(f), cpu, "solve")

    batch = [s * LENGTH for s in BATCH_FRACTIONS]

    def load_cases() -> list[np.ndarray]:
        return [statics.solve(beam.point_load(x, force=FORCE)) for x in batch]

    t_batch, solutions = timed(load_cases, cpu, "per_load_case")
    batch_errors = [relative_tip_error(beam, qb, x) for qb, x in zip(solutions, batch, strict=True)]
    worst = int(np.argmax(batch_errors))
    return {
        "assembly": t_assembly,
        "factorisation": t_factor,
        "solve": t_solve,
        "per_load_case": t_batch / len(batch),
        **{f"cpu_{stage}": seconds for stage, seconds in cpu.items()},
        "cpu_per_load_case": cpu["per_load_case"] / len(batch),
        "rel_error": relative_tip_error(beam, q, xi),
        "batch_max_rel_error": batch_errors[worst],
        "batch_worst_xi": batch[worst],
        "n_dofs": beam.n_dofs,
    }


def summary(samples: Sequence[float]) -> dict[str, float]:
    """Median and minimum of timing samples (seconds)."""
    return {"median": float(np.median(samples)), "min": float(np.min(samples))}


def bench_size(
    n_elements: int, repeats: int, section: Section, formulation: str = "fv3"
) -> dict[str, Any]:
    """All repeats for one mesh size, summarised as one JSON row."""
    runs = [run_once(n_elements, section, formulation) for _ in range(repeats)]
    row: dict[str, Any] = {
        "formulation": formulation,
        "n_elements": n_elements,
        "n_dofs": runs[0]["n_dofs"],
        "repeats": repeats,
    }
    for stage in ("assembly", "factorisation", "solve", "per_load_case"):
        row[f"{stage}_s"] = summary([r[stage] for r in runs])
        row[f"{stage}_cpu_s"] = summary([r[f"cpu_{stage}"] for r in runs])
    for key, prefix in (("pipeline_s", ""), ("pipeline_cpu_s", "cpu_")):
        row[key] = summary([sum(r[f"{prefix}{stage}"] for stage in PIPELINE) for r in runs])
    row["n_load_cases"] = len(BATCH_FRACTIONS)
    # The answers are deterministic; the worst over the repeats guards against surprises.
    row[f"rel_error_xi_{XI_FRACTION}"] = max(r["rel_error"] for r in runs)
    row["per_load_case_max_rel_error"] = max(r["batch_max_rel_error"] for r in runs)
    row["per_load_case_worst_xi"] = runs[0]["batch_worst_xi"]
    return row


def loglog_slope(rows: Sequence[dict[str, Any]], key: str) -> float | None:
    """Least-squares slope of ``log(row[key]["median"])`` against ``log(n_elements)`` over
    the rows from :data:`SLOPE_FROM` elements on (all rows when fewer than two reach it);
    None for a single row."""
    chosen = [r for r in rows if r["n_elements"] >= SLOPE_FROM]
    chosen = chosen if len(chosen) >= 2 else list(rows)
    if len(chosen) < 2:
        return None
    n = np.log([r["n_elements"] for r in chosen])
    t = np.log([r[key]["median"] for r in chosen])
    return float(np.polyfit(n, t, 1)[0])


def scaling(formulation: str, rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The scaling summary of one formulation's rows: the slopes (wall and CPU) of the
    pipeline and of each stage, and the largest mesh's pipeline time beside its errors."""
    largest = max(rows, key=lambda r: r["n_elements"])
    return {
        "formulation": formulation,
        "n_elements": [r["n_elements"] for r in rows],
        "slope_from": SLOPE_FROM,
        "pipeline_slope": loglog_slope(rows, "pipeline_s"),
        "pipeline_cpu_slope": loglog_slope(rows, "pipeline_cpu_s"),
        **{f"{stage}_slope": loglog_slope(rows, f"{stage}_s") for stage in PIPELINE},
        "largest_n_elements": largest["n_elements"],
        "largest_pipeline_s": largest["pipeline_s"],
        "largest_pipeline_cpu_s": largest["pipeline_cpu_s"],
        f"largest_rel_error_xi_{XI_FRACTION}": largest[f"rel_error_xi_{XI_FRACTION}"],
        "largest_per_load_case_max_rel_error": largest["per_load_case_max_rel_error"],
    }


# -- environment and output -------------------------------------------------------------------
def _git_commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            capture_output=True,
            text=True,
            cwd=Path(__file__).resolve().parent,
            timeout=10,
            check=True,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() or None


def environment() -> dict[str, Any]:
    """Python and library versions, core counts, machine and date (UTC)."""
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        usable = os.cpu_count()
    return {
        "python": sys.version.split()[0],
        "implementation": platform.python_implementation(),
        "numpy": metadata.version("numpy"),
        "scipy": metadata.version("scipy"),
        "scikit-fem": metadata.version("scikit-fem"),
        "cpu_count": os.cpu_count(),
        "usable_cores": usable,
        "machine": platform.machine(),
        "platform": platform.platform(),
        "git_commit": _git_commit(),
        "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
    }


def setup_description(sizes: dict[str, dict[int, int]]) -> dict[str, Any]:
    """The problem definition stored next to the results."""
    return {
        "formulations": list(sizes),
        "length": LENGTH,
        "section": SECTION,
        "section_source": "paper Sec. 6",
        "support": "clamp at node 0",
        "force": list(FORCE),
        "accuracy_xi": XI_FRACTION * LENGTH,
        "accuracy_xi_over_L": XI_FRACTION,
        "batch_xi_over_L": [float(s) for s in BATCH_FRACTIONS],
        "exact": "cantilever_exact: F (xi^2 (3L - xi) / (6 EJz) + xi / GAy)",
        "repeats": {f: {str(n): r for n, r in s.items()} for f, s in sizes.items()},
        "timer": "time.perf_counter (wall) and time.process_time (*_cpu_s); median and min "
        "over repeats; one untimed warm-up run at n = 10 per formulation first",
        "assembly_includes": "straight() mesh + Beam() + beam.stiffness",
        "factorisation_includes": "LinearStatics(): global matrix, free-motion check, "
        "SparseLU (free dofs in the structure's RCM order, SuperLU)",
        "pipeline": "assembly + factorisation + first solve; slope: least squares of "
        f"log(median) against log(n) from n = {SLOPE_FROM}",
    }


def read_existing(path: Path) -> dict[str, Any]:
    """The JSON object already in ``path``, or ``{}`` when there is no such file.

    Raises ``ValueError`` if the file exists but is not a JSON object, rather than
    overwriting what another benchmark wrote.
    """
    if not path.exists():
        return {}
    try:
        data = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise ValueError(
            f"{path} exists but is not valid JSON ({exc}); move it away or fix it"
        ) from exc
    if not isinstance(data, dict):
        raise ValueError(f"{path} holds a JSON {type(data).__name__}, not an object")
    return data


def bench_arguments(
    module: str, doc: str, quick: str, argv: list[str] | None
) -> argparse.Namespace:
    """The arguments of a benchmark module ``module`` (``python -m studies.NAME``, described
    by the first line of its ``doc``): ``--out`` (its JSON, checked mergeable before any time
    is spent) and ``--quick`` (helped by ``quick``)."""
    parser = argparse.ArgumentParser(prog=f"python -m {module}", description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick)
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    args = parser.parse_args(argv)
    read_existing(args.out)
    return args


def write_merged(path: Path, sections: dict[str, Any]) -> dict[str, Any]:
    """Replace ``sections``' keys in the JSON object at ``path``, keeping the others; atomic."""
    data = read_existing(path)
    data.update(sections)
    write_atomic(path, lambda tmp: tmp.write_text(json.dumps(data, indent=2) + "\n"))
    return data


def format_table(rows: Sequence[dict[str, Any]]) -> str:
    """Human-readable table: median (min) seconds per stage and the relative errors."""
    err = f"rel_error_xi_{XI_FRACTION}"
    head = (
        f"{'form':>11} {'n_el':>6} {'dofs':>7} {'rep':>3} | {'assembly s':>19} | "
        f"{'factorisation s':>19} | {'first solve s':>19} | {'per load case s':>19} | "
        f"{'err xi=0.7L':>11} {'batch max err':>13}"
    )

    def cell(stat: dict[str, float]) -> str:
        return f"{stat['median']:9.3g} ({stat['min']:7.3g})"

    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(
            f"{r['formulation']:>11} {r['n_elements']:>6} {r['n_dofs']:>7} {r['repeats']:>3} | "
            f"{cell(r['assembly_s'])} | {cell(r['factorisation_s'])} | "
            f"{cell(r['solve_s'])} | {cell(r['per_load_case_s'])} | "
            f"{r[err]:11.2e} {r['per_load_case_max_rel_error']:13.2e}"
        )
    lines.append("times: median (min) over repeats; errors: relative tip deflection vs closed form")
    return "\n".join(lines)


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/bench.json"),
        help="JSON file to create or merge into (default: %(default)s)",
    )
    parser.add_argument(
        "--quick", action="store_true", help="smoke test: fv3 and fv2, n = 10 and 100, one repeat"
    )
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print the table, merge the results into ``--out``.

    Returns
    -------
    dict
        The whole JSON object written.
    """
    args = parse_args(argv)
    sizes = QUICK_SIZES if args.quick else FULL_SIZES
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    section = make_section()
    start = time.perf_counter()
    rows: dict[str, list[dict[str, Any]]] = {}
    for formulation, per_size in sizes.items():
        # warm-up: first-call costs (imports, compiled kernels) stay out of the timings
        run_once(10, section, formulation)
        rows[formulation] = []
        for n, repeats in per_size.items():
            t0 = time.perf_counter()
            rows[formulation].append(bench_size(n, repeats, section, formulation))
            print(
                f"{formulation} n = {n}: {repeats} repeat(s) in {time.perf_counter() - t0:.1f} s",
                flush=True,
            )
    setup = setup_description(sizes) | {"wall_time_s": round(time.perf_counter() - start, 2)}
    summaries = {f: scaling(f, r) for f, r in rows.items()}
    others = [row for f, r in rows.items() if f != "fv3" for row in r]
    data = write_merged(
        args.out,
        {
            "environment": environment(),
            RESULT_KEY: rows["fv3"],
            OTHERS_KEY: others,
            SCALING_KEY: summaries,
            SETUP_KEY: setup,
        },
    )
    print()
    print(format_table([row for r in rows.values() for row in r]))
    for f, summary_row in summaries.items():
        slope = summary_row["pipeline_slope"]
        print(
            f"{f}: assembly + factorisation + solve at n = {summary_row['largest_n_elements']}: "
            f"{summary_row['largest_pipeline_s']['median']:.3g} s wall, "
            f"{summary_row['largest_pipeline_cpu_s']['median']:.3g} s CPU; log-log slope "
            f"{'-' if slope is None else f'{slope:.2f}'} (CPU "
            f"{summary_row['pipeline_cpu_slope'] or float('nan'):.2f}); tip error "
            f"{summary_row[f'largest_rel_error_xi_{XI_FRACTION}']:.2e}"
        )
    print(f"\nwritten to {args.out} ({setup['wall_time_s']} s)")
    return data


if __name__ == "__main__":
    main()
