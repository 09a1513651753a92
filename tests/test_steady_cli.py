"""``lusm characteristic``: JSON keys, the stall force against the curve, bad input."""

import json
import math

import pytest

from lusm.cli import main


@pytest.mark.slow
def test_characteristic_json_curve_is_consistent(capsys):
    assert main(["characteristic", "--voltage", "400", "--preload", "14",
                 "--loads", "0:1.5:0.5", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc) == {"no_load_velocity_m_s", "direction", "stall_force_N",
                        "averaged_stall_force_N", "creep_from_N", "creep_from_rule",
                        "creep_speed_m_s", "holding_range_N", "accuracy", "limits",
                        "curve", "damping", "coupling", "coupling_from", "voltage_V",
                        "preload_N", "frequency_Hz", "frequency_from", "rest"}
    assert doc["accuracy"] == "exact"  # the default: the finite-mass motor from rest
    assert doc["rest"] == "probe"  # decided by the run out of the ripple zone (--rest)
    assert doc["coupling"] == "paper"  # auto: Table 2's set reproduces the paper
    curve = doc["curve"]
    assert [row["load_N"] for row in curve] == pytest.approx([0.0, 0.5, 1.0, 1.5])
    for row in curve:
        assert set(row) == {"load_N", "velocity_m_s", "input_power_W", "output_power_W",
                            "efficiency", "limits"}
        assert row["output_power_W"] == pytest.approx(row["load_N"] * row["velocity_m_s"])
    assert curve[0]["velocity_m_s"] == pytest.approx(doc["no_load_velocity_m_s"])
    # all four loads are below the stall force, so the slider moves against each
    assert doc["stall_force_N"] > 1.5 and all(row["velocity_m_s"] > 0 for row in curve)
    # a comma list in any order (map's --voltages take one; --loads refused it) is the grid
    assert main(["characteristic", "--voltage", "400", "--preload", "14",
                 "--loads", "1.5,0,1,0.5", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert listed["curve"] == curve and listed["stall_force_N"] == doc["stall_force_N"]


@pytest.mark.slow
def test_the_default_characteristic_is_what_a_start_from_rest_reaches(capsys):
    """At 30 kHz the averaged (fast) level's only branch runs at 0.0124 m/s while the motor
    started from rest creeps at 1.1e-4 m/s: the default must give the motor's value."""
    from contact.steady.settled import transient_reference
    from rom import table2

    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--frequency",
                 "30000", "--loads", "0:0.1:0.1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    # from rest, 0.3 s (9 000 periods, settled to 1e-9 by 1.2 s), last 400 periods' mean
    ref, _ = transient_reference(table2(), 200.0, 14.0, frequency_Hz=30e3, duration_s=0.3)
    assert ref < 1e-3
    assert doc["no_load_velocity_m_s"] == pytest.approx(ref, rel=1e-7)
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--frequency",
                 "30000", "--loads", "0:0.1:0.1", "--json", "--accuracy", "fast"]) == 0
    out = capsys.readouterr()
    fast = json.loads(out.out)["no_load_velocity_m_s"]
    assert fast > 50 * ref  # what the default used to print, silently
    assert "is not the one the finite-mass motor reaches from rest" in out.err


def test_simulate_steady_with_a_load_matches_a_settled_transient(capsys):
    """lusm simulate --steady --load-N against the transient with the same load, settled."""
    import json

    from contact.simulate import simulate
    from lusm.cli import main
    from rom import table2

    assert main(["simulate", "--voltage", "400", "--preload", "14", "--load-N", "1",
                 "--steady", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["method"] == "steady" and doc["load_N"] == 1.0
    ref = simulate(table2(), 400.0, 14.0, load_N=1.0, duration_s=0.3)
    assert ref.steady.settled
    assert doc["steady_velocity_m_s"] == pytest.approx(ref.steady.velocity_m_s, rel=1e-4)
    # the load slows the motor (below the no-load velocity of the same point)
    assert doc["steady_velocity_m_s"] < 0.9 * simulate(table2(), 400.0, 14.0,
                                                       method="steady").steady.velocity_m_s


@pytest.mark.slow
def test_characteristic_takes_a_list_of_voltages(capsys):
    """``--voltage 200,400``: one curve per voltage, each the single-voltage answer."""
    assert main(["characteristic", "--voltage", "200,400", "--preload", "14",
                 "--loads", "0:1:0.5", "--json"]) == 0
    many = json.loads(capsys.readouterr().out)
    assert many["voltages_V"] == [200.0, 400.0]
    for v, doc in zip((200, 400), many["characteristics"], strict=True):
        assert main(["characteristic", "--voltage", str(v), "--preload", "14",
                     "--loads", "0:1:0.5", "--json"]) == 0
        assert json.loads(capsys.readouterr().out) == doc


def test_simulate_takes_a_list_of_voltages(capsys):
    """``lusm simulate --voltage 200,400``: one run per voltage, each the single-voltage run."""
    args = ["--preload", "14", "--duration", "0.005", "--json"]
    assert main(["simulate", "--voltage", "200,400", *args]) == 0
    many = json.loads(capsys.readouterr().out)
    assert many["voltages_V"] == [200.0, 400.0]
    from validation.summaries import SIMULATION_KEYS

    for doc in many["runs"]:  # every run the same keys, a transient's branches null
        assert list(doc)[:len(SIMULATION_KEYS)] == list(SIMULATION_KEYS)
        assert doc["branches"] is None and doc["runs_away"] is None
    for v, doc in zip((200, 400), many["runs"], strict=True):
        assert main(["simulate", "--voltage", str(v), *args]) == 0
        one = json.loads(capsys.readouterr().out)
        assert one["steady_velocity_m_s"] == doc["steady_velocity_m_s"]
        assert one["voltage_V"] == doc["voltage_V"] == v


def test_map_takes_the_sets_own_frequency(capsys):
    # --frequency auto, as simulate and characteristic take it: the beam set's resonances lie
    # far above 40 kHz; the map's point equals the steady state at that frequency
    from contact.drive import auto_frequency
    from contact.steady.engine import steady_state
    from rom.sources import get_params

    assert main(["map", "--source", "beam", "--damping", "table2", "--frequency", "auto",
                 "--voltages", "200",
                 "--preloads", "14", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    p = get_params("beam")
    f = auto_frequency(p)
    assert doc["frequency_Hz"] == pytest.approx(f, rel=1e-12) and f > 50e3
    ref = steady_state(p, 200, 14, frequency_Hz=f, coupling="consistent", accuracy="exact",
                       energy=False)
    assert doc["steady_velocity_m_s"][0][0] == pytest.approx(ref.velocity_m_s, rel=1e-9)


@pytest.mark.parametrize("frequency_Hz", [100.0, 1e6])
@pytest.mark.slow
def test_steady_commands_do_not_check_the_transients_step(capsys, frequency_Hz):
    # --steady and the steady map take their own step: the default --duration (0.05 s) is
    # under 10 periods at 100 Hz and the default --dt (1e-7 s) over 1/(20 f) at 1 MHz, which
    # refused these drives though nobody typed either option. The answer is a transient's
    # at a step and length valid there (far from resonance the slider stays held)
    from contact.options import SimulationOptions
    from contact.simulate import simulate
    from rom import table2

    freq = f"{frequency_Hz:g}"
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--frequency", freq,
                 "--steady", "--json"]) == 0
    steady = json.loads(capsys.readouterr().out)
    assert main(["map", "--voltages", "200", "--preloads", "14", "--frequency", freq,
                 "--json"]) == 0
    mapped = json.loads(capsys.readouterr().out)
    t = simulate(table2(), 200, 14, frequency_Hz,
                 SimulationOptions(duration_s=max(0.05, 20 / frequency_Hz),
                                   dt_s=min(1e-7, 1 / (20 * frequency_Hz))))
    assert t.steady.motion == steady["motion"] == mapped["motion"][0][0]
    assert abs(steady["steady_velocity_m_s"] - t.steady.velocity_m_s) <= 1e-9
    assert mapped["steady_velocity_m_s"][0][0] == pytest.approx(steady["steady_velocity_m_s"],
                                                                abs=1e-12)


def test_a_drive_too_slow_for_the_steady_engine_is_refused_in_one_line(capsys):
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--frequency", "1",
                 "--steady"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--frequency" in err[0] and "steps per drive period" in err[0]


STEADY_COMMANDS = [["characteristic", "--voltage", "200", "--preload", "14"],
                   ["map", "--voltages", "200", "--preloads", "14"],
                   ["simulate", "--steady", "--voltage", "200", "--preload", "14"]]


@pytest.mark.parametrize("frequency, steps", [("10", 29846), ("14.92", 20004)])
def test_a_drive_too_slow_for_the_steady_engine_is_given_its_range_in_hz(frequency, steps,
                                                                         capsys):
    # it had said only "29846 steps per drive period, above 20000", and simulate --steady
    # "2.98e+04" in the engine's words; one message with the range for the three commands
    said = f"--frequency must be in [14.93, 1e+07] Hz for the steady engine on this stator, " \
           f"got {frequency}: too far below its fastest mode ({steps} steps per drive " \
           "period, above 20000)"
    for argv in STEADY_COMMANDS:
        assert main([*argv, "--frequency", frequency]) == 2
        err = capsys.readouterr().err.strip()
        assert err == f"lusm {argv[0]}: error: {said}", err


@pytest.mark.slow
@pytest.mark.benchmark  # what the command says, at a costly run's price
def test_the_lowest_steady_frequency_said_is_taken(capsys):
    # the bound said, 14.93 Hz, is one the engine runs (14.92 is refused above)
    assert main(["map", "--voltages", "200", "--preloads", "14", "--accuracy", "fast",
                 "--frequency", "14.93", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["motion"][0][0]


def test_no_drive_frequency_the_option_takes_suits_a_stiff_stator(monkeypatch):
    # where the lowest frequency is above the option's range, that range is said empty
    from lusm import limits
    from lusm.errors import LusmError
    from lusm.options import check_steady_frequency
    from rom import table2

    monkeypatch.setattr(limits, "FREQUENCY_HZ", (1.0, 10.0))
    with pytest.raises(LusmError, match=r"^--frequency: no drive in \[1, 10\] Hz suits the "
                       r"steady engine on this stator, whose fastest mode needs 14.93 Hz or "
                       r"more \(29846 steps per drive period, above 20000 at 10 Hz\)$"):
        check_steady_frequency(table2(), 10.0, "paper")


def test_simulate_steady_reports_no_run_length_it_did_not_use(capsys):
    from lusm.cli import main

    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["method"] == "steady" and d["duration_s"] is None and d["dt_s"] is None
    # nor windows or tip extremes it has not: they had read "y_tip_min_m nan" and the
    # default run's window, 0.000125 s, as if measured; nor a switch count: 200 V / 14 N is
    # stick-slip, and "events 0" said its orbit never switched
    assert d["motion"] == "stick-slip"
    unused = ("previous_window_velocity_m_s", "y_tip_min_m", "steady_window_s", "events")
    assert all(d[k] is None for k in unused) and d["settled"] is True
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady"]) == 0
    out = capsys.readouterr().out
    assert not any(k in out for k in ("duration_s", "dt_s", *unused)) and "nan" not in out


@pytest.mark.parametrize("load, way", [("1000", "backward"), ("-1000", "forward")])
def test_a_transient_under_a_load_the_motor_cannot_hold_says_so(load, way, capsys):
    # it printed -250 m/s as the "steady velocity" without a word; the steady engine refuses
    from lusm.cli import main

    args = ["simulate", "--voltage", "200", "--preload", "14", "--load-N", load,
            "--duration", "0.01"]
    assert main([*args, "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert not d["settled"] and (d["steady_velocity_m_s"] < 0) == (way == "backward")
    assert f"runs away {way}" in cap.err and len(cap.err.strip().splitlines()) == 1
    # the JSON says so in the key a --steady list's runaway has
    assert f"runs away {way}" in d["runs_away"] and "where the run stopped" in d["runs_away"]
    assert main([*args[:-2], "--steady"]) == 2  # the steady engine: no steady state
    assert f"runs away {way}" in capsys.readouterr().err


def test_a_steady_study_is_bounded_by_its_cost_at_the_drive_frequency(capsys):
    # a point costs in proportion to its steps per period: 10 000 points at 20 Hz were
    # accepted (hours); the refusal names the option and how many would fit
    from lusm.cli import main

    assert main(["map", "--frequency", "20", "--voltages", "50:446:4",
                 "--preloads", "10:25.84:0.16"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lusm map: error: --voltages: 10000 points at 20 Hz") and \
        "at most 33 here" in err
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--frequency", "20",
                 "--loads", "0:1.999:0.001"]) == 2
    assert "--loads: 2000 loads x voltages at 20 Hz" in capsys.readouterr().err


@pytest.mark.slow
def test_the_fast_level_says_when_the_averaging_does_not_hold(capsys):
    # at 100 Hz the averaged no-load velocity is far below the slider's ripple
    from lusm.cli import main

    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--frequency",
                 "100", "--loads", "0:0.1:0.1", "--json", "--accuracy", "fast"]) == 0
    assert "the averaging behind --accuracy fast does not hold" in capsys.readouterr().err
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--loads",
                 "0:0.1:0.1", "--json", "--accuracy", "fast"]) == 0
    assert "warning" not in capsys.readouterr().err


@pytest.mark.slow
def test_characteristic_names_its_operating_point(capsys):
    # with --frequency auto the frequency used was nowhere in the output
    from lusm.cli import main

    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--source", "beam",
                 "--frequency", "auto", "--loads", "0:0.1:0.1", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["voltage_V"] == 200 and d["preload_N"] == 14 and d["frequency_from"] == "auto"
    assert d["frequency_Hz"] > 1e3
    # " AUTO" is the same rule (the parser takes it): it was echoed as typed and untagged
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--source", "beam",
                 "--frequency", " AUTO", "--loads", "0:0.1:0.1"]) == 0
    drive = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("drive"))
    assert drive.endswith(f"{d['frequency_Hz']:.6g} Hz (auto)")


