# SPDX-License-Identifier: LGPL-2.1-or-later
"""The mfgeom package's modules import each other without cycles: read from the source
(every import statement, also those inside functions, so a lazy import that only hides a
cycle counts), no FreeCAD needed.  ALLOWED lists cycles that may stay (none)."""

import ast
import os

import pytest

WORKBENCH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "workbench")

# Cycles that may stay (a ratchet: an entry may only go; none may come).
ALLOWED = []


def modules():
    found = {}
    for folder, _dirs, files in os.walk(os.path.join(WORKBENCH, "mfgeom")):
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                module = os.path.relpath(path, WORKBENCH)[:-3].replace(os.sep, ".")
                found[module.removesuffix(".__init__")] = path
    return found


def import_graph():
    mods = modules()
    graph = {}
    for module, path in mods.items():
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read(), path)
        deps = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                for alias in node.names:
                    full = f"{node.module}.{alias.name}"
                    deps.add(full if full in mods else node.module)
            elif isinstance(node, ast.Import):
                deps.update(alias.name for alias in node.names)
        graph[module] = {d for d in deps if d in mods and d != module}
    return graph


def cycles(graph):
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(component)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_cycle_finder_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [{"a", "b", "c"}]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_graph_sees_lazy_imports():
    graph = import_graph()
    # medial_view imports medial_panel inside setEdit only
    assert "mfgeom.gui.medial_panel" in graph["mfgeom.gui.medial_view"]
    assert "mfgeom.core" in graph["mfgeom.parting"]


def test_no_import_cycles_but_the_allowed_ones():
    found = cycles(import_graph())
    assert [c for c in found if c not in ALLOWED] == []
    assert [c for c in ALLOWED if c not in found] == [], "a cycle went: remove it from ALLOWED"


@pytest.mark.parametrize("pair", [("mfgeom.gui.commands", "mfgeom.gui.clearance_command"),
                                  ("mfgeom.gui.medial_panel", "mfgeom.gui.medial_view"),
                                  ("mfgeom.gui.parting_panel", "mfgeom.gui.parting_view")])
def test_the_broken_cycles_stay_broken(pair):
    graph = import_graph()
    a, b = pair
    assert not (b in graph[a] and a in graph[b])
    assert a in graph[b] or b in graph[a]      # still one direction
