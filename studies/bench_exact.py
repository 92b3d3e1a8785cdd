"""Benchmark of geometrically exact beams in statics, merged into ``results/bench.json``.

``exact_statics``
    ``elastica``: the tip-loaded cantilever at ``P L^2 / EJ = 10`` (:data:`LOAD`; EJ = 1,
    EA = GA = 1e8) for fv2, fv3, galerkin-p1 and galerkin-p2 (reduced integration) on
    meshes halved until the tip's error against the elliptic-integral solution
    (:func:`fvbeam.elastica.tip_loaded_cantilever`: shortening, deflection, rotation, the
    largest, in units of the length and radians) is below :data:`TARGET`; per mesh the
    solve's time (``time.perf_counter`` around :func:`fvbeam.exact_statics.solve_static`,
    median and minimum of the repeats; the beam's build apart), the load steps and Newton
    iterations, beside the error.
    ``peer``: the same elastica in Exudyn (when installed, the ``peer`` extra): its static
    solve (:func:`peer_elastica`) on ANCF cable elements refined until the same error, timed
    the same way, for each of its load-step settings :data:`PEER_LOAD_STEPS` (its best is
    the fewest that converge: one);
    ``side_by_side``: per formulation, its first mesh within :data:`TARGET` against the
    peer's fastest setting within it, the two timed again in alternation, and the ratio of
    their minimum times.
    ``bend``: the 45-degree bend of Bathe and Bolourchi (:func:`bend`, tip force
    :data:`BEND_LOAD` out of plane) with 8 elements of each formulation: its time, its tip
    and the tip's distance from the published ones (:data:`BEND_PUBLISHED`) and from the
    converged one (fv3, 32 elements), for each of :data:`BEND_FORMULATIONS`.
    ``heavy``: the heavy cantilever (its own weight a dead distributed load,
    ``w L^3 / EJ = 10``, :mod:`fvbeam.exact_loads`) with 8 and 16 fv3 elements: the exact
    solve's time and its tip's error against the heavy elastica
    (:func:`fvbeam.elastica.heavy_cantilever`), beside the linear beam's solve (the clamped
    stiffness factorised and solved, ``scipy.sparse.linalg.spsolve``) and its error.

Run as ``python -m studies.bench_exact --out results/bench.json`` (``make bench``;
``--quick``: coarse meshes, one repeat).  Ctrl-C keeps and writes what was measured, marked
``interrupted``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from fvbeam import Beam, Section, from_curve, straight
from fvbeam.elastica import heavy_cantilever, tip_loaded_cantilever
from fvbeam.exact_beam import ExactBeam
from fvbeam.exact_loads import DeadLoad, distributed
from fvbeam.exact_statics import ExactStaticResult, solve_static

from .bench import environment, read_existing, summary, write_merged
from .peer_moving_load import exudyn


def peer_available() -> bool:
    """Whether Exudyn is installed."""
    try:
        exudyn()
    except RuntimeError:
        return False
    return True


KEY = "exact_statics"
#: The elastica's load parameter ``P L^2 / EJ`` and the error to reach.
LOAD = 10.0
TARGET = 1e-4
#: First meshes of the elastica (halved from there) and the most elements tried.
FIRST = {"fv2": 8, "fv3": 2, "galerkin-p1": 8, "galerkin-p2": 2}
MOST = 512
#: The peer's load-step settings (Exudyn's ``staticSolver.numberOfLoadSteps``, adaptive).
PEER_LOAD_STEPS = (1, 2, 5, 10)
#: The bend's tip force.
BEND_LOAD = 600.0
BEND_FORMULATIONS = ("fv2", "fv3", "galerkin-p1", "galerkin-p2")
#: Published tip positions of the bend at the tip force 600, in this module's axes (the
#: arc in x-y, tangent to y at the clamp, the force along z; the sources give the
#: displacement, here added to the tip's reference position (29.289, 70.711, 0)):
#: Bathe and Bolourchi (IJNME 14 (1979) 961-986) and Wang, Sprague, Jonkman and Johnson
#: (BeamDyn, AIAA SciTech 2015, NREL/CP-5000-63165), both as OpenFAST's regression test of
#: the problem quotes them (github.com/OpenFAST/r-test,
#: modules/beamdyn/bd_curved_beam/README.md: displacements (-13.4, 53.4, -23.5) and
#: (-13.5, 53.4, -23.7) in its axes, x towards the arc's centre, y the force, z the tangent
#: at the clamp); and one Legendre spectral element of 12 nodes, converged, of kynema
#: (github.com/kynema/kynema, docs/sphinx/testing/curved.rst: (-23.646, 13.721, 53.578),
#: tangent, away from the centre, force).
BEND_PUBLISHED = {
    "Bathe and Bolourchi 1979": (15.889, 47.211, 53.4),
    "Wang et al. 2015 (BeamDyn)": (15.789, 47.011, 53.4),
    "kynema (spectral, 12 nodes)": (15.568, 47.065, 53.578),
}


def nodes_per_element(name: str) -> int:
    """2 for ``fv2`` and ``galerkin-p1``, else 3."""
    return 2 if name in ("fv2", "galerkin-p1") else 3


def rod(name: str, n: int, slenderness: float = 1e8, GJ: float = 1.0) -> ExactBeam:
    """A unit rod along x of ``n`` elements, ``EJ = 1``, ``EA = GA = slenderness``."""
    s = slenderness
    section = Section.diagonal(EA=s, GAy=s, GAz=s, GJ=GJ, EJy=1.0, EJz=1.0)
    mesh = straight((0, 0, 0), (1, 0, 0), n, nodes_per_element(name))
    return ExactBeam(Beam(mesh, section, name))


def bend(name: str, n: int) -> ExactBeam:
    """The 45-degree bend of Bathe and Bolourchi (IJNME 14 (1979) 961-986): an arc of radius
    100 in the x-y plane from the origin, tangent to y there, clamped at the origin; unit
    square section, ``E = 1e7``, ``G = E / 2``, shear areas 5/6 and ``GJ = EJ = E / 12``
    (the section stiffness as the sources of :data:`BEND_PUBLISHED` pose the problem:
    ``kGA = 4.16667e6``, ``EA = 1e7``, ``EI = GJ = 8.333e5``)."""
    E, G = 1e7, 5e6
    section = Section.diagonal(
        EA=E, GAy=5 / 6 * G, GAz=5 / 6 * G, GJ=E / 12, EJy=E / 12, EJz=E / 12
    )

    def arc(u: np.ndarray) -> np.ndarray:
        angle = np.pi / 4 * u
        return np.column_stack([100 - 100 * np.cos(angle), 100 * np.sin(angle), 0 * u])

    return ExactBeam(Beam(from_curve(arc, n, nodes_per_element(name)), section, name))


def solve_tip(
    exact: ExactBeam, force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0)
) -> tuple[ExactStaticResult, np.ndarray]:
    """Equilibrium under a dead force and couple at the end, the start clamped; and the
    load vector."""
    beam = exact.beam
    load = beam.nodal_load("end", force=force, moment=moment)
    return solve_static(exact, load, beam.node_dofs("start")), load


def timed(exact: ExactBeam, repeats: int, **load: Any) -> tuple[ExactStaticResult, list[float]]:
    """The solve and its times over ``repeats``."""
    times = []
    for _ in range(repeats):
        clock = time.perf_counter()
        result, _ = solve_tip(exact, **load)
        times.append(time.perf_counter() - clock)
    return result, times


def elastica_error(exact: ExactBeam, result: ExactStaticResult) -> float:
    """The largest error of the tip's shortening, deflection and rotation."""
    tip = tip_loaded_cantilever(LOAD)
    d = exact.displacements(result.state)[exact.beam.node_index("end")]
    ours = np.array([-d[0], -d[1], -d[5]])
    return float(np.abs(ours - [tip.shortening, tip.deflection, tip.rotation]).max())


