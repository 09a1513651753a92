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
    with pytest.raises(ValueError, match="pzt8, paper, pzt4, pzt5a"):
        get_material("pzt2")
    assert MATERIAL_NAMES == ("pzt8", "paper", "pzt4", "pzt5a")


def test_named_materials_carry_q_and_limits():
    """The data-sheet Q_m of the hard and soft ceramics, and the paper's material without
    one (its set keeps Table 2's damping); every named material has limits."""
    assert [get_material(n).mechanical_Q for n in MATERIAL_NAMES] == [1000.0, None, 500.0,
                                                                       75.0]
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
