"""The generated tables of the docs are the stored output of their commands.

Each ``<!--table:key-->`` block must be byte for byte the output stored in
``docs/tables.json`` by ``python -m tools.doc_tables --update key``, every stored table
must be quoted, and each stored entry must name the command of :data:`TABLES`.
"""

from __future__ import annotations

import json
import math
import re

import pytest

from tests.conftest import ROOT
from tools.doc_numbers import DOC_FILES
from tools.doc_tables import (
    TABLES,
    TABLES_JSON,
    blocks,
    body,
    fill,
    run,
    tables_by_key,
    without_blocks,
)

STORED = json.loads(TABLES_JSON.read_text())


def _all_blocks() -> list[tuple[str, str, str]]:
    return [(rel, key, text) for rel in DOC_FILES if (ROOT / rel).exists()
            for key, text in blocks((ROOT / rel).read_text())]


def test_every_block_is_the_stored_output_of_a_known_table():
    bad = []
    for rel, key, text in _all_blocks():
        entry = STORED["tables"].get(key)
        if key not in tables_by_key() or entry is None:
            bad.append(f"{rel}: unknown table {key}")
        elif text != body(entry["markdown"]):
            bad.append(f"{rel}: block {key} differs from docs/tables.json; run "
                       "python -m tools.doc_tables --fill")
    assert not bad, "\n".join(bad)


def test_every_table_is_stored_with_its_command_and_quoted():
    quoted = {key for _, key, _ in _all_blocks()}
    assert set(STORED["tables"]) == set(tables_by_key()) == quoted
    for key, entry in STORED["tables"].items():
        assert entry["command"] == tables_by_key()[key].command
        assert entry["machine"] and entry["date"]


def test_fill_rewrites_a_stale_block_and_lint_skips_blocks(tmp_path):
    key = next(iter(STORED["tables"]))
    stale = f"before 3 mm\n<!--table:{key}-->\n\n| old | 1 Hz |\n\n<!--/table-->\nafter\n"
    (tmp_path / "README.md").write_text(stale)
    assert fill(STORED, tmp_path) == 1
    text = (tmp_path / "README.md").read_text()
    assert blocks(text) == [(key, body(STORED["tables"][key]["markdown"]))]
    assert fill(STORED, tmp_path) == 0
    assert "1 Hz" not in without_blocks(stale) and "3 mm" in without_blocks(stale)


@pytest.mark.parametrize("key", sorted(STORED["tables"]))
def test_generated_tables_print_no_bare_seconds(key):
    """Timings in a generated table are ratios measured in the same run."""
    assert " (s) |" not in STORED["tables"][key]["markdown"]


NUMBER = re.compile(r"[+\-−]?\d+(?:\.\d+)?(?:e[+\-−]?\d+)?")


def _same_output(a: str, b: str, rel: float = 1e-5, abs_: float = 1e-8) -> bool:
    """Equal text, and numbers equal to ``rel`` (printed roundings and round-off residuals
    such as a 1e-12 mismatch may differ between machines and BLAS builds)."""
    if NUMBER.split(a) != NUMBER.split(b):
        return False
    na, nb = NUMBER.findall(a), NUMBER.findall(b)
    return len(na) == len(nb) and all(
        x == y or math.isclose(float(x.replace("−", "-")), float(y.replace("−", "-")),
                               rel_tol=rel, abs_tol=abs_) for x, y in zip(na, nb, strict=True))


HEAVY_TABLES = {"tune_40k_2d", "sweep_width"}
"""Cheap tables that still take a tune or a sweep of their own: rerun in the benchmark
lane."""


@pytest.mark.parametrize("key", [
    pytest.param(t.key, marks=pytest.mark.benchmark) if t.key in HEAVY_TABLES else t.key
    for t in TABLES if t.cheap])
@pytest.mark.slow
def test_cheap_tables_rerun_to_the_stored_output(key):
    fresh = run(tables_by_key()[key])["markdown"]
    assert _same_output(fresh, STORED["tables"][key]["markdown"]), fresh