def test_an_unsettled_transient_says_so(capsys):
    # 300 V / 14 N at the default 50 ms: settled False in the table and nothing on stderr
    from lusm.cli import main

    assert main(["simulate", "--voltage", "300", "--preload", "14", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["settled"] is False
    assert "has not settled within the default duration 0.05 s" in cap.err
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["settled"] is True and "warning" not in cap.err


def test_a_held_slider_ringing_about_rest_is_settled(capsys):
    """200 V / 150 N is pure stick (the dead zone): the slider is held by the tip and its
    window means are the decaying ring about rest (-2.5e-8 after -4.5e-8 m/s), which the 1 %
    rule had called "not settled, give a longer --duration". A four times longer run agrees
    that the held velocity is zero to far below the motor's speeds."""
    from lusm.cli import main

    assert main(["simulate", "--voltage", "200", "--preload", "150", "--json"]) == 0
    cap = capsys.readouterr()
    short = json.loads(cap.out)
    assert short["motion"] == "pure-stick" and short["settled"] is True
    assert "has not settled" not in cap.err
    assert main(["simulate", "--voltage", "200", "--preload", "150", "--duration", "0.2",
                 "--json"]) == 0
    long = json.loads(capsys.readouterr().out)
    assert long["motion"] == "pure-stick"
    assert abs(long["steady_velocity_m_s"]) < 1e-7 and abs(short["steady_velocity_m_s"]) < 1e-6


def test_a_nan_efficiency_is_explained(capsys):
    """A load that assists the motion (-0.2 N) has negative output power and efficiency
    NaN (contact.steady.branches.motor_efficiency); the table printed 'nan' without a word."""
    from lusm.cli import main

    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--loads",
                 "-0.2:0.2:0.2", "--accuracy", "fast"]) == 0
    out = capsys.readouterr().out
    row = next(ln for ln in out.splitlines() if ln.strip().startswith("-0.2"))
    assert float(row.split()[3]) < 0 and row.split()[4] == "nan"
    assert "eff. nan: negative mechanical output" in out and "no electrical input" not in out
    # undriven, the output is 0 W and the input too: the note had blamed a negative output
    assert main(["characteristic", "--voltage", "0", "--preload", "14"]) == 0
    out = capsys.readouterr().out
    row = next(ln for ln in out.splitlines() if ln.split()[:1] == ["0"])
    assert float(row.split()[2]) == 0.0 and row.split()[4] == "nan"
    assert "eff. nan: no electrical input" in out and "negative mechanical" not in out