def bench_elastica(name: str, repeats: int, first: int, most: int) -> list[dict[str, Any]]:
    """Rows of meshes halved from ``first`` elements until the error is below TARGET."""
    rows = []
    n = first
    while n <= most:
        exact = rod(name, n)
        result, times = timed(exact, repeats, force=(0.0, -LOAD, 0.0))
        rows.append(
            {
                "n_elements": n,
                "seconds": summary(times),
                "load_steps": len(result.load_factors),
                "newton_iterations": result.newton_iterations,
                "error": elastica_error(exact, result),
            }
        )
        if rows[-1]["error"] <= TARGET:
            break
        n *= 2
    return rows


def peer_elastica(n: int, load_steps: int = 1) -> tuple[float, float]:
    """The elastica on ``n`` of Exudyn's ANCF cable elements (``ObjectANCFCable2D``: cubic
    Hermite positions, Euler-Bernoulli, ``EA = 1e8``, ``EJ = 1``), clamped by
    ``CoordinateConstraint`` on the first node's position and slope, the dead tip force a
    ``Force`` load; Exudyn's static solver (Newton, ``load_steps`` load steps, adaptive,
    relative tolerance 1e-10, Eigen's sparse solver: its fastest, ahead of its dense one
    from 32 elements on).  Returns the seconds of ``SolveStatic`` (the model's build and
    assembly apart) and the tip's error as :func:`elastica_error` measures it."""
    exu = exudyn()
    from exudyn import itemInterface as it

    system = exu.SystemContainer()
    mbs = system.AddSystem()
    h = 1.0 / n
    nodes = [
        mbs.AddNode(it.NodePoint2DSlope1(referenceCoordinates=[i * h, 0, 1, 0]))
        for i in range(n + 1)
    ]
    for i in range(n):
        mbs.AddObject(
            it.ObjectANCFCable2D(
                length=h,
                massPerLength=1.0,
                bendingStiffness=1.0,
                axialStiffness=1e8,
                nodeNumbers=[nodes[i], nodes[i + 1]],
            )
        )
    ground = mbs.AddNode(it.NodePointGround(referenceCoordinates=[0, 0, 0]))
    held = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    for coordinate in (0, 1, 3):  # x, y and the slope's y: clamped
        marker = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=coordinate))
        mbs.AddObject(it.CoordinateConstraint(markerNumbers=[held, marker]))
    tip = mbs.AddMarker(it.MarkerNodePosition(nodeNumber=nodes[-1]))
    mbs.AddLoad(it.Force(markerNumber=tip, loadVector=[0, -LOAD, 0]))
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.staticSolver.numberOfLoadSteps = load_steps
    settings.staticSolver.adaptiveStep = True
    settings.staticSolver.newton.relativeTolerance = 1e-10
    settings.staticSolver.verboseMode = 0
    settings.solution.file.write = False
    settings.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    clock = time.perf_counter()
    mbs.SolveStatic(settings)
    seconds = time.perf_counter() - clock
    d = mbs.GetNodeOutput(nodes[-1], exu.OutputVariableType.Coordinates)
    ours = np.array([-d[0], -d[1], np.arctan2(-d[3], 1 + d[2])])
    ref = tip_loaded_cantilever(LOAD)
    return seconds, float(np.abs(ours - [ref.shortening, ref.deflection, ref.rotation]).max())


