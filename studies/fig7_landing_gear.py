"""Figure 7 of the paper: a telescopic nose landing gear drop with spin-up and spring-back.

The gear (:mod:`sliders.gear.model`, ``docs/landing_gear.md``): a 300 kg airframe
touching down at 2.8 m/s sink and 40 m/s forward speed on a vertical strut of two tubes joined
by two sliders (the paper's Figures 3-5), an oleo-pneumatic strut, a 12 kg axle and a wheel
spun up by the ground.  Models ``rigid`` (the tubes' section scaled by 1e5), ``fv3-1``,
``fv3-3``, ``fv3-5`` (elements per tube), classical sliders (``--slider spherical`` for the
other kind), 0.3 s each.

Run as ``python -m studies.fig7_landing_gear --out DIR``; writes

* ``DIR/fig7_landing_gear.csv``: columns ``model,t,attachment_longitudinal,ground_vertical,
  ground_longitudinal,top_slider,bottom_slider,stroke,wheel_speed`` (every step);
* ``DIR/fig7_landing_gear.png``: the paper's four panels (longitudinal attachment load,
  ground loads, top and bottom slider loads against time, every model on each);
* ``DIR/fig7_landing_gear_summary.csv``: per model the peaks with their times, the spin-up,
  lift-off and spring-back, and the peak bearing friction over the peak vertical load with
  ``mu = 0.02`` on both sliders, post-processed from the slider reactions
  (``friction_post_fraction``), and in the dynamics (``friction_dynamic``, its time and
  ``friction_dynamic_fraction``, a second run of each model with friction on its sliders:
  :func:`friction_in_dynamics`); the strut's bottoming stop (``bottoming``: the first time it
  is reached, empty if never, its largest penetration, zero if never, its time and the
  strut's force then);
* ``DIR/fig7_render.png``: the finest model at its spin-up peak, deflections magnified
  (pyvista, when installed).

The rigid model is compared with its independent ODEs (``studies/landing_gear_ode.py``) in
:func:`reproduce`'s table.  Every file is written atomically; an interrupted run (Ctrl-C)
writes the models finished so far and stops.
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import math
import time
from pathlib import Path

import numpy as np

from fvbeam.io import write_atomic
from sliders.gear.model import MODELS, GearModel
from sliders.gear.outputs import COLUMNS, GearRun

#: The paper's figures (Sec. 7) this study is compared with.
PAPER_VERTICAL = 13_000.0
PAPER_FRICTION = (0.08, 0.10)
#: The fixed step [s] (``docs/landing_gear.md``, "Convergence": it converges the peaks of
#: every model to better than 1 %).
STEP = 1e-4
T_END = 0.3
#: The friction run's summary columns (:func:`friction_in_dynamics`).
FRICTION = ("friction_dynamic", "friction_dynamic_time", "friction_dynamic_fraction")
#: The summary's columns, in order.
SUMMARY = (
    "model",
    "slider",
    "ground_vertical",
    "ground_vertical_time",
    "ground_longitudinal",
    "ground_longitudinal_time",
    "attachment_longitudinal_spin_up",
    "attachment_longitudinal_spin_up_time",
    "attachment_longitudinal",
    "attachment_longitudinal_time",
    "top_slider",
    "top_slider_time",
    "bottom_slider",
    "bottom_slider_time",
    "stroke",
    "stroke_time",
    "spin_up_time",
    "lift_off_time",
    "spring_back",
    "spring_back_time",
    "spring_back_frequency",
    "friction_post",
    "friction_post_time",
    "friction_post_fraction",
    "friction_dynamic",
    "friction_dynamic_time",
    "friction_dynamic_fraction",
    "bottoming",
    "bottoming_penetration",
    "bottoming_penetration_time",
    "bottoming_force",
    "steps",
    "iterations",
    "seconds",
)


def friction_in_dynamics(model: str, slider: str, step: float, t_end: float) -> dict[str, float]:
    """The peak bearing friction along the strut, its time and its fraction of the peak
    vertical load, with ``mu_b = 0.02`` on both sliders in the dynamics
    (:class:`sliders.joints.friction.Friction` on the sliders of ``GearModel(model,
    slider=slider, friction=True)``): the friction run's own summary
    (:meth:`sliders.gear.outputs.GearRun.summary`, ``friction_dynamic*``)."""
    summary = GearModel(model, slider=slider, friction=True).simulate(t_end, step).summary()
    return {key: float(summary[key]) for key in FRICTION}


def simulate(
    models: tuple[str, ...] = MODELS,
    slider: str = "classical",
    step: float = STEP,
    t_end: float = T_END,
    progress: bool = True,
    keep: str | None = None,
) -> tuple[dict[str, GearRun], dict[str, dict[str, float]]]:
    """Each model's run, in order (``keep``: the model whose states are kept, for the
    render), and its friction in the dynamics (:func:`friction_in_dynamics`).  Ctrl-C stops
    after the runs finished so far (returned)."""
    from tqdm.auto import tqdm

    runs: dict[str, GearRun] = {}
    frictions: dict[str, dict[str, float]] = {}
    try:
        for name in tqdm(models, desc="models", unit="model", disable=None if progress else True):
            run = GearModel(name, slider=slider).simulate(t_end, step, False, keep == name)
            frictions[name] = friction_in_dynamics(name, slider, step, t_end)
            runs[name] = run
    except KeyboardInterrupt:
        print(f"interrupted: writing the {len(runs)} models finished")
    return runs, frictions


def write_rows(path: Path, rows: list[dict], columns: tuple[str, ...]) -> None:
    """Rows as CSV (floats at full precision, NaN as empty), atomically."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
            writer.writeheader()
            for row in rows:
                writer.writerow(
                    {
                        k: ("" if isinstance(v, float) and math.isnan(v) else v)
                        for k, v in row.items()
                    }
                )

    write_atomic(path, write)


