"""The README's whiteboard holds: data flows fem -> rom -> contact -> validation.

Checked on the source with ``ast`` (every import, at module level or inside functions):
``contact`` never imports ``fem``; ``fem`` never imports ``rom``, ``contact`` or
``validation``; ``rom`` never imports ``contact`` or ``validation``; no module imports a private
name (leading underscore) from another module of the project. Inside the packages the
subpackages are layers: the transient schemes never import the steady engine, neither imports
the entry points built on them (``contact.simulate``, ``characteristic``, ``maps``), the
meshing never imports the FE models meshed with it; and no two modules import each other,
directly or around a cycle.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from tests.conftest import ROOT

PACKAGES = ("fem", "rom", "contact", "validation")
FORBIDDEN = {
    "fem": {"rom", "contact", "validation"},
    "rom": {"contact", "validation"},
    "contact": {"fem", "validation"},
    "validation": set(),
}


LAYERS = {
    "contact.transient": ("contact.steady", "contact.simulate", "contact.characteristic",
                          "contact.maps", "contact.phase_plane"),
    "contact.steady": ("contact.simulate", "contact.characteristic", "contact.maps",
                       "contact.phase_plane"),
    "fem.meshing": ("fem.model", "fem.modes", "fem.solid3d"),
}
"""Subpackage -> the modules (or packages) its modules never import: the layer above it."""


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """(line, imported module, imported names) of every import statement in a file."""
    tree = ast.parse(path.read_text(), filename=str(path))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.lineno, node.module, [a.name for a in node.names]))
    return out


def _sources(package: str) -> list[Path]:
    return sorted((ROOT / package).rglob("*.py"))


def _module(path: Path) -> str:
    """The dotted name of a source file (a package's ``__init__`` is the package)."""
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _within(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


@pytest.mark.parametrize("package", PACKAGES)
def test_data_flows_one_way(package):
    bad = []
    for path in _sources(package):
        for line, module, _names in _imports(path):
            top = module.split(".")[0]
            if top in FORBIDDEN[package]:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("layer", list(LAYERS))
def test_subpackages_are_layers(layer):
    package = layer.split(".")[0]
    bad = [f"{path.relative_to(ROOT)}:{line} imports {module}"
           for path in _sources(package) if _within(_module(path), layer)
           for line, module, _n in _imports(path)
           if any(_within(module, above) for above in LAYERS[layer])]
    assert not bad, "\n".join(bad)


def _import_graph(packages: tuple[str, ...]) -> dict[str, set[str]]:
    """Module -> the project modules it imports (``from pkg import name`` counts as the
    submodule ``pkg.name`` where there is one, else as ``pkg``)."""
    modules = {_module(p): p for package in packages for p in _sources(package)}

    def known(name: str) -> str | None:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {m: set() for m in modules}
    for m, path in modules.items():
        for _line, module, names in _imports(path):
            subs = [f"{module}.{n}" for n in names if f"{module}.{n}" in modules]
            for target in subs or [module]:
                found = known(target)
                if found is not None and found != m:
                    graph[m].add(found)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_cycles():
    """No module imports itself around a loop of imports (at module level or in a function)."""
    graph = _import_graph(("fem", "rom", "contact"))
    assert graph["contact.steady.engine"] >= {"contact.steady.exact", "contact.steady.slow"}
    assert _cycles(graph) == []
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_module_imports_a_private_name_of_another():
    bad = []
    for package in (*PACKAGES, "benchmarks"):
        for path in _sources(package):
            for line, module, names in _imports(path):
                if module.split(".")[0] not in PACKAGES:
                    continue
                private = [n for n in names if n.startswith("_") and not n.startswith("__")]
                if private:
                    bad.append(f"{path.relative_to(ROOT)}:{line} imports {private} from "
                               f"{module}")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("package", ("fem", "rom", "contact"))
def test_only_validation_draws_plots(package):
    """Plots are the presentation layer: matplotlib is imported in ``validation`` only (mode
    pictures in ``fem.render`` use pyvista off screen, not matplotlib)."""
    bad = [f"{path.relative_to(ROOT)}:{line} imports {module}"
           for path in _sources(package) for line, module, _n in _imports(path)
           if module.split(".")[0] == "matplotlib"]
    assert not bad, "\n".join(bad)


def test_the_checks_see_the_imports():
    """The scan finds the imports it is meant to judge (guards against a vacuous pass)."""
    found = {module for path in _sources("rom") for _l, module, _n in _imports(path)}
    assert "rom.params" in found and "fem.model" in found  # rom.from_fem builds on fem


def _exits_clean(code: str) -> None:
    """Run ``code`` in a fresh interpreter (imports counted from zero); it exits 0 when its
    check holds, and prints what it found otherwise."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_default_frequency_check_imports_no_optimizer():
    """`lusm simulate` at the default 40 kHz checks how far that is from the set's modes
    (validation.options.warn_default_frequency); asking contact.drive.auto_frequency for it
    imported scipy.optimize (0.36 s) into every default run. On Table 2's set, whose own
    point is 39.8 kHz, the grid's best decides without the optimizer."""
    code = (
        "import sys, validation.options as o; from rom import table2;"
        "o.warn_default_frequency(table2(), 40e3);"
        "sys.exit(1 if 'scipy.optimize' in sys.modules else 0)"
    )
    _exits_clean(code)


def test_the_contact_hot_path_imports_no_scipy_solvers():
    """``lusm simulate``'s import path (event kernel, window, results, Table 2) loads no SciPy
    solver module: the propagators are NumPy (``contact.expm``); ``solve_ivp`` and
    ``minimize_scalar`` are imported only by the reference scheme and ``--frequency auto``."""
    code = (
        "import sys, contact.simulate, rom.table2, rom.sources;"
        "bad=sorted(m for m in sys.modules if m.startswith(('scipy.linalg', 'scipy.integrate',"
        " 'scipy.optimize', 'scipy.sparse')));"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    _exits_clean(code)
