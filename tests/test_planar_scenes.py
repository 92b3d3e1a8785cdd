"""Every shipped scene that lies in a plane (:attr:`sliders.app.model.Model.plane`) gives the
same answer solved on its in-plane dofs (the default) as in three dimensions
(``study.planar = false``): each static or sweep sample's displacements and joint unknowns,
and a dynamic run's state at its end (the first quarter of its time), to ``10 tol`` of the
largest value (both solves stop on the Newton tolerance ``tol`` of the scene; a dynamic run
adds the roundoff of its steps, well below it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene, parse_scene

SCENES = sorted((Path(__file__).parent.parent / "studies" / "scenes").glob("*.toml"))
PLANAR = {
    "arch": "xy",
    "arch_mesh": "xy",
    "elastica": "xy",
    "end_stops": "xy",
    "fig1_cantilever": "xy",
    "fig4_sliding_beams": "xy",
    "heavy_cantilever": "xy",
    "landing_gear": "zx",
    "long_run_probes": "xy",
    "pendulum": "xy",
    "pushed_body": "xy",
    "telescope": "xy",
    "tube_cantilever": "zx",
}


def variant(path: Path, planar: bool) -> Model:
    scene = load_scene(path)
    data = scene.model_dump(mode="python", exclude_none=True)
    data["study"]["planar"] = planar
    if scene.study.kind == "dynamic":
        data["study"]["t_end"] = scene.study.t_end / 4
    return Model(parse_scene(data, base=path.parent))


def test_the_planar_scenes_are_found() -> None:
    found = {p.stem: Model(load_scene(p)).plane for p in SCENES}
    assert {name: plane for name, plane in found.items() if plane is not None} == PLANAR


@pytest.mark.parametrize("name", list(PLANAR))
def test_planar_equals_three_dimensions(name: str) -> None:
    path = next(p for p in SCENES if p.stem == name)
    planar, full = variant(path, True), variant(path, False)
    assert planar.plane == PLANAR[name] and full.plane is None
    tol = planar.scene.study.tol
    a, b = run(planar), run(full)
    if planar.scene.study.kind == "dynamic":
        pairs = [(a.state.q, b.state.q)] + list(
            zip(a.state.unknowns, b.state.unknowns, strict=True)
        )
    else:
        pairs = []
        for s, r in zip(a.samples, b.samples, strict=True):
            pairs.append((s.solution.q, r.solution.q))
            pairs += list(zip(s.solution.unknowns, r.solution.unknowns, strict=True))
    for got, expected in pairs:
        assert np.abs(got - expected).max() <= 10 * tol * max(np.abs(expected).max(), 1.0)
