"""Checkpoints of dynamic runs and ``fvslider run SCENE --resume DIR``.

The one source of every assertion on numbers here is determinism: a resumed run repeats the
arithmetic of the uninterrupted one (the same state, next step size, steps left and work
integrals go into the same code), so its files must equal the uninterrupted run's byte for
byte: ``history.csv``, the per-step tables, ``state.npz``, the VTU series.  A run is killed
for real (SIGKILL, at seeded random steps) or, in process, by an exception that nothing
catches, raised after a chosen step: like a kill, it leaves the checkpoint and no output.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import tomli_w
from test_scenes import ROOT, data

from fvbeam import Beam, Section, Structure, straight
from sliders.app import checkpoint, run_dynamic
from sliders.app.checkpoint import COMMIT, Checkpoints, checkpoint_directory
from sliders.app.cli import main
from sliders.app.history import Recorder
from sliders.app.model import Model
from sliders.app.scene import load_scene
from sliders.solve import condensed
from sliders.solve.condensed import CondensedOperator
from sliders.solve.dynamics import Adaptive, Cursor, Dynamics, DynamicsError
from sliders.solve.integrator import State

unit = Section.diagonal(1.0, 1.0, 1.0, 1.0, 1.0, 1.0)


class Killed(BaseException):
    """Ends a run in process as a kill does: nothing catches it, nothing is written."""


def scene_file(
    folder: Path, name: str = "push", t_end: float = 2.0, elements: int = 1, **study
) -> Path:
    """The pushed body (``studies/scenes/pushed_body.toml``), its drive a cosine ramp from
    rest, for ``t_end`` s of 0.05 s steps; every table, a VTU state every 3 steps."""
    scene = data("pushed_body")
    scene["beam"][0]["straight"]["elements"] = elements
    scene["drive"][0]["motion"] = {
        "kind": "ramp",
        "start": 0.6,
        "end": 0.95,
        "t0": 0.0,
        "t1": 10.0,
    }
    scene["study"].update(t_end=t_end, every=3, **study)
    scene["output"] = {"csv": ["nodes", "sliders", "internal_forces", "reactions"], "vtu": True}
    path = folder / f"{name}.toml"
    path.write_text(tomli_w.dumps(scene))
    return path


def files(directory: Path) -> dict[str, bytes]:
    """Every file under ``directory``, by relative path, with its bytes."""
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


def assert_same_files(resumed: Path, whole: Path) -> None:
    a, b = files(resumed), files(whole)
    assert sorted(a) == sorted(b)
    assert [name for name in a if a[name] != b[name]] == []
    assert "history.csv" in a and "state.npz" in a and "states/states.pvd" in a


def kill_after(monkeypatch: pytest.MonkeyPatch, step: int, error: type = Killed) -> None:
    """Raise ``error`` once step ``step`` is recorded (before its checkpoint is due)."""
    record = Recorder.record

    def call(self: Recorder, dynamics: Dynamics, new: State, old: State) -> None:
        record(self, dynamics, new, old)
        if self.count("history") - 1 == step:
            raise error

    monkeypatch.setattr(Recorder, "record", call)


def run(scene: Path, *args: str) -> int:
    return main(["run", str(scene), *args])


def whole_run(tmp_path: Path, scene: Path) -> Path:
    out = tmp_path / "whole"
    assert run(scene, "--out", str(out)) == 0
    assert not checkpoint_directory(out).exists()  # a run that ended keeps no checkpoint
    return out


def killed_run(tmp_path: Path, scene: Path, step: int, monkeypatch) -> Path:
    out = tmp_path / "killed"
    with monkeypatch.context() as patch:
        kill_after(patch, step)
        with pytest.raises(Killed):
            run(scene, "--out", str(out))
    assert not out.exists() and (checkpoint_directory(out) / COMMIT).is_file()
    return out


@pytest.mark.parametrize(
    "study",
    [
        {"checkpoint": {"steps": 4}},
        {"checkpoint": {"steps": 3}, "method": "bordered", "damping": 0.0},
        {"checkpoint": {"steps": 5}, "adaptive": {"rtol": 1e-5, "h_max": 0.1}},
    ],
    ids=["condensed", "bordered", "adaptive"],
)
def test_a_killed_run_resumes_to_the_bytes_of_an_uninterrupted_one(tmp_path, monkeypatch, study):
    """Killed once step 17 is recorded (the last checkpoint: step 16, 15 or 15), resumed:
    the same files as a run never stopped.  The fixed steps keep their count and size, the
    adaptive ones (27 steps of 0.025 to 0.1 s) their next size; the bytes a kill left
    beyond the checkpoint's tables are cut off."""
    scene = scene_file(tmp_path, **study)
    whole = whole_run(tmp_path, scene)
    out = killed_run(tmp_path, scene, 17, monkeypatch)
    kept = checkpoint_directory(out)
    for name in ("history.csv", "nodes.csv"):  # a kill in the middle of appending rows
        with open(kept / name, "ab") as stream:
            stream.write(b"0,0.1,half a row")
    assert run(scene, "--resume", str(out)) == 0
    assert_same_files(out, whole)
    assert not kept.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["killed", "push.toml", "whole"]


