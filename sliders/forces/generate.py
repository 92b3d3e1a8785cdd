"""Write the force laws' numpy and compiled forms from their one statement:
``python -m sliders.forces.generate``.

Each law of :mod:`sliders.forces.statements` runs on sympy symbols; its value and its
partial derivatives in its states, after common-subexpression elimination, are printed twice:
as numpy functions of arrays (:mod:`sliders.forces.array_laws`, which
:mod:`sliders.forces.laws` calls after checking its inputs) and as compiled functions of one
point with the parameters in a row (:mod:`sliders.forces.compiled_laws`, which the force
elements' kernel calls).  Both modules are committed; ``tests/test_force_statements.py``
regenerates them and requires the same text, so a law changes in one place, its statement.

Needs sympy (the ``test`` extra); nothing at run time imports this module.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import sympy
from sympy.printing.numpy import NumPyPrinter

from sliders.forces import statements
from sliders.joints.generate import SYMPY, common_subexpressions


class _ArrayPrinter(NumPyPrinter):
    """numpy's printer with ``and``/``or`` as pairwise ``logical_and``/``logical_or``, which
    broadcast operands of different shapes (its ``reduce`` form stacks them first)."""

    def _pairwise(self, name: str, args: tuple) -> str:
        first, *rest = (self._print(a) for a in args)
        for other in rest:
            first = f"numpy.{name}({first}, {other})"
        return first

    def _print_And(self, expr: sympy.And) -> str:
        return self._pairwise("logical_and", expr.args)

    def _print_Or(self, expr: sympy.Or) -> str:
        return self._pairwise("logical_or", expr.args)


class Printed(NamedTuple):
    """A law to print: its name in the generated module, its statement, the names of its
    states (the statement's positional arguments, in order) and of its parameters (its
    keywords; for a compiled law, the row of parameters it reads, by name)."""

    name: str
    statement: Callable[..., sympy.Expr]
    states: tuple[str, ...]
    parameters: tuple[str, ...]


#: The laws of :mod:`sliders.forces.laws`, as numpy functions of arrays.
ARRAY_LAWS = (
    Printed(
        "gas_spring",
        statements.gas_spring,
        ("stroke",),
        ("area", "pressure", "volume", "exponent", "ambient"),
    ),
    Printed("orifice_damper", statements.orifice_damper, ("rate",), ("compression", "rebound")),
    Printed("end_stops", statements.end_stops, ("stroke",), ("stiffness", "lower", "upper")),
    Printed(
        "tyre_radial", statements.tyre_radial, ("deflection", "rate"), ("stiffness", "damping")
    ),
    Printed(
        "slip_ratio", statements.slip_ratio, ("forward_speed", "spin"), ("radius", "speed_eps")
    ),
    Printed("friction_curve", statements.friction_curve, ("kappa",), ("B", "C", "D")),
    Printed(
        "tyre_longitudinal",
        statements.tyre_longitudinal,
        ("forward_speed", "spin", "normal"),
        ("radius", "speed_eps", "B", "C", "D"),
    ),
    Printed(
        "coulomb_friction", statements.coulomb_friction, ("velocity", "normal"), ("mu", "v_eps")
    ),
    Printed(
        "stribeck_friction",
        statements.stribeck_friction,
        ("velocity", "normal"),
        ("mu_static", "mu_kinetic", "v_stribeck", "v_eps"),
    ),
)
#: The rows of parameters of the compiled laws, by name.
PARAMETERS = {
    "strut": (
        "area",
        "pressure",
        "volume",
        "exponent",
        "ambient",
        "compression",
        "rebound",
        "stop_stiffness",
        "stroke_min",
        "stroke_max",
    ),
    "tyre": ("radius", "stiffness", "damping", "B", "C", "D", "speed_eps"),
}
_ARRAY = {law.name: law for law in ARRAY_LAWS}
#: The compiled laws: each reads the row ``PARAMETERS[row]`` (the names the statement's
#: keywords take from it in ``parameters``); the tyre's are its array laws.
COMPILED_LAWS = (
    (Printed("strut", statements.strut, ("stroke", "rate"), PARAMETERS["strut"]), "strut"),
    (_ARRAY["tyre_radial"], "tyre"),
    (_ARRAY["tyre_longitudinal"], "tyre"),
)
ARRAY_TARGET = Path(__file__).with_name("array_laws.py")
COMPILED_TARGET = Path(__file__).with_name("compiled_laws.py")


def _derived(law: Printed, parameter: Callable[[str], sympy.Symbol]) -> list[sympy.Expr]:
    """The law's value on symbols and its partial derivatives in its states, in order."""
    states = [sympy.Symbol(name, real=True) for name in law.states]
    keywords = {name: parameter(name) for name in law.parameters}
    value = sympy.sympify(law.statement(*states, **keywords, ops=SYMPY))
    return [value, *(sympy.diff(value, s) for s in states)]


