"""Stator geometry validation, structured meshes and mesh I/O (fem.geometry, fem.meshing.mesh)."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

from fem.geometry import PlateStator, reverse_drive
from fem.meshing.mesh import PlateMesh, structured_mesh
from fem.meshing.mesh_io import read_stator_mesh, write_mesh


@pytest.mark.parametrize("name", ["length_m", "width_m", "thickness_m"])
@pytest.mark.parametrize("value", [0.0, -1e-3, float("nan")])
def test_non_positive_dimension_is_rejected(name, value):
    with pytest.raises(ValueError, match=name):
        PlateStator(**{name: value})


def test_gap_that_leaves_no_electrode_is_rejected():
    with pytest.raises(ValueError, match="electrode_gap_m.*leaves no electrode"):
        PlateStator(width_m=7.5e-3, electrode_gap_m=7.5e-3)
    with pytest.raises(ValueError, match="electrode_gap_m"):
        PlateStator(electrode_gap_m=-1e-4)


@pytest.mark.parametrize("drive", [(0, 4), (1, 5), (), (1, 1)])
def test_bad_drive_electrodes_are_rejected(drive):
    with pytest.raises(ValueError, match="drive_electrodes"):
        PlateStator(drive_electrodes=drive)


def test_reverse_drive_uses_the_other_diagonal():
    st = PlateStator()
    assert reverse_drive(st).drive_electrodes == (2, 3)
    assert st.reversed().reversed() == st


def test_electrode_areas_follow_the_gap():
    st = PlateStator(electrode_gap_m=0.5e-3)
    mesh = structured_mesh(st, refine=4)
    p = mesh.points_m
    area = []
    for k in range(5):
        q = mesh.quads[:, mesh.elements_of(k)]
        dx = p[0, q].max(axis=0) - p[0, q].min(axis=0)
        dy = p[1, q].max(axis=0) - p[1, q].min(axis=0)
        area.append(float(np.sum(dx * dy)))
    quadrant = (st.width_m - st.electrode_gap_m) / 2 * (st.length_m - st.electrode_gap_m) / 2
    np.testing.assert_allclose(area[1:], quadrant, rtol=1e-12)
    assert sum(area) == pytest.approx(st.width_m * st.length_m, rel=1e-12)
    # Fig. 1 layout: 1, 2 at x > 0; 1, 3 at the preload end y < l/2
    c = p[:, mesh.quads].mean(axis=1)
    for k, (sx, near) in {1: (1, True), 2: (1, False), 3: (-1, True), 4: (-1, False)}.items():
        ck = c[:, mesh.elements_of(k)]
        assert np.all(np.sign(ck[0]) == sx)
        assert np.all((ck[1] < st.length_m / 2) == near)


def _same(a: PlateMesh, b: PlateMesh) -> bool:
    def key(m):
        c = m.points_m[:, m.quads].mean(axis=1)
        o = np.lexsort(c)
        return c[:, o], m.electrode[o]

    (ca, ta), (cb, tb) = key(a), key(b)
    return np.allclose(ca, cb) and np.array_equal(ta, tb)


@pytest.mark.parametrize(
    ("name", "fmt", "version"),
    [("plate.msh", None, "4.1"), ("plate22.msh", "gmsh22", "2.2"), ("plate.vtu", None, None)],
)
def test_mesh_roundtrip_keeps_electrode_tags(tmp_path, name, fmt, version):
    mesh = structured_mesh(PlateStator(), refine=3)
    path = write_mesh(mesh, tmp_path / name, file_format=fmt)
    if version is not None:
        assert path.read_text().splitlines()[1].split()[0] == version
        m = meshio.read(path)
        names = {"electrode1", "electrode2", "electrode3", "electrode4"}
        assert names <= set(m.field_data)  # gmsh $PhysicalNames
        assert "gmsh:physical" in m.cell_data
        if version == "4.1":  # meshio turns MSH 4.1 physical groups into cell_sets
            assert names <= set(m.cell_sets)
    assert _same(read_stator_mesh(path).mesh, mesh)


def test_mesh_without_electrode_tags_is_rejected(tmp_path):
    mesh = structured_mesh(PlateStator(), refine=2)
    pts = np.vstack((mesh.points_m, np.zeros(mesh.points_m.shape[1]))).T
    path = tmp_path / "untagged.msh"
    meshio.write(path, meshio.Mesh(pts, [("quad", mesh.quads.T)]), file_format="gmsh22",
                 binary=False)
    # meshio writes physical tag 0 for cells without one, as gmsh does with Mesh.SaveAll
    with pytest.raises(ValueError, match=r"all \d+ of its surface cells belong to no physical "
                       r"group .*groups named electrode1\.\.electrode4"):
        read_stator_mesh(path)


def test_unreadable_or_missing_mesh_is_rejected(tmp_path):
    bad = tmp_path / "garbage.msh"
    bad.write_text("this is not a mesh\n")
    with pytest.raises(ValueError, match="could not read mesh file"):
        read_stator_mesh(bad)
    with pytest.raises(FileNotFoundError):
        read_stator_mesh(tmp_path / "missing.msh")


def test_refine_must_be_a_positive_integer():
    with pytest.raises(ValueError, match="refine"):
        structured_mesh(PlateStator(), refine=0)


def test_old_group_spelling_is_still_read(tmp_path):
    """lusm writes ``electrode1..4``; files with ``electrode_1..4`` give the same tags."""
    mesh = structured_mesh(PlateStator(), refine=2)
    new = write_mesh(mesh, tmp_path / "new.msh", file_format="gmsh22")
    old = tmp_path / "old.msh"
    old.write_text(new.read_text().replace('"electrode', '"electrode_'))
    assert '"electrode_3"' in old.read_text()
    assert _same(read_stator_mesh(old).mesh, mesh)
    assert _same(read_stator_mesh(new).mesh, mesh)


def test_broken_mesh_files_are_named_for_what_is_wrong(tmp_path):
    """A folder read as "file not found", an empty file as "need at least one array to
    concatenate", and a NaN coordinate as the tip lying "off the mesh (x in [nan, nan])"
    or an infinite one as "this looks like millimetres" (exploratory testing)."""
    from fem.geometry import PlateStator
    from fem.meshing.mesh import structured_mesh
    from fem.meshing.mesh_io import write_mesh

    (tmp_path / "adir").mkdir()
    with pytest.raises(ValueError, match="is a folder, not a file"):
        read_stator_mesh(tmp_path / "adir")
    (tmp_path / "empty.msh").write_text("")
    with pytest.raises(ValueError, match="empty.msh: it is empty"):
        read_stator_mesh(tmp_path / "empty.msh")
    good = write_mesh(structured_mesh(PlateStator(), 2), tmp_path / "p.msh")
    text = good.read_text()
    cut = tmp_path / "cut.msh"
    cut.write_text(text[: len(text) // 2])
    with pytest.raises(ValueError, match="could not read mesh file .*cut.msh"):
        read_stator_mesh(cut)
    for value in ("nan", "inf"):
        lines = text.splitlines()
        start = lines.index("$Nodes")
        # the first coordinate line after the node tags of the first entity block
        i = next(k for k in range(start + 3, len(lines)) if len(lines[k].split()) == 3
                 and "." in lines[k])
        x, y, z = lines[i].split()
        lines[i] = f"{value} {y} {z}"
        bad = tmp_path / f"{value}.msh"
        bad.write_text("\n".join(lines) + "\n")
        with pytest.raises(ValueError, match="non-finite coordinate"):
            read_stator_mesh(bad)
