"""Benchmarks of ``fvslider run`` as a user runs it, merged into ``results/bench.json`` under
``command``.

``start_up``
    Wall time of ``fvslider run`` in a fresh interpreter (``python -m sliders.app.cli``) of
    a small static scene (a 10-element fv3 cantilever under a tip load: one linear solve)
    and of a small dynamic one (``studies/scenes/pushed_body.toml`` to ``t_end = 0.1``: two
    steps), against ``python -c "import numpy, scipy.sparse"`` on the same machine, timed
    alternately (least of the repeats each).  Targets: at most 2.5 and 3.5 times the
    baseline.
``recording``
    ``studies/scenes/pushed_body.toml`` through the command with ``history.csv`` (every
    column) and ``nodes.csv`` written at every step, against the same run writing only
    ``step, t`` and no table: seconds per step, the difference of a long run and a short
    one over their difference in steps (the start-up cancels), in CPU seconds of the
    command's process, least of the repeats.  The
    steps are of :data:`RECORDING_STEP` (a hundredth of the scene's), so that the long run's
    steps outweigh the start-up's spread on a shared machine.  Target: at most 1.3 times.
``moving_load``
    The moving load of the work-precision study's Euler-Bernoulli case (a body on a
    spherical slider driven along a simply supported beam: :func:`studies.moving_load.scene`)
    through the command, its recording on (``history.csv`` of the steps, and ``nodes.csv``
    of the beam's deflections at every step), for each run of :data:`MOVING_RUNS`: the CPU
    seconds of the run over 1.5 crossings less those of the same scene stopped after one
    step (so that the start-up, timed above, is not counted twice), and the error of the
    mid-span deflection against the closed form (:func:`studies.moving_load.relative_error`).
    At each level of
    :data:`MOVING_LEVELS`, the cheapest run reaching it (a run whose difference is not
    positive, its steps below the start-up's spread, is left out and counted) beside the
    peer's cheapest (Exudyn, either loading: :mod:`studies.peer_moving_load`, run here when
    the ``peer`` extra is installed, else read from ``results/peer_moving_load.csv`` if
    there).  Target: at most half the peer's time.
``large``
    ``fvslider run`` of an fv3 cantilever of 1e4 and 1e5 elements (solved in its plane),
    static, and dynamic (with a mass, from its static equilibrium under the tip load, three
    steps, ``nodes.csv`` of the tip at every step): wall time, and the largest difference
    of the tip deflection from Timoshenko's closed form (fv3 is exact at the nodes under an
    end load, and an equilibrium is a fixed point of the integrator; what remains is
    round-off, growing with the operator's condition number).

Run as ``python -m studies.bench_command --out results/bench.json`` (``make bench``);
``--quick`` shortens every part (the smoke test's setting).
"""

from __future__ import annotations

import csv
import resource
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from fvbeam.closed_forms import cantilever_exact

from . import moving_load as ml
from . import work_precision as wp
from .bench import bench_arguments, environment, summary, write_merged

KEY = "command"
SCENES = Path(__file__).parent / "scenes"
BASELINE = [sys.executable, "-c", "import numpy, scipy.sparse"]
#: Targets: the command's wall time over the baseline's; recording over writing nothing.
STATIC_TARGET, DYNAMIC_TARGET, RECORDING_TARGET = 2.5, 3.5, 1.3
#: The recording benchmark's step (s): 2e4 steps over the scene's 10 s.
RECORDING_STEP = 5e-4
L, EJ, GA, F = 10.0, 1.75e6, 8e8, 1e3
#: The moving load's runs through the command: ``(formulation, elements, steps per
#: crossing, rho_inf)``; the quick set for the smoke test.  The levels and the target: at
#: most this fraction of the peer's time at each.
MOVING_RUNS = tuple(
    ("cubic", n, steps, 0.8) for n in (4, 8, 16, 32) for steps in (50, 200, 800, 1600, 3200)
)
#: Repeats of each moving-load run (the least CPU time of each of its two runs).
MOVING_REPEATS = 3
MOVING_QUICK = (("cubic", 4, 50, 1.0),)
MOVING_LEVELS, MOVING_TARGET = (1e-2, 1e-3, 1e-4), 0.5
MOVING_CASE = "euler-bernoulli"


def cantilever(elements: int, dynamic: bool = False) -> dict[str, Any]:
    """An fv3 cantilever of ``elements`` clamped at its start under a tip force, writing its
    tip's ``nodes`` row: static, or ``dynamic`` (steel's mass, 7850 kg/m^3 on 0.01 m^2; three
    steps of 1 ms from the static equilibrium)."""
    study = {"kind": "dynamic", "t_end": 0.003, "step": 0.001} if dynamic else {"kind": "static"}
    mass = {"mass_per_length": 78.5, "inertia": [1e-4, 1e-4, 1e-4]} if dynamic else {}
    return {
        "title": f"cantilever of {elements} elements",
        "formulation": "fv3",
        "section": [
            {"name": "steel", "EA": 2.1e9, "GAy": GA, "GAz": GA, "GJ": 1.6e6, "EJy": EJ, "EJz": EJ}
            | mass
        ],
        "beam": [
            {
                "name": "cantilever",
                "section": "steel",
                "straight": {"start": [0.0, 0.0, 0.0], "end": [L, 0.0, 0.0], "elements": elements},
            }
        ],
        "support": [{"node": "cantilever.start"}],
        "load": [{"kind": "nodal", "node": "cantilever.end", "force": [0.0, F, 0.0]}],
        "study": study,
        "output": {"csv": ["nodes"], "nodes": {"nodes": ["cantilever.end"]}},
    }


