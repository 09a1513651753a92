"""Finite-mass ("exact") steady states and coexisting branches against long transients."""

from pathlib import Path

import pytest

from contact.steady.engine import steady_state
from contact.steady.settled import transient_reference
from rom import table2


@pytest.fixture(scope="module")
def params():
    return table2()


def test_exact_level_matches_a_long_transient(params):
    # the issue asks 1e-6. Both run exact propagators (the exact level at 25 steps per period,
    # the transient at 250), so they agree far better unless a step-dependent bias creeps in:
    # the stick projection that kicked the slider put 3.1e-7 between them at commit b58f8d2
    r = steady_state(params, 200, 14, accuracy="exact")
    v_t, _ = transient_reference(params, 200, 14, duration_s=0.3)
    assert r.velocity_m_s == pytest.approx(v_t, rel=1e-8)


def test_averaging_error_scales_as_one_over_slider_mass(params):
    # without guide friction the averaged velocity does not depend on M (M g loads the guide)
    errs = []
    for mass in (0.2, 0.4):
        p = params.with_(M_slider=mass, mu_sd=0.0)  # Table 2's coupling, as docs/steady.md
        fast = steady_state(p, 200, 14, coupling="paper", accuracy="fast").velocity_m_s
        exact = steady_state(p, 200, 14, accuracy="exact", coupling="paper").velocity_m_s
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

    monkeypatch.setitem(cs.METHODS, "steady", "contact.steady.engine:solve_steady")
    r = cs.simulate(params, 400, 14, method="steady")
    v_t, motion_t = transient_reference(params, 400, 14, duration_s=0.3)
    assert r.steady.velocity_m_s == pytest.approx(v_t, rel=1e-5)
    assert r.steady.motion == motion_t and r.steady.settled


@pytest.mark.parametrize(("voltage_V", "preload_N"), [(150, 14), (400, 14), (50, 26)])
def test_without_energy_runs_the_branches_are_the_same(params, voltage_V, preload_N):
    """energy=False (lusm map, simulate --steady) skips only the work runs: the same
    branches and motion, and NaN powers instead of the energy balance's. The orbit's last
    run is then at 25 instead of 250 steps per period, so its distance and phase times move
    by the event-location error only (a few 1e-8 at most, docs/steady.md "Step")."""
    full = steady_state(params, voltage_V, preload_N, accuracy="exact")
    lean = steady_state(params, voltage_V, preload_N, accuracy="exact", energy=False)
    assert [(b.k, b.stable, b.motion, b.from_rest) for b in lean.branches] == \
        [(b.k, b.stable, b.motion, b.from_rest) for b in full.branches]
    for a, b in zip(lean.branches, full.branches, strict=True):
        assert a.velocity_m_s == pytest.approx(b.velocity_m_s, rel=5e-8, abs=1e-15)
        assert a.phase_fraction == pytest.approx(b.phase_fraction, abs=1e-8)
    assert all(b.input_power_W > 0 for b in full.branches)
    assert all(b.input_power_W != b.input_power_W for b in lean.branches)  # NaN


def test_a_held_orbit_beside_a_creep_from_rest_is_a_branch(params):
    """252 V / 25.64 N / 40 414 Hz (found by exploratory testing): a start from rest creeps on
    a 15-period orbit below the slider's velocity ripple, and a held orbit (the slider
    rocking with no net travel) coexists with it. The averages see neither (G(0+) > 0), so
    the engine reported the creep alone. Independent checks: the transient from rest creeps
    at the reported speed, and the full model started on the held orbit stays held over
    10 000 periods of plain integration."""
    from contact.model import OperatingPoint
    from contact.steady.exact import REST_TRANSIENT_PERIODS
    from contact.steady.full_orbit import full_system, run_periods, shoot
    from contact.steady.slow import slow_problem

    f = 40414.0
    r = steady_state(params, 252, 25.64, frequency_Hz=f, accuracy="exact")
    held = [b for b in r.branches if b.motion == "dead-zone"]
    creep = r.from_rest
    assert len(held) == 1 and held[0].stable and not held[0].from_rest
    assert creep.k > 1 and creep.velocity_m_s > 0
    # averaged over whole orbits: 26 of 15 periods (400 periods read 1 % off)
    v_t, _ = transient_reference(params, 252, 25.64, frequency_Hz=f, duration_s=0.3,
                                 steady_periods=26 * creep.k)
    assert creep.velocity_m_s == pytest.approx(v_t, rel=1e-6)
    op = OperatingPoint(252, 25.64, f)
    fs = full_system(params, op, slow_problem(params, op, accuracy="exact").mu_d_eff, "paper")
    z, m, _, _, _ = run_periods(fs, fs.system.z0, fs.system.mode0, REST_TRANSIENT_PERIODS)
    h = shoot(fs, z, m, 1, energy=False)
    _, _, dist, _, _ = run_periods(fs, h.z, h.mode, 10_000)
    assert abs(dist) / (10_000 * op.period_s) < 1e-12


