"""The application layer: scenes, running them, and what a run writes.

- :mod:`~sliders.app.schema`, :mod:`~sliders.app.checks`, :mod:`~sliders.app.errors`,
  :mod:`~sliders.app.scene`: a TOML scene read and validated, every problem at its key path;
- :mod:`~sliders.app.model`: a validated scene as fvbeam and sliders objects;
- :mod:`~sliders.app.run`, :mod:`~sliders.app.run_dynamic`: a scene's study run;
  :mod:`~sliders.app.kinematics`, :mod:`~sliders.app.run_exact`: its kinematics, linear or
  geometrically exact;
- :mod:`~sliders.app.tables`, :mod:`~sliders.app.history`, :mod:`~sliders.app.vtu`,
  :mod:`~sliders.app.render`: CSV tables, per-step histories, VTU/PVD files, pyvista renders;
  :mod:`~sliders.app.motion`: the rigid and elastic parts of a motion, for the last two;
- :mod:`~sliders.app.cli`: the ``fvslider`` command.
"""
