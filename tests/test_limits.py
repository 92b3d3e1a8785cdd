"""Limits on what a scene may ask for (``sliders/app/limits.py``, ``docs/scenes.md`` Limits):
each refused by ``fvslider check`` and ``run`` with exit code 2, one message that says the
limit and its environment variable, no traceback and nothing written; each admits a scene
exactly at the limit, and its variable raises it."""

import re
import tomllib

import pytest
from test_scenes import SCENES

from sliders.app.cli import main
from sliders.app.errors import SceneError
from sliders.app.limits import DEPTH, Limits, nesting
from sliders.app.model import Model
from sliders.app.scene import load_scene, parse_scene

FIG1 = (SCENES / "fig1_cantilever.toml").read_text()


def refused(tmp_path, text: str, capsys) -> str:
    """The stderr of ``check`` on the scene ``text``, after asserting that ``check`` and
    ``run`` both exit 2 without a traceback and that ``run`` wrote nothing."""
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    assert main(["check", str(scene)]) == 2
    out, err = capsys.readouterr()
    assert "valid" not in out and "Traceback" not in err
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err == err
    assert [p.name for p in tmp_path.iterdir()] == ["scene.toml"]
    return err


def admitted(tmp_path, text: str, capsys) -> None:
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    code = main(["check", str(scene)])
    out, err = capsys.readouterr()
    assert code == 0 and "valid" in out, err


def over(err: str, limit: int, name: str) -> bool:
    """Whether the message says the limit and how to raise it."""
    return f"more than the limit of {limit} " in err and f"FVSLIDER_MAX_{name.upper()}" in err


def test_ten_billion_elements_are_refused_before_any_is_allocated(tmp_path, capsys):
    err = refused(tmp_path, FIG1.replace("elements = 1 ", "elements = 10000000000 "), capsys)
    assert "beam[0].straight.elements: 10000000000 elements" in err
    assert over(err, Limits().elements, "elements")


def test_elements_count_in_all(tmp_path, capsys, monkeypatch):
    """rigid_lines.toml has four beams of 4 elements: 16 in all.  A limit of 4 admits each
    beam and not the total; 16 admits the scene, 15 does not."""
    text = (SCENES / "rigid_lines.toml").read_text()
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "4")
    err = refused(tmp_path, text, capsys)
    assert "beam: the beams have 16 elements in all" in err and over(err, 4, "elements")
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "15")
    assert "16 elements in all" in refused(tmp_path, text, capsys)
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "16")
    admitted(tmp_path, text, capsys)


def test_elements_of_a_mesh_file_once_read(tmp_path, capsys, monkeypatch):
    """arch.msh holds the 8 line3 elements of fvbeam.arc (arch.toml): 7 refuses it."""
    text = (SCENES / "arch_mesh.toml").read_text()
    text = text.replace('"meshes/arch.msh"', repr(str(SCENES / "meshes" / "arch.msh")))
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "7")
    err = refused(tmp_path, text, capsys)
    assert "beam[0].mesh: 8 elements" in err and over(err, 7, "elements")
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "8")
    admitted(tmp_path, text, capsys)


def test_mesh_bytes(tmp_path, capsys, monkeypatch):
    mesh = SCENES / "meshes" / "arch.msh"
    text = (SCENES / "arch_mesh.toml").read_text().replace('"meshes/arch.msh"', repr(str(mesh)))
    size = mesh.stat().st_size
    monkeypatch.setenv("FVSLIDER_MAX_MESH_BYTES", str(size - 1))
    err = refused(tmp_path, text, capsys)
    assert "beam[0].mesh = '/" in err
    assert f"mesh files have {size} bytes" in err and over(err, size - 1, "mesh_bytes")
    monkeypatch.setenv("FVSLIDER_MAX_MESH_BYTES", str(size))
    admitted(tmp_path, text, capsys)


def test_a_billion_samples_are_refused_before_the_sweep_values_exist(tmp_path, capsys):
    err = refused(tmp_path, FIG1.replace("num = 21", "num = 1000000000"), capsys)
    assert "study.range.num = 1000000000: 1000000000 samples x 1 load step" in err
    assert over(err, Limits().solves, "solves")


