"""Stress tests of the dynamics of a body sliding on a chain of beams.

The model: five straight fv3 beams of length ``L = 1`` (two elements each, element length
``h_e = 1/2``) joined end to start along x into a chain of length ``L_c = 5``, clamped at both
ends; a massless rigid body on a spherical slider whose abscissa ``xi`` is driven
(:class:`sliders.joints.drives.Tabulated`, piecewise linear: constant speed ``c`` between turning
points), carrying a transverse force ``F = (0, 1, 0)``.  Section: ``EJ = 1``,
``GA = EJ / (r L^2)`` with the slenderness ratio ``r``, ``EA = 1e4``, ``GJ = 1``, ``m = 1``,
rotary inertia ``1e-4`` per length; no damping, generalized-alpha (``Case.rho_inf``).

Dimensionless parameters of a run (:class:`Case`):

``speed``
    ``c / c_cr`` with the first-mode critical speed ``c_cr = omega_1 L_c / pi``: the speed at
    which the load crosses the span in half the first period (the moving-load resonance of a
    simply supported span, Fryba, *Vibration of solids and structures under moving loads*,
    1972, Sec. 1.2; here the clamped chain's analogue, ``omega_1`` from
    :func:`fvbeam.modes.natural_frequencies`).
``step``
    ``h / h_ref`` with ``h_ref = h_e / (4 c)``: at ``step = 1`` the body moves a quarter element
    per step.
``smearing``
    the kernel's half-width (:mod:`fvbeam.smearing`, ``box``) over the element length.
``slenderness``
    ``r = EJ / (GA L^2)``.

A sweep run drives the body at constant speed from ``xi = 0.1`` towards ``4.9`` (all 20
evaluation points and the 4 beam junctions) in at most :data:`STEPS` steps; a run whose
steps are short stops after :data:`STEPS` steps, its path centred on the evaluation point
next to the middle junction so that it still crosses one.  The shuttle drives the body back
and forth between 0.1 and 4.9.

What a run measures (:func:`measure`): Newton iterations per step, the joint's constraint
residual against the bound its convergence rule implies (:func:`residual_bound`), the drift
``xi - xi_d(t)``, finiteness of every column, and the energy balance split into the work of
the skew part of the fv stiffness (:func:`skew_work`) and what is left, the scheme's
numerical dissipation (zero to roundoff at ``rho_inf = 1``, :func:`identity_bound`).  Each
sweep case runs at ``rho_inf = 0.8`` (the default) and 1 (:data:`RHO_INF`).

Run as ``python -m studies.stress --out DIR [--quick]``: writes ``DIR/sweeps.csv`` (one row
per run), ``DIR/shuttle/history.csv`` (the shuttle's per-step record), and the plots
``DIR/sweeps.png`` and ``DIR/shuttle.png``.  Progress bars show the runs; Ctrl-C stops the
sweeps and keeps (and plots) the runs done.
"""

from __future__ import annotations

import argparse
import csv
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from fvbeam.elements import evaluation_points
from fvbeam.io import replace_directory, write_atomic
from fvbeam.modes import natural_frequencies
from sliders.app.history import Recorder
from sliders.joints.drives import Tabulated
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics, DynamicsError

BEAMS, ELEMENTS, LENGTH, EJ = 5, 2, 1.0, 1.0
ELEMENT = LENGTH / ELEMENTS
CHAIN = BEAMS * LENGTH
ENDS = (0.1, CHAIN - 0.1)
FORCE = (0.0, 1.0, 0.0)
TOL = 1e-8
#: Largest number of steps of a sweep run.
STEPS = 40
#: Lebesgue constant of quadratic Lagrange interpolation at 0, 1/2, 1: the largest
#: ``sum |N_i|`` over the element, 1.25, at the points 1/2 -+ 1/4.
LEBESGUE = 1.25


@dataclass(frozen=True)
class Case:
    """One run's dimensionless parameters (module docstring)."""

    speed: float = 0.25
    step: float = 1.0
    smearing: float = 0.2
    slenderness: float = 1e-2
    rho_inf: float = 0.8


