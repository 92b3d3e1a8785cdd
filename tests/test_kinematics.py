"""A scene's kinematics (``kinematics = "exact" | "linear" | "auto"``) through ``fvslider run``
and ``sliders.app.run.run``: the exact path against the elastica, the linear path kept at
small loads, the refusals naming the scene item.

Tolerances:

* elastica: the fv3 error falls as ``h^4`` (measured, ``tests/test_exact_statics.py``), so
  the error of ``n`` elements is estimated by Richardson from ``n`` and ``2n``,
  ``|u_n - u_2n| 2^4 / (2^4 - 1)``; twice that is allowed (its own higher-order terms), plus
  the model's difference from the inextensible rod, ``P L / GA + P L / EA``;
* roll-up: a converged state is off by the solver's round-off floor: ``16 eps`` per element
  length in the positions' sums, with the Newton corrections of a few times it;
* linear limit: the exact-minus-linear difference is second order in the load with a next term
  of relative size ``theta^2`` (``theta = P L^2 / 2 EJ = 5e-4``): the measured slope is 2 to
  ``theta^2 / ln 2 < 1e-6``; 1e-4 is allowed.
"""

import csv

import numpy as np
import pytest
from test_scenes import SCENES

from fvbeam import rotations
from fvbeam.elastica import tip_loaded_cantilever
from sliders.app.cli import main
from sliders.app.errors import SceneError
from sliders.app.kinematics import neglected, unsupported
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene

EPS = np.finfo(float).eps
STIFF = 1e8  # EA = GA, in units of EJ / L^2


def cantilever(
    elements: int = 10,
    force: float = 10.0,
    moment: float = 0.0,
    kinematics: str | None = None,
    factors: tuple[float, ...] | None = None,
    extra: str = "",
) -> str:
    """A unit fv3 cantilever along x, EJ = 1, a dead tip force along y and couple about z."""
    head = f'kinematics = "{kinematics}"\n' if kinematics else ""
    study = (
        f'kind = "sweep"\nparameter = {{ kind = "load_factor" }}\nvalues = {list(factors)}'
        if factors
        else 'kind = "static"'
    )
    return f"""{head}title = "cantilever"
formulation = "fv3"
[[section]]
name = "rod"
EA = {STIFF}
GAy = {STIFF}
GAz = {STIFF}
GJ = 1.0
EJy = 1.0
EJz = 1.0
[[beam]]
name = "rod"
section = "rod"
straight = {{ start = [0.0, 0.0, 0.0], end = [1.0, 0.0, 0.0], elements = {elements} }}
[[support]]
node = "rod.start"
[[load]]
kind = "nodal"
node = "rod.end"
force = [0.0, {force!r}, 0.0]
moment = [0.0, 0.0, {moment!r}]
{extra}
[study]
{study}
[output]
csv = ["samples", "nodes", "internal_forces", "reactions"]
"""


def run_scene(tmp_path, text: str, capsys, name: str = "scene") -> tuple[int, str, str]:
    """``fvslider run`` of the scene ``text``: exit code, stdout, stderr."""
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    code = main(["run", "--out", str(tmp_path / name), str(path)])
    out, err = capsys.readouterr()
    return code, out, err


def tips(tmp_path, name: str = "scene") -> np.ndarray:
    """Each sample's tip ``[x, y, z, rx, ry, rz]`` (current position, rotation vector)."""
    with open(tmp_path / name / "nodes.csv", newline="") as file:
        rows = [r for r in csv.DictReader(file) if float(r["xi"]) == 1.0]
    return np.array(
        [
            [float(r[c]) + float(r[d]) for c, d in zip("xyz", ("ux", "uy", "uz"), strict=True)]
            + [float(r[c]) for c in ("rx", "ry", "rz")]
            for r in rows
        ]
    )


