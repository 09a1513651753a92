"""3D piezoelastic reference model (fem.solid3d.model): matrices, rigid modes, 2D vs 3D limits."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fem.geometry import PlateStator
from fem.mesh_settings import MeshSettings
from fem.modes import plate_modes
from fem.solid3d.model import build_solid_model, solid_frequencies_Hz, solid_model, solid_modes
from lusm.cli import main

COARSE = MeshSettings(refine=2, layers=2)


@pytest.fixture(scope="module")
def coarse_model():
    return solid_model(PlateStator(), "pzt8", COARSE)


def test_matrices_symmetric_and_mass_total(coarse_model):
    m = coarse_model
    for a in (m.Kuu, m.M, m.Kphiphi):
        assert abs(a - a.T).max() <= 1e-12 * abs(a).max()
    # total mass: a rigid translation along x carries rho * volume
    n = m.n_nodes
    tx = np.zeros(3 * n)
    tx[:n] = 1.0
    st = m.stator
    vol = st.length_m * st.width_m * st.thickness_m
    assert tx @ (m.M @ tx) == pytest.approx(7600.0 * vol, rel=1e-12)
    # a uniform potential stores no energy and couples to nothing
    ones = np.ones(n)
    assert np.abs(m.Kphiphi @ ones).max() < 1e-12 * abs(m.Kphiphi).max()
    assert np.abs(m.Kuphi @ ones).max() < 1e-9 * abs(m.Kuphi).max()


def test_six_rigid_body_modes(coarse_model):
    f, _ = solid_frequencies_Hz(coarse_model, n_modes=8, f_center_Hz=0.0)
    assert np.all(np.abs(f[:6]) < 1.0)
    assert f[6] > 5e3


def test_electrodes_are_disjoint_and_on_top(coarse_model):
    m = coarse_model
    h = m.stator.thickness_m
    all_dofs = np.concatenate(m.electrode_dofs)
    assert all_dofs.size == np.unique(all_dofs).size
    assert np.allclose(m.basis.doflocs[2, all_dofs], h / 2)
    assert np.allclose(m.basis.doflocs[2, m.ground_dofs], -h / 2)


@pytest.mark.slow
def test_default_plate_3d_vs_2d_and_open_above_short():
    r3 = solid_modes(PlateStator(), "pzt8")  # default 3D mesh
    r2 = plate_modes(PlateStator(), "pzt8")
    for name in ("L1", "B2"):
        a, b = getattr(r3, name), getattr(r2, name)
        assert a.f_open_Hz >= a.f_short_Hz
        assert a.f_short_Hz == pytest.approx(b.f_short_Hz, rel=0.01)
        assert a.f_open_Hz == pytest.approx(b.f_open_Hz, rel=0.02)
        assert a.mac > 0.9
    assert r3.dofs > 0 and r3.wall_time_s > 0


@pytest.mark.slow
def test_thin_plate_approaches_plane_stress():
    """As h -> 0 plane stress becomes exact: the 3D/2D gap shrinks well below the 3 mm one.

    The 0.5 mm gap of the 0.1 mm plate is five thicknesses wide: nothing shorts it, so the
    2D model takes its ``D3 = 0`` gap (``gap_model='open'``); the thick plate compares the
    earlier 2D model too, so that the ratio measures the thickness effect alone."""
    thick = PlateStator()
    thin = PlateStator(thickness_m=0.1e-3)
    errs = {}
    for key, st in (("thick", thick), ("thin", thin)):
        r3 = solid_modes(st, "pzt8", MeshSettings(2, 3, 1 if key == "thin" else 2))
        r2 = plate_modes(st, "pzt8", mesh=MeshSettings(gap_model="open", thickness_inertia=False))
        errs[key] = max(
            abs(getattr(r3, n).__getattribute__(f) / getattr(r2, n).__getattribute__(f) - 1)
            for n in ("L1", "B2") for f in ("f_short_Hz", "f_open_Hz")
        )
    assert errs["thin"] < 2e-3
    assert errs["thin"] < errs["thick"] / 4


@pytest.mark.slow
def test_thin_plate_modal_force_factors_match_2d():
    """Modal force per volt (drive 1 + 4) of a thin plate: 3D vs 2D, up to the sign convention."""
    from fem.model import plate_model

    st = PlateStator(thickness_m=0.1e-3)
    mesh3 = MeshSettings(2, 3, 1)
    m3, r3 = solid_model(st, "pzt8", mesh3), solid_modes(st, "pzt8", mesh3)
    mesh2 = MeshSettings(gap_model="open", thickness_inertia=False)  # gap = 5 h: unshorted
    m2, r2 = plate_model(st, mesh=mesh2), plate_modes(st, mesh=mesh2)
    f3, g2 = m3.voltage_coupling_N_V((1, 4)), m2.coupling((1, 4))
    for name, tol in (("L1", 0.04), ("B2", 0.01)):
        a3 = abs(getattr(r3, name).shape @ f3)
        a2 = abs(getattr(r2, name).shape @ g2)
        assert a3 == pytest.approx(a2, rel=tol)
    with pytest.raises(ValueError, match="electrodes"):
        m3.voltage_coupling_N_V((0,))


def test_bad_input():
    with pytest.raises(ValueError, match="layers"):
        solid_model(PlateStator(), mesh=MeshSettings(layers=0))
    with pytest.raises(ValueError, match="element"):
        solid_model(PlateStator(), mesh=MeshSettings(element="hex64"))
    with pytest.raises(ValueError, match="gap"):
        build_solid_model(PlateStator(electrode_gap_m=0.0))


@pytest.mark.slow
def test_cli_modes_3d_json_keys(capsys):
    assert main(["modes", "--model", "3d", "--refine", "2", "--layers", "2", "--json"]) == 0
    out3 = json.loads(capsys.readouterr().out)
    assert main(["modes", "--json"]) == 0
    out2 = json.loads(capsys.readouterr().out)
    assert set(out2) <= set(out3)
    assert set(out3["L1"]) == set(out2["L1"]) == {"f_short_Hz", "f_open_Hz", "k_eff"}
    assert out3["model"] == "3d" and out3["layers"] == 2
    assert main(["modes", "--model", "3d", "--layers", "0"]) == 2


@pytest.mark.slow
def test_edge_grading_refines_at_the_electrode_edges():
    """Grading towards the electrode edges (issue 8): lines at the gap centre and g outside
    each edge, a layer g below the top face; B2's k_eff, underestimated by uniform meshes
    (one element across the gap, where the potential is singular), rises towards the graded
    value (0.118 on the default mesh, 0.1245 with three grading levels, docs/fem3d.md).
    Trilinear bricks: the grid lines and the rise do not depend on the order, and the graded
    quadratic mesh costs ten times as much; the rise on the default quadratic mesh is
    test_solid3d_symmetric's ungraded-note test."""
    from fem.solid3d.model import modes_of_solid_model

    st = PlateStator()
    m0 = build_solid_model(st, "pzt8", MeshSettings(1, 2, 1))
    m1 = build_solid_model(st, "pzt8", MeshSettings(1, 2, 1, edge_grading=1))
    x, z = m1.basis.mesh.p[0], m1.basis.mesh.p[2]
    g = st.electrode_gap_m
    for xv in (0.0, g / 2 + g, -g / 2 - g):
        assert np.any(np.abs(x - xv) < 1e-12)
    assert np.any(np.abs(z - (st.thickness_m / 2 - g)) < 1e-12)
    owner = np.zeros(m1.n_nodes, dtype=int)
    for k, dofs in enumerate(m1.electrode_dofs, start=1):
        assert np.all(owner[dofs] == 0)
        owner[dofs] = k
    k0 = modes_of_solid_model(m0).B2.k_eff
    k1 = modes_of_solid_model(m1).B2.k_eff
    assert k1 > k0 * 1.1
    with pytest.raises(ValueError, match="edge_grading"):
        build_solid_model(st, "pzt8", MeshSettings(2, 2, 1, edge_grading=-1))


