"""Write the vectorised joint rows from their one statement.

``python -m sliders.joints.exact_generate``: the rows ``ux`` and ``rx`` of
:func:`sliders.joints.exact_laws.rows` (the other four are these two on the frames' columns
taken in another order, :data:`sliders.joints.exact_laws.GENERATED`) run on sympy symbols
in place of the two nodes' positions and rotations and of the joint's offsets and frames,
each node moved as :func:`~sliders.joints.exact_laws.derive` seeds it,
``R -> (I + skew(eta)) (I + skew(epsilon)) R`` and ``x -> x + eta + epsilon`` (the variation
``eta`` inside the change of state ``epsilon``).  The row, its first derivatives in ``eta``
(a row of ``B``) and its mixed second derivatives in ``eta`` and ``epsilon`` (the row's share
of ``H`` per unit multiplier), at zero, after common-subexpression elimination, are printed
as one numpy function per row into :mod:`sliders.joints.exact_rows`, vectorised over any
number of joints.  The module is committed; ``tests/test_exact_joints.py`` regenerates it
and requires the same text, and holds it to :func:`~sliders.joints.exact_laws.derive` (the
dual numbers' derivation of the same statement) on every row to round-off.

Needs sympy (the ``test`` extra); nothing at run time imports this module.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import sympy

from sliders.joints.exact_laws import GENERATED, JointLaw, rows

#: What a row reads, in order, with sizes: the nodes' positions and rotations (row-major),
#: the joint's offsets and frames (row-major).
INPUTS = (
    ("x_a", 3),
    ("R_a", 9),
    ("x_b", 3),
    ("R_b", 9),
    ("p_a", 3),
    ("p_b", 3),
    ("F_a", 9),
    ("F_b", 9),
)
TARGET = Path(__file__).with_name("exact_rows.py")


def _skew(v: list[sympy.Symbol]) -> sympy.Matrix:
    return sympy.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def traced(row: str) -> tuple[sympy.Expr, list[sympy.Symbol], list[sympy.Symbol]]:
    """The row on symbols ``p[k]`` (:data:`INPUTS` order), with the nodes turned and moved
    by the variation ``eta`` and the change ``epsilon`` (12 each: ``[du_a, dphi_a, du_b,
    dphi_b]``): the expression and the two lists of symbols."""
    first = np.cumsum([0, *(size for _, size in INPUTS)])
    p = {
        name: [sympy.Symbol(f"p[{first[k] + i}]", real=True) for i in range(size)]
        for k, (name, size) in enumerate(INPUTS)
    }
    eta = list(sympy.symbols("eta0:12", real=True))
    eps = list(sympy.symbols("eps0:12", real=True))
    ends = []
    for k, (x, R) in enumerate((("x_a", "R_a"), ("x_b", "R_b"))):
        e, d = eta[6 * k : 6 * k + 6], eps[6 * k : 6 * k + 6]
        moved = sympy.Matrix(p[x]) + sympy.Matrix(e[:3]) + sympy.Matrix(d[:3])
        turned = (
            (sympy.eye(3) + _skew(e[3:])) * (sympy.eye(3) + _skew(d[3:])) * sympy.Matrix(3, 3, p[R])
        )
        ends += [np.array(list(moved), dtype=object), np.array(turned.tolist(), dtype=object)]
    law = JointLaw(
        (row,),
        np.array(p["p_a"], dtype=object),
        np.array(p["p_b"], dtype=object),
        np.array(p["F_a"], dtype=object).reshape(3, 3),
        np.array(p["F_b"], dtype=object).reshape(3, 3),
    )
    (value,) = rows(law, *ends)
    return value, eta, eps


def _function(row: str) -> str:
    """The numpy function of one row: its value, ``B`` row and ``H`` share."""
    value, eta, eps = traced(row)
    no_eta = {s: sympy.Integer(0) for s in eta}
    no_eps = {s: sympy.Integer(0) for s in eps}
    gradient = [sympy.diff(value, e).xreplace(no_eta) for e in eta]  # functions of epsilon
    entries = [
        (i, j, sympy.diff(g, d).xreplace(no_eps))
        for i, g in enumerate(gradient)
        for j, d in enumerate(eps)
    ]
    entries = [(i, j, h) for i, j, h in entries if h != 0]
    firsts = [(j, g.xreplace(no_eps)) for j, g in enumerate(gradient)]
    firsts = [(j, g) for j, g in firsts if g != 0]
    value = value.xreplace(no_eta).xreplace(no_eps)
    expressions = [value, *(g for _, g in firsts), *(h for _, _, h in entries)]
    shared, reduced = sympy.cse(expressions, symbols=sympy.numbered_symbols("t"), order="none")
    size = sum(s for _, s in INPUTS)
    lines = [
        f"def row_{row}(p, B, H):",
        f'    """The row ``{row}`` of joints whose inputs are ``p`` ({size}, n)',
        "    (:data:`INPUTS`): returns its values (n,); writes its ``B`` row into ``B`` (12, n)",
        '    and its share of ``H`` per unit multiplier into ``H`` (12, 12, n), zero on entry."""',
    ]
    lines += [f"    {s} = {sympy.pycode(e)}" for s, e in shared]
    lines += [
        f"    B[{j}] = {sympy.pycode(e)}" for (j, _), e in zip(firsts, reduced[1:], strict=False)
    ]
    rest = reduced[1 + len(firsts) :]
    lines += [
        f"    H[{i}, {j}] = {sympy.pycode(e)}" for (i, j, _), e in zip(entries, rest, strict=True)
    ]
    lines.append(f"    return {sympy.pycode(reduced[0])}")
    return "\n".join(lines)


def source() -> str:
    """The text of :mod:`sliders.joints.exact_rows`."""
    header = f'''"""The joint rows of :mod:`sliders.joints.exact_laws`, vectorised (generated).

Written by ``python -m sliders.joints.exact_generate`` from the rows' one statement (sympy
traces each row and differentiates it); ``tests/test_exact_joints.py`` checks that
regenerating changes nothing.  Each function evaluates one row of any number of joints at
once: its values, its ``B`` row and its share of ``H`` per unit multiplier.
"""

# ruff: noqa

#: The inputs (name, size) in their order (rotations and frames row-major).
INPUTS = {INPUTS!r}
'''
    bodies = [_function(row) for row in GENERATED]
    table = (
        "#: The function of each row.\nROW_FUNCTIONS = {"
        + ", ".join(f"{row!r}: row_{row}" for row in GENERATED)
        + "}"
    )
    return "\n\n\n".join([header.rstrip(), *bodies, table]) + "\n"


if __name__ == "__main__":
    TARGET.write_text(source())
    print(f"wrote {TARGET}")