def test_elastica_sweep_takes_the_exact_path_and_matches_the_closed_form(tmp_path, capsys):
    """P L^2 / EJ = 1, 2, 5, 10 as a load-factor sweep of a 10-element fv3 cantilever: auto
    sees the linear answer's 5 rad and solves exactly; the tips are the elastica's."""
    factors = (0.1, 0.2, 0.5, 1.0)
    code, out, _ = run_scene(tmp_path, cantilever(factors=factors), capsys, "coarse")
    assert code == 0
    assert "kinematics: exact (auto: the linear answer's largest rotation 5 rad" in out
    code, out, _ = run_scene(tmp_path, cantilever(20, factors=factors), capsys, "fine")
    assert code == 0
    coarse, fine = tips(tmp_path, "coarse"), tips(tmp_path, "fine")
    for k, factor in enumerate(factors):
        load = 10.0 * factor
        closed = tip_loaded_cantilever(load)
        exact = np.array([1 - closed.shortening, closed.deflection, closed.rotation])
        ours = coarse[k, [0, 1, 5]]
        richardson = np.abs(coarse[k] - fine[k])[[0, 1, 5]] * 16 / 15
        model = 2 * load / STIFF
        assert np.all(np.abs(ours - exact) <= 2 * richardson + model), (load, ours - exact)
    assert abs(coarse[-1, 1] - 0.81061) < 1e-3  # Mattiasson's deflection, not 3.33 m


def test_roll_up_through_a_scene(tmp_path, capsys):
    """An end couple 2 pi EJ / L rolls the rod into a circle: the tip back at the root."""
    n = 8
    code, out, _ = run_scene(tmp_path, cantilever(n, 0.0, 2 * np.pi, "exact"), capsys)
    assert code == 0, out
    assert "kinematics: exact (asked)" in out
    tip = tips(tmp_path)[0]
    # Newton stops at a residual of at most 1e-12 (solve_static's tolerance) times the load
    # in each of the 6 n free dofs; the rod's flexibility has no entry above L^3 / EJ = 1
    # (a straight cantilever's largest is L^3 / 3 EJ, the circle's is of the same order)
    converged = 6 * n * 1e-12 * 2 * np.pi
    np.testing.assert_allclose(tip[:3], 0.0, atol=converged + 4 * 16 * EPS * n)
    assert np.linalg.norm(tip[3:]) < 1e-6  # a full turn: the identity rotation


def test_small_load_keeps_the_linear_answer_and_says_so(tmp_path, capsys):
    """At P L^2 / EJ = 1e-9 the bound (about 4e-10) is within tol = 1e-8: auto keeps the
    linear answer, the same as linear kinematics."""
    code, out, _ = run_scene(tmp_path, cantilever(force=1e-9), capsys, "auto")
    assert code == 0
    assert "kinematics: linear (auto: largest rotation 5e-10 rad" in out
    assert "within the study's tol 1e-08" in out
    code, out, _ = run_scene(tmp_path, cantilever(force=1e-9, kinematics="linear"), capsys, "lin")
    assert code == 0 and "kinematics" not in out
    for table in ("nodes", "internal_forces", "reactions"):
        auto = (tmp_path / "auto" / f"{table}.csv").read_text()
        assert auto == (tmp_path / "lin" / f"{table}.csv").read_text()


def test_linear_beyond_its_bound_warns_with_the_number(tmp_path, capsys):
    code, out, err = run_scene(tmp_path, cantilever(kinematics="linear"), capsys)
    assert code == 0
    assert "warning: kinematics linear: largest rotation 5 rad" in err
    # the linear answer kept, P L^3 / 3 EJ, to the rounding of a stiffness of condition
    # EA L^2 / EJ n^2 = 1e10 (2e-6)
    assert tips(tmp_path)[0, 1] == pytest.approx(10 / 3, rel=1e-5)


def test_exact_and_linear_differ_at_second_order(tmp_path):
    """The exact-minus-linear tip difference at P = 1e-3 and 2e-3 (Python entry point, both
    kinematics on one scene): slope 2, and the bound of ``auto`` above it."""
    path = tmp_path / "small.toml"
    differences = []
    loads = (1e-3, 2e-3)
    for P in loads:
        path.write_text(cantilever(4, P))
        model = Model(load_scene(path))
        q = {}
        for kind in ("linear", "exact"):
            results = run(model, progress=False, kinematics=kind)
            q[kind] = results.samples[0].solution.q
        differences.append(np.abs(q["exact"] - q["linear"]).max())
        bound = run(model, progress=False, kinematics="linear").kinematics
        eta = float(bound.split("neglected terms by ")[1].split(" ")[0])
        assert (
            np.abs(q["exact"] - q["linear"]).reshape(-1, 6)[:, :3].max()
            <= eta * np.abs(q["linear"]).reshape(-1, 6)[:, :3].max()
        )
    slope = np.log(differences[1] / differences[0]) / np.log(2)
    assert abs(slope - 2) < 1e-4


