"""Malformed scenes (hypothesis): a valid shipped scene with one thing broken always gives one
SceneError that names where, never another exception.

Each mutation breaks one place, the ``target`` path (``slider[1].smearing`` style):

* an unknown key added to a table: the problem is at the new key;
* a value replaced by one of a wrong type, a non-finite number, a non-positive value where
  only positive ones are allowed, or an undefined name where a name is referred to: the
  problem is at that value (or inside it, for a list or table replaced whole);
* a key deleted: either the scene stays valid (an optional key whose default fits) or the
  problems are in the table that lost it (a required key is missing, or the default does not
  fit the rest of that table, e.g. a slider's offset); a deleted ``name`` may instead be
  missed where it is referred to.
"""

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_scenes import FILES, SCENES, data

from sliders.app.errors import SceneError
from sliders.app.model import Model
from sliders.app.scene import parse_scene

BASES = [p.stem for p in FILES]
#: Keys whose values must be > 0 (or >= 0: smearing, at; >= 1: counts).
POSITIVE = {
    "EA",
    "GAy",
    "GAz",
    "GJ",
    "EJy",
    "EJz",
    "mass",
    "mass_per_length",
    "radius",
    "turns",
    "tol",
    "smearing",
    "at",
    "elements",
    "num",
    "max_iterations",
    "load_steps",
}
#: Keys that refer to something by name.
REFERENCES = {"section", "line", "body", "node", "nodes", "beam", "of", "move"}
WRONG = [7, 2.5, True, "text", [1.0, "a"], {"x": 1.0}]


def places(value, path=""):
    """Every (path, container, key) in a TOML document, depth first."""
    items = (
        value.items()
        if isinstance(value, dict)
        else enumerate(value)
        if isinstance(value, list)
        else []
    )
    for key, child in items:
        where = f"{path}[{key}]" if isinstance(key, int) else (f"{path}.{key}" if path else key)
        yield where, value, key
        yield from places(child, where)


def key_of(path: str) -> str:
    """The last table key of a path (``slider[0].line[1]`` -> ``line``)."""
    return path.split(".")[-1].split("[")[0]


def wrong_types(value):
    """Replacements of another type than ``value``'s (ints and floats count as numbers)."""
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    return [
        w for w in WRONG if type(w) is not type(value) and not (number and type(w) in (int, float))
    ]


#: The mutations of :func:`mutations`; :data:`SIZES` also oversizes a count, a time step or an
#: array (with ``entries`` at most), or nests a value deeper than a scene may, and
#: ``perturbed`` scales a number (the scene may stay valid).
KINDS = ("unknown key", "wrong type", "non-finite", "non-positive", "undefined name", "deleted")
SIZES = ("huge", "deep", "perturbed")


@st.composite
def mutations(draw, load=data, kinds=KINDS, entries=None):
    """A broken scene (``load`` of a shipped scene's name), what was done, the target path and
    whether the problems may instead lie anywhere in the target's table (deletions)."""
    scene = load(draw(st.sampled_from(BASES)))
    spots = list(places(scene))
    tables = [("", scene, None)] + [s for s in spots if isinstance(s[1][s[2]], dict)]
    kind = draw(st.sampled_from(kinds))
    if kind in SIZES:
        return resized(draw, scene, spots, kind, entries)
    if kind == "unknown key":
        path, container, key = draw(st.sampled_from(tables))
        table = container[key] if key is not None else container
        new = draw(st.text("qwxz_", min_size=3, max_size=8))
        table[new] = 1.0
        return scene, kind, f"{path}.{new}" if path else new, False
    if kind == "wrong type":
        path, container, key = draw(st.sampled_from(spots))
        container[key] = draw(st.sampled_from(wrong_types(container[key])))
        return scene, kind, path, False
    if kind == "non-finite":
        numbers = [s for s in spots if isinstance(s[1][s[2]], float)]
        path, container, key = draw(st.sampled_from(numbers))
        container[key] = draw(st.sampled_from([math.nan, math.inf, -math.inf]))
        return scene, kind, path, False
    if kind == "non-positive":
        positive = [
            s for s in spots if key_of(s[0]) in POSITIVE and isinstance(s[1][s[2]], (int, float))
        ]
        if not positive:
            return scene, "none", "", False
        path, container, key = draw(st.sampled_from(positive))
        container[key] = draw(
            st.sampled_from([-1, -0.5] if key in ("smearing", "at") else [0, -1, 0.0, -2.5])
        )
        return scene, kind, path, False
    if kind == "undefined name":
        names = [
            s
            for s in spots
            if key_of(s[0]) in REFERENCES
            and isinstance(s[1][s[2]], str)
            and not s[0].startswith("line[")
        ]
        path, container, key = draw(st.sampled_from(names))
        container[key] = "nowhere"
        return scene, kind, path, False
    path, container, key = draw(st.sampled_from([s for s in spots if isinstance(s[2], str)]))
    del container[key]
    table = path.rpartition(".")[0] if "." in path and key != "name" else ""
    return scene, kind, table, True


def resized(draw, scene, spots, kind, entries):
    """The ``kind`` of :data:`SIZES` applied to ``scene``: a count (elements, samples) made
    ten billion, a dynamic study's step a billionth of its end time, or an array given one
    entry more than ``entries`` ("huge"); a value wrapped in 40 arrays, deeper than the 32
    levels a scene may nest ("deep"); a number scaled by a factor in [1/2, 2] ("perturbed")."""
    if kind == "huge":
        counts = [s for s in spots if key_of(s[0]) in ("elements", "num")]
        arrays = [s for s in spots if isinstance(s[1][s[2]], list) and s[1][s[2]]]
        study = scene["study"]
        steps = [("study.step", study, "step")] if study["kind"] == "dynamic" else []
        path, container, key = draw(st.sampled_from(counts + steps + arrays))
        value = container[key]
        if key == "step":
            container[key] = study["t_end"] * 1e-9
        elif isinstance(value, list):
            container[key] = value[:1] * (entries + 1)
        else:
            container[key] = 10**10
        return scene, kind, path, False
    if kind == "deep":
        path, container, key = draw(st.sampled_from(spots))
        for _ in range(40):
            container[key] = [container[key]]
        return scene, kind, path, False
    numbers = [s for s in spots if type(s[1][s[2]]) is float]
    path, container, key = draw(st.sampled_from(numbers))
    container[key] *= draw(st.floats(0.5, 2.0))
    return scene, kind, path, True


def inside(path: str, target: str) -> bool:
    return (
        not target
        or path == target
        or path.startswith(target + ".")
        or path.startswith(target + "[")
    )


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutations())
def test_one_clear_error_at_the_broken_place(mutation):
    scene, kind, target, anywhere_in_table = mutation
    try:
        Model(parse_scene(scene, SCENES, "mutated.toml"), "mutated.toml")
    except SceneError as exc:
        problems = exc.problems
        assert problems, str(exc)
        assert all(inside(p.path, target) for p in problems), (kind, target, str(exc))
        if not anywhere_in_table:
            assert target in str(exc)
        return
    assert kind in ("deleted", "none"), (kind, target)
