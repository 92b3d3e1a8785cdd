"""The peer: the work-precision moving load in Exudyn, on ANCF cable elements.

The problem of :mod:`studies.work_precision`'s ``euler-bernoulli`` case: a simply supported
beam, ``L = 1``, ``EJ = 1e4``, mass 10 per length, ``F = 100`` crossing at half the critical
speed, from rest, to 1.5 crossing times.  Exudyn's ``ObjectANCFCable2D`` is a cubic Hermite
(ANCF, position and slope per node) Euler-Bernoulli element with a consistent mass; the
cable's axial stiffness is ``EA = 1e3 EJ`` as in our section.  Supports: ``x, y`` at the first
node, ``y`` at the last (``CoordinateConstraint``).  Error: the same measure, ``max_t |w(L/2,
t) - w_exact| / max_t |w_exact|`` over every step, against the same closed form taken at its
own section, ``GA = inf`` (the cable has no shear; ours have ``EJ / (GA L^2) = 1e-5``, and each
model is measured against its own continuum).

Two ways to move the force (:data:`LOADINGS`):

``load``
    the force's consistent load vector on the element under it (cubic Hermite shape functions
    at ``c t``, on the nodes' ``y`` and ``y'`` coordinates, ``LoadCoordinate``), set before
    every step by a pre-step function.  This is the fair comparison with our ``point_load``
    rows: both rebuild the load vector of a point force once per step, and both then solve a
    fixed-step generalized-alpha step.
``joint``
    a massless point carrying the force, its ``x`` driven at ``c t`` by a ``CoordinateConstraint``
    with an offset function, held on the cable by ``ObjectJointSliding2D``: Exudyn's own way to
    move a body along cables, the counterpart of our ``slider`` rows.  Measured here: its
    error decays at first order in the step (the deflection runs one step ahead of the
    closed form; driving the point at ``c (t - h)`` gives the ``load`` rows' second order),
    so this front lies above the ``load`` one.

Solver: Exudyn's generalized-alpha (index 3) with the same ``rho_inf`` (``spectralRadius``),
fixed steps (``adaptiveStep = False``), its (modified) Newton at a relative tolerance of
:data:`NEWTON_RTOL`, the sparse linear solver (``EigenSparse``, as our ``splu``).  At
Exudyn's default ``1e-8`` its Newton stalls at roundoff on some steps and the solve stops
(``SolverError``: 16 elements, 200 steps per crossing, ``rho_inf = 0.5``), so the tolerance is
``1e-6``, which favours the peer (fewer iterations; ours are linear solves, one per step).
A solve that still stops is a row with an infinite error.  Timed: wall
and CPU seconds of ``Assemble`` and ``SolveDynamic`` (the model's items are built outside),
the minimum over the repeats, a fresh system every repeat.

Run as ``python -m studies.peer_moving_load --out DIR [--quick]`` (needs the ``peer`` extra,
``pip install 'fvslider[peer]'``); writes ``DIR/peer_moving_load.csv`` in the columns of
:data:`studies.work_precision.COLUMNS` (formulation ``exudyn-ancf``, loading ``load`` or
``joint``), which ``python -m studies.work_precision --out DIR`` then draws beside its fronts.
Ctrl-C writes the rows computed so far.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from . import moving_load as ml
from . import work_precision as wp
from .bench import least_time

CASE = "euler-bernoulli"
#: The peer's continuum: the work-precision problem without shear.
PROBLEM = replace(wp.CASES[CASE], GA=np.inf)
FORMULATION = "exudyn-ancf"
LOADINGS = ("load", "joint")
#: Exudyn's Newton tolerance, relative to the step's first residual (module docstring).
NEWTON_RTOL = 1e-6


@dataclass(frozen=True)
class Grid:
    """Meshes x steps x ``rho_inf`` x loadings, and ``fine`` single ``(elements, steps,
    rho_inf)`` runs of the ``load`` loading beyond them."""

    elements: tuple[int, ...]
    steps: tuple[int, ...]
    rho_infs: tuple[float, ...]
    loadings: tuple[str, ...]
    repeats: int
    fine: tuple[tuple[int, int, float], ...] = ()


FULL = Grid(
    wp.FULL.moving_elements,
    wp.FULL.moving_steps,
    wp.FULL.rho_infs,
    LOADINGS,
    wp.FULL.repeats,
    fine=wp.FINE_RUNS,
)
QUICK = Grid((4, 8), (200,), (0.8,), LOADINGS, 1)


def exudyn() -> Any:
    """The ``exudyn`` module, or a ``RuntimeError`` saying how to install it."""
    try:
        import exudyn as exu
    except ImportError as exc:
        raise RuntimeError(
            "the peer study needs Exudyn: pip install 'fvslider[peer]' (exudyn >= 1.13)"
        ) from exc
    return exu


def hermite(xi: float, h: float) -> np.ndarray:
    """Cubic Hermite shape functions at ``xi = s / h`` for ``(y0, y0', y1, y1')``."""
    return np.array(
        [
            1 - 3 * xi**2 + 2 * xi**3,
            h * (xi - 2 * xi**2 + xi**3),
            3 * xi**2 - 2 * xi**3,
            h * (xi**3 - xi**2),
        ]
    )


class Cable:
    """The supported ANCF cable of ``n`` elements with the moving force, ready to solve."""

    def __init__(self, n: int, steps: int, rho_inf: float, loading: str) -> None:
        if loading not in LOADINGS:
            raise ValueError(f"loading must be one of {', '.join(LOADINGS)}, got {loading!r}")
        exu = exudyn()
        from exudyn import itemInterface as it

        p = PROBLEM
        self.exu, self.n, self.steps = exu, n, steps
        self.SC = exu.SystemContainer()
        mbs = self.mbs = self.SC.AddSystem()
        h = p.L / n
        nodes = [
            mbs.AddNode(it.NodePoint2DSlope1(referenceCoordinates=[i * h, 0, 1, 0]))
            for i in range(n + 1)
        ]
        cables = [
            mbs.AddObject(
                it.ObjectANCFCable2D(
                    physicsLength=h,
                    physicsMassPerLength=p.m,
                    physicsBendingStiffness=p.EJ,
                    physicsAxialStiffness=1e3 * p.EJ,
                    nodeNumbers=[nodes[i], nodes[i + 1]],
                )
            )
            for i in range(n)
        ]
        ground = mbs.AddMarker(
            it.MarkerNodeCoordinate(
                nodeNumber=mbs.AddNode(it.NodePointGround(referenceCoordinates=[0, 0, 0])),
                coordinate=0,
            )
        )

        def hold(node: int, coordinate: int, offset: Any = 0) -> None:
            marker = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
            mbs.AddObject(it.CoordinateConstraint(markerNumbers=[ground, marker], **offset))

        for node, coordinate in ((nodes[0], 0), (nodes[0], 1), (nodes[-1], 1)):
            hold(node, coordinate, {})
        if loading == "load":
            loads = [
                mbs.AddLoad(
                    it.LoadCoordinate(
                        markerNumber=mbs.AddMarker(
                            it.MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate)
                        ),
                        load=0.0,
                    )
                )
                for node in nodes
                for coordinate in (1, 3)
            ]
            active: list[int] = []

            def before_step(mbs: Any, t: float) -> bool:  # t: the step's end
                a = min(p.speed * t, p.L)
                for k in active:
                    mbs.SetLoadParameter(loads[k], "load", 0.0)
                active.clear()
                if a < p.L:
                    e = min(int(a / h), n - 1)
                    for k, value in enumerate(p.F * hermite(a / h - e, h)):
                        mbs.SetLoadParameter(loads[2 * e + k], "load", float(value))
                        active.append(2 * e + k)
                return True

            mbs.SetPreStepUserFunction(before_step)
        else:
            point = mbs.AddNode(
                it.NodePoint2D(referenceCoordinates=[0, 0], initialVelocities=[p.speed, 0])
            )
            mbs.AddObject(it.MassPoint2D(physicsMass=0.0, nodeNumber=point))
            carried = mbs.AddMarker(it.MarkerNodePosition(nodeNumber=point))
            mbs.AddLoad(it.Force(markerNumber=carried, loadVector=[0, p.F, 0]))
            hold(
                point,
                0,
                {"offsetUserFunction": lambda mbs, t, item, offset: min(p.speed * t, p.L)},
            )
            markers = [mbs.AddMarker(it.MarkerBodyCable2DCoordinates(bodyNumber=e)) for e in cables]
            data = mbs.AddNode(
                it.NodeGenericData(initialCoordinates=[0, 0], numberOfDataCoordinates=2)
            )
            mbs.AddObject(
                it.ObjectJointSliding2D(
                    markerNumbers=[carried, markers[0]],
                    slidingMarkerNumbers=markers,
                    slidingMarkerOffsets=[i * h for i in range(n)],
                    nodeNumber=data,
                )
            )
        self.sensor = mbs.AddSensor(
            it.SensorNode(
                nodeNumber=nodes[n // 2],
                outputVariableType=exu.OutputVariableType.Displacement,
                storeInternal=True,
                writeToFile=False,
            )
        )
        s = self.settings = exu.SimulationSettings()
        total = round(wp.WINDOW * steps)
        s.timeIntegration.numberOfSteps = total
        s.timeIntegration.endTime = total * p.crossing / steps
        s.timeIntegration.generalizedAlpha.spectralRadius = rho_inf
        s.timeIntegration.adaptiveStep = False
        s.timeIntegration.verboseMode = 0
        s.timeIntegration.newton.relativeTolerance = NEWTON_RTOL
        s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
        s.solution.file.write = False
        s.solution.sensors.writePeriod = 0.0
        s.show.statistics = False
        s.show.computationTime = False

    def solve(self) -> np.ndarray:
        """Assemble and integrate; the mid-span deflection at every step's time."""
        self.mbs.Assemble()
        self.mbs.SolveDynamic(self.settings)
        data = self.mbs.GetSensorStoredData(self.sensor)
        return np.asarray(data)[:, 2]