#: The axes of the sweeps: CI (coarse) and long (dense) values.
AXES = {
    "speed": ((1e-3, 0.1, 1.0), tuple(np.logspace(-3, 0, 13))),
    "step": ((1e-2, 1e-1, 1.0, 10.0), tuple(np.logspace(-2, 1, 13))),
    "smearing": ((0.0, 0.2, 0.4), tuple(np.linspace(0.0, 0.4, 9))),
    "slenderness": ((1e-6, 1e-3, 1.0), tuple(np.logspace(-6, 0, 13))),
}


#: The scheme's spectral radii at infinity of the sweep: the default, and the trapezoidal rule.
RHO_INF = (0.8, 1.0)


def cases(
    dense: bool = False, base: Case = Case(), rho_inf: Sequence[float] = RHO_INF
) -> list[tuple[str, Case]]:
    """The sweep: each axis of :data:`AXES` varied alone about ``base``, at each
    ``rho_inf``."""
    return [
        (axis, replace(base, **{axis: float(v)}, rho_inf=rho))
        for rho in rho_inf
        for axis, values in AXES.items()
        for v in values[dense]
    ]


def section(slenderness: float) -> Section:
    """The chain's section with ``EJ / (GA L^2) = slenderness``."""
    GA = EJ / (slenderness * LENGTH**2)
    return Section.diagonal(
        EA=1e4,
        GAy=GA,
        GAz=GA,
        GJ=1.0,
        EJy=EJ,
        EJz=EJ,
        mass_per_length=1.0,
        inertia=np.diag([1e-4] * 3),
        name="chain",
    )


def chain_beams(slenderness: float) -> tuple[list[Beam], list[tuple]]:
    """The five beams along x and the ties joining them end to start."""
    beams = [
        Beam(
            straight((k * LENGTH, 0, 0), ((k + 1) * LENGTH, 0, 0), ELEMENTS, 3),
            section(slenderness),
            "fv3",
        )
        for k in range(BEAMS)
    ]
    return beams, [(k, "end", k + 1, "start") for k in range(BEAMS - 1)]


CLAMPS = [Support(0, "start", "clamp"), Support(BEAMS - 1, "end", "clamp")]


def critical_speed(slenderness: float) -> float:
    """``c_cr = omega_1 L_c / pi`` of the clamped chain (module docstring)."""
    beams, ties = chain_beams(slenderness)
    omega = natural_frequencies(Structure(beams, ties), CLAMPS, 1).omega[0]
    return float(omega * CHAIN / np.pi)


def chain_points(chain: BeamChain) -> tuple[np.ndarray, np.ndarray]:
    """Abscissae along ``chain`` of the evaluation points of its beams' elements (paper
    Sec. 5: ``s = -+1/sqrt(3)`` on each fv3 element) and of its beam junctions."""
    points = []
    for offset, beam in zip(chain.offsets[:-1], chain.beams, strict=True):
        mesh = beam.mesh
        X = evaluation_points(mesh.nodes_per_element)
        e = np.repeat(np.arange(mesh.n_elements), len(X))
        points.append(offset + mesh.abscissae(e, np.tile(X, mesh.n_elements)))
    return np.sort(np.concatenate(points)), chain.offsets[1:-1].copy()


def crossings(xi: np.ndarray, points: np.ndarray) -> int:
    """How many times the path through the recorded ``xi`` (monotone between records)
    passes one of ``points``."""
    below = np.searchsorted(np.sort(points), xi, side="right")
    return int(np.abs(np.diff(below)).sum())


@dataclass
class Model:
    """A built run: the dynamics, its slider, chain and drive, the step and the end time."""

    dynamics: Dynamics
    slider: Slider
    chain: BeamChain
    drive: Tabulated
    h: float
    t_end: float


def build(
    case: Case, waypoints: Sequence[float], leg_time: float, h: float, *, max_iterations: int = 25
) -> Model:
    """The chain and the driven body of ``case``: ``xi`` runs through ``waypoints`` at
    constant speed, ``leg_time`` per leg (a drive table; the first waypoint is held before)."""
    beams, ties = chain_beams(case.slenderness)
    structure = Structure(beams, ties, bodies=[RigidBody("body", (waypoints[0], 0, 0), mass=0.0)])
    chain = BeamChain(structure, list(range(BEAMS)), name="rail")
    times = leg_time * np.arange(len(waypoints))
    drive = Tabulated(times, np.asarray(waypoints, dtype=float), order=1)
    slider = Slider(
        "spherical", chain, "body", drive=drive, smearing=case.smearing * ELEMENT, name="carriage"
    )
    supports = CLAMPS + [Support("body", kind="rx+ry+rz")]
    dynamics = Dynamics(
        structure,
        supports,
        [slider],
        structure.nodal_load("body", FORCE),
        rho_inf=case.rho_inf,
        method="condensed",
        tol=TOL,
        max_iterations=max_iterations,
    )
    return Model(dynamics, slider, chain, drive, h, float(times[-1]))


