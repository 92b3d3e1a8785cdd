"""Work-precision: run time against error, one Pareto front per formulation.

Three studies, each a grid of runs; every run gives one row (:data:`COLUMNS`):

``statics``
    The sliding-beams tip stiffness (:mod:`studies.fig4_stiffness`, the paper's Sec. 6 setup)
    at the stations ``s / L = 0, 0.01, ..., 0.95``, both slider kinds, over element counts.
    Error: the largest ``|k / k_exact - 1|`` over the stations against the analytic two-beam
    solution (:func:`sliders.sliding_beams.exact.sliding_beams`).  Timed: the sweep, from the
    beams' meshes to the stiffness at every station (assembly, factorisation, Newton).
``moving_load``
    A force crossing a simply supported beam (:class:`studies.moving_load.Problem`: ``L = 1``,
    ``EJ = 1e4``, mass 10 per length, ``F = 100`` at half the critical speed), two sections
    (:data:`CASES`): the Euler-Bernoulli limit (``EJ / (GA L^2) = 1e-5``, the verification
    scene's slenderness: at far larger ``GA`` the P2 semi-discrete error stops falling under
    refinement before the accuracy levels studied) and a shear-flexible one (``1e-3``, the
    paper's Sec. 6 slenderness).  Over meshes x steps per
    crossing x ``rho_inf``, fixed generalized-alpha steps from rest to 1.5 crossing times.
    Error: ``max_t |w(L/2, t) - w_exact| / max_t |w_exact|`` over every step's time, against
    :func:`fvbeam.closed_forms.moving_load_simply_supported` (the crossing *and* the free
    vibration after it).  The force is applied as users apply it
    (:data:`studies.moving_load.LOADINGS`): ``point_load`` (its load vector rebuilt every
    step) on the whole grid, and ``slider`` (a massless body driven along the beam by a
    spherical slider) on a smaller one.  Timed: :func:`studies.moving_load.simulate`
    (assembly, factorisation of the step operator, every step), on a model (mesh, section,
    beam, supports) built before the timing, as the peer builds its items before its.
``fig2``
    The Figure 2 scene (:mod:`studies.fig2_smearing`, damped, 100 periods) per smearing
    level over steps per period, on the paper's fv3 element and, at smearing 0, on one cubic
    element (:func:`fig2_levels`).  Error: the end tip displacement's distance from its static
    closed form (:func:`studies.fig2_smearing.static_tip`), beside (fv3) the overshoot of
    the shear at the evaluation point.  Timed: :meth:`studies.fig2_smearing.Crossing.run`.

Timing: wall (:func:`time.perf_counter`) and CPU (:func:`time.process_time`) of the timed
part only, each the minimum over the repeats, a fresh model every repeat; the fronts and the
tables use the CPU time (:data:`TIME`).  Run as a module, the study restarts itself with
``OPENBLAS_NUM_THREADS=1`` if that is not set.  A peer's rows
(:mod:`studies.peer_moving_load`, same columns, ``DIR/peer_moving_load.csv``) are drawn beside
the moving-load fronts when present.

Run as ``python -m studies.work_precision --out DIR [--quick] [--docs docs/performance.md]``;
writes ``DIR/work_precision.csv``, ``DIR/work_precision_{statics,moving_load,fig2}.png`` and
``DIR/work_precision.md`` (the tables of the cheapest run per accuracy level, which
``--docs`` also puts between the markers of that file).  ``--quick`` runs a small grid in
seconds (the test suite's smoke test); ``--replot`` redraws and retabulates an existing CSV
(after the peer's study has written its rows beside it).  Ctrl-C writes the rows computed so
far.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from fvbeam.io import write_atomic
from sliders.sliding_beams.exact import sliding_beams

from . import fig2_smearing as fig2
from . import fig4_stiffness as fig4
from . import moving_load as ml
from .bench import least_time

#: The formulations compared; a new element joins the study by its name here.
FORMULATIONS: tuple[str, ...] = ("fv2", "fv3", "galerkin-p1", "galerkin-p2", "cubic")
#: The moving-load sections (module docstring).
CASES = {
    "euler-bernoulli": ml.Problem(L=1.0, EJ=1e4, GA=1e9, m=10.0, F=100.0, alpha=0.5),
    "shear-flexible": ml.Problem(L=1.0, EJ=1e4, GA=1e7, m=10.0, F=100.0, alpha=0.5),
}
#: The window of the moving-load error, in crossing times.
WINDOW = 1.5
#: Truncation of the closed form, relative to the static mid-span deflection.
REFERENCE_RTOL = 1e-8
COLUMNS = (
    "study",
    "case",
    "formulation",
    "loading",
    "n_elements",
    "steps",
    "rho_inf",
    "smearing",
    "wall_seconds",
    "cpu_seconds",
    "error",
    "overshoot",
)
#: Accuracy levels of the summary tables.
LEVELS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
PEER_CSV = "peer_moving_load.csv"
#: The run time the fronts and tables use: CPU seconds, since on the shared 2-core machine
#: the wall time also counts the waits for other jobs (one BLAS thread: no parallel work).
TIME = "cpu_seconds"
MARKERS = ("<!-- work-precision:begin -->", "<!-- work-precision:end -->")


@dataclass(frozen=True)
class Grid:
    """The runs of a study: element counts, steps, ``rho_inf``, repeats per row; ``fine``
    adds single ``(formulation, elements, steps, rho_inf)`` moving-load runs beyond the
    grid (the accurate end of a front)."""

    formulations: tuple[str, ...]
    statics_kinds: tuple[str, ...]
    statics_elements: tuple[int, ...]
    cases: tuple[str, ...]
    moving_elements: tuple[int, ...]
    moving_steps: tuple[int, ...]
    rho_infs: tuple[float, ...]
    fine: tuple[tuple[str, int, int, float], ...]
    slider_formulations: tuple[str, ...]
    slider_elements: tuple[int, ...]
    slider_steps: tuple[int, ...]
    fig2_formulations: tuple[str, ...]
    fig2_levels: tuple[float, ...]
    fig2_steps_per_period: tuple[int, ...]
    fig2_variant: str
    repeats: int


#: The moving-load runs beyond the grid, ``(elements, steps, rho_inf)``: the accurate end of
#: the fronts (to errors of 1e-5 and below), for the two most accurate formulations and for
#: the peer alike (:mod:`studies.peer_moving_load`).
FINE_RUNS: tuple[tuple[int, int, float], ...] = (
    (16, 3200, 0.8),
    (32, 3200, 0.8),
    (32, 3200, 1.0),
    (64, 1600, 0.8),
    (64, 3200, 0.8),
    (32, 6400, 0.8),
    (32, 6400, 1.0),
    (64, 6400, 0.8),
)
FULL = Grid(
    formulations=FORMULATIONS,
    statics_kinds=("spherical", "classical"),
    statics_elements=(1, 2, 3, 5, 10, 20, 40),
    cases=tuple(CASES),
    moving_elements=(4, 8, 16, 32),
    moving_steps=(50, 100, 200, 400, 800, 1600),
    rho_infs=(1.0, 0.8, 0.5),
    fine=tuple((f, *run) for f in ("galerkin-p2", "cubic") for run in FINE_RUNS),
    slider_formulations=("fv3", "galerkin-p2", "cubic"),
    slider_elements=(4, 8, 16),
    slider_steps=(50, 100, 200, 400),
    fig2_formulations=tuple(fig2.FORMULATIONS),
    fig2_levels=fig2.LEVELS,
    fig2_steps_per_period=(10, 20, 40),
    fig2_variant="damped",
    repeats=2,
)
QUICK = Grid(
    formulations=("fv3", "galerkin-p2", "cubic"),
    statics_kinds=("spherical",),
    statics_elements=(1, 3, 5),
    cases=("euler-bernoulli",),
    moving_elements=(4, 8, 16),
    moving_steps=(800,),
    rho_infs=(0.8,),
    fine=(),
    slider_formulations=(),
    slider_elements=(),
    slider_steps=(),
    fig2_formulations=tuple(fig2.FORMULATIONS),
    fig2_levels=(0.0, 0.01),
    fig2_steps_per_period=(40,),
    fig2_variant="fast",
    repeats=1,
)


#: CPU seconds of a run beyond which it is not repeated (its timing noise is small already).
LONG_RUN = 1.0


def row(**values: Any) -> dict[str, Any]:
    """A row of :data:`COLUMNS`, the ones not given empty."""
    unknown = set(values) - set(COLUMNS)
    if unknown:
        raise ValueError(f"unknown columns {sorted(unknown)}")
    return {column: values.get(column, "") for column in COLUMNS}


def step_times(problem: ml.Problem, steps: int) -> np.ndarray:
    """The times of ``steps`` steps per crossing over the :data:`WINDOW`."""
    return problem.crossing / steps * np.arange(round(WINDOW * steps) + 1)


def moving_load_row(
    case: str,
    formulation: str,
    loading: str,
    n: int,
    steps: int,
    rho_inf: float,
    times: tuple[float, float],
    error: float,
) -> dict[str, Any]:
    """A moving-load row; ``times`` are the wall and CPU seconds."""
    return row(
        study="moving_load",
        case=case,
        formulation=formulation,
        loading=loading,
        n_elements=n,
        steps=steps,
        rho_inf=rho_inf,
        wall_seconds=times[0],
        cpu_seconds=times[1],
        error=error,
    )


class Study:
    """The runs of a :class:`Grid`, with the references each needs computed once."""

    def __init__(self, grid: Grid) -> None:
        self.grid = grid
        self._exact_stiffness: dict[str, np.ndarray] = {}
        self._exact_midspan: dict[tuple[str, int], np.ndarray] = {}

    def jobs(self) -> list[tuple[str, dict[str, Any]]]:
        """Every run as ``(study, parameters)``, the long moving-load grid last."""
        g = self.grid
        out: list[tuple[str, dict[str, Any]]] = [
            ("statics", dict(kind=k, formulation=f, n=n))
            for k in g.statics_kinds
            for f in g.formulations
            for n in g.statics_elements
        ]
        out += [
            ("fig2", dict(formulation=f, level=level, steps_per_period=s))
            for f in g.fig2_formulations
            for level in fig2_levels(g, f)
            for s in g.fig2_steps_per_period
        ]
        out += [
            ("moving_load", dict(case=c, formulation=f, n=n, steps=s, rho_inf=r, loading=lo))
            for c in g.cases
            for lo, forms, meshes, steps, rhos in (
                ("point_load", g.formulations, g.moving_elements, g.moving_steps, g.rho_infs),
                ("slider", g.slider_formulations, g.slider_elements, g.slider_steps, (0.8,)),
            )
            for f in forms
            for n in meshes
            for s in steps
            for r in rhos
            if lo == "point_load" or c == "euler-bernoulli"
        ]
        out += [
            (
                "moving_load",
                dict(case=c, formulation=f, n=n, steps=s, rho_inf=r, loading="point_load"),
            )
            for c in g.cases
            for f, n, s, r in g.fine
        ]
        return out

    def run(self, study: str, p: dict[str, Any]) -> dict[str, Any]:
        """One row."""
        return {"statics": self.statics, "moving_load": self.moving_load, "fig2": self.fig2}[study](
            **p
        )

    def statics(self, kind: str, formulation: str, n: int) -> dict[str, Any]:
        if kind not in self._exact_stiffness:
            self._exact_stiffness[kind] = np.array(
                [
                    sliding_beams(s * fig4.L, fig4.L, fig4.EJ, fig4.GA, kind)["k_norm"]
                    for s in fig4.STATIONS
                ]
            )
        (k, _), wall, cpu = least_time(
            lambda: fig4.sweep(kind, formulation, n, 0.0), self.grid.repeats, LONG_RUN
        )
        error = np.abs(k / self._exact_stiffness[kind] - 1)
        return row(
            study="statics",
            case=kind,
            formulation=formulation,
            n_elements=n,
            wall_seconds=wall,
            cpu_seconds=cpu,
            error=float(np.max(error)) if np.all(np.isfinite(error)) else math.inf,
        )

    def exact_midspan(self, case: str, steps: int) -> np.ndarray:
        """The closed form at the step times of ``steps`` steps per crossing."""
        if (case, steps) not in self._exact_midspan:
            problem = CASES[case]
            t = step_times(problem, steps)
            self._exact_midspan[case, steps] = problem.exact_midspan(t, REFERENCE_RTOL)
        return self._exact_midspan[case, steps]

    def moving_load(
        self, case: str, formulation: str, n: int, steps: int, rho_inf: float, loading: str
    ) -> dict[str, Any]:
        problem = CASES[case]
        exact = self.exact_midspan(case, steps)
        t_end = WINDOW * problem.crossing
        wall, cpu, w = math.inf, math.inf, np.empty(0)
        for _ in range(self.grid.repeats):
            m = ml.model(formulation, n, problem=problem)  # untimed, like the peer's items
            w, once_wall, once_cpu = least_time(
                lambda m=m: ml.simulate(m, steps, rho_inf, t_end, loading)[1], 1
            )
            wall, cpu = min(wall, once_wall), min(cpu, once_cpu)
            if once_cpu > LONG_RUN:
                break
        error = ml.relative_error(w, exact)
        return moving_load_row(case, formulation, loading, n, steps, rho_inf, (wall, cpu), error)

    def fig2(self, formulation: str, level: float, steps_per_period: int) -> dict[str, Any]:
        variant = fig2.VARIANTS[self.grid.fig2_variant]
        wall, cpu, run = math.inf, math.inf, {}
        for _ in range(self.grid.repeats):
            crossing = fig2.Crossing(level, variant.zeta, variant.periods, name=formulation)
            run, w, c = least_time(lambda crossing=crossing: crossing.run(steps_per_period))
            wall, cpu = min(wall, w), min(cpu, c)
        tip = fig2.static_tip(float(run["xi"][-1]), level, formulation)
        return row(
            study="fig2",
            case=self.grid.fig2_variant,
            formulation=formulation,
            loading="slider",
            n_elements=1,
            steps=steps_per_period,
            rho_inf=fig2.RHO_INF,
            smearing=level,
            wall_seconds=wall,
            cpu_seconds=cpu,
            error=abs(float(run["tip"][-1]) - tip),
            overshoot=fig2.overshoot(run) if formulation == "fv3" else "",
        )


def fig2_levels(grid: Grid, formulation: str) -> tuple[float, ...]:
    """The smearing levels of the Figure 2 scene on ``formulation``: the grid's on fv3;
    0 on the cubic element, whose load vector is smooth in the load's abscissa (no
    evaluation point to smear across, :data:`studies.fig2_smearing.FORMULATIONS`)."""
    return grid.fig2_levels if formulation == "fv3" else (0.0,)


def compute(grid: Grid, progress: bool = True) -> tuple[list[dict[str, Any]], bool]:
    """Every row of ``grid`` and whether Ctrl-C stopped it (then the rows done so far).  The
    first run of each kind of job (study, formulation, loading, slider kind) runs once more,
    untimed, before it: the first call of a compiled kernel in a process loads it from its
    cache or compiles it, which would otherwise be timed with that row."""
    from tqdm import tqdm

    study = Study(grid)
    rows: list[dict[str, Any]] = []
    warm: set[tuple[Any, ...]] = set()
    bar = tqdm(study.jobs(), desc="work-precision", unit="run", disable=None if progress else True)
    try:
        for name, parameters in bar:
            kind = (name, *(parameters.get(k) for k in ("formulation", "loading", "kind")))
            if kind not in warm:  # untimed: the kind's compiled kernels loaded or compiled
                warm.add(kind)
                study.run(name, parameters)
            rows.append(study.run(name, parameters))
    except KeyboardInterrupt:
        bar.close()
        return rows, True
    return rows, False


# -- reading the rows ----------------------------------------------------------------------
def _number(value: Any) -> float:
    return math.nan if value in ("", None) else float(value)


def pareto(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows that no other row beats in both run time (:data:`TIME`) and error, by time."""
    front: list[dict[str, Any]] = []
    for r in sorted(rows, key=lambda r: (_number(r[TIME]), _number(r["error"]))):
        if not front or _number(r["error"]) < _number(front[-1]["error"]):
            front.append(r)
    return front


