"""``lusm tune --write``: the tuned stator file, its round trip and its refusals."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from fem.stator_file import load_stator, tuned_stator_text
from lusm.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _json(capsys) -> dict:
    return json.loads(capsys.readouterr().out)


@pytest.mark.slow
def test_the_written_file_has_l1_on_b2_and_tunes_to_the_same_plate(tmp_path, capsys):
    out = tmp_path / "tuned.toml"
    assert main(["tune", "--fix", "length", "--length-mm", "35", "--refine", "2", "--json",
                 "--write", str(out)]) == 0
    tuned = _json(capsys)
    assert tuned["written"] == str(out)
    text = out.read_text()
    assert text.startswith("# Tuned by: lusm tune --fix length --length-mm 35")
    assert "|f_L1 - f_B2| / f =" in text
    design = load_stator(out)
    assert design.stator.length_m == pytest.approx(35e-3, rel=1e-12)
    assert design.stator.width_m * 1e3 == pytest.approx(tuned["width_mm"], rel=1e-11)
    # lusm modes on the written file: L1 on B2, as the tuning left them
    assert main(["modes", "--geometry", str(out), "--refine", "2", "--json"]) == 0
    modes = _json(capsys)
    assert abs(modes["split_rel"]) < 1e-6
    # tuned again from the written file: the same plate, at once
    assert main(["tune", "--fix", "length", "--geometry", str(out), "--refine", "2",
                 "--json"]) == 0
    again = _json(capsys)
    assert again["width_mm"] == pytest.approx(tuned["width_mm"], rel=1e-6)


@pytest.mark.slow
def test_write_refuses_an_existing_file_and_keeps_it_with_force(tmp_path, capsys):
    out = tmp_path / "tuned.toml"
    out.write_text("mine")
    args = ["tune", "--fix", "length", "--length-mm", "35", "--refine", "2",
            "--write", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "--write" in err and "already exists" in err and "--force" in err
    assert out.read_text() == "mine"
    assert main([*args, "--force"]) == 0
    assert (tmp_path / "tuned.toml.bak-1").read_text() == "mine"
    assert load_stator(out).stator.length_m == pytest.approx(35e-3)


def test_the_users_file_keeps_its_comments_tables_and_features():
    src = (EXAMPLES / "tip_parametric" / "stator.toml").read_text()
    text = tuned_stator_text({"length_mm": 31.5, "width_mm": 8.25, "thickness_mm": 3.0},
                             "Tuned by: lusm tune\nsecond line", source_text=src)
    assert text.startswith("# Tuned by: lusm tune\n# second line\n")
    assert "length_mm = 31.5 # tuned (was 30)" in text
    assert "width_mm = 8.25 # tuned (was 7.5)" in text
    assert "thickness_mm = 3.0\n" in text  # unchanged: no comment
    for kept in ("[tip]", "# beyond the plate's end y = 30 mm", "[points]", "[mesh]",
                 'name = "plate with a parametric contact tip"'):
        assert kept in text
    body = text.split("\n\n", 1)[1]
    assert body.replace("31.5 # tuned (was 30)", "30.0        # the plate body; the tip is "
                        "added beyond it").replace("8.25 # tuned (was 7.5)", "7.5") == src


@pytest.mark.slow
def test_tune_writes_a_parametric_stator_file(tmp_path, capsys):
    src = tmp_path / "stator.toml"
    shutil.copy(EXAMPLES / "tip_parametric" / "stator.toml", src)
    out = tmp_path / "tuned.toml"
    assert main(["tune", "--fix", "length", "--geometry", str(src), "--write", str(out),
                 "--json"]) == 0
    tuned = _json(capsys)
    design = load_stator(out)
    assert design.stator.tip_length_m == pytest.approx(1e-3)
    assert design.stator.width_m * 1e3 == pytest.approx(tuned["width_mm"], rel=1e-11)
    assert main(["modes", "--geometry", str(out), "--json"]) == 0
    assert abs(_json(capsys)["split_rel"]) < 1e-6
