"""Derived results of a dynamic scene (sliders/app/events.py): slider forces and friction,
attachment loads, events, peaks and frequencies, and the landing-gear scene's summary.

Sources of the asserted numbers: the Python model's outputs and summary
(sliders/gear/outputs.py) computed from the same states as the scene's, which the scene's
summary must equal to round-off (the same definitions; 64 eps relative allows for the few
operations in a different order, such as a dot product for a product); the strut law's
stops (stroke_max); closed forms of the time-series functions (a parabola's vertex, a
sine's frequency, linear interpolation).
"""

import csv
import math

import numpy as np
import pytest
from test_scenes import SCENES, data, problems

from sliders.app import events
from sliders.app.history import Recorder
from sliders.app.model import Model
from sliders.app.run_dynamic import integrate, write_dynamic
from sliders.app.scene import parse_scene
from sliders.gear.outputs import GearRecorder
from sliders.gear.parameters import Gear

ROUNDOFF = 64 * np.finfo(float).eps


class Parts:
    """The scene's gear as the Python recorder reads it (sliders.gear.outputs.Parts)."""

    def __init__(self, model: Model) -> None:
        self.model, self.slider_kind, self.gear = "scene", "classical", Gear()
        self.structure, self.sliders = model.structure, model.sliders
        self.strut, self.tyre = model.forces


class Both:
    """Both recorders on one run."""

    def __init__(self, *recorders) -> None:
        self.recorders = recorders

    def start(self, dynamics, state) -> None:
        for r in self.recorders:
            r.start(dynamics, state)

    def record(self, dynamics, new, old) -> None:
        for r in self.recorders:
            r.record(dynamics, new, old)

    def close(self) -> None:
        for r in self.recorders:
            r.close()


def gear(sink: float = 2.8, t_end: float = 0.3, friction: bool = False) -> Model:
    scene = data("landing_gear")
    scene["study"].update(t_end=t_end)
    scene["study"]["start"]["velocity"] = [40.0, 0.0, -sink]
    if friction:
        for slider in scene["slider"]:
            slider["friction"] = {"mu": 0.02, "v_eps": 1e-3}
    return Model(parse_scene(scene, SCENES, "landing_gear.toml"))


def both(model: Model) -> tuple[dict[str, float], dict]:
    """The scene's summary and the Python model's, from one run."""
    dynamics = model.dynamics()
    ours = Recorder(None, (), model.probes(), history=model.scene.output.history)
    python = GearRecorder(Parts(model))
    study = model.scene.study
    dynamics.run(model.start_state(dynamics), study.t_end, study.step, recorder=Both(ours, python))
    return events.summary(model.scene.output, model.forces, ours.table()), python.result()


@pytest.mark.parametrize("friction", [False, True])
def test_the_gear_scene_writes_the_python_models_summary(friction):
    """Every quantity of the Python model's summary the scene asks for, equal to round-off
    on the same run; NaN nowhere (the fv3-3 gear has every event but the bottoming, whose
    times are empty by definition); the friction in the dynamics zero without friction and
    a few per cent of the vertical peak with it."""
    ours, run = both(gear(friction=friction))
    theirs = run.summary()
    shared = [k for k in theirs if k in ours]
    assert len(shared) == 31, shared
    for key in shared:
        assert ours[key] == pytest.approx(theirs[key], rel=ROUNDOFF, abs=1e-300, nan_ok=True), key
    bottoming = {k for k in ours if k.startswith("bottoming") and k != "bottoming_penetration"}
    assert not [k for k, v in ours.items() if math.isnan(v) and k not in bottoming]
    assert ours["bottoming_penetration"] == 0.0
    if friction:  # docs/landing_gear.md: 1.50 % for fv3-3 with classical sliders
        assert 0.01 < ours["friction_dynamic_fraction"] < 0.03
    else:
        assert ours["friction_dynamic"] == 0.0 == ours["friction_dynamic_fraction"]
    # the per-step columns: the Python model's, to round-off
    t = run.t
    assert ours["ground_vertical.stroke"] == pytest.approx(
        np.interp(ours["ground_vertical_time"], t, run.outputs["strut_stroke"]), rel=ROUNDOFF
    )


