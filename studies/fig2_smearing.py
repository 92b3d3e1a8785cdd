"""Figure 2 of the paper: a body crossing an evaluation point, with increasing smearing.

The scene (the paper's Sec. 5.4 paragraph on Figure 2 gives no numbers, so this is
its definition): one fv3 element of length ``L = 1`` along x, clamped at 0, ``EJ = GA = 1``
(``EA = 1e3``, ``GJ = 1``: no role in this planar bending), linear kinematics, mass per length
``m = 1`` lumped over the fv regions (``docs/dynamics.md``) and a small rotary inertia
``rhoJ = 1e-4 m L^2`` per length about every axis (its modes, near 125-180 rad/s, are two
orders above the first bending mode).  Light structural damping: a viscoelastic section,
``C = c K`` with ``c = 2 zeta / omega_1``, ``zeta = 2 %`` of critical in the first mode
(``omega_1`` from :func:`fvbeam.modes.natural_frequencies` of the same lumped model).

A massless body carrying a unit transverse force ``F`` (global y) slides on the element
(``spherical`` slider, the body's rotations held) and is pushed at constant speed
(:class:`sliders.joints.drives.Linear`) from ``xi = 0.6 L`` to ``xi = 0.95 L`` in ``PERIODS = 100``
periods ``T_1 = 2 pi / omega_1`` of the first mode, starting from the static equilibrium at
``xi = 0.6 L``.  On the way it crosses the element's second evaluation point
``b = L (1 + 1/sqrt(3)) / 2`` (natural coordinate ``+1/sqrt(3)``), where its reaction passes
from the mid node's region to the tip node's.

Smearing levels, as fractions of the element length: 0, 1 %, 5 %, 10 %, 20 % of ``L`` is the
*total width* of the smearing, so the slider's box kernel (:mod:`fvbeam.smearing`) has the
half-width ``fraction L / 2``.  This is the reference implementation's ``smearing, dL``: a
linear ramp of the nodal shares over ``|s - s*| < dL`` in natural coordinates (the element
spans 2 natural units), i.e. over ``dL L`` of arc length (MBDyn's ``beam slider``; its test
value 0.01 is the paper's 1 %).  With this reading every level starts with the whole load on
the mid node's region and ends with it on the tip node's.

Time integration: generalized-alpha, ``rho_inf = RHO_INF``
(:class:`sliders.solve.dynamics.Dynamics`), fixed step ``T_1 / STEPS_PER_PERIOD``.
``docs/stability.md`` gives the step-halving check and the measured numbers.

Variants (:data:`VARIANTS`): ``damped`` (the figure), ``undamped`` (``zeta = 0``) and
``fast`` (a 10-period crossing, damped).

Run as ``python -m studies.fig2_smearing --out DIR``; writes ``DIR/fig2_smearing.csv``
(columns ``smearing,t,xi,shear_eval_point,tip_displacement_norm``: smearing as a fraction of
``L``, the shear ``Vy`` at the evaluation point ``b`` in units of ``F``, the tip displacement
in units of ``F L^3 / EJ``) and ``DIR/fig2_smearing.png`` (left: shear at ``b`` against
``xi / L``; right: tip displacement against ``xi / L``), and the same two files for the other
variants, ``fig2_smearing_undamped.*`` and ``fig2_smearing_10periods.*``.  Ctrl-C writes the
levels computed so far (the interrupted one up to its last step).
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fvbeam import (
    Beam,
    RigidBody,
    Section,
    Structure,
    Support,
    closed_forms,
    formulation,
    straight,
)
from fvbeam.io import write_atomic
from fvbeam.modes import natural_frequencies
from sliders.app.history import Recorder
from sliders.app.probes import LinearProbe, force_probe, node_probe
from sliders.joints.drives import Linear
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics

L, EJ, GA, F = 1.0, 1.0, 1.0, 1.0
MASS_PER_LENGTH = 1.0
#: Rotary inertia per length (about every axis), ``1e-4 m L^2``.
ROTARY_INERTIA = 1e-4
ZETA = 0.02
XI_START, XI_END = 0.6 * L, 0.95 * L
PERIODS = 100
#: Smearing levels: total width of the smearing as a fraction of the element length.
LEVELS = (0.0, 0.01, 0.05, 0.10, 0.20)
RHO_INF = 0.8
STEPS_PER_PERIOD = 40
#: The evaluation point crossed, ``b = L (1 + 1/sqrt(3)) / 2`` (recovery point 1).
EVALUATION_POINT = L * (1 + 1 / np.sqrt(3)) / 2
COLUMNS = ("smearing", "t", "xi", "shear_eval_point", "tip_displacement_norm")
#: The element's formulation and its mass: the paper's fv3 (lumped, its only kind) and, beside
#: it in the work-precision study, the cubic element (consistent), whose load vector is smooth
#: in the load's abscissa (no evaluation point to cross: smearing and the overshoot of the
#: shear at ``b`` are fv's).
FORMULATIONS = {"fv3": "lumped", "cubic": "consistent"}


@dataclass(frozen=True)
class Variant:
    """A run of every smearing level: damping ratio, crossing time in periods, file stem."""

    zeta: float
    periods: float
    stem: str


VARIANTS = {
    "damped": Variant(ZETA, PERIODS, "fig2_smearing"),
    "undamped": Variant(0.0, PERIODS, "fig2_smearing_undamped"),
    "fast": Variant(ZETA, 10, "fig2_smearing_10periods"),
}


def section() -> Section:
    """The element's section (module docstring)."""
    return Section.diagonal(
        EA=1e3,
        GAy=GA,
        GAz=GA,
        GJ=1.0,
        EJy=EJ,
        EJz=EJ,
        mass_per_length=MASS_PER_LENGTH,
        inertia=np.diag([ROTARY_INERTIA] * 3),
        name="fig2",
    )


