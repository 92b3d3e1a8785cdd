"""Finite-volume and Galerkin linear Timoshenko beams assembled with scikit-fem.

Typical use, parts named as in a scene (:mod:`fvbeam.names`): a unit cantilever
(``EJ = GA = 1``) of four 3-node finite-volume elements, clamped at its start, under a unit
transverse force at its tip.  Its tip deflection and rotation are the exact Timoshenko ones,
``F L^3 / (3 EJ) + F L / GA = 4/3`` and ``F L^2 / (2 EJ) = 1/2``
(:func:`fvbeam.closed_forms.cantilever_exact`), to round-off:

>>> from fvbeam import Beam, LinearStatics, Section, Support, straight
>>> section = Section.diagonal(EA=1e3, GAy=1, GAz=1, GJ=1, EJy=1, EJz=1)
>>> beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, name="shaft"), section, "fv3")
>>> statics = LinearStatics(beam, [Support("shaft.start")])  # factorised once
>>> q = statics.solve(beam.point_load(1.0, force=(0, 1, 0)))
>>> ux, uy, uz, rx, ry, rz = beam.displacements(q, 1.0)[0]
>>> print(f"{uy:.10f} {rz:.10f}")
1.3333333333 0.5000000000
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from fvbeam.lazy import lazy_names

if TYPE_CHECKING:
    from fvbeam.beam import Beam, InternalForces
    from fvbeam.body import RigidBody
    from fvbeam.formulations import FORMULATIONS, formulation
    from fvbeam.linear_statics import LinearStatics
    from fvbeam.mesh import BeamMesh, arc, from_curve, read_beams, straight
    from fvbeam.modes import Modes, natural_frequencies
    from fvbeam.names import NodeRef, parse_node
    from fvbeam.section import Section
    from fvbeam.structure import Structure
    from fvbeam.support import DOF_NAMES, Support

#: Each public name's module: imported on first use (PEP 562), so that ``import fvbeam``
#: costs nothing until a name is used (scipy, scikit-fem and the numba kernels load then).
_MODULES = {
    "Beam": "fvbeam.beam",
    "InternalForces": "fvbeam.beam",
    "RigidBody": "fvbeam.body",
    "FORMULATIONS": "fvbeam.formulations",
    "formulation": "fvbeam.formulations",
    "LinearStatics": "fvbeam.linear_statics",
    "BeamMesh": "fvbeam.mesh",
    "arc": "fvbeam.mesh",
    "from_curve": "fvbeam.mesh",
    "read_beams": "fvbeam.mesh",
    "straight": "fvbeam.mesh",
    "Modes": "fvbeam.modes",
    "natural_frequencies": "fvbeam.modes",
    "NodeRef": "fvbeam.names",
    "parse_node": "fvbeam.names",
    "Section": "fvbeam.section",
    "Structure": "fvbeam.structure",
    "DOF_NAMES": "fvbeam.support",
    "Support": "fvbeam.support",
}
__all__ = [
    "Beam",
    "BeamMesh",
    "DOF_NAMES",
    "FORMULATIONS",
    "InternalForces",
    "LinearStatics",
    "Modes",
    "NodeRef",
    "RigidBody",
    "Section",
    "Structure",
    "Support",
    "arc",
    "formulation",
    "from_curve",
    "natural_frequencies",
    "parse_node",
    "read_beams",
    "straight",
]


__getattr__, __dir__ = lazy_names(__name__, _MODULES, globals())
