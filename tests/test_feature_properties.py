"""The command on generated landing gears (hypothesis): force elements, tyres, slider
friction, start states, output selections and checkpoints, drawn valid or with one thing
wrong, run by ``fvslider check`` and ``run`` in process.

The shipped landing gear (``studies/scenes/landing_gear.toml``) is the base: it alone has
an axial force element, a tyre, a static start and derived outputs.  Its study is cut to
:data:`STEPS` time steps.  A variant (:func:`variants`) draws

* the strut's law (every coefficient scaled by a factor in [1/2, 2], the gas column's
  length ``volume / area`` kept, ``stroke_max`` within it and within the extended length);
* the tyre's coefficients (scaled likewise) and its ``normal`` and ``forward`` scaled by
  powers of two from ``2^-1000`` to ``2^1000`` (the vectors whose squares overflow or
  underflow; a power of two scales a float exactly, so the direction read is exactly the
  unit one and the run's bytes are the unscaled run's);
* friction on either slider or none (``mu``, ``mu_static``, ``v_eps``, ``v_stribeck``);
* the start's velocity and held nodes (the airframe and the wheel, maybe the axle);
* the tables of ``output.csv``, the columns of ``history`` and of ``[output.nodes]``, the
  probes (the derived outputs, which read them all, kept or dropped);
* the checkpoint's interval in steps.

Properties:

* a valid variant is accepted by ``check``, with a warning at its key for every option the
  study ignores (``v_stribeck`` without ``mu_static``), and ``run`` writes exactly the
  selected tables, with exactly the selected columns in the tables' order (the probes in
  the scene's);
* with its tyre's vectors scaled by powers of two, its ``history.csv`` is byte for byte the
  one of the unit vectors (an overflowing norm once made ``[0, 0, 1e200]`` a zero normal);
* killed after a drawn step and resumed, it writes the files of an uninterrupted run and
  exits with its code; killed before its first checkpoint, ``--resume`` says there is none;
* with one thing made wrong (:func:`broken`, each kind of :data:`BROKEN` in turn: a
  geometry ``run`` would refuse, a name that is not there or is repeated, a number out of
  range or of the wrong type, an unknown key) it is refused by both commands with one
  message naming the key path, and nothing is written (:func:`test_cli_properties.examine`).

Examples are few (each runs the command), derandomised (the same ones on every run) and not
shrunk (a failure is reported as drawn): about 20 s in all once the kernels are loaded.
"""

from __future__ import annotations

import copy
import csv
import math
import re
from datetime import timedelta
from pathlib import Path

import pytest
import tomli_w
from hypothesis import HealthCheck, Phase, event, given, settings
from hypothesis import strategies as st
from test_checkpoint import Killed, files, kill_after
from test_cli_properties import command, examine, small

from sliders.app.checkpoint import checkpoint_directory
from sliders.sliding_beams.model import compile_kernels

#: Time steps of a variant's study: enough for checkpoints to fall between a kill and the end.
STEPS = 6
#: The per-step tables a dynamic study may write, in ``output.csv``.
TABLES = ("nodes", "sliders", "internal_forces", "reactions")
#: ``history`` columns of the gear that need no probe: in the order ``history.csv`` has them.
HISTORY = (
    "h",
    "iterations",
    "kinetic",
    "strain",
    "external_work",
    "constraint_work",
    "dissipated",
    "energy_error",
    *(
        f"{s}.{c}"
        for s in ("top", "bottom")
        for c in ("xi", "lambda_x", "lambda_y", "lambda_z", "mu_2", "mu_3", "residual")
    ),
)
#: ``[output.nodes]`` rows and columns to draw from.
PARTS = ("C", "P", "airframe", "axle", "wheel", "C.start", "P.end")
NODE_COLUMNS = ("x", "y", "z", "ux", "uy", "uz", "rx", "ry", "rz")
#: The derived outputs of the gear (they read its probes).
DERIVED = ("load", "event", "peak", "frequency")


def gear() -> dict:
    """The shipped landing gear, :data:`STEPS` steps long, with no renders."""
    scene = small("landing_gear")
    scene["study"]["t_end"] = STEPS * scene["study"]["step"]
    return scene


@pytest.fixture(scope="module", autouse=True)
def compiled():
    """The numba kernels loaded before the examples (see ``test_cli_properties``)."""
    compile_kernels()


def scaled(draw, value: float) -> float:
    return value * draw(st.floats(0.5, 2.0))