TUNED_60K = Path(__file__).resolve().parents[1] / "examples" / "tuned_60k" / "stator.toml"


def test_a_slower_orbit_the_averaging_cannot_see_catches_the_start_from_rest():
    """Found by exploratory testing on a designer's stator: at 140 V / 14 N, no load, the
    averages see one stable branch (pure slip at 1.36e-2 m/s, far above the slider's
    velocity ripple), which the exact level took as reached from rest without a transient;
    a start from rest settles on a stick-slip orbit at less than half that speed. The
    reference is the transient from rest. The scan misses that orbit's sheet of the slow
    equation; the full model's run out of the slider's ripple zone finds it and follows it
    to its root (contact.steady.from_rest), without the transient of REST_TRANSIENT_PERIODS."""
    from contact.drive import auto_frequency
    from contact.steady.from_rest import PROBE_PERIODS
    from rom.from_fem import fem_params_from_file

    p = fem_params_from_file(TUNED_60K)
    f = auto_frequency(p)
    r = steady_state(p, 140, 14, frequency_Hz=f, energy=False)
    ref, motion = transient_reference(p, 140, 14, frequency_Hz=f, duration_s=0.1)
    assert motion == "stick-slip" and r.velocity_m_s == pytest.approx(ref, rel=1e-6)
    assert r.rest_periods <= PROBE_PERIODS
    faster = [b for b in r.branches if b.stable and not b.from_rest]
    assert [b.motion for b in faster] == ["pure-slip"] and faster[0].velocity_m_s > 2 * ref


def _least_period_of_transient(window, period_s: float, most: int = 3) -> int:
    """The smallest d <= ``most`` drive periods after which the trace ``window`` (every step
    of its last periods) repeats the slider's velocity and the modal coordinates to 1e-6 of
    their size (0 if none does; an orbit misses a shorter period by its own size)."""
    import numpy as np

    per = int(round(period_s / (window.t_s[1] - window.t_s[0])))
    for d in range(1, most + 1):
        last = slice(len(window.t_s) - 1 - per, len(window.t_s))
        back = slice(len(window.t_s) - 1 - per - d * per, len(window.t_s) - d * per)
        if all(np.max(np.abs(a[last] - a[back])) <= 1e-6 * np.max(np.abs(a))
               for a in (window.v_m_s, window.u_l_m, window.w_b_m)):
            return d
    return 0


@pytest.mark.slow
def test_a_held_slider_reports_the_least_period_of_its_orbit_on_every_path(params):
    """200 V / 14 N driven at 1 kHz holds the slider under 0 to 3 N, each load decided on
    another path: an averaged creep's three-period shot converging to the held orbit (0 N),
    the hold check beside the averaged dead zone (1, 2 N), the transient from rest (3 N).
    The dead zone's k had been 3, 0, 0, 1. The reference: a transient from rest under each
    load ends held, its state repeating after one drive period; with energy=False (lusm map,
    simulate --steady) the same. Its mean normal force is the preload (no separation)."""
    from contact.simulate import simulate

    f = 1000.0
    for load in (0.0, 1.0, 2.0, 3.0):
        r = simulate(params, 200, 14, f, duration_s=0.2, full_periods=4, load_N=load)
        assert r.steady.motion == "pure-stick" and abs(r.steady.velocity_m_s) < 1e-12
        k_transient = _least_period_of_transient(r.window, 1.0 / f)
        assert k_transient == 1
        for energy in (True, False):
            b = steady_state(params, 200, 14, frequency_Hz=f, load_N=load,
                             energy=energy).from_rest
            assert b.motion == "dead-zone" and b.velocity_m_s == 0.0
            assert b.k == k_transient, (load, energy)
            assert b.mean_FN_N == pytest.approx(14.0, rel=1e-9)


