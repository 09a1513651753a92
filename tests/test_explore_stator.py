"""``[study] stator``: a design-space study of a designer's stator file (studies.study,
studies.explore), checked against the single-point commands on the same file."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from studies.dataset import assemble
from studies.study import load_study, study_from_dict
from studies.task import compute_geometry

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TUNED = EXAMPLES / "tuned_60k" / "stator.toml"
MESHED = EXAMPLES / "chamfered" / "stator.toml"


@pytest.mark.parametrize("stator, volts, damping", [
    (TUNED, 140, "zeta_L1 = 0.008333, zeta_B2 = 0.008333 ([damping] Q_m = 60"),
    (MESHED, 300, "zeta_L1 = 0.002167, zeta_B2 = 0.002167 (material pzt8's Q_m = 1000")])
@pytest.mark.slow
def test_a_stator_study_is_the_single_point_commands_on_its_file_bit_for_bit(
        stator, volts, damping, capsys):
    """The file's plate, material, holes, tip, chamfers and its own damping (Q_m = 60, or
    without [damping] its material's with the default mount's, not Table 2's ratios, which
    move the no-load velocity) reach the study: its answers are lusm
    characteristic's and lusm modes' on the same file. A file with its own mesh too: its
    plate's nominal gap (0) had refused every motor output as a short circuit."""
    from lusm.cli import main

    s = study_from_dict({"study": {"stator": str(stator)},
                         "outputs": ["f_B2_short", "no_load_velocity", "stall_force"],
                         "axes": {"voltage": f"{volts} V", "preload": "14 N"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert str(ds["status"].item()) == "ok"
    assert damping in ds.attrs["damping"]
    assert main(["characteristic", "--geometry", str(stator), "--voltage", str(volts),
                 "--preload", "14", "--frequency", "auto", "--loads", "0:0.1:0.1",
                 "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert float(ds["f_drive"].item()) == cli["frequency_Hz"]
    assert float(ds["no_load_velocity"].item()) == cli["no_load_velocity_m_s"]
    assert float(ds["stall_force"].item()) == cli["stall_force_N"]
    assert main(["modes", "--geometry", str(stator), "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)
    assert float(ds["f_B2_short"].item()) == modes["B2"]["f_short_Hz"]
    assert ds.attrs["stator_file"] == str(stator)


@pytest.mark.slow
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
    # nor a comment or a trailing newline (that had made it "another study"), as in the study
    (b / "stator.toml").write_text("# my notes\n" + text + "\n\n")
    assert fingerprint(a) == fingerprint(b)
    (b / "stator.toml").write_text(text.replace("Q_m = 60", "Q_m = 80"))
    assert fingerprint(a) != fingerprint(b)


@pytest.mark.parametrize("doc, words", [
    ({"study": {"stator": str(TUNED)}, "axes": {"material": "pzt8"}},
     "axes.material cannot be combined with study.stator"),
    ({"study": {"stator": str(MESHED)}, "axes": {"width": "7 mm"}},
     "axes.width cannot vary study.stator"),
    ({"study": {"stator": str(TUNED)}, "axes": {"length": ["11 mm", "26 mm"]}},
     "axes.length 11 mm: the 11 x 6.6025 mm plate no longer holds the features"),
    ({"study": {"stator": str(TUNED)}, "axes": {"gap": "5.5 mm"}},
     "axes.gap 5.5 mm: the 25.6938 x 6.6025 mm plate no longer holds the features of "
     f"study.stator {TUNED} ([chamfers] size_mm 0.8 mm must be below"),
    ({"study": {"stator": "no/such/stator.toml"}}, "study.stator stator file not found"),
    ({"study": {"stator": ""}}, "study.stator must name a stator TOML file"),
    ({"study": {"stator": str(EXAMPLES)}}, "study.stator stator file"),
])
def test_what_a_stator_study_cannot_do_is_one_line_naming_the_key(doc, words):
    with pytest.raises(ValueError) as err:
        study_from_dict({"outputs": ["f_L1_short"], **doc})
    assert words in str(err.value) and "\n" not in str(err.value)


def test_the_cli_refuses_a_bad_stator_study_with_exit_2(tmp_path, capsys):
    from lusm.cli import main

    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nstator = "{MESHED}"\n[axes]\nlength = "31 mm"\n')
    assert main(["explore", str(study), "--out", str(tmp_path / "s.nc")]) == 2
    err = capsys.readouterr().err
    assert "axes.length cannot vary study.stator" in err and "Traceback" not in err
    assert not (tmp_path / "s.nc").exists() and not (tmp_path / "s.nc.parts").exists()


@pytest.mark.filterwarnings("ignore::fem.model.GapValidityWarning")  # 0.5 mm gap, 2.5 mm
@pytest.mark.slow
def test_a_stator_with_its_own_mesh_varies_in_thickness_only(tmp_path):
    """Its 2D mesh is not rescaled, but the plane-stress thickness is a number: the plate at
    another thickness is the file with that ``thickness_mm``, and its gap is no number (the
    mesh's tagged electrodes). The file's own thickness giving the file's own modes is the
    bit-for-bit test's case above."""
    import math

    from fem.stator_file import load_stator

    s = study_from_dict({"study": {"stator": str(MESHED)}, "outputs": ["f_L1_short"],
                         "axes": {"thickness": ["2.5 mm"]}})
    assert math.isnan(s.axes["gap"][0])
    for name in ("stator.toml", "chamfered.msh"):
        shutil.copy(MESHED.parent / name, tmp_path / name)
    edited = tmp_path / "stator.toml"
    edited.write_text(edited.read_text().replace("thickness_mm = 3.0", "thickness_mm = 2.5"))
    assert float(compute_geometry(s, 0)["f_L1_short"]) == load_stator(edited).modes().L1.f_short_Hz


def _stator_with(tmp_path, old: str, new: str) -> Path:
    path = tmp_path / "stator.toml"
    path.write_text(TUNED.read_text().replace(old, new))
    return path


def test_a_stators_motor_tables_and_gap_are_checked_before_any_fe_solve(tmp_path, monkeypatch):
    """An invalid set of the file's motor tables with Table 2's other constants, and a gap of
    0 that would short the drive, are refused when the study is read, in the file's keys (they
    failed every plate after its FE solve, and the gap's message named axes.gap)."""
    import fem.modes

    monkeypatch.setattr(fem.modes, "plate_modes", lambda *a, **k: pytest.fail("FE solve"))
    bad = _stator_with(tmp_path, "[damping]", "[friction]\nmu_s = 0.3\n\n[damping]")
    with pytest.raises(ValueError, match=r"study.stator .*\[friction\] mu_s"):
        study_from_dict({"study": {"stator": str(bad)}, "outputs": ["no_load_velocity"]})
    # FE outputs only: the motor tables play no part
    study_from_dict({"study": {"stator": str(bad)}, "outputs": ["f_L1_short"]})
    shorted = _stator_with(tmp_path, "gap_mm = 0.4", "gap_mm = 0")
    with pytest.raises(ValueError, match=r"its \[electrodes\] gap_mm 0 makes the four"):
        study_from_dict({"study": {"stator": str(shorted)}, "outputs": ["stall_force"]})


@pytest.mark.slow
def test_a_stators_mesh_bound_is_estimated_before_it_is_meshed(tmp_path, monkeypatch):
    """A plate whose gmsh mesh is far above the bound is refused from its area and element
    size, without meshing it (a 1000 mm plate at 0.067 mm was meshed for 29 s and 564 MB
    first)."""
    import fem.cell_count

    fine = _stator_with(tmp_path, "[damping]", "[mesh]\nsize_mm = 0.3\n\n[damping]")
    count = fem.cell_count.fe_cell_count

    def only_small(plate, *args, **kwargs):
        if plate.length_m > 0.5:
            pytest.fail("the 1000 mm plate was meshed to count its elements")
        return count(plate, *args, **kwargs)

    monkeypatch.setattr(fem.cell_count, "fe_cell_count", only_small)
    with pytest.raises(ValueError, match=r"needs about \d+ 2D elements, above the limit"):
        study_from_dict({"study": {"stator": str(fine)}, "outputs": ["f_L1_short"],
                         "axes": {"length": ["25.6938 mm", "1000 mm"]}})


def _no_2d_mesh(monkeypatch, own_length_m: float):
    """Fail the test on a 2D planform mesh of any plate but the stator file's own (which
    reading the file meshes, to check it) or on an FE solve; the 1D boundary mesh of
    fem.meshing.parametric.estimated_elements is allowed."""
    import fem.meshing.parametric
    import fem.modes

    made = fem.meshing.parametric._cached_mesh

    def only_the_files(stator):
        if stator.length_m != own_length_m:
            pytest.fail(f"the {stator.length_m * 1e3:g} mm plate's 2D mesh was made")
        return made(stator)

    monkeypatch.setattr(fem.meshing.parametric, "_cached_mesh", only_the_files)
    monkeypatch.setattr(fem.modes, "plate_modes", lambda *a, **k: pytest.fail("FE solve"))


@pytest.mark.parametrize("case", ["above", "far_below", "meshed_over", "meshed_at"])
def test_a_stator_studys_fe_work_bound_meshes_only_where_the_estimate_cannot_decide(
        case, monkeypatch):
    """The study's FE work (its largest plate's elements x its plates) of a stator meshed by
    gmsh is bounded from fem.meshing.parametric.estimated_elements' count, from the boundary alone,
    which is never high but up to ESTIMATE_LOW_FACTOR low: a study whose estimate is above
    the bound is refused, one that far below it accepted, neither meshing a plate; in between
    the largest plate is meshed and its real count decides, to the element x solve (the
    estimate alone had let a study up to 6.5 times over its bound start; review)."""
    from dataclasses import replace

    import studies.study
    from fem.meshing.parametric import ESTIMATE_LOW_FACTOR, estimated_elements, parametric_mesh
    from fem.stator_file import load_stator

    base = load_stator(TUNED).stator
    plates = [replace(base, length_m=v) for v in (20e-3, 30e-3)]
    counts = [estimated_elements(p) for p in plates]
    largest = max(counts)
    real = parametric_mesh(plates[counts.index(largest)]).n_elements
    assert largest <= real <= 1.5 * largest  # never high; 1.5 low at the default size
    bound = {"above": 2 * largest - 1, "far_below": 2 * ESTIMATE_LOW_FACTOR * largest,
             "meshed_over": 2 * real - 1, "meshed_at": 2 * real}[case]
    monkeypatch.setattr(studies.study, "MAX_STUDY_FE_WORK", bound)
    doc = {"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
           "axes": {"length": ["20 mm", "30 mm"]}}
    with monkeypatch.context() as m:
        if case in ("above", "far_below"):
            _no_2d_mesh(m, base.length_m)
        if case == "above":
            with pytest.raises(ValueError, match=rf"2 geometries \(FE solves\) x about "
                               rf"{largest} 2D elements \(the study's largest plate, 30 x "):
                study_from_dict(doc)
        elif case == "meshed_over":
            with pytest.raises(ValueError, match=rf"2 geometries \(FE solves\) x {real} 2D "
                               rf"elements \(the study's largest plate, 30 x "):
                study_from_dict(doc)
        else:
            assert study_from_dict(doc).n_geometries == 2


def test_fe_refine_is_said_unused_for_a_stator_meshed_by_gmsh():
    with pytest.warns(UserWarning, match="solver.fe_refine is unused: study.stator"):
        study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
                         "solver": {"fe_refine": 1}})


def test_a_stator_file_that_cannot_be_opened_is_one_line_with_the_os_reason(
        monkeypatch, capsys):
    """A file the user may not read: the operating system's reason, not Python's
    ``[Errno 13] Permission denied: '...'`` (only reproducible as root by patching)."""
    import fem.small_file
    from lusm.cli import main

    def denied(path, max_bytes):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(fem.small_file, "read_small_text", denied)
    with pytest.raises(ValueError) as err:
        study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"]})
    assert str(err.value) == f"study.stator {TUNED}: Permission denied"
    assert main(["modes", "--geometry", str(TUNED)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"lusm modes: error: --geometry {TUNED}: Permission denied")


@pytest.mark.slow
def test_a_parametric_stators_features_are_axes_of_their_own(tmp_path):
    """``tip_length``, ``tip_width`` and ``chamfer`` vary the file's ``[tip]`` and
    ``[chamfers]``: a plate of the study is the file with that value (the same FE frequencies
    to the bit), and the dataset has the feature's dimension after the plate's."""
    from fem.stator_file import load_stator

    s = study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short", "split"],
                         "axes": {"chamfer": ["0.5 mm", "0.8 mm"], "tip_length": "1.2 mm"}})
    assert s.geometry_axes[-2:] == ("tip_length", "chamfer") and s.n_geometries == 2
    ds = assemble(s, {i: compute_geometry(s, i) for i in range(2)})
    assert ds["split"].dims[-2:] == ("tip_length", "chamfer")
    edited = _stator_with(tmp_path, "size_mm = 0.8", "size_mm = 0.5")
    edited.write_text(edited.read_text().replace("length_mm = 0.8", "length_mm = 1.2"))
    modes = load_stator(edited).modes()
    assert float(ds["f_L1_short"].values.ravel()[0]) == modes.L1.f_short_Hz
    assert float(ds["split"].values.ravel()[0]) == modes.B2.f_short_Hz - modes.L1.f_short_Hz


@pytest.mark.parametrize("doc, words", [
    ({"axes": {"chamfer": "1 mm"}},
     "axes.chamfer varies a parametric stator's feature: it needs study.stator"),
    ({"study": {"stator": str(MESHED)}, "axes": {"tip_length": "1 mm"}},
     "axes.tip_length varies a parametric stator's feature"),
    ({"study": {"stator": str(TUNED)}, "axes": {"tip_width": ["1 mm", "7 mm"]}},
     "axes.tip_width 7 mm: the 25.6938 x 6.6025 mm plate no longer holds the features of "
     f"study.stator {TUNED} ([tip] width_mm 7 mm must be at most the 5.003 mm end face"),
])
def test_a_feature_axis_a_stator_cannot_take_is_one_line(doc, words):
    with pytest.raises(ValueError) as err:
        study_from_dict({"outputs": ["f_L1_short"], **doc})
    assert words in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("name, geometries", [("tuned_60k_length.toml", 5),
                                              ("tuned_60k_tip.toml", 6)])
def test_the_example_stator_studies_read_as_documented(name, geometries):
    """The examples' stator and axes: the file's plate where no axis is named."""
    s = load_study(EXAMPLES / "studies" / name)
    assert s.stator.path.resolve() == TUNED.resolve()
    assert s.axes["width"] == (s.stator.stator.width_m,)
    assert s.n_geometries == geometries


def test_a_range_gives_the_values_a_user_would_type():
    """``start + i * step`` put 25.9 mm at 0.025900000000000003 m, one ulp from a stator
    file's ``length_mm = 25.9``: gmsh meshed that plate anew and its L1 moved by 0.6 Hz
    against the single-point command's. A range's values are its decimals, as typed."""
    from studies.study import parse_quantity

    s = study_from_dict({"outputs": ["f_L1_short"], "axes": {
        "length": {"start": "25.5 mm", "stop": "26.1 mm", "step": "0.2 mm"},
        "width": {"start": "4100 um", "stop": "8300 um", "num": 3}}})
    assert s.axes["length"] == tuple(parse_quantity(f"{v} mm", "length", "x")
                                     for v in ("25.5", "25.7", "25.9", "26.1"))
    assert s.axes["width"] == tuple(parse_quantity(f"{v} um", "length", "x")
                                    for v in ("4100", "6200", "8300"))


def test_the_mesh_bound_takes_the_feature_axes_at_their_largest(monkeypatch):
    """The largest tip and the smallest chamfer of the axes make the largest gmsh mesh (a
    30 mm tip on the axis was meshed at full size where lusm modes refuses that plate)."""
    import fem.meshing.parametric

    seen = []  # the plates whose elements are counted (estimated, for a gmsh planform)
    monkeypatch.setattr(fem.meshing.parametric, "estimated_elements",
                        lambda plate: seen.append(plate) or 1)
    study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
                     "axes": {"tip_length": ["0.4 mm", "2 mm"], "tip_width": ["1 mm", "2 mm"],
                              "chamfer": ["0.5 mm", "0.8 mm"]}})
    assert seen and all((p.tip_length_m, p.tip_width_m, p.chamfer_m) == (2e-3, 2e-3, 0.5e-3)
                        for p in seen)


def test_a_tip_axis_on_a_stator_without_a_tip_needs_both_sizes(tmp_path):
    no_tip = _stator_with(tmp_path, "[tip]\nlength_mm = 0.8\nwidth_mm = 1.6\n", "")
    with pytest.raises(ValueError, match=r"axes.tip_width needs a tip length too: the stator "
                                         r"file .* has no \[tip\]; give axes.tip_length"):
        study_from_dict({"study": {"stator": str(no_tip)}, "outputs": ["f_L1_short"],
                         "axes": {"tip_width": "1 mm"}})
    with pytest.raises(ValueError, match=r"axes.tip_length 30 mm: .* \(\[tip\] length_mm 30 "
                                         r"mm must be at most the plate's length, on a "
                                         r"25.6938 x 6.603 mm plate\)"):
        study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
                         "axes": {"tip_length": "30 mm"}})
    with pytest.raises(ValueError, match=r"axes.chamfer values must be > 0 mm"):
        study_from_dict({"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
                         "axes": {"chamfer": ["0 mm", "0.05 mm"]}})


