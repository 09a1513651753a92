"""The README's whiteboard holds: data flows fem -> rom -> contact -> validation.

Checked on the source with ``ast`` (every import, at module level or inside functions):
``contact`` never imports ``fem``; ``fem`` never imports ``rom``, ``contact`` or
``validation``; ``rom`` never imports ``contact`` or ``validation``; no module imports a private
name (leading underscore) from another module of the project.
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


@pytest.mark.parametrize("package", PACKAGES)
def test_data_flows_one_way(package):
    bad = []
    for path in _sources(package):
        for line, module, _names in _imports(path):
            top = module.split(".")[0]
            if top in FORBIDDEN[package]:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    assert not bad, "\n".join(bad)


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