def test_exact_refuses_what_it_does_not_carry_naming_the_item(tmp_path, capsys):
    def cubic(text: str) -> str:
        return text.replace('formulation = "fv3"', 'formulation = "cubic"')

    path = tmp_path / "scene.toml"
    path.write_text(cubic(cantilever(kinematics="exact")))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "formulation: the cubic element: exact kinematics does not carry it" in err
    # the Python argument refuses it as the key does
    model = Model(load_scene(_auto(path)))
    with pytest.raises(SceneError, match=r"formulation: the cubic element"):
        run(model, progress=False, kinematics="exact")
    # auto takes it linearly and says why
    code, out, _ = run_scene(tmp_path, cubic(cantilever()), capsys, "auto")
    assert code == 0
    assert "kinematics: linear (auto: the exact path does not carry formulation, the cubic" in out


def _auto(path):
    """The scene at ``path`` with its kinematics key removed (default auto)."""
    auto = path.with_name("auto.toml")
    auto.write_text(path.read_text().replace('kinematics = "exact"\n', ""))
    return auto


def test_shipped_scenes_take_the_path_their_bound_says():
    """Under auto, every scene of studies/scenes but the elastica and the heavy cantilever
    (the exact path's examples, tested above), the spline slider's twist test (a slider on a
    chain, tested in ``tests/test_exact_slider_scenes.py``) and those with joints (exact
    only) either has an item the exact path does not carry (sliders on rigid lines or with
    friction, drives, dynamics) and keeps its linear answer, or is the arch under its weight
    (a distributed load), whose linear answer's bound (4.4e-4 of its displacement) is above
    the study's ``tol`` (1e-8): auto solves it exactly, and the two answers differ by the
    bound's size, a second-order difference (measured 1.06 times the bound, which is of
    leading order: 2 allowed)."""
    for path in sorted(SCENES.glob("*.toml")):
        scene = load_scene(path)
        if path.stem in ("elastica", "heavy_cantilever", "spline_slider") or scene.joint:
            continue
        assert scene.kinematics == "auto"
        if unsupported(scene) is None:
            assert path.stem in ("arch", "arch_mesh")
            linear = run(Model(scene), progress=False, kinematics="linear")
            auto = run(Model(scene), progress=False)
            assert auto.kinematics.startswith("kinematics: exact (auto: the linear answer's")
            sample = linear.samples[0]
            bound = neglected(sample.statics.structure, sample.solution.q)
            moved = (sample.solution.q - auto.samples[0].solution.q).reshape(-1, 6)[:, :3]
            assert bound.eta > scene.study.tol
            assert np.abs(moved).max() <= 2 * bound.eta * bound.displacement


def read(path) -> list[dict]:
    with open(path, newline="") as file:
        return list(csv.DictReader(file))


