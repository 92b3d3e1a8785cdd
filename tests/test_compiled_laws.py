"""The compiled slider laws are generated from their one statement.

- Regenerating :mod:`sliders.joints.compiled_laws` from the laws of
  :mod:`sliders.joints.equations` (``python -m sliders.joints.generate``) gives the committed
  text: no edit by hand, no statement changed without its compiled form.
- A mutation check: changing one term of one law's statement (the section axis'
  ``xi``-derivative, as in ``tests/test_joint_laws.py``) changes the generated function of
  every law that reads it and of no other; that the compiled kernel then equals the
  reference entry by entry is ``tests/test_joint_reference.py``.
- The generated layout is the one the kernel's stack space holds.
"""

from pathlib import Path

import pytest

sympy = pytest.importorskip("sympy")

from sliders.joints import compiled_laws, equations, generate  # noqa: E402


def test_regenerating_changes_nothing():
    """The committed module is the generator's text, byte for byte."""
    committed = Path(compiled_laws.__file__).read_text()
    assert generate.source() == committed


def test_a_mutated_statement_regenerates_the_laws_that_read_it(monkeypatch):
    """Scaling ``t_0/xi`` by 1 + 1e-3 in the statement changes the generated classical and
    spline section laws (which read the section axis) and leaves the spherical law and the
    slope law (which do not) as they were."""
    laws = list(equations.LAWS)
    before = {key: generate._function("law", *key)[0] for key in laws}
    section_axis = equations._section_axis

    def mutated(line_point):
        t0, t1 = section_axis(line_point)
        return t0, t1 * 1.001

    monkeypatch.setattr(equations, "_section_axis", mutated)
    after = {key: generate._function("law", *key)[0] for key in laws}
    changed = {key for key in laws if after[key] != before[key]}
    assert changed == {("classical", "section"), ("spline", "section")}


def test_the_layout_fits_the_kernels_stack_space():
    """The kernel reserves 69 point quantities, 16 constants, 22 rows and 256 derivatives on
    its stack (literals, as numba needs them): the generated layout's sizes, and the most
    nonzero derivatives of any law."""
    sizes = [
        sum(size for _, size in fields)
        for fields in (compiled_laws.POINT, compiled_laws.CONSTANTS, compiled_laws.ROWS)
    ]
    assert sizes == [69, 16, 22]
    assert compiled_laws.DERIVATIVE_ROW.shape[1] == max(compiled_laws.DERIVATIVES) <= 256
