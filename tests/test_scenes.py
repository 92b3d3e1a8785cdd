"""Scenes: the shipped files and the docs' examples validate, round trips, and the messages of
invalid scenes (path, value, what is allowed; several problems in one exception)."""

import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from sliders.app.errors import SceneError
from sliders.app.model import COINCIDENT, ON_LINE, Model
from sliders.app.scene import dump_scene, load_scene, parse_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "studies" / "scenes"
FILES = sorted(SCENES.glob("*.toml"))
DOCS = ROOT / "docs" / "scenes.md"


def data(name: str) -> dict:
    return tomllib.loads((SCENES / f"{name}.toml").read_text())


def problems(scene: dict, base: Path = SCENES) -> list:
    """The problems of validating and building ``scene`` (fails if it is valid)."""
    with pytest.raises(SceneError) as info:
        Model(parse_scene(scene, base, "test.toml"), "test.toml")
    return list(info.value.problems)


def docs_blocks() -> list[str]:
    return re.findall(r"```toml\n(.*?)```", DOCS.read_text(), re.S)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_shipped_scenes_validate_and_build(path):
    model = Model(load_scene(path), str(path))
    assert model.structure.n_dofs > 0


def test_every_docs_example_is_a_shipped_file_and_every_file_is_in_the_docs():
    """Each ```toml block of docs/scenes.md starts with the file it shows and is that file's
    text; the files are validated above, so every example in the docs is a tested file."""
    shown = {}
    for block in docs_blocks():
        name = block.splitlines()[0].removeprefix("# ")
        assert block == (ROOT / name).read_text(), name
        shown[name] = block
    assert sorted(shown) == [f"studies/scenes/{p.name}" for p in FILES]


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_round_trip_gives_the_same_scene_and_model(path):
    """Written back with dump_scene and read again: an equal scene, and a model with the same
    stiffness and loads (bit for bit: the same numbers go through the same code)."""
    scene = load_scene(path)
    again = parse_scene(tomllib.loads(dump_scene(scene)))
    assert again == scene
    first, second = Model(scene).problem(), Model(again).problem()
    assert (first[0].K != second[0].K).nnz == 0
    np.testing.assert_array_equal(first[1], second[1])


def test_several_problems_in_one_error_each_with_path_value_and_what_is_allowed():
    scene = data("fig4_sliding_beams")
    scene["slider"][1]["smering"] = 0.01
    scene["slider"][0]["kind"] = "sphercal"
    scene["section"][0]["EA"] = -1.0
    scene["load"][0]["force"][1] = float("nan")
    with pytest.raises(SceneError) as info:
        parse_scene(scene, source="fig4.toml")
    text = str(info.value)
    assert text.startswith("fig4.toml: invalid scene, 4 problems")
    assert "section[0].EA = -1.0: must be > 0" in text
    assert "slider[0].kind = 'sphercal': must be one of" in text
    assert "(did you mean 'spherical'?)" in text
    assert "slider[1].smering = 0.01: unknown key (did you mean 'smearing'?)" in text
    assert "load[0].force[1] = nan: must be a finite number" in text


def test_references_name_what_exists():
    scene = data("carriage_on_chain")
    scene["beam"][1]["section"] = "rial"
    scene["slider"][0]["line"] = ["c1", "c3"]
    found = {p.path: p.message for p in problems(scene)}
    assert "did you mean 'rail'?" in found["beam[1].section"]
    assert "['c1.end', 'c3.start']" in found["slider[0].line"]


def test_names_are_unique_across_beams_bodies_and_lines():
    scene = data("rigid_lines")
    scene["line"].append(dict(scene["line"][0], name="a"))
    (problem,) = problems(scene)
    assert problem.path == "line[4].name" and problem.message == "already the name of beam[0]"


def test_a_broken_tie_is_reported_once():
    """A tie naming a beam instead of its end is an error there; the chain that relies on
    ties is not reported as unjoined on top of it."""
    scene = data("carriage_on_chain")
    scene["tie"][0]["nodes"][1] = "c2"
    (problem,) = problems(scene)
    assert problem.path == "tie[0].nodes[1]"
    assert "'c2' is a beam: name one of its ends" in problem.message


def test_unreadable_mesh_file(tmp_path):
    (tmp_path / "broken.msh").write_text("$MeshFormat\nthis is not gmsh\n")
    scene = data("arch_mesh")
    scene["beam"][0]["mesh"] = "broken.msh"
    (problem,) = problems(scene, tmp_path)
    assert problem.path == "beam[0].mesh" and "meshio cannot read" in problem.message
    scene["beam"][0]["mesh"] = "missing.msh"
    (problem,) = problems(scene, tmp_path)
    assert problem.path == "beam[0].mesh" and "does not exist" in problem.message
    scene = data("arch_mesh")
    scene["formulation"] = "fv2"
    (problem,) = problems(scene)
    assert problem.path == "beam[0].mesh" and "needs 2-node elements" in problem.message


def test_not_toml(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[[beam]\nname = 1\n")
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(path)


def on_rail(gap: float) -> dict:
    """end_stops.toml with the rail moved by ``gap`` along z, off the tip at the origin."""
    scene = data("end_stops")
    scene["line"][0]["start"][2] = scene["line"][0]["end"][2] = gap
    return scene


def test_body_on_line_tolerance():
    """The rail from (-1, 0, 0) to the origin has size 1 (its length; its ends and the tip
    are at most 1 from the origin), so the tolerance is ON_LINE = 1e-6 m: a gap of half of
    it passes (rounding of six significant digits), twice it is an error naming the body."""
    Model(parse_scene(on_rail(0.5 * ON_LINE)))
    (problem,) = problems(on_rail(2 * ON_LINE))
    assert problem.path == "slider[0].body"
    assert "from line 'rail'" in problem.message


def test_sweep_that_moves_a_body_off_its_line():
    """Moving the piston of the sliding beams beyond s = L leaves slider A's body (P's bottom)
    past the end of the cylinder and slider B's (C's top) below the piston: the range is
    named, with the first bad value, once per slider."""
    scene = data("fig4_sliding_beams")
    scene["study"]["range"] = {"start": 0.0, "stop": 0.9, "num": 10}
    found = problems(scene)
    assert [p.path for p in found] == ["study.range", "study.range"]
    for problem, name in zip(found, "AB", strict=True):
        assert problem.value == pytest.approx(0.7)
        assert f"slider '{name}'" in problem.message
        assert "(and 2 more values)" in problem.message


def test_ties_join_coincident_nodes():
    """The library's rule for body ties (COINCIDENT of the scene's size) holds for every tie."""
    scene = data("carriage_on_chain")
    size = np.linalg.norm([1.8, 0.0, 0.25])
    scene["beam"][1]["straight"]["start"][2] = 2 * COINCIDENT * size
    (problem,) = problems(scene)
    assert problem.path == "tie[0].nodes" and "apart" in problem.message


def test_abscissa_outside_the_line():
    scene = data("carriage_on_chain")
    scene["study"]["range"]["stop"] = 1.9
    (problem,) = problems(scene)
    assert problem.path == "study.range" and "[0, 1.8]" in problem.message
