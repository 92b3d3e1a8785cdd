"""A scene names the outputs it wants (``[output]``: history columns, each table's rows and
columns, VTU fields, probes); ``fvslider run`` writes only those, and they are the full
output's values.

Sources of the asserted numbers: the full run of the same scene.  Both runs do the same
arithmetic (a selection only leaves out rows, columns and fields, and what they alone
need), so every kept cell and VTU array is the full run's exactly; a probe reads one cell of
a table (a node's dof, the internal force at a recovery point) and equals it exactly.
"""

from __future__ import annotations

import csv

import meshio
import numpy as np
import tomli_w
from test_scenes import data

from sliders.app.cli import main
from sliders.app.vtu import ALWAYS

FIELDS = {"displacement", "force"}


def write(tmp_path, scene: dict, name: str):
    path = tmp_path / f"{name}.toml"
    path.write_text(tomli_w.dumps(scene))
    return path


def read(path) -> tuple[list[str], list[list[str]]]:
    with open(path, newline="") as handle:
        header, *rows = list(csv.reader(handle))
    return header, rows


def columns(path, names: list[str]) -> list[list[str]]:
    header, rows = read(path)
    return [[row[header.index(n)] for n in names] for row in rows]


def run(tmp_path, scene: dict, name: str):
    out = tmp_path / name
    assert main(["run", str(write(tmp_path, scene, name)), "--out", str(out)]) == 0
    return out


def test_a_dynamic_run_writes_only_the_outputs_asked_for(tmp_path):
    scene = data("pushed_body")
    scene["study"].update(t_end=1.0, every=5)
    scene["output"] = {"csv": ["nodes", "sliders", "internal_forces", "reactions"], "vtu": True}
    full = run(tmp_path, scene, "full")
    scene["output"] = {
        "csv": ["nodes", "internal_forces"],
        "vtu": True,
        "history": ["kinetic", "push.xi"],
        "vtu_fields": sorted(FIELDS),
        "nodes": {"nodes": ["cantilever.end"], "columns": ["uy"]},
        "internal_forces": {"columns": ["V2"]},
        "probe": [
            {"name": "tip", "node": "cantilever.end", "value": "uy"},
            {"name": "shear", "beam": "cantilever", "at": 0.79, "value": "V2"},
        ],
    }
    part = run(tmp_path, scene, "part")
    written = {p.name for p in part.iterdir()} - {".fvslider-output"}
    assert written == {
        "scene.toml",
        "state.npz",
        "states",
        "history.csv",
        "nodes.csv",
        "internal_forces.csv",
    }
    header, _ = read(part / "history.csv")
    assert header == ["step", "t", "kinetic", "push.xi", "tip", "shear"]
    assert columns(part / "history.csv", header[:4]) == columns(full / "history.csv", header[:4])
    assert read(part / "nodes.csv")[0] == ["step", "t", "part", "xi", "uy"]
    ends = [
        r
        for r in columns(full / "nodes.csv", ["step", "t", "part", "xi", "uy"])
        if r[3] == "1.0" and r[2] == "cantilever"
    ]
    assert read(part / "nodes.csv")[1] == ends
    forces = columns(full / "internal_forces.csv", ["step", "t", "beam", "xi", "V2"])
    assert read(part / "internal_forces.csv") == (["step", "t", "beam", "xi", "V2"], forces)
    # the probes are the cells they read
    assert [r[0] for r in columns(part / "history.csv", ["tip"])] == [r[4] for r in ends]
    nearest = min({r[3] for r in forces}, key=lambda x: abs(float(x) - 0.79))
    assert [r[0] for r in columns(part / "history.csv", ["shear"])] == [
        r[4] for r in forces if r[3] == nearest
    ]
    # the VTU states: the fields asked for (and those always written), the full run's arrays
    vtus = sorted((part / "states").glob("*.vtu"))
    assert [p.name for p in vtus] == [p.name for p in sorted((full / "states").glob("*.vtu"))]
    for path in vtus:
        mine, whole = meshio.read(path), meshio.read(full / "states" / path.name)
        assert set(mine.point_data) | set(mine.cell_data) == FIELDS | set(ALWAYS)
        for name, value in mine.point_data.items():
            np.testing.assert_array_equal(value, whole.point_data[name])
        for name, blocks in mine.cell_data.items():
            for a, b in zip(blocks, whole.cell_data[name], strict=True):
                np.testing.assert_array_equal(a, b)