def test_the_lazy_columns_of_a_large_condensed_operator_resume_bit_for_bit(tmp_path, monkeypatch):
    """Above ``DENSE_LIMIT`` free dofs the condensed back end computes the columns of
    ``B^-1`` as the sliders reach them: the resumed run reaches them in other groups than
    the uninterrupted one, and must still compute the same bits.  The cantilever in 100
    elements of 1 cm: the body crosses into the next one in the 2 s."""
    monkeypatch.setattr(condensed, "DENSE_LIMIT", 0)
    scene = scene_file(tmp_path, elements=100, checkpoint={"steps": 4})
    whole = whole_run(tmp_path, scene)
    out = killed_run(tmp_path, scene, 17, monkeypatch)
    assert run(scene, "--resume", str(out)) == 0
    assert_same_files(out, whole)


def test_a_run_killed_after_its_last_step_resumes_to_its_outputs(tmp_path, monkeypatch):
    """Killed after the checkpoint of its last step (42, a kept VTU state: ``every = 3``)
    but before its outputs: the resume takes no step and writes the same files."""
    scene = scene_file(tmp_path, t_end=2.1, checkpoint={"steps": 1})
    whole = whole_run(tmp_path, scene)
    out = tmp_path / "killed"

    def killed(outcome, directory):
        raise Killed

    with monkeypatch.context() as patch:
        patch.setattr(run_dynamic, "write_dynamic", killed)
        with pytest.raises(Killed):
            run(scene, "--out", str(out))
    assert committed_step(checkpoint_directory(out)) == 42 and not out.exists()
    assert run(scene, "--resume", str(out)) == 0
    assert_same_files(out, whole)


