"""``lusm harmonic``: the reduced model's free tip response against the direct FE solve."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.sparse as sp

from fem.geometry import PlateStator
from fem.harmonic import fe_tip_response, modally_damped_solve
from fem.mesh_settings import MeshSettings
from fem.model import plate_model
from fem.modes import plate_modes
from lusm.cli import main
from rom.from_fem import fem_params
from rom.harmonic import tip_ellipse, tip_response

REFINE = 2  # a coarse mesh: the check compares two models on one mesh
ZETA = 0.005


@pytest.fixture(scope="module")
def plate():
    st = PlateStator()
    model = plate_model(st, "pzt8", MeshSettings(2, REFINE))
    modes = plate_modes(st, "pzt8", MeshSettings(2, REFINE))
    params = fem_params(st, "pzt8", MeshSettings(2, REFINE), damping_ratios=(ZETA, ZETA))
    return model, modes, params


def test_the_reduced_response_is_the_fe_one_near_resonance(plate):
    model, modes, params = plate
    f = [modes.L1.f_short_Hz, modes.B2.f_short_Hz]
    fe = fe_tip_response(model, modes, f, 100.0, ZETA, ZETA)
    rom = tip_response(params, f, 100.0)
    # each mode's own component at its resonance: within 1 % (complex amplitude)
    normal = abs(rom.normal_m[0] - fe.normal_m[0]) / abs(fe.normal_m[0])
    tangential = abs(rom.tangential_m[1] - fe.tangential_m[1]) / abs(fe.tangential_m[1])
    assert normal < 0.01 and tangential < 0.01
    assert abs(fe.normal_m[0]) * 1e6 > 1.0  # a resonance: microns at 100 V


def test_away_from_resonance_the_fe_solve_keeps_what_the_reduction_drops(plate):
    model, modes, params = plate
    f = [0.8 * modes.B2.f_short_Hz]
    fe = fe_tip_response(model, modes, f, 1.0, ZETA, ZETA)
    rom = tip_response(params, f, 1.0)
    # the other modes' quasi-static share: several per cent where neither mode resonates
    assert abs(rom.tangential_m[0] - fe.tangential_m[0]) / abs(fe.tangential_m[0]) > 0.03


def test_the_modal_damping_is_applied_exactly():
    rng = np.random.default_rng(1)
    n = 12
    a = rng.standard_normal((n, n))
    K = sp.csr_matrix(a @ a.T + n * np.eye(n))
    M = sp.csr_matrix(np.diag(rng.uniform(1.0, 2.0, n)))
    MPhi = rng.standard_normal((n, 2))
    d = np.array([3.0, 0.0])
    rhs = rng.standard_normal(n)
    w = 1.7
    dense = K.toarray() - w**2 * M.toarray() + 1j * w * (MPhi[:, :1] * d[0]) @ MPhi[:, :1].T
    assert np.allclose(modally_damped_solve(K, M, MPhi, d, rhs, w),
                       np.linalg.solve(dense, rhs), rtol=1e-10, atol=1e-12)


def test_the_ellipse_is_the_phasors_path(plate):
    _, modes, params = plate
    f = 0.5 * (modes.L1.f_short_Hz + modes.B2.f_short_Hz)
    e = tip_ellipse(params, f, 50.0)
    r = tip_response(params, [f], 50.0)
    assert np.max(np.abs(e.tangential_m)) == pytest.approx(abs(r.tangential_m[0]), rel=1e-3)
    assert np.max(np.abs(e.normal_m)) == pytest.approx(abs(r.normal_m[0]), rel=1e-3)
    assert e.width_m == abs(r.tangential_m[0])


@pytest.mark.slow
def test_cli_harmonic_json_and_figures(tmp_path, capsys):
    out = tmp_path / "h"
    assert main(["harmonic", "--refine", str(REFINE), "--points", "21", "--zeta", str(ZETA),
                 "--voltage", "50", "--json", "--plot", str(out)]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("frequency_Hz", "tip_tangential_um", "tip_normal_um",
                "tip_tangential_phase_deg", "tip_normal_phase_deg"):
        assert len(d[key]) == 21
    points = {p["at"]: p for p in d["fe_check"]["points"]}
    assert points["L1"]["normal_rel_error"] < 0.01
    assert points["B2"]["tangential_rel_error"] < 0.01
    assert d["damping"]["zeta_L1"] == ZETA
    assert sorted(p.name for p in out.glob("*.png")) == ["harmonic.png", "tip_ellipse.png"]
    assert all(p.stat().st_size > 10_000 for p in out.glob("*.png"))


def _harmonic_json(capsys, *extra: str) -> dict:
    assert main(["harmonic", "--length-mm", "32", "--refine", str(REFINE), "--points", "21",
                 "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.slow
def test_cli_harmonic_plate_options_take_the_material_damping(capsys):
    """A plate option gets the material's data-sheet Q_m with the mount's, named, and the
    reduced model's amplitude at each mode's resonance goes as 1/(2 zeta): against Table 2's
    ratios (``--damping table2``) it grows by their ratio to the material's."""
    from fem.material import material_damping, pzt8

    light, heavy = _harmonic_json(capsys), _harmonic_json(capsys, "--damping", "table2")
    zeta, _ = material_damping(pzt8())
    assert light["damping"]["zeta_L1"] == light["damping"]["zeta_B2"] == zeta
    assert "pzt8's Q_m" in light["damping"]["from"]
    assert "Table 2" in heavy["damping"]["from"]
    for mode, comp, key in (("L1", "normal", "zeta_L1"), ("B2", "tangential", "zeta_B2")):
        at = [{p["at"]: p for p in d["fe_check"]["points"]}[mode][f"{comp}_rom_um"]
              for d in (light, heavy)]
        expected = heavy["damping"][key] / light["damping"][key]  # 53.95 and 32.75
        assert at[0] / at[1] == pytest.approx(expected, rel=0.005), mode