def pushed(t_end: float, record: bool, step: float | None = None) -> dict[str, Any]:
    """``pushed_body.toml`` to ``t_end`` in steps of ``step`` (default the scene's),
    recording ``history.csv`` and ``nodes.csv`` in full (``record``) or only ``step, t``."""
    scene = tomllib.loads((SCENES / "pushed_body.toml").read_text())
    scene["study"]["t_end"] = t_end
    if step is not None:
        scene["study"]["step"] = step
    scene["output"] = {"csv": ["nodes"]} if record else {"csv": [], "history": []}
    return scene


def command(path: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "sliders.app.cli", "run", str(path), "--out", str(out)]


def wall(argv: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(argv, capture_output=True, check=True)
    return time.perf_counter() - start


def cpu(argv: list[str]) -> float:
    """CPU seconds (user and system) of running ``argv`` to its end: its own work, whatever
    else the shared machine runs meanwhile."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, capture_output=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def start_up(repeats: int) -> dict[str, Any]:
    """Least wall time of the baseline and of the two small runs, timed alternately."""
    with tempfile.TemporaryDirectory() as tmp:
        scenes = {"static": cantilever(10), "dynamic": pushed(0.1, record=True)}
        argv = {"baseline": BASELINE}
        for name, scene in scenes.items():
            path = Path(tmp) / f"{name}.toml"
            path.write_text(tomli_w.dumps(scene))
            argv[name] = command(path, Path(tmp) / name)
        for args in argv.values():
            wall(args)  # the numba cache and the files warm
        times: dict[str, list[float]] = {name: [] for name in argv}
        for _ in range(repeats):
            for name, args in argv.items():
                times[name].append(wall(args))
    base = min(times["baseline"])
    out: dict[str, Any] = {name: {"seconds": summary(t)} for name, t in times.items()}
    for name, target in (("static", STATIC_TARGET), ("dynamic", DYNAMIC_TARGET)):
        ratio = min(times[name]) / base
        out[name] |= {"ratio": ratio, "target": target, "met": ratio <= target}
        print(
            f"fvslider run, small {name}: {min(times[name]):.2f} s, {ratio:.2f} x baseline "
            f"{base:.2f} s (target {target})",
            flush=True,
        )
    return out


def recording(repeats: int, short: float, long: float) -> dict[str, Any]:
    """CPU seconds per step with full recording and with none, through the command."""
    per_step: dict[str, list[float]] = {"recorded": [], "nothing": []}
    with tempfile.TemporaryDirectory() as tmp:
        runs = {}
        for record, name in ((True, "recorded"), (False, "nothing")):
            for t_end in (short, long):
                path = Path(tmp) / f"{name}_{t_end}.toml"
                path.write_text(tomli_w.dumps(pushed(t_end, record, RECORDING_STEP)))
                runs[name, t_end] = command(path, Path(tmp) / f"{name}_{t_end}")
        cpu(runs["recorded", short])
        for _ in range(repeats):
            for name in per_step:
                seconds = cpu(runs[name, long]) - cpu(runs[name, short])
                per_step[name].append(seconds / round((long - short) / RECORDING_STEP))
    ratio = min(per_step["recorded"]) / min(per_step["nothing"])
    print(
        f"recording history.csv and nodes.csv: {1e3 * min(per_step['recorded']):.2f} ms per "
        f"step, {ratio:.2f} x writing nothing (target {RECORDING_TARGET})",
        flush=True,
    )
    return {
        "seconds_per_step": {name: summary(t) for name, t in per_step.items()},
        "ratio": ratio,
        "target": RECORDING_TARGET,
        "met": 0 < ratio <= RECORDING_TARGET,
    }


def moving_run(
    formulation: str, n: int, steps: int, rho_inf: float, tmp: Path, repeats: int = 1
) -> dict[str, Any]:
    """One run of the moving load through the command: a work-precision row, its CPU and
    wall seconds the least of ``repeats`` runs over 1.5 crossings less the least of as many
    stopped after one step."""
    problem = wp.CASES[MOVING_CASE]
    h, total = problem.crossing / steps, round(wp.WINDOW * steps)
    least: dict[str, tuple[float, float]] = {}
    for name, t_end in (("short", h), ("long", total * h)):
        path, out = tmp / f"{name}.toml", tmp / name
        path.write_text(tomli_w.dumps(ml.scene(formulation, n, steps, rho_inf, t_end, problem)))
        walls, cpus = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            cpus.append(cpu(command(path, out)))
            walls.append(time.perf_counter() - start)
        least[name] = (min(walls), min(cpus))
    with open(tmp / "long" / "nodes.csv") as stream:
        w = [float(r["uy"]) for r in csv.DictReader(stream) if float(r["xi"]) == problem.L / 2]
    exact = problem.exact_midspan(h * np.arange(len(w)), wp.REFERENCE_RTOL)
    error = ml.relative_error(np.array(w), exact) if len(w) == total + 1 else np.inf
    times = (least["long"][0] - least["short"][0], least["long"][1] - least["short"][1])
    return wp.moving_load_row(MOVING_CASE, formulation, "slider", n, steps, rho_inf, times, error)


def peer_rows(quick: bool = False) -> tuple[list[dict[str, Any]], str]:
    """The peer's rows and where they come from: run (the ``peer`` extra installed; its
    quick grid with ``quick``), read (``results/peer_moving_load.csv``), or none."""
    import importlib.util

    if importlib.util.find_spec("exudyn") is not None:
        from . import peer_moving_load as peer

        return peer.compute(peer.QUICK if quick else peer.FULL, progress=False)[0], "run"
    saved = Path("results") / wp.PEER_CSV
    return (wp.read_csv(saved), str(saved)) if saved.is_file() else ([], "none")


def moving_load(quick: bool) -> dict[str, Any]:
    """The moving load through the command against the peer, per error level (``quick``:
    one run, once, and the peer's quick grid)."""
    runs, repeats = (MOVING_QUICK, 1) if quick else (MOVING_RUNS, MOVING_REPEATS)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for run in runs:
            rows.append(moving_run(*run, Path(tmp), repeats))
            print(
                f"moving load through the command, {run}: {rows[-1]['cpu_seconds']:.3f} s CPU, "
                f"error {rows[-1]['error']:.1e}",
                flush=True,
            )
    peer, source = peer_rows(quick)
    # a run whose steps cost less than the start-up's spread is not resolved: left out
    resolved = [r for r in rows if r["cpu_seconds"] > 0]
    levels = []
    for level in MOVING_LEVELS:
        ours, theirs = wp.cheapest(resolved, level), wp.cheapest(peer, level)
        entry: dict[str, Any] = {"level": level, "ours": ours, "peer": theirs}
        if ours is not None and theirs is not None:
            ratio = float(ours["cpu_seconds"]) / float(theirs["cpu_seconds"])
            entry |= {"ratio": ratio, "target": MOVING_TARGET, "met": 0 < ratio <= MOVING_TARGET}
        levels.append(entry)
        print(
            f"moving load, error <= {level:g}: ours "
            + (f"{float(ours['cpu_seconds']):.4f} s" if ours else "never")
            + ", peer "
            + (f"{float(theirs['cpu_seconds']):.4f} s" if theirs else "none")
            + (
                f", ratio {entry['ratio']:.2f} (target {MOVING_TARGET})" if "ratio" in entry else ""
            ),
            flush=True,
        )
    return {"runs": rows, "unresolved": len(rows) - len(resolved), "peer": source, "levels": levels}


def large(sizes: tuple[int, ...]) -> list[dict[str, Any]]:
    """Wall time and tip error of ``fvslider run`` on long cantilevers, static and
    dynamic."""
    rows = []
    bending, shear, _ = cantilever_exact(L, L, EJ, GA, F)
    with tempfile.TemporaryDirectory() as tmp:
        for study in ("static", "dynamic"):
            for elements in sizes:
                name = f"{study}{elements}"
                path, out = Path(tmp) / f"{name}.toml", Path(tmp) / name
                path.write_text(tomli_w.dumps(cantilever(elements, study == "dynamic")))
                seconds = wall(command(path, out))
                with open(out / "nodes.csv") as stream:
                    tips = [float(row["uy"]) for row in csv.DictReader(stream)]
                error = max(abs(uy / (bending + shear) - 1) for uy in tips)
                rows.append(
                    {"study": study, "n_elements": elements, "seconds": seconds}
                    | {"tip_rel_error": error}
                )
                print(
                    f"fvslider run, {study} cantilever of {elements} elements: {seconds:.1f} "
                    f"s, tip error {error:.1e}",
                    flush=True,
                )
    return rows


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks, merge them into ``--out`` (``--quick``: the smoke test's short
    runs)."""
    args = bench_arguments("studies.bench_command", __doc__ or "", "short runs (smoke test)", argv)
    short = args.quick
    result = {
        "start_up": start_up(repeats=1 if short else 5),
        "recording": recording(1 if short else 3, 0.1, 0.5 if short else 10.0),
        "moving_load": moving_load(short),
        "large": large((100,) if short else (10_000, 100_000)),
    }
    write_merged(args.out, {"environment": environment(), KEY: result})


if __name__ == "__main__":
    main()
