"""Benchmark of the modes about a state, merged into ``results/bench.json`` (key ``modes``).

Two rows, on the scene ``studies/scenes/sliding_beams_modes.toml`` (the sliding beams of the
paper's Figures 3-5 with a 10 kg tip mass; two spherical sliders):

``large``
    20 modes about the static state of the scene with :data:`LARGE_ELEMENTS` fv3 elements
    per beam (1e4 in all) of steel tubes (:data:`LARGE_TUBES`), the piston at ``s = 0.3 L``
    (target: 2 s).  ``seconds`` is :func:`sliders.solve.modes.modes_about` (the problem
    reduced to the motions the sliders leave free, its one sparse LU and the shift-invert
    iterations); ``setup_seconds`` the model, the statics and its static solve.
``stroke``
    The scene's modes study (4 modes) along a stroke of :data:`STROKE_POINTS` piston
    positions ``s = 0 ... 0.95 L``, as ``fvslider run`` runs it (:func:`sliders.app.run.run`:
    the static sweep in continuation and the modes about every point, followed by MAC;
    target: 5 s); ``setup_seconds`` building the model.

Beside each time, the accuracy: the first frequency squared times the tip mass against the
static tip stiffness of the same model, ``|omega_1^2 M / k - 1|`` (bounded by the tubes'
share of the mass: 1.2e-4 on the stroke, ``tests/test_modes_study.py``; 0.6 with the large
row's steel tubes, a bound only), the largest over the stroke.
Each row is the least of :data:`REPEATS` runs (wall and CPU seconds).  The numba kernels
are compiled (or loaded) before any timing, by one small run.

Run as ``python -m studies.bench_modes --out results/bench.json``.
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path
from typing import Any

from sliders.app.model import Model
from sliders.app.run import Results, run
from sliders.app.scene import parse_scene
from sliders.solve.modes import StateModes, modes_about
from sliders.solve.statics import SliderStatics

from .bench import environment, least_time, write_merged

KEY = "modes"
SCENE = Path(__file__).parent / "scenes" / "sliding_beams_modes.toml"
#: fv3 elements per beam of the large row, its modes, and its tubes' mass (kg/m): steel
#: tubes.
LARGE_ELEMENTS, LARGE_MODES, LARGE_TUBES = 5000, 20, 5.0
#: Piston positions of the stroke row.
STROKE_POINTS = 100
REPEATS = 3
#: The scene's tip mass (kg).
TIP_MASS = 10.0
TARGETS = {"large": 2.0, "stroke": 5.0}


def scene(elements: int, tubes: float | None = None, **study: Any) -> dict:
    """The scene with ``elements`` per beam (and tubes of ``tubes`` kg/m, section inertia in
    proportion: None keeps the scene's)."""
    data = tomllib.loads(SCENE.read_text())
    for beam in data["beam"]:
        beam["straight"]["elements"] = elements
    if tubes is not None:
        section = data["section"][0]
        scale = tubes / section["mass_per_length"]
        section["mass_per_length"] = tubes
        section["inertia"] = [scale * j for j in section["inertia"]]
    data["study"].update(study)
    return data


def consistency(statics: SliderStatics, modes: StateModes) -> float:
    """``|omega_1^2 M / k - 1|``, ``k`` the static tip stiffness of ``statics``."""
    tip = statics.structure.node_dofs("P.end")[1]
    f = statics.structure.nodal_load("P.end", (0.0, 1.0, 0.0))
    k = 1.0 / statics.solve(f, tol=1e-6).q[tip]  # 1e-8 stalls at round-off on 1e4 elements
    return float(abs(modes.omega[0] ** 2 * TIP_MASS / k - 1))


def large(elements: int = LARGE_ELEMENTS, count: int = LARGE_MODES, repeats: int = REPEATS):
    """The ``large`` row (module docstring)."""
    (statics, solution), setup, _ = least_time(lambda: _state(elements), 1)
    modes, wall, cpu = least_time(lambda: modes_about(statics, solution, count), repeats)
    return {
        "elements": 2 * elements,
        "dofs": statics.structure.n_dofs,
        "modes": len(modes.omega),
        "seconds": wall,
        "cpu_seconds": cpu,
        "setup_seconds": setup,
        "first_hz": float(modes.hertz[0]),
        "tip_mass_consistency": consistency(statics, modes),
        "target_seconds": TARGETS["large"],
    }


def _state(elements: int) -> tuple[SliderStatics, Any]:
    data = scene(elements, LARGE_TUBES, values=[0.18], range=None)
    data["study"].pop("range", None)
    model = Model(parse_scene(data, SCENE.parent, SCENE.name))
    statics, f = model.problem(0.18)
    return statics, statics.solve(f)


def stroke(points: int = STROKE_POINTS, repeats: int = REPEATS) -> dict[str, Any]:
    """The ``stroke`` row (module docstring)."""
    data = scene(5, range={"start": 0.0, "stop": 0.57, "num": points})
    model, setup, _ = least_time(lambda: Model(parse_scene(data, SCENE.parent, SCENE.name)), 1)
    results, wall, cpu = least_time(
        lambda: run(Model(parse_scene(data, SCENE.parent, SCENE.name)), progress=False), repeats
    )
    assert isinstance(results, Results) and results.modes is not None
    worst = max(
        consistency(e.sample.statics, e.modes)
        for e in results.modes
        if e.modes is not None and e.sample.statics is not None
    )
    return {
        "points": points,
        "modes": data["study"]["count"],
        "converged": sum(e.modes is not None for e in results.modes),
        "seconds": wall,
        "cpu_seconds": cpu,
        "setup_seconds": setup,
        "tip_mass_consistency": worst,
        "target_seconds": TARGETS["stroke"],
    }


def bench(
    elements: int = LARGE_ELEMENTS, points: int = STROKE_POINTS, repeats: int = REPEATS
) -> dict[str, Any]:
    """Both rows, after a small untimed run that compiles (or loads) the kernels."""
    stroke(3, 1)
    return {"large": large(elements, LARGE_MODES, repeats), "stroke": stroke(points, repeats)}


def main(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    args = parser.parse_args(argv)
    result = bench()
    for name, row in result.items():
        print(
            f"modes {name}: {row['seconds']:.3f} s (target {row['target_seconds']:g} s), "
            f"|omega^2 M / k - 1| = {row['tip_mass_consistency']:.2e}"
        )
    write_merged(args.out, {KEY: result, "environment": environment()})
    return result


if __name__ == "__main__":
    main()
