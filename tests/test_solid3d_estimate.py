"""The default 3D answer (fem.solid3d.estimate): two graded meshes, the fine one's numbers,
each with its estimated discretisation error (docs/fem3d.md section 1.1)."""

import json

import pytest

from fem.geometry import PlateStator
from fem.mesh_settings import MeshSettings
from fem.solid3d.estimate import MeshLevel, estimated_solid_modes

QUANTITIES = ("f_short_Hz", "f_open_Hz", "k_eff")
TINY = (MeshLevel(1, 1, 1), MeshLevel(2, 1, 1))
"""A pair small enough for the CLI tests (seconds); the default's numbers are measured in the
docs."""


@pytest.mark.slow
@pytest.mark.benchmark
def test_the_estimate_brackets_the_error_against_a_finer_mesh():
    """On the paper's plate, the pair refine 2 / 3, layers 1, grading 1 / 2 (the default
    family one step coarser) against refine 4, layers 2, grading 3: every estimated error
    of the fine mesh is at least its difference from the finer mesh, and none is more than
    a hundred times it where that difference is above the reference's own 1e-5."""
    from fem.solid3d.symmetric import symmetric_solid_modes

    est = estimated_solid_modes(PlateStator(), meshes=(MeshLevel(2, 1, 1), MeshLevel(3, 1, 2)))
    ref = symmetric_solid_modes(PlateStator(), "pzt8", MeshSettings(2, 4, 2, edge_grading=3))
    for mode in ("L1", "B2"):
        for q in QUANTITIES:
            fine, truth = (getattr(getattr(r, mode), q) for r in (est.fine, ref))
            estimated = est.error(mode, q)
            assert abs(fine - truth) <= estimated, (mode, q)
            if abs(fine / truth - 1.0) > 1e-5:
                assert estimated < 100 * abs(fine - truth), (mode, q)


def test_the_estimate_is_the_change_between_the_meshes_times_the_safety():
    from fem.solid3d.estimate import SAFETY

    est = estimated_solid_modes(PlateStator(), meshes=TINY)
    assert est.quarter and est.meshes == TINY
    errors = est.errors()
    for mode in ("L1", "B2"):
        for q in QUANTITIES:
            change = getattr(getattr(est.fine, mode), q) - getattr(getattr(est.coarse, mode), q)
            assert errors[mode][q] == pytest.approx(SAFETY * abs(change), rel=1e-12)
    assert est.fine.refine == 2 and est.coarse.refine == 1


def test_modes_3d_prints_each_number_with_its_estimate(monkeypatch, capsys):
    """`lusm modes --model 3d` without mesh options: the fine mesh's numbers, each with
    +- its estimate, in the text and in the JSON (error_estimate); --quick and --refine
    give one mesh and no estimate, and --quick with the 2D model is refused."""
    from fem.solid3d import estimate
    from lusm.cli import main

    monkeypatch.setattr(estimate, "DEFAULT_MESHES", TINY)
    assert main(["modes", "--model", "3d", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    est = estimated_solid_modes(PlateStator(), meshes=TINY)
    assert out["B2"]["k_eff"] == est.fine.B2.k_eff
    assert out["error_estimate"]["B2"]["k_eff"] == pytest.approx(est.error("B2", "k_eff"))
    assert out["error_estimate"]["coarse_mesh"] == {"refine": 1, "layers": 1,
                                                    "edge_grading": 1}
    assert out["quarter_model"] and out["edge_grading"] == 1 and out["refine"] == 2
    assert main(["modes", "--model", "3d"]) == 0
    text = capsys.readouterr().out
    row = next(line for line in text.splitlines() if line.startswith("B2 "))
    assert row.count("+-") == 3 and "estimated discretisation error" in text
    assert main(["modes", "--model", "3d", "--quick", "--refine", "2", "--layers", "1",
                 "--json"]) == 0
    assert "error_estimate" not in json.loads(capsys.readouterr().out)
    assert main(["modes", "--quick"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--quick applies to --model 3d only" in err
    assert main(["modes", "--model", "3d", "--quick", "--edge-grading", "1"]) == 2
    assert "--quick" in capsys.readouterr().err


def designer_toml(width_mm: float, mesh: str = "") -> str:
    """The designer's stator of issue 38 (35 x 8 x 3 mm PZT-8 with a 2 x 1 mm tip,
    ``tools.doc_numbers.BAND_DESIGNER_TOML``) at ``width_mm`` (9.532 mm once tuned with
    `lusm tune --fix length`), with ``mesh`` appended."""
    from tools.doc_numbers import BAND_DESIGNER_TOML

    return BAND_DESIGNER_TOML.replace("width_mm = 8.0", f"width_mm = {width_mm}", 1) + mesh


@pytest.mark.slow
@pytest.mark.benchmark
def test_3d_tune_agrees_with_modes_3d_on_the_tuned_plate(monkeypatch, capsys):
    """`tune_plate(model='3d')` starts from the 2D tuning and takes a few 3D solves on the
    fine mesh of `lusm modes --model 3d`'s default; that command on the tuned plate gives
    the tuning's frequencies (tiny meshes here: the default's are measured in the docs)."""
    from fem.solid3d import estimate
    from fem.tuning import tune_plate
    from lusm.cli import main

    monkeypatch.setattr(estimate, "DEFAULT_MESHES", TINY)
    d = tune_plate(fix="length", start=PlateStator(length_m=35e-3, width_m=9.5e-3), model="3d")
    assert d.relative_mismatch < 1e-5 and 1 <= d.solves_3d <= 4
    assert d.fe_solves > d.solves_3d  # the 2D tuning's solves come first
    assert main(["modes", "--model", "3d", "--length-mm", "35", "--width-mm",
                 repr(d.stator.width_m * 1e3), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for name, mode in (("L1", d.L1), ("B2", d.B2)):
        for q in QUANTITIES:
            assert out[name][q] == pytest.approx(getattr(mode, q), rel=1e-9), (name, q)


def test_the_designers_stator_runs_in_3d_at_the_default_bound(tmp_path, capsys):
    """Issue 38: `lusm tune --fix length --model 3d` on the designer's stator was refused at
    the default bound (15 solves x 1 572 bricks); its default 3D meshes and a 3D tuning's
    solves now fit, and a stator file meshed 4 times finer is refused in one line naming
    --geometry and its [mesh] size_mm, before any solve."""
    from lusm.cli import build_parser
    from lusm.commands import tune
    from lusm.commands.modes import _mesh_settings
    from lusm.options import stator_from_args

    path = tmp_path / "stator.toml"
    path.write_text(designer_toml(8.0))
    parser = build_parser()
    args = parser.parse_args(["tune", "--geometry", str(path), "--fix", "length", "--model",
                              "3d"])
    tune._start_plate(args)  # the bounds pass
    path.write_text(designer_toml(9.532))
    args = parser.parse_args(["modes", "--geometry", str(path), "--model", "3d"])
    mesh = _mesh_settings(args, stator_from_args(args).stator, True)
    assert mesh.coarse is not None and mesh.edge_grading == 1
    from lusm.cli import main

    path.write_text(designer_toml(9.532, "[mesh]\nsize_mm = 0.3\n"))
    for command in (["tune", "--fix", "length"], ["modes"]):
        assert main([*command, "--geometry", str(path), "--model", "3d"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "--geometry" in err and "size_mm" in err, err