def element(name: str = "fv3") -> Beam:
    """One element of formulation ``name`` (:data:`FORMULATIONS`) on ``[0, L]`` along x."""
    if name not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {', '.join(FORMULATIONS)}, got {name!r}")
    npe = formulation(name).nodes_per_element
    return Beam(straight((0, 0, 0), (L, 0, 0), 1, npe), section(), name)


def first_frequency(name: str = "fv3") -> float:
    """``omega_1`` (rad/s) of the clamped element with its mass (:data:`FORMULATIONS`)."""
    modes = natural_frequencies(
        Structure([element(name)]), [Support(0, 0, "clamp")], 1, mass=FORMULATIONS[name]
    )
    return float(modes.omega[0])


def speed(periods: float, name: str = "fv3") -> float:
    """Constant sliding speed that covers ``[XI_START, XI_END]`` in ``periods`` periods of
    the ``name`` element."""
    return (XI_END - XI_START) * first_frequency(name) / (2 * np.pi * periods)


def static_shear_and_tip(xi: float, smearing: float) -> tuple[float, float]:
    """Closed-form static shear at ``b`` and tip displacement for the load at ``xi`` smeared
    over the total width ``smearing L`` (box, cut at the element's ends and rescaled), valid
    when the kernel lies on one side of ``b``.

    On the tip node's region (``xi > b``) the shear at ``b`` is ``F`` and the tip displacement
    (:func:`fvbeam.closed_forms.cantilever_fv3`) is linear in the load's station, so a smeared
    load acts at its kernel's mean station; on the mid node's region the shear is 0.
    """
    lo, hi = max(xi - smearing * L / 2, 0.0), min(xi + smearing * L / 2, L)
    if lo < EVALUATION_POINT < hi:
        raise ValueError(
            f"the kernel [{lo:.4g}, {hi:.4g}] straddles b = "
            f"{EVALUATION_POINT:.4g}: no single-region closed form"
        )
    mean = (lo + hi) / 2 if hi > lo else xi
    flexural, shear, _ = closed_forms.cantilever_fv3(mean, L=L, EJ=EJ, GA=GA, F=F)
    return (F if mean > EVALUATION_POINT else 0.0), float(flexural + shear) * EJ / (F * L**3)


def static_tip(xi: float, smearing: float, name: str = "fv3") -> float:
    """The static tip displacement (units of ``F L^3 / EJ``) for the load at ``xi`` on the
    ``name`` element: fv3's from :func:`static_shear_and_tip`; the cubic element's is the
    Timoshenko cantilever's, ``xi^2 (3 L - xi) / (6 EJ) + xi / GA`` times ``F``
    (:func:`fvbeam.closed_forms.cantilever_exact`), exact at its nodes for a load anywhere
    (``docs/theory.md`` Sec. 9), for a point load only (smearing 0)."""
    if name == "fv3":
        return static_shear_and_tip(xi, smearing)[1]
    if name != "cubic" or smearing:
        raise ValueError(
            f"static tip of the {name!r} element at smearing {smearing}: fv3 at any smearing, "
            "cubic at smearing 0"
        )
    flexural, shear, _ = closed_forms.cantilever_exact(xi, L=L, EJ=EJ, GA=GA, F=F)
    return float(flexural + shear) * EJ / (F * L**3)