def test_simulate_steady_names_the_stable_branches_a_start_from_rest_does_not_reach(capsys):
    """At 150 V / 14 N a period-1 branch is stable beside the period-2 one reached from rest
    (docs/steady.md): a one-point answer names it, with the velocity a settled transient
    started on that branch keeps; at 200 V / 14 N there is one branch and no word."""
    from contact import state as S
    from contact.model import OperatingPoint
    from contact.steady.engine import steady_state
    from contact.steady.full_orbit import full_system, run_periods
    from contact.steady.slow import slow_problem
    from rom import table2

    assert main(["simulate", "--voltage", "150", "--preload", "14", "--steady", "--json"]) == 0
    out = capsys.readouterr()
    err = out.err.strip().splitlines()
    assert len(err) == 1 and "another stable steady state" in err[0]
    other = float(err[0].split("reaches: ")[1].split(" m/s")[0])
    r = steady_state(table2(), 150, 14, energy=False)
    k1 = next(b for b in r.branches if b.stable and not b.from_rest)
    assert other == pytest.approx(k1.velocity_m_s, rel=1e-3)  # printed to 4 figures
    # the JSON lists both, as lusm map writes a point's branches (the other one had been in
    # the warning alone, to 4 figures)
    doc = json.loads(out.out)
    assert [(b["k"], b["motion"], b["from_rest"], b["held"]) for b in doc["branches"]] == [
        (2, "stick-slip", True, False), (1, "stick-slip", False, False)]
    assert doc["branches"][0]["velocity_m_s"] == pytest.approx(doc["steady_velocity_m_s"],
                                                                rel=1e-12)
    assert doc["branches"][1]["velocity_m_s"] == pytest.approx(k1.velocity_m_s, rel=1e-9)
    # and the text, one line per branch
    assert main(["simulate", "--voltage", "150", "--preload", "14", "--steady"]) == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("branch")]
    assert len(lines) == 2 and lines[0].startswith("branch (from rest)")
    assert "period 2" in lines[0] and "period 1" in lines[1]
    assert float(lines[1].split()[1]) == pytest.approx(k1.velocity_m_s, rel=1e-5)
    # a slider put on that orbit stays there: 4 000 periods of the full model (0.1 s) keep it
    op = OperatingPoint(150.0, 14.0, 40e3)
    sp = slow_problem(table2(), op, coupling="paper", accuracy="exact")
    fsys = full_system(table2(), op, sp.mu_d_eff, "paper")
    o = sp.orbit(k1.velocity_m_s)
    z = o.z.copy()
    z[S.DX] = k1.velocity_m_s
    z, m, _, _, _ = run_periods(fsys, z, o.mode - o.mode % 3 + S.FORWARD, 4000)
    _, _, dist, _, _ = run_periods(fsys, z, m, 400)
    assert dist / (400 / 40e3) == pytest.approx(k1.velocity_m_s, rel=1e-3)
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady"]) == 0
    assert capsys.readouterr().err == ""


