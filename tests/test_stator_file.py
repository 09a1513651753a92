"""Stator TOML files and planform mesh import (fem.stator_file, fem.meshing.mesh_io)."""

from __future__ import annotations

import json
import math
import re
from dataclasses import fields

import meshio
import numpy as np
import pytest

from fem.geometry import PlateStator
from fem.material import pzt8
from fem.mesh_settings import MeshSettings
from fem.meshing.mesh import structured_mesh
from fem.meshing.mesh_io import read_stator_mesh, write_mesh, write_stator_msh
from fem.meshing.meshed_stator import MeshedStator
from fem.model import build_model
from fem.modes import modes_of_model, plate_modes
from fem.stator_file import load_stator

PLATE_TOML = """
name = "a small plate"
[plate]
length_mm = 25.0
width_mm = 6.0
thickness_mm = 2.0
[electrodes]
gap_mm = 0.3
drive = [2, 3]
[material]
name = "paper"
"""


def _write(tmp_path, text, name="stator.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _toml_matrix(a):
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in a) + "]"


@pytest.mark.slow
def test_toml_plate_is_the_programmatic_plate(tmp_path):
    design = load_stator(_write(tmp_path, PLATE_TOML))
    st = PlateStator(25e-3, 6e-3, 2e-3, 0.3e-3, (2, 3))
    assert design.stator == st and type(design.stator) is PlateStator
    assert design.material == plate_modes.__globals__["get_material"]("paper")
    assert design.name == "a small plate"
    # identical matrices, assembled independently of the caches, hence identical frequencies
    # (up to ARPACK's random start vector: 1e-12)
    ref_model = build_model(structured_mesh(st, 3), st, "paper", 2)
    model = design.model(MeshSettings(2, 3))
    assert (model.K != ref_model.K).nnz == 0 and (model.M != ref_model.M).nnz == 0
    np.testing.assert_array_equal(model.G, ref_model.G)
    ref = modes_of_model(ref_model)
    res = design.modes(MeshSettings(2, 3))
    for a, b in ((res.L1, ref.L1), (res.B2, ref.B2)):
        assert a.f_short_Hz == pytest.approx(b.f_short_Hz, rel=1e-12)
        assert a.f_open_Hz == pytest.approx(b.f_open_Hz, rel=1e-12)


@pytest.mark.slow
def test_inline_material_constants(tmp_path):
    m = pzt8()
    inline = (
        "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\n"
        f"name = \"mine\"\ncE_Pa = {_toml_matrix(m.cE_Pa)}\ne_C_m2 = {_toml_matrix(m.e_C_m2)}\n"
        f"epsS_F_m = {_toml_matrix(m.epsS_F_m)}\nrho_kg_m3 = 7600.0\n"
    )
    d = load_stator(_write(tmp_path, inline))
    np.testing.assert_array_equal(d.material.cE_Pa, m.cE_Pa)
    assert d.material.name == "mine"
    # base + override: f_short scales exactly as 1/sqrt(rho) (K does not depend on rho)
    heavy = load_stator(_write(
        tmp_path,
        "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
        "[material]\nbase = \"pzt8\"\nrho_kg_m3 = 8000.0\n",
        "heavy.toml",
    ))
    f0 = d.modes(MeshSettings(refine=3)).L1.f_short_Hz
    f1 = heavy.modes(MeshSettings(refine=3)).L1.f_short_Hz
    assert f1 / f0 == pytest.approx(math.sqrt(7600.0 / 8000.0), rel=1e-9)


def _plate_msh(tmp_path, file_format="gmsh", names="electrode{k}", scale=1.0, name="p.msh"):
    """The structured paper plate written with gmsh physical groups (tip/preload vertices)."""
    st = PlateStator()
    mesh = structured_mesh(st, 3)
    pts = mesh.points_m.T * scale
    tip = int(np.argmin(np.hypot(pts[:, 0], pts[:, 1] - 0.03 * scale)))
    path = write_stator_msh(
        tmp_path / name, pts, {"quad": mesh.quads.T}, {"quad": mesh.electrode},
        {"tip": tip}, file_format=file_format,
    )
    if names != "electrode{k}":  # rename the groups in the file
        text = path.read_text()
        for k in range(1, 5):
            text = text.replace(f'"electrode{k}"', '"' + names.format(k=k) + '"')
        path.write_text(text)
    return st, mesh, path


@pytest.mark.parametrize("file_format", ["gmsh", "gmsh22"])
def test_mesh_file_plate_equals_structured_plate(tmp_path, file_format):
    st, mesh, path = _plate_msh(tmp_path, file_format)
    head = path.read_text().splitlines()[1]
    assert head.startswith("4.1" if file_format == "gmsh" else "2.2")
    _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n')
    d = load_stator(tmp_path / "stator.toml")
    assert isinstance(d.stator, MeshedStator)
    assert d.stator.length_m == pytest.approx(30e-3) and d.stator.width_m == pytest.approx(7.5e-3)
    tip = mesh.points_m[:, np.argmin(np.hypot(*(mesh.points_m - [[0.0], [0.03]])))]
    np.testing.assert_allclose(d.stator.tip_point_m, tip, atol=1e-15)  # the 'tip' vertex
    _assert_same_tags(d.stator.mesh, st)
    res = d.modes()
    ref = plate_modes(st, "pzt8", MeshSettings(2, 3))
    assert res.L1.f_short_Hz == pytest.approx(ref.L1.f_short_Hz, rel=1e-10)
    assert res.B2.f_open_Hz == pytest.approx(ref.B2.f_open_Hz, rel=1e-10)
    # the mesh-based stator's electrode lookup agrees with the quadrant rule
    x = np.array([2e-3, 2e-3, -2e-3, -2e-3, 0.0])
    y = np.array([5e-3, 25e-3, 5e-3, 25e-3, 10e-3])
    np.testing.assert_array_equal(d.stator.electrode_of(x, y), st.electrode_of(x, y))


