"""The numba kernel against the independent event-driven solve_ivp reference."""

from __future__ import annotations

import pytest

from contact.reference import reference_simulate
from tests.conftest import cached_run

CASES = [
    (200.0, 10.0, "pure-slip"),
    (200.0, 14.0, "stick-slip"),
    (400.0, 14.0, "slip-separation"),
]


@pytest.mark.parametrize(("voltage", "preload", "motion"), CASES)
def test_kernel_matches_event_driven_reference(paper_params, voltage, preload, motion):
    fast = cached_run(voltage, preload)
    assert fast.steady.motion == motion
    ref = reference_simulate(paper_params, voltage, preload, mu_d_eff=fast.mu_d_eff)
    v, v_ref = fast.steady.velocity_m_s, ref.velocity_m_s
    assert abs(v - v_ref) <= 0.01 * abs(v_ref)
    assert abs(fast.steady.stick_fraction - ref.stick_fraction) <= 0.02
    assert abs(fast.steady.separation_fraction - ref.separation_fraction) <= 0.02
    assert fast.events == ref.n_events