def test_an_undriven_characteristic_says_why_it_has_no_holding_range(capsys):
    """0 V / 14 N: holding_range_N is NaN (the tip sticks at the scan's ends) and the text
    had simply left the line out (found by exploratory testing); the loads beyond the tip's
    sliding friction run away from rest, as the transient says."""
    from contact.steady.runaway import stiction_hold_N
    from rom import table2

    assert main(["characteristic", "--voltage", "0", "--preload", "14", "--loads",
                 "5:6:1"]) == 0
    out = capsys.readouterr().out
    assert "no runaway within (N)      no full-slip bound" in out
    slide, static = stiction_hold_N(table2(), 14.0, table2().mu_d)
    assert slide < 6.0 < static
    rows = [ln.split() for ln in out.splitlines() if ln.strip().startswith(("5 ", "6 "))]
    assert rows[0][1] == "0" and rows[1][1:] == ["runs", "away"]


@pytest.mark.slow
@pytest.mark.benchmark  # what the command says, at a costly run's price
def test_the_creep_band_below_the_exact_stall_force_is_said(capsys):
    """A designer read the speed-load curve's knee as the stall force and found half the
    printed one (0.76 against 1.38 N): between the averaged stall force and the exact one the
    finite slider only creeps. The command prints where the creep begins (the fast level's
    stall force, computed here independently) and the JSON carries it; "holds loads" read as
    a holding force and is now "no runaway within"."""
    from contact.characteristic import characteristic
    from rom import table2

    fast = characteristic(table2(), 200.0, 14.0, accuracy="fast")
    exact = characteristic(table2(), 200.0, 14.0, loads_N=[0.0, 0.6])
    assert exact.averaged_stall_force_N == pytest.approx(fast.stall_force_N, rel=1e-12)
    assert exact.stall_force_N > 2.0 * exact.averaged_stall_force_N
    # the creep: a load in the band moves the slider at under 2 % of its no-load speed
    assert 0.0 < exact.velocity_m_s[1] < 0.02 * exact.no_load_velocity_m_s
    # the exact curve's orbits include each load's own steady state
    assert exact.orbits > fast.orbits
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--loads",
                 "0:0.6:0.6"]) == 0
    out = capsys.readouterr().out
    assert f"creeps from (N)            {fast.stall_force_N:.6g} (the averaged stall" in out
    assert "no runaway within (N)" in out and "holds loads" not in out
    assert main(["characteristic", "--voltage", "200", "--preload", "14", "--loads",
                 "0:0.2:0.2", "--accuracy", "fast"]) == 0
    assert "creeps from" not in capsys.readouterr().out
    # where the full model stalls first (450 V / 40 N: 2.73 N against the averaged 3.16 N)
    # there is no creep band, and none is said (it had printed "creeps from 3.157 ... at most
    # 0 m/s"; review)
    high = characteristic(table2(), 450.0, 40.0, loads_N=[0.0, 3.0])
    assert high.stall_force_N < high.averaged_stall_force_N and math.isnan(high.creep_from_N)
    assert main(["characteristic", "--voltage", "450", "--preload", "40", "--loads",
                 "0,3"]) == 0
    assert "creeps from" not in capsys.readouterr().out
    assert exact.creep_from_N == exact.averaged_stall_force_N