def test_fem_params_from_file_equals_fem_params(tmp_path):
    from rom.from_fem import fem_params, fem_params_from_file

    p = fem_params_from_file(_write(tmp_path, PLATE_TOML), mesh=MeshSettings(refine=3))
    q = fem_params(PlateStator(25e-3, 6e-3, 2e-3, 0.3e-3, (2, 3)), "paper",
                   mesh=MeshSettings(refine=3))
    for f in fields(p):
        if f.name != "source":
            assert getattr(p, f.name) == getattr(q, f.name), f.name
    assert "stator.toml" in p.source
    with pytest.raises(ValueError, match="stator"):
        fem_params_from_file(tmp_path / "stator.toml", stator=PlateStator())


def _assert_same_tags(mesh, stator):
    """Electrode tags of ``mesh`` follow the quadrant rule of ``stator`` (cell order free)."""
    centre = mesh.points_m[:, mesh.quads].mean(axis=1)
    np.testing.assert_array_equal(mesh.electrode, stator.electrode_of(*centre))


def test_old_style_group_names_and_vtu_electrode_array(tmp_path):
    st, mesh, path = _plate_msh(tmp_path, names="electrode_{k}")
    _assert_same_tags(read_stator_mesh(path).mesh, st)
    vtu = write_mesh(mesh, tmp_path / "p.vtu")  # integer cell array 'electrode'
    imp = read_stator_mesh(vtu)
    np.testing.assert_array_equal(imp.mesh.electrode, mesh.electrode)
    assert imp.points_m == {}


def test_millimetre_mesh_needs_its_unit(tmp_path):
    _plate_msh(tmp_path, scale=1e3)
    _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n')
    with pytest.raises(ValueError, match="looks like millimetres"):
        load_stator(tmp_path / "stator.toml")
    _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\nunit = "mm"\n')
    assert load_stator(tmp_path / "stator.toml").stator.length_m == pytest.approx(0.03)


BAD_TOML = [
    ("[plate]\nlength_mm = -30\nwidth_mm = 7.5\nthickness_mm = 3",
     r"\[plate\] length_mm must lie in \[0.1, 1000\] mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5", r"missing \[plate\] thickness_mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[electrodes]\ngap_mm = 8",
     r"\[electrodes\] gap_mm must lie in \[0, 7.5\) mm"),
    # below the smallest gap the file's own unit, not PlateStator's metres
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[electrodes]\n"
     "gap_mm = 0.0001", r"\[electrodes\] gap_mm must be 0 \(touching quadrants\) or at least "
     r"0.001 mm, got 0.0001$"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[electrodes]\ndrive = [1, 5]",
     r"electrode 5, which is not on the plate; allowed electrode numbers 1..4"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nname = \"pzt5\"",
     r"\[material\] name 'pzt5' is unknown; allowed: pzt8, paper"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nrho_kg_m3 = 7000",
     r"inline constants need cE_Pa"),
    # a coupling 1e5 times PZT-8's gave a clamped capacitance of 0.78 F without a word
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nbase = \"pzt8\"\n"
     "e_C_m2 = [[0,0,0,0,1e6,0],[0,0,0,1e6,0,0],[1e6,1e6,1e6,0,0,0]]",
     r"\[material\] e_C_m2's largest entry must lie in \[0, 100\] C/m\^2"),
    # densities no solid has: 1e-30 gave L1 at 5e21 Hz, 1e30 ARPACK's noise on the terminal
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nbase = \"pzt8\"\n"
     "rho_kg_m3 = 1e-30", r"\[material\] rho_kg_m3 must lie in \[100, 50000\] kg/m\^3"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\nlenght_mm = 3",
     r"unknown key 'lenght_mm' at \[plate\]; allowed: length_mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nnmae = 1",
     r"unknown key 'nmae' at \[material\]"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[points]\ntip_mm = [0, 40]",
     r"\[points\] tip_mm"),
    ("[plate]\nthickness_mm = 3\n[mesh]\nfile = \"missing.msh\"", r"missing.msh"),
    ("[plate\nlength_mm = 30", r"not valid TOML"),
]


@pytest.mark.parametrize(("text", "match"), BAD_TOML)
def test_bad_stator_files_name_the_key(tmp_path, text, match):
    with pytest.raises((ValueError, FileNotFoundError), match=match):
        load_stator(_write(tmp_path, text))


