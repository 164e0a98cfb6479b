"""The package's import structure, read from the source without importing it: the graph of
imports between the modules of python/mdrvisc has no cycle, analytic stays below geometry and
media, and only mdrvisc.paper imports matplotlib.

Every ``import`` and ``from ... import`` statement counts, at module level or inside a
function (a deferred import closes a cycle just the same, only later). ``from . import name``
points at the submodule ``name`` when there is one, else at the package's ``__init__``.
Parents a submodule's import runs implicitly (``mdrvisc.paper`` for ``mdrvisc.paper.studies``)
are not edges: each package's ``__init__`` imports its own submodules.
"""

import ast
from pathlib import Path

import pytest

PACKAGE = "mdrvisc"
SOURCE = Path(__file__).resolve().parents[1] / "python" / PACKAGE


def module_files(root=SOURCE, package=PACKAGE):
    """{dotted module name: path} of every .py file under ``root`` (``__init__`` as the
    package itself)."""
    modules = {}
    for path in sorted(root.rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        modules[".".join([package, *parts])] = path
    return modules


def imported_names(name, path):
    """(absolute module name, imported names) for every import statement of module ``name``;
    the names are None for ``import x``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(alias.name, None) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            found.append((module, [alias.name for alias in node.names]))
    return found


def bound_names(path):
    """Names a module binds at its top level (definitions, assignments, imports)."""
    names = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name))
    return names


def import_graph(modules):
    """{module: set of modules of the package it imports}.

    ``import a.b`` points at a.b; ``from a import n`` at the submodule a.n if there is one
    (``from . import analytic``), else at a when a is a module (``from .geometry import Rod``)
    or a package whose ``__init__`` binds n; a name a package does not bind is a submodule
    that is not Python source (``from . import _core``, the compiled extension): no edge.
    """
    graph = {}
    for name, path in modules.items():
        targets = set()
        for module, names in imported_names(name, path):
            if names is None:
                targets.add(module)
                continue
            for imported in names:
                if f"{module}.{imported}" in modules:
                    targets.add(f"{module}.{imported}")
                elif module in modules and (modules[module].name != "__init__.py"
                                            or imported in bound_names(modules[module])):
                    targets.add(module)
        graph[name] = (targets & modules.keys()) - {name}
    return graph


def find_cycle(graph):
    """A cycle of ``graph`` as [a, b, ..., a], or None when it is acyclic (depth-first search
    with white/grey/black marks: an edge to a grey node closes a cycle)."""
    state = dict.fromkeys(graph, "white")
    stack = []

    def visit(node):
        state[node] = "grey"
        stack.append(node)
        for target in sorted(graph.get(node, ())):
            if state.get(target, "white") == "grey":
                return stack[stack.index(target):] + [target]
            if state.get(target, "white") == "white":
                cycle = visit(target)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = "black"
        return None

    for node in sorted(graph):
        if state[node] == "white":
            cycle = visit(node)
            if cycle:
                return cycle
    return None


@pytest.fixture(scope="module")
def graph():
    return import_graph(module_files())


def test_the_graph_covers_the_package(graph):
    # sanity: the parser sees the modules and the edges we know of
    for module in ("mdrvisc", "mdrvisc._validate", "mdrvisc.analytic", "mdrvisc.geometry",
                   "mdrvisc.media", "mdrvisc.solve", "mdrvisc.paper", "mdrvisc.paper.studies",
                   "mdrvisc.paper.report"):
        assert module in graph
    assert "mdrvisc.geometry" in graph["mdrvisc"]
    assert "mdrvisc.geometry" in graph["mdrvisc.profiles"]
    assert "mdrvisc._validate" in graph["mdrvisc.media"]
    assert "mdrvisc.analytic" in graph["mdrvisc.paper.studies"]  # from .. import analytic
    assert "mdrvisc.paper.studies" in graph["mdrvisc.paper.report"]
    assert "mdrvisc.paper.report" in graph["mdrvisc.paper"]


def test_imports_are_acyclic(graph):
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_the_cycle_check_finds_cycles(tmp_path):
    # a deferred import inside a function closes a cycle, as analytic -> geometry once did
    (tmp_path / "__init__.py").write_text("from . import a\n")
    (tmp_path / "a.py").write_text("from .b import f\n")
    (tmp_path / "b.py").write_text("def f():\n    from . import a\n    return a\n")
    graph = import_graph(module_files(tmp_path, "pkg"))
    assert graph == {"pkg": {"pkg.a"}, "pkg.a": {"pkg.b"}, "pkg.b": {"pkg.a"}}
    assert find_cycle(graph) == ["pkg.a", "pkg.b", "pkg.a"]
    (tmp_path / "b.py").write_text("def f():\n    return 1\n")
    assert find_cycle(import_graph(module_files(tmp_path, "pkg"))) is None


def test_analytic_imports_neither_geometry_nor_media(graph):
    assert not graph["mdrvisc.analytic"] & {"mdrvisc.geometry", "mdrvisc.media"}
    assert graph["mdrvisc._validate"] <= {"mdrvisc.errors"}


def test_only_the_paper_and_force_maps_import_matplotlib():
    modules = module_files()
    users = {name for name, path in modules.items()
             if any(module.split(".")[0] == "matplotlib"
                    for module, _ in imported_names(name, path))}
    assert users and all(name.startswith("mdrvisc.paper.") or name == "mdrvisc.afm._maps"
                         for name in users), users
    # and only inside functions: importing mdrvisc.paper does not import matplotlib
    for name in users:
        tree = ast.parse(modules[name].read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                assert "matplotlib" not in ast.unparse(node), (name, ast.unparse(node))


NO_SCIPY = """
import sys
sys.modules["scipy"] = None  # any import of scipy now fails
import mdrvisc as mv
sphere = mv.Scene(indenter=mv.Sphere(radius=1.0), medium=mv.Viscous(eta=1.0), force=1.0, duration=2.0)
for method, n in (("bem", 33), ("mdr", 2001)):
    assert mv.solve(sphere, method, n).depth[-1] > 0
assert mv.Sphere(1.0).depth_from_impulse(0.2, 1.0) > 0
assert mv.analytic.lee_radok_depth_from_impulse(0.2, mv.Sphere(1.0), 1.0) > 0
print("ok")
"""


def test_the_package_runs_without_scipy():
    """scipy is a test dependency only: solving, the indenters' closed and numerical
    Lee-Radok depths and the analytic module work with it unimportable."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", NO_SCIPY], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]
