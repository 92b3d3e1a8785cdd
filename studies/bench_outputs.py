"""Benchmarks of what a run writes and of what the command imports, merged into
``results/bench.json`` under ``outputs``.

``recording``
    The Figure 2 scene (:mod:`studies.fig2_smearing`, smearing 1 %, the 10-period crossing,
    400 steps) integrated once; its states are then recorded again by each recorder set-up
    (:class:`sliders.app.history.Recorder`), the load at each step's time asked first as
    the step does.  Reported per set-up: seconds per recorded step (median and minimum of
    the repeats; the work done by blocks of steps, the energies and linear probes, included),
    and seconds per row to turn the recording into CSV text (the formatting that
    checkpoints and the end of a run pay, a block of rows at a time).  Set-ups: ``default``
    (every ``history.csv`` column), ``no_residuals`` (without the sliders' constraint
    residuals, which :meth:`sliders.solve.dynamics.Dynamics.joint_residuals` evaluates per
    step), ``probes`` (that, and the study's shear and tip probes as linear probes),
    ``probes_by_function`` (the same probes as functions of the state, as the study writes
    them), ``tables`` (that, and the four per-step tables).  Beside them the largest
    difference of the recorded energies from their definitions evaluated per step
    (``v.M v / 2``, ``q.K q / 2``), relative to the largest energy: round-off.
``recovery``
    Internal forces of a state at every recovery point: :meth:`fvbeam.beam.Beam.internal_forces`
    (one product with the recovery map) against the scikit-fem field path it replaced
    (:func:`fvbeam.beam.internal_forces_reference`), per call, on the Figure 2 element and
    on a 100-element fv3 beam; and the largest difference between the two, relative to the
    largest force.
``imports``
    Wall time of ``python -m sliders.app.cli --help`` and ``... check
    studies/scenes/pushed_body.toml`` in a fresh interpreter (minimum of the repeats), and
    which of numba, scipy, scikit-fem, pydantic, matplotlib, pyvista each has imported.
``scene``
    ``studies/scenes/pushed_body.toml`` run in process (:func:`sliders.app.run.run` and
    :func:`sliders.app.run_dynamic.write_dynamic`) with every output (history, the four
    tables) and with a selection (``history`` of ``t`` and ``push.xi``, the ``nodes`` table of
    ``cantilever.end``'s ``uy``): seconds per step, the difference of a long run and a short
    one divided by the difference of their steps (the set-up cancels).

Run as ``python -m studies.bench_outputs --out results/bench.json`` (``make bench``);
``--quick`` shortens every part (the smoke test's setting).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from fvbeam import Beam, Section, straight
from fvbeam.beam import internal_forces_reference
from sliders.app.history import Recorder, history_columns
from sliders.app.model import Model
from sliders.app.probes import force_probe, node_probe
from sliders.app.run import run
from sliders.app.run_dynamic import DynamicRun, write_dynamic
from sliders.app.scene import parse_scene

from . import fig2_smearing as fig2
from .bench import environment, read_existing, summary, write_merged

KEY = "outputs"
TABLES = ("nodes", "sliders", "internal_forces", "reactions")
SCENE = Path(__file__).parent / "scenes" / "pushed_body.toml"
HEAVY = ("numba", "scipy", "skfem", "pydantic", "matplotlib", "pyvista")


def recording(repeats: int = 5, periods: float = 10) -> dict[str, Any]:
    """Seconds per recorded step and per formatted row of each recorder set-up."""
    crossing = fig2.Crossing(0.01, periods=periods)
    d = crossing.dynamics
    keep = Recorder(history=["t"], every=1)  # every state
    d.run(
        d.static_state(),
        crossing.t_end,
        crossing.period / fig2.STEPS_PER_PERIOD,
        recorder=keep,
        progress=False,
    )
    states = keep.states
    columns = [c for c in history_columns(d.sliders) if not c.endswith(".residual")]
    linear = {
        "shear": force_probe(crossing.structure, 0, fig2.EVALUATION_POINT, "V2"),
        "tip": node_probe(crossing.structure, (0, "end"), "uy"),
    }
    setups = {
        "default": lambda: Recorder(),
        "no_residuals": lambda: Recorder(history=columns),
        "probes": lambda: Recorder(probes=linear, history=columns),
        "probes_by_function": lambda: Recorder(probes=crossing.recorder().probes, history=columns),
        "tables": lambda: Recorder(None, TABLES, linear, history=columns),
    }
    rows = []
    for name, make in setups.items():
        per_step, per_row = [], []
        for _ in range(repeats):
            recorder = make()
            recorder.start(d, states[0])
            spent = 0.0
            for old, new in zip(states[:-1], states[1:], strict=True):
                d.load(new.t)  # the step asked for it: the recorder reads it cached
                start = time.perf_counter()
                recorder.record(d, new, old)
                spent += time.perf_counter() - start
            start = time.perf_counter()
            recorder.close()
            recorder.carry()  # the last block's energies and probes
            per_step.append((spent + time.perf_counter() - start) / (len(states) - 1))
            start = time.perf_counter()
            texts = [recorder.text(table) for table in recorder.headers]
            rows_written = sum(text.count("\n") for text in texts)
            per_row.append((time.perf_counter() - start) / rows_written)
        table = recorder.table()
        kinetic = [s.v @ (d.M @ s.v) / 2 for s in states]
        strain = [s.q @ (d.K @ s.q) / 2 for s in states]
        scale = max(np.abs(kinetic).max(), np.abs(strain).max())
        rows.append(
            {
                "setup": name,
                "steps": len(states) - 1,
                "history_columns": len(recorder.columns),
                "rows_per_step": rows_written / len(states),
                "seconds_per_step": summary(per_step),
                "seconds_per_row_formatted": summary(per_row),
                "energy_rel_error": float(
                    max(
                        np.abs(table["kinetic"] - kinetic).max(),
                        np.abs(table["strain"] - strain).max(),
                    )
                    / scale
                ),
            }
        )
        r = rows[-1]
        print(
            f"record {name:20s} {1e6 * r['seconds_per_step']['median']:8.1f} us/step, "
            f"format {1e6 * r['seconds_per_row_formatted']['median']:6.1f} us/row "
            f"({r['history_columns']} history columns, {r['rows_per_step']:.0f} rows/step), "
            f"energy error {r['energy_rel_error']:.1e}",
            flush=True,
        )
    return {"scene": "studies/fig2_smearing.py, smearing 1 %", "periods": periods, "rows": rows}


def recovery(repeats: int = 2000) -> dict[str, Any]:
    """Seconds per internal-forces call, map against field path, and their difference."""
    rows = []
    section = Section.diagonal(EA=1e3, GAy=1, GAz=1, GJ=1, EJy=1, EJz=1)
    for elements in (1, 100):
        beam = Beam(straight((0, 0, 0), (1, 0.2, 0.1), elements, 3), section, "fv3")
        q = np.random.default_rng(0).standard_normal(beam.n_dofs)
        beam.internal_forces(q)
        times = {}
        n = max(1, repeats // elements)
        for name, call, args in (
            ("recovery_map", Beam.internal_forces, (beam, q)),
            ("field_path", internal_forces_reference, (beam, q)),
        ):
            start = time.perf_counter()
            for _ in range(n):
                call(*args)
            times[name] = (time.perf_counter() - start) / n
        forces = beam.internal_forces(q)
        reference = internal_forces_reference(beam, q)
        mine = np.hstack([forces.force, forces.moment])
        rows.append(
            {
                "formulation": "fv3",
                "n_elements": elements,
                "seconds_per_call": times,
                "speed_up": times["field_path"] / times["recovery_map"],
                "max_rel_difference": float(
                    np.abs(mine - reference).max() / np.abs(reference).max()
                ),
            }
        )
        print(
            f"internal forces, {elements} elements: {1e6 * times['recovery_map']:.1f} us "
            f"(field path {1e6 * times['field_path']:.1f} us), difference "
            f"{rows[-1]['max_rel_difference']:.1e}",
            flush=True,
        )
    return {"rows": rows}


def imports(repeats: int = 3) -> dict[str, Any]:
    """Wall time and heavy imports of ``--help`` and ``check`` in fresh interpreters."""
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        commands = {
            "help": ["--help"],
            "check": ["check", str(SCENE), "--out", str(Path(tmp) / "out")],
        }
        for name, argv in commands.items():
            script = (
                "import json, sys\nfrom sliders.app.cli import main\n"
                f"try:\n    main({argv!r})\nexcept SystemExit:\n    pass\n"
                f"print(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}} & "
                f"set({list(HEAVY)!r}))))"
            )
            seconds, loaded = [], []
            for _ in range(repeats):
                start = time.perf_counter()
                done = subprocess.run(
                    [sys.executable, "-c", script], capture_output=True, text=True, check=True
                )
                seconds.append(time.perf_counter() - start)
                loaded = json.loads(done.stdout.splitlines()[-1])
            out[name] = {"seconds": summary(seconds), "imports": loaded}
            print(f"fvslider {name}: {min(seconds):.2f} s, imports {', '.join(loaded) or 'none'}")
    return out


def scene(t_short: float = 2.0, t_long: float = 10.0) -> dict[str, Any]:
    """Seconds per step of the pushed body through run and write, every output against a
    selection."""
    outputs = {
        "every": {"csv": list(TABLES)},
        "selected": {
            "csv": ["nodes"],
            "history": ["t", "push.xi"],
            "nodes": {"nodes": ["cantilever.end"], "columns": ["uy"]},
        },
    }
    data = tomllib.loads(SCENE.read_text())
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, output in outputs.items():
            spent = {}
            for t_end in (t_short, t_long):
                data["study"]["t_end"] = t_end
                data["output"] = output
                model = Model(parse_scene(data, SCENE.parent))
                start = time.perf_counter()
                outcome = run(model, progress=False)
                assert isinstance(outcome, DynamicRun)
                write_dynamic(outcome, Path(tmp) / name)
                spent[t_end] = (time.perf_counter() - start, outcome.recorder.count("history") - 1)
            (a, na), (b, nb) = spent[t_short], spent[t_long]
            rows.append(
                {"outputs": name, "seconds_per_step": (b - a) / (nb - na), "steps": [na, nb]}
            )
            print(f"pushed body, {name} outputs: {1e3 * rows[-1]['seconds_per_step']:.2f} ms/step")
    return {"scene": str(SCENE.relative_to(SCENE.parents[2])), "rows": rows}


def main(argv: list[str] | None = None) -> None:
    """Run the benchmarks, merge them into ``--out``."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench_outputs", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--quick", action="store_true", help="short runs (smoke test)")
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    quick = args.quick
    result = {
        "recording": recording(repeats=1 if quick else 5, periods=1 if quick else 10),
        "recovery": recovery(repeats=20 if quick else 2000),
        "imports": imports(repeats=1 if quick else 3),
        "scene": scene(0.5, 1.0) if quick else scene(),
    }
    write_merged(args.out, {"environment": environment(), KEY: result})
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
