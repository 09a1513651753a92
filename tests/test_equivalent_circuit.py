"""The Butterworth-Van Dyke circuit (fem.equivalent_circuit): fit, IEEE 176 quantities, CLI."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fem.admittance import plate_admittance
from fem.equivalent_circuit import bvd_admittance_S, equivalent_circuit, fit_bvd
from fem.mesh_settings import MeshSettings

C0 = 2.0e-9
ONE = [(150.0, 0.12, 8.0e-11)]
TWO = [(150.0, 0.12, 8.0e-11), (400.0, 0.3, 3.0e-11)]


def _f_s(branch) -> float:
    return 1.0 / (2.0 * math.pi * math.sqrt(branch[1] * branch[2]))


def _off(branch, f_rel: float, c_rel: float, q_rel: float):
    """``branch`` with its series resonance, C1 and Q moved by the given shares."""
    r, ell, c = branch
    q = math.sqrt(ell / c) / r * (1.0 + q_rel)
    c2 = c * (1.0 + c_rel)
    w = 2.0 * math.pi * _f_s(branch) * (1.0 + f_rel)
    ell2 = 1.0 / (w * w * c2)
    return (math.sqrt(ell2 / c2) / q, ell2, c2)


@pytest.mark.parametrize("true, start", [
    (ONE, [_off(ONE[0], 0.01, 0.3, -0.4)]),
    (TWO, [_off(TWO[0], 0.005, 0.2, 0.3), _off(TWO[1], -0.005, -0.2, -0.3)]),
])
def test_the_fit_recovers_a_synthetic_circuit(true, start):
    """A synthetic admittance of known C0, R1, L1, C1 (one and two branches) is recovered to
    1e-6 from a start 0.5-1 % off in frequency and 20-40 % off in C1 and Q."""
    f0 = _f_s(true[0])
    f = np.linspace(0.8 * f0, 1.3 * f0, 3001)
    circuit = fit_bvd(f, bvd_admittance_S(f, C0, true), 0.8 * C0, start)
    assert circuit.C0_F == pytest.approx(C0, rel=1e-6)
    assert len(circuit.branches) == len(true)
    for b, (r, ell, c) in zip(circuit.branches, sorted(true, key=_f_s), strict=True):
        assert (b.R_ohm, b.L_H, b.C_F) == pytest.approx((r, ell, c), rel=1e-6)
    assert circuit.rms_rel < 1e-9


def test_ieee_176_quantities_are_consistent():
    f0 = _f_s(ONE[0])
    f = np.linspace(0.9 * f0, 1.1 * f0, 2001)
    circuit = fit_bvd(f, bvd_admittance_S(f, C0, ONE), C0, ONE)
    (b,) = circuit.branches
    f_p = b.f_p_Hz(circuit.C0_F)
    assert b.f_s_Hz == pytest.approx(f0, rel=1e-12)
    assert b.k_eff(circuit.C0_F) ** 2 == pytest.approx(1.0 - (b.f_s_Hz / f_p) ** 2, rel=1e-12)
    assert b.Q_m == pytest.approx(1.0 / (2 * math.pi * b.f_s_Hz * b.R_ohm * b.C_F), rel=1e-12)
    # the circuit's own series and parallel resonance: |Y| of the undamped circuit is
    # infinite at f_s and zero at f_p
    lossless = [(0.0, b.L_H, b.C_F)]
    assert abs(bvd_admittance_S(np.array([f_p]), circuit.C0_F, lossless)[0]) < 1e-9
    d = circuit.to_dict()["modes"][0]
    assert d["k_eff"] ** 2 == pytest.approx(1.0 - (d["f_s_Hz"] / d["f_p_Hz"]) ** 2, rel=1e-12)


def test_the_fe_admittance_gives_each_modes_branch():
    """On the paper's plate the fitted f_s is each FE mode's frequency to 1e-4 (here far
    closer), Q_m is 1 / (2 zeta), and the circuit lies on the computed curve."""
    zeta = 0.004
    res = plate_admittance(f_min_Hz=45e3, f_max_Hz=65e3, n_points=1001, zeta=zeta,
                           mesh=MeshSettings(refine=2))
    circuit = equivalent_circuit(res)
    assert [b.mode for b in circuit.branches] == ["B2", "L1"]
    for b in circuit.branches:
        assert abs(b.f_s_Hz / b.f_mode_Hz - 1.0) < 1e-4
        assert b.Q_m == pytest.approx(1.0 / (2.0 * zeta), rel=1e-6)
    y_fit = circuit.admittance_S(res.f_Hz)
    assert np.max(np.abs(y_fit - res.Y_S) / np.abs(res.Y_S)) == pytest.approx(circuit.max_rel)
    assert circuit.max_rel < 5e-3
    # the clamped capacitance lies below the one beside the resonances (higher modes' share)
    assert res.port.C0_F < circuit.C0_F < res.port.C_free_F


@pytest.mark.slow
def test_coincident_modes_keep_their_own_branches():
    """A stator tuned to L1 = B2 with one damping for both: the admittance cannot tell the
    two branches apart, and the fit keeps each the mode's own (one of them had wandered
    0.5 % off to fit the modes outside the band)."""
    from fem.equivalent_circuit import modal_branches
    from fem.geometry import PlateStator
    from fem.tuning import tune_plate

    tuned = tune_plate(56e3, start=PlateStator(), mesh=MeshSettings(refine=2))
    res = plate_admittance(tuned.stator, f_min_Hz=45e3, f_max_Hz=65e3, n_points=801,
                           zeta=0.004, mesh=MeshSettings(refine=2))
    circuit = equivalent_circuit(res)
    modal = {n: b for b, n, _ in modal_branches(res.port, 45e3, 65e3, 1e-3)}
    assert set(modal) == {"L1", "B2"}
    for b in circuit.branches:
        assert (b.R_ohm, b.L_H, b.C_F) == pytest.approx(modal[b.mode], rel=1e-6)


def test_cli_admittance_carries_the_circuit(tmp_path, capsys):
    from lusm.cli import main

    argv = ["admittance", "--refine", "2", "--zeta", "0.004", "--points", "801"]
    assert main([*argv, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["equivalent_circuit"]
    assert [m["mode"] for m in d["modes"]] == ["B2", "L1"]
    for m in d["modes"]:
        assert m["Q_m"] == pytest.approx(125.0, rel=1e-6)
        assert abs(m["f_s_rel_to_mode"]) < 1e-4
    assert main([*argv, "--out", str(tmp_path / "out")]) == 0
    text = capsys.readouterr().out
    assert "Butterworth-Van Dyke circuit fitted over the band" in text
    assert (tmp_path / "out" / "admittance.png").is_file()


def test_the_figure_draws_impedance_and_the_circuit():
    from validation.fem_figures import draw_admittance
    from validation.plotting import pyplot

    res = plate_admittance(f_min_Hz=45e3, f_max_Hz=65e3, n_points=401, zeta=0.004,
                           mesh=MeshSettings(refine=2))
    circuit = equivalent_circuit(res)
    fig, _ = draw_admittance(res, circuit)
    ax = fig.axes[0]
    assert ax.get_ylabel() == "|Z| (ohm)"
    computed, fitted = ax.get_lines()[:2]
    np.testing.assert_allclose(computed.get_ydata(), 1.0 / np.abs(res.Y_S))
    np.testing.assert_allclose(fitted.get_ydata(), 1.0 / np.abs(circuit.admittance_S(res.f_Hz)))
    pyplot().close(fig)
