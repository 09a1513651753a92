"""Load, speed-thrust characteristic and energy balance of the steady engine."""

import numpy as np
import pytest

from contact.characteristic import characteristic
from contact.steady.engine import steady_state
from contact.steady.settled import transient_reference
from rom import table2


@pytest.fixture(scope="module")
def params():
    return table2()


@pytest.fixture(scope="module")
def char400(params):
    return characteristic(params, 400, 14, points=9, accuracy="fast")


@pytest.mark.parametrize("coupling", ["consistent", "paper"])
def test_energy_balance_over_the_orbit(params, coupling):
    # input = output + damping + interface + guide, each an independent work integral
    b = steady_state(params, 400, 14, load_N=0.5, coupling=coupling, accuracy="fast").from_rest
    losses = b.output_power_W + b.damping_power_W + b.interface_power_W + b.guide_power_W
    assert b.input_power_W == pytest.approx(losses, rel=1e-8)
    assert b.output_power_W > 0 and b.damping_power_W > 0 and b.guide_power_W > 0
    if coupling == "consistent":  # there the interface term is pure friction: F_T v_rel >= 0
        assert b.interface_power_W > 0


@pytest.mark.slow
def test_energy_balance_of_a_held_slider_rocking_with_the_tip(params):
    """139 V / 14 N lies in the dead zone, on a one-period orbit of the full model: no net
    travel, but the slider rocks with the stuck tip and the guide dissipates. Its guide
    power had been set to 0 W, and the balance missed 2e-4 of the input (up to 13 % on the
    beam set under a load, found by exploratory testing). The reference: a transient's own
    guide work over its window."""
    from contact.simulate import simulate

    b = steady_state(params, 139, 14, accuracy="exact").from_rest
    assert b.motion == "dead-zone" and b.k == 1 and b.output_power_W == 0.0
    losses = b.damping_power_W + b.interface_power_W + b.guide_power_W
    assert b.input_power_W == pytest.approx(losses, rel=1e-8)
    r = simulate(params, 139, 14, 40e3, duration_s=0.6, energy=True)
    assert b.guide_power_W == pytest.approx(-r.energy.guide_J / r.steady.window_s, rel=1e-5)
    assert b.guide_power_W > 1e-4 * b.input_power_W


@pytest.mark.parametrize("load_N", [0.0, 1.5])
@pytest.mark.slow
def test_a_held_slider_far_below_resonance_has_the_transients_input_power(params, load_N):
    """200 V / 14 N driven at 1 kHz holds the slider at loads 0-3 N. The exact level gave its
    input power from the full model's held orbit at some loads (1.07e-3 W) and from the
    averaged orbit at 0+ at others (2.4e-5 W: an infinitely heavy slider does not rock
    against the guide), found by exploratory testing. The reference: a transient's own input
    work over its window at the same load."""
    from contact.simulate import simulate

    b = steady_state(params, 200, 14, frequency_Hz=1e3, load_N=load_N,
                     accuracy="exact").from_rest
    assert b.motion == "dead-zone" and b.velocity_m_s == 0.0
    r = simulate(params, 200, 14, 1e3, duration_s=0.3, energy=True, load_N=load_N)
    assert abs(r.steady.velocity_m_s) < 1e-12
    assert b.input_power_W == pytest.approx(r.energy.input_J / r.steady.window_s, rel=1e-6)
    assert b.guide_power_W == pytest.approx(-r.energy.guide_J / r.steady.window_s, rel=1e-6)


def test_speed_falls_monotonically_with_load_to_zero_at_stall(char400):
    v = char400.velocity_m_s
    assert v[0] == pytest.approx(char400.no_load_velocity_m_s)
    assert np.all(np.diff(v) < 0)
    assert v[-1] == 0.0 and char400.load_N[-1] == pytest.approx(char400.stall_force_N)
    inner = char400.efficiency[1:-1]
    assert np.all((inner > 0) & (inner < 1))


@pytest.mark.slow
def test_stall_force_matches_transient_runs_with_load(params, char400):
    stall, v0 = char400.stall_force_N, char400.no_load_velocity_m_s
    loads = (0.8 * stall, 0.95 * stall)
    v = [transient_reference(params, 400, 14, load_N=f, duration_s=0.3)[0] for f in loads]
    # the zero of the transient speed-thrust line through the two loads
    zero = loads[1] + v[1] * (loads[1] - loads[0]) / (v[0] - v[1])
    assert zero == pytest.approx(stall, rel=0.02)
    # the steady curve at these loads agrees with the transients to the finite-mass error
    for f, vt in zip(loads, v, strict=True):
        v = steady_state(params, 400, 14, load_N=f, accuracy="fast").velocity_m_s
        assert v == pytest.approx(vt, rel=1e-2)
    # beyond stall the transient slider creeps at most by its velocity ripple
    v_over = transient_reference(params, 400, 14, load_N=1.05 * stall, duration_s=0.1)[0]
    assert abs(v_over) < 1e-3 * v0


