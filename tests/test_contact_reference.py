"""The numba kernel against the independent event-driven solve_ivp reference."""

from __future__ import annotations

import pytest

from contact.simulate import simulate
from tests.conftest import cached_run

CASES = [
    (200.0, 10.0, "pure-slip"),
    (200.0, 14.0, "stick-slip"),
    (400.0, 14.0, "slip-separation"),
]
DURATION_S = 0.01
"""400 drive periods at 40 kHz: the kernel and the reference agree to ~1e-8 in velocity and
~1e-9 in the fractions at 10 ms as at the default 50 ms, and each case's motion class is
already the settled one; the comparison is between two solvers of the same run."""


@pytest.mark.parametrize(("voltage", "preload", "motion"), CASES)
@pytest.mark.slow
def test_kernel_matches_event_driven_reference(paper_params, voltage, preload, motion):
    fast = cached_run(voltage, preload, duration_s=DURATION_S)
    assert fast.steady.motion == motion
    ref = simulate(paper_params, voltage, preload, duration_s=DURATION_S, method="reference")
    assert ref.method == "reference" and ref.mu_d_eff == fast.mu_d_eff
    v, v_ref = fast.steady.velocity_m_s, ref.steady.velocity_m_s
    assert abs(v - v_ref) <= 0.01 * abs(v_ref)
    assert ref.steady.motion == motion
    for name in ("stick_fraction", "separation_fraction", "driving_slip_fraction"):
        assert abs(getattr(fast.steady, name) - getattr(ref.steady, name)) <= 0.02, name
    # the same window measured the same way: the earlier window's velocity agrees too
    assert ref.steady.previous_velocity_m_s == pytest.approx(
        fast.steady.previous_velocity_m_s, rel=0.01, abs=1e-6)
    assert fast.events == ref.events
    # solver counters: the adaptive reference takes far fewer, far costlier steps
    assert ref.steps < fast.steps and ref.nfev > 10 * ref.steps


def test_literal_scheme_counts_and_shares_the_result_type(paper_params):
    lit = simulate(paper_params, 200.0, 14.0, duration_s=0.005, method="literal")
    assert lit.method == "literal" and lit.trace is None
    assert lit.steps == round(0.005 / 1e-7)
    assert lit.nfev >= 4 * lit.steps  # RK4: four evaluations per step (plus stick tests)
    fr = lit.steady
    assert fr.stick_fraction + fr.slip_fraction + fr.separation_fraction == pytest.approx(1.0)


def test_unknown_method_is_refused(paper_params):
    with pytest.raises(ValueError, match="method must be one of event, reference, literal, steady"):
        simulate(paper_params, 200.0, 14.0, method="rk45")


def test_the_reference_undriven_without_preload_is_separated_at_once(paper_params):
    """0 V / 0 N (found by API testing): the normal force is exactly zero, solve_ivp counts
    0 -> 0 as a crossing, and "contact" and "separate" fired in turn at t = 0 without end
    (54 000 solver calls in 40 s, none advancing time). Events now fire past roundoff of
    their own scale; the reference agrees with the event scheme: separated, at rest."""
    ev = simulate(paper_params, 0.0, 0.0, duration_s=2.5e-4)
    ref = simulate(paper_params, 0.0, 0.0, duration_s=2.5e-4, method="reference")
    assert ref.steady.motion == ev.steady.motion == "separated"
    assert ref.steady.velocity_m_s == ev.steady.velocity_m_s == 0.0
    assert ref.events == ev.events == 0


@pytest.mark.parametrize("rtol", [1e-8, 1e-10])
@pytest.mark.slow
def test_the_reference_sees_the_brief_separations_past_the_onset(paper_params, rtol):
    """322 V / 14 N, just past the separation onset (found by an audit): F_N dips below zero
    for ~1e-7 s every period, inside one of solve_ivp's ~1e-6 s steps, and the reference saw
    no sign change at the step ends: pure slip at rtol 1e-8, a separation fraction of 0.0033
    against the kernel's 0.0041 at rtol 1e-10 (velocity off by 9e-6 and 2.3e-6). Each guard's
    maximum is now an event, and a maximum above zero is traced back to its crossing."""
    d = 0.005
    ev = simulate(paper_params, 322.0, 14.0, duration_s=d)
    ref = simulate(paper_params, 322.0, 14.0, duration_s=d, method="reference", rtol=rtol)
    assert ev.steady.motion == ref.steady.motion == "slip-separation"
    assert ref.events == ev.events
    # the reference's own error scales with rtol (measured: 1.3e-6 and 7e-9 in the fraction,
    # 5e-8 and 3e-10 in the velocity); the kernel's is ~1e-9
    assert abs(ref.steady.separation_fraction - ev.steady.separation_fraction) <= 1e3 * rtol
    assert ref.steady.velocity_m_s == pytest.approx(ev.steady.velocity_m_s, rel=1e2 * rtol)


def test_a_reference_run_beyond_its_work_bound_is_refused_before_it_starts(
        paper_params, monkeypatch):
    """The default 50 ms at 10 MHz is 500 000 drive periods, about 1e6 solve_ivp restarts
    (~24 min, found by an audit): refused at once, naming both inputs and their ranges. The
    longest reference the tests, docs and benchmarks run (50 ms at 40 kHz) is 2 000."""
    import time

    from contact.model import OperatingPoint
    from contact.transient.reference import MAX_REFERENCE_PERIODS, check_reference_work

    monkeypatch.delenv("LUSM_MAX_WORK", raising=False)
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=(
            r"^method='reference' runs 10 to 20000 drive periods: duration_s must lie in "
            r"\[1e-06, 0\.002\] s at frequency_Hz = 1e\+07 Hz, or frequency_Hz in "
            r"\[200, 4e\+05\] Hz for duration_s = 0\.05 s \(got 5e\+05 periods")):
        simulate(paper_params, 200.0, 14.0, 1e7, method="reference")
    assert time.perf_counter() - t0 < 5.0  # before the A_N pre-pass and the integration
    op = OperatingPoint(200.0, 14.0, 40e3)
    assert MAX_REFERENCE_PERIODS == 20_000
    assert check_reference_work(op, 0.05) == pytest.approx(2000)  # the default run
    assert check_reference_work(op, 0.5) == pytest.approx(20_000)
    with pytest.raises(ValueError, match="duration_s must lie in"):
        check_reference_work(op, 0.51)
    monkeypatch.setenv("LUSM_MAX_WORK", "2")  # asked for on purpose
    assert check_reference_work(op, 1.0) == pytest.approx(40_000)