def test_a_bottoming_strut_reports_its_stop(tmp_path):
    """At 6 m/s sink the strut bottoms out: the stop event gives the first time the stroke
    passes stroke_max, the largest penetration (the strut element's stroke less stroke_max,
    to the peak's parabola) and the force then, through ``fvslider run``'s summary.csv; the
    Python model's summary the same to round-off."""
    model = gear(sink=6.0, t_end=0.1)
    ours, run = both(model)
    theirs = run.summary()
    for key in ("bottoming", "bottoming_penetration", "bottoming_penetration_time"):
        assert ours[key] == pytest.approx(theirs[key], rel=ROUNDOFF), key
    stroke = run.outputs["strut_stroke"]
    beyond = stroke - Gear().strut.stroke_max
    assert beyond.max() > 0
    first = np.argmax(beyond > 0)
    assert run.t[first - 1] <= ours["bottoming"] <= run.t[first]
    # the parabola's vertex lies above the largest sample b by (a - c)^2 / (8 (2b - a - c)),
    # at most a quarter of the larger drop to a neighbour
    i = int(np.argmax(beyond))
    drop = max(beyond[i] - beyond[i - 1], beyond[i] - beyond[i + 1])
    assert beyond[i] <= ours["bottoming_penetration"] <= beyond[i] + drop / 4
    assert ours["bottoming_force"] > 3 * Gear().strut(Gear().strut.stroke_max, 0.0)[0]
    outcome = integrate(model, progress=False)
    write_dynamic(outcome, tmp_path / "out")
    with open(tmp_path / "out" / "summary.csv", newline="") as handle:
        (row,) = csv.DictReader(handle)
    assert float(row["bottoming"]) == pytest.approx(ours["bottoming"], rel=ROUNDOFF)


def test_time_series_functions_against_closed_forms():
    """A parabola's vertex from three samples (exact), a window that holds no sample, a
    crossing interpolated linearly, a sine's frequency from its zero crossings."""
    t = np.linspace(0.0, 1.0, 21)
    value, when = events.peak(t, 2.0 - 3.0 * (t - 0.612) ** 2, +1.0)
    assert (value, when) == pytest.approx((2.0, 0.612), rel=1e-12)
    assert all(math.isnan(x) for x in events.peak(t, t, 0.0, start=2.0))
    assert events.peak(t, -t, -1.0, stop=0.5) == pytest.approx((-0.5, 0.5))
    assert events.crossing(t, t - 0.33) == pytest.approx(0.33)
    assert events.crossing(t, 0.33 - t, rising=False) == pytest.approx(0.33)
    assert math.isnan(events.crossing(t, t + 1.0))
    assert events.first_above(t, t - 0.33) == pytest.approx(0.33)
    assert events.first_above(t, t + 1.0) == 0.0
    fine = np.linspace(0.0, 2.0, 4001)
    assert events.frequency(fine, np.sin(2 * np.pi * 7.5 * fine + 0.3)) == pytest.approx(7.5)
    assert math.isnan(events.frequency(fine, np.sin(0.5 * fine + 0.1)))


def test_derived_output_problems_are_named():
    """Each bad name is one problem at its key path: the slider's name with the scene's
    names, then the rest against the built model."""
    scene = data("landing_gear")
    scene["output"]["probe"].append({"name": "p", "slider": "middle", "value": "force"})
    paths = {p.path: p.message for p in problems(scene)}
    assert "no slider named 'middle'" in paths["output.probe[12].slider"]
    scene = data("landing_gear")
    output = scene["output"]
    output["probe"].append({"name": "q", "slider": "top", "value": "pull"})
    output["probe"].append({"name": "r", "force": "tyre", "value": "Fz", "axes": ["x"]})
    output["load"].append({"name": "held", "body": "airframe", "components": ["Fy"]})
    output["load"].append({"name": "nobody", "body": "tail"})
    output["event"].append({"name": "late", "kind": "stop", "force": "tyre"})
    output["peak"].append({"name": "p1", "of": "nothing", "after": "never"})
    output["peak"].append({"name": "spin_up_time", "of": "F_z", "per": "later"})
    output["frequency"].append({"name": "f", "of": "F_z", "before": "p1"})
    paths = {p.path: p.message for p in problems(scene)}
    expected = {
        "output.probe[12].value": "'force', 'friction', 'couple'",
        "output.probe[13].axes": "axes are for a slider's force",
        "output.load[1].components[0]": "'airframe' is held there",
        "output.load[2].body": "no body of that name",
        "output.event[4].force": "a stop event needs a AxialForce, 'tyre' is a Tyre",
        "output.peak[11].of": "not a column of history.csv",
        "output.peak[11].after": "no [[output.event]] of that name",
        "output.peak[12].name": "already the name of output.event[1]",
        "output.peak[12].per": "no [[output.peak]] of that name before this one",
        "output.frequency[1].before": "no [[output.event]] of that name",
    }
    for path, message in expected.items():
        assert message in paths.get(path, ""), (path, paths)
    assert len(paths) == len(expected), paths
