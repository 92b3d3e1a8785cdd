"""The columns ``history.csv`` can hold (:mod:`sliders.app.history` records them), named
without importing the integrator: a scene's output names are checked against them before
anything is solved."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sliders.joints.slider import Slider

ENERGIES = ("kinetic", "strain", "external_work", "constraint_work", "dissipated", "energy_error")
#: The columns of ``history.csv`` before the energies; ``step, t`` are always kept.
STEP = ("step", "t", "h", "iterations")


def history_columns(sliders: Sequence[Slider]) -> list[str]:
    """Every column ``history.csv`` can hold for a dynamics of ``sliders``, before its
    probes."""
    columns = [*STEP, *ENERGIES]
    for s in sliders:
        columns += [f"{s.name}.{u}" for u in s.unknown_names] + [f"{s.name}.residual"]
    return columns
