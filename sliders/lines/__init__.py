"""Lines a body slides on, each parametrised by an arc-length abscissa ``xi`` (paper Sec. 3).

- :mod:`~sliders.lines.rigid`: rigid C1 curves (straight, arc, helix, cubic spline);
- :mod:`~sliders.lines.chain`: a chain of deformable beams as one line (paper Sec. 4);
- :mod:`~sliders.lines.batched`: many chains of one topology queried at once, with its
  compiled kernel :mod:`~sliders.lines.batched_kernel` and that kernel's numpy reference
  :mod:`~sliders.lines.batched_reference`.
"""