def sweep_model(case: Case) -> Model:
    """The sweep run of ``case`` (module docstring)."""
    c = case.speed * critical_speed(case.slenderness)
    h = case.step * ELEMENT / (4 * c)
    travel = min(STEPS * c * h, ENDS[1] - ENDS[0])
    if travel < ENDS[1] - ENDS[0]:
        points, _ = reference_points()
        centre = points[np.searchsorted(points, CHAIN / 2 + 0.5 * LENGTH) - 1]
        start = float(np.clip(centre - travel / 2, ENDS[0], ENDS[1] - travel))
    else:
        start = ENDS[0]
    return build(case, [start, start + travel], travel / c, h)


def reference_points() -> tuple[np.ndarray, np.ndarray]:
    """:func:`chain_points` of the stress chain (its geometry does not depend on the case)."""
    beams, ties = chain_beams(1.0)
    return chain_points(BeamChain(Structure(beams, ties), list(range(BEAMS))))


def shuttle_model(case: Case, passes: int, steps_per_pass: int) -> Model:
    """``passes`` legs between the ends :data:`ENDS` at ``case.speed``, ``steps_per_pass``
    steps each."""
    c = case.speed * critical_speed(case.slenderness)
    leg = (ENDS[1] - ENDS[0]) / c
    waypoints = [ENDS[k % 2] for k in range(passes + 1)]
    return build(case, waypoints, leg, leg / steps_per_pass)


def residual_bound(reach: float, tol: float = TOL, length: float = CHAIN) -> float:
    """Largest position-constraint residual a converged step may leave.

    Newton stops when its last increments satisfy ``|dq| <= tol reach`` and
    ``|d xi| <= tol L_c`` (:func:`sliders.solve.statics.converged`).  The constraint
    ``r = x_b - sum N_i (X_i + u_i)`` was zero to first order after that increment, so what is
    left is at most the change of its Jacobian times the increment:
    ``|r| <= 2 (|dr/dq| |dq| + |dr/dxi| |dxi|)`` with ``|dr/dq| <= 1 + Lambda`` (the body's
    identity and the line's shape functions, Lebesgue constant ``Lambda``) and
    ``|dr/dxi| = |l| <= 1 + reach / h_e`` (the deformed tangent)."""
    return 2 * tol * ((1 + LEBESGUE) * reach + (1 + reach / ELEMENT) * length)


#: :attr:`Outcome.error` of a run cut short by Ctrl-C.
INTERRUPTED = "interrupted"


@dataclass
class Outcome:
    """What a run measured (:func:`measure`)."""

    steps: int
    max_iterations: int
    residual: float
    residual_bound: float
    drift: float
    energy_error: float
    skew_work: float
    identity: float
    identity_bound: float
    work: float
    finite: bool
    evaluation_crossings: int
    junction_crossings: int
    seconds: float
    error: str = ""


def run(
    model: Model, directory: Path | None = None, progress: bool = False, interruptible: bool = False
) -> tuple[Outcome, dict[str, np.ndarray]]:
    """Integrate ``model`` from its static state with a recorder (CSV files in ``directory``
    if given; a progress bar over time with ``progress``); returns what :func:`measure`
    finds and the recorded table.  A :class:`DynamicsError` is kept in
    :attr:`Outcome.error`, with the steps done; so is a Ctrl-C (:data:`INTERRUPTED`) if
    ``interruptible``."""
    d = model.dynamics
    structure = d.structure
    body = structure.node_dofs("body")[:3]
    recorder = Recorder(
        directory,
        probes={
            "skew_work": StepSum(skew_work),
            "roundoff_scale": StepSum(roundoff_scale),
            "reach": lambda s, dyn: float(np.abs(s.q).max()),
            "body_uy": lambda s, dyn: float(s.q[body[1]]),
            "drive": lambda s, dyn: model.drive(s.t)[0],
        },
    )
    start = time.perf_counter()
    error = ""
    try:
        d.run(d.static_state(), model.t_end, model.h, recorder=recorder, progress=progress)
    except DynamicsError as exc:
        error = str(exc)
    except KeyboardInterrupt:
        if not interruptible:
            raise
        error = INTERRUPTED
    table = recorder.table() if recorder.rows else {}
    return measure(model, table, time.perf_counter() - start, error), table