def test_bad_meshes(tmp_path):
    _plate_msh(tmp_path)
    base = '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n'
    with pytest.raises(ValueError, match=r"length_mm = 31 mm does not match"):
        load_stator(_write(tmp_path, base.replace("thickness_mm = 3", "thickness_mm = 3\n"
                                                  "length_mm = 31")))
    with pytest.raises(ValueError, match=r"\[points\] preload_mm .* lies off the mesh"):
        load_stator(_write(tmp_path, base + "[points]\npreload_mm = [5.0, 0.0]\n"))
    with pytest.raises(ValueError, match="gap_mm applies to the generated plate only"):
        load_stator(_write(tmp_path, base + "[electrodes]\ngap_mm = 0.5\n"))
    st = PlateStator()
    mesh = structured_mesh(st, 2)
    pts, quads = mesh.points_m.T, mesh.quads.T
    # unknown physical group
    p = write_stator_msh(tmp_path / "u.msh", pts, {"quad": quads}, {"quad": mesh.electrode})
    p.write_text(p.read_text().replace('"gap"', '"foo"'))
    with pytest.raises(ValueError, match="unknown physical group 'foo'"):
        read_stator_mesh(p)
    p.write_text(p.read_text().replace('"foo"', '"gap"').replace('"electrode1"', '"electrode5"'))
    with pytest.raises(ValueError, match="electrode 5, but the electrodes are numbered 1..4"):
        read_stator_mesh(p)
    # no electrode at all
    p = write_stator_msh(tmp_path / "n.msh", pts, {"quad": quads}, {"quad": 0 * mesh.electrode})
    with pytest.raises(ValueError, match="has no electrode"):
        read_stator_mesh(p)
    # unsupported cells, not planar, not in the stator frame, no tags
    m3 = meshio.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]) * 1e-3,
                     [("tetra", np.array([[0, 1, 2, 3]]))])
    meshio.write(tmp_path / "t.vtu", m3)
    with pytest.raises(ValueError, match="unsupported cell type 'tetra'"):
        read_stator_mesh(tmp_path / "t.vtu")
    shifted = meshio.Mesh(np.column_stack((pts + [0.01, 0.0], np.zeros(len(pts)))),
                          [("quad", quads)], cell_data={"electrode": [mesh.electrode]})
    meshio.write(tmp_path / "s.vtu", shifted)
    with pytest.raises(ValueError, match="x centred on 0"):
        read_stator_mesh(tmp_path / "s.vtu")
    # said in the file's unit: the same mesh in mm spans x = [6.25, 13.75] mm
    shifted.points = shifted.points * 1e3
    meshio.write(tmp_path / "s.vtu", shifted)
    with pytest.raises(ValueError, match=r"spans x = \[6.25, 13.75\] mm"):
        read_stator_mesh(tmp_path / "s.vtu", unit="mm")
    bare = meshio.Mesh(np.column_stack((pts, np.zeros(len(pts)))), [("quad", quads)])
    meshio.write(tmp_path / "b.vtu", bare)
    with pytest.raises(ValueError, match="no electrode tags"):
        read_stator_mesh(tmp_path / "b.vtu")
    with pytest.raises(FileNotFoundError):
        read_stator_mesh(tmp_path / "nothing.msh")