def bench_peer(repeats: int, first: int, most: int, load_steps: int) -> list[dict[str, Any]]:
    """Rows of the peer's meshes halved from ``first`` until the error is below TARGET."""
    rows = []
    n = first
    while n <= most:
        runs = [peer_elastica(n, load_steps) for _ in range(repeats)]
        seconds = summary([t for t, _ in runs])
        rows.append(
            {"n_elements": n, "load_steps": load_steps, "seconds": seconds, "error": runs[0][1]}
        )
        if rows[-1]["error"] <= TARGET:
            break
        n *= 2
    return rows


def side_by_side(
    elastica: dict[str, list[dict[str, Any]]],
    peer: dict[str, list[dict[str, Any]]],
    repeats: int,
) -> dict[str, Any]:
    """Each formulation's first mesh within TARGET beside the peer's fastest setting within
    it, both timed again in alternation (one solve of ours, one of the peer's, ``repeats``
    times, so that a change of the machine's load falls on both), with the ratio of their
    minimum times (ours over the peer's)."""
    within = [
        (setting, row) for setting, rows in peer.items() for row in rows if row["error"] <= TARGET
    ]
    if not within:
        return {}
    setting, best = min(within, key=lambda item: item[1]["seconds"]["min"])
    out: dict[str, Any] = {"peer": {"setting": setting, **best}}
    for name, rows in elastica.items():
        ours = next((row for row in rows if row["error"] <= TARGET), None)
        if ours is None:
            continue
        exact = rod(name, ours["n_elements"])
        mine, theirs = [], []
        for _ in range(repeats):
            mine += timed(exact, 1, force=(0.0, -LOAD, 0.0))[1]
            theirs.append(peer_elastica(best["n_elements"], best["load_steps"])[0])
        out[name] = {
            "n_elements": ours["n_elements"],
            "error": ours["error"],
            "seconds": min(mine),
            "peer_seconds": min(theirs),
            "ratio_to_peer": min(mine) / min(theirs),
        }
    return out