def test_outputs_of_an_exact_state(tmp_path, capsys):
    """P L^2 / EJ = 10: the internal forces are the tip force wherever the point is (the
    region balances make each point's force the resultant of the loads beyond it), in global
    axes and, by its length, in the turned section frame; the clamp's couple is the tip
    force's about the root at the tip's current place; the VTU holds the current positions
    (points plus displacement) and the rotation matrices.  Tolerance: the residual's
    round-off floor, ``16 eps`` times its terms, the largest ``EA |x'|`` (2e8), about 7e-7."""
    text = cantilever().replace('csv = ["samples"', 'vtu = true\ncsv = ["samples"')
    code, out, _ = run_scene(tmp_path, text, capsys)
    assert code == 0, out
    floor = 16 * EPS * (10 + 2 * STIFF)
    tip = tips(tmp_path)[0]
    forces = read(tmp_path / "scene" / "internal_forces.csv")
    assert len(forces) == 20  # two evaluation points per fv3 element
    for row in forces:
        np.testing.assert_allclose(
            [float(row[c]) for c in ("Fx", "Fy", "Fz")], [0, 10, 0], atol=floor
        )
        local = np.hypot(float(row["N"]), float(row["V2"]))
        assert abs(local - 10) <= floor and abs(float(row["V3"])) <= floor
    (reaction,) = read(tmp_path / "scene" / "reactions.csv")
    np.testing.assert_allclose(
        [float(reaction[c]) for c in ("fx", "fy", "mz")], [0, -10, -10 * tip[0]], atol=floor
    )
    assert tip[0] == pytest.approx(1 - 0.555, abs=1e-3)  # not the linear -10 N m at x = 1
    import meshio

    mesh = meshio.read(tmp_path / "scene" / "states" / "step_000000.vtu")
    nodes = len(mesh.cells[0].data) * 2 + 1  # fv3: vertices and mid nodes
    current = mesh.points[:nodes] + mesh.point_data["displacement"][:nodes]
    end = int(np.argmax(mesh.points[:nodes, 0]))
    np.testing.assert_allclose(current[end], tip[:3], atol=floor)
    R = mesh.point_data["rotation_matrix"][end].reshape(3, 3)
    c, s = np.cos(tip[5]), np.sin(tip[5])
    np.testing.assert_allclose(R, [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=4 * EPS)
    global_forces = mesh.cell_data["force_global"][1]  # the recovery points' block
    np.testing.assert_allclose(global_forces, np.tile([0, 10, 0], (20, 1)), atol=floor)


def test_linear_tables_carry_the_global_axes_too(tmp_path, capsys):
    """A beam along x with up z has the section frame (x, y, z): its global columns are its
    section columns."""
    code, _, _ = run_scene(tmp_path, cantilever(force=1.0, kinematics="linear"), capsys)
    assert code == 0
    for row in read(tmp_path / "scene" / "internal_forces.csv"):
        for local, world in zip(
            ("N", "V2", "V3", "T", "M2", "M3"), ("Fx", "Fy", "Fz", "Mx", "My", "Mz"), strict=True
        ):
            assert float(row[world]) == pytest.approx(float(row[local]), abs=1e-12)


def test_renders_do_not_shrink_a_large_deflection():
    """The automatic magnification draws the largest elastic displacement as a tenth of the
    structure's size, and never below 1: a deflection of 0.8 of a unit beam is drawn as it
    is, one of 1e-3 magnified 100 times."""
    from fvbeam import Beam, Section, Structure, straight
    from sliders.app.render import magnification_for

    section = Section.diagonal(EA=1.0, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)
    structure = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), section, "fv3")])
    q = np.zeros(structure.n_dofs)
    q[-5] = 0.8
    assert magnification_for(structure, q, None) == 1.0
    assert magnification_for(structure, q * 1.25e-3, None) == pytest.approx(100.0)


def test_the_benchmark_writes_its_rows(tmp_path, capsys):
    """The shape of studies.bench_kinematics --quick, never its speed: both kinematics timed,
    the path auto took (linear, on scenes chosen to stay linear) and its bound."""
    import json

    from studies.bench_kinematics import main as bench

    out = tmp_path / "bench.json"
    bench(["--out", str(out), "--quick"])
    rows = json.loads(out.read_text())["kinematics"]
    assert [r["scene"] for r in rows] == ["sliders", "cantilever"]
    for r in rows:
        assert r["path"] == "linear" and r["linear_s"] > 0 and r["auto_s"] > 0
    assert rows[1]["eta"] < 1e-8 and rows[1]["tip_rel_error"] >= 0
    assert "the bound alone" in capsys.readouterr().out


def test_a_dynamic_study_says_it_stays_linear(tmp_path, capsys):
    """The exact path carries no dynamics: auto integrates linearly and says so, with the
    last state's bound."""
    text = (
        cantilever(force=1e-3)
        .replace("EJz = 1.0\n", "EJz = 1.0\nmass_per_length = 1.0\ninertia = [1e-3, 1e-3, 1e-3]\n")
        .replace('kind = "static"', 'kind = "dynamic"\nt_end = 0.002\nstep = 0.001')
    )
    code, out, _ = run_scene(tmp_path, text, capsys)
    assert code == 0, out
    assert "kinematics: linear (auto: the exact path does not carry study.kind, a dynamic" in out


def test_a_point_load_at_a_node_is_that_nodes_load(tmp_path, capsys):
    """On the exact path a point load at the tip is the tip's nodal load (the same tables);
    one between nodes is carried too (``tests/test_exact_loads.py`` checks its answer)."""
    nodal = cantilever(force=5.0, kinematics="exact")
    at_tip = 'kind = "point"\nbeam = "rod"\nat = 1.0'
    point = nodal.replace('kind = "nodal"\nnode = "rod.end"', at_tip)
    assert run_scene(tmp_path, nodal, capsys, "nodal")[0] == 0
    assert run_scene(tmp_path, point, capsys, "point")[0] == 0
    for table in ("nodes", "internal_forces", "reactions"):
        nodes = (tmp_path / "nodal" / f"{table}.csv").read_text()
        assert nodes == (tmp_path / "point" / f"{table}.csv").read_text()
    between = point.replace("at = 1.0", "at = 0.53")
    assert run_scene(tmp_path, between, capsys, "between")[0] == 0