def test_cli_geometry(tmp_path, capsys):
    from lusm.cli import main

    path = _write(tmp_path, PLATE_TOML)
    assert main(["modes", "--geometry", str(path), "--refine", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = load_stator(path).modes(MeshSettings(refine=3))
    assert out["L1"]["f_short_Hz"] == ref.L1.f_short_Hz
    assert out["geometry"] == str(path)
    assert main(["params", "--source", "fem", "--geometry", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["phi_L0"] == pytest.approx(1.0)
    bad = _write(tmp_path, BAD_TOML[0][0], "bad.toml")
    assert main(["modes", "--geometry", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "length_mm" in err
    assert main(["params", "--source", "table2", "--geometry", str(path)]) == 2
    assert "--source fem" in capsys.readouterr().err


@pytest.mark.slow
def test_mixed_triangle_quad_mesh_is_conforming(tmp_path):
    """Half the plate as quads, half as triangles: the converted mesh gives the plate's modes."""
    st = PlateStator()
    mesh = structured_mesh(st, 3)
    q = mesh.quads.T
    y = mesh.points_m[1, q].mean(axis=1)
    split = y > 15e-3
    tris = np.vstack((q[split][:, [0, 1, 2]], q[split][:, [0, 2, 3]]))
    t_tags = np.concatenate((mesh.electrode[split], mesh.electrode[split]))
    # clockwise input for half of the quads: orientation is repaired on reading
    quads = q[~split].copy()
    quads[::2] = quads[::2, ::-1]
    path = write_stator_msh(tmp_path / "mixed.msh", mesh.points_m.T,
                            {"quad": quads, "triangle": tris},
                            {"quad": mesh.electrode[~split], "triangle": t_tags})
    imp = read_stator_mesh(path)
    assert imp.converted and set(imp.cell_types) == {"quad", "triangle"}
    _assert_same_tags(imp.mesh, st)
    sm = MeshedStator(length_m=30e-3, width_m=7.5e-3, thickness_m=3e-3, electrode_gap_m=0.0,
                      mesh=imp.mesh, tip_m=(0.0, 30e-3), preload_m=(0.0, 0.0))
    res = modes_of_model(build_model(imp.mesh, sm, "pzt8", 2))
    ref = plate_modes(st, "pzt8", MeshSettings(2, 8))
    assert res.L1.f_short_Hz == pytest.approx(ref.L1.f_short_Hz, rel=1e-4)
    assert res.B2.f_short_Hz == pytest.approx(ref.B2.f_short_Hz, rel=1e-3)


def test_unnamed_tags_and_non_planar_meshes(tmp_path):
    mesh = structured_mesh(PlateStator(), 2)
    pts, quads = mesh.points_m.T, mesh.quads.T
    p = write_stator_msh(tmp_path / "u.msh", pts, {"quad": quads}, {"quad": mesh.electrode},
                         file_format="gmsh22")
    text = p.read_text()
    p.write_text(text.replace('2 3 "electrode3"', '2 33 "electrode3"'))
    with pytest.raises(ValueError, match="physical tag 3 .*has no name"):
        read_stator_mesh(p)
    bent = meshio.Mesh(np.column_stack((pts, 1e-3 * pts[:, 1])), [("quad", quads)],
                       cell_data={"electrode": [mesh.electrode]})
    meshio.write(tmp_path / "z.vtu", bent)
    with pytest.raises(ValueError, match="not planar"):
        read_stator_mesh(tmp_path / "z.vtu")
    with pytest.raises(ValueError, match="unit must be one of m, mm"):
        read_stator_mesh(p, unit="inch")


@pytest.mark.slow
def test_a_hole_on_the_centreline_solves(tmp_path):
    # the mode identification's sampling points next to the hole's polygonal edge were
    # counted inside by the nominal outline but not located by scikit-fem: "Point is outside
    # of the mesh" for holes at x = 0 (y = 3, 10, 15, 20 mm); 1 mm off the line it solved
    from fem.modes import plate_modes

    text = ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[[holes]]\n"
            "center_mm = [{x}, 15]\ndiameter_mm = 1\n")
    on = load_stator(_write(tmp_path, text.format(x=0)))
    res = plate_modes(on.stator, on.material)
    assert res.L1.mac > 0.9 and res.B2.mac > 0.9
    ref = plate_modes(load_stator(_write(tmp_path, text.format(x=0.2))).stator, on.material)
    assert res.L1.f_short_Hz == pytest.approx(ref.L1.f_short_Hz, rel=0.01)  # nearby hole


@pytest.mark.slow
def test_a_stator_files_fine_mesh_is_blamed_on_its_size_not_on_refine(tmp_path, capsys):
    # "--refine: ... lower --refine" from commands that have no --refine (lusm report)
    from lusm.cli import main

    path = _write(tmp_path, "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
                  "[mesh]\nsize_mm = 0.075\n[[holes]]\ncenter_mm = [0.0, 15.0]\n"
                  "diameter_mm = 1.0\n")
    assert main(["modes", "--geometry", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]  # after the hole's 2D warning
    assert err.startswith("lusm modes: error: --geometry: the stator's mesh needs")
    assert "[mesh] size_mm" in err and "--refine" not in err


@pytest.mark.parametrize("relabel, match", [
    # 1, 2 <-> 3, 4: the mirror image across the length axis (a different wiring on paper)
    ([0, 3, 4, 1, 2], r"electrodes 1, 2 must lie on x > 0 and 3, 4 on x < 0"),
    # 1 <-> 2, 3 <-> 4: the tip's and the preload end's halves swapped
    ([0, 2, 1, 4, 3], r"electrodes 2, 4 must lie on the tip's half"),
    # two electrodes along the length: no quadrant at x < 0
    ([0, 1, 2, 1, 2], r"no cells under electrodes 3, 4: a stator needs all four"),
    # one electrode on each side of both centre lines, but 2 and 3 missing: the model failed
    # with "mesh has no elements under electrode(s) [2, 3]", naming no file or rule
    ([0, 1, 0, 0, 4], r"no cells under electrodes 2, 3: a stator needs all four quadrant "
                      r"electrodes 1..4 .*electrode1, electrode2, electrode3, electrode4"),
])
def test_electrode_tags_must_be_the_quadrants_of_fig1(tmp_path, relabel, match):
    """The 2D model reads its gap strips from where the tags lie. A mirrored numbering gave
    B2 f_open = f_short (k_eff 0) without a word, and a two-electrode mesh a NumPy error."""
    mesh = structured_mesh(PlateStator(), 2)
    tags = np.array(relabel)[mesh.electrode]
    p = write_stator_msh(tmp_path / "r.msh", mesh.points_m.T, {"quad": mesh.quads.T},
                         {"quad": tags})
    with pytest.raises(ValueError, match=match):
        read_stator_mesh(p)
    from fem.meshing.mesh import PlateMesh
    from fem.model import gap_layout

    with pytest.raises(ValueError, match=match):
        gap_layout(PlateMesh(mesh.points_m, mesh.quads, tags))
    assert mesh.quadrant_problem() is None


def test_a_stator_file_saved_with_a_bom_is_the_same_plate(tmp_path):
    """Windows editors save UTF-8 with a byte-order mark; it was refused as bad TOML."""
    text = "[plate]\nlength_mm = 25\nwidth_mm = 6\nthickness_mm = 2\n"
    plain = load_stator(_write(tmp_path, text, "a.toml"))
    bom = tmp_path / "b.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode())
    assert load_stator(bom).stator == plain.stator


def test_unreadable_and_fractional_meshes_say_why_in_one_message(tmp_path, capsys):
    """meshio printed its reason on stderr and raised SystemExit(1): the error ended in ': 1'.
    A float 'electrode' array was truncated (1.9 read as 1)."""
    (tmp_path / "g.vtu").write_bytes(b"x")
    with pytest.raises(ValueError, match=r"could not read mesh file .*g\.vtu: Couldn't read"):
        read_stator_mesh(tmp_path / "g.vtu")
    assert capsys.readouterr().err == ""
    mesh = structured_mesh(PlateStator(), 2)
    m = meshio.Mesh(np.column_stack((mesh.points_m.T, np.zeros(mesh.points_m.shape[1]))),
                    [("quad", mesh.quads.T)],
                    cell_data={"electrode": [mesh.electrode - 0.1 * (mesh.electrode > 0)]})
    meshio.write(tmp_path / "f.vtu", m)
    with pytest.raises(ValueError, match="must hold one integer 0..4 per cell"):
        read_stator_mesh(tmp_path / "f.vtu")


@pytest.mark.parametrize("text, extra, expected", [
    # the default gap on a plate narrower than it: PlateStator's metres were printed
    ("length_mm = 1000\nwidth_mm = 0.1\nthickness_mm = 0.1\n", [],
     "the default [electrodes] gap_mm 0.5 mm leaves no electrode"),
    # the 3D model's gap: '--gap-mm', which the user did not type, was named
    ("length_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[electrodes]\ngap_mm = 0\n",
     ["--model", "3d"], "[electrodes] gap_mm must be at least 0.001 mm with --model 3d"),
])
def test_stator_file_plates_are_refused_in_the_files_terms(tmp_path, capsys, text, extra,
                                                           expected):
    from lusm.cli import main

    path = _write(tmp_path, "[plate]\n" + text)
    assert main(["modes", "--geometry", str(path), *extra]) == 2
    err = capsys.readouterr().err
    assert expected in err and "--gap-mm" not in err and err.count("\n") == 1


@pytest.mark.filterwarnings("ignore::fem.stator_file.InteriorPointWarning")
def test_a_tip_on_a_node_of_b2_names_the_point(tmp_path):
    """B2 is antisymmetric about the plate's middle: a tip there has no B2 motion to
    normalise. The error said 'FE mode shape vanishes at the normalization point'."""
    from rom.from_fem import fem_params_from_file

    _plate_msh(tmp_path)
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n'
                  "[points]\ntip_mm = [0.0, 15.0]\n")
    with pytest.raises(ValueError, match=r"B2 mode's x displacement at the tip point "
                                         r"\(0, 15\) mm is .* of its largest .*\[points\] "
                                         r"tip_mm"):
        fem_params_from_file(path, mesh=MeshSettings(refine=2))


@pytest.mark.filterwarnings("ignore::fem.stator_file.InteriorPointWarning")
@pytest.mark.slow
def test_a_preload_point_on_a_node_of_l1_is_refused_not_reduced(tmp_path):
    """L1's centre is a node of its y motion. The FE value there is not exactly 0 (1.3e-8 of
    the largest on a user's gmsh plate), and the reduction normalised L1 by it: M_l came out
    1.5e13 kg and the warning blamed the drive electrodes. The modal mass scales as the
    inverse square of the share, so a share below 1e-2 is refused, and the same set
    reduced at the plate's end is a plain one."""
    from rom.from_fem import NODE_SHARE, fem_params_from_file

    _plate_msh(tmp_path)
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n'
                  "[points]\npreload_mm = [0.0, 15.0]\n")
    with pytest.raises(ValueError, match=r"L1 mode's y displacement at the preload point "
                                         r"\(0, 15\) mm is .* of its largest"):
        fem_params_from_file(path, mesh=MeshSettings(refine=2))
    end = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n', "end.toml")
    from rom.from_fem import fem_params

    at_end = fem_params_from_file(end, mesh=MeshSettings(refine=2))
    same_mesh = fem_params(mesh=MeshSettings(refine=3))  # the same mesh
    assert at_end.M_l == pytest.approx(same_mesh.M_l, rel=1e-6)
    assert NODE_SHARE == 1e-2


def test_the_gap_validity_warning_is_in_the_files_terms(tmp_path, capsys):
    """A stator file's gap above thickness/6 was warned about as "electrode gap 0.8 mm
    exceeds thickness/6", while the file's keys are [electrodes] gap_mm and [plate]
    thickness_mm; the plate options keep the library's words."""
    from lusm.cli import main

    path = tmp_path / "wg.toml"
    path.write_text("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 1.5\n"
                    "[electrodes]\ngap_mm = 0.8\n")
    assert main(["modes", "--geometry", str(path), "--json"]) == 0
    err = capsys.readouterr().err
    assert "[electrodes] gap_mm" in err and "[plate] thickness_mm / 6 = 0.25 mm" in err
    assert main(["modes", "--gap-mm", "0.8", "--thickness-mm", "1.5", "--json"]) == 0
    assert "electrode gap 0.8 mm exceeds thickness/6" in capsys.readouterr().err


def _seamed_plate(y_seam=15.25e-3):
    """The structured plate with its own nodes on ``y = y_seam``, ``x < 0`` for the cells
    above: an unmerged seam (a crack) between the gap strip and electrode 4."""
    mesh = structured_mesh(PlateStator(), 2)
    pts, quads = mesh.points_m.T, mesh.quads.T
    on = np.flatnonzero((np.abs(pts[:, 1] - y_seam) < 1e-12) & (pts[:, 0] < 0))
    copy = np.arange(len(pts))
    copy[on] = len(pts) + np.arange(on.size)
    above = pts[quads].mean(axis=1)[:, 1] > y_seam
    quads = np.where(above[:, None], copy[quads], quads)
    return np.vstack((pts, pts[on])), quads, mesh.electrode, on.size


def test_an_unmerged_seam_is_refused_naming_a_place_and_the_remedy(tmp_path):
    """Duplicate nodes at the same coordinates, used by the cells on either side of a line,
    were accepted: a 2.6 mm crack moved L1 by 11 % and a longer one failed as 'L1 and B2
    were not found' (exploratory testing)."""
    pts, quads, tags, n_seam = _seamed_plate()
    assert n_seam == 2
    path = write_stator_msh(tmp_path / "seam.msh", pts, {"quad": quads}, {"quad": tags})
    with pytest.raises(ValueError) as err:
        read_stator_mesh(path)
    text = str(err.value)
    assert "\n" not in text and "seam.msh" in text
    assert "has 4 nodes used by its cells that coincide with another node (2 places" in text
    assert re.search(r"one at x = -(3\.75|0\.25) mm, y = 15\.25 mm\)", text), text
    assert "merge the duplicate nodes" in text and "Geometry.AutoCoherence" in text


def test_duplicate_nodes_no_cell_uses_are_still_accepted(tmp_path):
    """Unused copies of nodes (as some exporters leave them) are dropped, not refused."""
    mesh = structured_mesh(PlateStator(), 2)
    pts = mesh.points_m.T
    path = write_stator_msh(tmp_path / "spare.msh", np.vstack((pts, pts[:5])),
                            {"quad": mesh.quads.T}, {"quad": mesh.electrode},
                            file_format="gmsh22")
    imp = read_stator_mesh(path)
    assert imp.mesh.points_m.shape == mesh.points_m.shape
    _assert_same_tags(imp.mesh, PlateStator())


def test_a_point_off_the_mesh_names_where_it_came_from(tmp_path):
    """A mesh's 'tip' vertex off its cells was reported as "[points] tip_mm = [0, 40] mm lies
    off the mesh" in a file without a [points] table (exploratory testing)."""
    mesh = structured_mesh(PlateStator(), 2)
    pts, quads = mesh.points_m.T, mesh.quads.T
    far = np.vstack((pts, [[0.0, 0.04]]))  # a node no cell uses, 10 mm beyond the tip end
    write_stator_msh(tmp_path / "far.msh", far, {"quad": quads}, {"quad": mesh.electrode},
                     {"tip": len(pts)})
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "far.msh"\n')
    with pytest.raises(ValueError) as err:
        load_stator(path)
    text = str(err.value)
    assert "[points]" not in text.split(";")[0], text
    assert ("the 'tip' vertex group of the mesh file far.msh is at [0, 40] mm, off the mesh's "
            "cells (x in [-3.75, 3.75] mm, y in [0, 30] mm); put its node on the planform or "
            "set [points] tip_mm") in text
    # no vertex group: the default preload point (0, 0), here in a notch of the preload end
    centre = pts[quads].mean(axis=1)
    notch = (np.abs(centre[:, 0]) < 1e-6) & (centre[:, 1] < 5e-3)
    assert notch.sum() == 1
    write_stator_msh(tmp_path / "notch.msh", pts, {"quad": quads[~notch]},
                     {"quad": mesh.electrode[~notch]})
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "notch.msh"\n')
    with pytest.raises(ValueError, match=r"the default preload point \[0, 0\] mm \(no \[points\] "
                       r"preload_mm, no 'preload' vertex group in notch.msh\) lies off the "
                       r"mesh's cells .*; set \[points\] preload_mm or add a 'preload' vertex"):
        load_stator(path)
    # given in [points]: named as before
    with pytest.raises(ValueError, match=r"\[points\] preload_mm = \[0, 0\] mm lies off"):
        load_stator(_write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "notch.msh"\n'
                           '[points]\npreload_mm = [0, 0]\n'))


def _gmsh_quadrants(path, version, groups, save_all):
    """The paper's plate as four touching quadrants meshed by gmsh (mm), written as MSH
    ``version`` with or without the electrode physical groups and with ``Mesh.SaveAll``."""
    import gmsh

    from fem.meshing.parametric import _initialize_keeping_signals

    _initialize_keeping_signals(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("quadrants")
        occ = gmsh.model.occ
        rects = [occ.addRectangle(x, y, 0, 3.75, 15) for x in (-3.75, 0) for y in (0, 15)]
        occ.fragment([(2, rects[0])], [(2, r) for r in rects[1:]])
        occ.synchronize()
        if groups:
            for _, tag in gmsh.model.getEntities(2):
                x, y, _ = occ.getCenterOfMass(2, tag)
                k = (1 if y < 15 else 2) if x > 0 else (3 if y < 15 else 4)
                gmsh.model.addPhysicalGroup(2, [tag], k, name=f"electrode{k}")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 2.0)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.option.setNumber("Mesh.SaveAll", int(save_all))
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


@pytest.mark.parametrize("version", [2.2, 4.1])
@pytest.mark.parametrize("kind", ["save_all", "no_groups"])
def test_elements_without_a_physical_group_say_so_in_both_formats(tmp_path, capsys, version,
                                                                  kind):
    """gmsh's Mesh.SaveAll read as "malformed or truncated (Incompatible cell data
    'gmsh:physical' ...)" in MSH 4.1 and as "physical tag 0 (dimension 0) has no name" in
    MSH 2.2, as did a 2.2 mesh without groups (exploratory testing)."""
    from lusm.cli import main

    mesh = _gmsh_quadrants(tmp_path / "q.msh", version, groups=kind == "save_all",
                           save_all=kind == "save_all")
    assert _gmsh_quadrants(tmp_path / "ok.msh", version, True, False)  # the groups alone: read
    ok = read_stator_mesh(tmp_path / "ok.msh", unit="mm")
    assert set(np.unique(ok.mesh.electrode)) == {1, 2, 3, 4}
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "q.msh"\nunit = "mm"\n')
    assert main(["modes", "--geometry", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"[mesh] file: mesh file {mesh}: " in err
    assert "belong to no physical group (gmsh writes such elements with Mesh.SaveAll = 1, " \
           "or when the model has no physical groups)" in err
    assert "physical groups named electrode1..electrode4" in err and "Mesh.SaveAll = 0" in err
    assert "malformed" not in err and "has no name" not in err


MESHED_PLATE = '[plate]\nthickness_mm = 3\n[mesh]\nfile = "{mesh}"\n'


@pytest.mark.parametrize("text, expected", [
    # a folder was "not found"
    pytest.param(MESHED_PLATE.format(mesh="."),
                 "[mesh] file '.' is a folder ({dir}); name the mesh file, e.g. \"plate.msh\"",
                 id="mesh-folder"),
    # no or an unknown extension: "malformed or truncated (Could not deduce file format ...)"
    pytest.param(MESHED_PLATE.format(mesh="plate"),
                 "[mesh] file: mesh file {dir}/plate has no extension: the extension gives the "
                 "mesh's format; name it .msh (gmsh MSH 4.1 or 2.2) or, with an integer cell "
                 "array 'electrode', another format meshio reads (.vtu, .vtk, .xdmf, ...)",
                 id="mesh-no-extension"),
    pytest.param(MESHED_PLATE.format(mesh="plate.mymesh"),
                 "mesh file {dir}/plate.mymesh has the extension '.mymesh', which names no "
                 "format meshio reads: the extension gives the mesh's format; name it .msh",
                 id="mesh-unknown-extension"),
    # one point without its list: "must be [x, y] in mm, got 0"
    pytest.param(MESHED_PLATE.format(mesh="p.msh") + "[points]\nmounts_mm = [0, 15]\n",
                 "[points] mounts_mm must be a list of [x, y] pairs in mm, e.g. [[0, 15]] for "
                 "one point, got [0, 15]", id="mounts-flat-list"),
    # an empty [mesh] was read as no mesh: "missing [plate] length_mm"
    pytest.param("[plate]\nthickness_mm = 3\n[mesh]\n",
                 "[mesh] is empty; give it file = \"plate.msh\" (a mesh file, with unit = \"m\" "
                 "or \"mm\"), or size_mm (the element size of a parametric stator: [tip], "
                 "[chamfers], [[holes]]), or remove the table", id="mesh-empty-table"),
    pytest.param(PLATE_TOML + "[chamfers]\nsize_mm = 1\n[mesh]\n", "[mesh] is empty;",
                 id="mesh-empty-table-parametric"),
    # a source next to a named material was dropped without a word
    pytest.param(PLATE_TOML.replace('name = "paper"', 'name = "pzt8"\nsource = "my datasheet"'),
                 "[material] source describes inline constants (cE_Pa, e_C_m2, epsS_F_m, "
                 "rho_kg_m3) and cannot be combined with name = 'pzt8' alone, whose source is "
                 "fixed; remove source, or give constants inline (with base = 'pzt8' to start "
                 "from it)", id="material-source-with-name"),
])
def test_small_mistakes_are_named_for_what_they_are(tmp_path, capsys, text, expected):
    """Each of these was refused with a message about something else (exploratory testing)."""
    from lusm.cli import main

    _, _, msh = _plate_msh(tmp_path)
    for name in ("plate", "plate.mymesh"):  # a good gmsh mesh under a name meshio cannot place
        (tmp_path / name).write_bytes(msh.read_bytes())
    path = _write(tmp_path, text)
    assert main(["modes", "--geometry", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"lusm modes: error: --geometry {path}: ")
    assert expected.format(dir=tmp_path) in err, err


@pytest.mark.slow
def test_a_tip_inside_the_planform_is_warned_about_and_the_points_are_printed(tmp_path,
                                                                              capsys):
    """A tip 1 mm inside the plate was taken as given (B2 normalised there, M_b 0.0089 ->
    0.0155 kg) without a word, and no command said which tip and preload points it used.
    The warning gives the distance to the outline; modes prints and --json lists both."""
    import warnings

    from fem.stator_file import InteriorPointWarning, load_stator
    from lusm.cli import main

    _plate_msh(tmp_path)
    inside = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n'
                    "[points]\ntip_mm = [0.0, 29.0]\n")
    with pytest.warns(InteriorPointWarning, match=r"tip_mm = \[0, 29\] mm lies 1 mm inside"):
        load_stator(inside)
    end = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "p.msh"\n', "end.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error", InteriorPointWarning)
        load_stator(end)
    assert main(["modes", "--geometry", str(inside), "--json"]) == 0
    out = capsys.readouterr()
    d = json.loads(out.out)
    assert d["tip_mm"] == [0.0, 29.0] and d["preload_mm"] == [0.0, 0.0]
    assert "lies 1 mm inside the planform" in out.err and out.err.count("\n") == 1
    assert main(["modes", "--geometry", str(end)]) == 0
    # the file's tip vertex: the mesh node nearest (0, 30) mm, on the gap strip's edge
    assert "tip (-0.25, 30) mm, preload (0, 0) mm" in capsys.readouterr().out


def test_a_msh41_surface_in_two_physical_groups_is_refused(tmp_path):
    """MSH 4.1 ties physical tags to entities and meshio keeps one per entity: a surface in
    both electrode1 and gap ran as one of them without a word (MSH 2.2 writes its cells
    twice, which the duplicated-cell check refuses)."""
    from fem.meshing.mesh_io import read_stator_mesh

    _, _, path = _plate_msh(tmp_path)
    text = path.read_text()
    one = "\n2 0 0 0 0 0 0 1 1 0\n"  # surface entity 2: physical group 1 (electrode1)
    assert text.count(one) == 1
    read_stator_mesh(path)  # as written: one group per surface
    path.write_text(text.replace(one, "\n2 0 0 0 0 0 0 2 1 10 0\n"))  # and gap (tag 10)
    with pytest.raises(ValueError, match=r"surface entity 2 belongs to 2 physical groups "
                                         r"\(electrode1, gap\)"):
        read_stator_mesh(path)


def test_tip_and_preload_at_one_point_and_a_fifo_mesh_name_the_file_keys(tmp_path):
    """Both found by exploratory testing: tip_mm = preload_mm had been refused as
    "MotorParams.phi_Ll must differ from phi_L0", naming no key; a [mesh] file that is a
    FIFO or a device as "not found"."""
    import os

    mesh = structured_mesh(PlateStator(), 2)
    write_stator_msh(tmp_path / "p.msh", mesh.points_m.T, {"quad": mesh.quads.T},
                     {"quad": mesh.electrode})
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[points]\ntip_mm = [0, 30]\n'
                            'preload_mm = [0, 30]\n[mesh]\nfile = "p.msh"\n')
    with pytest.raises(ValueError, match=r"the tip and the preload point are the same point, "
                                         r"\[0, 30\] mm \(\[points\] tip_mm and preload_mm"):
        load_stator(path)
    os.mkfifo(tmp_path / "fifo.msh")
    path = _write(tmp_path, '[plate]\nthickness_mm = 3\n[mesh]\nfile = "fifo.msh"\n')
    with pytest.raises(ValueError, match=r"\[mesh\] file 'fifo.msh' is a FIFO \(named pipe\)"):
        load_stator(path)


@pytest.mark.slow
def test_a_point_on_a_mirrored_meshs_centre_line_is_not_minus_zero(tmp_path, capsys):
    """The tip example's mesh mirrored in x (electrodes renumbered to the paper's quadrants):
    its tip and preload vertices lie at x = -0.0 and were printed as "tip (-0, 31) mm" and
    "tip_mm": [-0.0, 31.0] (exploratory testing)."""
    from lusm.cli import main
    from tests.conftest import ROOT

    example = ROOT / "examples" / "tip_protrusion"
    mesh = meshio.read(example / "tip_protrusion.msh")
    mesh.points[:, 0] *= -1.0
    swap = {1: 3, 3: 1, 2: 4, 4: 2}  # the mirror image's quadrants
    for block in mesh.cell_data["gmsh:physical"]:
        block[:] = [swap.get(int(t), int(t)) for t in block]
    meshio.write(tmp_path / "mirrored.msh", mesh, file_format="gmsh22", binary=False)
    toml = (example / "stator.toml").read_text().replace("tip_protrusion.msh", "mirrored.msh")
    (tmp_path / "stator.toml").write_text(toml)
    assert main(["modes", "--geometry", str(tmp_path / "stator.toml"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["tip_mm"] == [0.0, 31.0] and math.copysign(1.0, d["tip_mm"][0]) == 1.0
    assert math.copysign(1.0, d["preload_mm"][0]) == 1.0
    assert main(["modes", "--geometry", str(tmp_path / "stator.toml")]) == 0
    assert "tip (0, 31) mm, preload (0, 0) mm" in capsys.readouterr().out


@pytest.mark.parametrize("text, key, value, allowed", [
    ("[plate]\nlength_mm = -1\nwidth_mm = 7.5\nthickness_mm = 3\n", "[plate] length_mm", -1,
     "in [0.1, 1000] mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[points]\ntip_mm = [1]\n",
     "[points] tip_mm", [1], "[x, y] in mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[mesh]\nfile = \"p.msh\"\n"
     "unit = \"cm\"\n", "[mesh] unit", "cm", "one of m, mm"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[damping]\nzeta_L1 = 0.01\n",
     "[damping] zeta_B2", None, "a finite number"),
    ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n[material]\nbase = \"pzt8\"\n"
     "epsS_F_m = [[-8e-9, 0, 0], [0, 8e-9, 0], [0, 0, 7e-9]]\n", "[material] epsS_F_m", None,
     "positive definite"),
])
def test_a_refusal_names_the_files_key_as_a_field(tmp_path, text, key, value, allowed):
    """A caller tells which key failed, the value and what the key takes from the
    refusal's fields, not its message; the fields survive a worker's pickling."""
    import pickle

    from fem.errors import StatorFileError
    from fem.stator_file import load_stator

    path = _write(tmp_path, text)
    with pytest.raises(StatorFileError) as info:
        load_stator(path)
    for exc in (info.value, pickle.loads(pickle.dumps(info.value))):
        assert (exc.key, exc.value, exc.allowed, exc.source) == (key, value, allowed,
                                                                 str(path))
        assert str(exc).startswith(f"{path}: ") and key in str(exc)