def write_csv(runs: dict[str, GearRun], path: Path) -> None:
    """The study's columns, every step of every model."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["model", "t", *COLUMNS])
            for name, run in runs.items():
                table = np.column_stack([run.t] + [run.outputs[c] for c in COLUMNS])
                writer.writerows([name, *map(repr, row)] for row in table.tolist())

    write_atomic(path, write)


def plot(runs: dict[str, GearRun], path: Path) -> None:
    """The paper's Figure 7: longitudinal attachment load (top left), ground loads (top
    right: vertical solid, longitudinal dashed), top and bottom slider loads (bottom)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 8), sharex=True)
    panels = (
        (axes[0, 0], ("attachment_longitudinal",), "longitudinal attachment load [N]"),
        (axes[0, 1], ("ground_vertical", "ground_longitudinal"), "ground loads [N]"),
        (axes[1, 0], ("top_slider",), "top slider load [N]"),
        (axes[1, 1], ("bottom_slider",), "bottom slider load [N]"),
    )
    for k, (name, run) in enumerate(runs.items()):
        colour = f"C{k}"
        for ax, columns, _ in panels:
            for column, style in zip(columns, ("-", "--"), strict=False):
                label = name if column == columns[0] else None
                ax.plot(run.t, run.outputs[column] / 1e3, style, color=colour, lw=1, label=label)
    for ax, _, title in panels:
        ax.set_title(title.replace("[N]", "[kN]"))
        ax.grid(alpha=0.3)
        ax.set_ylabel("kN")
    axes[0, 1].text(
        0.98,
        0.95,
        "solid: vertical\ndashed: longitudinal",
        ha="right",
        va="top",
        transform=axes[0, 1].transAxes,
        fontsize=8,
    )
    axes[0, 0].legend(fontsize=8)
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    slider = next(iter(runs.values())).slider
    fig.suptitle(f"landing gear drop, {slider} sliders (paper Figure 7)")
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def render_spin_up(run: GearRun, path: Path, slider: str = "classical") -> str:
    """The gear at its spin-up peak (the largest backward attachment load before the
    spin-up), seen from the side, elastic deflections magnified, drawn relative to the
    airframe (its travel taken off every part, the ground's included), the wheel on its
    ground.  The tubes are drawn at their section's size, the cylinder translucent around
    the piston (:mod:`sliders.app.shapes`)."""
    from sliders.app.render import render

    assert run.states is not None, "the run must keep its states"
    _, when = run.peak("attachment_longitudinal", -1.0, stop=run.spin_up_time())
    t, q, unknowns = min(run.states, key=lambda s: abs(s[0] - when))
    model = GearModel(run.model, slider=slider)
    s = model.structure
    scale = render(
        path,
        s,
        q,
        model.sliders,
        unknowns,
        title=f"landing gear {run.model}, {slider} sliders, spin-up peak, t = {1e3 * t:.1f} ms",
        window_size=(1000, 900),
        held=s.support_dofs(model.supports),
        forces=model.forces,
        follow="airframe",
    )
    return f"{path} (deflections x {scale:.3g})"


