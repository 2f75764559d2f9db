"""The house's rules, read from the code itself: the import graph of ``src/acordcs`` has no cycle
(imports inside functions and ``if TYPE_CHECKING:`` blocks included, and the built-in tables'
``"module:attribute"`` references, which are imports made later); the
generator and the engines import nothing of the runtime; no two modules share a name for
different things; no package holds more than 25 modules.

The graph is drawn with :mod:`ast` and cross-checked with networkx's cycle finder."""

from __future__ import annotations

import ast
import re
from collections import Counter
from pathlib import Path

import networkx as nx

SRC = Path(__file__).resolve().parent.parent / "src"
PACKAGE = SRC / "acordcs"
REFERENCE = re.compile(r"(acordcs(?:\.\w+)+):[\w.]+\Z")
"""A built-in table's reference: ``"acordcs.engines.engine_registry:FUZZY"``."""
CONVENTIONAL = {"__init__", "__main__", "errors"}
"""Names that mean the same in every package (its package module, its entry, its errors)."""


def modules() -> dict[str, Path]:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def _imported(tree: ast.AST, name: str, is_package: bool, known: dict[str, Path]) -> set[str]:
    """The modules of the package the module ``name`` imports (resolved to the longest module
    that exists: ``from pkg import submodule`` is an import of the submodule)."""
    package = name if is_package else name.rpartition(".")[0]
    wanted: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.Import):
            wanted.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*parent, *([base] if base else [])])
            subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in known]
            wanted.update(subs)
            if len(subs) < len(node.names):
                wanted.add(base)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            match = REFERENCE.match(node.value)
            if match:
                wanted.add(match.group(1))
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    resolved = set()
    for target in wanted:
        while target and target not in known:
            target = target.rpartition(".")[0]
        if target.startswith("acordcs") and target != name:
            resolved.add(target)
    return resolved


def import_graph() -> nx.DiGraph:
    known = modules()
    graph = nx.DiGraph()
    for name, path in known.items():
        graph.add_node(name)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for target in _imported(tree, name, path.name == "__init__.py", known):
            graph.add_edge(name, target)
    return graph


def test_the_graph_reads_imports_of_every_kind():
    """The graph's reader sees what matters, or the tests below could pass on an empty graph."""
    graph = import_graph()
    assert graph.has_edge("acordcs.generator.pipeline", "acordcs.generator.writer")  # top level
    assert graph.has_edge("acordcs.generator.pipeline", "acordcs.model.reading")  # in a function
    assert graph.has_edge("acordcs.generator.targets", "acordcs.generator.targets.rule_files")
    assert graph.number_of_edges() > 300


def test_the_import_graph_has_no_cycle():
    cycles = list(nx.simple_cycles(import_graph()))
    assert not cycles, "import cycles: " + "; ".join(" -> ".join([*c, c[0]]) for c in cycles)


def test_the_generator_and_the_engines_import_nothing_of_the_runtime():
    graph = import_graph()
    for part in ("acordcs.generator", "acordcs.engines", "acordcs.model", "acordcs.descriptor"):
        roots = [n for n in graph if n == part or n.startswith(part + ".")]
        reached = set().union(*(nx.descendants(graph, n) for n in roots))
        runtime = sorted(n for n in reached if n.startswith("acordcs.runtime"))
        assert not runtime, f"{part} reaches {runtime}"
    engines = [n for n in graph if n.startswith("acordcs.engines")]
    reached = set().union(*(nx.descendants(graph, n) for n in engines))
    assert not [n for n in reached if n.startswith("acordcs.generator")]


def test_no_two_modules_share_a_name():
    names = Counter(p.stem for p in PACKAGE.rglob("*.py") if p.stem not in CONVENTIONAL)
    packages = Counter(p.name for p in PACKAGE.rglob("*") if (p / "__init__.py").is_file())
    shared = {n for n in names if names[n] > 1 or n in packages}
    shared |= {n for n in packages if packages[n] > 1}
    assert not shared, f"module or package names used twice: {sorted(shared)}"


def test_every_directory_of_code_is_a_regular_package_of_at_most_25_modules():
    for directory in [PACKAGE, *(p for p in PACKAGE.rglob("*") if p.is_dir())]:
        code = [p for p in directory.glob("*.py") if p.name != "__init__.py"]
        if directory.name == "__pycache__" or not (code or list(directory.glob("*/__init__.py"))):
            continue
        assert (directory / "__init__.py").is_file(), f"{directory} is not a regular package"
        assert len(code) <= 25, f"{directory} holds {len(code)} modules"
