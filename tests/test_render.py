"""Offscreen rendering of mode shapes (fem.render, lusm render) and mode export (fem.export)."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

pv = pytest.importorskip("pyvista")
pv.OFF_SCREEN = True

from fem.export import export_modes, vertex_displacements  # noqa: E402
from fem.geometry import PlateStator  # noqa: E402
from fem.mesh_settings import MeshSettings  # noqa: E402
from fem.model import plate_model  # noqa: E402
from fem.modes import plate_modes  # noqa: E402
from fem.render import (  # noqa: E402
    centre_line_offset_px,
    mirror_difference,
    mode_image,
    render_mode_gif,
    render_mode_png,
)

SMALL = (480, 200)


@pytest.fixture(scope="module")
def plate():
    return plate_model(PlateStator(), "pzt8",
                       MeshSettings(2, 4)), plate_modes(PlateStator(), "pzt8", MeshSettings(2, 4))


@pytest.fixture(scope="module")
def images(plate):
    model, modes = plate
    return {
        m.name: mode_image(model, m, decorations=False, window_size=SMALL).astype(float)
        for m in (modes.L1, modes.B2)
    }


@pytest.mark.slow
def test_images_are_not_blank_and_differ(images):
    for img in images.values():
        assert img.shape == (SMALL[1], SMALL[0], 3)
        assert img.std() > 20.0  # a white or single-colour image has std ~ 0
        assert np.mean(np.all(img > 250, axis=-1)) > 0.2  # white background around the plate
    assert np.mean(np.abs(images["L1"] - images["B2"])) > 10.0


@pytest.mark.slow
def test_L1_image_is_symmetric_about_the_long_axis_and_B2_is_not(images):
    sym_l1 = mirror_difference(images["L1"])
    sym_b2 = mirror_difference(images["B2"])
    assert sym_l1 < 0.3 * sym_b2, (sym_l1, sym_b2)
    # where they differ: the plate's deformed centre line stays on the axis for L1 and leaves
    # it for B2 (bending)
    offsets = {name: centre_line_offset_px(img) for name, img in images.items()}
    assert offsets["L1"] < 1.5, offsets
    assert offsets["B2"] > 6.0, offsets


@pytest.mark.slow
def test_png_and_gif_files(tmp_path, plate):
    from PIL import Image

    model, modes = plate
    png = render_mode_png(tmp_path / "L1.png", model, modes.L1, window_size=SMALL)
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size == SMALL
        assert np.asarray(im.convert("RGB"), dtype=float).std() > 20.0
    gif = render_mode_gif(tmp_path / "B2.gif", model, modes.B2, n_frames=4,
                          window_size=SMALL, decorations=False)
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.n_frames == 4
        frames = []
        for k in range(4):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGB"), dtype=float))
    # phase 0 and pi are mirror images (cos(pi) = -1 flips u_x): the B2 picture flips
    np.testing.assert_array_less(5.0, np.mean(np.abs(frames[0] - frames[2])))
    assert np.mean(np.abs(frames[0] - frames[2][::-1])) < 0.5 * np.mean(
        np.abs(frames[0] - frames[2])
    )


@pytest.mark.slow
def test_cli_render(tmp_path, capsys):
    from lusm.cli import main

    assert main(["render", "--mode", "L1", "--out", str(tmp_path), "--refine", "3"]) == 0
    assert (tmp_path / "L1.png").is_file() and not (tmp_path / "B2.png").exists()
    assert str(tmp_path / "L1.png") in capsys.readouterr().out
    assert main(["render", "--geometry", str(tmp_path / "none.toml")]) == 2


@pytest.mark.parametrize("suffix", [".vtu", ".vtk", ".msh"])  # .msh: gmsh's, not ANSYS's
def test_export_round_trips_the_mode_shapes(tmp_path, plate, suffix):
    model, modes = plate
    path = export_modes(tmp_path / f"modes{suffix}", model, modes, n_modes=6)
    m = meshio.read(path)
    np.testing.assert_allclose(m.points[:, :2].T, model.mesh.points_m, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(m.cells_dict["quad"].T, model.mesh.quads)
    np.testing.assert_array_equal(np.concatenate(m.cell_data["electrode"]), model.mesh.electrode)
    for mode in (modes.L1, modes.B2):
        u = np.asarray(m.point_data[mode.name])
        np.testing.assert_allclose(u[:, :2].T, vertex_displacements(model, mode.shape),
                                   rtol=1e-12, atol=0)
        assert np.all(u[:, 2] == 0.0)
    # vertex values are the field itself: probing the FE field at the preload vertex agrees
    i = int(np.argmin(np.hypot(*model.mesh.points_m)))
    P = model.probe(model.mesh.points_m[:, [i]] * (1 - 1e-12))
    np.testing.assert_allclose(P @ modes.L1.shape, m.point_data["L1"][i, :2], rtol=1e-9)
    # the extra modes carry their frequencies; L1 and B2 are among them
    extra = [k for k in m.point_data if k.startswith("mode_")]
    freqs = [float(k.split("_")[2][:-2]) for k in extra]
    assert 2 <= len(extra) <= 6 and min(freqs) > 1e3  # the 0 Hz rigid-body modes are dropped
    for mode in (modes.L1, modes.B2):
        assert min(abs(f - mode.f_short_Hz) for f in freqs) < 1.0


@pytest.mark.slow
def test_cli_modes_export(tmp_path):
    from lusm.cli import main

    out = tmp_path / "m.vtu"
    assert main(["modes", "--refine", "3", "--export", str(out)]) == 0
    assert {"L1", "B2"} <= set(meshio.read(out).point_data)
    assert main(["modes", "--refine", "3", "--export", str(tmp_path / "m.unknownext")]) == 2


@pytest.mark.parametrize("suffix", [".stl", ".ply"])
def test_formats_that_drop_the_shapes_are_refused(tmp_path, suffix, capsys):
    # .stl wrote a 15-byte file (triangles only) and .ply dropped the vectors, both "wrote"
    from lusm.cli import main

    assert main(["modes", "--refine", "3", "--export", str(tmp_path / f"m{suffix}")]) == 2
    assert "cannot carry the mode shapes" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


@pytest.mark.slow
def test_an_xdmf_kept_by_force_still_reads_its_own_data(tmp_path, capsys):
    """--force keeps m.xdmf and m.h5 as .bak-1; the kept .xdmf must read the kept .h5 (it
    pointed at the new m.h5 and showed the new plate)."""
    pytest.importorskip("h5py")
    from lusm.cli import main

    out = tmp_path / "m.xdmf"
    assert main(["modes", "--refine", "3", "--export", str(out)]) == 0
    assert main(["modes", "--refine", "3", "--width-mm", "8", "--export", str(out),
                 "--force"]) == 0
    width = {f: np.ptp(meshio.read(tmp_path / f, file_format="xdmf").points[:, 0])
             for f in ("m.xdmf", "m.xdmf.bak-1")}
    assert width["m.xdmf"] == pytest.approx(8e-3)
    assert width["m.xdmf.bak-1"] == pytest.approx(7.5e-3)


@pytest.mark.slow
def test_headless_render_prints_nothing_on_stderr(tmp_path):
    """With no display, rendering selects EGL itself instead of letting VTK try X first and
    print 'bad X server connection' (issue 13: no VTK warning on stderr)."""
    import ctypes.util
    import os
    import subprocess
    import sys

    if ctypes.util.find_library("EGL") is None:
        pytest.skip("no libEGL: VTK's own fallback order applies")
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")}
    p = subprocess.run([sys.executable, "-m", "lusm.cli", "render", "--out",
                        str(tmp_path / "r"), "--mode", "L1"], capture_output=True, text=True,
                       env=env, cwd=tmp_path, timeout=300)
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""
    assert (tmp_path / "r" / "L1.png").stat().st_size > 1000


@pytest.mark.slow
def test_exports_skip_rigid_body_modes_and_work_in_3d(tmp_path):
    """``--export``: no rigid-body (0 Hz) mode among the extra 2D modes; with ``--model 3d`` a
    VTU of hexahedra whose L1 is axial (u_y, antisymmetric about mid-length) and whose B2 is
    transverse on the long axis (u_x there), as the modes are (issue 13)."""
    import re

    from lusm.cli import main

    out2 = tmp_path / "m2.vtu"
    assert main(["modes", "--refine", "2", "--export", str(out2)]) == 0
    freqs = [float(m.group(1)) for n in meshio.read(out2).point_data
             if (m := re.fullmatch(r"mode_\d+_(\d+)Hz", n))]
    assert freqs and min(freqs) > 1e3
    out3 = tmp_path / "m3.vtu"
    assert main(["modes", "--model", "3d", "--refine", "2", "--layers", "1", "--export",
                 str(out3)]) == 0
    m3 = meshio.read(out3)
    assert m3.cells[0].type == "hexahedron"
    y = m3.points[:, 1]
    l1, b2 = m3.point_data["L1"], m3.point_data["B2"]
    assert np.abs(l1[:, 1]).max() > 3 * np.abs(l1[:, 0]).max()
    x = m3.points[:, 0]
    axis = np.isclose(np.abs(x), np.abs(x).min())  # the points nearest the long axis
    assert np.abs(b2[axis, 0]).max() > 3 * np.abs(b2[axis, 1]).max()  # bends across it
    ends = np.isclose(y, y.min()) | np.isclose(y, y.max())
    assert np.sign(l1[np.isclose(y, y.min()), 1]).mean() == -np.sign(
        l1[np.isclose(y, y.max()), 1]).mean() and ends.any()


@pytest.mark.parametrize("width_mm", [12.0, 16.0])
@pytest.mark.slow
def test_a_wide_plates_ruler_and_plate_stay_between_title_and_colour_bar(width_mm):
    """From a width of about 0.4 of the length the mm ruler was drawn through the title and
    the plate over the colour bar's label. Measured on the default picture: the title ends
    about a quarter of the half-height below the top, the bar begins a third above the
    bottom. The ruler's line and the deformed plate at either extreme of its swing must stay
    inside that band; the default plate keeps its view (bound by its length)."""
    from fem.render import DECORATED_BAND, SCALE_FRACTION, WINDOW_SIZE, _Scene, _title

    st = PlateStator(width_m=width_mm * 1e-3)
    model, modes = plate_model(st, "pzt8", MeshSettings(2, 4)), plate_modes(st, "pzt8",
                                                                            MeshSettings(2, 4))
    for mode in (modes.L1, modes.B2):
        scene = _Scene(model, mode.shape, _title(mode, st), WINDOW_SIZE, SCALE_FRACTION,
                       True, 1)
        try:
            half = scene.plotter.camera.parallel_scale
            swing = np.abs(scene.pts[0]) + np.abs(scene.disp[0])  # across the width (m)
            ruler = 0.5 * st.width_m + 1.4 * SCALE_FRACTION * st.length_m
            assert swing.max() <= DECORATED_BAND * half
            assert ruler <= DECORATED_BAND * half
        finally:
            scene.close()


def test_lusm_render_draws_with_the_signals_held(monkeypatch, tmp_path):
    """A Ctrl-C inside VTK's rendering (about three seconds with --animate) printed VTK
    errors: the pictures are drawn with SIGINT and SIGTERM held, delivered once they are
    done, and nothing is moved in."""
    import signal

    import fem.render
    from contact import deferred_signals
    from lusm.cli import main

    seen = []

    def draw(*args, **kwargs):
        seen.append(signal.getsignal(signal.SIGINT) is deferred_signals._record)
        return []

    monkeypatch.setattr(fem.render, "render_modes", draw)
    assert main(["render", "--animate", "--refine", "4", "--out", str(tmp_path / "r")]) == 0
    assert seen == [True]
    assert signal.getsignal(signal.SIGINT) is not deferred_signals._record  # released


# --- 3D pictures (fem.render3d, lusm render --model 3d) --------------------------------------

SOLID = MeshSettings(refine=2, layers=2)
"""A cheap 3D mesh: the pictures' checks need the shapes' classes, not converged frequencies."""


@pytest.fixture(scope="module")
def solid_band():
    from fem.band import band_shapes
    from fem.solid3d.model import solid_model

    model = solid_model(PlateStator(), "pzt8", SOLID)
    return model, {m.name: m for m in band_shapes(model, 44e3, 60e3)}


@pytest.mark.slow
def test_the_3d_picture_is_not_blank_and_its_box_moves_with_the_mode(solid_band):
    from fem.render3d import Scene3D

    model, band = solid_band
    moved = {}
    for name in ("L1", "B2"):
        scene = Scene3D(model, band[name], window_size=SMALL, decorations=False)
        try:
            scene.frame(0.5 * np.pi)  # cos = 0: the undeformed solid
            rest = np.array(scene.bounds_m())
            scene.frame(0.0)
            img = scene.image().astype(float)
            moved[name] = np.abs(np.array(scene.bounds_m()) - rest) / 30e-3
        finally:
            scene.close()
        assert img.std() > 20.0 and np.mean(np.all(img > 250, axis=-1)) > 0.2
        assert np.mean(np.any(img < 200, axis=-1)) > 0.05  # the solid covers part of it
    # drawn at 6 % of the length: L1 stretches the length (y), B2 bends across (x)
    assert max(moved["L1"][2:4]) > 0.03 and max(moved["L1"][0:2]) < max(moved["L1"][2:4])
    assert max(moved["B2"][0:2]) > 0.03 and max(moved["B2"][2:4]) < max(moved["B2"][0:2])


@pytest.mark.slow
def test_the_potential_is_signed_and_zero_on_the_electrodes(solid_band):
    from fem.render3d import mode_potential

    model, band = solid_band
    phi = mode_potential(model, band["B2"].shape)
    assert np.max(phi) > 0.0 > np.min(phi)
    for dofs in (*model.electrode_dofs, model.ground_dofs):
        assert np.all(phi[dofs] == 0.0)


@pytest.mark.slow
def test_cli_render_3d_any_mode_png_and_gif(tmp_path, capsys):
    from lusm.cli import main

    out = tmp_path / "r"
    base = ["render", "--model", "3d", "--refine", "2", "--layers", "2", "--out", str(out)]
    assert main([*base, "--band", "44:60", "--mode", "1", "--color", "potential",
                 "--animate"]) == 0
    written = capsys.readouterr().out.split()
    assert [p.rsplit(".", 1)[1] for p in written] == ["png", "gif"]
    assert all((out / p.rsplit("/", 1)[1]).stat().st_size > 5_000 for p in written)
    first = sorted(p.name for p in out.glob("*.*"))
    assert main(base) == 0  # a folder lusm wrote: L1 and B2 go in beside the others
    assert sorted(p.name for p in out.glob("*.*")) == sorted([*first, "3d_B2.png",
                                                              "3d_L1.png"])
    assert main([*base, "--band", "44:60", "--mode", "9"]) == 2  # beyond the band's rows
    assert "holds" in capsys.readouterr().err
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "x.txt").write_text("x")
    assert main([*base[:-1], str(tmp_path / "mine")]) == 2  # the user's folder: refused
