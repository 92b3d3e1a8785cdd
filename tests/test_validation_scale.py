"""Validation is linear in the size of the scene: the largest scene the limits admit (a
file of ``FVSLIDER_MAX_SCENE_BYTES``, 1 MB, an array of up to ``FVSLIDER_MAX_ENTRIES``)
validates in about a second, whatever it repeats.  The repeat checks counted each entry over
the whole list (quadratic: 7.8 s at 20 000 entries, minutes at 90 000); they now keep a set
of the entries seen (:func:`sliders.app.checks.repeated`)."""

import time
import tomllib

import pytest
from test_scenes import SCENES

from sliders.app.checks import repeated, tied_parts
from sliders.app.errors import SceneError
from sliders.app.limits import Limits
from sliders.app.scene import load_scene, parse_scene

GEAR = (SCENES / "landing_gear.toml").read_text()
#: Seconds allowed for a 1 MB scene: about 0.5 s measured on an idle core; ten times that
#: leaves room for a loaded machine and is still a hundredth of the quadratic checks' time.
SECONDS = 5.0


def largest(text: str, marker: str, entry: str) -> str:
    """``text`` with ``marker`` replaced by ``entry`` repeated as often as the default limits
    allow: until the file has the most bytes, or the array the most entries."""
    room = Limits().scene_bytes - len(text.encode()) + len(marker) - 64
    count = min(room // (len(entry) + 2), Limits().entries - 8)  # 8: the array's others
    return text.replace(marker, ", ".join([entry] * count))


CASES = {
    "study.start.hold": (GEAR, '"airframe", "wheel"', '"airframe"'),
    "output.history": (GEAR, '"h", "iterations"', '"h"'),
    "output.nodes": (
        GEAR.replace("csv = []", 'csv = ["nodes"]\nnodes = { nodes = [C_NODES] }'),
        "C_NODES",
        '"C"',
    ),
}


@pytest.mark.parametrize("key", CASES)
def test_the_largest_scene_with_one_name_repeated_validates_in_about_a_second(tmp_path, key):
    text, marker, entry = CASES[key]
    path = tmp_path / "scene.toml"
    path.write_text(largest(text, marker, entry))
    assert path.stat().st_size <= Limits().scene_bytes
    start = time.perf_counter()
    with pytest.raises(SceneError) as info:
        load_scene(path)
    seconds = time.perf_counter() - start
    (problem,) = info.value.problems
    assert problem.path.startswith(key) and "more than once" in problem.message
    assert seconds < SECONDS


def test_repeated_names_each_value_once_in_order():
    assert repeated(["b", "a", "b", "c", "a", "b"]) == ["a", "b"]
    assert repeated([]) == [] and repeated(["x", "y"]) == []


def test_a_long_chain_of_ties_is_followed_in_one_pass():
    """200 bodies tied in a line: the first is joined to all of them (the search grew the
    group one tie per sweep over every tie: quadratic)."""
    data = tomllib.loads((SCENES / "fig1_cantilever.toml").read_text())
    n = 200
    data["body"] = [{"name": f"b{k}", "position": [0.0, 0.0, 0.0]} for k in range(n)]
    data["tie"] = [{"nodes": [f"b{k + 1}", f"b{k}"]} for k in reversed(range(n - 1))]
    scene = parse_scene(data, SCENES)
    assert tied_parts(scene, "b0") == {f"b{k}" for k in range(n)}
    assert tied_parts(scene, "cantilever") == {"cantilever"}
