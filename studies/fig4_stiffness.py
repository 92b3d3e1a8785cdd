"""Figures 4 and 5 of the paper: tip stiffness of two beams joined by two sliders.

The sliding-beams setup (paper Sec. 6; Figure 3 is not in the text, so this is its
definition): cylinder beam C on ``[0, L]`` along x, clamped at 0; piston beam P on
``[s, s + L]``, its axial translation and its spin about x held at its bottom node (a real
strut's gas spring and torque links; their reactions vanish to first order).  Slider A: P's
bottom end node slides on C.  Slider B: C's top end node slides on P.  A transverse force
``F`` at P's tip.  ``EJ = 4.1e4 N m^2``, ``GA = 1.1e8 N``, ``L = 0.6 m``; ``EA = 10 GA`` and
``GJ = EJ`` play no role in this bending problem.  The tip stiffness ``k = F / v(s + L)`` is
normalised by ``EJ / L^3`` and compared with the analytic two-beam solution
(:func:`sliders.analytic.sliding_beams`, ``docs/sliders.md``).  The section, ``L`` and ``F``
are read from the setup's scene, ``studies/scenes/fig4_sliding_beams.toml``; this script
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
from functools import cached_property
from pathlib import Path

import numpy as np

from fvbeam import Beam, Section, Structure, Support, straight
from fvbeam.io import write_atomic
from sliders.analytic import sliding_beams
from sliders.chain import BeamChain
from sliders.joint import Slider
from sliders.statics import SliderSolution, SliderStatics, solve_translated

SCENE = Path(__file__).parent / "scenes" / "fig4_sliding_beams.toml"


def read_setup(path: Path = SCENE) -> tuple[Section, float, float]:
    """The section, the beams' length ``L`` and the tip force ``F`` from the scene (its
    first section and beam, its one load), which ``fvslider run`` also runs."""
    from sliders.scene import load_scene

    scene = load_scene(path)
    tube, beam = scene.section[0], scene.beam[0]
    section = Section.diagonal(EA=tube.EA, GAy=tube.GAy, GAz=tube.GAz, GJ=tube.GJ,
                               EJy=tube.EJy, EJz=tube.EJz)
    length = float(np.linalg.norm(np.subtract(beam.straight.end, beam.straight.start)))
    return section, length, float(np.linalg.norm(scene.load[0].force))


SECTION, L, F = read_setup()
EJ, GA = float(SECTION.stiffness[5, 5]), float(SECTION.stiffness[1, 1])  # EJz, GAy
KINDS = ("spherical", "classical")
STATIONS = np.arange(96) / 100
CASES = ([("fv3", n) for n in (1, 3, 5, 10, 20, 40)] + [("galerkin-p2", n) for n in (1, 3, 5)])
SMEARINGS = (0.0, 0.01)
COLUMNS = ("slider", "formulation", "n_elements", "smearing", "s_over_L", "k_norm",
           "k_norm_exact", "rel_error")
#: Paper Sec. 6 bounds on |rel_error|: (elements, on [0, 0.95], on [0, 0.8]).
BOUNDS = {"spherical": ((1, 0.07, 0.07), (3, 0.02, 0.011), (5, 0.02, 0.011)),
          "classical": ((1, 0.07, 0.07), (3, 0.025, 0.015), (5, 0.025, 0.015))}


class SlidingBeams:
    """The two beams built once; :meth:`stiffness` moves the piston and solves.
    ``orientation``: the classical sliders' form (:class:`sliders.joint.Slider`).  The
    piston is the cylinder's beam moved (same mesh, section and formulation), so one
    stiffness is assembled for both."""

    def __init__(self, formulation: str, n_elements: int, kind: str,
                 smearing: float = 0.0, orientation: str = "section") -> None:
        npe = 2 if formulation in ("fv2", "galerkin-p1") else 3
        self.cylinder = Beam(straight((0, 0, 0), (L, 0, 0), n_elements, npe), SECTION,
                             formulation)
        self.kind, self.smearing = kind, smearing * L / n_elements
        self.orientation = orientation if kind == "classical" else "section"
        self.supports = [Support(0, "start"), Support(1, "start", "ux+rx")]
        self._previous: SliderStatics | None = None
        self.iterations: list[int] = []

    def problem(self, s_over_L: float) -> tuple[SliderStatics, np.ndarray]:
        """The statics (condensed back end) and the tip load with the piston at
        ``s = s_over_L L``."""
        piston = self.cylinder.translated((s_over_L * L, 0, 0))
        structure = Structure([self.cylinder, piston])
        options = dict(smearing=self.smearing, orientation=self.orientation)
        sliders = [Slider(self.kind, BeamChain(structure, [0], "C"), (1, "start"), name="A",
                          **options),
                   Slider(self.kind, BeamChain(structure, [1], "P"), (0, "end"), name="B",
                          **options)]
        statics = SliderStatics(structure, self.supports, sliders, reuse=self._previous,
                                method="condensed")
        self._previous = statics
        return statics, structure.gather(1, piston.nodal_load("end", (0, F, 0)))

    @cached_property
    def template(self) -> tuple[SliderStatics, np.ndarray]:
        """The problem with the piston on the cylinder (``s = 0``): the statics every
        position's is a translation of (its stiffness assembled and factorised here, once)
        and the tip load; the sliders' batches that every position moves are built here
        too (:meth:`sliders.statics.SliderStatics.prepare_translations`)."""
        statics, load = self.problem(0.0)
        statics.prepare_translations()
        return statics, load

    def shifts(self, stations: np.ndarray) -> np.ndarray:
        """The beams' translations (B, 2, 3) at the stations ``s / L``: the cylinder stays,
        the piston moves along x by ``s``."""
        shifts = np.zeros((len(stations), 2, 3))
        shifts[:, 1, 0] = np.asarray(stations, dtype=float) * L
        return shifts

    def solve(self, stations: np.ndarray) -> list[SliderSolution | str]:
        """Every station at once, from the template moved (:func:`sliders.statics.
        solve_translated`): per station its solution or its failure message."""
        statics, f = self.template
        return solve_translated(statics, self.shifts(stations), np.tile(f, (len(stations), 1)))

    def stiffness(self, s_over_L: float) -> float:
        """Normalised tip stiffness ``F L^3 / (EJ v)`` with the piston at ``s = s_over_L L``."""
        statics, f = self.problem(s_over_L)
        solution = statics.solve(f)
        self.iterations.append(solution.iterations)
        return tip_stiffness(statics, solution)


def compile_kernels() -> None:
    """Compile the numba kernels of a static solve (joint equations, line state, condensed
    step, test functions at a point), or load them from their cache: two positions of
    each slider kind on one fv3 element (``fvslider compile``; about half a minute the
    first time on a machine, well under a second once cached)."""
    for kind in KINDS:
        SlidingBeams("fv3", 1, kind).solve(STATIONS[:2])


def tip_stiffness(statics: SliderStatics, solution: SliderSolution) -> float:
    """``F L^3 / (EJ v)`` from the piston's tip deflection ``v``."""
    structure = statics.structure
    tip = structure.beams[1].displacements(structure.local(1, solution.q), L)[0, 1]
    return F / tip * L**3 / EJ


