"""The force laws are generated from their one statement (:mod:`sliders.forces.statements`).

- Regenerating :mod:`sliders.forces.array_laws` and :mod:`sliders.forces.compiled_laws`
  (``python -m sliders.forces.generate``) gives the committed text.
- The generated value is the statement's: each law's statement evaluated in numpy
  (:data:`sliders.forces.statements.NUMPY`) against the generated function at random states,
  within ``16 eps`` of the largest term (the two group the same terms differently after
  common-subexpression elimination; a few roundings each).
- A mutation check: scaling one term of one statement changes the generated text of the
  laws that read it and of no other.
- Their derivatives against central differences: ``tests/test_force_laws.py``; the
  compiled form against the numpy form: ``tests/test_laws_kernel.py``.
"""

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sympy")

from sliders.forces import array_laws, compiled_laws, generate, statements

EPS = np.finfo(float).eps
#: Parameters of the gear's laws (``docs/landing_gear.md``), by keyword.
PARAMETERS = dict(
    area=1.6e-3,
    pressure=4.1e5,
    volume=2.8e-4,
    exponent=1.3,
    ambient=101_325.0,
    compression=5000.0,
    rebound=20000.0,
    stiffness=2.5e5,
    lower=0.0,
    upper=0.16,
    damping=250.0,
    radius=0.22,
    speed_eps=0.1,
    B=10.0,
    C=1.65,
    D=0.8,
    mu=0.3,
    v_eps=1e-3,
    mu_static=0.5,
    mu_kinetic=0.3,
    v_stribeck=0.01,
)
#: Physical ranges of the states, by name.
RANGES = dict(
    stroke=(-0.01, 0.17),
    rate=(-5.0, 5.0),
    deflection=(-0.02, 0.05),
    forward_speed=(-5.0, 60.0),
    spin=(-10.0, 300.0),
    kappa=(-2.0, 2.0),
    normal=(0.0, 3e4),
    velocity=(-0.05, 0.05),
)


def test_regenerating_changes_nothing():
    """The committed modules are the generator's text, byte for byte."""
    assert generate.array_source() == Path(array_laws.__file__).read_text()
    assert generate.compiled_source() == Path(compiled_laws.__file__).read_text()


@pytest.mark.parametrize("law", generate.ARRAY_LAWS, ids=lambda law: law.name)
def test_the_generated_value_is_the_statements(law):
    """At 200 random states over the physical ranges, the generated value equals the
    statement run in numpy within ``16 eps`` of the largest value."""
    rng = np.random.default_rng(3)
    states = [rng.uniform(*RANGES[name], 200) for name in law.states]
    keywords = {name: PARAMETERS[name] for name in law.parameters}
    stated = law.statement(*states, **keywords, ops=statements.NUMPY)
    generated = getattr(array_laws, law.name)(*states, *keywords.values())[0]
    scale = np.abs(stated).max()
    assert np.all(np.abs(generated - stated) <= 16 * EPS * scale)


def test_a_mutated_statement_regenerates_the_laws_that_read_it(monkeypatch):
    """Scaling the slip ratio's regularisation by 1 + 1e-3 changes the generated slip ratio
    and longitudinal tyre force, numpy and compiled, and no other law."""
    before_array, before_compiled = generate.array_source(), generate.compiled_source()
    slip_ratio = statements.slip_ratio

    def mutated(u, w, *, radius, speed_eps, ops):
        return slip_ratio(u, w, radius=radius, speed_eps=speed_eps * 1.001, ops=ops)

    monkeypatch.setattr(statements, "slip_ratio", mutated)
    after_array, after_compiled = generate.array_source(), generate.compiled_source()

    def functions(text):
        return {block.split("(")[0]: block for block in text.split("\ndef ")[1:]}

    changed = {
        name
        for before, after in ((before_array, after_array), (before_compiled, after_compiled))
        for name, block in functions(after).items()
        if functions(before)[name] != block
    }
    assert changed == {"tyre_longitudinal"}