class StepSum:
    """A probe: a sum over the steps recorded so far of ``term(old, new, dynamics)``."""

    def __init__(self, term: Callable) -> None:
        self.term, self.previous, self.total = term, None, 0.0

    def __call__(self, state, dynamics: Dynamics) -> float:
        if self.previous is not None:
            self.total += float(self.term(self.previous, state, dynamics))
        self.previous = state
        return self.total


def skew_work(old, new, dynamics: Dynamics) -> float:
    """``q_{n+1} . A q_n`` with ``A = (K - K^T) / 2``: a step's work of the skew-symmetric part
    of the stiffness.

    Why: the trapezoidal rule (``rho_inf = 1``: ``alpha_m = alpha_f = 1/2``, ``beta = 1/4``,
    ``gamma = 1/2``, so ``a_n + a_{n+1} = qdd_n + qdd_{n+1}`` from a start at rest) gives
    ``q_{n+1} - q_n = h (v_n + v_{n+1}) / 2`` and ``v_{n+1} - v_n = h (qdd_n + qdd_{n+1}) / 2``,
    hence ``Delta (v.M v / 2) = (q_{n+1} - q_n) . M (qdd_n + qdd_{n+1}) / 2`` exactly.  With
    the recorder's trapezoidal work of ``f`` and of the constraint forces
    ``M qdd + K q - f`` (no damping), and ``q.K q / 2`` the energy of the symmetric part,
    the balance of a step is left with exactly ``-q_{n+1} . A q_n``: at ``rho_inf = 1``,
    ``energy_error + skew_work = 0`` to roundoff, whatever the joints and drives do.  At
    ``rho_inf < 1`` the sum is the scheme's numerical dissipation."""
    K = dynamics.K
    return new.q @ ((K @ old.q - K.T @ old.q) / 2)


def roundoff_scale(old, new, dynamics: Dynamics) -> float:
    """``(|K| (|q_n| + |q_{n+1}|) + |M| (|qdd_n| + |qdd_{n+1}|) + |f_n| + |f_{n+1}|) . |dq|``:
    the componentwise scale of the rounding errors of a step's energy balance (the sums of
    products behind ``K q``, ``M qdd`` and the works; Higham, *Accuracy and stability of
    numerical algorithms*, 2002, Sec. 3.1: ``|fl(x . y) - x . y| <= gamma_n |x| . |y|``, and
    the constraint forces are ``M qdd + K q - f``)."""
    K, M = abs(dynamics.K), abs(dynamics.M)
    force = (
        K @ (np.abs(old.q) + np.abs(new.q))
        + M @ (np.abs(old.qdd) + np.abs(new.qdd))
        + np.abs(dynamics.load(old.t))
        + np.abs(dynamics.load(new.t))
    )
    return force @ np.abs(new.q - old.q)


def identity_bound(dynamics: Dynamics, scale: float) -> float:
    """Roundoff bound of ``|energy_error + skew_work|`` (:func:`skew_work`): ``8 n eps`` times
    the summed :func:`roundoff_scale` (``gamma_n ~ n eps`` per sum of products; the balance
    of a step holds four such sums, each entering twice)."""
    return 8 * dynamics.structure.n_dofs * np.finfo(float).eps * scale


