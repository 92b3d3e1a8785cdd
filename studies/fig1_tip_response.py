"""Figure 1 of the paper: tip response of a one-element cantilever to a travelling force.

A cantilever of length ``L = 1``, clamped at 0, with ``EJ = GA = 1``, carries a unit
transverse force ``F`` at the station ``xi``.  Figure 1 plots, against ``xi / L``, the
flexural and the shear parts of the tip displacement ``v(L)`` and the tip rotation
``phi(L)`` (paper Secs. 5.1-5.4).  Closed forms (``fvbeam.closed_forms``):

* exact Timoshenko beam (Sec. 5.1)::

      v(L) = F (xi^2 (3 L - xi) / (6 EJ) + xi / GA),     phi(L) = F xi^2 / (2 EJ)

* one 2-node finite-volume element, evaluation point ``L / 2`` (Sec. 5.2)::

      v(L) = F (L^2 (xi - L/2) / (2 EJ) + L / GA) step(xi - L/2)
      phi(L) = F L ramp(xi - L/2) / EJ

* one 3-node finite-volume element, evaluation points ``a, b = L (1 -+ 1/sqrt(3)) / 2``
  (Sec. 5.3): nothing moves for ``xi < a``; for ``a < xi < b``
  ``v(L) = F (L b (xi - a) / (2 EJ) + L / (2 GA))``, ``phi(L) = F L (xi - a) / (2 EJ)``;
  for ``xi > b``::

      v(L) = F (L^2 (3 xi - L) / (6 EJ) + L / GA),       phi(L) = F L (xi - L/2) / EJ

A force exactly on an evaluation point (here ``xi = L / 2`` for fv2) is shared half and
half between the two influence regions, by the library and by the closed forms alike.
The Galerkin elements (one P1 or P2 element, reduced integration) have no closed form here.

The numerical rows come from ``fvbeam`` solves.  For these one-element cantilevers the
internal forces at the evaluation (quadrature) points do not depend on the stiffnesses, so
the tip displacement is exactly ``v = a / EJ + b / GA``: two solves, with ``GA = 1`` and
``GA = 2`` (``EJ = 1``), give the flexural part ``a`` and the shear part ``b``, and a third
solve with ``GA = 4`` checks the assumption (the script raises if it fails).  ``EA`` and
``GJ`` play no role in bending in the x-y plane; they are set to 1e3.

The setup (length, stiffnesses, load) is read from its scene,
``studies/scenes/fig1_cantilever.toml``, which ``fvslider run`` also runs; this script varies
the formulation and ``GA`` and samples 101 load stations.

Run as ``python -m studies.fig1_tip_response --out DIR``; writes
``DIR/fig1_tip_response.csv`` and ``DIR/fig1_tip_response.png``.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

from fvbeam import Beam, LinearStatics, Section, Support, closed_forms, straight
from fvbeam.io import write_atomic

SCENE = Path(__file__).parent / "scenes" / "fig1_cantilever.toml"


def read_setup(path: Path = SCENE) -> tuple[float, float, float, float]:
    """``L``, ``EJ``, ``F`` and the stiffness of ``EA`` and ``GJ`` (no role in this bending
    problem) from the scene: its one straight beam, its section and its point load."""
    from sliders.app.scene import load_scene

    scene = load_scene(path)
    beam, section, load = scene.beam[0], scene.section[0], scene.load[0]
    length = float(np.linalg.norm(np.subtract(beam.straight.end, beam.straight.start)))
    return length, section.EJz, float(np.linalg.norm(load.force)), section.EA


L, EJ, F, STIFFNESS = read_setup()
FORMULATIONS = ("exact", "fv2", "fv3", "galerkin-p1", "galerkin-p2")
CLOSED_FORMS = {
    "exact": closed_forms.cantilever_exact,
    "fv2": closed_forms.cantilever_fv2,
    "fv3": closed_forms.cantilever_fv3,
}
COLUMNS = ("formulation", "xi_over_L", "v_flexural", "v_shear", "phi")
STATIONS = np.arange(101) / 100
SPLIT_TOLERANCE = 1e-12


def tip_response(formulation: str, GA: float, stations: np.ndarray) -> np.ndarray:
    """Tip displacement and rotation of one element for a unit force at each station.

    Parameters
    ----------
    formulation
        ``fv2``, ``fv3``, ``galerkin-p1`` or ``galerkin-p2`` (reduced integration).
    GA
        Shear stiffness (``EJ = 1``).
    stations
        Load stations ``xi / L``.

    Returns
    -------
    ``(n, 2)`` array of ``(v(L), phi(L))``.
    """
    nodes = 2 if formulation in ("fv2", "galerkin-p1") else 3
    section = Section.diagonal(EA=STIFFNESS, GAy=GA, GAz=GA, GJ=STIFFNESS, EJy=EJ, EJz=EJ)
    beam = Beam(
        straight((0, 0, 0), (L, 0, 0), n_elements=1, nodes_per_element=nodes), section, formulation
    )
    statics = LinearStatics(beam, [Support(0, "start")])
    out = np.empty((len(stations), 2))
    for k, s in enumerate(stations):
        q = statics.solve(beam.point_load(s * L, force=(0, F, 0)))
        out[k] = beam.displacements(q, L)[0, [1, 5]]
    return out


def split(formulation: str, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flexural and shear parts of ``v(L)`` and ``phi(L)`` from solves with ``GA = 1, 2``.

    Raises
    ------
    RuntimeError
        If a third solve (``GA = 4``) does not match ``v = a + b / GA`` and a
        ``GA``-independent ``phi`` to ``SPLIT_TOLERANCE`` relative.
    """
    (v1, phi), (v2, _), (v4, phi4) = (
        tip_response(formulation, GA, stations).T for GA in (1.0, 2.0, 4.0)
    )
    shear = 2 * (v1 - v2)
    flexural = v1 - shear
    scale = max(np.abs(v1).max(), np.abs(phi).max(), np.finfo(float).tiny)
    error = max(np.abs(flexural + shear / 4 - v4).max(), np.abs(phi4 - phi).max()) / scale
    if error > SPLIT_TOLERANCE:
        raise RuntimeError(
            f"{formulation}: v(L) is not a / EJ + b / GA (relative misfit {error:.2e} at GA = 4)"
        )
    return flexural, shear, phi