def compute(grid: Grid, progress: bool = True) -> tuple[list[dict[str, Any]], bool]:
    """Every row of ``grid`` and whether Ctrl-C stopped it (then the rows done so far)."""
    from tqdm import tqdm

    exudyn()
    jobs = [
        (lo, n, s, r)
        for lo in grid.loadings
        for n in grid.elements
        for s in grid.steps
        for r in grid.rho_infs
    ] + [("load", n, s, r) for n, s, r in grid.fine]
    exact: dict[int, np.ndarray] = {}
    rows: list[dict[str, Any]] = []
    bar = tqdm(jobs, desc="peer", unit="run", disable=None if progress else True)
    try:
        for loading, n, steps, rho_inf in bar:
            if steps not in exact:
                t = wp.step_times(PROBLEM, steps)
                exact[steps] = PROBLEM.exact_midspan(t, wp.REFERENCE_RTOL)
            cables = iter([Cable(n, steps, rho_inf, loading) for _ in range(grid.repeats)])
            try:
                w, wall, cpu = least_time(
                    lambda cables=cables: next(cables).solve(), grid.repeats, wp.LONG_RUN
                )
                error = ml.relative_error(w, exact[steps])
            except RuntimeError:  # Exudyn's SolverError: the solve stopped
                wall, cpu, error = math.nan, math.nan, math.inf
            rows.append(
                wp.moving_load_row(
                    CASE, FORMULATION, loading, n, steps, rho_inf, (wall, cpu), error
                )
            )
    except KeyboardInterrupt:
        bar.close()
        return rows, True
    return rows, False


def main(argv: list[str] | None = None) -> int:
    """Run the grid and write the CSV; exit code 130 on Ctrl-C, 2 without Exudyn."""
    parser = argparse.ArgumentParser(
        prog="python -m studies.peer_moving_load", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--quick", action="store_true", help="a small grid (seconds)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    try:
        rows, interrupted = compute(QUICK if args.quick else FULL, not args.no_progress)
    except RuntimeError as exc:
        print(exc, file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    wp.write_csv(rows, args.out / wp.PEER_CSV)
    print(wp.markdown(rows))
    print(f"written to {args.out / wp.PEER_CSV}" + (" (interrupted)" if interrupted else ""))
    return 130 if interrupted else 0


if __name__ == "__main__":
    wp.run_with_one_blas_thread(main, __spec__.name)