def test_without_a_converged_linear_answer_auto_says_so(tmp_path):
    from sliders.app.run_exact import choose

    path = tmp_path / "scene.toml"
    path.write_text(cantilever())
    choice = choose(Model(load_scene(path)), "auto", [], "scene")
    assert not choice.exact
    assert choice.statement == "kinematics: linear (auto: no converged linear answer to bound)"


def test_heavy_cantilever_scene_takes_the_exact_path_and_matches_its_elastica(tmp_path, capsys):
    """studies/scenes/heavy_cantilever.toml (gravity on a static study, w L^3 / EJ = 10):
    auto sees the linear answer's 1.67 rad and solves exactly, the weight a dead distributed
    load on the current configuration; the tip is the heavy elastica's
    (:func:`fvbeam.elastica.heavy_cantilever`) within twice the Richardson estimate of 8
    against 16 fv3 elements (order 4, ``tests/test_exact_loads.py``) plus the model's share,
    ``w L^2 / GA + w L^2 / EA``."""
    from fvbeam.elastica import heavy_cantilever

    text = (SCENES / "heavy_cantilever.toml").read_text()
    code, out, _ = run_scene(tmp_path, text, capsys, "coarse")
    assert code == 0
    assert "kinematics: exact (auto: the linear answer's largest rotation 1.67 rad" in out
    fine = text.replace("elements = 8", "elements = 16")
    assert run_scene(tmp_path, fine, capsys, "fine")[0] == 0
    coarse, fine_tip = tips(tmp_path, "coarse")[0], tips(tmp_path, "fine")[0]
    closed = heavy_cantilever(10.0)
    exact = np.array([1 - closed.shortening, -closed.deflection, -closed.rotation])
    richardson = np.abs(coarse - fine_tip)[[0, 1, 5]] * 16 / 15
    model = 2 * 9.81 / STIFF
    assert np.all(np.abs(coarse[[0, 1, 5]] - exact) <= 2 * richardson + model)


def test_a_modes_study_refuses_loads_between_nodes_under_exact(tmp_path, capsys):
    """Modes about an exact state take the structure's tangent, which holds no load
    stiffness: a modes study with a distributed load is refused under exact, naming it."""
    distributed = '[[load]]\nkind = "distributed"\nbeam = "rod"\nforce = [0.0, 1.0, 0.0]\n'
    text = (
        cantilever(kinematics="exact", extra=distributed)
        .replace('kind = "static"', 'kind = "modes"\ncount = 2')
        .replace("EJz = 1.0\n", "EJz = 1.0\nmass_per_length = 1.0\n", 1)
    )
    path = tmp_path / "modes.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    assert "load[1]: in a modes study, a load between nodes" in capsys.readouterr().err


STRUT = (
    '{ kind = "strut", area = 1.6e-3, pressure = 4.1e5, volume = 2.8e-4, exponent = 1.3, '
    "compression = 5000.0, rebound = 20000.0, stop_stiffness = 1e8, stroke_max = 0.16 }"
)


def test_a_force_element_between_exact_nodes(tmp_path, capsys):
    """A strut from the tip of a rod along x (``EA = 1e5``, 4 fv3 elements) to a held body
    0.4 m beyond it, extended 0.45 m: it pushes the tip back along the rod, and the tip's
    displacement ``u`` solves ``EA u / L = -F(0.05 + u)`` with the strut's law
    (:class:`sliders.forces.laws.Strut`; scipy's ``brentq`` to 1e-14): the beam is
    compressed uniformly, which its fv3 elements represent exactly, so the exact path is held
    to the solver's round-off (the force's terms, ``16 eps`` each, over ``EA / L``), and
    the linear path, with the same element, gives the same answer."""
    import scipy.optimize

    from sliders.forces.laws import Strut

    law = Strut(1.6e-3, 4.1e5, 2.8e-4, 1.3, 5000.0, 20000.0, 1e8, 0.16)
    EA = 1e5
    u = scipy.optimize.brentq(lambda u: EA * u + law(0.05 + u, 0.0)[0], -0.04, 0.0, xtol=1e-14)
    strut = (
        '[[body]]\nname = "anchor"\nposition = [1.4, 0.0, 0.0]\n\n'
        '[[support]]\nnode = "anchor"\n\n'
        '[[force]]\nkind = "axial"\nname = "strut"\nnodes = ["rod.end", "anchor"]\n'
        f"extended = 0.45\nlaw = {STRUT}\n"
    )
    text = cantilever(4, force=0.0, extra=strut).replace(f"EA = {STIFF}", f"EA = {EA}")
    assert f"EA = {EA}" in text
    for kinematics in ("exact", "linear"):
        scene = text.replace('title = "cantilever"', f'kinematics = "{kinematics}"\ntitle = "c"')
        code, out, err = run_scene(tmp_path, scene, capsys, kinematics)
        assert code == 0, err
        row = next(r for r in read(tmp_path / kinematics / "nodes.csv") if r["xi"] == "1.0")
        force = abs(law(0.05 + u, 0.0)[0])
        error = float(row["ux"]) - u
        assert abs(error) <= 64 * EPS * force / EA + 16 * EPS, (kinematics, error)