def sweep(kind: str, formulation: str, n: int, smearing: float,
          stations: np.ndarray = STATIONS) -> tuple[np.ndarray, SlidingBeams]:
    """``k_norm`` at every station (all solved at once, :meth:`SlidingBeams.solve`); NaN
    where the configuration is singular."""
    model = SlidingBeams(formulation, n, kind, smearing)
    out = np.full(len(stations), np.nan)
    for i, solution in enumerate(model.solve(stations)):
        if not isinstance(solution, str):
            out[i] = tip_stiffness(model.template[0], solution)
            model.iterations.append(solution.iterations)
    return out, model


def compute(cases=CASES, smearings=SMEARINGS, stations: np.ndarray = STATIONS,
            progress: bool = True) -> list[dict]:
    """Rows of Figures 4 and 5 for every slider kind, formulation, mesh and smearing.

    ``progress``: a progress bar on a terminal (never when the output is not a terminal).
    """
    from tqdm import tqdm

    exact = {kind: np.array([sliding_beams(s * L, L, EJ, GA, kind)["k_norm"]
                             for s in stations]) for kind in KINDS}
    jobs = [(k, f, n, sm) for k in KINDS for f, n in cases for sm in smearings]
    rows = []
    for kind, formulation, n, smearing in tqdm(jobs, disable=None if progress else True,
                                               desc="fig4"):
        k, _ = sweep(kind, formulation, n, smearing, stations)
        for s, kn, ke in zip(stations, k, exact[kind]):
            rows.append(dict(slider=kind, formulation=formulation, n_elements=n,
                             smearing=smearing, s_over_L=s, k_norm=kn, k_norm_exact=ke,
                             rel_error=kn / ke - 1))
    return rows