def test_solves_count_the_load_steps(tmp_path, capsys, monkeypatch):
    """fig1's 21 samples x 5 load steps are 105 solves: a limit of 104 refuses them at the
    larger factor, the samples; 105 admits them."""
    text = FIG1.replace('kind = "sweep"', 'kind = "sweep"\nload_steps = 5')
    monkeypatch.setenv("FVSLIDER_MAX_SOLVES", "104")
    err = refused(tmp_path, text, capsys)
    assert "study.range.num = 21: 21 samples x 5 load steps = 105 static solves" in err
    monkeypatch.setenv("FVSLIDER_MAX_SOLVES", "105")
    admitted(tmp_path, text, capsys)
    many = FIG1.replace('kind = "sweep"', 'kind = "sweep"\nload_steps = 1000000')
    assert "study.load_steps = 1000000" in refused(tmp_path, many, capsys)


def test_time_steps(tmp_path, capsys, monkeypatch):
    """pushed_body.toml integrates to t_end = 10 s in steps of 0.05 s: 200 steps."""
    text = (SCENES / "pushed_body.toml").read_text()
    err = refused(tmp_path, text.replace("step = 0.05", "step = 1e-9"), capsys)
    assert "study.step = 1e-09: t_end / step = 10 / 1e-09 = 1e+10 time steps" in err
    assert over(err, Limits().steps, "steps")
    monkeypatch.setenv("FVSLIDER_MAX_STEPS", "199")
    assert "= 200 time steps" in refused(tmp_path, text, capsys)
    monkeypatch.setenv("FVSLIDER_MAX_STEPS", "200")
    admitted(tmp_path, text, capsys)


def test_a_large_file_is_refused_before_it_is_read_whole(tmp_path, capsys):
    """Ten million numbers under an unknown key: the file's size is over the limit."""
    text = FIG1 + "\nextra = [" + "0," * 10_000_000 + "]\n"
    err = refused(tmp_path, text, capsys)
    assert f"(scene): the file has {len(text)} bytes" in err
    assert over(err, Limits().scene_bytes, "scene_bytes")


def test_an_endless_file_is_read_no_further_than_the_limit(capsys):
    """/dev/zero never ends: only limit + 1 bytes of it are read."""
    assert main(["check", "/dev/zero"]) == 2
    err = capsys.readouterr().err
    assert f"the file has more than {Limits().scene_bytes} bytes" in err


def test_entries_of_an_array(tmp_path, capsys, monkeypatch):
    """An array under an unknown key is refused for its size, before the schema looks at
    it; at the limit it reaches the schema, which names the unknown key."""
    monkeypatch.setenv("FVSLIDER_MAX_ENTRIES", "1000")
    err = refused(tmp_path, FIG1 + "\nextra = [" + "0," * 1001 + "]\n", capsys)
    assert "extra: has 1001 entries" in err and over(err, 1000, "entries")
    err = refused(tmp_path, FIG1 + "\nextra = [" + "0," * 1000 + "]\n", capsys)
    assert "extra = [0, 0, 0," in err and "unknown key" in err


def test_entries_of_a_python_table_are_counted_before_the_schema():
    data = tomllib.loads(FIG1)
    data["section"][0].update({f"k{i}": 1.0 for i in range(20)})
    with pytest.raises(SceneError) as info:
        parse_scene(data, limits=Limits(entries=20))
    assert [p.path for p in info.value.problems] == ["section[0]"]
    assert "has 27 entries" in str(info.value)


def test_nesting_three_thousand_deep_is_refused_before_parsing(tmp_path, capsys):
    err = refused(tmp_path, FIG1 + "\nextra = " + "[" * 3000 + "]" * 3000 + "\n", capsys)
    line = FIG1.count("\n") + 2
    assert f"(scene): line {line} nests arrays and inline tables 3000 levels deep" in err
    assert f"more than the {DEPTH} a scene may nest" in err and "fixed" in err


