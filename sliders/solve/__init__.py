"""Solvers: Newton on the slider unknowns, statics, sweeps and implicit dynamics.

- :mod:`~sliders.solve.statics`: static equilibrium, one or many problems at once;
- :mod:`~sliders.solve.condensed`: the Newton step condensed on a cached factorisation of the
  beams' operator, with its compiled kernel :mod:`~sliders.solve.condensed_kernel` and that
  kernel's dense reference :mod:`~sliders.solve.condensed_reference`;
- :mod:`~sliders.solve.sweep`: continuation sweeps over a parameter;
- :mod:`~sliders.solve.integrator`, :mod:`~sliders.solve.dynamics`: generalized-alpha time
  integration.
"""
