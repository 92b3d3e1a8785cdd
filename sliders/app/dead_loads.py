"""A scene's loads on the exact path: its ``[[load]]`` tables and a static study's gravity
as dead loads whose virtual work follows the configuration
(:class:`fvbeam.exact_loads.DeadLoad`).

Nodal loads are vectors, as on the linear path; distributed loads and point loads, smeared
or not, act through the beams' test functions on the current configuration
(:func:`fvbeam.exact_loads.distributed`, :func:`~fvbeam.exact_loads.point`); ``gravity`` is
each beam's weight ``m g`` per length, a dead distributed load
(:func:`~fvbeam.exact_loads.weight`), and each body's weight at its centre of mass, whose
moment about the body's node turns with the body.  In the reference configuration these are
the linear path's load vectors, but for gravity on fv beams with the ``lumped`` mass: the
lumped weight puts each region's weight at its node with no couple, where the distributed
weight's couple about an end node, ``m g h^2 / 8`` on an ``fv2`` end region of half an element,
vanishes with the mesh (second order in ``h``).  A load-factor sweep scales the scene's
loads, not gravity, as on the linear path (:meth:`sliders.app.model.Model.load_vector`).
"""

from __future__ import annotations

import numpy as np

from fvbeam.exact_loads import BodyForce, DeadLoad, LoadPoints, distributed, point, weight
from fvbeam.structure import Structure
from sliders.app.model import Model
from sliders.app.schema import DynamicStudy


def scaled(points: LoadPoints, factor: float) -> LoadPoints:
    """``points`` with their forces and couples times ``factor``."""
    return LoadPoints(points.element, points.X, points.wrench * factor)


def dead_load(model: Model, structure: Structure, value: float | None) -> DeadLoad:
    """The scene's loads and gravity on ``structure`` at the study point ``value`` (module
    docstring)."""
    factor = model.load_factor(value)
    nodal = np.zeros(structure.n_dofs)
    parts: list[list[LoadPoints]] = [[] for _ in structure.beams]
    for spec in model.scene.load:
        if spec.kind == "nodal":
            nodal += factor * structure.nodal_load(spec.node, spec.force, spec.moment)
            continue
        i = structure.beam_index(spec.beam)
        beam = structure.beams[i]
        if spec.kind == "distributed":
            pts = distributed(beam, spec.force, spec.moment)
        else:
            at = model.load_at(spec, value)
            pts = point(beam, at, spec.force, spec.moment, spec.smearing, spec.kernel)
        parts[i].append(scaled(pts, factor))
    study = model.scene.study
    gravity = None if isinstance(study, DynamicStudy) else study.gravity
    bodies = []
    if gravity is not None:
        g = np.asarray(gravity, dtype=float)
        for i, beam in enumerate(structure.beams):
            parts[i].append(weight(beam, g))
        for body in structure.bodies:
            node = int(structure.node_dofs(body.name)[0] // 6)
            bodies.append(BodyForce(node, body.mass * g, np.asarray(body.centre, dtype=float)))
    beams = [
        (beam, dofs[::6] // 6, LoadPoints.join(p))
        for beam, dofs, p in zip(structure.beams, structure.dof_maps, parts, strict=True)
        if p
    ]
    return DeadLoad(structure.n_dofs, nodal, beams, bodies)
