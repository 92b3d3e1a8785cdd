"""Figures 4 and 5 of the paper: tip stiffness of two beams joined by two sliders.

The sliding-beams setup (paper Sec. 6; Figure 3 is not in the text, so this is its
definition): cylinder beam C on ``[0, L]`` along x, clamped at 0; piston beam P on
``[s, s + L]``, its axial translation and its spin about x held at its bottom node (a real
strut's gas spring and torque links; their reactions vanish to first order).  Slider A: P's
bottom end node slides on C.  Slider B: C's top end node slides on P.  A transverse force
``F`` at P's tip.  ``EJ = 4.1e4 N m^2``, ``GA = 1.1e8 N``, ``L = 0.6 m``; ``EA = 10 GA`` and
``GJ = EJ`` play no role in this bending problem.  The tip stiffness ``k = F / v(s + L)`` is
normalised by ``EJ / L^3`` and compared with the analytic two-beam solution
(:func:`sliders.sliding_beams.exact.sliding_beams`, ``docs/sliders.md``).  The section, ``L``
and ``F`` are read from the setup's scene, ``studies/scenes/fig4_sliding_beams.toml``; this script
varies the slider kind, the formulation, the mesh, the smearing and the stations.

Run as ``python -m studies.fig4_stiffness --out DIR``; writes ``DIR/fig4_stiffness.csv``
(columns ``slider,formulation,n_elements,smearing,s_over_L,k_norm,k_norm_exact,rel_error``;
``smearing`` as a fraction of the element length; an empty ``k_norm`` where the
configuration is singular), ``DIR/fig4_stiffness.png`` (Figure 4) and
``DIR/fig5_rel_error.png`` (Figure 5), and prints the largest errors against the paper's
bounds.
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import time
from pathlib import Path

import numpy as np

from fvbeam import Section
from fvbeam.io import write_atomic
from sliders.sliding_beams.exact import sliding_beams
from sliders.sliding_beams.model import KINDS, Setup, SlidingBeams

SCENE = Path(__file__).parent / "scenes" / "fig4_sliding_beams.toml"


def read_setup(path: Path = SCENE) -> Setup:
    """The section, the beams' length ``L`` and the tip force ``F`` from the scene (its
    first section and beam, its one load), which ``fvslider run`` also runs."""
    from sliders.app.scene import load_scene

    scene = load_scene(path)
    tube, beam = scene.section[0], scene.beam[0]
    section = Section.diagonal(
        EA=tube.EA, GAy=tube.GAy, GAz=tube.GAz, GJ=tube.GJ, EJy=tube.EJy, EJz=tube.EJz
    )
    length = float(np.linalg.norm(np.subtract(beam.straight.end, beam.straight.start)))
    return Setup(section, length, float(np.linalg.norm(scene.load[0].force)))


SETUP = read_setup()
L, EJ, GA = SETUP.length, SETUP.EJ, SETUP.GA
STATIONS = np.arange(96) / 100
CASES = (
    [("fv3", n) for n in (1, 3, 5, 10, 20, 40)]
    + [("galerkin-p2", n) for n in (1, 3, 5)]
    + [("cubic", n) for n in (1, 3, 5)]
)
SMEARINGS = (0.0, 0.01)
COLUMNS = (
    "slider",
    "formulation",
    "n_elements",
    "smearing",
    "s_over_L",
    "k_norm",
    "k_norm_exact",
    "rel_error",
)
#: Paper Sec. 6 bounds on |rel_error|: (elements, on [0, 0.95], on [0, 0.8]).
BOUNDS = {
    "spherical": ((1, 0.07, 0.07), (3, 0.02, 0.011), (5, 0.02, 0.011)),
    "classical": ((1, 0.07, 0.07), (3, 0.025, 0.015), (5, 0.025, 0.015)),
}
#: The target for the cubic element with 3 elements per beam, both slider kinds.
CUBIC_TARGET = 0.002


def sweep(
    kind: str, formulation: str, n: int, smearing: float, stations: np.ndarray = STATIONS
) -> tuple[np.ndarray, SlidingBeams]:
    """``k_norm`` at every station (all solved at once, :meth:`SlidingBeams.solve`); NaN
    where the configuration is singular."""
    model = SlidingBeams(formulation, n, kind, smearing, setup=SETUP)
    out = np.full(len(stations), np.nan)
    for i, solution in enumerate(model.solve(stations)):
        if not isinstance(solution, str):
            out[i] = model.tip_stiffness(model.template[0], solution)
            model.iterations.append(solution.iterations)
    return out, model


def compute(
    cases=CASES, smearings=SMEARINGS, stations: np.ndarray = STATIONS, progress: bool = True
) -> list[dict]:
    """Rows of Figures 4 and 5 for every slider kind, formulation, mesh and smearing.

    ``progress``: a progress bar on a terminal (never when the output is not a terminal).
    """
    from tqdm import tqdm

    exact = {
        kind: np.array([sliding_beams(s * L, L, EJ, GA, kind)["k_norm"] for s in stations])
        for kind in KINDS
    }
    jobs = [(k, f, n, sm) for k in KINDS for f, n in cases for sm in smearings]
    rows = []
    for kind, formulation, n, smearing in tqdm(
        jobs, disable=None if progress else True, desc="fig4"
    ):
        k, _ = sweep(kind, formulation, n, smearing, stations)
        for s, kn, ke in zip(stations, k, exact[kind], strict=True):
            rows.append(
                dict(
                    slider=kind,
                    formulation=formulation,
                    n_elements=n,
                    smearing=smearing,
                    s_over_L=s,
                    k_norm=kn,
                    k_norm_exact=ke,
                    rel_error=kn / ke - 1,
                )
            )
    return rows


def write_csv(rows: list[dict], path: Path) -> None:
    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, COLUMNS)
            writer.writeheader()
            for row in rows:
                writer.writerow(
                    {k: ("" if isinstance(v, float) and np.isnan(v) else v) for k, v in row.items()}
                )

    write_atomic(path, write)


def unsmeared(rows: list[dict], kind: str, formulation: str, n: int) -> list[dict]:
    """The rows of a slider kind, formulation and mesh without smearing."""
    return [
        r
        for r in rows
        if r["slider"] == kind
        and r["formulation"] == formulation
        and r["n_elements"] == n
        and r["smearing"] == 0.0
    ]


def plot(rows: list[dict], out: Path) -> None:
    """Figure 4 (stiffness) and Figure 5 (relative error), fv3 with 1, 3, 5 elements, and
    the cubic element with 3 when the rows hold it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def series(kind, formulation, n):
        pick = unsmeared(rows, kind, formulation, n)
        return (
            np.array([r["s_over_L"] for r in pick]),
            np.array([r["k_norm"] for r in pick]),
            np.array([r["k_norm_exact"] for r in pick]),
        )

    for name, error in (("fig4_stiffness.png", False), ("fig5_rel_error.png", True)):
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharex=True)
        for ax, kind in zip(axes, KINDS, strict=True):
            s, _, exact = series(kind, "fv3", 1)
            if not error:
                ax.plot(s, exact, "k-", lw=2, label="analytic")
            curves = [("fv3", n, style) for n, style in ((1, ":"), (3, "--"), (5, "-."))]
            curves.append(("cubic", 3, "-"))
            for formulation, n, style in curves:
                s, k, exact = series(kind, formulation, n)
                if not len(s):
                    continue
                ax.plot(
                    s,
                    100 * (k / exact - 1) if error else k,
                    style,
                    label=f"{formulation}, {n} element{'s' if n > 1 else ''}",
                )
            ax.set_title(f"{kind} slider")
            ax.set_xlabel("s / L")
            ax.set_ylabel("relative error of k [%]" if error else "k L^3 / EJ")
            ax.grid(alpha=0.3)
            ax.legend()
        fig.tight_layout()
        write_atomic(out / name, lambda tmp, fig=fig: fig.savefig(tmp, dpi=120))
        plt.close(fig)