def test_an_unreadable_mesh_file_is_named_not_its_stator_file(monkeypatch):
    import fem.meshing.mesh_io

    def denied(path, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(fem.meshing.mesh_io, "read_stator_mesh", denied)
    with pytest.raises(ValueError, match=r"chamfered.msh: Permission denied$"):
        study_from_dict({"study": {"stator": str(MESHED)}, "outputs": ["f_L1_short"]})


@pytest.mark.parametrize("doc, words", [
    ({"axes": {"width": ["0.3 mm", "6.6 mm"]}},
     f"study.stator {TUNED}'s [electrodes] gap_mm 0.4 mm must be below every length"),
    ({"axes": {"width": ["6.6025 mm", "100 mm"], "length": ["25.6938 mm", "100 mm"]}},
     "([mesh] size_mm 0.8 mm must lie in [1, 100] mm, 1/100 to 1 of the plate's smaller side, "
     "on a 100 x 100 mm plate)"),
    ({"axes": {"length": {"start": "25 mm", "stop": "25.0000000000000001 mm",
                          "step": "0.00000000000000001 mm"}}},
     "axes.length is finer than a float can tell apart near its start '25 mm'"),
    ({"axes": {"length": {"start": "20 mm", "stop": "40 mm", "num": 1000},
               "width": {"start": "5 mm", "stop": "8 mm", "num": 1000}}},
     "1000000 geometries (FE solves) is above the limit"),
])
def test_a_stator_studys_refusals_say_what_the_user_wrote(doc, words, tmp_path):
    stator = TUNED
    if "size_mm" in words:  # a stator file with its own element size
        stator = _stator_with(tmp_path, "[damping]", "[mesh]\nsize_mm = 0.8\n\n[damping]")
    with pytest.raises(ValueError) as err:
        study_from_dict({"study": {"stator": str(stator)}, "outputs": ["f_L1_short"], **doc})
    assert words in str(err.value), str(err.value)


def test_a_stator_with_a_hole_gets_the_2d_hole_warning_once(tmp_path, monkeypatch, capsys):
    """Said for the study's smallest, thickest plate, before any work (the single-point
    commands say it for their plate); with feature axes too, whose plates the warning does
    not need to build."""
    import studies.explore
    from lusm.cli import main

    def stop(*args, **kwargs):
        raise ValueError("stopped before the study ran")

    monkeypatch.setattr(studies.explore, "explore", stop)
    study = tmp_path / "s.toml"
    study.write_text(f'outputs = ["f_L1_short"]\n[study]\nstator = "{TUNED}"\n[axes]\n'
                     'tip_length = ["0.4 mm", "1.2 mm"]\nthickness = ["2 mm", "2.5 mm"]\n')
    assert main(["explore", str(study), "--out", str(tmp_path / "s.nc")]) == 2
    err = capsys.readouterr().err
    assert err.count("a through hole of 1.2 mm in a 2.5 mm plate") == 1, err
    assert "stopped before the study ran" in err


def test_the_study_bound_does_not_mesh_a_plate_its_task_refuses_as_too_wide(monkeypatch):
    """A corner plate wider than long is refused by its task before any mesh
    (fem.modes.WidePlateError): the study's FE-work bound does not mesh it to count, even
    where its estimate lies in the band the others are meshed in (review)."""
    import fem.meshing.parametric
    import studies.study
    from fem.meshing.parametric import estimated_elements
    from fem.stator_file import load_stator

    base = load_stator(TUNED).stator
    made = fem.meshing.parametric._cached_mesh
    meshed = []

    def record(stator):
        meshed.append((stator.length_m, stator.width_m))
        assert stator.width_m <= stator.overall_length_m, "a plate wider than long was meshed"
        return made(stator)

    monkeypatch.setattr(fem.meshing.parametric, "_cached_mesh", record)
    from dataclasses import replace

    largest = estimated_elements(replace(base, length_m=30e-3, width_m=28e-3))
    # the band where every corner is meshed to count: 4 plates x its estimate, below 6.5 x
    monkeypatch.setattr(studies.study, "MAX_STUDY_FE_WORK", 4 * 2 * largest)
    doc = {"study": {"stator": str(TUNED)}, "outputs": ["f_L1_short"],
           "axes": {"length": ["26 mm", "30 mm"], "width": ["6.6025 mm", "28 mm"]}}
    study_from_dict(doc)
    assert (30e-3, 28e-3) in meshed  # narrower than long: counted
    assert not any(w > length for length, w in meshed)
