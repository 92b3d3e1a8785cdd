"""Write the compiled slider laws from their one statement: ``python -m sliders.joints.generate``.

Each law of :mod:`sliders.joints.equations` (:data:`~sliders.joints.equations.LAWS`) runs on
sympy symbols in place of its point quantities; its rows (:class:`PointRows`, flattened) and
their derivatives in the point quantities, after common-subexpression elimination, are
printed as one compiled function per law into :mod:`sliders.joints.compiled_laws`, with the
layout of the point quantities it reads.  :func:`sliders.joints.kernel.joint_equations`
fills that layout from the line at ``xi`` and chains the derivatives through the line's maps
(the compiled twin of :func:`sliders.joints.equations.derive`'s seeding, written once for
every kind).  The module is committed; ``tests/test_compiled_laws.py`` regenerates it and
requires the same text, so a law changes in one place, its statement.

Needs sympy (the ``test`` extra); nothing at run time imports this module.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import sympy

from sliders.joints.equations import LAWS, BodyPoint, LinePoint, PointRows, Unknowns
from sliders.joints.friction import friction_term

#: The arithmetic of the statements on sympy expressions
#: (:data:`sliders.joints.arithmetic.NUMPY`'s twin).
SYMPY = SimpleNamespace(
    where=lambda condition, a, b: sympy.Piecewise((a, condition), (b, True)),
    both=sympy.And,
    abs=sympy.Abs,
    sqrt=sympy.sqrt,
    exp=sympy.exp,
    tanh=sympy.tanh,
    atan=sympy.atan,
    sin=sympy.sin,
)
#: The point quantities a law reads and is differentiated in, in order, with their sizes:
#: the body node's displacement ``u_b`` and rotation ``theta_b``; the line at ``xi``
#: (``x``, ``l``, ``l_/xi``, the recovered tangent ``l~``, the section rotation ``theta_L``
#: and ``theta_L/xi``, the compliance ``C_L`` (3x3, row-major), the position compliance
#: ``[G_uu, G_u theta]`` (3x6, zero where the line has none), the reference frame ``R_0``
#: (3x3) and curvature ``k_0``); the multipliers ``lambda`` and ``mu`` (the law's ``J``).
POINT = (
    ("u", 3),
    ("theta", 3),
    ("x", 3),
    ("l", 3),
    ("l_xi", 3),
    ("tangent", 3),
    ("theta_L", 3),
    ("theta_L_xi", 3),
    ("flex", 9),
    ("contact", 18),
    ("R0", 9),
    ("k0", 3),
    ("lam", 3),
    ("mu", 3),
)
#: What a law reads and is not differentiated in: the offset ``f``, the slider axes ``F``
#: (3x3, row-major), the point's reference position ``X_b + f`` and the multipliers' scale.
CONSTANTS = (("offset", 3), ("frame", 9), ("reference", 3), ("scale", 1))
#: The rows a law returns, flattened in this order (:class:`PointRows`; ``orientation`` has
#: the law's ``J``).
ROWS = (
    ("body_force", 3),
    ("body_couple", 3),
    ("line_load", 6),
    ("section_couple", 3),
    ("xi", 1),
    ("position", 3),
    ("orientation", 3),
)
#: The multipliers ``mu`` of each slider kind.
CONSTRAINTS = {"spherical": 0, "classical": 2, "spline": 3}
TARGET = Path(__file__).with_name("compiled_laws.py")


def _offsets(fields: tuple[tuple[str, int], ...]) -> dict[str, int]:
    """The first entry of each field in the flat layout."""
    first = np.cumsum([0, *(size for _, size in fields)])
    return {name: int(at) for (name, _), at in zip(fields, first, strict=False)}


def _symbols(prefix: str, fields: tuple[tuple[str, int], ...]) -> dict[str, np.ndarray]:
    """Each field as an object array of sympy symbols ``prefix[i]`` at its flat place."""
    at = _offsets(fields)
    return {
        name: np.array(
            [sympy.Symbol(f"{prefix}[{at[name] + i}]", real=True) for i in range(size)],
            dtype=object,
        )
        for name, size in fields
    }


def traced(kind: str, orientation: str) -> tuple[list[sympy.Expr], list[sympy.Symbol]]:
    """The law's rows (flat, :data:`ROWS` order) on symbols, and the symbols of the point
    quantities (:data:`POINT` order, ``mu`` cut to the kind's ``J``)."""
    p, c = _symbols("p", POINT), _symbols("c", CONSTANTS)
    J = CONSTRAINTS[kind]
    body = BodyPoint(
        offset=c["offset"],
        frame=c["frame"].reshape(3, 3),
        reference=c["reference"],
        u=p["u"],
        theta=p["theta"],
    )
    line = LinePoint(
        x=p["x"],
        l=p["l"],
        l_xi=p["l_xi"],
        tangent=p["tangent"],
        G=np.zeros((0, 6)),  # the scatter's, not the law's
        theta=p["theta_L"],
        theta_xi=p["theta_L_xi"],
        W=np.zeros((3, 0)),
        flex=p["flex"].reshape(3, 3),
        contact=p["contact"].reshape(3, 6),
        R0=p["R0"].reshape(3, 3),
        k0=p["k0"],
    )
    y = Unknowns(p["lam"], p["mu"][:J], c["scale"][0])
    rows: PointRows = LAWS[kind, orientation](body, line, y)
    flat = [sympy.sympify(e) for field in rows for e in np.asarray(field, dtype=object).flat]
    inputs = [s for name, _ in POINT for s in p[name]]
    return flat, inputs[: len(inputs) - 3 + J]


def common_subexpressions(
    expressions: list[sympy.Expr], printer: Callable[[sympy.Expr], str]
) -> tuple[list[str], list[str]]:
    """``expressions`` after common-subexpression elimination (sympy's ``cse``), printed by
    ``printer``: the lines assigning the shared terms ``t0, t1, ...`` (indented for a
    function body) and each expression in their terms."""
    shared, reduced = sympy.cse(expressions, symbols=sympy.numbered_symbols("t"), order="none")
    return [f"    {s} = {printer(e)}" for s, e in shared], [printer(e) for e in reduced]


def derivatives(
    rows: list[sympy.Expr], inputs: list[sympy.Symbol]
) -> list[tuple[int, int, sympy.Expr]]:
    """The derivatives of ``rows`` in ``inputs`` that are not identically zero: ``(row, point
    quantity, derivative)`` in row-major order (the law's sparsity)."""
    entries = [(i, j, sympy.diff(e, s)) for i, e in enumerate(rows) for j, s in enumerate(inputs)]
    return [(i, j, d) for i, j, d in entries if d != 0]


def _function(name: str, kind: str, orientation: str) -> tuple[str, list[tuple[int, int]]]:
    """The compiled function of one law (its rows and their nonzero derivatives in the point
    quantities, in the order of :func:`derivatives`, after common-subexpression
    elimination), and the row and point quantity of each derivative."""
    rows, inputs = traced(kind, orientation)
    entries = derivatives(rows, inputs)
    shared, reduced = common_subexpressions([*rows, *(d for _, _, d in entries)], sympy.pycode)
    lines = [
        "@numba.njit(cache=True)",
        f"def {name}(p, c, rows, d):",
        f'    """The {kind} slider ({orientation} orientation): rows ``rows`` ({len(rows)})',
        f"    and their {len(entries)} nonzero derivatives ``d`` in the point quantities ``p``",
        "    (:data:`POINT`; the row and quantity of each: :data:`DERIVATIVE_ROW`,",
        '    :data:`DERIVATIVE_OF`), with the constants ``c`` (:data:`CONSTANTS`)."""',
    ]
    lines += shared
    lines += [f"    rows[{i}] = {e}" for i, e in enumerate(reduced[: len(rows)])]
    lines += [f"    d[{k}] = {e}" for k, e in enumerate(reduced[len(rows) :])]
    return "\n".join(lines), [(i, j) for i, j, _ in entries]


def _sparsity(entries: list[list[tuple[int, int]]]) -> str:
    """The module's constants naming each law's derivatives (``entries``, in :data:`CODES`
    order): their count, row and point quantity, padded to the longest."""
    most = max(len(e) for e in entries)
    row = [[i for i, _ in e] + [0] * (most - len(e)) for e in entries]
    of = [[j for _, j in e] + [0] * (most - len(e)) for e in entries]
    return "\n".join(
        [
            "#: The nonzero derivatives of each law (:data:`CODES`): their count, and the row",
            "#: (:data:`ROWS`) and the point quantity (:data:`POINT`) of each, padded with zeros.",
            f"DERIVATIVES = np.array({[len(e) for e in entries]!r})",
            f"DERIVATIVE_ROW = np.array({row!r})",
            f"DERIVATIVE_OF = np.array({of!r})",
        ]
    )


def _friction() -> str:
    """The compiled friction term of the ``xi`` equation (:func:`friction_term`): its value
    ``e``, the force ``F`` and the partials of ``e`` in ``l~``, ``w`` and ``lambda``."""
    vectors = {
        name: [sympy.Symbol(f"{name}[{c}]", real=True) for c in range(3)]
        for name in ("l", "w", "lam")
    }
    mu, v_eps, mu_static, v_stribeck = sympy.symbols("mu v_eps mu_static v_stribeck", real=True)
    l, w, lam = vectors["l"], vectors["w"], vectors["lam"]
    e, F = friction_term(l, w, lam, mu, v_eps, mu_static, v_stribeck, ops=SYMPY)
    partials = [sympy.diff(e, x) for v in vectors.values() for x in v]
    shared, reduced = common_subexpressions([e, F, *partials], sympy.pycode)
    outputs = [f"d_{name}" for name in vectors]
    return "\n".join(
        [
            # numpy's error model: a branch not taken (N = 0) may divide by zero first
            '@numba.njit(cache=True, inline="never", error_model="numpy")',
            "def friction_at(l, w, lam, mu, v_eps, mu_static, v_stribeck, d_l, d_w, d_lam):",
            '    """:func:`sliders.joints.friction.friction_term` compiled: returns ``e`` and',
            '    ``F``, the partials of ``e`` into ``d_l``, ``d_w``, ``d_lam`` (3,)."""',
            *shared,
            *(f"    {outputs[i // 3]}[{i % 3}] = {value}" for i, value in enumerate(reduced[2:])),
            f"    return {reduced[0]}, {reduced[1]}",
        ]
    )


def source() -> str:
    """The text of :mod:`sliders.joints.compiled_laws`."""
    header = f'''"""The slider laws of :mod:`sliders.joints.equations`, compiled (generated).

Written by ``python -m sliders.joints.generate`` from the laws' one statement (sympy traces
each law and differentiates it); ``tests/test_compiled_laws.py`` checks that regenerating
changes nothing.  Each function writes a law's rows (:data:`ROWS`) and its nonzero
derivatives in the point quantities (:data:`POINT`; which they are: :data:`DERIVATIVE_ROW`,
:data:`DERIVATIVE_OF`); :func:`sliders.joints.kernel.joint_equations` chains them through
the line's maps.
"""

# ruff: noqa

import math

import numba
import numpy as np

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: The point quantities (name, size) in their flat order (``mu``: the kind's ``J``).
POINT = {POINT!r}
#: The constants (name, size): offset, slider axes (row-major), reference, scale.
CONSTANTS = {CONSTANTS!r}
#: The rows (name, size) in their flat order (``orientation``: the kind's ``J``).
ROWS = {ROWS!r}
#: The first entry of each point quantity, constant and row.
AT_POINT = {_offsets(POINT)!r}
AT_CONSTANT = {_offsets(CONSTANTS)!r}
AT_ROW = {_offsets(ROWS)!r}
'''
    names = {key: f"{key[0]}_{key[1]}" for key in LAWS}
    laws = [_function(names[key], *key) for key in LAWS]
    codes = ", ".join(f"{key!r}: {i}" for i, key in enumerate(LAWS))
    footer = (
        f"#: The code of each ``(kind, orientation)`` law (:func:`law`).\nCODES = {{{codes}}}\n"
    )
    dispatch = [
        "@numba.njit(cache=True)",
        "def law(code, p, c, rows, d):",
        '    """Run the law of ``code`` (:data:`CODES`)."""',
    ]
    for i, key in enumerate(LAWS):
        word = "if" if i == 0 else "elif"
        dispatch += [f"    {word} code == {i}:", f"        {names[key]}(p, c, rows, d)"]
    sparsity = _sparsity([entries for _, entries in laws])
    constants = header.rstrip() + "\n" + footer.rstrip() + "\n" + sparsity
    parts = [constants, *(text for text, _ in laws), "\n".join(dispatch), _friction()]
    return "\n\n\n".join(parts) + "\n"


def main() -> int:
    """Write :data:`TARGET`."""
    TARGET.write_text(source())
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
