"""Slider joints on rigid curves and on chains of deformable beams (paper Secs. 3-4).

Typical use, a scene from Python (``docs/scenes.md``)::

    import sliders

    model = sliders.Model(sliders.load_scene("studies/scenes/fig4_sliding_beams.toml"))
    results = sliders.run(model)  # a sweep's samples; a dynamic study's steps
    sliders.write_results(results, "results/sliding_beams")

or the objects built directly, parts named as in a scene (``README.md``, section Python: the
paper's Figure 4 setup)::

    joints = [Slider("spherical", BeamChain(structure, "C"), "P.start", name="A"), ...]
    statics = SliderStatics(structure, [Support("C.start"), ...], joints)
    write_vtu("fig4.vtu", statics, statics.solve(structure.nodal_load("P.end", (0, 1, 0))))

The subpackages: :mod:`sliders.lines` (rigid lines, beam chains), :mod:`sliders.joints`
(sliders, drives), :mod:`sliders.solve` (statics, sweeps, dynamics), :mod:`sliders.app`
(scenes, runs, outputs), :mod:`sliders.sliding_beams` (the paper's Figure 4 setup).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from fvbeam.lazy import lazy_names

if TYPE_CHECKING:
    from sliders.app.errors import SceneError
    from sliders.app.history import Recorder
    from sliders.app.model import Model
    from sliders.app.render import render
    from sliders.app.run import Results, run
    from sliders.app.run_dynamic import DynamicRun, write_dynamic
    from sliders.app.scene import load_scene, parse_scene
    from sliders.app.tables import write_results
    from sliders.app.vtu import Frame, to_meshio, write_series, write_vtu
    from sliders.joints.drives import DofDrive, Linear, Ramp, Tabulated
    from sliders.joints.slider import Slider
    from sliders.lines.chain import BeamChain
    from sliders.lines.rigid import CircularArc, CubicSpline, Helix, StraightLine
    from sliders.solve.dynamics import Adaptive, Dynamics, DynamicsError
    from sliders.solve.modes import StateModes, modes_about
    from sliders.solve.statics import SliderSolution, SliderStatics, solve_translated
    from sliders.solve.sweep import sweep

#: Each public name's module: imported on first use (PEP 562), so that ``import sliders``
#: (and the ``fvslider`` command's ``--help``) costs nothing until a name is used.
_MODULES = {
    "SceneError": "sliders.app.errors",
    "Recorder": "sliders.app.history",
    "Model": "sliders.app.model",
    "render": "sliders.app.render",
    "Results": "sliders.app.run",
    "run": "sliders.app.run",
    "DynamicRun": "sliders.app.run_dynamic",
    "write_dynamic": "sliders.app.run_dynamic",
    "load_scene": "sliders.app.scene",
    "parse_scene": "sliders.app.scene",
    "write_results": "sliders.app.tables",
    "Frame": "sliders.app.vtu",
    "to_meshio": "sliders.app.vtu",
    "write_series": "sliders.app.vtu",
    "write_vtu": "sliders.app.vtu",
    "DofDrive": "sliders.joints.drives",
    "Linear": "sliders.joints.drives",
    "Ramp": "sliders.joints.drives",
    "Tabulated": "sliders.joints.drives",
    "Slider": "sliders.joints.slider",
    "BeamChain": "sliders.lines.chain",
    "CircularArc": "sliders.lines.rigid",
    "CubicSpline": "sliders.lines.rigid",
    "Helix": "sliders.lines.rigid",
    "StraightLine": "sliders.lines.rigid",
    "StateModes": "sliders.solve.modes",
    "modes_about": "sliders.solve.modes",
    "Adaptive": "sliders.solve.dynamics",
    "Dynamics": "sliders.solve.dynamics",
    "DynamicsError": "sliders.solve.dynamics",
    "SliderSolution": "sliders.solve.statics",
    "SliderStatics": "sliders.solve.statics",
    "solve_translated": "sliders.solve.statics",
    "sweep": "sliders.solve.sweep",
}

__all__ = [
    "Adaptive",
    "BeamChain",
    "CircularArc",
    "CubicSpline",
    "DofDrive",
    "DynamicRun",
    "Dynamics",
    "DynamicsError",
    "Frame",
    "Helix",
    "Linear",
    "Model",
    "Ramp",
    "Recorder",
    "Results",
    "SceneError",
    "Slider",
    "SliderSolution",
    "SliderStatics",
    "StateModes",
    "StraightLine",
    "Tabulated",
    "load_scene",
    "modes_about",
    "parse_scene",
    "render",
    "run",
    "solve_translated",
    "sweep",
    "to_meshio",
    "write_dynamic",
    "write_results",
    "write_series",
    "write_vtu",
]


__getattr__, __dir__ = lazy_names(__name__, _MODULES, globals())