def write_csv(rows: list[dict], path: Path) -> None:
    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, COLUMNS)
            writer.writeheader()
            for row in rows:
                writer.writerow({k: ("" if isinstance(v, float) and np.isnan(v) else v)
                                 for k, v in row.items()})

    write_atomic(path, write)


def plot(rows: list[dict], out: Path) -> None:
    """Figure 4 (stiffness) and Figure 5 (relative error), fv3 with 1, 3, 5 elements."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def series(kind, formulation, n):
        pick = [r for r in rows if r["slider"] == kind and r["formulation"] == formulation
                and r["n_elements"] == n and r["smearing"] == 0.0]
        return (np.array([r["s_over_L"] for r in pick]),
                np.array([r["k_norm"] for r in pick]),
                np.array([r["k_norm_exact"] for r in pick]))

    for name, error in (("fig4_stiffness.png", False), ("fig5_rel_error.png", True)):
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharex=True)
        for ax, kind in zip(axes, KINDS):
            s, _, exact = series(kind, "fv3", 1)
            if not error:
                ax.plot(s, exact, "k-", lw=2, label="analytic")
            for n, style in ((1, ":"), (3, "--"), (5, "-.")):
                s, k, exact = series(kind, "fv3", n)
                ax.plot(s, 100 * (k / exact - 1) if error else k, style,
                        label=f"fv3, {n} element{'s' if n > 1 else ''}")
            ax.set_title(f"{kind} slider")
            ax.set_xlabel("s / L")
            ax.set_ylabel("relative error of k [%]" if error else "k L^3 / EJ")
            ax.grid(alpha=0.3)
            ax.legend()
        fig.tight_layout()
        write_atomic(out / name, lambda tmp: fig.savefig(tmp, dpi=120))
        plt.close(fig)


def max_errors(rows: list[dict]) -> list[tuple[str, float, str]]:
    """Largest |rel_error| of fv3 (smearing 0) on [0, 0.95] and on [0, 0.8], one
    ``(case, error, reference)`` per slider kind, mesh and range, the reference being the
    paper's bound (and the stations where the configuration is singular, if any)."""
    out = []
    for kind in KINDS:
        for n, bound_all, bound_08 in BOUNDS[kind]:
            pick = [r for r in rows if r["slider"] == kind and r["formulation"] == "fv3"
                    and r["n_elements"] == n and r["smearing"] == 0.0]
            err = np.array([abs(r["rel_error"]) for r in pick])
            s = np.array([r["s_over_L"] for r in pick])
            singular = int(np.isnan(err).sum())
            note = f"; singular at {singular} stations" if singular else ""
            for top, bound in ((0.95, bound_all), (0.8, bound_08)):
                out.append((f"{kind} fv3 n={n}, s/L in [0, {top}]",
                            float(np.nanmax(err[s <= top])), f"paper: <= {bound}{note}"))
    return out


def reproduce(out: Path, plot_png: bool = True,
              progress: bool = True) -> list[tuple[str, float, str]]:
    """Compute Figures 4 and 5, write the CSV (and the PNGs, with pyvista renders of the
    deformed setup when pyvista is installed: :func:`studies.render.render_sliding_beams`)
    into ``out``, return :func:`max_errors`."""
    rows = compute(progress=progress)
    write_csv(rows, out / "fig4_stiffness.csv")
    if plot_png:
        plot(rows, out)
        if importlib.util.find_spec("pyvista") is not None:
            from studies.render import render_sliding_beams

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
