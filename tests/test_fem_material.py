"""Material constants and their plane-stress reduction (fem.material)."""

from __future__ import annotations

import numpy as np
import pytest

from fem.material import (
    EPS0_F_M,
    MATERIAL_NAMES,
    PiezoMaterial,
    get_material,
    paper_material,
    plane_stress,
    pzt8,
)
from fem.mesh_settings import MeshSettings


def test_pzt8_stiffness_form_reproduces_the_published_compliance_form():
    mat = pzt8()
    s = np.linalg.inv(mat.cE_Pa)
    assert s[0, 0] == pytest.approx(11.5e-12, rel=1e-12)
    assert s[0, 1] == pytest.approx(-3.7e-12, rel=1e-12)
    assert s[0, 2] == pytest.approx(-4.8e-12, rel=1e-12)
    assert s[2, 2] == pytest.approx(13.5e-12, rel=1e-12)
    d = mat.e_C_m2 @ s  # d = e s^E
    assert d[2, 0] == pytest.approx(-97e-12, rel=1e-10)
    assert d[2, 2] == pytest.approx(225e-12, rel=1e-10)
    # eps^T = eps^S + d c^E d^T
    eps_t = mat.epsS_F_m + d @ mat.cE_Pa @ d.T
    assert eps_t[2, 2] / EPS0_F_M == pytest.approx(1000.0, rel=1e-10)
    # commonly tabulated stiffness values of PZT-8 (1e10 Pa): c11 ~ 14.9, c33 ~ 13.2
    assert mat.cE_Pa[0, 0] == pytest.approx(14.7e10, rel=0.02)
    assert mat.e_C_m2[2, 2] == pytest.approx(14.0, rel=0.02)
    assert "Berlincourt" in mat.source


def test_plane_stress_modulus_equals_uniaxial_compliance():
    """Under T1 = T3 = 0 and E3 = 0 the axial modulus of the plate must be 1/s11^E."""
    mat = pzt8()
    ps = plane_stress(mat)
    s = np.linalg.inv(mat.cE_Pa)
    assert ps.young_modulus_Pa(1) == pytest.approx(1.0 / s[1, 1], rel=1e-12)
    assert ps.young_modulus_Pa(0) == pytest.approx(1.0 / s[0, 0], rel=1e-12)
    np.testing.assert_allclose(ps.c_Pa, ps.c_Pa.T)
    # c66 unchanged, in-plane isotropy: c66 = (c11 - c12)/2
    assert ps.c_Pa[2, 2] == pytest.approx(mat.cE_Pa[5, 5])
    assert ps.c_Pa[2, 2] == pytest.approx(0.5 * (ps.c_Pa[0, 0] - ps.c_Pa[0, 1]), rel=1e-9)


def test_plane_stress_piezo_constants_match_compliance_form():
    """e31* = d31 / (s11 + s12) and eps33* = eps33^T - 2 d31^2 / (s11 + s12) (thin plate)."""
    mat = pzt8()
    ps = plane_stress(mat)
    s = np.linalg.inv(mat.cE_Pa)
    d = mat.e_C_m2 @ s
    eps_t = mat.epsS_F_m + d @ mat.cE_Pa @ d.T
    ssum = s[0, 0] + s[0, 1]
    assert ps.e31_C_m2 == pytest.approx(d[2, 0] / ssum, rel=1e-10)
    assert ps.e32_C_m2 == pytest.approx(ps.e31_C_m2)
    assert ps.eps33_F_m == pytest.approx(eps_t[2, 2] - 2 * d[2, 0] ** 2 / ssum, rel=1e-10)
    # unelectroded (D3 = 0) material is stiffer
    assert ps.c_open_Pa[1, 1] > ps.c_Pa[1, 1]


def test_paper_material_carries_table1_values():
    mat = paper_material()
    assert mat.cE_Pa[0, 0] == 12.6e10
    assert mat.cE_Pa[5, 5] == 3.46e10
    assert mat.e_C_m2[2, 0] == -5.2
    assert mat.rho_kg_m3 == 7600.0
    assert "Table 1" in mat.source and "pzt8" in mat.source


def test_get_material_and_hashing():
    assert get_material("pzt8") == pzt8()
    assert hash(get_material("PZT-8")) == hash(pzt8())
    assert get_material("paper") != pzt8()
    with pytest.raises(ValueError, match="pzt8, paper, pzt4, pzt5a, pzt5h, apc880"):
        get_material("pzt2")
    assert MATERIAL_NAMES == ("pzt8", "paper", "pzt4", "pzt5a", "pzt5h", "apc880")
    assert get_material("PZT-5H") == get_material("pzt5h")


