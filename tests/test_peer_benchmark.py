"""The SfePy peer check (benchmarks/fem_peer_sfepy.py) stays an optional extra.

The benchmark must import without SfePy (SfePy is imported inside its functions only), and
without SfePy its ``main`` stops with a one-line hint instead of a traceback. Its own pieces
that need no SfePy are checked against what they must be: electrode node sets follow the
plate's quadrants, and at gap 0 the touching quadrants form one conductor.
"""

from __future__ import annotations

import ast
import importlib.util
import subprocess
import sys

import numpy as np
import pytest

from tests.conftest import ROOT

BENCH = ROOT / "benchmarks" / "fem_peer_sfepy.py"


def test_sfepy_is_imported_inside_functions_only():
    tree = ast.parse(BENCH.read_text())
    top = []
    for node in tree.body:
        if isinstance(node, ast.Import):
            top += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            top.append(node.module)
    assert top, "the scan found no module-level import (vacuous)"
    assert not [m for m in top if m.split(".")[0] == "sfepy"]


@pytest.mark.slow
def test_benchmark_imports_and_explains_itself_without_sfepy():
    code = (
        "import sys; sys.modules['sfepy'] = None; sys.path.insert(0, 'benchmarks');"
        "import fem_peer_sfepy as b; b.main([])"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 1, out.stdout + out.stderr
    assert "pip install" in out.stdout and "Traceback" not in out.stderr


def _bench():
    spec = importlib.util.spec_from_file_location("fem_peer_sfepy", BENCH)
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(spec.name, module)  # dataclasses look their module up there
    spec.loader.exec_module(sys.modules[spec.name])
    return sys.modules[spec.name]


def test_electrode_sets_follow_the_quadrants():
    from fem.geometry import PlateStator

    bench = _bench()
    electrode_nodes, plate_lines = bench.electrode_nodes, bench.plate_lines

    for gap in (0.0, 0.5e-3):
        st = PlateStator(electrode_gap_m=gap)
        x, y, z = plate_lines(st, 3, 2, levels=1)
        X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
        coor = np.column_stack((X.ravel(), Y.ravel(), Z.ravel()))
        bottom, conductors = electrode_nodes(st, coor)
        top = np.flatnonzero(np.isclose(coor[:, 2], st.thickness_m / 2))
        assert np.allclose(coor[bottom, 2], -st.thickness_m / 2)
        assert bottom.size == top.size
        if gap == 0.0:
            assert len(conductors) == 1 and conductors[0].size == top.size
            continue
        assert len(conductors) == 4
        joined = np.concatenate(conductors)
        assert np.unique(joined).size == joined.size  # disjoint
        for k, nodes in zip((1, 2, 3, 4), conductors, strict=True):
            xs, ys = coor[nodes, 0], coor[nodes, 1]
            assert nodes.size > 0
            assert np.all((xs >= gap / 2 - 1e-12) if k in (1, 2) else (xs <= -gap / 2 + 1e-12))
            half = st.length_m / 2
            assert np.all((ys <= half - gap / 2 + 1e-12) if k in (1, 3)
                          else (ys >= half + gap / 2 - 1e-12))
        # the gap strips carry top nodes that belong to no electrode
        assert joined.size < top.size


def test_report_quotes_the_peer_summary_of_the_docs(tmp_path):
    """The report's 2D-vs-3D section quotes docs/fem3d.md's block without running SfePy, and
    quotes nothing when the block (or the file) is missing."""
    from validation.report import PEER_END, PEER_START, peer_check_summary

    lines = peer_check_summary()
    doc = (ROOT / "docs" / "fem3d.md").read_text(encoding="utf-8")
    block = doc[doc.index(PEER_START) + len(PEER_START):doc.index(PEER_END)]
    quoted = block.replace("<!--input-->", "").strip("\n").splitlines()
    # the block at the end, without the docs' number markers (the HTML showed four of them)
    assert quoted and lines[-len(quoted):] == quoted and "<!--" not in "".join(lines)
    assert "<!--input-->" in block
    assert any("benchmarks/fem_peer_sfepy.py" in ln for ln in lines)
    plain = tmp_path / "fem3d.md"
    plain.write_text("# no summary here\n", encoding="utf-8")
    assert peer_check_summary(plain) == []
    assert peer_check_summary(tmp_path / "missing.md") == []