def test_dotted_keys_three_thousand_deep_are_refused_before_validating(tmp_path, capsys):
    """Dotted keys nest tables without brackets: the parsed document is walked."""
    text = "a" + ".a" * 3000 + " = 1\n" + FIG1
    err = refused(tmp_path, text, capsys)
    assert "(scene)" not in err and "a." * DEPTH + "a: nested more than 32 levels deep" in err


def test_deep_python_data_is_walked_without_recursion():
    data = tomllib.loads(FIG1)
    deep: list = []
    for _ in range(100_000):
        deep = [deep]
    data["extra"] = deep
    with pytest.raises(SceneError, match=re.escape(f"extra{'[0]' * DEPTH}: nested more than")):
        parse_scene(data)


def test_nesting_counts_brackets_outside_strings_and_comments():
    """Two levels of arrays, with brackets in every kind of TOML string and in comments."""
    text = (
        'title = "[[[ \\" {{{"\n'
        "a = [[1], '[[[[', \"\"\"\n[[[\n\"\"\", '''\n{{{\n''']  # [[[[[\n"
        "[table]\n"
        "b = { c = 1 }\n"
    )
    assert tomllib.loads(text)["a"][0] == [1]
    assert nesting(text) == (2, 2)


def test_bad_variable_is_named(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("FVSLIDER_MAX_ELEMENTS", "lots")
    err = refused(tmp_path, FIG1, capsys)
    assert "environment: invalid limits, 1 problem" in err
    assert "FVSLIDER_MAX_ELEMENTS = 'lots': must be an integer from 1 to 2**53" in err


@pytest.mark.parametrize("text", ["1e11", "9007199254740992"])
def test_a_large_limit_is_enforced_without_allocating_it(tmp_path, capsys, monkeypatch, text):
    """A limit on scene bytes of 1e11 (100 GB) was allocated before the file was read (a
    MemoryError); the file is read in pieces, so any limit up to 2**53 costs nothing."""
    monkeypatch.setenv("FVSLIDER_MAX_SCENE_BYTES", text)
    admitted(tmp_path, FIG1, capsys)


@pytest.mark.parametrize("text", ["9.3e18", "9007199254740993", "1e400"])
def test_a_limit_beyond_two_to_the_53_is_named(tmp_path, capsys, monkeypatch, text):
    """9.3e18 overflowed the size of a read (an OverflowError); above 2**53 a float no
    longer holds every integer, so that is the largest limit."""
    monkeypatch.setenv("FVSLIDER_MAX_SCENE_BYTES", text)
    err = refused(tmp_path, FIG1, capsys)
    assert f"FVSLIDER_MAX_SCENE_BYTES = '{text}': must be an integer from 1 to 2**53" in err


def test_limits_from_python_are_bounded():
    with pytest.raises(ValueError, match="from 1 to 2"):
        Limits(scene_bytes=2**53 + 1)


@pytest.mark.parametrize("text,value", [("2_000", 2000), ("2e3", 2000), ("7", 7)])
def test_variables_take_integers_in_python_and_exponent_forms(text, value):
    assert Limits.from_environment({"FVSLIDER_MAX_STEPS": text}).steps == value


@pytest.mark.parametrize("text", ["0", "-3", "2.5", "1e-3", "nan", "inf", ""])
def test_variables_must_be_positive_integers(text):
    with pytest.raises(SceneError, match="FVSLIDER_MAX_STEPS"):
        Limits.from_environment({"FVSLIDER_MAX_STEPS": text})


def test_limits_from_python():
    path = SCENES / "rigid_lines.toml"
    with pytest.raises(SceneError, match="16 elements in all"):
        load_scene(path, limits=Limits(elements=15))
    scene = load_scene(path, limits=Limits(elements=16))
    with pytest.raises(SceneError, match="16 elements in all"):
        Model(scene, limits=Limits(elements=15))
    with pytest.raises(ValueError, match="limit elements must be an integer from 1 to 2"):
        Limits(elements=0)
