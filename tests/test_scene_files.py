"""What a scene points to, checked by ``fvslider check`` as by ``run`` (issue 12, item 3).

A restart state is read and matched to the model (its dofs, its sliders and the unknowns of
each one's kind, every slider on its line, a time before ``t_end``); a damaged file is a
``ValueError`` naming it, whatever the damage (:meth:`State.load`, property-tested on mutated
bytes); every abscissa drive keeps its slider on its line from the start to ``t_end``, at
every time its motion may be least or greatest (``turning_times``, property-tested against
dense sampling).  ``check`` and ``run`` both exit 2 with the problem's line and write
nothing.

Sources of the numbers: the pushed-body scene (``studies/scenes/pushed_body.toml``: a
spherical slider on a cantilever of length 1 m, its drive from xi = 0.6 m at 0.035 m/s), the
model's own sizes, and the closed forms of the motions (a line, a table's vertices, the
quadratic that a not-a-knot cubic spline through four symmetric points is).
"""

import zipfile

import numpy as np
import numpy.lib.format as npy
import pytest
import tomli_w
from hypothesis import given, settings
from hypothesis import strategies as st
from test_scenes import SCENES, data

from sliders.app.cli import main
from sliders.app.model import Model
from sliders.app.scene import parse_scene
from sliders.joints.drives import Linear, Ramp, Tabulated
from sliders.solve.integrator import State

EPS = np.finfo(float).eps


def pushed(**study) -> dict:
    """The pushed-body scene, 1 s long, with ``study`` keys changed."""
    scene = data("pushed_body")
    scene["study"].update(t_end=1.0, **study)
    return scene


MODEL = Model(parse_scene(pushed(), SCENES, "pushed"), "pushed")
N_DOFS = MODEL.structure.n_dofs
(SLIDER,) = MODEL.sliders


def state(t: float = 0.5, n: int = N_DOFS, unknowns=((0.6, 0.0, 1.0, 0.0),)) -> State:
    """A state of the pushed-body model (or of another, with ``n`` dofs and ``unknowns``)."""
    return State(t, *(np.zeros(n) for _ in range(4)), [np.array(y) for y in unknowns], 0.05)


def checked(capsys, tmp_path, scene: dict, verb: str) -> tuple[int, str]:
    """``fvslider VERB`` of ``scene`` (written beside ``tmp_path / "out"``): the exit code
    and stderr, and nothing written whatever the outcome of ``check``."""
    path = tmp_path / "scene.toml"
    path.write_text(tomli_w.dumps(scene))
    before = sorted(p.name for p in tmp_path.iterdir())
    code = main([verb, str(path), "--out", str(tmp_path / "out")])
    if code != 0 or verb == "check":
        assert sorted(p.name for p in tmp_path.iterdir()) == before
    return code, capsys.readouterr().err


def test_a_state_of_this_model_is_read_once_and_started_from(tmp_path, capsys):
    state().save(tmp_path / "state.npz")
    scene = pushed(restart=str(tmp_path / "state.npz"))
    assert checked(capsys, tmp_path, scene, "check")[0] == 0
    model = Model(parse_scene(scene, SCENES, "r"), "r")
    assert model.restart is not None and model.restart.t == 0.5
    np.testing.assert_array_equal(model.restart.unknowns[0], [0.6, 0.0, 1.0, 0.0])


def npz(path, **arrays) -> None:
    with open(path, "wb") as stream:
        np.savez(stream, **arrays)


def saved(**changes) -> dict:
    """The arrays :meth:`State.save` writes for :func:`state`, with ``changes``."""
    arrays = dict(
        t=np.array(0.5),
        q=np.zeros(N_DOFS),
        v=np.zeros(N_DOFS),
        a=np.zeros(N_DOFS),
        qdd=np.zeros(N_DOFS),
        h=np.array(0.05),
        sizes=np.array([4]),
        unknowns=np.array([0.6, 0.0, 1.0, 0.0]),
    )
    arrays.update(changes)
    return {k: v for k, v in arrays.items() if v is not None}