def test_named_materials_carry_q_and_limits():
    """The data-sheet Q_m of the hard and soft ceramics, and the paper's material without
    one (its set keeps Table 2's damping); every named material has limits."""
    assert [get_material(n).mechanical_Q for n in MATERIAL_NAMES] == [1000.0, None, 500.0,
                                                                       75.0, 65.0, 1000.0]
    for name in MATERIAL_NAMES:
        lim = get_material(name).limits
        assert lim is not None and lim.vibration_velocity_m_s > 0 and lim.drive_field_V_m > 0
    assert get_material("pzt4") != get_material("pzt8")
    assert get_material("pzt5a").rho_kg_m3 == 7750.0


def test_combined_quality_factor_adds_inverse_q():
    from fem.material import combined_quality_factor

    assert combined_quality_factor(1000.0, 300.0) == pytest.approx(300000.0 / 1300.0,
                                                                    rel=1e-15)
    assert combined_quality_factor(1000.0, 300.0, np.inf) == combined_quality_factor(1000.0,
                                                                                      300.0)
    assert combined_quality_factor(200.0, 200.0, 200.0) == pytest.approx(200.0 / 3.0)
    with pytest.raises(ValueError):
        combined_quality_factor(1000.0, 0.0)


def test_material_rejects_bad_arrays():
    mat = pzt8()
    with pytest.raises(ValueError, match="cE_Pa"):
        PiezoMaterial("x", np.eye(5), mat.e_C_m2, mat.epsS_F_m, 7600.0)
    with pytest.raises(ValueError, match="rho_kg_m3"):
        PiezoMaterial("x", mat.cE_Pa, mat.e_C_m2, mat.epsS_F_m, -1.0)
    with pytest.raises(ValueError):
        mat.cE_Pa[0, 0] = 1.0  # read-only


# The data sheets' own figures (APC International's materials chart for the Navy-type
# equivalents: APC 840 = PZT-4, 850 = PZT-5A, 855 = PZT-5H, 880 = PZT-8, and APC 880 itself)
_CHART_K31 = {"pzt8": 0.30, "pzt4": 0.35, "pzt5a": 0.36, "pzt5h": 0.40, "apc880": 0.30}


@pytest.mark.parametrize("name", sorted(_CHART_K31))
def test_k31_of_the_constants_is_the_data_sheet_coupling(name):
    """k31 = |d31| / sqrt(s11E eps33T), recovered from the stored e-form, is the published
    k31 within 8 % (a Navy type and a vendor's equivalent differ by that much; PZT-4 against
    APC 840 is the widest, 0.327 against 0.35)."""
    from fem.material import transverse_coupling

    assert transverse_coupling(get_material(name))["k31"] == pytest.approx(_CHART_K31[name],
                                                                           rel=0.08)


def test_apc880_rebuilds_its_chart():
    """The chart's own figures come back from the derived e-form: d31, d33, YE11, KT, and
    the length mode's frequency constant N_L = 1725 Hz m within 0.5 %."""
    from fem.material import transverse_coupling

    mat = get_material("apc880")
    t = transverse_coupling(mat)
    s = np.linalg.inv(mat.cE_Pa)
    d = mat.e_C_m2 @ s
    assert 1.0 / t["s11E_m2_N"] == pytest.approx(9.0e10, rel=1e-10)
    assert 1.0 / s[2, 2] == pytest.approx(7.2e10, rel=1e-10)
    assert d[2, 0] == pytest.approx(-95e-12, rel=1e-10)
    assert d[2, 2] == pytest.approx(215e-12, rel=1e-10)
    assert d[0, 4] == pytest.approx(330e-12, rel=1e-10)
    assert t["eps33T_F_m"] / EPS0_F_M == pytest.approx(1050.0, rel=1e-10)
    assert t["N31_Hz_m"] == pytest.approx(1725.0, rel=5e-3)
    assert "APC" in mat.source and "assumption" in mat.source


@pytest.mark.parametrize("name", [n for n in MATERIAL_NAMES if n != "paper"])
def test_k31_bar_resonates_at_its_frequency_constant(name):
    """A free bar 30 x 1.5 x 0.5 mm, electroded and short-circuited, in the 2D FE: its L1 is
    f_s = 1 / (2 L sqrt(rho s11E)) within 0.05 % (the Rayleigh-Love lateral inertia of a
    1.5 mm by 0.5 mm section lowers it by about 1e-4)."""
    from fem.geometry import PlateStator
    from fem.material import transverse_coupling
    from fem.modes import plate_modes

    bar = PlateStator(length_m=30e-3, width_m=1.5e-3, thickness_m=0.5e-3, electrode_gap_m=0.0)
    f_fe = plate_modes(bar, name, mesh=MeshSettings(order=2, refine=2)).L1.f_short_Hz
    f_s = transverse_coupling(get_material(name))["N31_Hz_m"] / bar.length_m
    assert f_fe == pytest.approx(f_s, rel=5e-4)
    assert f_fe < f_s


