"""The branch a start from rest reaches: the full model's run out of the slider's ripple zone
and the averaged sheet it is on (contact.steady.from_rest), each case against a transient from
rest."""

import math

import pytest

from contact.model import OperatingPoint, resolve_coupling
from contact.steady import from_rest
from contact.steady.engine import steady_state
from contact.steady.exact import REST_TRANSIENT_PERIODS
from contact.steady.from_rest import PROBE_PERIODS, probe_from_rest
from contact.steady.full_orbit import full_system
from contact.steady.settled import transient_reference
from contact.steady.slow import slow_problem
from rom import table2


@pytest.fixture(scope="module")
def params():
    return table2()


def _probe(params, voltage_V, preload_N, load_N=0.0):
    coupling = resolve_coupling(params, "auto")  # as steady_state's default
    op = OperatingPoint(voltage_V, preload_N, 40e3, load_N)
    sp = slow_problem(params, op, coupling=coupling, accuracy="exact")
    return probe_from_rest(sp, full_system(params, op, sp.mu_d_eff, coupling))


@pytest.mark.parametrize(("voltage_V", "preload_N"), [(200, 14), (300, 18)])
def test_the_sheet_from_rest_gives_the_settled_transient(params, voltage_V, preload_N):
    # stick-slip and pure slip: the run from rest leaves the ripple zone within the probe's
    # budget, and the orbit shot at its sheet's root is the one a 0.3 s transient settles on
    r = steady_state(params, voltage_V, preload_N, energy=False)
    ref, _ = transient_reference(params, voltage_V, preload_N, duration_s=0.3)
    assert r.rest_periods <= PROBE_PERIODS < REST_TRANSIENT_PERIODS
    assert r.velocity_m_s == pytest.approx(ref, rel=1e-8)


def test_a_slider_that_leaves_its_sheet_is_left_to_the_transient(params, monkeypatch):
    """126.9 V / 14.72 N under -1.57 N: the full model leaves the ripple zone on a period-1
    sheet whose root is stable, but its slider accelerates at about half the rate that sheet
    predicts and settles on a slower period-2 orbit. The tracking check sends the point to
    the transient from rest; without it the probe answers with the faster orbit."""
    probe = _probe(params, 126.9, 14.72, -1.57)
    assert probe.orbit is None and "does not follow" in probe.reason
    r = steady_state(params, 126.9, 14.72, load_N=-1.57, energy=False)
    ref, _ = transient_reference(params, 126.9, 14.72, load_N=-1.57, duration_s=0.3)
    assert r.rest_periods == REST_TRANSIENT_PERIODS and r.from_rest.k == 2
    assert r.velocity_m_s == pytest.approx(ref, rel=1e-6)
    monkeypatch.setattr(from_rest, "TRACK_RTOL", math.inf)
    unchecked = steady_state(params, 126.9, 14.72, load_N=-1.57, energy=False)
    assert unchecked.rest_periods < REST_TRANSIENT_PERIODS
    assert unchecked.from_rest.k == 1 and unchecked.velocity_m_s > 1.3 * ref


@pytest.mark.slow
def test_a_sheet_that_folds_before_its_root_is_left_to_the_transient():
    # the FE set at 159.48 V / 9.85 N under 2.622 N: the period-1 sheet the slider leaves the
    # ripple zone on ends before its root; a start from rest goes on to another orbit
    from rom.sources import get_params

    p = get_params("fem")
    probe = _probe(p, 159.48, 9.85, 2.622)
    assert probe.orbit is None and "folds" in probe.reason
    r = steady_state(p, 159.48, 9.85, frequency_Hz=40e3, load_N=2.622, energy=False)
    ref, _ = transient_reference(p, 159.48, 9.85, frequency_Hz=40e3, load_N=2.622,
                                 duration_s=0.3)
    assert r.rest_periods == REST_TRANSIENT_PERIODS
    assert r.velocity_m_s == pytest.approx(ref, rel=1e-6)


def test_a_slider_held_in_the_ripple_zone_is_left_to_the_transient(params):
    # 150 V / 14 N: the start from rest settles on a period-2 orbit at 8.4e-4 m/s, ten
    # ripple scales, below the probe's threshold of twenty
    probe = _probe(params, 150, 14)
    assert probe.orbit is None and probe.full_periods == PROBE_PERIODS
    r = steady_state(params, 150, 14, energy=False)
    assert r.rest_periods == REST_TRANSIENT_PERIODS and r.from_rest.k == 2


