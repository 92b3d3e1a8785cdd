"""The command on malformed scenes (hypothesis): a small variant of a shipped scene with one
thing broken (:func:`test_scene_properties.mutations`: unknown keys, wrong types, non-finite
and out-of-range numbers, undefined names, deleted keys, oversized counts, steps and arrays,
deep nesting, scaled numbers), written to a file and given to ``fvslider check`` and ``run``
in process.

* A scene ``check`` refuses: both commands exit 2 with the same message, which names the
  broken place (its key path; a nesting too deep, found before parsing, by its line), on
  stderr; ``run`` writes nothing, not even a temporary directory.
* A scene ``check`` accepts: ``run`` solves it and exits 0 or 1 (a solve that failed), never
  with an exception.

The studies are made small (three sweep samples, three time steps, no renders) so that a few
hundred examples run in well under a minute; ``derandomize`` makes the examples the same on
every run.
"""

import contextlib
import io
import os
import tempfile
from datetime import timedelta
from pathlib import Path
from unittest import mock

import pytest
import tomli_w
from hypothesis import HealthCheck, event, given, settings
from test_scene_properties import KINDS, SIZES, mutations
from test_scenes import SCENES, data

from sliders.app.cli import main
from sliders.sliding_beams.model import compile_kernels

#: ``FVSLIDER_MAX_ENTRIES`` while the examples run: an oversized array needs only this many
#: entries and one more, and every shipped scene's arrays and tables hold far fewer.
ENTRIES = 64
#: Kinds of mutation that always make a scene invalid.
INVALID = tuple(k for k in KINDS + SIZES if k not in ("deleted", "perturbed"))


def small(name: str) -> dict:
    """The shipped scene ``name`` with a small study (three samples or time steps), no
    renders or VTU, and its mesh paths absolute (the file is written elsewhere)."""
    scene = data(name)
    study = scene["study"]
    if "range" in study:
        study["range"]["num"] = min(study["range"]["num"], 3)
    if "values" in study:
        study["values"] = study["values"][:3]
    if study["kind"] == "dynamic":
        study["t_end"] = 3 * study["step"]
    scene.setdefault("output", {}).update(png="none", vtu=False)
    for beam in scene.get("beam", []):
        if "mesh" in beam:
            beam["mesh"] = str(SCENES / beam["mesh"])
    return scene


@pytest.fixture(scope="module", autouse=True)
def compiled():
    """The numba kernels loaded (or compiled once, 30-50 s) before the examples, whose
    deadline guards against unbounded work, not against a first compilation."""
    compile_kernels()


def command(*args: str) -> tuple[int, str, str]:
    """``fvslider ARGS`` in process: the exit code, stdout and stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


def listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def examine(mutation) -> int:
    """Run ``check`` on the mutated scene, then ``run``; assert the properties of the module
    docstring; return the exit code of ``check``."""
    scene, kind, target, anywhere = mutation
    with (
        tempfile.TemporaryDirectory() as folder,
        mock.patch.dict(os.environ, {"FVSLIDER_MAX_ENTRIES": str(ENTRIES)}),
    ):
        path, out = Path(folder) / "scene.toml", Path(folder) / "out"
        path.write_text(tomli_w.dumps(scene))
        checked, stdout, err = command("check", str(path))
        assert checked in (0, 2), (kind, target, err)
        event(f"{kind}: check exits {checked}")
        if checked == 2:
            # stdout: nothing of ours (meshio prints a blank line when it reads Gmsh)
            assert "invalid scene" in err and "Traceback" not in err and not stdout.strip()
            if kind == "deep":  # found in the text, before parsing: by its line
                assert "nests arrays and inline tables" in err, (target, err)
            elif not anywhere:
                assert target in err, (kind, target, err)
            code, stdout, again = command("run", str(path), "--out", str(out))
            assert (code, stdout.strip(), again) == (2, "", err)
            assert listing(Path(folder)) == ["scene.toml"]
            return checked
        code, stdout, err = command("run", str(path), "--out", str(out))
        assert code in (0, 1), (kind, target, err)
        event(f"run exits {code}")
        # a dynamic run whose start fails (exit 1) writes nothing, and says so
        started = "written to" in stdout or (code == 1 and "nothing written to" in err)
        assert started and "Traceback" not in err
        return checked


SETTINGS = settings(
    max_examples=150,
    deadline=timedelta(seconds=30),
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@SETTINGS
@given(mutations(load=small, kinds=INVALID, entries=ENTRIES))
def test_malformed_scenes_are_refused_cleanly(mutation):
    assert examine(mutation) == 2


@SETTINGS
@given(mutations(load=small, kinds=("deleted", "perturbed"), entries=ENTRIES))
def test_a_scene_check_accepts_runs(mutation):
    examine(mutation)