def measure(model: Model, table: dict[str, np.ndarray], seconds: float, error: str = "") -> Outcome:
    """The figures of a recorded run (module docstring): ``energy_error`` and ``skew_work``
    at the end, ``identity`` the largest ``|energy_error + skew_work|`` (:func:`skew_work`),
    ``work`` the total absolute work of the loads and of the joint (the sum of the
    magnitudes of each step's increments)."""
    name = model.slider.name
    if not table:
        return Outcome(0, 0, *[np.nan] * 9, False, 0, 0, seconds, error)
    points, junctions = chain_points(model.chain)
    xi = table[f"{name}.xi"]
    work = (
        np.abs(np.diff(table["external_work"])).sum()
        + np.abs(np.diff(table["constraint_work"])).sum()
    )
    return Outcome(
        steps=len(xi) - 1,
        max_iterations=int(table["iterations"][1:].max(initial=0)),
        residual=float(table[f"{name}.residual"].max()),
        residual_bound=residual_bound(float(table["reach"].max())),
        drift=float(np.abs(xi - table["drive"]).max()),
        energy_error=float(table["energy_error"][-1]),
        skew_work=float(table["skew_work"][-1]),
        identity=float(np.abs(table["energy_error"] + table["skew_work"]).max()),
        identity_bound=identity_bound(model.dynamics, float(table["roundoff_scale"][-1])),
        work=float(work),
        finite=bool(all(np.all(np.isfinite(v)) for v in table.values())),
        evaluation_crossings=crossings(xi, points),
        junction_crossings=crossings(xi, junctions),
        seconds=seconds,
        error=error,
    )


def sweep(
    runs: Iterable[tuple[str, Case]],
    progress: bool = True,
    on_result: Callable[[str, Case, Outcome], None] | None = None,
) -> tuple[list[tuple[str, Case, Outcome]], bool]:
    """Run the sweep's cases in order (a tqdm bar over the runs); Ctrl-C stops it and
    returns the runs done with ``interrupted = True``."""
    from tqdm.auto import tqdm

    done: list[tuple[str, Case, Outcome]] = []
    runs = list(runs)
    try:
        for axis, case in tqdm(runs, disable=not progress, desc="runs"):
            outcome, _ = run(sweep_model(case))
            done.append((axis, case, outcome))
            if on_result is not None:
                on_result(axis, case, outcome)
    except KeyboardInterrupt:
        return done, True
    return done, False


COLUMNS = ["axis", *asdict(Case()), *Outcome.__dataclass_fields__]