def test_a_static_study_selects_rows_and_columns(tmp_path):
    scene = data("arch")
    full = run(tmp_path, scene, "full")
    scene["output"] = {
        "csv": ["internal_forces", "reactions"],
        "internal_forces": {"columns": ["N", "M3"]},
        "reactions": {"nodes": ["arch.end"], "columns": ["fx", "fy"]},
    }
    part = run(tmp_path, scene, "part")
    assert not (part / "nodes.csv").exists()
    names = ["sample", "value", "beam", "xi", "N", "M3"]
    assert read(part / "internal_forces.csv") == (
        names,
        columns(full / "internal_forces.csv", names),
    )
    names = ["sample", "value", "node", "fx", "fy"]
    rows = [r for r in columns(full / "reactions.csv", names) if r[2] == "arch.end"]
    assert read(part / "reactions.csv") == (names, rows)


def test_unknown_output_names_are_problems_at_their_key(tmp_path, capsys):
    scene = data("pushed_body")
    scene["output"] = {
        "csv": ["nodes", "internal_forces"],
        "vtu": True,
        "history": ["kinetc"],
        "vtu_fields": ["forces"],
        "nodes": {"nodes": ["cantilver.end"], "columns": ["uyy", "xi"]},
        "internal_forces": {"beams": ["cantilever"], "columns": ["V4"]},
        "reactions": {"columns": ["fy"]},
        "probe": [
            {"name": "tip", "node": "cantilever.end", "value": "uyy"},
            {"name": "kinetic", "beam": "cantilever", "at": 2.0, "value": "V2"},
            {"name": "both", "node": "cart", "beam": "cantilever", "value": "ux"},
        ],
    }
    assert main(["check", str(write(tmp_path, scene, "bad"))]) == 2
    err = capsys.readouterr().err
    # phase 2: the reactions table is not written; a probe names a node and a beam
    assert "output.reactions: selects from the reactions table, not in output.csv" in err
    assert "output.probe[2]: give exactly one of node, beam" in err
    scene["output"]["csv"].append("reactions")
    scene["output"]["probe"].pop()
    assert main(["check", str(write(tmp_path, scene, "bad"))]) == 2
    err = capsys.readouterr().err
    expected = [
        "output.history[0] = 'kinetc': must be one of 'step', 't', ",
        "(did you mean 'kinetic'?)",
        "output.vtu_fields[0] = 'forces': must be one of 'displacement', ",
        "(did you mean 'force'?)",
        "output.nodes.nodes[0] = 'cantilver.end': must be one of 'cantilever', ",
        "(did you mean 'cantilever.end'?)",
        "output.nodes.columns[0] = 'uyy': must be one of 'x', 'y', 'z', 'ux', ",
        "output.nodes.columns[1] = 'xi': a key column, always written",
        "output.internal_forces.columns[0] = 'V4': must be one of 'N', 'V2', ",
        "output.probe[0].value = 'uyy': must be one of 'ux', ",
        "output.probe[1].name = 'kinetic': already a column of history.csv",
        "output.probe[1].at = 2.0: beyond the end of beam 'cantilever' (length 1 m)",
    ]
    for text in expected:
        assert text in err, text
    scene = data("arch")
    scene["output"]["history"] = ["t"]
    scene["output"]["probe"] = [{"name": "tip", "node": "arch.end", "value": "uy"}]
    assert main(["check", str(write(tmp_path, scene, "static"))]) == 2
    err = capsys.readouterr().err
    assert "output.history: history.csv is a dynamic study's: study.kind = 'static'" in err
    assert "output.probe: history.csv is a dynamic study's" in err