def test_transient_energy_balance_closes_with_a_load(params):
    # the load enters the slider's guide/load force rows, so the work-energy balance of the
    # transient must still close
    from contact.model import OperatingPoint
    from contact.options import SimulationOptions
    from contact.transient.event import solve_event
    from contact.transient.window import run_window

    op = OperatingPoint(400, 14, 40e3, 1.0)
    opts = SimulationOptions(duration_s=0.01, energy=True)
    out = solve_event(params, op, opts, run_window(op, 0.01, 1e-7, 20), params.mu_d)
    e = out.energy
    assert abs(e.residual_J) < 1e-6 * e.input_J
    assert e.guide_J < 0 and e.load_J < 0  # guide friction and the load take the slider's energy


@pytest.mark.parametrize("load_N", [0.3, -0.1])
def test_transient_energy_balance_splits_the_loads_work_from_the_guides(load_N):
    """The load's work over the window is -load_N times the slider's travel (the motor's
    output, with its sign), and the guide's friction is what the steady engine's balance gives
    (input = output + damping + interface + guide). ``guide_J`` had held the load's work too:
    on the beam set at its own frequency, 300 V / 14 N, driving backward, a 0.3 N load assists
    the slider with 7.0e-4 W, which ``guide_J`` read as the guide's (found by exploratory
    testing of ``lusm simulate --energy``). The reference: the steady engine's own powers
    (exact level) of the same point."""
    from contact.drive import auto_frequency
    from contact.simulate import simulate
    from rom.sources import get_params

    beam = get_params("beam")
    f = auto_frequency(beam)
    r = simulate(beam, 300, 14, f, duration_s=0.05, energy=True, load_N=load_N,
                 coupling="consistent")
    e, t = r.energy, r.steady.window_s
    v = r.steady.velocity_m_s
    assert v < -1e-4  # the beam set drives backward here: a positive load assists
    assert e.load_J == pytest.approx(-load_N * v * t, rel=1e-9)
    b = steady_state(beam, 300, 14, frequency_Hz=f, load_N=load_N, coupling="consistent",
                     accuracy="exact").from_rest
    assert b.velocity_m_s == pytest.approx(v, rel=1e-6)
    assert -e.load_J / t == pytest.approx(b.output_power_W, rel=1e-5)
    assert -e.guide_J / t == pytest.approx(b.guide_power_W, rel=1e-5)
    assert b.guide_power_W > 0
    assert abs(e.residual_J) < 1e-8 * e.input_J


@pytest.mark.slow
def test_exact_characteristic_follows_transients_with_the_load(params):
    # the finite-mass level against a settled transient with the load; the averaged level
    # differs by its O(1/M) error, which the exact one removes
    fast = characteristic(params, 200, 14, [0.2], accuracy="fast")
    exact = characteristic(params, 200, 14, [0.2], accuracy="exact")
    ref = transient_reference(params, 200, 14, load_N=0.2, duration_s=0.3)[0]
    assert exact.accuracy == "exact" and exact.velocity_m_s[0] == pytest.approx(ref, rel=1e-6)
    assert abs(fast.velocity_m_s[0] / ref - 1) > 1e-4
    assert exact.input_power_W[0] > 0 and exact.efficiency[0] > 0