def series(r: dict[str, Any]) -> str:
    """The front a row belongs to: its formulation, and its loading unless a point load."""
    label = str(r["formulation"])
    if r["study"] == "moving_load" and r["loading"] not in ("point_load", ""):
        label += f" ({r['loading']})"
    if r["study"] == "fig2":
        label = f"{label}, smearing {100 * _number(r['smearing']):g} %"
    return label


def is_peer(r: dict[str, Any]) -> bool:
    """A row of the peer's study (:mod:`studies.peer_moving_load`)."""
    return str(r["formulation"]).startswith("exudyn")


def settings(r: dict[str, Any]) -> str:
    """A row's mesh and steps, as words."""
    if r["study"] == "statics":
        return f"{r['n_elements']} el."
    if r["study"] == "fig2":
        return f"{r['steps']} steps/period"
    return f"{r['n_elements']} el., {r['steps']} steps/crossing, rho_inf {r['rho_inf']}"


def groups(rows: Sequence[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault((str(r["study"]), str(r["case"])), []).append(r)
    return out


def cheapest(rows: Sequence[dict[str, Any]], level: float) -> dict[str, Any] | None:
    """The fastest row (:data:`TIME`) whose error is at most ``level``."""
    within = [r for r in rows if _number(r["error"]) <= level]
    return min(within, key=lambda r: _number(r[TIME])) if within else None


def markdown(rows: Sequence[dict[str, Any]]) -> str:
    """Per study and case, per accuracy level: the cheapest run overall (CPU and wall
    seconds), each front's cheapest run (CPU seconds) and, beside a peer, the ratio of our
    cheapest run's time to the peer's; for the Figure 2 scene each level's runs."""
    lines = []
    for (study, case), members in groups(rows).items():
        lines += ["", f"**{study}, {case}**", ""]
        if study == "fig2":
            lines += [
                "| formulation | smearing | steps per period | wall s | CPU s | end error "
                "| overshoot |",
                "|---|---|---|---|---|---|---|",
            ]
            for r in sorted(
                members,
                key=lambda r: (str(r["formulation"]), _number(r["smearing"]), int(r["steps"])),
            ):
                overshoot = _number(r["overshoot"])
                lines.append(
                    f"| {r['formulation']} | {100 * _number(r['smearing']):g} % | {r['steps']} | "
                    f"{_number(r['wall_seconds']):.3g} | {_number(r['cpu_seconds']):.3g} | "
                    f"{_number(r['error']):.2e} | "
                    f"{'-' if math.isnan(overshoot) else f'{overshoot:.3g}'} |"
                )
            continue
        fronts = sorted({series(r) for r in members})
        ours = [r for r in members if not is_peer(r)]
        peers = [r for r in members if is_peer(r)]
        ratio = ["ours / peer"] if peers and ours else []
        lines += [
            "| error <= | cheapest | "
            + " | ".join([f"{f} [CPU s]" for f in fronts] + ratio)
            + " |",
            "|---|---|" + "---|" * (len(fronts) + len(ratio)),
        ]
        for level in LEVELS:
            best = cheapest(members, level)
            if best is None:
                continue
            cells = []
            for name in fronts:
                r = cheapest([m for m in members if series(m) == name], level)
                cells.append("-" if r is None else f"{_number(r[TIME]):.3g}")
            if ratio:
                mine, theirs = cheapest(ours, level), cheapest(peers, level)
                cells.append(
                    f"{_number(mine[TIME]) / _number(theirs[TIME]):.2g}"
                    if mine is not None and theirs is not None
                    else "-"
                )
            lines.append(
                f"| {level:.0e} | {series(best)}, {settings(best)}: "
                f"{_number(best['cpu_seconds']):.3g} s CPU, "
                f"{_number(best['wall_seconds']):.3g} s wall | " + " | ".join(cells) + " |"
            )
    return "\n".join(lines).lstrip("\n") + "\n"


# -- writing -------------------------------------------------------------------------------
def write_csv(rows: Sequence[dict[str, Any]], path: Path) -> None:
    """The rows, :data:`COLUMNS`, floats at full precision."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, COLUMNS)
            writer.writeheader()
            for r in rows:
                writer.writerow({k: repr(v) if isinstance(v, float) else v for k, v in r.items()})

    write_atomic(path, write)


def read_csv(path: Path) -> list[dict[str, Any]]:
    """Rows written by :func:`write_csv` (or the peer's study); ``ValueError`` naming the
    file if its columns are not :data:`COLUMNS`."""
    with open(path, newline="") as handle:
        reader = csv.DictReader(handle)
        if tuple(reader.fieldnames or ()) != COLUMNS:
            raise ValueError(f"{path}: columns {reader.fieldnames}, expected {list(COLUMNS)}")
        return list(reader)


def update_docs(path: Path, table: str) -> None:
    """Put ``table`` between the :data:`MARKERS` of ``path`` (written atomically)."""
    text = path.read_text()
    begin, end = MARKERS
    if text.count(begin) != 1 or text.count(end) != 1:
        raise ValueError(f"{path}: needs one {begin} and one {end}")
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    new = f"{head}{begin}\n{table}{end}{tail}"
    write_atomic(path, lambda tmp: tmp.write_text(new))


def plot(rows: Sequence[dict[str, Any]], out: Path) -> list[Path]:
    """One PNG per study: every run faint, each front as a line, error against wall time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    written = []
    by_study: dict[str, list[tuple[str, list[dict[str, Any]]]]] = {}
    for (study, case), members in groups(rows).items():
        by_study.setdefault(study, []).append((case, members))
    for study, panels in by_study.items():
        extra = study == "fig2"
        ncols = 2 if extra else len(panels)
        fig, axes = plt.subplots(1, ncols, figsize=(6 * ncols, 4.6), squeeze=False)
        for i, (case, members) in enumerate(panels[:1] if extra else panels):
            for ax, key in (
                ((axes[0, i], "error"),)
                if not extra
                else (
                    (axes[0, 0], "error"),
                    (axes[0, 1], "overshoot"),
                )
            ):
                for name in sorted({series(r) for r in members}):
                    mine = [
                        r for r in members if series(r) == name and math.isfinite(_number(r[key]))
                    ]
                    if not mine:
                        continue
                    peer = is_peer(mine[0])
                    t = [_number(r[TIME]) for r in mine]
                    e = [abs(_number(r[key])) for r in mine]
                    (line,) = ax.plot(t, e, ".", alpha=0.25)
                    front = pareto([{**r, "error": abs(_number(r[key]))} for r in mine])
                    ax.plot(
                        [_number(r[TIME]) for r in front],
                        [_number(r["error"]) for r in front],
                        "--" if peer else "-",
                        color=line.get_color(),
                        marker="o",
                        ms=3,
                        label=name,
                    )
                ax.set_xscale("log")
                ax.set_yscale("log")
                ax.xaxis.set_minor_formatter(NullFormatter())
                ax.set_xlabel("CPU time of the solve [s]")
                ax.set_ylabel(
                    "overshoot of V(b) [F]"
                    if key == "overshoot"
                    else ("end error of v(L) [F L^3/EJ]" if extra else "relative error")
                )
                ax.set_title(f"{study}, {case}")
                ax.grid(alpha=0.3, which="both")
                ax.legend(fontsize=7)
        fig.tight_layout()
        path = out / f"work_precision_{study}.png"
        write_atomic(path, lambda tmp, fig=fig: fig.savefig(tmp, dpi=110, format="png"))
        plt.close(fig)
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    """Run the grid, write the CSV, the PNGs and the tables; exit code 130 on Ctrl-C."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.work_precision", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--quick", action="store_true", help="a small grid (seconds)")
    parser.add_argument("--docs", type=Path, help="put the tables between the markers there")
    parser.add_argument("--no-plot", action="store_true", help="CSV and tables only")
    parser.add_argument(
        "--replot", action="store_true", help="no runs: read DIR/work_precision.csv again"
    )
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.replot:
        rows, interrupted = read_csv(args.out / "work_precision.csv"), False
    else:
        rows, interrupted = compute(QUICK if args.quick else FULL, not args.no_progress)
        write_csv(rows, args.out / "work_precision.csv")
    peer_path = args.out / PEER_CSV
    shown = rows + (read_csv(peer_path) if peer_path.exists() else [])
    table = markdown(shown)
    write_atomic(args.out / "work_precision.md", lambda tmp: tmp.write_text(table))
    if not args.no_plot:
        plot(shown, args.out)
    print(table)
    if args.docs is not None and not interrupted:
        update_docs(args.docs, table)
    print(f"written to {args.out}" + (" (interrupted)" if interrupted else ""))
    return 130 if interrupted else 0


def run_with_one_blas_thread(main: Callable[[], int], module: str) -> None:
    """Exit with ``main()``'s code, first restarting ``python -m module`` with
    ``OPENBLAS_NUM_THREADS=1`` if that is not set (OpenBLAS reads it when it loads)."""
    if os.environ.get("OPENBLAS_NUM_THREADS") != "1":
        os.environ["OPENBLAS_NUM_THREADS"] = "1"
        os.execv(sys.executable, [sys.executable, "-m", module, *sys.argv[1:]])
    sys.exit(main())


if __name__ == "__main__":
    run_with_one_blas_thread(main, __spec__.name)
