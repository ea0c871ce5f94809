"""The import graph of the FreeCAD workbench package (Mod/OracleMesh/oraclemesh_fc), read from
the sources with ast (no FreeCAD needed): no cycles, counting imports inside functions too;
the GUI commands never reach the task panel; every package-relative import names a module
that exists."""
import ast
import os

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PACKAGE_NAME = "oraclemesh_fc"
PACKAGE = os.path.join(REPO, "Mod", "OracleMesh", PACKAGE_NAME)
INIT = "__init__"  # the package itself: `from . import name` of a name that is no module


def package_modules():
    return sorted(f[:-3] for f in os.listdir(PACKAGE) if f.endswith(".py"))


def import_targets(source, modules):
    """Modules of the package that source imports, anywhere in it (module level, functions,
    methods), as module names; INIT for the package itself."""
    def module_of(dotted):  # "job" or "job.sub" -> "job"
        return dotted.split(".")[0]

    def names_from_package(aliases):  # `from . import a, b`: submodules, else the package
        return {a.name if a.name in modules else INIT for a in aliases}

    targets = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1:
                targets |= ({module_of(node.module)} if node.module
                            else names_from_package(node.names))
            elif node.level == 0 and node.module == PACKAGE_NAME:
                targets |= names_from_package(node.names)
            elif node.level == 0 and (node.module or "").startswith(PACKAGE_NAME + "."):
                targets.add(module_of(node.module[len(PACKAGE_NAME) + 1:]))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == PACKAGE_NAME:
                    targets.add(INIT)
                elif alias.name.startswith(PACKAGE_NAME + "."):
                    targets.add(module_of(alias.name[len(PACKAGE_NAME) + 1:]))
    return targets


def import_graph():
    modules = package_modules()
    graph = {}
    for name in modules:
        with open(os.path.join(PACKAGE, name + ".py")) as f:
            graph[name] = import_targets(f.read(), modules)
    return graph


def find_cycle(graph):
    """A list of modules [a, b, ..., a] forming a cycle, or None."""
    state = {}  # module -> "open" while on the depth-first path, "done" after

    def visit(node, path):
        state[node] = "open"
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt, path + [nxt])
                if found:
                    return found
        state[node] = "done"
        return None

    for start in sorted(graph):
        if start not in state:
            found = visit(start, [start])
            if found:
                return found
    return None


def reachable(graph, start):
    seen, todo = set(), [start]
    while todo:
        for nxt in graph.get(todo.pop(), ()):
            if nxt not in seen:
                seen.add(nxt)
                todo.append(nxt)
    return seen


def test_the_reader_sees_function_level_and_package_imports():
    modules = ["a", "b", "panel"]
    source = (
        "import os\n"
        "from . import b\n"
        "from . import helper_function\n"
        "def f():\n"
        "    from .panel import open_panel\n"
        "class C:\n"
        "    def m(self):\n"
        "        import oraclemesh_fc.a.x\n"
        "        from oraclemesh_fc import makeMesh\n")
    assert import_targets(source, modules) == {"b", INIT, "panel", "a"}


def test_the_cycle_finder_finds_cycles():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"x": {"x"}}) == ["x", "x"]


def test_the_package_is_read():
    graph = import_graph()
    # The modules the GUI is made of, and imports between them: an empty graph would pass
    # every check below.
    assert {INIT, "commands", "factory", "mesh_object", "task_panel", "view_provider",
            "selection"} <= set(graph)
    assert "factory" in graph[INIT] and "mesh_object" in graph["factory"]


def test_no_import_cycles():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle in %s: %s" % (PACKAGE_NAME, " -> ".join(cycle))


def test_relative_imports_name_existing_modules():
    graph = import_graph()
    missing = {name: sorted(t for t in targets if t not in graph)
               for name, targets in graph.items()}
    assert not any(missing.values()), missing


@pytest.mark.parametrize("module", ["commands", "selection"])
def test_commands_never_reach_the_task_panel(module):
    """The commands act through FreeCADGui (doCommand, setEdit); the view provider opens the
    panel. Neither they nor anything they import brings in task_panel."""
    graph = import_graph()
    assert "task_panel" not in graph[module]
    assert "task_panel" not in reachable(graph, module), sorted(reachable(graph, module))
