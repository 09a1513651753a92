"""Finite-mass ("exact") steady states and coexisting branches against long transients."""

import pytest

from contact.steady import steady_state, transient_reference
from rom import table2


@pytest.fixture(scope="module")
def params():
    return table2()


def test_exact_level_matches_a_long_transient_to_1e_6(params):
    r = steady_state(params, 200, 14, accuracy="exact")
    v_t, _ = transient_reference(params, 200, 14, duration_s=0.3)
    assert r.velocity_m_s == pytest.approx(v_t, rel=1e-6)


def test_averaging_error_scales_as_one_over_slider_mass(params):
    # without guide friction the averaged velocity does not depend on M (M g loads the guide)
    errs = []
    for mass in (0.2, 0.4):
        p = params.with_(M_slider=mass, mu_sd=0.0)
        fast = steady_state(p, 200, 14).velocity_m_s
        exact = steady_state(p, 200, 14, accuracy="exact").velocity_m_s
        errs.append(fast - exact)
    assert errs[0] / errs[1] == pytest.approx(2.0, rel=0.02)


def test_coexisting_branches_at_150_V_14_N(params):
    r = steady_state(params, 150, 14, accuracy="exact")
    stable = [b for b in r.branches if b.stable]
    assert sorted(b.k for b in stable) == [1, 2]
    rest = r.from_rest
    v_t, _ = transient_reference(params, 150, 14, duration_s=0.2)
    assert rest.velocity_m_s == pytest.approx(v_t, rel=1e-6)
    assert rest.k == 2
    one = next(b for b in stable if b.k == 1)
    assert one.velocity_m_s > 1.5 * rest.velocity_m_s


def test_adapter_for_the_simulate_method_table(params, monkeypatch):
    import contact.simulate as cs

    monkeypatch.setitem(cs.METHODS, "steady", "contact.steady:solve_steady")
    r = cs.simulate(params, 400, 14, method="steady")
    v_t, motion_t = transient_reference(params, 400, 14, duration_s=0.3)
    assert r.steady.velocity_m_s == pytest.approx(v_t, rel=1e-5)
    assert r.steady.motion == motion_t and r.steady.settled
