"""Finite-volume and Galerkin linear Timoshenko beams assembled with scikit-fem.

Typical use: a unit cantilever (``EJ = GA = 1``) of four 3-node finite-volume elements,
clamped at its start, under a unit transverse force at its tip.  Its tip deflection and
rotation are the exact Timoshenko ones, ``F L^3 / (3 EJ) + F L / GA = 4/3`` and
``F L^2 / (2 EJ) = 1/2`` (:func:`fvbeam.closed_forms.cantilever_exact`), to round-off:

>>> from fvbeam import Beam, LinearStatics, Section, Support, straight
>>> beam = Beam(straight((0, 0, 0), (1, 0, 0), 4), Section.diagonal(1e3, 1, 1, 1, 1, 1), "fv3")
>>> statics = LinearStatics(beam, [Support(0, "start")])  # factorised once
>>> q = statics.solve(beam.point_load(1.0, force=(0, 1, 0)))
>>> ux, uy, uz, rx, ry, rz = beam.displacements(q, 1.0)[0]
>>> print(f"{uy:.10f} {rz:.10f}")
1.3333333333 0.5000000000
"""

from fvbeam.beam import Beam, InternalForces
from fvbeam.body import RigidBody
from fvbeam.formulations import FORMULATIONS, formulation
from fvbeam.linear_statics import LinearStatics
from fvbeam.mesh import BeamMesh, arc, from_curve, read_beams, straight
from fvbeam.section import Section
from fvbeam.structure import Structure
from fvbeam.support import Support

__all__ = [
    "Beam",
    "BeamMesh",
    "FORMULATIONS",
    "InternalForces",
    "LinearStatics",
    "RigidBody",
    "Section",
    "Structure",
    "Support",
    "arc",
    "formulation",
    "from_curve",
    "read_beams",
    "straight",
]
