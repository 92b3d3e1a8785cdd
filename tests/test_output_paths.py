"""Output paths and the leftovers of killed runs (issue 12, items 2 and 6).

Every path, file or permission problem of ``fvslider run``, ``check`` and ``reproduce`` is one
line on stderr and exit code 2, found before any work, with nothing written
(:func:`fvbeam.io.check_replaceable`, :func:`fvbeam.io.check_writable`); a write that fails
later names the file it was writing, not a temporary one.  The next run into an output
directory removes the temporary directories that killed runs left beside it, and nothing else
(:func:`fvbeam.io.remove_leftovers`).
"""

import errno
import fcntl
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_scenes import ROOT, SCENES

from fvbeam.io import (
    OUTPUT_MARKER,
    TEMPORARY_EXTRA,
    OutputError,
    remove_leftovers,
    replace_directory,
    write_atomic,
)
from sliders.app.cli import main
from sliders.app.scene import load_scene

#: A static scene, validated and solved in well under a second once the kernels are cached.
SCENE = str(SCENES / "spline_slider.toml")
ENOSPC = os.strerror(errno.ENOSPC)


def listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def command(capsys, *args: str) -> tuple[int, str]:
    """Exit code and stderr of ``fvslider ARGS``, run in this process (an exception out of
    ``main``, a traceback, fails the test)."""
    code = main(list(args))
    return code, capsys.readouterr().err


