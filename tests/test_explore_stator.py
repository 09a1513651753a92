"""``[study] stator``: a design-space study of a designer's stator file (validation.study,
validation.explore), checked against the single-point commands on the same file."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from validation.explore import assemble, compute_geometry
from validation.study import load_study, study_from_dict

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TUNED = EXAMPLES / "tuned_60k" / "stator.toml"
MESHED = EXAMPLES / "chamfered" / "stator.toml"


def test_a_stator_study_is_the_single_point_commands_on_its_file_bit_for_bit(capsys):
    """The file's plate, material, holes, tip, chamfers and its own damping (Q_m = 60, not
    Table 2's ratios, which move the no-load velocity) reach the study: its answers are lusm
    characteristic's and lusm modes' on the same file."""
    from validation.cli import main

    s = study_from_dict({"study": {"stator": str(TUNED)},
                         "outputs": ["f_B2_short", "no_load_velocity", "stall_force"],
                         "axes": {"voltage": "140 V", "preload": "14 N"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert str(ds["status"].item()) == "ok"
    assert main(["characteristic", "--geometry", str(TUNED), "--voltage", "140", "--preload",
                 "14", "--frequency", "auto", "--loads", "0:0.1:0.1", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert float(ds["f_drive"].item()) == cli["frequency_Hz"]
    assert float(ds["no_load_velocity"].item()) == cli["no_load_velocity_m_s"]
    assert float(ds["stall_force"].item()) == cli["stall_force_N"]
    assert main(["modes", "--geometry", str(TUNED), "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)
    assert float(ds["f_B2_short"].item()) == modes["B2"]["f_short_Hz"]
    assert "Q_m = 60" in ds.attrs["parameter_set_source"]
    assert ds.attrs["stator_file"] == str(TUNED)


def test_a_varied_dimension_is_the_stator_file_with_that_dimension(tmp_path):
    """A length on the study's axis gives the plate the file would give with that
    ``length_mm``: its tip, chamfers and hole are kept (the same FE frequencies to the bit)."""
    from fem.stator_file import load_stator

    s = study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short", "split"],
                         "axes": {"length": ["24 mm", "27 mm"]}})
    edited = tmp_path / "stator.toml"
    edited.write_text(TUNED.read_text().replace("length_mm = 25.6938", "length_mm = 27"))
    modes = load_stator(edited).modes()
    part = compute_geometry(s, 1)
    assert float(part["f_L1_short"]) == modes.L1.f_short_Hz
    assert float(part["split"]) == modes.B2.f_short_Hz - modes.L1.f_short_Hz
    # the axes not named are the file's plate, exactly
    assert s.axes["width"] == (load_stator(TUNED).stator.width_m,)
    assert s.axes["material"] == ("paper",)


def test_the_stator_path_is_taken_from_the_study_files_folder(tmp_path):
    (tmp_path / "designs").mkdir()
    shutil.copy(TUNED, tmp_path / "designs" / "mine.toml")
    study = tmp_path / "study.toml"
    study.write_text('outputs = ["f_L1_short"]\n[study]\nstator = "designs/mine.toml"\n')
    s = load_study(study)
    assert s.stator.name == "a designer's tuned 60 kHz stator"


def test_resume_sees_a_changed_stator_file_not_a_moved_one(tmp_path):
    """The fingerprint holds the file's contents: an edited stator makes another study, the
    same file elsewhere does not."""
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    shutil.copy(TUNED, a / "stator.toml")
    shutil.copy(TUNED, b / "stator.toml")

    def fingerprint(folder):
        return study_from_dict({"study": {"stator": str(folder / "stator.toml")},
                                "outputs": ["f_L1_short"]}).fingerprint

    assert fingerprint(a) == fingerprint(b)
    text = (b / "stator.toml").read_text()
    (b / "stator.toml").write_text(text.replace("Q_m = 60", "Q_m = 80"))
    assert fingerprint(a) != fingerprint(b)


@pytest.mark.parametrize("doc, words", [
    ({"study": {"stator": str(TUNED)}, "axes": {"material": "pzt8"}},
     "axes.material cannot be combined with study.stator"),
    ({"study": {"stator": str(MESHED)}, "axes": {"width": "7 mm"}},
     "axes.width cannot vary study.stator"),
    ({"study": {"stator": str(TUNED)}, "axes": {"length": ["11 mm", "26 mm"]}},
     "the 11 x 6.6025 mm plate with a 0.4 mm gap no longer holds the features"),
    ({"study": {"stator": "no/such/stator.toml"}}, "study.stator stator file not found"),
    ({"study": {"stator": ""}}, "study.stator must name a stator TOML file"),
    ({"study": {"stator": str(EXAMPLES)}}, "study.stator stator file"),
])
def test_what_a_stator_study_cannot_do_is_one_line_naming_the_key(doc, words):
    with pytest.raises(ValueError) as err:
        study_from_dict({"outputs": ["f_L1_short"], **doc})
    assert words in str(err.value) and "\n" not in str(err.value)


def test_the_cli_refuses_a_bad_stator_study_with_exit_2(tmp_path, capsys):
    from validation.cli import main

    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nstator = "{MESHED}"\n[axes]\nlength = "31 mm"\n')
    assert main(["explore", str(study), "--out", str(tmp_path / "s.nc")]) == 2
    err = capsys.readouterr().err
    assert "axes.length cannot vary study.stator" in err and "Traceback" not in err
    assert not (tmp_path / "s.nc").exists() and not (tmp_path / "s.nc.parts").exists()
