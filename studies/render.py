"""Off-screen renders of the sliding-beams setup (paper Sec. 6) under its tip load.

Run as ``python -m studies.render --out DIR``: renders the setup
(:class:`sliders.sliding_beams.model.SlidingBeams`, fv3, 5 elements per beam) at
``s/L = 0.3``, one file per slider kind: ``DIR/render_spherical.png``,
``DIR/render_classical.png`` (:func:`sliders.app.render.render`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from sliders.app.render import AUTO_FRACTION, render
from sliders.sliding_beams.model import KINDS, SlidingBeams


def render_sliding_beams(out: Path, magnification: float | None = None) -> list[str]:
    """Render the sliding-beams setup at ``s/L = 0.3`` (fv3, 5 elements), both slider kinds,
    into ``out/render_KIND.png``; one line per image (path and magnification)."""
    lines = []
    for kind in KINDS:
        statics, load = SlidingBeams("fv3", 5, kind).problem(0.3)
        solution = statics.solve(load)
        target = Path(out) / f"render_{kind}.png"
        scale = render(
            target,
            statics.structure,
            solution.q,
            statics.sliders,
            solution.unknowns,
            magnification,
            f"sliding beams, {kind} sliders, s/L = 0.3, fv3 x 5 elements",
        )
        lines.append(f"{target} (displacements x {scale:.3g})")
    return lines


def main(argv: list[str] | None = None) -> None:
    """Render the sliding-beams setup at ``s/L = 0.3``, both slider kinds."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument(
        "--magnification",
        type=float,
        default=None,
        help="displacement scale (default: largest displacement drawn as "
        f"{AUTO_FRACTION:g} of the structure's size)",
    )
    args = parser.parse_args(argv)
    for line in render_sliding_beams(args.out, args.magnification):
        print(line)


if __name__ == "__main__":
    main()