def against(runs: dict[str, GearRun], summaries: dict[str, dict]) -> list[tuple[str, float, str]]:
    """The study's checks (``fvslider reproduce``'s table): the rigid model against its ODEs
    (target 1e-3), the peak vertical load against the paper's 13 kN, the spread of the
    flexible models' peaks (the paper: practically indistinguishable) and the friction
    fraction against the paper's 8-10 %."""
    rows: list[tuple[str, float, str]] = []
    if "rigid" in summaries:
        from . import landing_gear_ode as ode

        reference = ode.summary(ode.simulate(rtol=1e-8))
        ours = summaries["rigid"]
        for name in ("ground_vertical", "ground_longitudinal", "attachment_longitudinal"):
            rows.append(
                (
                    f"rigid vs ODE: peak {name}",
                    abs(abs(float(ours[name])) / abs(reference[name]) - 1),
                    "target: <= 1e-3",
                )
            )
        rows.append(
            (
                "rigid vs ODE: spin-up time",
                abs(float(ours["spin_up_time"]) / reference["spin_up_time"] - 1),
                "target: <= 1e-3",
            )
        )
    flexible = [summaries[m] for m in MODELS[1:] if m in summaries]
    for s in flexible[-1:]:
        rows.append(
            (
                f"{s['model']} peak vertical vs 13 kN",
                abs(float(s["ground_vertical"]) / PAPER_VERTICAL - 1),
                "paper: about 13 kN",
            )
        )
    if len(flexible) > 1:
        for name in ("ground_vertical", "attachment_longitudinal_spin_up", "spring_back"):
            values = np.array([float(s[name]) for s in flexible])
            rows.append(
                (
                    f"fv3-1/3/5 spread: {name}",
                    float(np.ptp(values) / np.abs(values).max()),
                    "paper: indistinguishable",
                )
            )
    for s in flexible[-1:]:
        low, high = PAPER_FRICTION
        for how in ("post", "dynamic"):
            fraction = float(s[f"friction_{how}_fraction"])
            rows.append(
                (
                    f"{s['model']} friction fraction ({how}) {100 * fraction:.1f} % "
                    f"({s['slider']})",
                    max(low - fraction, fraction - high, 0.0),
                    "paper: 8-10 %",
                )
            )
    return rows


def reproduce(
    out: Path,
    plot_png: bool = True,
    progress: bool = True,
    slider: str = "classical",
    step: float = STEP,
    models: tuple[str, ...] = MODELS,
) -> list[tuple[str, float, str]]:
    """Simulate, write the CSV, the summary, the figure and the render into ``out``, and
    return the checks (:func:`against`)."""
    render_it = plot_png and importlib.util.find_spec("pyvista") is not None
    runs, frictions = simulate(
        models, slider, step, progress=progress, keep=models[-1] if render_it else None
    )
    summaries = {name: run.summary() | frictions[name] for name, run in runs.items()}
    write_csv(runs, out / "fig7_landing_gear.csv")
    write_rows(out / "fig7_landing_gear_summary.csv", list(summaries.values()), SUMMARY)
    if plot_png and runs:
        plot(runs, out / "fig7_landing_gear.png")
        if render_it and models[-1] in runs:
            print(render_spin_up(runs[models[-1]], out / "fig7_render.png", slider))
    for s in summaries.values():
        print(
            f"{s['model']:6s} F_z {float(s['ground_vertical']):8.0f} N at "
            f"{1e3 * float(s['ground_vertical_time']):5.1f} ms, spin-up attachment "
            f"{float(s['attachment_longitudinal_spin_up']):7.0f} N, spin-up "
            f"{1e3 * float(s['spin_up_time']):5.1f} ms, spring-back "
            f"{float(s['spring_back']):6.0f} N at {float(s['spring_back_frequency']):5.1f} Hz, "
            f"friction {100 * float(s['friction_post_fraction']):4.1f} % post-processed, "
            f"{100 * float(s['friction_dynamic_fraction']):4.1f} % in the dynamics, "
            f"{float(s['seconds']):.2f} s"
        )
    return against(runs, summaries)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--slider", choices=("classical", "spherical"), default="classical")
    parser.add_argument("--step", type=float, default=STEP, help="fixed time step [s]")
    parser.add_argument(
        "--models",
        type=lambda text: tuple(text.split(",")),
        default=MODELS,
        help=f"comma-separated, of {','.join(MODELS)}",
    )
    args = parser.parse_args(argv)
    start = time.perf_counter()
    for case, error, reference in reproduce(
        args.out, slider=args.slider, step=args.step, models=args.models
    ):
        print(f"{case:48s} {error:.3g} ({reference})")
    print(f"in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
