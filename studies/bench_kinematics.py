"""Benchmark of what ``kinematics = "auto"`` costs a scene that stays linear, merged into
``results/bench.json`` under ``kinematics``.

``auto`` solves linearly first and bounds the neglected terms from the linear answer's
largest rotation and strain (:mod:`sliders.app.kinematics`); a scene that stays linear pays
for the bound (one pass over the elements) and, when the exact path carries the scene, the
check of its items.  Timed in one process, ``sliders.app.run.run(model, kinematics=...)``
with ``"linear"`` and with ``"auto"`` alternately (least of the repeats each, after one run
of each), on:

``sliders``
    ``studies/scenes/rigid_lines.toml`` (a static study with sliders on rigid lines: the
    exact path does not carry them);
``cantilever``
    an fv3 cantilever of 1e3 and 1e4 elements under a tip load small enough for the linear
    answer to be kept (``P L^2 / EJ = 1e-10``: a rotation of 5e-11 rad).

Each row holds both times, their ratio (on a shared machine the difference is within the
timing's noise), the time of the bound alone (``bound_s``), the path ``auto`` took and its
bound ``eta``, and the tip deflection's relative error against Timoshenko's closed form beside
the time.

Run as ``python -m studies.bench_kinematics --out results/bench.json`` (``make bench``);
``--quick`` shortens it (100 elements, one repeat).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from fvbeam.closed_forms import cantilever_exact
from sliders.app.kinematics import neglected
from sliders.app.model import Model
from sliders.app.run import Results, run
from sliders.app.scene import load_scene

from .bench import bench_arguments, environment, write_merged

KEY = "kinematics"
SCENES = Path(__file__).parent / "scenes"
#: The cantilever: unit length, EJ = 1, GA = EA = 1e6; the load P L^2 / EJ.
LOAD = 1e-10
GA = 1e6


def cantilever(elements: int) -> dict[str, Any]:
    """A unit fv3 cantilever of ``elements`` under a tip force ``LOAD`` (EJ = 1)."""
    section = {"name": "rod", "EA": GA, "GAy": GA, "GAz": GA, "GJ": 1.0, "EJy": 1.0, "EJz": 1.0}
    return {
        "title": f"cantilever of {elements} elements",
        "formulation": "fv3",
        "section": [section],
        "beam": [
            {
                "name": "rod",
                "section": "rod",
                "straight": {"start": [0, 0, 0], "end": [1, 0, 0], "elements": elements},
            }
        ],
        "support": [{"node": "rod.start"}],
        "load": [{"kind": "nodal", "node": "rod.end", "force": [0.0, LOAD, 0.0]}],
        "study": {"kind": "static"},
        "output": {"csv": ["nodes"]},
    }


def timed(model: Model, repeats: int) -> tuple[dict[str, float], Results]:
    """Least wall time of ``run`` with linear and with auto kinematics, alternately, after
    one run of each (compiled kernels loaded, the model's statics built); and the last auto
    run."""
    best = {"linear": np.inf, "auto": np.inf}
    for kind in best:
        run(model, progress=False, kinematics=kind)
    last = None
    for _ in range(repeats):
        for kind in best:
            clock = time.perf_counter()
            results = run(model, progress=False, kinematics=kind)
            best[kind] = min(best[kind], time.perf_counter() - clock)
            if kind == "auto":
                last = results
    assert isinstance(last, Results)
    return best, last


def row(name: str, model: Model, repeats: int, elements: int | None = None) -> dict[str, Any]:
    """One scene's times, path and bound (and the cantilever's tip error)."""
    best, results = timed(model, repeats)
    line = results.kinematics
    out: dict[str, Any] = {
        "scene": name,
        "n_elements": elements,
        "linear_s": best["linear"],
        "auto_s": best["auto"],
        "ratio": best["auto"] / best["linear"],
        "path": "exact" if line.startswith("kinematics: exact") else "linear",
        "eta": float(line.split("neglected terms by ")[1].split(" ")[0]),
    }
    sample = results.samples[0]
    assert sample.solution is not None and sample.statics is not None
    bound = []
    for _ in range(repeats):
        clock = time.perf_counter()
        neglected(sample.statics.structure, sample.solution.q)
        bound.append(time.perf_counter() - clock)
    out["bound_s"] = min(bound)
    if elements is not None:
        bending, shear, _ = cantilever_exact(1.0, 1.0, 1.0, GA, LOAD)
        tip = sample.statics.structure.node_dofs("rod.end")[1]
        out["tip_rel_error"] = abs(sample.solution.q[tip] / (bending + shear) - 1)
    print(
        f"{name}{'' if elements is None else f' of {elements} elements'}: linear "
        f"{best['linear']:.4f} s, auto {best['auto']:.4f} s ({out['ratio']:.3f} times), "
        f"{out['path']} path, eta {out['eta']:.2g}; the bound alone {out['bound_s']:.2g} s",
        flush=True,
    )
    return out


def main(argv: list[str] | None = None) -> None:
    """Run the benchmark and merge it into ``--out``."""
    args = bench_arguments("studies.bench_kinematics", __doc__ or "", "short runs", argv)
    repeats = 1 if args.quick else 5
    rows = [row("sliders", Model(load_scene(SCENES / "rigid_lines.toml")), repeats)]
    for elements in (100,) if args.quick else (1_000, 10_000):
        model = Model(load_scene(cantilever(elements)))
        rows.append(row("cantilever", model, repeats, elements))
    write_merged(args.out, {"environment": environment(), KEY: rows})


if __name__ == "__main__":
    main()