@pytest.mark.parametrize("offset", [False, True])
def test_a_pendulum_hangs_along_gravity(tmp_path, capsys, offset):
    """A bob on a revolute joint to the ground (about z), 1.5 m below it, under a gravity
    tilted by ``atan(9.81)`` from the vertical: it swings through 1.47 rad to hang along
    gravity.  The bob is its node (its weight at it), or a body whose node is at the pin and
    whose centre of mass is 1.5 m below it (its weight's moment about the node turning with
    it); the bob's centre ends at ``1.5 g / |g|`` (closed form) to the solver's round-off
    (16 eps of the 1.5 m arm)."""
    g = np.array([-9.81, -1.0, 0.0])
    position, centre = (
        ("[0.0, 0.0, 0.0]", "centre = [0.0, -1.5, 0.0]\n")
        if offset
        else (
            "[0.0, -1.5, 0.0]",
            "",
        )
    )
    text = (
        f'title = "pendulum"\n[[body]]\nname = "bob"\nposition = {position}\nmass = 1.0\n{centre}'
        '[[joint]]\nkind = "revolute"\na = "ground"\nb = "bob"\nposition = [0.0, 0.0, 0.0]\n'
        'axis = [0.0, 0.0, 1.0]\n[study]\nkind = "static"\ngravity = [-9.81, -1.0, 0.0]\n'
        '[output]\ncsv = ["nodes"]\n'
    )
    code, out, err = run_scene(tmp_path, text, capsys)
    assert code == 0, err
    assert "kinematics: exact (auto: the scene has joints, exact only)" in out
    row = read(tmp_path / "scene" / "nodes.csv")[0]
    node = np.array([float(row[c]) + float(row["u" + c]) for c in "xyz"])
    turn = np.array([float(row[c]) for c in ("rx", "ry", "rz")])
    bob = node + (rotations.exp_map(turn) @ [0.0, -1.5, 0.0] if offset else 0.0)
    np.testing.assert_allclose(bob, 1.5 * g / np.linalg.norm(g), atol=16 * EPS * 1.5)


def test_reactions_take_the_loads_lever_arms_of_the_exact_state(tmp_path, capsys):
    """The heavy cantilever (softened, ``EA = GA = 1e4``, so that its residual's round-off
    floor is small): the clamp's reaction is the weight about the clamp on the deformed
    rod, ``w int x ds`` with the nodes' current positions (Simpson per fv3 element, exact
    for its quadratic interpolation): the region balances sum to the global moment balance.
    Bound: the free dofs' residuals on their floor, ``16 eps EA |x| / h`` per node, times
    the unit arm, over the 17 nodes.  With the reference's lever arms it is 3.4e-3 off."""
    text = (
        (SCENES / "heavy_cantilever.toml")
        .read_text()
        .replace('nodes = { nodes = ["rod.end"] }\n', "")
    )
    for key in ("EA", "GAy", "GAz"):
        text = text.replace(f"{key} = 1e8", f"{key} = 1e4")
    assert run_scene(tmp_path, text, capsys)[0] == 0
    rows = read(tmp_path / "scene" / "nodes.csv")
    xi, x = np.array(sorted((float(r["xi"]), float(r["x"]) + float(r["ux"])) for r in rows)).T
    integral = sum(
        (xi[k + 2] - xi[k]) / 6 * (x[k] + 4 * x[k + 1] + x[k + 2]) for k in range(0, 16, 2)
    )
    clamp = next(r for r in read(tmp_path / "scene" / "reactions.csv") if r["node"] == "rod.start")
    bound = 17 * 16 * EPS * 1e4 * 1.0 / 0.125
    assert abs(float(clamp["mz"]) - 9.81 * integral) <= bound
    assert abs(float(clamp["fy"]) - 9.81) <= bound
