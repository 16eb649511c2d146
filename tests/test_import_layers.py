"""No import cycle between the package's modules, imports inside functions included.

The layer order itself is import-linter's contract (pyproject.toml, `lint-imports` in
scripts/check.sh); this test keeps the weaker promise everywhere, inside subpackages too:
whatever imports what, lazily or not, no module can reach itself. Imports made only for
type checking (under ``if TYPE_CHECKING:``) never run and are left out."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest

grimp = pytest.importorskip("grimp", reason="grimp comes with import-linter (the test extra)")


def import_graph(package: str) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (grimp: module level and in functions).
    ``from . import _core`` names the compiled extension, which the graph does not see
    and records as an import of the package itself: such edges are dropped."""
    graph = grimp.build_graph(package, exclude_type_checking_imports=True, cache_dir=None)
    edges: dict[str, set[str]] = {}
    for module in graph.modules:
        targets = set()
        for imported in graph.find_modules_directly_imported_by(module):
            if imported == package:
                details = graph.get_import_details(importer=module, imported=imported)
                if all("_core" in d["line_contents"] for d in details):
                    continue
            targets.add(imported)
        edges[module] = targets
    return edges


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_the_package_has_no_import_cycle() -> None:
    edges = import_graph("linkwork")
    assert "linkwork.model.compiled" in edges and "linkwork.view.drawing" in edges
    # the declared lazy imports are in the graph: a cycle through one would be found
    assert "linkwork.view.notebook" in edges["linkwork.model.results"]
    assert cycles(edges) == []


def test_a_cycle_through_a_lazy_import_is_found(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    package = tmp_path / "cyclepkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("")
    (package / "low.py").write_text("from .sub import high\n")
    (package / "sub" / "high.py").write_text(
        textwrap.dedent(
            """
            from typing import TYPE_CHECKING

            if TYPE_CHECKING:
                from .. import typed  # never runs: not an edge


            def convenience():
                from ..low import something  # lazy, and still a cycle

                return something
            """
        )
    )
    (package / "typed.py").write_text("from .sub import high\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    edges = import_graph("cyclepkg")
    assert cycles(edges) == [["cyclepkg.low", "cyclepkg.sub.high"]]
    sys.modules.pop("cyclepkg", None)
