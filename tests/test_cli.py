"""The ``fvslider`` command: exit codes, messages on stderr, the light start-up, reproduce."""

import csv
import subprocess
import sys
from pathlib import Path

import pytest
from test_scenes import ROOT, SCENES

from sliders.app.cli import main

HEAVY = ("matplotlib", "pyvista")


def fvslider(*args: str, importtime: bool = False) -> subprocess.CompletedProcess:
    """``python -m sliders.app.cli ARGS`` in a fresh interpreter, from the repository root."""
    flags = ["-X", "importtime"] if importtime else []
    return subprocess.run(
        [sys.executable, *flags, "-m", "sliders.app.cli", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )


def imported(stderr: str) -> set[str]:
    """Top-level packages in a ``-X importtime`` report."""
    return {
        line.split("|")[-1].strip().split(".")[0]
        for line in stderr.splitlines()
        if line.startswith("import time:") and "|" in line
    }


@pytest.mark.parametrize("args", [["--help"], ["check", "studies/scenes/fig4_sliding_beams.toml"]])
def test_help_and_check_import_neither_matplotlib_nor_pyvista(args):
    done = fvslider(*args, importtime=True)
    assert done.returncode == 0, done.stderr
    modules = imported(done.stderr)
    assert "sliders" in modules and not modules & set(HEAVY)


def test_help_shows_examples():
    done = fvslider("--help")
    assert "examples:" in done.stdout and "fvslider run" in done.stdout


def test_console_script_is_installed():
    script = Path(sys.executable).parent / "fvslider"
    done = subprocess.run([script, "studies"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "studies/fig4_stiffness.py" in done.stdout


def test_invalid_scene_exits_2_with_the_message_on_stderr_and_no_traceback(tmp_path):
    scene = tmp_path / "bad.toml"
    text = (SCENES / "fig4_sliding_beams.toml").read_text()
    scene.write_text(text.replace('kind = "spherical"', 'kind = "spherical"\nsmering = 0.0', 1))
    done = fvslider("check", str(scene))
    assert done.returncode == 2
    assert "slider[0].smering = 0.0: unknown key (did you mean 'smearing'?)" in done.stderr
    assert "Traceback" not in done.stderr and done.stdout == ""


def test_check_valid(capsys):
    assert main(["check", str(SCENES / "spline_slider.toml")]) == 0
    assert "valid" in capsys.readouterr().out


def test_run_writes_the_tables(tmp_path, capsys):
    out = tmp_path / "fig1"
    assert main(["run", str(SCENES / "fig1_cantilever.toml"), "--out", str(out)]) == 0
    with open(out / "samples.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 21 and all(r["converged"] == "true" for r in rows)
    assert "21 of 21 samples" in capsys.readouterr().out


def test_run_with_failed_points_exits_1_and_keeps_them(tmp_path, capsys):
    """end_stops.toml without its stops: pushed outwards (factors 0.5, 1) the tip would leave
    the rail, which is an error naming it (tests/test_end_stops.py); pulled, it converges."""
    scene = tmp_path / "no_stops.toml"
    scene.write_text(
        (SCENES / "end_stops.toml").read_text().replace("end_stops = true", "end_stops = false")
    )
    out = tmp_path / "out"
    assert main(["run", str(scene), "--out", str(out)]) == 1
    assert "rail" in capsys.readouterr().err
    with open(out / "samples.csv", newline="") as handle:
        converged = [r["converged"] for r in csv.DictReader(handle)]
    assert converged == ["true", "true", "false", "false"]


def test_run_refuses_a_foreign_output_directory(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("mine")
    assert main(["run", str(SCENES / "spline_slider.toml"), "--out", str(tmp_path)]) == 2
    assert "not written by this program" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_interrupted_run_exits_130_after_writing_the_completed_samples(
    tmp_path, monkeypatch, capsys
):
    from sliders.app.model import Model

    build, calls = Model.problem, []

    def interrupt(self, value=None):
        calls.append(value)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return build(self, value)

    monkeypatch.setattr(Model, "problem", interrupt)
    out = tmp_path / "out"
    assert main(["run", str(SCENES / "fig1_cantilever.toml"), "--out", str(out)]) == 130
    assert "interrupted" in capsys.readouterr().err
    with open(out / "samples.csv", newline="") as handle:
        assert len(list(csv.DictReader(handle))) == 2


def test_studies_lists_the_paper_figures(capsys):
    assert main(["studies"]) == 0
    out = capsys.readouterr().out
    assert "studies/fig1_tip_response.py" in out and "studies/fig4_stiffness.py" in out


def test_reproduce_fig1(tmp_path, capsys):
    """Figure 1 into --out, with the table of errors against the closed forms; the fv rows
    are exact for one element (tests/test_fig1_study.py: 1e-10, roundoff only)."""
    assert main(["reproduce", "fig1", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "fig1_tip_response.csv").is_file()
    lines = capsys.readouterr().out.splitlines()
    rows = {line.split()[1]: float(line.split()[2]) for line in lines if line.startswith("fig1 ")}
    assert set(rows) == {"exact", "fv2", "fv3"} and max(rows.values()) <= 1e-10


def test_reproduce_rejects_unknown_figures(capsys):
    with pytest.raises(SystemExit) as info:
        main(["reproduce", "fig9"])
    assert info.value.code == 2
    assert "unknown figure 'fig9'" in capsys.readouterr().err


def test_compile_solves_each_slider_kind(capsys, monkeypatch):
    import sliders.sliding_beams.model as fig4

    solved = []
    monkeypatch.setattr(
        fig4.SlidingBeams, "solve", lambda self, stations: solved.append((self.kind, len(stations)))
    )
    assert main(["compile"]) == 0
    assert sorted(solved) == [("classical", 2), ("spherical", 2)]
    assert "compiled in" in capsys.readouterr().out
