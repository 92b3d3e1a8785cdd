"""``--resume`` goes on only from what the checkpoint was computed from, and only from a
checkpoint that is whole: a changed mesh file the scene names, one flipped byte in any file
of a checkpoint, or a commit whose arrays have the wrong shape, count or range is refused
with exit code 2 and a message naming the file or the array, never resumed into outputs
that match neither model (``sliders/app/checkpoint.py``).  Every figure compared is a
SHA-256 or a count: a difference is a byte that differs."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import tomli_w
from test_checkpoint import killed_run, run, scene_file

from fvbeam import straight
from sliders.app.checkpoint import COMMIT, checkpoint_directory


def meshed_scene(folder):
    """The pushed body of ``test_checkpoint.scene_file``, its beam read from a mesh file, a
    checkpoint every 4 steps."""
    path = scene_file(folder, checkpoint={"steps": 4})
    scene = tomllib.loads(path.read_text())
    straight((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 1, 3, name="cantilever").write(folder / "c.vtu")
    del scene["beam"][0]["straight"]
    scene["beam"][0]["mesh"] = "c.vtu"
    path.write_text(tomli_w.dumps(scene))
    return path


def test_a_changed_mesh_file_is_refused_by_name(tmp_path, monkeypatch, capsys):
    scene = meshed_scene(tmp_path)
    out = killed_run(tmp_path, scene, 10, monkeypatch)
    mesh = tmp_path / "c.vtu"
    straight((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 2, 3, name="cantilever").write(mesh)
    capsys.readouterr()
    assert run(scene, "--resume", str(out)) == 2
    err = capsys.readouterr().err
    assert f"{mesh}: changed since the checkpoint" in err and "SHA-256" in err
    assert not out.exists()


def flipped(path, offset: int) -> None:
    data = bytearray(path.read_bytes())
    data[offset] ^= 0x01
    path.write_bytes(bytes(data))


def test_one_flipped_byte_in_any_file_of_a_checkpoint_is_refused(tmp_path, monkeypatch, capsys):
    """Each file of the checkpoint, a byte in its middle flipped (the length unchanged),
    the checkpoint restored between: every flip is refused naming its file."""
    scene = scene_file(tmp_path, checkpoint={"steps": 4})
    out = killed_run(tmp_path, scene, 10, monkeypatch)
    kept = checkpoint_directory(out)
    names = sorted(
        str(p.relative_to(kept))
        for p in kept.rglob("*")
        if p.is_file() and p.name not in (COMMIT, ".fvslider-checkpoint")
    )
    assert "history.csv" in names and any(n.startswith("states/") for n in names)
    for name in names:
        path = kept / name
        original = path.read_bytes()
        flipped(path, len(original) // 2)
        capsys.readouterr()
        assert run(scene, "--resume", str(out)) == 2, name
        err = capsys.readouterr().err
        assert "a damaged checkpoint" in err and path.name in err, (name, err)
        path.write_bytes(original)
    assert run(scene, "--resume", str(out)) == 0


@pytest.mark.parametrize(
    "key,value,message",
    [
        ("steps", np.array(10**18), "steps left"),
        ("rows", np.array([1, 2]), "rows is not"),
        ("states", np.array(-1), "states is not"),
        ("h", np.array(np.nan), "h = nan"),
        ("tables", np.array(["history"] * 7), "rows is not 7 integers"),
    ],
)
def test_a_commit_with_arrays_out_of_shape_or_range_is_refused(
    tmp_path, monkeypatch, capsys, key, value, message
):
    """A hand-edited commit: ``steps = 1e18`` ran past ``t_end``, arrays of the wrong shape
    gave a TypeError or a ZeroDivisionError; each is named."""
    scene = scene_file(tmp_path, checkpoint={"steps": 4})
    out = killed_run(tmp_path, scene, 10, monkeypatch)
    commit = checkpoint_directory(out) / COMMIT
    with np.load(commit) as saved:
        fields = {k: saved[k] for k in saved.files}
    fields[key] = value
    np.savez(commit, **fields)
    capsys.readouterr()
    assert run(scene, "--resume", str(out)) == 2
    err = capsys.readouterr().err
    assert "a damaged checkpoint" in err and message in err, err
    assert "Traceback" not in err