def compute(
    stations: np.ndarray | None = None, *, timings: dict[str, float] | None = None
) -> list[dict]:
    """Rows of Figure 1: one per formulation and station.

    Parameters
    ----------
    stations
        Load stations ``xi / L``; default 0, 0.01, ..., 1.
    timings
        If given, filled with the wall time in seconds of each formulation.

    Returns
    -------
    Dicts with the keys of ``COLUMNS``, formulations in the order of ``FORMULATIONS``.
    """
    stations = STATIONS if stations is None else np.asarray(stations, dtype=float)
    rows = []
    for name in FORMULATIONS:
        start = time.perf_counter()
        if name == "exact":
            values = closed_forms.cantilever_exact(stations * L, L=L, EJ=EJ, GA=1.0, F=F)
        else:
            values = split(name, stations)
        if timings is not None:
            timings[name] = time.perf_counter() - start
        rows += [
            dict(zip(COLUMNS, (name, float(s), *map(float, v)), strict=True))
            for s, *v in zip(stations, *values, strict=True)
        ]
    return rows


def write_csv(rows: list[dict], path: Path) -> None:
    """Write the rows with header ``COLUMNS``, floats at full precision (``repr``)."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=COLUMNS)
            writer.writeheader()
            writer.writerows(rows)

    write_atomic(path, write)


def plot(rows: list[dict], path: Path) -> None:
    """Three panels as in the paper: flexural part, shear part, tip rotation vs ``xi / L``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(10, 8), layout="constrained")
    grid = fig.add_gridspec(2, 2)
    panels = [
        (fig.add_subplot(grid[0, 0]), "v_flexural", "flexural part of v(L) [F L^3 / EJ]"),
        (fig.add_subplot(grid[0, 1]), "v_shear", "shear part of v(L) [F L / GA]"),
        (fig.add_subplot(grid[1, :]), "phi", "tip rotation phi(L) [F L^2 / EJ]"),
    ]
    styles = {
        "exact": "k-",
        "fv2": "C0--",
        "fv3": "C1-.",
        "galerkin-p1": "C2:",
        "galerkin-p2": "C3:",
    }
    for ax, key, label in panels:
        for name in FORMULATIONS:
            mine = [r for r in rows if r["formulation"] == name]
            ax.plot(
                [r["xi_over_L"] for r in mine], [r[key] for r in mine], styles[name], label=name
            )
        ax.set(xlabel="xi / L", ylabel=label)
        ax.grid(alpha=0.3)
    panels[0][0].legend()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=150))
    plt.close(fig)


def closed_form_errors(rows: list[dict]) -> list[tuple[str, float, str]]:
    """Largest difference of the rows from their closed form, one ``(formulation, error,
    closed form)`` per formulation that has one."""
    out = []
    for name, closed_form in CLOSED_FORMS.items():
        mine = [r for r in rows if r["formulation"] == name]
        xi = np.array([r["xi_over_L"] for r in mine]) * L
        got = np.array([[r[k] for k in COLUMNS[2:]] for r in mine]).T
        diff = np.abs(got - np.array(closed_form(xi, L=L, EJ=EJ, GA=1.0, F=F))).max()
        out.append((name, float(diff), f"closed_forms.cantilever_{name}"))
    return out


def reproduce(
    out: Path, plot_png: bool = True, timings: dict[str, float] | None = None
) -> list[tuple[str, float, str]]:
    """Compute Figure 1, write the CSV (and the PNG) into ``out``, return
    :func:`closed_form_errors`; ``timings`` as in :func:`compute`."""
    rows = compute(timings=timings)
    write_csv(rows, out / "fig1_tip_response.csv")
    if plot_png:
        plot(rows, out / "fig1_tip_response.png")
    return closed_form_errors(rows)


def main(argv: list[str] | None = None) -> None:
    """Compute Figure 1, write the CSV and PNG to ``--out``, print one line per formulation."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"), help="output directory")
    args = parser.parse_args(argv)
    timings: dict[str, float] = {}
    errors = {name: (error, form) for name, error, form in reproduce(args.out, timings=timings)}
    for name in FORMULATIONS:
        check = (
            f"max |row - {errors[name][1]}| = {errors[name][0]:.1e}"
            if name in errors
            else "no closed form"
        )
        print(f"{name:12s} {check:46s} {timings[name]:.3f} s")


if __name__ == "__main__":
    main()
