"""One writer per output, and a checkpoint a short run can resume from.

- A run holds ``DIR.lock`` beside its output directory (:func:`fvbeam.io.writer`) while it
  works: a second run into ``DIR`` meanwhile is refused (exit 2) with a message naming the
  running one, and writes nothing; once the holder dies (SIGKILL: the kernel drops its
  lock) the next run takes the lock over, runs, and leaves nothing beside its output.
- Two real runs of different scenes into one directory (they both exited 0 and shared one
  checkpoint): the second, by ``--out`` or ``--resume``, is refused naming the first, which
  goes on checkpointing its own scene.
- The default checkpoint interval has a number of steps (``CheckpointSpec().steps``), so a
  run killed after that many steps, well within the default minute, leaves a checkpoint of
  exactly that step to resume from.
"""

from __future__ import annotations

import subprocess
import sys
import time
import tomllib

import pytest
import tomli_w
from test_checkpoint import Killed, committed_step, files, fvslider, kill_after, run, scene_file

from sliders.app.checkpoint import checkpoint_directory
from sliders.app.schema import CheckpointSpec

HOLD = """
import sys
from fvbeam.io import writer
with writer(sys.argv[1], "a test's run"):
    print("held", flush=True)
    sys.stdin.read()
"""


def test_a_second_run_into_a_directory_being_written_is_refused(tmp_path, capsys):
    scene = scene_file(tmp_path, t_end=0.2)
    out = tmp_path / "out"
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(out)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        capsys.readouterr()
        assert run(scene, "--out", str(out)) == 2
        err = capsys.readouterr().err
        assert f"cannot write {out}: another fvslider run is writing it (pid {holder.pid}: " in err
        assert "a test's run" in err
        assert not out.exists()
    finally:
        holder.kill()  # dies holding the lock: the kernel drops it
        holder.wait()
    assert (tmp_path / "out.lock").exists()
    assert run(scene, "--out", str(out)) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "push.toml"]


def test_two_runs_of_different_scenes_into_one_directory(tmp_path, capsys):
    first = scene_file(tmp_path, name="first", t_end=1000.0, checkpoint={"steps": 1})
    second = scene_file(tmp_path, name="second", t_end=0.2, elements=2)
    out = tmp_path / "out"
    kept = checkpoint_directory(out)
    process = fvslider("run", str(first), "--out", str(out))
    try:
        deadline = time.monotonic() + 300
        while committed_step(kept) < 1:
            assert process.poll() is None and time.monotonic() < deadline
            time.sleep(0.01)
        for option in ("--out", "--resume"):
            capsys.readouterr()
            assert run(second, option, str(out)) == 2, option
            err = capsys.readouterr().err
            assert f"another fvslider run is writing it (pid {process.pid}: " in err, err
            assert str(first) in err and not out.exists()
        step = committed_step(kept)
        while committed_step(kept) == step:  # the first goes on, with its own checkpoint
            assert process.poll() is None and time.monotonic() < deadline
            time.sleep(0.01)
    finally:
        process.kill()
        process.wait()
    assert run(second, "--out", str(out)) == 0  # the lock taken over, the checkpoint replaced
    assert run(second, "--out", str(tmp_path / "alone")) == 0
    assert files(out) == files(tmp_path / "alone") and not kept.exists()


def test_a_short_run_killed_after_the_default_steps_can_resume(tmp_path, monkeypatch):
    steps = CheckpointSpec().steps
    assert 0 < steps
    scene = scene_file(tmp_path, t_end=0.05 * (steps + 20))
    text = tomllib.loads(scene.read_text())
    text["study"]["every"] = 10 * steps  # no VTU states to speak of
    text["output"] = {"csv": ["nodes"]}
    scene.write_text(tomli_w.dumps(text))
    out = tmp_path / "killed"
    with monkeypatch.context() as patch:
        kill_after(patch, steps + 1)
        with pytest.raises(Killed):
            run(scene, "--out", str(out))
    assert committed_step(checkpoint_directory(out)) == steps
    assert run(scene, "--resume", str(out)) == 0