def _body(outputs: list[sympy.Expr], printer: Callable[[sympy.Expr], str]) -> list[str]:
    """The lines computing ``outputs`` and returning them."""
    shared, reduced = common_subexpressions(outputs, printer)
    return [*shared, f"    return {', '.join(reduced)}"]


def _summary(law: Printed) -> str:
    """What a generated function returns."""
    names = ", ".join(f"d/d{s}" for s in law.states)
    return f"``(value, {names})``"


def array_source() -> str:
    """The text of :mod:`sliders.forces.array_laws`."""
    printer = _ArrayPrinter({"fully_qualified_modules": True}).doprint
    functions = []
    for law in ARRAY_LAWS:
        outputs = _derived(law, lambda name: sympy.Symbol(name, real=True))
        arguments = ", ".join([*law.states, *law.parameters])
        functions.append(
            "\n".join(
                [
                    f"def {law.name}({arguments}):",
                    f'    """:func:`sliders.forces.statements.{law.statement.__name__}` and its '
                    f'derivatives: {_summary(law)}."""',
                    *_body(outputs, printer),
                ]
            )
        )
    header = '''"""The force laws of :mod:`sliders.forces.statements` on arrays (generated).

Written by ``python -m sliders.forces.generate`` from the laws' one statement (sympy traces
each law and differentiates it); ``tests/test_force_statements.py`` checks that regenerating
changes nothing.  :mod:`sliders.forces.laws` checks the inputs and calls these.
"""

# ruff: noqa
# mypy: ignore-errors

import numpy
'''
    return "\n\n\n".join([header.rstrip(), *functions]) + "\n"


def compiled_source() -> str:
    """The text of :mod:`sliders.forces.compiled_laws`."""
    functions = []
    for law, row in COMPILED_LAWS:
        index = {name: i for i, name in enumerate(PARAMETERS[row])}

        def in_row(name: str, index: dict[str, int] = index) -> sympy.Symbol:
            return sympy.Symbol(f"p[{index[name]}]", real=True)

        outputs = _derived(law, in_row)
        arguments = ", ".join(["p", *law.states])
        functions.append(
            "\n".join(
                [
                    '@numba.njit(cache=True, inline="never")',
                    f"def {law.name}({arguments}):",
                    f'    """:func:`sliders.forces.statements.{law.statement.__name__}` at one '
                    f'point, ``p``: ``PARAMETERS["{row}"]``; returns {_summary(law)}."""',
                    *_body(outputs, sympy.pycode),
                ]
            )
        )
    header = f'''"""The force laws of :mod:`sliders.forces.statements`, compiled (generated).

Written by ``python -m sliders.forces.generate`` from the laws' one statement (sympy traces
each law and differentiates it); ``tests/test_force_statements.py`` checks that regenerating
changes nothing.  Each function reads its parameters in a row of floats, in the order its
:data:`PARAMETERS` entry lists (the force elements check them once, where they are built),
and returns the value and its partial derivatives in the order of its state arguments.
"""

# ruff: noqa

import math

import numba

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: The parameter rows of the laws, by name (:mod:`sliders.forces.laws` keyword arguments).
PARAMETERS = {PARAMETERS!r}
'''
    return "\n\n\n".join([header.rstrip(), *functions]) + "\n"


def main() -> int:
    """Write :data:`ARRAY_TARGET` and :data:`COMPILED_TARGET`."""
    ARRAY_TARGET.write_text(array_source())
    COMPILED_TARGET.write_text(compiled_source())
    print(f"wrote {ARRAY_TARGET} and {COMPILED_TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
