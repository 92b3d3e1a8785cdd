"""The telescopic nose landing gear of the paper's Section 7 (issue 14): its parameters
(:mod:`sliders.gear.parameters`), the models ``rigid``, ``fv3-1``, ``fv3-3``, ``fv3-5`` built
from beams, sliders and force elements (:mod:`sliders.gear.model`), and their outputs and
events (:mod:`sliders.gear.outputs`)."""
