"""The import graph of the project, read with ``ast``: layers point one way, no cycles.

Every import counts, wherever it stands (module level, inside a function, under
``TYPE_CHECKING``): a lazy import is a dependency all the same.  ``fvbeam`` depends on
nothing of ours, ``sliders`` on ``fvbeam`` only, ``studies`` on both; nothing imports
``studies`` but ``studies`` and the tests.  Inside ``sliders`` the subpackages are layered
too (``docs/architecture.md``): lines, joints, forces, solve, the sliding-beams setup, the
application (scenes, runs, outputs), and the landing-gear model, which reads the
application's derived results.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("fvbeam", "sliders", "studies")
#: What each package may import of ours (besides itself).
ALLOWED = {"fvbeam": set(), "sliders": {"fvbeam"}, "studies": {"fvbeam", "sliders"}}
#: The layers inside ``sliders``: a subpackage imports only those of a lower rank.
SLIDERS_LAYERS = {
    "lines": 0,
    "joints": 1,
    "forces": 2,
    "solve": 3,
    "sliding_beams": 4,
    "app": 5,
    "gear": 6,
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for package in PACKAGES for p in (ROOT / package).rglob("*.py")}


def resolve(name: str, known: dict[str, Path]) -> str | None:
    """The longest known module that ``name`` (a module or a name inside one) starts with."""
    while name:
        if name in known:
            return name
        name = name.rpartition(".")[0]
    return None


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """Our modules that ``name`` imports, anywhere in its source."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            # ``from package import module`` depends on the module; ``from module import
            # name`` on the module that holds the name.
            targets = [
                f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                for alias in node.names
            ]
        for target in targets:
            hit = resolve(target, known)
            if hit is not None and hit != name:
                found.add(hit)
    return found


def graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imports(name, path, known) for name, path in known.items()}


def test_the_graph_sees_the_modules():
    """The walk finds every package and the edges it must (guards against a vacuous pass)."""
    edges = graph()
    assert {n.split(".")[0] for n in edges} == set(PACKAGES)
    assert "fvbeam.beam" in edges["fvbeam.structure"]
    assert "sliders.solve.statics" in edges["sliders.app.run"]


@pytest.mark.parametrize("package", PACKAGES)
def test_layers_point_one_way(package):
    """``fvbeam`` imports nothing of ours, ``sliders`` only ``fvbeam``: never ``studies``."""
    wrong = sorted(
        f"{name} -> {target}"
        for name, targets in graph().items()
        if name.split(".")[0] == package
        for target in targets
        if target.split(".")[0] not in ALLOWED[package] | {package}
    )
    assert not wrong, "imports against the layers:\n" + "\n".join(wrong)


def test_no_import_cycles():
    """Tarjan's strongly connected components of the module graph are all single modules.
    A package's ``__init__`` re-exporting its modules is an edge like any other, so a module
    importing its own package's ``__init__`` would close a cycle and is caught here too."""
    edges = graph()
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    assert not cycles, "import cycles: " + "; ".join(" <-> ".join(c) for c in cycles)


def test_the_layers_inside_sliders_point_one_way():
    """A subpackage of ``sliders`` imports only subpackages below it (:data:`SLIDERS_LAYERS`;
    every subpackage is ranked), and the walk sees the edges it must."""
    edges = graph()
    subpackages = {p.name for p in (ROOT / "sliders").iterdir() if (p / "__init__.py").exists()}
    assert subpackages == set(SLIDERS_LAYERS), "rank every subpackage of sliders"
    layer_of = {name: name.split(".")[1] for name in edges if name.startswith("sliders.")}
    wrong = sorted(
        f"{name} -> {target}"
        for name, targets in edges.items()
        if name.startswith("sliders.") and layer_of[name] in SLIDERS_LAYERS
        for target in targets
        if target.startswith("sliders.")
        and layer_of[target] in SLIDERS_LAYERS
        and layer_of[target] != layer_of[name]
        and SLIDERS_LAYERS[layer_of[target]] >= SLIDERS_LAYERS[layer_of[name]]
    )
    assert not wrong, "imports against the layers of sliders:\n" + "\n".join(wrong)
    assert "sliders.joints.equations" in edges["sliders.joints.slider"]
    assert "sliders.lines.chain" in edges["sliders.forces.moving_load"]