def test_a_chattering_fast_problem_is_left_to_the_transient(params, monkeypatch):
    # the probe's fast orbits can meet a chattering contact the transient does not: the
    # point is then decided by the transient from rest, not lost
    from contact.errors import ChatteringError

    def chatters(*args, **kwargs):
        raise ChatteringError("contact chattering in the fixed-velocity fast problem")

    monkeypatch.setattr(from_rest, "find_orbit", chatters)
    probe = _probe(params, 200, 14)
    assert probe.orbit is None and "no periodic fast orbit" in probe.reason
    r = steady_state(params, 200, 14, energy=False)
    ref, _ = transient_reference(params, 200, 14, duration_s=0.3)
    assert r.rest_periods == REST_TRANSIENT_PERIODS
    assert r.velocity_m_s == pytest.approx(ref, rel=1e-8)


@pytest.fixture(scope="module")
def beam_miss_ref():
    """The settled transient (0.4 s) at the probe's known miss: the beam set at 1000 V /
    10 N under -1 N, 40 kHz (m/s); three tests compare with it."""
    from rom.sources import get_params

    return transient_reference(get_params("beam"), 1000, 10, load_N=-1.0, frequency_Hz=40e3,
                               duration_s=0.4)[0]


def test_rest_transient_decides_where_the_probe_is_known_to_miss(beam_miss_ref):
    """A known failure of the probe (docs/steady.md, "The start from rest"): the beam set at
    1000 V / 10 N under -1 N. The slider follows its sheet out of the ripple zone, then
    settles 5 % below the sheet's root on another stable orbit; the probe answers with the
    stable orbit at the root. ``rest="transient"`` decides by the transient from rest and
    gives what a settled transient gives."""
    from rom.sources import get_params

    p = get_params("beam")
    kw = {"load_N": -1.0, "frequency_Hz": 40e3}  # the failure is at 40 kHz, below the modes
    ref = beam_miss_ref
    strict = steady_state(p, 1000, 10, energy=False, rest="transient", **kw)
    assert strict.rest_periods == REST_TRANSIENT_PERIODS
    assert strict.velocity_m_s == pytest.approx(ref, rel=1e-6)
    probe = steady_state(p, 1000, 10, energy=False, **kw)
    assert probe.rest_periods < PROBE_PERIODS and probe.from_rest.stable
    assert probe.velocity_m_s > 1.03 * ref  # the documented miss
    with pytest.raises(ValueError, match="rest must be one of"):
        steady_state(p, 1000, 10, rest="shortcut")


@pytest.mark.slow
@pytest.mark.benchmark  # what the command says, at a costly run's price
def test_the_cli_takes_rest_transient_where_the_probe_is_known_to_miss(capsys, beam_miss_ref):
    # the same point from lusm characteristic: --rest transient gives the transient's value
    import json

    from lusm.cli import main

    argv = ["characteristic", "--source", "beam", "--damping", "table2", "--voltage", "1000",
            "--preload", "10",
            "--loads=-1:-1:1", "--json", "--frequency", "40e3"]  # the reference's drive
    assert main([*argv, "--rest", "transient"]) == 0
    strict = json.loads(capsys.readouterr().out)["curve"][0]["velocity_m_s"]
    assert main(argv) == 0
    probe = json.loads(capsys.readouterr().out)["curve"][0]["velocity_m_s"]

    ref = beam_miss_ref
    assert strict == pytest.approx(ref, rel=1e-6) and probe > 1.03 * ref
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--loads", "0:0:1",
                 "--accuracy", "fast", "--rest", "transient"]) == 0
    assert "--rest has no effect" in capsys.readouterr().err
    assert main(["map", "--voltages", "200", "--preloads", "14", "--rest", "never"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--rest" in err[0]


def test_simulate_steady_takes_rest_too(capsys, beam_miss_ref):
    # the single-point steady answer: --rest transient at the known miss gives the
    # transient's value, as lusm map and lusm characteristic do
    import json

    from contact.options import SimulationOptions
    from lusm.cli import main

    argv = ["simulate", "--source", "beam", "--damping", "table2", "--voltage", "1000",
            "--preload", "10",
            "--load-N=-1", "--frequency", "40000", "--steady", "--json"]
    assert main([*argv, "--rest", "transient"]) == 0
    v = json.loads(capsys.readouterr().out)["steady_velocity_m_s"]
    ref = beam_miss_ref
    assert v == pytest.approx(ref, rel=1e-6)
    with pytest.raises(ValueError, match="rest must be one of"):
        SimulationOptions(rest="never")
