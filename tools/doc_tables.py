"""Tables in ``docs/`` that are a command's own output, pasted by one script.

A study that prints a whole table (a mesh-convergence sequence, a 2D-against-3D comparison)
is quoted in the Markdown as a *generated block*: the command's Markdown output between two
invisible markers::

    <!--table:fe2d_convergence-->

    | order | refine | ... |
    |---|---|---|

    <!--/table-->

:data:`TABLES` names the command of each block. ``python -m tools.doc_tables --update
KEY`` runs it (in a fresh interpreter, from the project root) and stores its output, the date,
the machine and the command in ``docs/tables.json``; ``--fill`` pastes the stored output into
the blocks. ``tests/test_doc_tables.py`` checks that every block is byte for byte the stored
output of a known table and that every table is quoted; the number lint of
``tests/test_docs_numbers.py`` skips the blocks, whose numbers are the command's. Timings in
a generated table are ratios measured in the same run (never bare seconds), as for the
claims of :mod:`tools.doc_numbers`. Most commands are benchmarks (minutes), which the
tests do not rerun; the ``cheap`` ones (seconds, no timings) are rerun and compared. A reader
reruns the command printed above each block.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from tools.doc_numbers import DOC_FILES, ROOT, machine

TABLES_JSON = ROOT / "docs" / "tables.json"
"""Where the stored outputs live (in a source checkout)."""

BLOCK = re.compile(r"<!--table:(?P<key>\w+)-->\n(?P<body>.*?)<!--/table-->", re.S)
"""A generated block: its key and the text between the markers."""


@dataclass(frozen=True)
class Table:
    """One generated table.

    Attributes
    ----------
    key : str
        Name used by the block's marker.
    argv : tuple of str
        Arguments of ``python`` (run from the project root) that print the block's Markdown
        on stdout.
    cheap : bool
        Whether the test suite reruns the command (seconds) and compares its output with
        the stored one; a cheap table prints no timing.
    fence : bool
        Quote the output verbatim in a ``text`` code block (a command's own printout rather
        than Markdown).
    """

    key: str
    argv: tuple[str, ...]
    cheap: bool = False
    fence: bool = False

    @property
    def command(self) -> str:
        """The command a reader runs to see the table (``lusm ...`` for the CLI)."""
        if self.argv[:2] == ("-m", "lusm.cli"):
            return "lusm " + " ".join(self.argv[2:])
        return "python " + " ".join(self.argv)


TABLES: tuple[Table, ...] = (
    Table("fe2d_convergence", ("benchmarks/fem_convergence.py", "--markdown")),
    Table("fe_vs_paper", ("benchmarks/fem_vs_paper.py",), cheap=True),
    Table("tune_40k_2d", ("-m", "lusm.cli", "tune", "--target-frequency", "40e3"),
          cheap=True, fence=True),
    Table("tune_40k_3d", ("-m", "lusm.cli", "tune", "--target-frequency", "40e3",
                          "--model", "3d"), fence=True),
    Table("tune_tip_3d", ("-m", "lusm.cli", "tune", "--geometry",
                          "examples/tip_parametric/stator.toml", "--fix", "length", "--model",
                          "3d"), fence=True),
    Table("sweep_width", ("-m", "lusm.cli", "sweep", "--width-mm", "6:10:0.25", "--out",
                          "out"), cheap=True, fence=True),
    Table("admittance_light", ("-m", "lusm.cli", "admittance", "--zeta", "0.002",
                               "--out", "out"), cheap=True, fence=True),
    Table("admittance_paper", ("-m", "lusm.cli", "admittance", "--geometry",
                               "examples/table2_damping/stator.toml", "--out", "out"),
          cheap=True, fence=True),
    Table("fe_fidelity_uniform", ("benchmarks/fem_fidelity.py", "--gaps-mm", "0.02", "0.1",
                                  "0.25", "0.5", "1", "2", "--meshes", "3x3", "4x4")),
    Table("fe3d_convergence", ("benchmarks/fem3d_convergence.py",)),
    Table("fe_2d_vs_3d_plate", ("benchmarks/fem_2d_vs_3d.py", "--part", "plate")),
    Table("fe_2d_vs_3d_stators", ("benchmarks/fem_2d_vs_3d.py", "--part", "stators")),
    Table("fe_holes_2d_3d", ("benchmarks/fem_holes_2d_3d.py",)),
    Table("steady_work_precision", ("benchmarks/steady_work_precision.py",)),
    Table("fe_peer_sfepy", ("benchmarks/fem_peer_sfepy.py",), fence=True),
    Table("fe_fidelity_graded", ("benchmarks/fem_fidelity.py", "--gaps-mm", "0.5",
                                 "--meshes", "3x3", "--graded", "1", "2", "3")),
    Table("fe3d_narrow_gap", ("benchmarks/fem3d_narrow_gap.py",)),
    Table("fe3d_narrow_gap_base4", ("benchmarks/fem3d_narrow_gap.py", "--gaps-mm", "0.1", "0.02",
                                    "--mesh", "4x4", "--gradings", "1")),
)
"""Every generated table."""


def tables_by_key() -> dict[str, Table]:
    """The tables indexed by key."""
    return {t.key: t for t in TABLES}


def blocks(text: str) -> list[tuple[str, str]]:
    """The ``(key, body)`` of every generated block in ``text``."""
    return [(m.group("key"), m.group("body")) for m in BLOCK.finditer(text)]


def without_blocks(text: str) -> str:
    """``text`` with the bodies of its generated blocks removed (for the number lint)."""
    return BLOCK.sub("", text)


def body(markdown: str) -> str:
    """The block body that quotes ``markdown``: blank lines around it, so that GitHub renders
    the table after the marker."""
    return "\n" + markdown.strip("\n") + "\n\n"


def run(table: Table) -> dict[str, str]:
    """Run the command of ``table`` in an empty temporary folder (so that files it writes,
    named relative to it, never touch the checkout and print the same paths every time) and
    return its stored entry."""
    import tempfile

    env = dict(os.environ, PYTHONPATH=str(ROOT))
    argv = [str(ROOT / a) if a.startswith(("benchmarks/", "examples/")) else a
            for a in table.argv]
    with tempfile.TemporaryDirectory(prefix="lusm-doc-table-") as tmp:
        out = subprocess.run([sys.executable, *argv], cwd=tmp, env=env, text=True,
                             capture_output=True, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"{table.command} failed ({out.returncode}):\n{out.stderr[-2000:]}")
    # a file of the checkout named in the output reads as typed, whatever the checkout's path
    stdout = out.stdout.replace(f"{ROOT}/", "")
    text = f"```text\n{stdout.rstrip()}\n```\n" if table.fence else stdout
    return {"command": table.command, "date": time.strftime("%Y-%m-%d", time.gmtime()),
            "machine": machine(), "markdown": text}


def fill(stored: dict, root: Path = ROOT) -> int:
    """Paste the stored outputs into every block of :data:`DOC_FILES`; return how many
    blocks changed."""
    changed = 0
    for rel in DOC_FILES:
        path = root / rel
        if not path.exists():
            continue
        text = path.read_text()

        def paste(m: re.Match) -> str:
            nonlocal changed
            entry = stored["tables"].get(m.group("key"))
            if entry is None:
                return m.group(0)
            new = f"<!--table:{m.group('key')}-->\n{body(entry['markdown'])}<!--/table-->"
            changed += new != m.group(0)
            return new

        new_text = BLOCK.sub(paste, text)
        if new_text != text:
            path.write_text(new_text)
    return changed


def main(argv: list[str] | None = None) -> int:
    """``python -m tools.doc_tables [--update PATTERN ...] [--fill] [--list]``."""
    ap = argparse.ArgumentParser(prog="python -m tools.doc_tables",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--update", nargs="+", metavar="PATTERN",
                    help="rerun the tables matching these keys or glob patterns and store "
                         "their output in docs/tables.json")
    ap.add_argument("--fill", action="store_true",
                    help="paste the stored outputs into the docs' blocks (no computing)")
    ap.add_argument("--list", action="store_true", help="print each table and its command")
    args = ap.parse_args(argv)
    stored = (json.loads(TABLES_JSON.read_text()) if TABLES_JSON.exists()
              else {"generated_by": "python -m tools.doc_tables", "tables": {}})
    if args.list:
        for t in TABLES:
            entry = stored["tables"].get(t.key, {})
            print(f"{t.key:<24} {entry.get('date', 'never'):<11} {t.command}")
    if args.update:
        keys = [k for k in tables_by_key() if any(fnmatch.fnmatchcase(k, p) for p in args.update)]
        if not keys:
            print(f"doc_tables: error: --update {' '.join(args.update)} matches no table "
                  f"(known: {', '.join(tables_by_key())})")
            return 2
        fresh = {}
        for key in keys:
            print(f"running {tables_by_key()[key].command} ...", flush=True)
            fresh[key] = run(tables_by_key()[key])
        if TABLES_JSON.exists():  # reread: another update may have stored a table meanwhile
            stored = json.loads(TABLES_JSON.read_text())
        stored["tables"].update(fresh)
        stored["tables"] = {k: stored["tables"][k] for k in tables_by_key()
                            if k in stored["tables"]}
        tmp = TABLES_JSON.with_name(TABLES_JSON.name + ".partial")
        tmp.write_text(json.dumps(stored, indent=1) + "\n")
        os.replace(tmp, TABLES_JSON)
        print(f"{len(keys)} table(s) stored in {TABLES_JSON}")
    if args.fill:
        print(f"{fill(stored)} block(s) updated from {TABLES_JSON}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
