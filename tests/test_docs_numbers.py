"""The numbers quoted in the README and docs/ are the ones the code computes today.

Every marked number (``123.4<!--n:key-->``) must round-trip to ``docs/numbers.json`` at its
printed precision; the cheap claims are recomputed here and must match ``numbers.json``; the
README's findings quote no result without a marker.
"""

from __future__ import annotations

import json
import re

import pytest

from tests.conftest import ROOT
from tools.doc_numbers import CLAIMS, DOC_FILES, NUMBERS_JSON, claims_by_key, quotes
from tools.doc_tables import without_blocks

DOC = json.loads(NUMBERS_JSON.read_text())


def test_numbers_json_holds_exactly_the_claims():
    assert set(DOC["numbers"]) == {c.key for c in CLAIMS}
    assert DOC["machine"] and DOC["date"]


def test_every_marked_number_equals_numbers_json_at_its_printed_precision():
    qs = quotes(ROOT)
    assert len(qs) >= 20
    bad = []
    for q in qs:
        entry = DOC["numbers"].get(q.key)
        if entry is None:
            bad.append(f"{q.path}:{q.line}: unknown key {q.key}")
        elif entry["value"] is None or not q.agrees(entry["value"]):
            bad.append(f"{q.path}:{q.line}: {q.text} but {q.key} = {entry['value']!r} "
                       f"(x{q.factor:g}); run python -m tools.doc_numbers --fill")
    assert not bad, "\n".join(bad)


def test_every_claim_is_quoted_somewhere():
    quoted = {q.key for q in quotes(ROOT)}
    assert {c.key for c in CLAIMS} <= quoted


@pytest.mark.parametrize("key", [c.key for c in CLAIMS if c.cheap])
def test_cheap_claims_recompute_to_numbers_json(key):
    claim = claims_by_key()[key]
    stored = DOC["numbers"][key]["value"]
    value = claim.compute()
    assert value == pytest.approx(stored, rel=claim.rel_tol, abs=1e-12), claim.command


UNIT = r"(?:k?Hz|V|m/s|mm/s|µm|mm|N|%|ms|s)(?!\w)"
NUMBER_WITH_UNIT = re.compile(r"(?<![\w.])\d[\d ]*(?:\.\d+)?(?:e-?\d+)?\s?" + UNIT)
COVER = re.compile(r"<!--(?:n:\w+(?:\*[0-9.eE+-]+)?|paper|input)-->")


def _unmarked(text: str) -> list[str]:
    """Numbers with a unit in ``text`` that no marker covers (fenced code blocks and the
    generated tables of :mod:`tools.doc_tables` skipped).

    A paper/input marker covers every number since the previous marker within its own
    paragraph, table row or list item; an n:key marker only the number right before it (whose
    unit follows the marker).
    """
    text = without_blocks(re.sub(r"```.*?```", "", text, flags=re.S))
    unmarked = []
    pos = 0
    for m in COVER.finditer(text):
        chunk = text[pos:m.start()]
        if m.group(0).startswith("<!--n:"):  # the marked number stands before its unit
            unmarked += [n.group(0) for n in NUMBER_WITH_UNIT.finditer(chunk)]
        else:  # an input/paper marker does not reach back past its paragraph, row or item
            cut = max(chunk.rfind(sep) for sep in ("\n\n", "\n|", "\n- ", "\n* "))
            unmarked += [n.group(0) for n in NUMBER_WITH_UNIT.finditer(chunk[:max(cut, 0)])]
        pos = m.end()
    return unmarked + [n.group(0) for n in NUMBER_WITH_UNIT.finditer(text[pos:])]


LINTED = {"README.md": None, "docs/beam.md": None, "docs/designer.md": None,
          "docs/limits.md": None, "docs/distributed.md": None, "docs/fem.md": None,
          "docs/fem3d.md": None,
          "docs/contact.md": re.compile(r"\d+ ?(?:V|N|ms|kHz)|\d(?:\.\d+)?e-\d+ s"),
          "docs/steady.md": re.compile(r"\d+ ?(?:V|N)")}
"""Documents in which every number with a unit is a marked result or marked paper/input, with
the pattern of operating points a document may quote without a marker (docs/contact.md: whole
volts, newtons, milliseconds and kilohertz, and time steps such as ``1e-7 s``; its results in
those units carry decimals and markers; docs/steady.md: whole volts and newtons, its results
in volts marked). Add a file here once its inputs are marked."""


@pytest.mark.parametrize("rel", LINTED)
def test_linted_docs_quote_no_unmarked_number_with_a_unit(rel):
    allowed = LINTED[rel]
    unmarked = [n for n in _unmarked((ROOT / rel).read_text())
                if allowed is None or not allowed.fullmatch(n)]
    assert not unmarked, (rel, unmarked)


def test_no_marker_inside_a_code_span():
    """A marker inside backticks would show as text on GitHub."""
    bad = []
    for rel in DOC_FILES:
        path = ROOT / rel
        if not path.exists():
            continue
        for i, line in enumerate(path.read_text().splitlines(), 1):
            spans = line.split("`")[1:-1:2]
            bad += [f"{rel}:{i}: `{s}`" for s in spans if "<!--" in s]
    assert not bad, "\n".join(bad)


def test_the_lint_sees_an_unmarked_result():
    assert _unmarked("3 mm<!--input-->, 139.1<!--n:k--> V, f = 56 479.5 Hz") == ["56 479.5 Hz"]