class Crossing:
    """The scene at one smearing level (total width ``smearing L``), damping ratio ``zeta``
    and crossing time ``periods`` T_1; ``xi_start`` (default ``XI_START``) starts the same
    motion later, from the static equilibrium there (the tests' shorter windows); ``name``
    the element's formulation (:data:`FORMULATIONS`, the paper's fv3 by default)."""

    def __init__(
        self,
        smearing: float,
        zeta: float = ZETA,
        periods: float = PERIODS,
        xi_start: float = XI_START,
        name: str = "fv3",
    ) -> None:
        if not 0 <= smearing < 1:
            raise ValueError(
                f"smearing must be a fraction of the element length in [0, 1), got {smearing}"
            )
        self.smearing, self.xi_start, self.omega_1 = smearing, xi_start, first_frequency(name)
        self.period = 2 * np.pi / self.omega_1
        self.velocity = speed(periods, name)
        self.t_end = (XI_END - xi_start) / self.velocity
        self.beam = element(name)
        self.structure = Structure(
            [self.beam], bodies=[RigidBody("body", (xi_start, 0, 0), mass=0.0)]
        )
        slider = Slider(
            "spherical",
            BeamChain(self.structure, [0]),
            "body",
            drive=Linear(xi_start, self.velocity),
            smearing=smearing * L / 2,
            kernel="box",
            name="body",
        )
        supports = [Support(0, 0, "clamp"), Support("body", kind="rx+ry+rz")]
        self.dynamics = Dynamics(
            self.structure,
            supports,
            [slider],
            self.structure.nodal_load("body", (0, F, 0)),
            damping=2 * zeta / self.omega_1,
            mass=FORMULATIONS[name],
            rho_inf=RHO_INF,
            method="condensed",
        )
        self._tip = self.structure.node_dofs((0, "end"))[1]

    def shear(self, q: np.ndarray) -> float:
        """Shear ``Vy`` at the evaluation point ``b``, in units of ``F``."""
        return float(self.beam.internal_forces(self.structure.local(0, q)).force[1, 1]) / F

    def tip(self, q: np.ndarray) -> float:
        """Tip displacement in units of ``F L^3 / EJ``."""
        return float(q[self._tip]) * EJ / (F * L**3)

    def recorder(self) -> Recorder:
        """An in-memory recorder with the shear and tip probes (linear in ``q``: the
        recorder evaluates them a block of steps at a time), in the units of
        :meth:`shear` and :meth:`tip`."""
        shear = force_probe(self.structure, 0, EVALUATION_POINT, "V2")
        tip = node_probe(self.structure, (0, "end"), "uy")
        return Recorder(
            None,
            probes={
                "shear": LinearProbe(shear.weights / F),
                "tip": LinearProbe(tip.weights * EJ / (F * L**3)),
            },
        )

    def run(
        self,
        steps_per_period: int = STEPS_PER_PERIOD,
        recorder: Recorder | None = None,
        progress: bool = False,
    ) -> dict[str, np.ndarray]:
        """Integrate from the static state to ``XI_END``; :func:`history` per step.  A
        ``KeyboardInterrupt`` propagates; ``recorder`` then holds the steps computed."""
        recorder = recorder if recorder is not None else self.recorder()
        self.dynamics.run(
            self.dynamics.static_state(),
            self.t_end,
            self.period / steps_per_period,
            recorder=recorder,
            progress=progress,
        )
        return history(recorder)


def history(recorder: Recorder) -> dict[str, np.ndarray]:
    """``t, xi, shear, tip`` and Newton ``iterations`` per step from a :class:`Crossing`
    recorder."""
    table = recorder.table() if recorder.rows else {}
    return {
        key: table.get(column, np.empty(0))
        for key, column in (
            ("t", "t"),
            ("xi", "body.xi"),
            ("shear", "shear"),
            ("tip", "tip"),
            ("iterations", "iterations"),
        )
    }


def overshoot(run: dict[str, np.ndarray]) -> float:
    """Largest excess of the shear at ``b`` over its static value ``F`` after the crossing."""
    return float(run["shear"].max() - 1.0)


