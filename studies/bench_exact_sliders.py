"""Benchmark of a slider on a line of exact beams in statics, beside the linear slider, merged
into ``results/bench.json`` under ``exact_sliders``.

``bearing``
    A rod (``L = 1`` m along ``x``, ``EJ = 1`` N m^2, ``GA = 1e3`` N, ``EA = 1e5`` N, fv3)
    pushed through a bearing held in space at ``x = 0.4`` m (a classical slider whose body
    is held), held axially (and in twist) at its far end, a tip load ``P = 1`` N along
    ``y`` (:func:`bearing`).  Per mesh (8, 16, 32 elements): the exact static solve
    (:func:`fvbeam.exact_statics.solve_static` on
    :class:`~sliders.joints.exact_slider_model.SlidingModel`) and the linear one
    (:class:`~sliders.solve.statics.SliderStatics`), each timed with ``time.perf_counter``
    around the solve (median and minimum of the repeats, the models built apart), with its
    Newton iterations and, beside the time, the relative error of the configurational force
    (the far end's support force) against the energy closed form ``M^2 / 2 EJ + V^2 / 2 GA``
    (``docs/exact_sliders.md``; ``M`` from the exact tip's place).

Run as ``python -m studies.bench_exact_sliders --out results/bench.json`` (``make bench``;
``--quick``: 8 elements, one repeat).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.exact_statics import solve_static
from fvbeam.mesh import straight
from fvbeam.section import Section
from fvbeam.structure import Structure
from fvbeam.support import Support
from sliders.joints.exact_model import ExactModel
from sliders.joints.exact_slider_model import ExactSlider, SlidingModel
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.statics import SliderStatics

from .bench import bench_arguments, environment, summary, write_merged

KEY = "exact_sliders"
#: The rod's stiffness (N m^2, N), the bearing's place (m) and the tip load (N).
EJ, GA, EA = 1.0, 1e3, 1e5
BEARING, LOAD = 0.4, 1.0


def bearing(formulation: str, n: int) -> tuple[SlidingModel, np.ndarray, np.ndarray]:
    """The rod through the bearing (module docstring) on ``n`` elements: its exact model
    with the slider, the held dofs and the load."""
    npe = 2 if formulation in ("fv2", "galerkin-p1") else 3
    section = Section.diagonal(EA=EA, GAy=GA, GAz=GA, GJ=1.0, EJy=EJ, EJz=EJ)
    rod = Beam(straight([0, 0, 0], [1, 0, 0], n, npe, name="rod"), section, formulation)
    st = Structure([rod], (), [RigidBody("bearing", [BEARING, 0.0, 0.0])])
    model = SlidingModel(ExactModel.on(st, []), [ExactSlider("classical", "rod", "bearing")])
    held, start, tip = (model.model._node(ref, ref) for ref in ("bearing", "rod.start", "rod.end"))
    fixed = np.concatenate([6 * held + np.arange(6), [6 * start, 6 * start + 3]])
    load = np.zeros(model.n_dofs)
    load[6 * tip + 1] = LOAD
    return model, fixed, load


def configurational(model: SlidingModel, x_tip: float, pull: float) -> tuple[float, float]:
    """The closed form ``M^2 / 2 EJ + V^2 / 2 GA`` at the tip's place ``x_tip`` and the
    relative error of the support's ``pull``."""
    exact = (LOAD * (x_tip - BEARING)) ** 2 / (2 * EJ) + LOAD**2 / (2 * GA)
    return exact, abs(pull - exact) / exact


def timed(solve: Any, repeats: int) -> tuple[Any, list[float]]:
    """The last result of ``solve()`` and the times of the repeats."""
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = solve()
        times.append(time.perf_counter() - start)
    return out, times


def bench_bearing(n: int, repeats: int) -> dict[str, Any]:
    """One mesh's exact and linear solves, timed beside their errors."""
    model, fixed, load = bearing("fv3", n)
    start, tip = (model.model._node(ref, ref) for ref in ("rod.start", "rod.end"))
    result, exact_times = timed(lambda: solve_static(model, load, fixed), repeats)
    state = result.state
    pull = -float(model.residual(state)[6 * start])
    closed, error = configurational(model, float(state.x[tip, 0]), pull)
    st = model.model.structure
    slider = Slider("classical", BeamChain(st, "rod"), "bearing")
    statics = SliderStatics(
        st, [Support("bearing", kind="clamp"), Support("rod.start", kind="ux+rx")], [slider]
    )
    f = load[: st.n_dofs]
    solution, linear_times = timed(lambda: statics.solve(f), repeats)
    dofs, r_q, _, _ = slider.assemble(st, solution.q, solution.unknowns[0])
    residual = statics.K @ solution.q - f
    np.add.at(residual, dofs, r_q)
    linear_pull = -float(residual[6 * start])
    row = {
        "n_elements": n,
        "closed_form_N": closed,
        "exact": {
            "seconds": summary(exact_times),
            "newton_iterations": result.newton_iterations,
            "force_N": pull,
            "rel_error": error,
        },
        "linear": {
            "seconds": summary(linear_times),
            "newton_iterations": solution.iterations,
            "force_N": linear_pull,
            "rel_error": abs(linear_pull - closed) / closed,
        },
    }
    print(
        f"bearing, fv3 x {n}: exact {row['exact']['seconds']['min']:.3f} s "
        f"({result.newton_iterations} iterations), force {pull:.4f} N, error {error:.2%}; "
        f"linear {row['linear']['seconds']['min']:.4f} s, force {linear_pull:.4f} N, "
        f"error {row['linear']['rel_error']:.2%} (closed form {closed:.4f} N)",
        flush=True,
    )
    return row


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark and merge it into ``--out``."""
    args = bench_arguments("studies.bench_exact_sliders", __doc__ or "", "8 elements", argv)
    repeats = 1 if args.quick else 5
    rows = [bench_bearing(n, repeats) for n in ((8,) if args.quick else (8, 16, 32))]
    return write_merged(args.out, {"environment": environment(), KEY: {"bearing": rows}})


if __name__ == "__main__":
    main()