def write_sweep(rows: list[tuple[str, Case, Outcome]], path: Path) -> None:
    """The sweep's runs as CSV, one row each (:data:`COLUMNS`)."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as stream:
            writer = csv.writer(stream)
            writer.writerow(COLUMNS)
            for axis, case, outcome in rows:
                writer.writerow([axis, *asdict(case).values(), *asdict(outcome).values()])

    write_atomic(path, write)


AXIS_LABELS = {
    "speed": "speed c / c_cr",
    "step": "step h / h_ref (h_ref: quarter element)",
    "smearing": "smearing half-width / element length",
    "slenderness": "slenderness EJ / (GA L^2)",
}


def plot_sweep(rows: list[tuple[str, Case, Outcome]], path: Path) -> None:
    """Per axis, against the parameter: the largest Newton iterations per step, the largest
    constraint residual (and its bound), and the energy balance relative to the work: the
    scheme's dissipation ``energy_error + skew_work`` at ``rho_inf = 0.8``, the skew
    stiffness' work, and the identity's roundoff at ``rho_inf = 1`` (:func:`skew_work`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 4, figsize=(15, 9), sharey="row")
    for col, axis in enumerate(AXES):
        for rho, marker in zip(RHO_INF, "os", strict=True):
            mine = [
                (getattr(c, axis), o)
                for a, c, o in rows
                if a == axis and c.rho_inf == rho and o.steps
            ]
            x = np.array([v for v, _ in mine])
            got = {
                key: np.array([getattr(o, key) for _, o in mine])
                for key in (
                    "max_iterations",
                    "residual",
                    "residual_bound",
                    "energy_error",
                    "skew_work",
                    "identity",
                    "work",
                )
            }
            label = f"rho_inf = {rho:g}"
            axes[0, col].plot(x, got["max_iterations"], marker + "-", label=label)
            axes[1, col].semilogy(
                x,
                np.maximum(got["residual"], 1e-18),
                marker + "-",
                label=f"largest residual, {label}",
            )
            energy = axes[2, col]
            if rho == 1.0:
                energy.semilogy(
                    x,
                    np.maximum(got["identity"], 1e-18) / got["work"],
                    marker + "-",
                    label="|energy error + skew work|, " + label,
                )
                continue
            axes[1, col].semilogy(x, got["residual_bound"], "k--", label="bound (convergence rule)")
            energy.semilogy(
                x,
                np.abs(got["energy_error"] + got["skew_work"]) / got["work"],
                marker + "-",
                label="|scheme dissipation|, " + label,
            )
            energy.semilogy(
                x,
                np.abs(got["skew_work"]) / got["work"],
                "^:",
                label="|skew stiffness work|, " + label,
            )
        axes[2, col].set_xlabel(AXIS_LABELS[axis])
        for ax in axes[:, col]:
            if axis != "smearing":
                ax.set_xscale("log")
            ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].set_ylabel("largest Newton iterations per step")
    axes[1, 0].set_ylabel("position constraint residual")
    axes[2, 0].set_ylabel("energy / work")
    for row in range(3):
        axes[row, 0].legend(fontsize=7)
    fig.suptitle(
        "Stress sweeps: driven body on a clamped five-beam fv3 chain "
        "(one parameter varied about c = c_cr / 4, h = h_ref, smearing 0.2 h_e, "
        "r = 1e-2)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_shuttle(table: dict[str, np.ndarray], name: str, path: Path) -> None:
    """The shuttle over time: ``xi``, ``xi - xi_d``, the constraint residual, the body's
    transverse displacement and the energy balance (:func:`skew_work`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = table["t"]
    fig, axes = plt.subplots(4, 1, figsize=(10, 9), sharex=True)
    axes[0].plot(t, table[f"{name}.xi"], lw=0.6)
    axes[0].set_ylabel("xi")
    axes[1].plot(t, table[f"{name}.xi"] - table["drive"], lw=0.6, label="xi - xi_d")
    axes[1].plot(t, table[f"{name}.residual"], lw=0.6, label="position residual")
    axes[1].set_ylabel("drift, residual")
    axes[1].legend(fontsize=8)
    axes[2].plot(t, table["body_uy"], lw=0.6)
    axes[2].set_ylabel("body u_y")
    axes[3].plot(t, table["energy_error"], lw=0.6, label="energy error")
    axes[3].plot(t, -table["skew_work"], lw=0.6, label="- skew stiffness work")
    axes[3].plot(
        t,
        table["energy_error"] + table["skew_work"],
        lw=0.6,
        label="scheme dissipation (energy error + skew work)",
    )
    axes[3].set_ylabel("energy")
    axes[3].set_xlabel("t")
    axes[3].legend(fontsize=8)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle("Shuttle along the five-beam chain", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def reproduce(
    out: Path,
    dense: bool = True,
    passes: int = 100,
    steps_per_pass: int = 96,
    progress: bool = True,
) -> tuple[list, Outcome, bool]:
    """Run the shuttle and the sweep into ``out`` (replaced whole,
    :func:`fvbeam.io.replace_directory`); returns the sweep rows, the shuttle's outcome and
    whether Ctrl-C cut the sweep short."""
    result: dict = {}

    def fill(tmp: Path) -> None:
        model = shuttle_model(Case(), passes, steps_per_pass)
        shuttle, table = run(model, tmp / "shuttle", progress, interruptible=True)
        if table:
            plot_shuttle(table, model.slider.name, tmp / "shuttle.png")
        rows, interrupted = (
            ([], True) if shuttle.error == INTERRUPTED else sweep(cases(dense), progress)
        )
        write_sweep(rows, tmp / "sweeps.csv")
        if rows:
            plot_sweep(rows, tmp / "sweeps.png")
        result.update(rows=rows, shuttle=shuttle, interrupted=interrupted)

    replace_directory(out, fill)
    return result["rows"], result["shuttle"], result["interrupted"]


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="output directory")
    parser.add_argument(
        "--quick", action="store_true", help="the CI variant: coarse axes, a 50-pass shuttle"
    )
    args = parser.parse_args(argv)
    passes, steps = (50, 24) if args.quick else (100, 96)
    rows, shuttle, interrupted = reproduce(args.out, not args.quick, passes, steps)
    print(f"shuttle: {shuttle}")
    for axis, case, outcome in rows:
        print(
            f"rho_inf {case.rho_inf:g} {axis:12s} {getattr(case, axis):9.3g}  iterations "
            f"{outcome.max_iterations}  residual {outcome.residual:.2e} (bound "
            f"{outcome.residual_bound:.1e})  energy error / work "
            f"{outcome.energy_error / outcome.work:+.2e}, skew work / work "
            f"{outcome.skew_work / outcome.work:+.2e}, identity / work "
            f"{outcome.identity / outcome.work:.1e}  {outcome.error}"
        )
    if interrupted:
        print("interrupted: the runs above were kept")


if __name__ == "__main__":
    main()