def subset(draw, items, min_size: int = 0) -> list:
    """Some of ``items``, in a drawn order, none twice."""
    return draw(st.lists(st.sampled_from(items), min_size=min_size, unique=True))


@st.composite
def variants(draw, scale_vectors: bool = True) -> tuple[dict, dict]:
    """A valid variant of :func:`gear` (module docstring) and what its run must write:
    ``{"tables": [...], "history": [...] or None, "nodes": [...] or None, "probes": [...],
    "derived": bool, "warned": [...]}``."""
    scene = gear()
    strut, tyre = scene["force"]
    law = strut["law"]
    column = law["volume"] / law["area"]  # m: the gas column's length
    factor = draw(st.floats(0.5, 2.0))
    law.update(area=law["area"] * factor, volume=law["volume"] * factor)
    for key in ("pressure", "exponent", "compression", "rebound", "stop_stiffness"):
        law[key] = scaled(draw, law[key])
    law["stroke_max"] = draw(st.floats(0.05, 0.99)) * min(column, strut["extended"])
    for key in ("stiffness", "damping", "B", "C", "D"):
        tyre[key] = scaled(draw, tyre[key])
    if scale_vectors:
        for key, unit in (("normal", [0.0, 0.0, 1.0]), ("forward", [1.0, 0.0, 0.0])):
            tyre[key] = [2.0 ** draw(st.integers(-1000, 1000)) * u for u in unit]
    warned = []
    for i, slider in enumerate(scene["slider"]):
        if draw(st.booleans()):
            continue
        friction = {"mu": draw(st.floats(0.0, 0.3))}
        if draw(st.booleans()):
            friction["mu_static"] = friction["mu"] + draw(st.floats(0.0, 0.1))
        if draw(st.booleans()):
            friction["v_eps"] = draw(st.floats(1e-4, 1e-2))
        if draw(st.booleans()):
            friction["v_stribeck"] = draw(st.floats(1e-3, 0.1))
            if "mu_static" not in friction:
                warned.append(f"slider[{i}].friction.v_stribeck")
        slider["friction"] = friction
    study = scene["study"]
    study["start"] = {  # the static start holds what only the dynamics hold (the wheel's
        # spin, the airframe's fore-aft and vertical motion) and maybe the axle
        "velocity": [draw(st.floats(0.0, 60.0)), 0.0, draw(st.floats(-4.0, 0.0))],
        "hold": subset(draw, ["airframe", "wheel", "axle"], 3)
        if draw(st.booleans())
        else draw(st.permutations(["airframe", "wheel"])),
    }
    study["checkpoint"] = {"steps": draw(st.integers(1, STEPS))}
    output = scene["output"]
    expected: dict = {"tables": subset(draw, TABLES), "warned": warned, "nodes": None}
    output["csv"] = expected["tables"]
    expected["history"] = subset(draw, HISTORY) if draw(st.booleans()) else None
    if expected["history"] is None:
        del output["history"]
    else:
        output["history"] = expected["history"]
    if "nodes" in expected["tables"] and draw(st.booleans()):
        rows, columns = subset(draw, PARTS, 1), subset(draw, NODE_COLUMNS, 1)
        output["nodes"] = {"nodes": rows, "columns": columns}
        expected["nodes"] = columns
    expected["derived"] = draw(st.booleans())
    if expected["derived"] and expected["history"] is not None:  # a peak reads top.xi
        expected["history"] = [*expected["history"], "top.xi"]
        output["history"] = sorted(set(expected["history"]), key=expected["history"].index)
        expected["history"] = output["history"]
    if not expected["derived"]:
        for key in DERIVED:
            del output[key]
        probes = output["probe"]
        output["probe"] = [probes[i] for i in subset(draw, range(len(probes)))]
    expected["probes"] = [p["name"] for p in output["probe"]]
    return scene, expected


def header(path: Path) -> list[str]:
    return path.read_text().partition("\n")[0].split(",")


def run_to(folder: Path, scene: dict, name: str) -> tuple[int, Path, str]:
    """``fvslider run`` of ``scene`` written to ``folder/NAME.toml``, into ``folder/NAME``."""
    path, out = folder / f"{name}.toml", folder / name
    path.write_text(tomli_w.dumps(scene))
    code, _, err = command("run", str(path), "--out", str(out))
    assert "Traceback" not in err
    return code, out, err