def test_3d_runs_are_bit_identical():
    """A fixed ARPACK start vector: two solves of the same model agree to the last bit."""
    m = build_solid_model(PlateStator(), "pzt8", MeshSettings(2, 2, 1))
    f1, v1 = solid_frequencies_Hz(m, 6, 56e3, open_circuit=True)
    f2, v2 = solid_frequencies_Hz(m, 6, 56e3, open_circuit=True)
    assert np.array_equal(f1, f2) and np.array_equal(v1, v2)


@pytest.mark.slow
def test_an_ungraded_mesh_across_a_narrow_gap_is_said_so(capsys):
    """At 0.1 mm the default brick mesh keeps one element across the gap beside elements
    25 x wider: its B2 k_eff is far below the 2D model's (which graded 3D meshes approach,
    docs/fem3d.md), and nothing said so. At the paper's 0.5 mm gap (ratio 4.9) it stays
    silent. A narrower gap failed with an open-circuit pairing error blaming the plate."""
    import json

    from fem.solid3d.model import gap_element_ratio
    from lusm.cli import main

    assert gap_element_ratio(PlateStator(), 3, 3) < 10 < gap_element_ratio(
        PlateStator(electrode_gap_m=0.1e-3), 3, 3)
    assert main(["modes", "--model", "3d", "--quick", "--gap-mm", "0.1", "--json"]) == 0
    out = capsys.readouterr()
    assert "25 x wider than it" in out.err and "--edge-grading" in out.err
    k3 = json.loads(out.out)["B2"]["k_eff"]
    assert main(["modes", "--gap-mm", "0.1", "--json"]) == 0
    k2 = json.loads(capsys.readouterr().out)["B2"]["k_eff"]
    assert k3 < 0.85 * k2
    assert main(["modes", "--model", "3d", "--quick", "--json"]) == 0
    assert "wider than it" not in capsys.readouterr().err