def test_lazy_columns_do_not_depend_on_the_columns_computed_with_them(monkeypatch):
    """The property the resume above needs, on a random sparse SPD operator whose factors
    have wide supernodes (SuperLU then solves a group of right-hand sides with other
    roundoff than each alone): the same columns asked for in other groups, in another
    order, are the same bits."""
    monkeypatch.setattr(condensed, "DENSE_LIMIT", 0)
    rng = np.random.default_rng(5)
    structure = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 40, 3), unit, "fv3")])
    n = structure.n_dofs
    A = sp.random(n, n, density=0.02, random_state=rng)
    K = (A @ A.T + sp.diags(rng.uniform(1.0, 2.0, n))).tocsr()
    no_rigid_motion = np.zeros((n, 0))  # K is positive definite: nothing to border
    first, second = (CondensedOperator(K, np.arange(n), no_rigid_motion) for _ in range(2))
    order = rng.permutation(n)
    first._columns(order[: n // 2])
    first._columns(order[n // 2 :])
    for group in np.array_split(order[::-1], 7):
        second._columns(group)
    assert np.array_equal(first._store[first._slot], second._store[second._slot])


def test_ctrl_c_writes_the_steps_and_a_checkpoint_to_resume_from(tmp_path, monkeypatch, capsys):
    """Ctrl-C once step 17 is recorded, no periodic checkpoint due (``steps = 1000``,
    ``seconds = 0``): exit 130, the 18 rows written, and a checkpoint of the last step
    whose recording was whole, 16, from which ``--resume`` completes the run."""
    scene = scene_file(tmp_path, checkpoint={"steps": 1000, "seconds": 0.0})
    whole = whole_run(tmp_path, scene)
    out = tmp_path / "stopped"
    with monkeypatch.context() as patch:
        kill_after(patch, 17, KeyboardInterrupt)
        assert run(scene, "--out", str(out)) == 130
    assert f"--resume {out}" in capsys.readouterr().err
    assert len((out / "history.csv").read_text().splitlines()) == 1 + 18
    assert (checkpoint_directory(out) / "cursor_000016.npz").is_file()
    assert run(scene, "--resume", str(out)) == 0
    assert_same_files(out, whole)
    assert not checkpoint_directory(out).exists()


@pytest.mark.parametrize("failing", [1, 3], ids=["first", "third"])
def test_a_checkpoint_that_cannot_be_written_warns_and_the_run_goes_on(
    tmp_path, monkeypatch, failing
):
    """The disk full at the first checkpoint (written as a new directory) or at the third
    (appended): one warning naming the directory and the reason, no more checkpoints, and
    the run's outputs as those of any run."""
    scene = scene_file(tmp_path, checkpoint={"steps": 4})
    whole = whole_run(tmp_path, scene)
    write, calls = Checkpoints._write, []

    def full(self, directory):
        calls.append(directory)
        if len(calls) == failing:
            raise OSError(28, "No space left on device")
        return write(self, directory)

    monkeypatch.setattr(Checkpoints, "_write", full)
    out = tmp_path / "out"
    with pytest.warns(RuntimeWarning) as caught:
        assert run(scene, "--out", str(out)) == 0
    assert [str(w.message) for w in caught] == [
        f"cannot write {checkpoint_directory(out)}: No space left on device; the run goes on "
        "without checkpoints"
    ]
    assert len(calls) == failing
    assert_same_files(out, whole)
    assert not checkpoint_directory(out).exists()


def test_a_failed_run_writes_its_steps_and_removes_its_checkpoint(tmp_path, monkeypatch, capsys):
    """A step failing after step 9, checkpoints every 2 steps (one of step 8 is there when
    it fails): exit 1, the 10 rows written, and no checkpoint left (the run is over;
    resuming would fail again)."""
    scene = scene_file(tmp_path, checkpoint={"steps": 2})
    out = tmp_path / "out"
    record = Recorder.record

    def fail(self: Recorder, dynamics: Dynamics, new: State, old: State) -> None:
        record(self, dynamics, new, old)
        if self.count("history") - 1 == 9:
            assert committed_step(checkpoint_directory(out)) == 8
            raise DynamicsError("t = 0.5: no convergence", old)

    monkeypatch.setattr(Recorder, "record", fail)
    assert run(scene, "--out", str(out)) == 1
    assert "failed: t = 0.5: no convergence" in capsys.readouterr().err
    assert len((out / "history.csv").read_text().splitlines()) == 1 + 10
    assert not checkpoint_directory(out).exists()


def test_no_checkpoint_when_none_is_asked_for(tmp_path, monkeypatch):
    """``steps = 0, seconds = 0``: Ctrl-C writes the steps (130) and no checkpoint."""
    scene = scene_file(tmp_path, checkpoint={"steps": 0, "seconds": 0.0})
    with monkeypatch.context() as patch:
        kill_after(patch, 5, KeyboardInterrupt)
        assert run(scene, "--out", str(tmp_path / "out")) == 130
    assert not checkpoint_directory(tmp_path / "out").exists()


def test_resuming_a_finished_run_changes_nothing(tmp_path, capsys):
    scene = scene_file(tmp_path, t_end=0.5)
    whole = whole_run(tmp_path, scene)
    before = {p: p.stat().st_mtime_ns for p in whole.rglob("*")}
    written = files(whole)
    capsys.readouterr()
    assert run(scene, "--resume", str(whole)) == 0
    assert "nothing to resume" in capsys.readouterr().out
    assert {p: p.stat().st_mtime_ns for p in whole.rglob("*")} == before
    assert files(whole) == written
    assert not checkpoint_directory(whole).exists()


def test_a_checkpoint_of_another_scene_is_refused(tmp_path, monkeypatch, capsys):
    """Another ``t_end``: refused (exit 2) with the key, both values and the way out;
    nothing written, the checkpoint untouched.  Another checkpoint period changes no
    result: accepted, and only ``scene.toml`` (which records it) differs."""
    scene = scene_file(tmp_path, checkpoint={"steps": 4})
    out = killed_run(tmp_path, scene, 10, monkeypatch)
    commit = checkpoint_directory(out) / COMMIT
    saved = commit.read_bytes()
    other = scene_file(tmp_path, "other", t_end=1.5, checkpoint={"steps": 4})
    capsys.readouterr()
    assert run(other, "--resume", str(out)) == 2
    err = capsys.readouterr().err
    assert "the checkpoint of another scene (study.t_end = 2.0 there, 1.5 here)" in err
    assert "without --resume" in err and "Traceback" not in err
    assert not out.exists() and commit.read_bytes() == saved
    period = scene_file(tmp_path, "period", checkpoint={"steps": 7})
    assert run(period, "--resume", str(out)) == 0
    whole = whole_run(tmp_path, scene)
    differ = [k for k, v in files(out).items() if files(whole)[k] != v]
    assert differ == ["scene.toml"]


def test_a_missing_or_damaged_checkpoint_is_named(tmp_path, monkeypatch, capsys):
    scene = scene_file(tmp_path, checkpoint={"steps": 4})
    capsys.readouterr()
    assert run(scene, "--resume", str(tmp_path / "nothing")) == 2
    err = capsys.readouterr().err
    assert "nothing: no checkpoint to resume from" in err and "nothing.checkpoint" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["push.toml"]
    out = killed_run(tmp_path, scene, 10, monkeypatch)
    kept = checkpoint_directory(out)
    history = (kept / "history.csv").read_bytes()
    (kept / "history.csv").write_bytes(history[:-40])
    assert run(scene, "--resume", str(out)) == 2
    err = capsys.readouterr().err
    assert f"{kept}: a damaged checkpoint (history.csv is shorter" in err
    (kept / COMMIT).write_bytes(b"not a zip")
    assert run(scene, "--resume", str(out)) == 2
    assert f"{kept / COMMIT}: not a checkpoint" in capsys.readouterr().err
    assert not out.exists()


def test_a_foreign_directory_in_the_checkpoints_place_is_left_alone(tmp_path, capsys):
    scene = scene_file(tmp_path, t_end=0.5)
    foreign = checkpoint_directory(tmp_path / "out")
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    assert run(scene, "--out", str(tmp_path / "out")) == 2
    assert "was not written by this program" in capsys.readouterr().err
    assert not (tmp_path / "out").exists() and (foreign / "notes.txt").read_text() == "mine"


def test_the_next_run_removes_what_a_killed_checkpoint_left(tmp_path, capsys):
    """A kill inside a checkpoint's first writing or its removal leaves a temporary
    directory beside ``DIR.checkpoint``, holding the checkpoint's marker: the next run
    removes it and says so; a look-alike without the marker stays."""
    scene = scene_file(tmp_path, t_end=0.5)
    left, alike = tmp_path / ".out.checkpoint.k1l2m3n4", tmp_path / ".out.checkpoint.old.abcdefgh"
    for directory in (left, alike):
        directory.mkdir()
    (left / checkpoint.MARKER).write_text("")
    (alike / "notes.txt").write_text("mine")
    assert run(scene, "--out", str(tmp_path / "out")) == 0
    assert "removed 1 temporary directory" in capsys.readouterr().err
    assert not left.exists() and (alike / "notes.txt").is_file()


def test_resume_is_for_dynamic_studies_and_replaces_out(tmp_path, capsys):
    static = tmp_path / "static.toml"
    static.write_text((ROOT / "studies" / "scenes" / "fig1_cantilever.toml").read_text())
    assert run(static, "--resume", str(tmp_path / "out")) == 2
    assert "--resume: a sweep study has no checkpoints" in capsys.readouterr().err
    with pytest.raises(SystemExit) as info:
        run(static, "--resume", str(tmp_path / "a"), "--out", str(tmp_path / "b"))
    assert info.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["static.toml"]


@pytest.mark.parametrize("bad", [{"steps": -1}, {"seconds": -1.0}, {"every": 2}])
def test_checkpoint_options_are_checked(tmp_path, capsys, bad):
    scene = scene_file(tmp_path, checkpoint=bad)
    assert main(["check", str(scene)]) == 2
    key = next(iter(bad))
    assert f"study.checkpoint.{key}" in capsys.readouterr().err


def test_dynamics_resume_checks_its_cursor(tmp_path):
    """The library's resume: a cursor of fixed steps goes without adaptive control, one of
    adaptive steps with it, and a cursor needs a positive step."""
    dynamics = Model(load_scene(scene_file(tmp_path))).dynamics()
    state = dynamics.static_state()
    with pytest.raises(ValueError, match="a cursor of fixed steps resumes without adaptive"):
        dynamics.resume(Cursor(state, 0.1, 3), 1.0, adaptive=Adaptive())
    with pytest.raises(ValueError, match="a cursor of fixed steps resumes without adaptive"):
        dynamics.resume(Cursor(state, 0.1), 1.0)
    with pytest.raises(ValueError, match="a cursor needs a step h > 0"):
        dynamics.resume(Cursor(state, 0.0, 3), 1.0)


def fvslider(*args: str) -> subprocess.Popen:
    """``python -m sliders.app.cli ARGS`` in a new interpreter, from the repository root."""
    return subprocess.Popen(
        [sys.executable, "-m", "sliders.app.cli", *args],
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )


def committed_step(directory: Path) -> int:
    """The step of the last checkpoint in ``directory`` (-1: none yet)."""
    try:
        with np.load(directory / COMMIT) as saved:
            return int(saved["rows"][0]) - 1
    except (OSError, ValueError, KeyError):
        return -1


def test_a_run_killed_twice_at_random_steps_resumes_to_the_same_bytes(tmp_path):
    """SIGKILL twice, each some random time (up to two steps) after a seeded random step's
    checkpoint (so anywhere in a step or a checkpoint's writing), then resumed to the end:
    the same bytes as a run never stopped, and nothing left beside them."""
    rng = np.random.default_rng(20240612)
    first = int(rng.integers(5, 60))
    second = int(rng.integers(first + 10, 140))
    scene = scene_file(tmp_path, t_end=10.0, checkpoint={"steps": 1})
    whole = whole_run(tmp_path, scene)
    out = tmp_path / "killed"
    kept = checkpoint_directory(out)
    for step, option in ((first, "--out"), (second, "--resume")):
        process = fvslider("run", str(scene), option, str(out))
        deadline = time.monotonic() + 300
        while committed_step(kept) < step and process.poll() is None:
            assert time.monotonic() < deadline, "the run never reached its kill step"
            time.sleep(0.001)
        time.sleep(rng.uniform(0.0, 0.02))
        process.send_signal(signal.SIGKILL)
        _, err = process.communicate()
        assert process.returncode == -signal.SIGKILL, err.decode()
        assert not out.exists() and committed_step(kept) >= step
    assert run(scene, "--resume", str(out)) == 0
    assert_same_files(out, whole)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["killed", "push.toml", "whole"]


def test_a_run_with_checkpoints_writes_the_files_of_one_without(tmp_path):
    """The tables a run writes copy its last checkpoint's rows: the files of a run keeping a
    checkpoint every 7 steps are those of one keeping none, byte for byte."""
    kept = run(
        scene_file(tmp_path, "kept", checkpoint={"steps": 7, "seconds": 0.0}),
        "--out",
        str(tmp_path / "kept"),
    )
    assert kept == 0
    none = scene_file(tmp_path, "none", checkpoint={"steps": 0, "seconds": 0.0})
    assert run(none, "--out", str(tmp_path / "none")) == 0
    a, b = files(tmp_path / "kept"), files(tmp_path / "none")
    a.pop("scene.toml"), b.pop("scene.toml")  # their checkpoint tables differ
    assert sorted(a) == sorted(b) and [n for n in a if a[n] != b[n]] == []
