"""``fvslider check`` refuses what ``run`` would refuse, before anything is written: the back
end a scene asks for against its force elements and friction, a consistent mass of fv beams,
an axial element between coincident nodes, a stop its stroke never reaches; and warns of every
option the study ignores (``sliders/app/model.py``, ``sliders/app/ignored.py``)."""

import tomllib

import pytest
import tomli_w
from test_scenes import SCENES

from sliders.app.cli import main
from sliders.app.ignored import ignored_options
from sliders.app.scene import parse_scene


def scene(name: str) -> dict:
    return tomllib.loads((SCENES / f"{name}.toml").read_text())


def check(tmp_path, data: dict, capsys) -> tuple[int, str, str]:
    path = tmp_path / "scene.toml"
    path.write_text(tomli_w.dumps(data))
    code = main(["check", str(path), "--out", str(tmp_path / "out")])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]
    return code, out, err


def gear(**study) -> dict:
    data = scene("landing_gear")
    data["study"].update(t_end=0.01, **study)
    return data


def test_bordered_with_force_elements(tmp_path, capsys):
    code, _, err = check(tmp_path, gear(method="bordered"), capsys)
    assert code == 2
    assert "study.method: the scene has force elements, which runs on the condensed" in err


def test_bordered_with_friction_in_a_dynamic_study(tmp_path, capsys):
    data = gear(method="bordered")
    data["force"], data["output"]["probe"] = [], []
    data["slider"][0]["friction"] = {"mu": 0.1}
    code, _, err = check(tmp_path, data, capsys)
    assert code == 2 and "slider[0].friction: slider friction runs on the condensed" in err


def test_a_consistent_mass_of_fv_beams(tmp_path, capsys):
    code, _, err = check(tmp_path, gear(mass="consistent"), capsys)
    assert code == 2
    assert "study.mass = 'consistent': beam 'C' (fv3): finite-volume beams take the lumped" in err


def test_an_axial_element_between_coincident_nodes(tmp_path, capsys):
    data = gear()
    data["force"][0]["nodes"] = ["airframe", "C.start"]  # tied: the same point
    code, _, err = check(tmp_path, data, capsys)
    assert code == 2 and "force[0].nodes = ['airframe', 'C.start']: the nodes are 0 m apart" in err


def test_a_stop_beyond_the_extended_length(tmp_path, capsys):
    """The stroke ``extended - |x_b - x_a|`` is at most ``extended`` (0.45 m), where the nodes
    meet; a gas column long enough for 0.6 m leaves the law itself valid."""
    data = gear()
    data["force"][0]["law"].update(stroke_max=0.6, volume=2.8e-3)
    code, _, err = check(tmp_path, data, capsys)
    assert code == 2 and "force[0].law.stroke_max = 0.6: at or beyond the element's" in err


WARNED = {
    "slider[0].friction": lambda d: d["slider"][0].update(friction={"mu": 0.3}),
    "slider[0].kernel": lambda d: d["slider"][0].update(kernel="hat"),
    "study.planar": lambda d: d["study"].update(method="bordered", planar=True),
}


@pytest.mark.parametrize("key", WARNED)
def test_an_option_a_static_sweep_ignores_is_a_warning(tmp_path, capsys, key):
    data = scene("fig4_sliding_beams")
    WARNED[key](data)
    code, out, err = check(tmp_path, data, capsys)
    assert code == 0 and "valid" in out
    assert f"warning: {key}" in err and "ignore" in err


def test_options_a_dynamic_study_ignores():
    data = gear(every=10)
    data["slider"][0]["friction"] = {"mu": 0.1, "v_stribeck": 0.05}
    found = {p.path for p in ignored_options(parse_scene(data, SCENES))}
    assert found == {"study.every", "slider[0].friction.v_stribeck"}


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.toml")), ids=lambda p: p.name)
def test_the_shipped_scenes_set_no_ignored_option(path):
    assert ignored_options(parse_scene(tomllib.loads(path.read_text()), SCENES)) == []


@pytest.mark.parametrize(
    "change,path,message",
    [
        (lambda f: f[0]["law"].update(volume=1e-5), "force[0].law", "leaves no gas"),
        (lambda f: f[1].update(normal=[0.0, 0.0, 0.0]), "force[1].normal", "non-zero"),
        (lambda f: f[1].update(forward=[0.0, 0.0, 0.0]), "force[1].forward", "non-zero"),
    ],
)
def test_a_force_elements_part_is_named_by_its_key(tmp_path, capsys, change, path, message):
    """A gas column ``volume / area`` shorter than ``stroke_max`` (6 mm against 0.16 m) and
    a zero tyre direction are refused at the key that holds them, not at the element."""
    data = gear()
    change(data["force"])
    code, _, err = check(tmp_path, data, capsys)
    (line,) = err.splitlines()[1:]
    assert code == 2 and line.startswith(f"  {path}") and message in line, err