DAMAGED = {
    "missing": (lambda p: None, "{p}: no such file"),
    "a directory": (lambda p: p.mkdir(), "{p}: a directory, not a saved integrator state"),
    "text": (
        lambda p: p.write_text("q = [0, 0]"),
        "{p}: not a saved integrator state (File is not a zip file)",
    ),
    "cut in half": (
        lambda p: (state().save(p), p.write_bytes(p.read_bytes()[: p.stat().st_size // 2])),
        "{p}: not a saved integrator state (File is not a zip file)",
    ),
    "an array missing": (
        lambda p: npz(p, **saved(unknowns=None)),
        "{p}: not a saved integrator state (no array 'unknowns')",
    ),
    "objects": (
        lambda p: npz(p, **saved(q=np.array([None] * N_DOFS))),
        f"{{p}}: not a saved integrator state ('q' is an array of object and shape ({N_DOFS},);"
        " a saved state's is real and 1-dimensional)",
    ),
    "sizes that do not add up": (
        lambda p: npz(p, **saved(sizes=np.array([3]))),
        "{p}: not a saved integrator state (its slider sizes [3] do not add up to its 4 unknowns)",
    ),
    "not finite": (
        lambda p: npz(p, **saved(v=np.full(N_DOFS, np.nan))),
        "{p}: not a saved integrator state (v is not finite)",
    ),
    "another model's dofs": (
        lambda p: state(n=N_DOFS + 6).save(p),
        f"{{p}} is a state of another model: {N_DOFS + 6} dofs, where this scene has {N_DOFS}",
    ),
    "another model's sliders": (
        lambda p: state(unknowns=()).save(p),
        "{p} is a state of another model: 0 sliders, where this scene has 1",
    ),
    "another kind of slider": (
        lambda p: state(unknowns=[np.r_[0.6, np.zeros(5)]]).save(p),
        f"{{p}} is a state of another model: 6 unknowns for slider 'push', a spherical slider "
        f"with {SLIDER.n_unknowns} here",
    ),
    "a slider off its line": (
        lambda p: state(unknowns=[(1.5, 0.0, 1.0, 0.0)]).save(p),
        "puts slider 'push' at xi = 1.5 m, outside its line 'cantilever' [0, 1] m",
    ),
}


@pytest.mark.parametrize("verb", ["check", "run"])
@pytest.mark.parametrize("case", DAMAGED, ids=str)
def test_a_restart_file_that_is_not_a_state_of_this_model(tmp_path, capsys, case, verb):
    make, message = DAMAGED[case]
    (tmp_path / "files").mkdir()
    path = tmp_path / "files" / "state.npz"
    make(path)
    code, err = checked(capsys, tmp_path, pushed(restart=str(path)), verb)
    assert code == 2
    assert err.endswith(f"invalid scene, 1 problem\n  study.restart: {message.format(p=path)}\n")


@pytest.mark.parametrize("verb", ["check", "run"])
def test_a_restart_state_at_or_after_t_end(tmp_path, capsys, verb):
    state(t=1.0).save(tmp_path / "state.npz")
    code, err = checked(capsys, tmp_path, pushed(restart=str(tmp_path / "state.npz")), verb)
    assert code == 2
    assert err.endswith("study.t_end = 1.0: must be after the restart state's time, t = 1 s\n")


def test_a_header_claiming_more_data_than_the_file_holds_allocates_nothing(tmp_path):
    """A ``q`` whose header claims 10^12 numbers (8 TB) over 24 bytes of data."""
    path = tmp_path / "state.npz"
    with zipfile.ZipFile(path, "w") as archive:
        for name, value in saved().items():
            with archive.open(f"{name}.npy", "w") as member:
                if name == "q":
                    header = {"descr": "<f8", "fortran_order": False, "shape": (10**12,)}
                    npy.write_array_header_1_0(member, header)
                    member.write(np.zeros(3).tobytes())
                else:
                    npy.write_array(member, value)
    with pytest.raises(ValueError, match=r"'q' claims more data than the archive holds"):
        State.load(path)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(data=st.data())
def test_any_damage_to_a_state_file_is_a_value_error_naming_it(tmp_path_factory, data):
    """Bytes overwritten, cut, or both, anywhere in a saved state: ``State.load`` returns a
    state or raises ``ValueError`` starting with the file's name, never anything else."""
    directory = tmp_path_factory.mktemp("damaged", numbered=True)
    source = directory / "good.npz"
    state().save(source)
    content = bytearray(source.read_bytes())
    for _ in range(data.draw(st.integers(0, 4), label="overwrites")):
        at = data.draw(st.integers(0, len(content) - 1), label="at")
        content[at] = data.draw(st.integers(0, 255), label="byte")
    content = content[: data.draw(st.integers(0, len(content)), label="length")]
    path = directory / "damaged.npz"
    path.write_bytes(bytes(content))
    try:
        loaded = State.load(path)
    except ValueError as exc:
        assert str(exc).startswith(f"{path}: ")
    else:
        assert isinstance(loaded, State)


def abscissa_drive(motion: dict) -> dict:
    scene = pushed()
    scene["drive"][0]["motion"] = motion
    return scene


OFF_THE_LINE = {
    # (cosine ramps and tables: motions that start from rest, as the body does)
    # starts beyond the end of the 1 m cantilever
    "starts outside": (
        {"kind": "ramp", "start": 1.5, "end": 0.9, "t0": 0.0, "t1": 1.0},
        "xi = 1.5 m at t = 0 s",
    ),
    # half way up a rise of 1 m from 0.6 m over 2 s at t_end = 1 s: 1.1 m
    "leaves before t_end": (
        {"kind": "ramp", "start": 0.6, "end": 1.6, "t0": 0.0, "t1": 2.0},
        "xi = 1.1 m at t = 1 s",
    ),
    # a ramp to 1.2 m done by t1 = 0.5 s, before t_end
    "ramps out": (
        {"kind": "ramp", "start": 0.6, "end": 1.2, "t0": 0.0, "t1": 0.5},
        "xi = 1.2 m at t = 1 s",
    ),
    # out and back in between the table's ends: caught at its vertex
    "a table out and back": (
        {"kind": "tabulated", "times": [0.0, 0.4, 0.8], "values": [0.6, 1.05, 0.6], "order": 1},
        "xi = 1.05 m at t = 0.4 s",
    ),
    # the not-a-knot cubic through 4 points symmetric about t = 0.3 is the quadratic
    # 0.6 + a t (0.6 - t), a = 0.39 / 0.08: every value <= 0.99, its top 1.03875 at 0.3 s
    "a cubic table that overshoots": (
        {
            "kind": "tabulated",
            "times": [0.0, 0.2, 0.4, 0.6],
            "values": [0.6, 0.99, 0.99, 0.6],
            "order": 3,
        },
        "xi = 1.03875 m at t = 0.3 s",
    ),
}


@pytest.mark.parametrize("verb", ["check", "run"])
@pytest.mark.parametrize("case", OFF_THE_LINE, ids=str)
def test_an_abscissa_drive_off_its_line(tmp_path, capsys, case, verb):
    motion, where = OFF_THE_LINE[case]
    code, err = checked(capsys, tmp_path, abscissa_drive(motion), verb)
    assert code == 2
    assert err.endswith(
        f"invalid scene, 1 problem\n  drive[0].motion: takes slider 'push' to {where}, "
        "outside its line 'cantilever' [0, 1] m\n"
    )


def test_an_abscissa_drive_is_checked_from_the_restart_time(tmp_path, capsys):
    """A table that is off the line only before the restart state's time, 0.5 s."""
    state().save(tmp_path / "state.npz")
    motion = {"kind": "tabulated", "times": [0.0, 0.5], "values": [1.2, 0.6], "order": 1}
    scene = abscissa_drive(motion)
    scene["study"]["restart"] = str(tmp_path / "state.npz")
    assert checked(capsys, tmp_path, scene, "check")[0] == 0
    del scene["study"]["restart"]
    assert checked(capsys, tmp_path, scene, "check")[0] == 2


def motions():
    """Motions of every kind with random parameters (tables: 2 to 8 points at least 0.1 s
    apart, values in [-1, 1])."""
    value = st.floats(-1, 1)
    linear = st.builds(Linear, value, value, value)
    ramp = st.builds(
        lambda a, b, t0, span, shape: Ramp(a, b, t0, t0 + span, shape),
        value,
        value,
        value,
        st.floats(0.1, 2),
        st.sampled_from(["linear", "cosine"]),
    )
    table = st.integers(4, 8).flatmap(
        lambda n: st.tuples(
            st.lists(st.floats(0.1, 1), min_size=n - 1, max_size=n - 1),
            st.lists(value, min_size=n, max_size=n),
            st.sampled_from([1, 3]),
        )
    )
    tabulated = table.map(lambda x: Tabulated(np.cumsum([0.0, *x[0]]) - 1, np.array(x[1]), x[2]))
    return st.one_of(linear, ramp, tabulated)


def roundoff(motion, start: float, end: float) -> float:
    """A bound on the roundoff of evaluating ``motion`` on [start, end]: 8 eps times the
    largest sum of the magnitudes of the terms it adds (a cubic piece's coefficients times
    powers of its length; a line's start and its travel; a ramp's start and rise; a linear
    table's values)."""
    spline = getattr(motion, "_spline", None)
    if spline is not None:
        lengths = np.diff(spline.x)
        powers = lengths[None, :] ** np.arange(3, -1, -1)[:, None]
        terms = float(np.max(np.sum(np.abs(spline.c) * powers, axis=0)))
    elif isinstance(motion, Linear):
        travel = max(abs(start - motion.t0), abs(end - motion.t0))
        terms = abs(motion.start) + abs(motion.velocity) * travel
    elif isinstance(motion, Ramp):
        terms = abs(motion.start) + abs(motion.end - motion.start)
    else:
        terms = 3 * float(np.max(np.abs(motion.values)))
    return 8 * EPS * terms


@settings(max_examples=200, deadline=None, derandomize=True)
@given(motion=motions(), start=st.floats(-2, 2), span=st.floats(0.01, 3))
def test_turning_times_hold_the_least_and_greatest_value(motion, start, span):
    """Over [start, start + span] no time sampled densely gives a value beyond those at the
    motion's turning times (to the roundoff of evaluating it)."""
    end = start + span
    times = motion.turning_times(start, end)
    assert times[0] == start and times[1] == end and np.all((times >= start) & (times <= end))
    at_turns = [motion(t)[0] for t in times]
    sampled = [motion(t)[0] for t in np.linspace(start, end, 2001)]
    tol = roundoff(motion, start, end)
    assert min(at_turns) - tol <= min(sampled) and max(sampled) <= max(at_turns) + tol