@pytest.mark.parametrize("verb", ["check", "run"])
def test_an_output_directory_under_a_file(tmp_path, capsys, verb):
    (tmp_path / "notes.txt").write_text("mine")
    out = tmp_path / "notes.txt" / "out"
    code, err = command(capsys, verb, SCENE, "--out", str(out))
    assert code == 2
    assert err == f"fvslider: cannot write {out}: {tmp_path / 'notes.txt'} is not a directory\n"
    assert listing(tmp_path) == ["notes.txt"]


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc and /sys")
@pytest.mark.parametrize("verb", ["check", "run"])
@pytest.mark.parametrize(
    ("out", "reason"),
    [
        # /proc holds only what the kernel puts there: mkdir finds no such entry
        (
            "/proc/fvslider-none/out",
            f"cannot create /proc/fvslider-none ({os.strerror(errno.ENOENT)})",
        ),
        # sysfs refuses new entries to everyone, root included
        ("/sys/fvslider-out", "cannot create entries in /sys ("),
    ],
)
def test_an_output_directory_in_a_system_location(capsys, verb, out, reason):
    code, err = command(capsys, verb, SCENE, "--out", out)
    assert code == 2
    assert err.startswith(f"fvslider: cannot write {out}: {reason}") and err.count("\n") == 1
    assert not Path(out).exists() and not Path(out).parent.joinpath("fvslider-none").exists()


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only directories")
def test_an_output_directory_in_a_read_only_directory(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    code, err = command(capsys, "run", SCENE, "--out", str(locked / "a" / "out"))
    assert code == 2
    assert err == (
        f"fvslider: cannot write {locked / 'a' / 'out'}: cannot create {locked / 'a'} "
        f"({os.strerror(errno.EACCES)})\n"
    )
    assert listing(locked) == []


def test_the_longest_output_name_is_the_filesystems_less_the_temporary_names(tmp_path, capsys):
    """NAME_MAX (the filesystem's) less the 14 bytes ``.NAME.old.XXXXXXXX`` adds: one byte
    more is refused before any work; the longest allowed name runs, twice (the second run
    renames the first's output to that longest temporary name)."""
    longest = os.pathconf(tmp_path, "PC_NAME_MAX") - TEMPORARY_EXTRA
    assert TEMPORARY_EXTRA == len(".") + len(".old.") + len("XXXXXXXX")
    too_long = tmp_path / ("n" * (longest + 1))
    code, err = command(capsys, "run", SCENE, "--out", str(too_long))
    assert code == 2 and err.count("\n") == 1
    assert f"is {longest + 1} bytes long, at most {longest} here" in err
    assert listing(tmp_path) == []
    fits = tmp_path / ("n" * longest)
    for _ in range(2):
        assert command(capsys, "run", SCENE, "--out", str(fits))[0] == 0
    assert listing(tmp_path) == [fits.name] and (fits / OUTPUT_MARKER).is_file()


def test_an_over_long_output_path(tmp_path, capsys):
    """PATH_MAX bytes with the terminating zero, less what the temporary names add."""
    limit = os.pathconf(tmp_path, "PC_PATH_MAX")
    out = tmp_path.joinpath(*["d" * 200] * (limit // 200 + 1))
    code, err = command(capsys, "check", SCENE, "--out", str(out))
    assert code == 2 and err.count("\n") == 1
    size = len(os.fsencode(out))
    assert f"the path is {size} bytes long, at most {limit - 1 - TEMPORARY_EXTRA} here" in err
    assert listing(tmp_path) == []


def test_a_bad_scene_and_a_bad_output_directory_are_both_reported(tmp_path, capsys):
    scene = tmp_path / "bad.toml"
    scene.write_text(Path(SCENE).read_text().replace('title = "', 'titel = "', 1))
    (tmp_path / "notes.txt").write_text("mine")
    out = tmp_path / "notes.txt" / "out"
    for verb in ("check", "run"):
        code, err = command(capsys, verb, str(scene), "--out", str(out))
        assert code == 2
        lines = err.splitlines()
        assert lines[0] == f"{scene}: invalid scene, 1 problem"
        assert (
            lines[1].startswith("  titel = ") and "unknown key (did you mean 'title'?)" in lines[1]
        )
        assert lines[2:] == [
            f"fvslider: cannot write {out}: {tmp_path / 'notes.txt'} is not a directory"
        ]
    assert listing(tmp_path) == ["bad.toml", "notes.txt"]


def test_any_other_file_problem_is_one_line(capsys, monkeypatch):
    """The command's last resort: an ``OSError`` from anywhere is its file and reason."""
    import sliders.app.cli as cli

    def denied(args):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), "/some/file")

    monkeypatch.setattr(cli, "_studies", denied)
    assert command(capsys, "studies") == (2, f"fvslider: /some/file: {os.strerror(errno.EACCES)}\n")


def test_check_probes_the_default_output_directory(tmp_path, capsys, monkeypatch):
    """Without --out, the directory run would write: results/SCENE, here a foreign one."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "results" / "spline_slider").mkdir(parents=True)
    (tmp_path / "results" / "spline_slider" / "notes.txt").write_text("mine")
    code, err = command(capsys, "check", SCENE)
    assert code == 2 and "results/spline_slider exists and was not written by this program" in err
    (tmp_path / "results" / "spline_slider" / "notes.txt").unlink()
    assert command(capsys, "check", SCENE)[0] == 0
    assert listing(tmp_path / "results") == ["spline_slider"]


def test_reproduce_into_a_file(tmp_path, capsys):
    (tmp_path / "results").write_text("")
    code, err = command(capsys, "reproduce", "fig1", "--out", str(tmp_path / "results"))
    assert code == 2
    assert err == f"fvslider: cannot write {tmp_path / 'results'}: it is not a directory\n"
    assert listing(tmp_path) == ["results"]


def test_a_failed_write_names_the_file_and_leaves_nothing(tmp_path, capsys, monkeypatch):
    """A disk that fills up while the tables are written: exit 2, the message names the
    table's final path (not the temporary directory's), and nothing is left."""
    import sliders.app.tables as tables

    def full(results, name, path, selection=None):
        raise OSError(errno.ENOSPC, ENOSPC, str(path))

    monkeypatch.setattr(tables, "write_table", full)
    out = tmp_path / "out"
    code, err = command(capsys, "run", SCENE, "--out", str(out))
    first = load_scene(SCENE).output.csv[0]
    assert code == 2
    assert err == f"fvslider: cannot write {out / f'{first}.csv'}: {ENOSPC}\n"
    assert listing(tmp_path) == []


def test_write_atomic_names_the_target_not_its_temporary_file(tmp_path):
    target = tmp_path / "a.csv"

    def full(tmp):
        raise OSError(errno.ENOSPC, ENOSPC, str(tmp))

    with pytest.raises(OutputError) as info:
        write_atomic(target, full)
    assert str(info.value) == f"cannot write {target}: {ENOSPC}"
    assert isinstance(info.value, ValueError) and isinstance(info.value, OSError)
    assert listing(tmp_path) == []


def leftover(parent: Path, name: str, marker: bool = True, files=("nodes.csv",)) -> Path:
    """A directory as a killed run leaves it: its marker (or not) and some files."""
    directory = parent / name
    directory.mkdir()
    if marker:
        (directory / OUTPUT_MARKER).write_text("written by fvslider\n")
    for file in files:
        (directory / file).write_text("partial")
    return directory


def test_the_next_run_removes_what_killed_runs_left_and_nothing_else(tmp_path, capsys):
    ours = [
        leftover(tmp_path, ".out.k1l2m3n4"),  # a temporary directory being filled
        leftover(tmp_path, ".out.old.a_b0c9d8"),  # an old output renamed aside
        leftover(tmp_path, ".out.zzzzzzzz", marker=False, files=()),  # killed at mkdtemp
    ]
    others = [
        leftover(tmp_path, ".out.q1w2e3r4", marker=False),  # no marker: not ours
        leftover(tmp_path, ".out.backup"),  # not a temporary name
        leftover(tmp_path, ".out.ABCDEFGH"),  # not mkdtemp's characters
        leftover(tmp_path, ".outer.k1l2m3n4"),  # beside another output
        leftover(tmp_path, "out.k1l2m3n4"),  # not hidden
        leftover(tmp_path, "elsewhere"),
    ]
    (tmp_path / ".out.l1nk2222").symlink_to(tmp_path / "elsewhere")  # a link: not followed
    (tmp_path / ".out.f1le3333").write_text("a file")
    out = tmp_path / "out"
    code, err = command(capsys, "run", SCENE, "--out", str(out))
    assert code == 0
    names = ", ".join(p.name for p in ours)
    removed = f"removed 3 temporary directories left beside {out} by interrupted runs"
    assert err == f"{removed}: {names}\n"
    assert listing(tmp_path) == sorted(
        [p.name for p in others] + ["out", ".out.l1nk2222", ".out.f1le3333"]
    )
    assert listing(tmp_path / "elsewhere") == [OUTPUT_MARKER, "nodes.csv"]
    assert command(capsys, "run", SCENE, "--out", str(out)) == (0, "")


def test_a_directory_a_live_process_locks_is_left_alone(tmp_path):
    live = leftover(tmp_path, ".out.l1v3l1v3")
    fd = os.open(live, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        assert remove_leftovers(tmp_path / "out") == []
    finally:
        os.close(fd)
    assert remove_leftovers(tmp_path / "out") == [live]
    assert listing(tmp_path) == []


def test_replace_directory_marks_and_locks_its_temporary_directory(tmp_path):
    """While ``fill`` runs, the temporary directory holds the marker and another run's
    cleanup leaves it alone."""
    out, seen = tmp_path / "out", []

    def fill(directory):
        seen.append(((directory / OUTPUT_MARKER).is_file(), remove_leftovers(out)))
        (directory / "a.csv").write_text("new")

    replace_directory(out, fill)
    replace_directory(out, fill)
    assert seen == [(True, [])] * 2
    assert listing(tmp_path) == ["out"] and listing(out) == [OUTPUT_MARKER, "a.csv"]


def test_a_killed_run_leaves_nothing_after_the_next(tmp_path):
    """``fvslider run`` of a dynamic scene killed (SIGKILL) while it writes its output (its
    temporary directory, marked, exists beside the output): the next run removes it, says
    so, and writes the output."""
    scene = tmp_path / "push.toml"
    text = (SCENES / "pushed_body.toml").read_text()
    scene.write_text(text.replace('csv = ["nodes"', 'vtu = true\ncsv = ["nodes"'))
    out = tmp_path / "out"
    argv = [sys.executable, "-m", "sliders.app.cli", "run", str(scene), "--out", str(out)]

    def temporary() -> list[Path]:
        return [p for p in tmp_path.iterdir() if p.name.startswith(".out.")]

    process = subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    try:
        while not any((p / OUTPUT_MARKER).exists() for p in temporary()):
            assert process.poll() is None, "the run ended before it began to write"
            assert time.monotonic() < deadline, "the run never began to write"
            time.sleep(0.001)
    finally:
        process.kill()
        process.communicate()
    left = temporary()
    assert left and not out.exists()
    done = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    removed = f"removed {len(left)} temporary director{'y' if len(left) == 1 else 'ies'}"
    assert done.stderr.startswith(f"{removed} left beside {out} by interrupted runs: ")
    assert listing(tmp_path) == ["out", "push.toml"]
    assert (out / "states" / "states.pvd").is_file()
