"""``lusm explore`` checks each geometry as the single-point commands check their stator
(issue 42): a drive that excites no B2 is a warning kept per geometry and listed in
``--json``; a failed drive point is that point's ``point_status`` while the others are
written; a stator file every plate fails on is one line and leaves no parts folder."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from lusm.cli import main  # noqa: E402
from studies.dataset import open_result  # noqa: E402
from studies.parts import parts_folder  # noqa: E402

PLATE = "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"


def _study(folder: Path, text: str) -> Path:
    path = folder / "study.toml"
    path.write_text(text)
    return path


@pytest.mark.slow
def test_a_drive_that_excites_no_b2_is_warned_in_the_dataset_and_the_json(
        dask_client, tmp_path, capsys):
    """``[electrodes] drive = [1, 2]``: status 'ok', zero velocity and no word, where every
    single-point command warns "excites no B2 ... the motor gives no thrust"."""
    (tmp_path / "s12.toml").write_text(PLATE + "[electrodes]\ndrive = [1, 2]\n")
    study = _study(tmp_path, 'outputs = ["no_load_velocity"]\n[study]\nstator = "s12.toml"\n'
                   '[axes]\nlength = ["29 mm", "30 mm"]\nvoltage = "200 V"\npreload = "6 N"\n'
                   '[solver]\nfe_refine = 1\naccuracy = "fast"\n')
    out = tmp_path / "x.nc"
    assert main(["explore", str(study), "--out", str(out), "--json",
                 "--scheduler", dask_client.scheduler.address]) == 0
    cap = capsys.readouterr()
    listed = json.loads(cap.out)["warnings"]
    said = [w for w in listed if "excites no B2" in w]
    assert len(said) == 1 and "2 of 2 geometries" in said[0], listed
    assert cap.err.count("excites no B2") == 1, cap.err
    ds = open_result(out)
    assert all("excites no B2" in str(w) and "no thrust" in str(w)
               for w in ds["warnings"].values.ravel())


@pytest.mark.slow
def test_a_failed_drive_point_is_its_status_and_the_others_are_written(dask_client, tmp_path,
                                                                       capsys):
    """1 Hz is below the steady engine's bound on every plate: the study wrote no dataset for
    the valid frequency beside it."""
    study = _study(tmp_path, 'outputs = ["no_load_velocity", "motion_class"]\n[axes]\n'
                   'length = "30 mm"\nfrequency = ["1 Hz", "40 kHz"]\nvoltage = "200 V"\n'
                   'preload = "6 N"\n[solver]\nfe_refine = 1\naccuracy = "fast"\n')
    out = tmp_path / "x.nc"
    assert main(["explore", str(study), "--out", str(out),
                 "--scheduler", dask_client.scheduler.address]) == 0
    assert "did not compute fully" in capsys.readouterr().err
    ds = open_result(out)
    ps = ds["point_status"].sel(frequency=[1.0, 40e3]).values.ravel()
    assert str(ps[0]).startswith("failed: axes.frequency 1 Hz is too far below") and \
        ps[1] == "ok"
    v = ds["no_load_velocity"].sel(frequency=[1.0, 40e3]).values.ravel()
    assert np.isnan(v[0]) and np.isfinite(v[1])
    assert not parts_folder(out).exists()


@pytest.mark.slow
def test_a_stator_every_plate_fails_on_is_one_line_and_leaves_no_parts(dask_client, tmp_path,
                                                                       capsys):
    """A preload point on a node of L1 (the plate's centre): --geometry refuses the file in
    about a second; the study solved every plate, failed, and left X.nc.parts for the user to
    delete."""
    from fem.geometry import PlateStator
    from fem.meshing.mesh import structured_mesh
    from fem.meshing.mesh_io import write_stator_msh

    m = structured_mesh(PlateStator(), 2)
    write_stator_msh(tmp_path / "plate.msh", m.points_m.T.copy(), {"quad": m.quads.T.copy()},
                     {"quad": m.electrode.copy()})
    (tmp_path / "node.toml").write_text('[plate]\nthickness_mm = 3\n[mesh]\nfile = '
                                        '"plate.msh"\n[points]\npreload_mm = [0, 15]\n')
    study = _study(tmp_path, 'outputs = ["no_load_velocity"]\n[study]\nstator = "node.toml"\n'
                   '[axes]\nthickness = ["2.5 mm", "3 mm"]\n')
    out = tmp_path / "x.nc"
    assert main(["explore", str(study), "--out", str(out),
                 "--scheduler", dask_client.scheduler.address]) == 2
    err = capsys.readouterr().err
    line = err.strip().splitlines()[-1]
    assert line.startswith("lusm explore: error: study.stator ") and "a node of the mode" in line
    assert "every plate of the study, 2 of 2" in line and "kept" not in line, err
    assert not out.exists() and not parts_folder(out).exists()
