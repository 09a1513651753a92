"""The README's whiteboard holds: data flows fem -> rom -> contact -> validation, with the
studies and the ``lusm`` command line above them.

Checked on the source with ``ast`` (every import, at module level or inside functions):
``bounds`` (the library's structured input refusal) imports no package of the project;
``contact`` never imports ``fem``; ``fem`` never imports ``rom``, ``contact`` or anything
above; ``rom`` never imports ``contact`` or above; no library package imports the command
line; no module imports a private name (leading underscore) from another module of the
project; and the modules' import graph has no cycle. Inside the library the subpackages are
layers: the transient schemes never import the steady engine, neither imports the entry
points built on them (``contact.simulate``, ``characteristic``, ``maps``), and the meshing
never imports the FE models meshed with it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from tests.conftest import ROOT

PACKAGES = ("bounds", "fem", "rom", "contact", "calibration", "validation", "studies",
            "lusm")
ABOVE = {"calibration", "validation", "studies", "lusm", "tools"}
FORBIDDEN = {
    "bounds": {"fem", "rom", "contact", *ABOVE},
    "fem": {"rom", "contact", *ABOVE},
    "rom": {"contact", *ABOVE},
    "contact": {"fem", *ABOVE},
    # above contact, below the command line; validation may report on a calibration
    "calibration": {"validation", "studies", "lusm", "tools"},
    "validation": {"tools"},
    "studies": {"tools"},
    "lusm": {"tools"},
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
    module = ROOT / f"{package}.py"  # a top-level module (bounds)
    return [module] if module.is_file() else sorted((ROOT / package).rglob("*.py"))


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _import_graph() -> dict[str, set[str]]:
    """Module -> the project's modules it imports (an imported name that is a module counts
    as that module, ``from fem import modes``; otherwise the module it comes from)."""
    files = {_module_name(p): p for pkg in (*PACKAGES, "tools") for p in _sources(pkg)}
    graph = {}
    for name, path in files.items():
        deps = set()
        for _line, module, names in _imports(path):
            if module.split(".")[0] not in files:
                continue
            subs = [f"{module}.{n}" for n in names if f"{module}.{n}" in files]
            deps.update(subs or ([module] if module in files else []))
        graph[name] = deps - {name}
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import cycle of ``graph`` (its modules in order), or None (depth-first search)."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                return path[path.index(dep):] + [dep]
            if dep not in state and (found := visit(dep)):
                return found
        state[node] = 2
        path.pop()
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_the_import_graph_has_no_cycle():
    graph = _import_graph()
    assert len(graph) > 90 and graph["lusm.cli"]  # the scan sees the modules and imports
    assert graph["contact.steady.engine"] >= {"contact.steady.exact", "contact.steady.slow"}
    cycle = _cycle(graph)
    assert cycle is None, " -> ".join(cycle)


def test_the_cycle_search_finds_a_cycle():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


@pytest.mark.parametrize("package", PACKAGES)
@pytest.mark.slow
def test_data_flows_one_way(package):
    bad = []
    for path in _sources(package):
        for line, module, _names in _imports(path):
            top = module.split(".")[0]
            if top in FORBIDDEN[package]:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    assert not bad, "\n".join(bad)


CLI_ONLY = ("lusm.cli", "lusm.commands", "lusm.options", "lusm.fe_errors", "lusm.ranges")
"""The command line proper: parsing and resolving options, the commands. The rest of
``lusm`` (its limits, errors, messages, output sets, interrupts) is the base every upper
package may use."""


@pytest.mark.parametrize("package", ("validation", "studies"))
def test_the_library_above_contact_never_imports_the_command_line(package):
    bad = [f"{path.relative_to(ROOT)}:{line} imports {module}"
           for path in _sources(package) for line, module, _n in _imports(path)
           if any(_within(module, cli) for cli in CLI_ONLY)]
    assert not bad, "\n".join(bad)


def _within(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


@pytest.mark.parametrize("layer", list(LAYERS))
def test_subpackages_are_layers(layer):
    package = layer.split(".")[0]
    bad = [f"{path.relative_to(ROOT)}:{line} imports {module}"
           for path in _sources(package) if _within(_module_name(path), layer)
           for line, module, _n in _imports(path)
           if any(_within(module, above) for above in LAYERS[layer])]
    assert not bad, "\n".join(bad)


@pytest.mark.slow
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
@pytest.mark.slow
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
    """`lusm simulate` without --frequency decides between the paper's 40 kHz and the set's
    own operating point (lusm.options.default_frequency_text); on Table 2's set, driven at
    40 kHz, that decision imports no scipy.optimize (0.36 s into every default run)."""
    code = (
        "import sys, lusm.options as o; from rom import table2;"
        "assert o.default_frequency_text(table2()) == '40e3';"
        "sys.exit(1 if 'scipy.optimize' in sys.modules else 0)"
    )
    _exits_clean(code)


@pytest.mark.slow
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