def _two_segment_rod_Hz(e1: float, rho1: float, a: float, e2: float, rho2: float, b: float,
                        near_Hz: float) -> float:
    """The free-free two-segment rod's first extensional frequency near ``near_Hz``:
    ``Z1 tan(k1 a) + Z2 tan(k2 b) = 0``, ``Z = sqrt(E rho)``, ``k = omega sqrt(rho / E)``."""
    import math

    from scipy.optimize import brentq

    def f(w: float) -> float:
        return (math.sqrt(e1 * rho1) * math.tan(w * math.sqrt(rho1 / e1) * a)
                + math.sqrt(e2 * rho2) * math.tan(w * math.sqrt(rho2 / e2) * b))

    ws = np.linspace(0.9, 1.1, 2001) * 2 * math.pi * near_Hz
    vals = np.array([f(w) for w in ws])
    # a sign change through zero, not through a pole of tan
    i = next(i for i in range(len(ws) - 1) if vals[i] * vals[i + 1] < 0
             and max(abs(vals[i]), abs(vals[i + 1])) < 1e3 * abs(vals).min() + 1e9)
    return brentq(f, ws[i], ws[i + 1]) / (2 * math.pi)


@pytest.mark.parametrize("tip", ["alumina", "steel"])
def test_a_tip_of_its_own_material_is_a_two_segment_rod(tip):
    """A 30 x 1.5 x 0.5 mm electroded strip with a 6 mm tip of alumina or steel across its
    whole width: its L1 in the 2D FE is the two-segment rod's, PZT-8 (1/s11E, short
    circuit) then the tip's Young's modulus and density, within 0.03 % (lateral inertia)."""
    from fem.material import tip_material
    from fem.meshing.parametric import ParametricStator
    from fem.modes import plate_modes

    length, width, tip_len = 30e-3, 1.5e-3, 6e-3
    st = ParametricStator(length_m=length, width_m=width, thickness_m=0.5e-3,
                          electrode_gap_m=0.0, tip_length_m=tip_len, tip_width_m=width,
                          tip_material=tip)
    f_fe = plate_modes(st, "pzt8", mesh=MeshSettings(order=2, refine=2)).L1.f_short_Hz
    t = tip_material(tip)
    f_rod = _two_segment_rod_Hz(plane_stress(pzt8()).young_modulus_Pa(1), 7600.0, length,
                                t.young_Pa, t.rho_kg_m3, tip_len, f_fe)
    assert f_fe == pytest.approx(f_rod, rel=3e-4)


def test_the_3d_tip_bricks_take_the_tip_material():
    """assemble_solid with every brick in the tip is the assembly of an isotropic material of
    the tip's constants with no piezoelectric coupling: the per-brick constants are the
    tip's, to round-off."""
    from skfem import MeshHex

    from fem.material import EPS0_F_M, PiezoMaterial, tip_material
    from fem.solid3d.model import assemble_solid

    mesh = MeshHex.init_tensor(np.linspace(0, 2e-3, 3), np.linspace(0, 4e-3, 4),
                               np.linspace(0, 1e-3, 2))
    t = tip_material("alumina")
    iso = PiezoMaterial("iso", t.stiffness_Pa(), np.zeros((3, 6)),
                        EPS0_F_M * t.relative_permittivity * np.eye(3), t.rho_kg_m3)
    cells = np.arange(mesh.t.shape[1])
    got = assemble_solid(mesh, pzt8(), 2, "hex20", (t, cells))[1:]
    want = assemble_solid(mesh, iso, 2, "hex20")[1:]
    for a, b in zip(got, want, strict=True):
        assert abs(a - b).max() <= 1e-12 * max(abs(b).max(), 1e-30)
    # and no tip is the ceramic everywhere (the one-material path)
    half = assemble_solid(mesh, pzt8(), 2, "hex20", (t, cells[:0]))[1:]
    for a, b in zip(half, assemble_solid(mesh, pzt8(), 2, "hex20")[1:], strict=True):
        assert abs(a - b).max() <= 1e-12 * abs(b).max()


def test_isotropic_tip_constants():
    from fem.material import TIP_MATERIALS, tip_material

    for t in TIP_MATERIALS.values():
        s = np.linalg.inv(t.stiffness_Pa())
        assert 1.0 / s[0, 0] == pytest.approx(t.young_Pa, rel=1e-12)
        assert -s[0, 1] / s[0, 0] == pytest.approx(t.poisson, rel=1e-12)
        assert 1.0 / np.linalg.inv(t.plane_stress_Pa())[1, 1] == pytest.approx(t.young_Pa)
        assert t.source
    with pytest.raises(ValueError, match="alumina, steel"):
        tip_material("brass")
