"""Slider joints: a body node held on a line (paper eqs. 1-5 and Sec. 4).

- :mod:`~sliders.joints.slider`: the spherical, classical and spline sliders and their
  batches (what the solvers call);
- :mod:`~sliders.joints.equations`: the joint equations in plain numpy, with the paper's
  numbers (the reference);
- :mod:`~sliders.joints.kernel`: the joint equations compiled (what the solvers run);
- :mod:`~sliders.joints.blocks`: a joint's Jacobian by blocks of its slots;
- :mod:`~sliders.joints.drives`: prescribed motions of a slider or a dof.
"""
