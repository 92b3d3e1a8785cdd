"""The paper's sliding-beams setup (Sec. 6, Figures 3-5): two beams joined by two sliders.

:mod:`~sliders.sliding_beams.model` builds it and solves it at any piston position;
:mod:`~sliders.sliding_beams.exact` is its closed-form tip stiffness.
"""