def bench_bend(repeats: int, converged_n: int) -> dict[str, Any]:
    """The bend with 8 elements of each formulation against the published and converged
    tips."""
    force = (0.0, 0.0, BEND_LOAD)
    fine = bend("fv3", converged_n)
    converged, _ = solve_tip(fine, force=force)
    reference = converged.state.x[fine.beam.node_index("end")]
    out: dict[str, Any] = {"load": BEND_LOAD, "converged_tip": reference.tolist()}
    for name in BEND_FORMULATIONS:
        exact = bend(name, 8)
        result, times = timed(exact, repeats, force=force)
        tip = result.state.x[exact.beam.node_index("end")]
        out[name] = {
            "n_elements": 8,
            "seconds": summary(times),
            "tip": tip.tolist(),
            "distance_to_published": {
                source: float(np.linalg.norm(tip - published))
                for source, published in BEND_PUBLISHED.items()
            },
            "distance_to_converged": float(np.linalg.norm(tip - reference)),
        }
    return out


def bench_heavy(repeats: int) -> dict[str, Any]:
    """The heavy cantilever at ``w L^3 / EJ = 10``, exact beside linear (module
    docstring)."""
    import scipy.sparse.linalg as spla

    tip = heavy_cantilever(LOAD)
    closed = np.array([-tip.shortening, -tip.deflection, -tip.rotation])
    out: dict[str, Any] = {}
    for n in (8, 16):
        exact = rod("fv3", n)
        beam = exact.beam
        fixed = beam.node_dofs("start")
        free = np.setdiff1d(np.arange(beam.n_dofs), fixed)
        points = distributed(beam, (0.0, -LOAD, 0.0))
        dead = DeadLoad(beam.n_dofs, beams=[(beam, np.arange(beam.mesh.n_nodes), points)])
        f = beam.distributed_load((0.0, -LOAD, 0.0))
        exact_times, linear_times = [], []
        for _ in range(repeats):
            clock = time.perf_counter()
            result = solve_static(exact, dead, fixed)
            exact_times.append(time.perf_counter() - clock)
            clock = time.perf_counter()
            q = np.zeros(beam.n_dofs)
            q[free] = spla.spsolve(beam.stiffness[free][:, free].tocsc(), f[free])
            linear_times.append(time.perf_counter() - clock)
        end = beam.node_index("end")
        ours = exact.displacements(result.state)[end][[0, 1, 5]]
        linear = q[6 * end : 6 * end + 6][[0, 1, 5]]
        out[f"fv3 x {n}"] = {
            "exact": {"seconds": summary(exact_times), "error": float(np.abs(ours - closed).max())},
            "linear": {
                "seconds": summary(linear_times),
                "error": float(np.abs(linear - closed).max()),
            },
        }
    return out


