"""The example stators in examples/: they load, identify L1/B2, and shift the frequencies of
the plain plate in the physically expected direction by the amount first-order perturbation
theory predicts from the plain plate's own mode shapes."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from fem.geometry import PlateStator
from fem.mesh_settings import MeshSettings
from fem.meshing.mesh_io import read_stator_mesh, write_stator_msh
from fem.meshing.meshed_stator import MeshedStator
from fem.model import build_model, plate_model
from fem.modes import modes_of_model, plate_modes
from fem.stator_file import load_stator

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RHO_H = 7600.0 * 3e-3  # PZT-8 density times thickness (kg/m^2)


def _script(name: str):
    path = EXAMPLES / name / "make_mesh.py"
    spec = importlib.util.spec_from_file_location(f"make_mesh_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def plain():
    """The plain 30 x 7.5 x 3 mm plate (converged mesh) and its model."""
    return plate_modes(PlateStator(), "pzt8",
                       MeshSettings(2, 8)), plate_model(PlateStator(), "pzt8", MeshSettings(2, 8))


@pytest.fixture(scope="module")
def tip():
    d = load_stator(EXAMPLES / "tip_protrusion" / "stator.toml")
    return d, d.modes()


@pytest.fixture(scope="module")
def chamfer():
    d = load_stator(EXAMPLES / "chamfered" / "stator.toml")
    return d, d.modes()


def _mean_sq(model, shape, points):
    """Mean of |u|^2 of a dof vector over sample points (2, n)."""
    u = (model.probe(points) @ shape).reshape(2, -1)
    return float(np.mean(np.sum(u * u, axis=0)))


@pytest.mark.parametrize("name", ["tip_protrusion", "chamfered"])
def test_shipped_mesh_is_what_the_script_generates(tmp_path, name):
    script = _script(name)
    build = script.protrusion_mesh if name == "tip_protrusion" else script.chamfered_mesh
    ctype = "quad" if name == "tip_protrusion" else "triangle"
    fresh = write_stator_msh(tmp_path / "m.msh", *build())
    unit = "mm" if name == "tip_protrusion" else "m"
    a = read_stator_mesh(EXAMPLES / name / f"{name}.msh", unit)
    b = read_stator_mesh(fresh, unit)
    np.testing.assert_array_equal(a.mesh.points_m, b.mesh.points_m)
    np.testing.assert_array_equal(a.mesh.electrode, b.mesh.electrode)
    assert a.points_m == b.points_m and set(a.points_m) == {"tip", "preload"}
    assert a.cell_types == (ctype,) and a.converted == (ctype == "triangle")


@pytest.mark.slow
def test_tip_protrusion_loads_with_its_points(tip):
    d, res = tip
    assert isinstance(d.stator, MeshedStator)
    assert d.stator.length_m == pytest.approx(31e-3) and d.stator.width_m == pytest.approx(7.5e-3)
    np.testing.assert_allclose(d.stator.tip_point_m, (0.0, 31e-3), atol=1e-12)
    np.testing.assert_allclose(d.stator.preload_point_m, (0.0, 0.0), atol=1e-12)
    # the protrusion carries no electrode: electroded area = plate minus the gap strips
    area = {k: 0.0 for k in range(5)}
    m = d.stator.mesh
    p = m.points_m[:, m.quads]
    a = 0.5 * np.abs((p[0, 2] - p[0, 0]) * (p[1, 3] - p[1, 1])
                     - (p[0, 3] - p[0, 1]) * (p[1, 2] - p[1, 0]))
    for k in range(5):
        area[k] = float(a[m.electrode == k].sum())
    quadrant = (7.5e-3 - 0.5e-3) / 2 * (30e-3 - 0.5e-3) / 2
    np.testing.assert_allclose([area[k] for k in (1, 2, 3, 4)], quadrant, rtol=1e-12)
    assert area[0] == pytest.approx(30e-3 * 7.5e-3 - 4 * quadrant + 2e-3 * 1e-3, rel=1e-12)
    assert res.L1.mac > 0.95 and res.B2.mac > 0.9


@pytest.mark.slow
def test_tip_mass_lowers_both_modes_as_perturbation_theory_predicts(plain, tip):
    ref, model = plain
    _, res = tip
    dm = RHO_H * 2e-3 * 1e-3  # protrusion mass (kg)
    xs = np.linspace(-1e-3, 1e-3, 21)
    end = np.vstack((xs, np.full_like(xs, 30e-3)))
    for name, rtol in (("L1", 0.03), ("B2", 0.25)):
        f0, f1 = getattr(ref, name).f_short_Hz, getattr(res, name).f_short_Hz
        shift = f1 / f0 - 1.0
        # added rigid mass at the tip end: d(omega^2)/omega^2 = -dm |phi|^2 (phi: M-normalized)
        predicted = -0.5 * dm * _mean_sq(model, getattr(ref, name).shape, end)
        assert -0.03 < shift < -0.003, (name, shift)
        assert shift == pytest.approx(predicted, rel=rtol), (name, shift, predicted)


@pytest.mark.slow
def test_chamfers_raise_both_modes_as_perturbation_theory_predicts(plain, chamfer):
    ref, model = plain
    d, res = chamfer
    assert d.notes and "triangle" in d.notes[0]
    assert res.L1.mac > 0.95 and res.B2.mac > 0.9
    c, w2, length = 1.5e-3, 3.75e-3, 30e-3
    g = np.linspace(0.0, 1.0, 41)[1:-1]
    u, v = np.meshgrid(g, g)
    keep = u + v > 1.0  # the removed corner triangle, sampled uniformly
    pts = []
    for sx in (1.0, -1.0):
        for far in (False, True):
            y = c - v[keep] * c
            pts.append(np.vstack((sx * (w2 - c + u[keep] * c), length - y if far else y)))
    removed = np.hstack(pts) * (1.0 - 1e-9)
    dm = RHO_H * 4 * c * c / 2
    for name, rtol in (("L1", 0.03), ("B2", 0.15)):
        f0, f1 = getattr(ref, name).f_short_Hz, getattr(res, name).f_short_Hz
        shift = f1 / f0 - 1.0
        # mass removed near the free ends, where the strain energy density is small
        predicted = 0.5 * dm * _mean_sq(model, getattr(ref, name).shape, removed)
        assert 0.005 < shift < 0.05, (name, shift)
        assert shift == pytest.approx(predicted, rel=rtol), (name, shift, predicted)


@pytest.mark.slow
def test_triangle_meshes_reproduce_the_quad_plate(tmp_path, plain):
    """Triangles -> 3 quads each: the triangulated plain plate matches the structured one."""
    ref, _ = plain
    path = write_stator_msh(tmp_path / "t.msh", *_script("chamfered").chamfered_mesh(chamfer_m=0.0),
                            file_format="gmsh22")
    imp = read_stator_mesh(path)
    st = MeshedStator(length_m=30e-3, width_m=7.5e-3, thickness_m=3e-3, electrode_gap_m=0.0,
                      mesh=imp.mesh, tip_m=imp.points_m["tip"], preload_m=(0.0, 0.0))
    res = modes_of_model(build_model(imp.mesh, st, "pzt8", 2))
    assert res.L1.f_short_Hz == pytest.approx(ref.L1.f_short_Hz, rel=2e-5)
    assert res.B2.f_short_Hz == pytest.approx(ref.B2.f_short_Hz, rel=5e-5)
    assert res.L1.f_open_Hz == pytest.approx(ref.L1.f_open_Hz, rel=5e-5)


@pytest.mark.slow
def test_example_parameter_sets(tip, chamfer):
    from rom.from_fem import fem_params_from_file

    for name in ("tip_protrusion", "chamfered"):
        p = fem_params_from_file(EXAMPLES / name / "stator.toml")
        assert p.phi_L0 == pytest.approx(1.0) and p.phi_Bl == pytest.approx(1.99845, rel=1e-4)
        assert p.A_l > 0 and p.A_b < 0  # Table 2's signs for drive 1 & 4
        assert name in p.source


def test_the_beam_column_is_the_electroded_body_for_either_description(capsys):
    """The tip protrusion as a mesh file and as a [tip] table is one stator: compare's beam
    column took the mesh's 31 mm bounding box (L1 65.7 kHz) but the table's 30 mm body
    (67.9 kHz)."""
    import argparse

    from lusm.options import beam_of_plate

    def beam(path):
        return beam_of_plate(argparse.Namespace(geometry=str(path), model=None))

    mesh = beam(EXAMPLES / "tip_protrusion" / "stator.toml")
    table = beam(EXAMPLES / "tip_parametric" / "stator.toml")
    plain = beam_of_plate(argparse.Namespace(geometry=None, model=None, length_mm=30.0))
    for p in (mesh, table):
        assert p.K_l / p.M_l == pytest.approx(plain.K_l / plain.M_l, rel=1e-12)
        assert p.K_b / p.M_b == pytest.approx(plain.K_b / plain.M_b, rel=1e-12)


def test_an_alumina_tip_lightens_the_tip_end():
    """examples/tip_alumina is examples/tip_parametric with its tip of alumina (half PZT-8's
    density, twice its stiffness): the tip end, an antinode of both modes, is lighter, so
    L1 and B2 rise, by the few hundred hertz a 2 mm^2 tip's mass is worth; the header names
    the tip's material."""
    ceramic = load_stator(EXAMPLES / "tip_parametric" / "stator.toml")
    alumina = load_stator(EXAMPLES / "tip_alumina" / "stator.toml")
    assert alumina.stator.tip_material == "alumina" and ceramic.stator.tip_material == ""
    assert "alumina)" in alumina.stator.features_text()
    a, c = alumina.modes(), ceramic.modes()
    for m in ("L1", "B2"):
        shift = getattr(a, m).f_short_Hz / getattr(c, m).f_short_Hz - 1
        assert 1e-3 < shift < 1e-2, (m, shift)