def test_a_shot_reports_the_least_period_of_the_orbit_it_converged_to(params):
    """A shot over two periods from the averaged one-period orbit at 200 V / 14 N converges
    to the same orbit as a one-period shot: it is reported with k = 1, the same velocity and
    means, and the coexisting period-2 orbit at 150 V / 14 N keeps k = 2 (its two periods
    differ: the transient from rest repeats after two, not one)."""
    from contact import state as S
    from contact.model import OperatingPoint
    from contact.simulate import simulate
    from contact.steady.full_orbit import full_system, shoot
    from contact.steady.slow import slow_problem

    sp = slow_problem(params, OperatingPoint(200, 14, 40000.0), accuracy="exact")
    v = steady_state(params, 200, 14, energy=False).velocity_m_s
    o = sp.orbit(v)
    fs = full_system(params, sp.op, sp.mu_d_eff, "paper")
    z = o.z.copy()
    z[S.DX] = v
    one = shoot(fs, z, o.mode - o.mode % 3 + S.FORWARD, 1, energy=False)
    two = shoot(fs, z, o.mode - o.mode % 3 + S.FORWARD, 2, energy=False)
    assert one.k == 1 and two.k == 1
    assert two.velocity_m_s == pytest.approx(one.velocity_m_s, rel=1e-9)
    assert two.mean_FT_N == pytest.approx(one.mean_FT_N, rel=1e-9)
    rest = steady_state(params, 150, 14, energy=False).from_rest
    r = simulate(params, 150, 14, duration_s=0.2, full_periods=6)
    assert rest.k == _least_period_of_transient(r.window, 1 / 40000.0) == 2


def test_exact_mean_forces_are_the_full_models(params):
    """The full model's own period means (they had been the averaged orbit's, or NaN on an
    orbit found only on the full model). Over an orbit the slider's momentum returns: where
    it never stops (400 V / 14 N, 0.22 and 0.10 m/s against a ripple of about 1e-3 m/s) the
    mean tangential force is the guide's kinetic friction plus the load. The tip separates
    there, so the mean normal force exceeds the preload; a 0.3 s transient's trace gives the
    same. Without separation it is the preload: the period-2 orbit from rest at 150 V / 14 N,
    which the averaging does not see."""
    import numpy as np

    from contact.simulate import simulate
    from rom.params import GRAVITY_M_S2

    guide = params.mu_sd * params.M_slider * GRAVITY_M_S2
    for load in (0.0, 1.0):
        b = steady_state(params, 400, 14, load_N=load, energy=False).from_rest
        assert b.k == 1 and b.velocity_m_s > 0.05 and b.motion == "slip-separation"
        assert b.mean_FT_N == pytest.approx(params.mu_sd * b.mean_FN_N + guide + load,
                                            rel=1e-9)
        if load == 0.0:
            w = simulate(params, 400, 14, duration_s=0.3, full_periods=40).window
            fn = np.trapezoid(w.F_N_N, w.t_s) / (w.t_s[-1] - w.t_s[0])
            assert b.mean_FN_N == pytest.approx(fn, rel=1e-5)
            assert b.mean_FN_N > 14.0 * (1 + 1e-3)
    rest = steady_state(params, 150, 14, energy=False).from_rest
    assert rest.k == 2
    assert rest.mean_FN_N == pytest.approx(14.0, rel=1e-9)
    assert rest.mean_FT_N == pytest.approx(params.mu_sd * 14.0 + guide, rel=1e-9)
