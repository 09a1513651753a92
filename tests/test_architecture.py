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
    return sorted((ROOT / package).glob("*.py"))


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


def test_the_checks_see_the_imports():
    """The scan finds the imports it is meant to judge (guards against a vacuous pass)."""
    found = {module for path in _sources("rom") for _l, module, _n in _imports(path)}
    assert "rom.params" in found and "fem.model" in found  # rom.from_fem builds on fem
