"""A_N of Eq. 11 in closed form against the simulated pre-pass (Eqs. 4 + 7 from rest)."""

from __future__ import annotations

import numpy as np
import pytest

from contact.drive import auto_frequency
from contact.model import OperatingPoint, linear_normal_amplitude
from contact.transient.pre_pass import normal_amplitude
from rom import table2
from rom.sources import get_params


@pytest.mark.parametrize("source", ["table2", "beam"])
def test_closed_form_equals_the_simulated_pre_pass_without_separation(source):
    """The harmonic orbit's amplitude is what 60 periods of the event kernel settle to (their
    own step error is ~1e-9); where the tip separates the closed form declines."""
    p = table2() if source == "table2" else get_params(source)
    f = 40e3 if source == "table2" else auto_frequency(p)
    closed = 0
    for v in np.linspace(25.0, 450.0, 6):
        for fp in (6.0, 14.0, 26.0):
            op = OperatingPoint(float(v), fp, f)
            ref = normal_amplitude(p, op, closed_form=False)
            a_n = linear_normal_amplitude(p, op)
            if a_n is None:
                assert normal_amplitude(p, op) == ref
                continue
            closed += 1
            assert a_n == pytest.approx(ref, rel=1e-8)
    assert closed >= 6


def test_separation_is_left_to_the_simulation():
    """At 400 V / 14 N Table 2's tip separates (docs/contact.md: from about 322 V at 14 N):
    the clipped orbit's amplitude is not the harmonic one."""
    op = OperatingPoint(400.0, 14.0)
    assert linear_normal_amplitude(table2(), op) is None
    below = OperatingPoint(300.0, 14.0)
    assert linear_normal_amplitude(table2(), below) is not None


def test_the_pre_pass_settles_on_a_lightly_damped_stator():
    """Table 2 with a hundredth of its damping (zeta_L1 = 0.0012, a real PZT's order) at
    300 V / 5 N, where the tip separates: a fixed 60-period pre-pass had put A_N 67 % above
    the amplitude the run itself settles to (mu_d,eff 0.213 instead of 0.250, the speed 18 %
    low). The pre-pass now lasts until the L1 transient has decayed; its A_N equals the
    settled window of a 0.1 s transient (4 000 periods, e^-25 of the start left)."""
    from dataclasses import replace

    from contact.simulate import simulate

    p = table2()
    light = replace(p, C_l=p.C_l / 100, C_b=p.C_b / 100)
    op = OperatingPoint(300.0, 5.0)
    assert linear_normal_amplitude(light, op) is None  # separating: the pre-pass decides
    a_n = normal_amplitude(light, op)
    run = simulate(light, 300.0, 5.0, 40e3, duration_s=0.1, coupling="paper")
    settled = 0.5 * (run.steady.y_tip_max_m - run.steady.y_tip_min_m)
    assert a_n == pytest.approx(settled, rel=1e-6)
    assert run.normal_amplitude_m == a_n
    assert normal_amplitude(light, op, periods=60) > 1.5 * settled  # the former pre-pass


def test_the_pre_pass_does_not_depend_on_the_coupling():
    """The normal coordinate does not feel F_T, so A_N cannot depend on the coupling: a set
    with phi_B0 = phi_Bl (no tangential force on B2 under the paper's coupling) asked to run
    the consistent coupling was refused at separating points, its pre-pass built with the
    paper's coupling."""
    from dataclasses import replace

    from contact.simulate import simulate

    p = table2()
    flat = replace(p, phi_B0=p.phi_Bl)
    op = OperatingPoint(400.0, 14.0)
    assert normal_amplitude(flat, op) == normal_amplitude(p, op)
    run = simulate(flat, 400.0, 14.0, duration_s=0.01, coupling="consistent")
    assert run.normal_amplitude_m == normal_amplitude(p, op)


@pytest.mark.slow
def test_a_long_pre_pass_is_bounded_and_computed_once():
    """Table 2 with C_l / 1e4 driven at 1 kHz (2000 V / 0.02 N, separating): the settling
    pre-pass at the transient's 1e-7 s would take 1e8 steps (14 s, five times the bound
    on a run); it takes 250 steps per period instead, the same A_N as asking for that step.
    A characteristic asks for A_N at every load: the pre-pass runs once per point."""
    from dataclasses import replace

    from contact.characteristic import characteristic
    from contact.transient import pre_pass

    p = table2()
    light = replace(p, C_l=p.C_l * 1e-4)
    op = OperatingPoint(2000.0, 0.02, 1000.0)
    assert linear_normal_amplitude(light, op) is None
    periods = pre_pass.pre_pass_periods(light, op)
    assert periods * op.period_s / 1e-7 > pre_pass.MAX_PRE_PASS_STEPS
    a = normal_amplitude(light, op, 1e-7)
    assert a == normal_amplitude(light, op, op.period_s / pre_pass.PRE_PASS_STEPS_PER_PERIOD)
    pre_pass._pre_pass.cache_clear()
    characteristic(p, 400.0, 14.0, loads_N=[0.0, 0.1, 0.2], frequency_Hz=40e3,
                   coupling="paper")  # the exact level: 49 asks at this separating point
    info = pre_pass._pre_pass.cache_info()
    assert info.misses == 1 and info.hits >= 3