@pytest.mark.slow
def test_affine_probes_match_scikit_fem_and_rescue_a_micrometre_gap_in_3d():
    """--model 3d --gap-mm 0.0012: scikit-fem's Newton inverse of the hex map stalled ("Newton
    iteration didn't converge"), and --gap-mm 0.001 was refused with an internal class name
    (found by exploratory testing). The affine inverse agrees with scikit-fem's where that
    converges, and the frequencies run on smoothly from 1.8 um, which scikit-fem solved.
    One layer: the micrometre gap is in the plane, and the default in-plane mesh keeps the
    default mesh's smoothness (B2 1.4e-7 apart from 1 to 1.8 um with one layer or three)."""
    from fem.model import affine_probes
    from fem.solid3d.model import modes_of_solid_model, solid_model

    one_layer = MeshSettings(layers=1)
    m = solid_model(mesh=one_layer)
    rng = np.random.default_rng(1)
    pts = np.vstack((rng.uniform(-3.7e-3, 3.7e-3, 200), rng.uniform(0.0, 30e-3, 200),
                     rng.uniform(-1.5e-3, 1.5e-3, 200)))
    assert abs(affine_probes(m.basis, pts) - m.basis.probes(pts).tocsr()).max() < 1e-12
    f = {g: modes_of_solid_model(solid_model(PlateStator(electrode_gap_m=g), mesh=one_layer))
         for g in (1e-6, 1.2e-6, 1.8e-6)}
    for mode in ("L1", "B2"):
        a, b, c = (getattr(f[g], mode).f_short_Hz for g in (1e-6, 1.2e-6, 1.8e-6))
        assert a == pytest.approx(c, rel=1e-6) and min(a, c) - 1e-3 <= b <= max(a, c) + 1e-3