@pytest.fixture(scope="module")
def everything(tmp_path_factory) -> list[str]:
    """The ``history.csv`` header of :func:`gear` with every output kept: the order every
    selection keeps."""
    scene = gear()
    del scene["output"]["history"]
    code, out, err = run_to(tmp_path_factory.mktemp("everything"), scene, "all")
    assert code == 0, err
    return header(out / "history.csv")


SETTINGS = settings(
    max_examples=8,
    phases=[Phase.explicit, Phase.generate],
    report_multiple_bugs=False,
    deadline=timedelta(seconds=60),
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@SETTINGS
@given(variant=variants())
def test_a_valid_gear_runs_and_writes_what_it_selects(variant, everything, tmp_path_factory):
    scene, expected = variant
    folder = tmp_path_factory.mktemp("gear")
    path = folder / "scene.toml"
    path.write_text(tomli_w.dumps(scene))
    code, stdout, err = command("check", str(path))
    assert code == 0 and "valid" in stdout, err
    assert re.findall(r": warning: ([^ :]+)", err) == expected["warned"], err
    code, out, err = run_to(folder, scene, "out")
    event(f"run exits {code}")
    assert code == 0, err
    written = {p.name for p in out.iterdir()}
    summary = {"summary.csv"} if expected["derived"] else set()
    tables = {f"{t}.csv" for t in expected["tables"]}
    assert written == {
        ".fvslider-output",
        "history.csv",
        "state.npz",
        "scene.toml",
        *tables,
        *summary,
    }
    kept = {"step", "t", *(HISTORY if expected["history"] is None else expected["history"])}
    derived = [c for c in everything if "." in c and c not in HISTORY]  # loads, events
    columns = [c for c in everything if c in kept] + expected["probes"]  # in the scene's order
    if expected["derived"]:
        columns += derived
    assert header(out / "history.csv") == columns
    if expected["nodes"] is not None:
        chosen = [c for c in NODE_COLUMNS if c in expected["nodes"]]
        assert header(out / "nodes.csv") == ["step", "t", "part", "xi", *chosen]


@SETTINGS
@given(variant=variants(scale_vectors=False), powers=st.tuples(*[st.integers(-1000, 1000)] * 2))
def test_the_tyre_is_the_same_whatever_the_length_of_its_vectors(variant, powers, tmp_path_factory):
    """``2^a e_z`` and ``2^b e_x`` are read as ``e_z`` and ``e_x``: the same bytes out (the
    overflowing norm of ``[0, 0, 1e200]`` once made the normal zero and the run exit 0)."""
    scene, _ = variant
    folder = tmp_path_factory.mktemp("tyre")
    unit = run_to(folder, scene, "unit")
    tyre = scene["force"][1]
    tyre["normal"] = [0.0, 0.0, 2.0 ** powers[0]]
    tyre["forward"] = [2.0 ** powers[1], 0.0, 0.0]
    long = run_to(folder, scene, "scaled")
    assert unit[0] == long[0] == 0, (unit[2], long[2])
    assert files(unit[1])["history.csv"] == files(long[1])["history.csv"]


@SETTINGS
@given(variant=variants(), kill=st.integers(2, STEPS - 1), every=st.integers(1, 3))
def test_a_gear_killed_and_resumed_writes_an_uninterrupted_runs_bytes(
    variant, kill, every, tmp_path_factory, monkeypatch
):
    """Killed after step ``kill``, with a checkpoint every ``every`` steps (before that
    step's checkpoint), resumed: the files of the uninterrupted run, and its exit code."""
    scene, _ = variant
    scene["study"]["checkpoint"] = {"steps": every}
    scene["output"]["vtu"] = True  # the states, too
    scene["study"]["every"] = 2
    folder = tmp_path_factory.mktemp("resume")
    code, whole, err = run_to(folder, scene, "whole")
    event(f"the whole run exits {code}")  # 1: a step failed, its steps written
    assert code in (0, 1), err
    path, out = folder / "whole.toml", folder / "killed"
    with monkeypatch.context() as patch:
        kill_after(patch, kill)
        with pytest.raises(Killed):
            command("run", str(path), "--out", str(out))
    event("a checkpoint to resume from" if kill > every else "no checkpoint yet")
    if kill <= every:  # killed before its first checkpoint: nothing to resume, and said so
        code, _, err = command("run", str(path), "--resume", str(out))
        assert code == 2 and "no checkpoint to resume from" in err
        return
    assert checkpoint_directory(out).is_dir()
    resumed, _, err = command("run", str(path), "--resume", str(out))
    assert resumed == code, err
    assert files(out) == files(whole) and (out / "history.csv").is_file()


def _one_of(draw, items):
    return draw(st.sampled_from(items))


def _wrong_number(draw, positive: bool = True):
    return draw(
        st.sampled_from([math.nan, math.inf, -1.0, "1.0", True] + ([0.0] if positive else []))
    )


#: What :func:`broken` makes wrong.
BROKEN = (
    "coincident nodes",
    "stop beyond the extended length",
    "gas column shorter than the stop",
    "undefined force node",
    "zero tyre vector",
    "forward along normal",
    "non-finite tyre vector",
    "force number",
    "friction number",
    "mu_static below mu",
    "bordered with force elements",
    "undefined held node",
    "held twice",
    "start velocity",
    "unknown history column",
    "history column twice",
    "unknown table",
    "unknown node column",
    "nodes without the table",
    "unknown probe value",
    "undefined probe force",
    "probe name twice",
    "checkpoint steps",
    "checkpoint seconds",
    "checkpoint key",
)


@st.composite
def broken(draw, kind: str) -> tuple[dict, str, str, bool]:
    """A valid variant with the ``kind`` of :data:`BROKEN` wrong, ``kind``, and the key path
    a message must name (the form of :func:`test_scene_properties.mutations`' draws)."""
    scene, _ = draw(variants())
    scene = copy.deepcopy(scene)
    strut, tyre = scene["force"]
    study, output = scene["study"], scene["output"]
    if kind == "coincident nodes":
        strut["nodes"] = ["airframe", "C.start"]  # tied together
        return scene, kind, "force[0].nodes", False
    if kind == "stop beyond the extended length":
        strut["law"]["volume"] = 10 * strut["law"]["area"]  # a column of 10 m: the law's fine
        strut["law"]["stroke_max"] = strut["extended"] * draw(st.floats(1.0, 3.0))
        return scene, kind, "force[0].law.stroke_max", False
    if kind == "gas column shorter than the stop":
        strut["law"]["volume"] = strut["law"]["area"] * strut["law"]["stroke_max"] / 2
        return scene, kind, "force[0].law", False
    if kind == "undefined force node":
        i = draw(st.integers(0, 1))
        strut["nodes"][i] = "nowhere"
        return scene, kind, f"force[0].nodes[{i}]", False
    if kind in ("zero tyre vector", "non-finite tyre vector"):
        keys = ["normal", "forward"] + (["ground"] if kind.startswith("non") else [])
        key = _one_of(draw, keys)
        tyre[key] = [0.0, 0.0, 0.0] if kind == "zero tyre vector" else [0.0, math.inf, 1.0]
        return scene, kind, f"force[1].{key}", False
    if kind == "forward along normal":
        tyre["forward"] = [0.0, 0.0, 2.0 ** draw(st.integers(-1000, 1000))]
        return scene, kind, "force[1]", False
    if kind == "force number":
        table, where = _one_of(
            draw,
            [(strut["law"], "force[0].law"), (tyre, "force[1]"), (strut, "force[0]")],
        )
        keys = {"force[0]": ["extended"], "force[1]": ["radius", "stiffness", "B", "C", "D"]}
        key = _one_of(draw, keys.get(where, ["area", "pressure", "volume", "stop_stiffness"]))
        table[key] = _wrong_number(draw)
        return scene, kind, f"{where}.{key}", False
    if kind == "friction number":
        i = draw(st.integers(0, 1))
        key = _one_of(draw, ["mu", "mu_static", "v_eps", "v_stribeck"])
        friction = {"mu": 0.1, key: _wrong_number(draw, positive=key.startswith("v"))}
        scene["slider"][i]["friction"] = friction
        return scene, kind, f"slider[{i}].friction.{key}", False
    if kind == "mu_static below mu":
        i = draw(st.integers(0, 1))
        scene["slider"][i]["friction"] = {"mu": 0.2, "mu_static": draw(st.floats(0.0, 0.19))}
        return scene, kind, f"slider[{i}].friction", False
    if kind == "bordered with force elements":
        study["method"] = "bordered"
        return scene, kind, "study.method", False
    start = study.setdefault("start", {"hold": ["airframe"]})
    if kind == "undefined held node":
        start["hold"] = [*start["hold"], "nowhere"]
        return scene, kind, f"study.start.hold[{len(start['hold']) - 1}]", False
    if kind == "held twice":
        start["hold"] = [*start["hold"], start["hold"][0]]
        return scene, kind, "study.start.hold", False
    if kind == "start velocity":
        start["velocity"] = _one_of(draw, [[0.0, math.nan, 0.0], [1.0, 2.0], [1.0, 2.0, "3"]])
        return scene, kind, "study.start.velocity", False
    if kind in ("unknown history column", "history column twice"):
        history = output.setdefault("history", ["h"]) or ["h"]
        output["history"] = [*history, "top.xx" if kind.startswith("unknown") else history[0]]
        return scene, kind, "output.history", False
    if kind == "unknown table":
        output["csv"] = [*output["csv"], "node"]
        return scene, kind, f"output.csv[{len(output['csv']) - 1}]", False
    if kind == "unknown node column":
        output["csv"] = sorted({*output["csv"], "nodes"})
        output["nodes"] = {"columns": ["ux", "uyy"]}
        return scene, kind, "output.nodes.columns[1]", False
    if kind == "nodes without the table":
        output["csv"] = [t for t in output["csv"] if t != "nodes"]
        output["nodes"] = {"columns": ["ux"]}
        return scene, kind, "output.nodes", False
    probe = {"name": "extra", "force": "tyre", "value": "Fz"}
    if kind == "unknown probe value":
        probe["value"] = "Fzz"
        key = "value"
    elif kind == "undefined probe force":
        probe["force"] = "nowhere"
        key = "force"
    if kind in ("unknown probe value", "undefined probe force"):
        output["probe"] = [*output["probe"], probe]
        return scene, kind, f"output.probe[{len(output['probe']) - 1}].{key}", False
    if kind == "probe name twice":
        output["probe"] = [*output["probe"], probe, dict(probe)]
        return scene, kind, "output.probe", False
    checkpoint = study["checkpoint"]
    if kind == "checkpoint steps":
        checkpoint["steps"] = _one_of(draw, [-1, 1.5, "3", True])
        return scene, kind, "study.checkpoint.steps", False
    if kind == "checkpoint seconds":
        checkpoint["seconds"] = _one_of(draw, [-1.0, math.nan, "60"])
        return scene, kind, "study.checkpoint.seconds", False
    checkpoint["minutes"] = 1.0
    return scene, kind, "study.checkpoint.minutes", False


@pytest.mark.parametrize("kind", BROKEN)
@settings(
    max_examples=4,
    deadline=timedelta(seconds=30),
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(data=st.data())
def test_a_gear_with_one_thing_wrong_is_refused_at_its_key(kind, data):
    assert examine(data.draw(broken(kind))) == 2


def test_a_planar_gear_whose_start_holds_the_axle_runs_as_the_3d_one(tmp_path):
    """Found by :func:`test_a_gear_killed_and_resumed_writes_an_uninterrupted_runs_bytes`:
    the start holding the axle too, a forward speed of 0.125 m/s.  The wheel spins up to
    rolling within 0.8 ms (the slip passes the tyre's linear range in one step), where the
    full step's Newton does not converge and the step is taken in halves: the planar run
    too (a diagnosis of the Newton matrix without the pinned multipliers' equations finds it
    singular along ``lambda_y`` and stops the run instead).  The two histories: the same
    steps, every column within 10 ``tol`` of its largest value (``tests/test_planar.py``'s
    bound)."""
    scene = gear()
    scene["study"]["start"] = {
        "velocity": [0.125, 0.0, -2.675],
        "hold": ["axle", "airframe", "wheel"],
    }
    tol = scene["study"].setdefault("tol", 1e-8)
    runs = []
    for planar in (False, True):
        scene["study"]["planar"] = planar
        code, out, err = run_to(tmp_path, scene, f"planar_{planar}")
        assert code == 0, err
        runs.append(columns(out / "history.csv"))
    three_d, planar_run = runs
    assert list(planar_run) == list(three_d)
    assert planar_run["h"] == three_d["h"]
    assert min(three_d["h"][1:]) == scene["study"]["step"] / 2  # a step taken in halves
    for name, values in three_d.items():
        scale = max(max(abs(v) for v in values), 1.0)
        worst = max(abs(a - b) for a, b in zip(planar_run[name], values, strict=True))
        assert worst <= 10 * tol * scale, name


def columns(path: Path) -> dict[str, list[float]]:
    """The columns of a CSV table of numbers, by name."""
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    return {name: [float(row[i]) for row in rows[1:]] for i, name in enumerate(rows[0])}
