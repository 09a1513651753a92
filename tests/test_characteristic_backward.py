"""The characteristic of a motor that runs backward (issue 42): a 1000 x 250 x 100 mm pzt8
plate at its own operating point drives the slider at -0.000946 m/s, where the averaged model
holds it. Its stall force is the load against its own direction (negative, as ``load_N``
signs it), its direction is said, and no NaN reaches an option's check (``--load-N must be a
finite number (N), got nan``, an option characteristic does not have)."""

from __future__ import annotations

import json

import pytest

from lusm.cli import main

BACKWARD = {
    "M_l": 94.00116685040449,
    "C_l": 232728.91356667483,
    "K_l": 10540840001.530523,
    "A_l": 2.047625330097838,
    "phi_L0": 1.0,
    "phi_Ll": -1.0000000000000573,
    "M_b": 328.71893297974236,
    "C_b": 476020.7162138645,
    "K_b": 34233691366.3498,
    "A_b": -2.6756378935840153,
    "phi_B0": -1.998448656660732,
    "phi_Bl": 1.9984486566597754,
    "k_contact": 17378000.0,
    "M_slider": 0.2,
    "mu_s": 0.5,
    "mu_d": 0.35,
    "mu_sd": 0.04,
    "a_mu": 0.15,
    "b_mu": 1000000.0,
    "source": "FE reduction of a 1000 x 250 x 100 mm pzt8 plate",
    "eta_N": 2.0000000000000573,
    "eta_T": -3.9968973133205075,
    "f_L1_Hz": 1685.3539373274562,
    "f_B2_Hz": 1624.181793361074,
    "zeta_L1": 0.11690043131491472,
    "zeta_B2": 0.07095069157891203,
}
"""The FE parameter set of that plate (``rom.from_fem.fem_params``, order 2, refine 4)."""

FREQUENCY_HZ = "1627.13734779033"
"""Its ``--frequency auto`` (Hz)."""


@pytest.fixture
def params_file(tmp_path):
    path = tmp_path / "backward.json"
    path.write_text(json.dumps(BACKWARD))
    return str(path)


@pytest.mark.slow
def test_a_backward_motor_has_a_stall_force_against_its_own_direction(params_file, capsys):
    argv = ["characteristic", "--params", params_file, "--voltage", "300", "--preload", "14",
            "--frequency", FREQUENCY_HZ]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "-0.000945" in out and "(backward: the slider runs toward -y" in out, out
    stall = float(next(ln for ln in out.splitlines() if ln.startswith("stall force")).split()[-1])
    assert -3.5 < stall < -2.5, out
    # loads the user gives: the stall force is the same, not NaN
    assert main([*argv, "--loads", "0,0.1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    char = doc if "stall_force_N" in doc else doc["characteristics"][0]
    assert char["direction"] == "backward"
    assert char["stall_force_N"] == pytest.approx(stall, rel=1e-5)
