"""No import cycle between the modules of the harness (vc, plc_stub, interfaces, fmu).

A cycle ties modules into one unit that can be neither understood nor tested alone; the layers of
vc/core (import-linter, pyproject.toml) only keep packages in order, this keeps every module so.
Imports inside functions and under ``TYPE_CHECKING`` count: they are dependencies all the same.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping, Set

import grimp

PACKAGES = ("vc", "plc_stub", "interfaces", "fmu")

# Cycles known and accepted, each as the set of modules it ties together (none today); any other
# cycle fails the test.
KNOWN_CYCLES: frozenset[frozenset[str]] = frozenset()


def import_graph() -> dict[str, set[str]]:
    graph = grimp.build_graph(*PACKAGES, exclude_type_checking_imports=False)
    return {module: set(graph.find_modules_directly_imported_by(module)) for module in graph.modules}


def tangles(edges: Mapping[str, Set[str]]) -> list[frozenset[str]]:
    """The strongly connected components of more than one module (or a module importing itself):
    each holds at least one cycle.  Tarjan's algorithm, iterative."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[frozenset[str]] = []
    for root in sorted(edges):
        if root in index:
            continue
        work: list[tuple[str, list[str]]] = [(root, sorted(edges[root]))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            module, pending = work[-1]
            if pending:
                target = pending.pop()
                if target not in edges:
                    continue
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, sorted(edges[target])))
                elif target in on_stack:
                    low[module] = min(low[module], index[target])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[module])
            if low[module] == index[module]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == module:
                        break
                if len(component) > 1 or module in edges[module]:
                    found.append(frozenset(component))
    return found


def shortest_cycle(edges: Mapping[str, Set[str]], component: frozenset[str]) -> list[str]:
    """A shortest cycle within ``component``, as the modules in import order, the first repeated last."""
    best: list[str] = []
    for start in sorted(component):
        came_from: dict[str, str] = {}
        queue = deque([start])
        while queue:
            module = queue.popleft()
            if start in edges[module]:
                path = [module]
                while path[-1] != start:
                    path.append(came_from[path[-1]])
                cycle = [*reversed(path), start]
                if not best or len(cycle) < len(best):
                    best = cycle
                break
            for target in sorted(edges[module] & component):
                if target not in came_from and target != start:
                    came_from[target] = module
                    queue.append(target)
    return best


def test_tangles_and_shortest_cycles_are_found() -> None:
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "e": {"e"}, "f": {"a"}}
    assert sorted(map(sorted, tangles(edges))) == [["a", "b", "c"], ["e"]]
    assert shortest_cycle(edges, frozenset({"a", "b", "c"})) == ["a", "b", "c", "a"]
    assert shortest_cycle(edges, frozenset({"e"})) == ["e", "e"]


def test_no_import_cycle_between_modules() -> None:
    edges = import_graph()
    new = [component for component in tangles(edges) if component not in KNOWN_CYCLES]
    described = ["\n  " + " -> ".join(shortest_cycle(edges, component))
                 + (f"  (ties {len(component)} modules: {', '.join(sorted(component))})" if len(component) > 2 else "")
                 for component in new]
    assert not new, "import cycles:" + "".join(described)
