"""Finite-volume and Galerkin linear Timoshenko beams assembled with scikit-fem.

Typical use::

    from fvbeam import Beam, LinearStatics, Section, Support, straight

    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4), Section.diagonal(1e3, 1, 1, 1, 1, 1), "fv3")
    statics = LinearStatics(beam, [Support(0, "start")])
    q = statics.solve(beam.point_load(0.7, force=(0, 1, 0)))
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