@pytest.mark.slow
@pytest.mark.benchmark  # what the command says, at a costly run's price
def test_a_creep_where_the_averaged_slider_is_held_is_said(capsys):
    """The beam set at 200 V / 14 N, driven at its own frequency: the averaged slider is
    held without load (fast stall force 0), while the finite slider creeps backward from
    rest, its velocity ripple crossing zero every period (a transient from rest, the
    independent reference). The whole curve is a creep band from 0 N; ``creep_from_N`` had
    been NaN there (``0 * stall <= 0`` read as "the other sign") and the command printed a
    plain stall force with no word of the creep."""
    from contact.characteristic import characteristic
    from contact.drive import auto_frequency
    from contact.simulate import simulate
    from rom.sources import get_params

    p = get_params("beam")
    f = auto_frequency(p)
    fast = characteristic(p, 200.0, 14.0, loads_N=[0.0], frequency_Hz=f, accuracy="fast")
    assert fast.stall_force_N == 0.0 and fast.no_load_velocity_m_s == 0.0
    exact = characteristic(p, 200.0, 14.0, loads_N=[0.0], frequency_Hz=f)
    r = simulate(p, 200.0, 14.0, f, duration_s=0.1)
    v = r.window.v_m_s
    assert v.min() < 0.0 < v.max()  # the slider stops in every period: a creep
    assert exact.no_load_velocity_m_s == pytest.approx(r.steady.velocity_m_s, rel=1e-3)
    assert exact.no_load_velocity_m_s < 0.0 and exact.stall_force_N < 0.0
    assert exact.averaged_stall_force_N == 0.0
    assert exact.creep_from_N == 0.0
    assert main(["characteristic", "--source", "beam", "--damping", "table2", "--voltage",
                 "200", "--preload", "14", "--frequency", "auto", "--loads", "0,-0.2"]) == 0
    out = capsys.readouterr().out
    top = abs(exact.no_load_velocity_m_s)
    assert "creeps from (N)            0 (the whole curve" in out
    assert exact.creep_rule == "whole curve"
    assert f"at most {top:.3g} m/s on this curve" in out


