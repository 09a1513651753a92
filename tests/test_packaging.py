"""The base install: every module of the installed packages imports without an optional
extra, and the README's first command needs no extra."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))

# Imports every module of the given packages with the given top-level modules made
# unimportable (a meta-path finder that refuses them), and prints the modules imported.
_IMPORT_ALL = """
import importlib, importlib.abc, pkgutil, sys
blocked = set(sys.argv[1].split(","))
class Refuse(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in blocked:
            raise ImportError(f"{name} is an optional extra, not in the base install")
sys.meta_path.insert(0, Refuse())
count = 0
for package in sys.argv[2].split(","):
    importlib.import_module(package)
    for info in pkgutil.walk_packages(sys.modules[package].__path__, package + "."):
        if info.name.endswith(".__main__"):  # runs the command when imported
            continue
        importlib.import_module(info.name)
        count += 1
print(count)
"""


def _name(requirement: str) -> str:
    """The distribution name of a requirement (``"gmsh>=4.11"`` -> ``"gmsh"``)."""
    return re.split(r"[\s\[<>=!~;]", requirement, maxsplit=1)[0].lower().replace("-", "_")


def _extras_modules() -> set[str]:
    """Top-level module names of every optional extra's requirements."""
    extras = PYPROJECT["project"]["optional-dependencies"].values()
    return {_name(req) for reqs in extras for req in reqs}


def test_every_module_imports_without_the_extras():
    packages = PYPROJECT["tool"]["setuptools"]["packages"]
    blocked = _extras_modules()
    assert {"pytest", "hypothesis"} <= blocked  # the test extra is among them
    out = subprocess.run([sys.executable, "-c", _IMPORT_ALL, ",".join(sorted(blocked)),
                          ",".join(packages)],
                         capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    assert int(out.stdout.split()[-1]) > 50  # the walk found the modules


def test_the_readme_first_command_is_a_base_install():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    quick = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    first, tests = re.findall(r"```bash\n(.*?)\n```", quick, re.S)[:2]
    assert first.startswith("pip install -e . &&")  # no extra in brackets
    assert "lusm report" in first and "pytest" in tests
    # gmsh meshes the parametric example stators the report loads: a core dependency
    assert "gmsh" in {_name(r) for r in PYPROJECT["project"]["dependencies"]}