def bench(repeats: int = 10, most: int = MOST, converged_n: int = 32) -> dict[str, Any]:
    """The benchmark's JSON section (module docstring)."""
    result: dict[str, Any] = {"load": LOAD, "target": TARGET, "interrupted": False}
    try:
        result["elastica"] = {
            name: bench_elastica(name, repeats, first, most) for name, first in FIRST.items()
        }
        result["bend"] = bench_bend(repeats, converged_n)
        result["heavy"] = bench_heavy(repeats)
        if peer_available():
            result["peer"] = {
                f"exudyn-ancf, {steps} load steps": bench_peer(repeats, 8, most, steps)
                for steps in PEER_LOAD_STEPS
            }
            result["side_by_side"] = side_by_side(result["elastica"], result["peer"], repeats)
    except KeyboardInterrupt:
        result["interrupted"] = True
    return result


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, merge it into ``--out``, print a table."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.bench_exact", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results/bench.json"))
    parser.add_argument("--quick", action="store_true", help="coarse meshes, one repeat")
    args = parser.parse_args(argv)
    read_existing(args.out)  # fail before spending the time if the file cannot be merged
    result = bench(1, 16, 8) if args.quick else bench()
    write_merged(args.out, {"environment": environment(), KEY: result})
    for name, rows in result.get("elastica", {}).items():
        for row in rows:
            print(
                f"elastica P L^2/EJ = {LOAD:g}, {name} x {row['n_elements']}: "
                f"{row['seconds']['min']:.3f} s ({row['load_steps']} steps, "
                f"{row['newton_iterations']} iterations), error {row['error']:.2e}"
            )
    for setting, rows in result.get("peer", {}).items():
        for row in rows:
            print(
                f"peer ({setting}) x {row['n_elements']}: {row['seconds']['min']:.4f} s, "
                f"error {row['error']:.2e}"
            )
    pair = result.get("side_by_side", {})
    for name in FIRST:
        if name in pair:
            print(
                f"at error <= {TARGET:g}: {name} x {pair[name]['n_elements']} "
                f"{pair[name]['seconds']:.4f} s, {pair[name]['ratio_to_peer']:.2f} times the "
                f"peer's {pair[name]['peer_seconds']:.4f} s ({pair['peer']['setting']} x "
                f"{pair['peer']['n_elements']}; timed in alternation)"
            )
    if "bend" in result:
        for name in BEND_FORMULATIONS:
            row = result["bend"][name]
            print(
                f"45-degree bend P = {BEND_LOAD:g}, {name} x 8: {row['seconds']['min']:.3f} s, "
                f"tip {np.round(row['tip'], 2).tolist()}, "
                f"{min(row['distance_to_published'].values()):.2f} to "
                f"{max(row['distance_to_published'].values()):.2f} from the published, "
                f"{row['distance_to_converged']:.3f} from the converged"
            )
    for mesh, row in result.get("heavy", {}).items():  # load: LOAD, as the elastica's
        print(
            f"heavy cantilever w L^3/EJ = {LOAD:g}, {mesh}: exact "
            f"{row['exact']['seconds']['min']:.4f} s, error {row['exact']['error']:.2e}; "
            f"linear {row['linear']['seconds']['min']:.4f} s, error {row['linear']['error']:.2e}"
        )
    print(f"written to {args.out}")
    return result


if __name__ == "__main__":
    main()
