"""The formulations' names, apart from their definitions (:mod:`fvbeam.formulations`), so that
a scene is validated without importing scikit-fem."""

from __future__ import annotations

from typing import Literal, get_args

#: The formulations by name (the scenes' ``formulation`` takes one of them).
FormulationName = Literal["fv2", "fv3", "galerkin-p1", "galerkin-p2", "cubic"]
FORMULATIONS: tuple[str, ...] = get_args(FormulationName)
