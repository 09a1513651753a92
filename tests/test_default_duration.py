"""``lusm simulate``'s run length follows the stator: without ``--duration`` a set other than
Table 2's runs its own settling time (:func:`contact.drive.settling_time_s`), Table 2's the
paper's 0.05 s, bounded by the work bound."""

from __future__ import annotations

import json

import numpy as np
import pytest

from contact.drive import settling_time_s
from lusm.cli import main
from lusm.options import PAPER_DURATION_S, default_duration_s
from rom.table2 import table2


def _light(zeta: float):
    """Table 2's set with both modes damped at ``zeta`` (a lightly damped stator)."""
    t = table2()
    return t.with_(C_l=2 * zeta * np.sqrt(t.K_l * t.M_l), C_b=2 * zeta * np.sqrt(t.K_b * t.M_b))


def test_the_estimate_adds_the_modes_and_the_slider():
    # by hand: tau = 1/(zeta omega_n) of the slower mode plus M v_tip / F_net, five of each
    from rom.damping import free_tip_phasors
    from rom.params import GRAVITY_M_S2

    p = _light(0.005)
    tau_modes = max(1 / (0.005 * 2 * np.pi * p.f_L1_Hz), 1 / (0.005 * 2 * np.pi * p.f_B2_Hz))
    v_tip = 2 * np.pi * 40e3 * abs(free_tip_phasors(p, 40e3, 200.0)[1])
    force = p.mu_d * 14 - p.mu_sd * (14 + p.M_slider * GRAVITY_M_S2)
    want = 5 * (tau_modes + p.M_slider * v_tip / force)
    assert settling_time_s(p, 200.0, 14.0, 40e3) == pytest.approx(want, rel=1e-12)
    # a load the friction cannot overcome leaves the modes only
    assert settling_time_s(p, 200.0, 14.0, 40e3, load_N=100.0) == pytest.approx(
        5 * tau_modes, rel=1e-12)


def test_table2_keeps_the_papers_run_and_the_bound_is_said(capsys):
    assert default_duration_s(table2(), [400.0], 14.0, 40e3, 1e-7) == PAPER_DURATION_S
    # a step 100 times finer: the settling run is above the step bound, which it is cut to
    from lusm import limits

    d = default_duration_s(_light(0.005), [200.0], 14.0, 40e3, 1e-9)
    assert d == pytest.approx(limits.work_bound(limits.MAX_STEPS) * 1e-9, rel=1e-12)
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--duration" in err[0] and "--steady" in err[0]


@pytest.mark.slow
def test_a_lightly_damped_stator_settles_by_default(tmp_path, capsys):
    """Table 2's set damped at zeta = 0.005 (Q = 100), 200 V / 14 N, 40 kHz: the paper's
    0.05 s leaves the slider at 28 % of its steady speed; the default settling time (0.88 s)
    settles it. Tolerance 1 %: the run calls itself settled when its last two window means
    agree to 1 %, and the rest of an exponential approach is of the order of that step (here
    0.24 %)."""
    from contact.steady.engine import steady_state

    p = _light(0.005)
    (tmp_path / "light.json").write_text(json.dumps(p.to_dict()))
    argv = ["simulate", "--params", str(tmp_path / "light.json"), "--voltage", "200",
            "--preload", "14", "--frequency", "40000", "--json"]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["duration_s"] == pytest.approx(settling_time_s(p, 200.0, 14.0, 40e3), rel=1e-12)
    assert d["settled"] is True
    steady = steady_state(p, 200.0, 14.0, frequency_Hz=40e3, coupling=d["coupling"])
    assert d["steady_velocity_m_s"] == pytest.approx(steady.velocity_m_s, rel=0.01)
    assert main([*argv, "--duration", "0.05"]) == 0  # a typed --duration is kept
    short = json.loads(capsys.readouterr().out)
    assert short["duration_s"] == 0.05 and short["settled"] is False
