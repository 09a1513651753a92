"""``lusm report --quick``: every section, valid figures, >= 12 hard cases, one source of truth."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import ROOT
from validation.report import SECTIONS


def _not_json(name: str):
    raise AssertionError(f"report.json holds {name}, which is not JSON")


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> tuple[Path, dict]:
    """The quick report, made once through the command's entry point in this process (the
    commands it is compared with below then share its cached FE solves)."""
    from lusm.cli import main

    out = tmp_path_factory.mktemp("report")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(ROOT)  # where the README runs it: the report cites the examples from here
        assert main(["report", "--quick", "--no-progress", "--out", str(out)]) == 0
    # strict JSON: a bare NaN (Python's default) is refused by every other reader
    return out, json.loads((out / "report.json").read_text(), parse_constant=_not_json)


@pytest.mark.slow
@pytest.mark.benchmark
def test_every_section_is_present(report):
    out, doc = report
    for s in SECTIONS:
        assert doc[s], s
    md = (out / "index.md").read_text()
    for heading in ("## 1. Parameter sets", "## 2. Paper reproduction",
                    "## 3. Speed against error", "## 4. Hard cases",
                    "## 5. Motor characteristics"):
        assert heading in md
    html = (out / "index.html").read_text()
    n_tables = sum(1 for ln in md.splitlines() if ln.startswith("|---|"))
    assert html.count("<table>") == n_tables > 0 and "<img" in html
    assert set(doc["paper_reproduction"]) == {"table2", "beam", "fem"}


@pytest.mark.slow
@pytest.mark.benchmark
def test_every_figure_is_a_valid_non_blank_png(report):
    from matplotlib.image import imread

    out, _ = report
    md = (out / "index.md").read_text()
    pngs = sorted((out / "figures").glob("*.png"))
    assert len(pngs) >= 3 * 14 + 2
    for png in pngs:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        img = imread(png)
        assert float(np.std(img[..., :3])) > 0.01, png.name
        assert f"figures/{png.name}" in md  # every figure is shown


@pytest.mark.slow
@pytest.mark.benchmark
def test_hard_cases_are_stable_or_fail_clearly_and_conserve_energy(report):
    _, doc = report
    rows = doc["hard_cases"]
    assert len(rows) >= 12
    for r in rows:
        if r["expected_error"]:
            assert r["status"].startswith("error: ")
            continue
        assert r["status"] == "stable", (r["name"], r["status"])
        assert math.isfinite(r["velocity_m_s"])
        if r["energy_residual"] is not None:  # null only without input work (0 V)
            assert r["energy_residual"] < 0.01, r["name"]


@pytest.mark.slow
@pytest.mark.benchmark
def test_report_numbers_match_the_cli(report, capsys, monkeypatch):
    from lusm.cli import main

    _, doc = report
    monkeypatch.chdir(ROOT)  # the report cites the example stators by relative path

    def lusm(*args):
        capsys.readouterr()
        assert main([*args, "--json"]) == 0
        return json.loads(capsys.readouterr().out)

    modes = lusm("modes")
    fe = doc["parameter_sets"]["fe_modes"]
    for m in ("L1", "B2"):
        assert fe[m]["f_short_Hz"] == modes[m]["f_short_Hz"]
        assert fe[m]["k_eff"] == modes[m]["k_eff"]
    case = doc["paper_reproduction"]["table2"]["numbers"]["cases"]["200V_18N"]
    sim = lusm("simulate", "--voltage", "200", "--preload", "18", "--duration", "0.01")
    assert case["velocity_m_s"] == sim["steady_velocity_m_s"]
    assert case["motion"] == sim["motion"]
    assert doc["parameter_sets"]["comparison"]["values"]["fem"]["f_L1_Hz"] == pytest.approx(
        modes["L1"]["f_short_Hz"], rel=1e-12)
    # the report's characteristics are the command's default, the exact level (they were the
    # averaged one: the FE set's stall force at 400 V 0.476 N against the motor's 1.014 N)
    char = lusm("characteristic", "--voltage", "400", "--preload", "14")
    rep = doc["motor_characteristics"]["table2"]["characteristics"]["400"]
    assert rep["stall_force_N"] == char["stall_force_N"] and rep["accuracy"] == "exact"
    assert rep["no_load_velocity_m_s"] == char["no_load_velocity_m_s"]
    # where the creep begins, as the command says it (the report's table had only the stall)
    assert rep["averaged_stall_force_N"] == char["averaged_stall_force_N"]
    assert 0.0 < rep["averaged_stall_force_N"] < rep["stall_force_N"]
    fe_char = lusm("characteristic", "--voltage", "400", "--preload", "14", "--source", "fem",
                   "--frequency", "auto", "--damping", "table2")
    rep = doc["motor_characteristics"]["fem"]["characteristics"]["400"]
    assert rep["stall_force_N"] == fe_char["stall_force_N"]
    # each set's subsection cites the options that name it (the section had cited one
    # `lusm characteristic --frequency F` for all, which runs Table 2's set)
    md = (report[0] / "index.md").read_text()
    cited = re.findall(r"`lusm characteristic([^`]*) --voltage V0 --preload 14`", md)
    assert cited == ["", " --source beam --frequency auto --damping table2",
                     " --source fem --frequency auto --damping table2",
                     " --geometry examples/tuned_40k/stator.toml --frequency auto",
                     " --geometry examples/tuned_40k/identified.toml --frequency auto"]
    for name, toml in (("tuned_40k", "stator"), ("tuned_40k_fitted", "identified")):
        tuned = lusm("characteristic", "--voltage", "400", "--preload", "14", "--frequency",
                     "auto", "--geometry", f"examples/tuned_40k/{toml}.toml")
        rep = doc["motor_characteristics"][name]["characteristics"]["400"]
        assert rep["stall_force_N"] == tuned["stall_force_N"]
        assert rep["no_load_velocity_m_s"] == tuned["no_load_velocity_m_s"]
    modes3d = lusm("modes", "--model", "3d", "--quick")
    f3d = doc["parameter_sets"]["plane_stress_vs_3d"]["f3d_Hz"]
    assert f3d["B2_open"] == pytest.approx(modes3d["B2"]["f_open_Hz"], rel=1e-9)


def test_a_failed_report_leaves_nothing_half_written(tmp_path, monkeypatch):
    from lusm.cli import main
    from lusm.output_set import output_set
    from validation import report as rep

    out = tmp_path / "r"
    with output_set(out) as stage:  # an earlier report, marked as lusm's
        (stage / "index.md").write_text("earlier report")

    def boom(out_dir, quick, progress):
        (out_dir / "figures" / "half.png").write_bytes(b"partial")
        raise RuntimeError("interrupted")

    monkeypatch.setattr(rep, "_parameter_sets", boom)
    assert main(["report", "--quick", "--no-progress", "--out", str(out)]) == 1  # a bug's exit
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r"]  # no partial folder left
    assert (out / "index.md").read_text() == "earlier report"
    assert not (out / "figures").exists()


def test_a_report_names_a_path_that_is_not_utf8(tmp_path):
    """A stator file whose name is not UTF-8 (Latin-1 bytes, decoded by Python with
    surrogate escapes) failed the whole report at its very end, when index.md was written:
    the files are written with the name's bytes escaped, and the JSON stays valid."""
    import json
    import os

    from validation.report import write_report_files

    name = os.fsdecode(b"/x/st\xfe.toml")
    write_report_files(tmp_path, f"# r\n\n`{name}`\n", {"geometry": name}, "r")
    assert "st\\udcfe.toml" in (tmp_path / "index.md").read_text(encoding="utf-8")
    assert json.loads((tmp_path / "report.json").read_text())["geometry"] == name
    assert "st\\udcfe.toml" in (tmp_path / "index.html").read_text(encoding="utf-8")


def test_report_figures_take_the_column_width_and_link_to_their_png():
    """The HTML page drew every figure at under half its column (max-width 48 %), its labels
    too small to read: a figure takes the column's width and links to its PNG."""
    from validation.report_html import to_html

    page = to_html("![speed-thrust](figures/a.png)\n", "t")
    assert '<a href="figures/a.png"><img src="figures/a.png"' in page
    assert "max-width:100%" in page and "48%" not in page
