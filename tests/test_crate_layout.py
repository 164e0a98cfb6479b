"""The Rust crate's layout, read from its source: the graph of ``crate::`` paths between its
modules (outside the Python bindings, test modules and comments) has no cycle, and no module
reaches a layer above its own. The layers, from the bottom: support, model, halfspace and
stepping, the engines bem and mdr (which do not import each other), run.

A module is a file (``foo.rs`` or ``foo/mod.rs``); a path ``crate::a::b::Item`` points at the
deepest module it names. A submodule's paths to its own parents are not edges (a parent
declares its children), and a parent's paths into its children are.
"""

import re
from pathlib import Path

import pytest

SOURCE = Path(__file__).resolve().parents[1] / "rust" / "src"
#: Layer of each top-level module; a module may import from its own layer and those below,
#: except that the two engines stay apart.
LAYERS = {"support": 0, "model": 1, "halfspace": 2, "stepping": 2, "bem": 3, "mdr": 3, "run": 4}
ENGINES = {"bem", "mdr"}


def modules():
    """{module path "a::b": source file} of the crate's modules outside the bindings and the
    binary."""
    found = {}
    for path in sorted(SOURCE.rglob("*.rs")):
        parts = list(path.relative_to(SOURCE).with_suffix("").parts)
        if parts[-1] == "mod":
            parts.pop()
        if parts[0] in ("lib", "main", "python", "bin"):
            continue
        found["::".join(parts)] = path
    return found


def code_of(path):
    """The source of ``path`` without its test modules and comments."""
    text = path.read_text(encoding="utf-8").split("#[cfg(test)]")[0]
    return re.sub(r"//[^\n]*", "", text)


def graph():
    """{module: modules it names}."""
    mods = modules()

    def resolve(parts):
        for k in range(len(parts), 0, -1):
            name = "::".join(parts[:k])
            if name in mods:
                return name
        return None

    edges = {}
    for name, path in mods.items():
        targets = set()
        for p in re.findall(r"\bcrate((?:::[A-Za-z_][A-Za-z0-9_]*)+)", code_of(path)):
            target = resolve(p.strip(":").split("::"))
            if target and target != name and not name.startswith(target + "::"):
                targets.add(target)
        edges[name] = targets
    return edges


def test_every_module_is_seen():
    mods = modules()
    assert {"model::scene", "model::body", "model::contact_law", "halfspace::body",
            "bem::static_contact", "mdr::foundation", "run", "stepping"} <= set(mods)
    assert set(name.split("::")[0] for name in mods) <= set(LAYERS) | {"paper"}


def test_the_crate_has_no_import_cycle():
    edges = graph()
    state = {}
    stack = []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(edges[node]):
            if state.get(nxt) == "open":
                pytest.fail("import cycle: " + " -> ".join(stack[stack.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = "done"

    for node in sorted(edges):
        if node not in state:
            visit(node)


def test_no_module_imports_a_layer_above_its_own():
    upward = []
    for name, targets in graph().items():
        top = name.split("::")[0]
        for target in targets:
            other = target.split("::")[0]
            if top == other or top not in LAYERS:
                continue
            if LAYERS[other] > LAYERS[top] or (top in ENGINES and other in ENGINES):
                upward.append(f"{name} -> {target}")
    assert not upward, upward