@pytest.mark.parametrize("accuracy", ["fast", "exact"])
@pytest.mark.slow
def test_a_motor_driving_backward_has_the_mirrored_characteristic(params, accuracy):
    # A_b -> -A_b reverses the bending drive, and with it the direction the tip pushes the
    # slider: the characteristic is the mirror image (loads and velocities negated, powers
    # and efficiency the same), stall force included
    # one coupling for both ("auto" gives the edited set the consistent one)
    from contact.characteristic import STALL_RTOL

    fwd = characteristic(params, 400, 14, accuracy=accuracy, coupling="paper")
    mirrored = params.with_(A_b=-params.A_b)
    back = characteristic(mirrored, 400, 14, accuracy=accuracy, coupling="paper")
    # the exact level's stall force is a root of the full model's velocity to STALL_RTOL
    # (each root within it of the true one); the fast level's is G(0+) itself
    rel = 2 * STALL_RTOL if accuracy == "exact" else 1e-8
    assert back.stall_force_N == pytest.approx(-fwd.stall_force_N, rel=rel)
    assert back.no_load_velocity_m_s == pytest.approx(-fwd.no_load_velocity_m_s, rel=1e-8)
    np.testing.assert_allclose(back.load_N, -fwd.load_N, rtol=rel, atol=1e-12)
    # the curve itself at the mirrored loads exactly: the mirrored motor's orbit at 0+ is the
    # original's at 0-, 2e-9 m/s of drift away (contact.steady.branches.branches_at_load), which the
    # steep curve near stall turns into about 2e-9 m/s
    back = characteristic(mirrored, 400, 14, -fwd.load_N, accuracy=accuracy, coupling="paper")
    np.testing.assert_allclose(back.velocity_m_s, -fwd.velocity_m_s, rtol=1e-7, atol=5e-9)
    np.testing.assert_allclose(back.efficiency, fwd.efficiency, rtol=1e-7, atol=1e-9)


@pytest.mark.slow
def test_the_exact_stall_force_is_where_transients_with_the_load_change_direction(params):
    # finite slider mass: beyond the averaged stall force (0.41 N at 200 V / 14 N) the
    # slider still creeps forward, pulled on in every stick phase; the full model's speed
    # crosses zero further out. Settled transients with the load just below and above the
    # exact level's stall force move forward and backward
    fast = characteristic(params, 200, 14, [0.0], accuracy="fast")
    exact = characteristic(params, 200, 14, [0.0], accuracy="exact")
    stall = exact.stall_force_N
    assert stall > 1.5 * fast.stall_force_N
    below, _ = transient_reference(params, 200, 14, load_N=0.97 * stall, duration_s=0.6)
    above, _ = transient_reference(params, 200, 14, load_N=1.03 * stall, duration_s=0.6)
    assert below > 0 > above


def test_efficiency_is_defined_only_where_the_motor_delivers_work(params):
    # a load pushing the slider along (negative) or one driving it backward puts mechanical
    # power in: no efficiency there (it came out at -31 % at -4.5 N)
    c = characteristic(params, 400, 14, [-1.0, 0.5, 3.5], accuracy="fast")
    assert np.isnan(c.efficiency[0]) and np.isnan(c.efficiency[2])
    assert c.output_power_W[0] < 0 and c.output_power_W[2] < 0
    assert 0 < c.efficiency[1] < 1
    # a steady branch says the same (SteadyBranch.efficiency was -0.057 at 3.5 N)
    from contact.steady.engine import steady_state

    for load, defined in ((3.5, False), (0.5, True)):
        b = steady_state(params, 400, 14, load_N=load, accuracy="fast").from_rest
        assert (b.output_power_W >= 0) == defined
        assert np.isfinite(b.efficiency) == defined


@pytest.mark.slow
def test_the_averaging_doubt_is_the_librarys(params):
    """The check behind `lusm characteristic --accuracy fast`'s warnings lived in the CLI,
    with the ripple from the static mu_d: at 30 kHz the averaged no-load branch (0.0124 m/s)
    is not the creep a start from rest reaches (1.1e-4 m/s, a transient's); at 400 V / 14 N
    and 40 kHz the two levels agree and nothing is said."""
    from contact.characteristic import averaging_doubt

    c30 = characteristic(params, 200, 14, [0.0], frequency_Hz=30e3, coupling="paper",
                         accuracy="fast")
    doubt = averaging_doubt(params, c30, coupling="paper")
    assert doubt is not None and "not the one the finite-mass motor reaches" in doubt
    ref, _ = transient_reference(params, 200.0, 14.0, frequency_Hz=30e3, duration_s=0.3)
    assert ref < 0.02 * c30.no_load_velocity_m_s
    c400 = characteristic(params, 400, 14, [0.0], coupling="paper", accuracy="fast")
    assert averaging_doubt(params, c400, coupling="paper") is None


@pytest.mark.slow
def test_the_library_answers_at_the_clis_level_by_default():
    """characteristic() and steady_state() defaulted to the averaged level while the CLI
    runs the exact one: the FE set's stall force at 400 V / 14 N was 0.476 N from the
    library and 1.014 N from `lusm characteristic` (found by review)."""
    import inspect

    from contact.steady.engine import steady_state as ss

    assert inspect.signature(ss).parameters["accuracy"].default == "exact"
    assert inspect.signature(characteristic).parameters["accuracy"].default == "exact"
    c = characteristic(table2(), 200, 14, [0.0])
    assert c.accuracy == "exact"
    assert c.no_load_velocity_m_s == pytest.approx(
        transient_reference(table2(), 200.0, 14.0, duration_s=0.3)[0], rel=1e-8)