def compute(
    variant: Variant, levels=LEVELS, steps_per_period: int = STEPS_PER_PERIOD, progress: bool = True
) -> tuple[dict[float, dict[str, np.ndarray]], bool]:
    """Every smearing level of ``variant``: ``{level: run}`` and whether Ctrl-C stopped it
    (then the levels computed so far, the interrupted one up to its last step)."""
    from tqdm.auto import tqdm

    runs = {}
    bar = tqdm(levels, desc=variant.stem, unit="level", disable=not progress)
    for level in bar:
        crossing = Crossing(level, variant.zeta, variant.periods)
        recorder = crossing.recorder()
        try:
            runs[level] = crossing.run(steps_per_period, recorder, progress=progress)
        except KeyboardInterrupt:
            runs[level] = history(recorder)
            bar.close()
            return runs, True
    return runs, False


def write_csv(runs: dict[float, dict[str, np.ndarray]], path: Path) -> None:
    """One row per level and step, ``COLUMNS``, floats at full precision."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(COLUMNS)
            for level, run in runs.items():
                for row in zip(run["t"], run["xi"], run["shear"], run["tip"], strict=True):
                    writer.writerow([repr(level), *map(repr, map(float, row))])

    write_atomic(path, write)


def plot(runs: dict[float, dict[str, np.ndarray]], variant: Variant, path: Path) -> None:
    """Two panels as the paper's Figure 2: shear at ``b`` and tip displacement vs ``xi / L``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2), sharex=True)
    for level, run in runs.items():
        label = "no smearing" if level == 0 else f"smearing {100 * level:g} % L"
        left.plot(run["xi"] / L, run["shear"], lw=1, label=label)
        right.plot(run["xi"] / L, run["tip"], lw=1, label=label)
    for ax in (left, right):
        ax.axvline(EVALUATION_POINT / L, color="0.6", ls=":", lw=1)
        ax.set_xlabel("xi / L")
        ax.grid(alpha=0.3)
    left.set_ylabel("shear at the evaluation point b [F]")
    right.set_ylabel("tip displacement [F L^3 / EJ]")
    left.legend()
    damping = f"zeta = {100 * variant.zeta:g} %" if variant.zeta else "undamped"
    fig.suptitle(
        f"one fv3 element, body crossing b = L (1 + 1/sqrt 3) / 2 in "
        f"{variant.periods:g} T_1 ({damping})"
    )
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=120))
    plt.close(fig)


def summary(
    runs: dict[float, dict[str, np.ndarray]], prefix: str = ""
) -> list[tuple[str, float, str]]:
    """Per level: the overshoot of the shear at ``b``, and the end values' differences from
    the static closed forms (:func:`static_shear_and_tip`); ``prefix`` starts each case."""
    out = []
    for level, run in runs.items():
        if not len(run["t"]):
            continue
        shear, tip = static_shear_and_tip(float(run["xi"][-1]), level)
        case = f"{prefix}{100 * level:g} %"
        out += [
            (f"{case} overshoot of V(b)", overshoot(run), "1 % cuts it tenfold (paper)"),
            (f"{case} end |V(b) - V_static|", abs(run["shear"][-1] - shear), "static closed form"),
            (
                f"{case} end |v(L) - v_static|",
                abs(run["tip"][-1] - tip),
                "closed_forms.cantilever_fv3",
            ),
        ]
    return out


def reproduce(
    out: Path, plot_png: bool = True, progress: bool = True, variants=tuple(VARIANTS)
) -> list[tuple[str, float, str]]:
    """Run the ``variants`` (keys of :data:`VARIANTS`), write their CSVs (and PNGs) into
    ``out``, return their :func:`summary` rows.  If Ctrl-C stops a run, what was computed is
    written and the ``KeyboardInterrupt`` raised again."""
    rows = []
    for key in variants:
        variant = VARIANTS[key]
        runs, interrupted = compute(variant, progress=progress)
        write_csv(runs, out / f"{variant.stem}.csv")
        if plot_png:
            plot(runs, variant, out / f"{variant.stem}.png")
        rows += summary(runs, prefix=f"{key} ")
        if interrupted:
            raise KeyboardInterrupt
    return rows


def main(argv: list[str] | None = None) -> int:
    """Run the variants asked for, print the summary; exit code 130 on Ctrl-C."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument(
        "--variants",
        nargs="+",
        choices=list(VARIANTS),
        default=list(VARIANTS),
        help="which runs (default: all)",
    )
    args = parser.parse_args(argv)
    start = time.perf_counter()
    try:
        rows = reproduce(args.out, variants=args.variants)
    except KeyboardInterrupt:
        print(f"interrupted: the levels computed are written to {args.out}", file=sys.stderr)
        return 130
    for case, value, reference in rows:
        print(f"{case:40s} {value:10.3e}  ({reference})")
    print(f"in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