def max_errors(rows: list[dict]) -> list[tuple[str, float, str]]:
    """Largest |rel_error| of fv3 (smearing 0) on [0, 0.95] and on [0, 0.8], one
    ``(case, error, reference)`` per slider kind, mesh and range, the reference being the
    paper's bound (and the stations where the configuration is singular, if any); then the
    cubic element's on [0, 0.95] against its target (when the rows hold it)."""

    def errors(kind: str, formulation: str, n: int) -> tuple[np.ndarray, np.ndarray]:
        pick = unsmeared(rows, kind, formulation, n)
        return np.array([abs(r["rel_error"]) for r in pick]), np.array(
            [r["s_over_L"] for r in pick]
        )

    out = []
    for kind in KINDS:
        for n, bound_all, bound_08 in BOUNDS[kind]:
            err, s = errors(kind, "fv3", n)
            singular = int(np.isnan(err).sum())
            note = f"; singular at {singular} stations" if singular else ""
            for top, bound in ((0.95, bound_all), (0.8, bound_08)):
                out.append(
                    (
                        f"{kind} fv3 n={n}, s/L in [0, {top}]",
                        float(np.nanmax(err[s <= top])),
                        f"paper: <= {bound}{note}",
                    )
                )
    for kind in KINDS:
        for n in (1, 3, 5):
            err, _ = errors(kind, "cubic", n)
            if len(err):
                out.append(
                    (
                        f"{kind} cubic n={n}, s/L in [0, 0.95]",
                        float(np.nanmax(err)),
                        f"target: <= {CUBIC_TARGET} with 3 elements",
                    )
                )
    return out


def reproduce(
    out: Path, plot_png: bool = True, progress: bool = True
) -> list[tuple[str, float, str]]:
    """Compute Figures 4 and 5, write the CSV (and the PNGs, with pyvista renders of the
    deformed setup when pyvista is installed: :func:`studies.render.render_sliding_beams`)
    into ``out``, return :func:`max_errors`."""
    rows = compute(progress=progress)
    write_csv(rows, out / "fig4_stiffness.csv")
    if plot_png:
        plot(rows, out)
        if importlib.util.find_spec("pyvista") is not None:
            from .render import render_sliding_beams

            for line in render_sliding_beams(out):
                print(line)
    return max_errors(rows)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"))
    args = parser.parse_args(argv)
    start = time.perf_counter()
    for case, error, reference in reproduce(args.out):
        print(f"{case:38s} max |err| {error:.4f} ({reference})")
    print(f"in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