TUNED_40K = "examples/tuned_40k/stator.toml"
TUNED_60K = "examples/tuned_60k/stator.toml"


def _designer_set(path):
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file

    p = fem_params_from_file(path)
    return p, auto_frequency(p)


@pytest.mark.slow
def test_the_stall_force_is_the_first_stop_the_curve_shows():
    """The tuned 40 kHz stator at 100 V / 14 N creeps below its velocity ripple, and its
    velocity from rest is not monotone in the load: ``brentq`` had returned a later zero
    crossing (0.4605 N) while the printed curve went backward at 0.299 N and forward again
    at 0.345 N (exploratory testing), and asked at other loads it printed another stall
    force (review). The reference: transients from rest under the loads on either side of
    the stall force now printed; and the same stall force whatever loads are asked, with a
    warning where a load beyond it drives the slider forward again."""
    from contact.characteristic import NonMonotoneWarning
    from contact.simulate import simulate

    p, f = _designer_set(TUNED_40K)
    c = characteristic(p, 100.0, 14.0, frequency_Hz=f)
    assert c.no_load_velocity_m_s > 0.0
    below = float(c.load_N[-2])  # the default curve ends at the stall force
    step = float(c.load_N[1] - c.load_N[0])
    for load, sign in ((below, 1.0), (c.stall_force_N + step, -1.0)):
        r = simulate(p, 100.0, 14.0, f, duration_s=1.0, load_N=load)
        assert sign * r.steady.velocity_m_s > 0.0, (load, r.steady.velocity_m_s)
    with pytest.warns(NonMonotoneWarning, match="not monotone"):
        asked = characteristic(p, 100.0, 14.0, [0.0, 0.2, 0.4, 0.5], frequency_Hz=f)
    assert asked.stall_force_N == c.stall_force_N
    assert asked.velocity_m_s[2] > 0.0  # forward again at 0.4 N, beyond the stall


@pytest.mark.slow
def test_a_creep_band_is_a_creep_not_thrust_on_another_branch(capsys):
    """The tuned 60 kHz stator at 140 V / 14 N: the averages follow the pure-slip sheet,
    whose stall (0.47 N) the creep band had started from, while the start from rest rides
    a stick-slip sheet at 2.9e-3 m/s there (46 % of its no-load speed; exploratory
    testing). The band now begins where the velocity from rest falls below CREEP_RIPPLES
    ripple scales, and the line says where it comes from. Reference: transients from rest
    just before the band (faster than that) and inside it (slower)."""
    from contact.characteristic import CREEP_RIPPLES
    from contact.model import OperatingPoint, resolve_coupling
    from contact.simulate import simulate
    from contact.steady.slow import ripple_scale, slow_problem
    from lusm.cli import main

    p, f = _designer_set(TUNED_60K)
    c = characteristic(p, 140.0, 14.0, frequency_Hz=f)
    op = OperatingPoint(140.0, 14.0, f)
    sp = slow_problem(p, op, coupling=resolve_coupling(p, "auto"))
    creep = CREEP_RIPPLES * ripple_scale(p, op, sp.mu_d_eff)
    assert c.creep_rule == "creep threshold"
    assert c.averaged_stall_force_N < c.creep_from_N < c.stall_force_N
    gap = c.stall_force_N - c.creep_from_N
    for load, faster in ((c.creep_from_N - 0.1 * gap, True), (c.creep_from_N + 0.5 * gap, False)):
        v = simulate(p, 140.0, 14.0, f, duration_s=0.3, load_N=load).steady.velocity_m_s
        assert (abs(v) > creep) is faster, (load, v, creep)
    assert main(["characteristic", "--geometry", TUNED_60K, "--voltage", "140", "--preload",
                 "14", "--frequency", "auto", "--loads", "0,0.5,1.5"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "creeps from" in ln)
    assert "another branch's" in line and "the averaged stall:" not in line


@pytest.mark.slow
def test_no_creep_band_where_the_full_model_stalls_first(params):
    """Table 2 at 450 V / 40 N: the full model stalls at 2.73 N, before the averaged 3.16 N.
    The curve's last loads before a stall crawl too, as any velocity falling to zero does;
    at the default loads a band had been read off them (2.19 N, 'another branch's', review)."""
    c = characteristic(params, 450.0, 40.0)
    assert c.stall_force_N < c.averaged_stall_force_N
    assert np.isnan(c.creep_from_N) and c.creep_rule == ""