@pytest.mark.slow
def test_the_tuned_stators_documented_command_shows_both_branches(capsys):
    """docs/numbers.json quotes the tuned 60 kHz stator's pure-slip branch at 140 V / 14 N from
    ``lusm simulate ... --steady --json (branches: ...)``, whose JSON had no branches: the
    number was in a stderr warning, to 4 figures, alone (found by exploratory testing). The
    command now shows it, and the branch from rest, to the claims' tolerance."""
    from tests.conftest import ROOT
    from tools.doc_numbers import claims_by_key

    numbers = json.loads((ROOT / "docs" / "numbers.json").read_text())["numbers"]
    slip, rest = (numbers[k] for k in ("tuned60k_140V_14N_slip_m_s",
                                       "tuned60k_140V_14N_rest_m_s"))
    assert "--steady --json (branches" in claims_by_key()["tuned60k_140V_14N_slip_m_s"].command
    assert main(["simulate", "--geometry", str(ROOT / "examples/tuned_60k/stator.toml"),
                 "--voltage", "140", "--preload", "14", "--frequency", "auto", "--steady",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["steady_velocity_m_s"] == pytest.approx(rest["value"], rel=1e-6)
    (pure_slip,) = [b for b in doc["branches"] if b["motion"] == "pure-slip"]
    assert pure_slip["velocity_m_s"] == pytest.approx(slip["value"], rel=1e-6)
    assert not pure_slip["from_rest"]
    (from_rest,) = [b for b in doc["branches"] if b["from_rest"]]
    assert from_rest["motion"] == "stick-slip"


def test_a_runs_summary_takes_no_key_the_others_lack():
    """Every run of one lusm simulate carries SIMULATION_KEYS: a key outside them is refused
    where the summary is built, not found later as one run's odd key."""
    from rom import table2
    from validation.summaries import SIMULATION_KEYS, runaway_summary

    d = runaway_summary(table2(), 400.0, 14.0, 40e3, 6.0, "paper", True, "runs away")
    assert list(d) == list(SIMULATION_KEYS)
    assert math.isnan(d["steady_velocity_m_s"]) and d["runs_away"] == "runs away"
    from validation import summaries

    with pytest.raises(KeyError, match="not keys of a run's summary"):
        summaries._run_summary(source="x", velocity=1.0)
