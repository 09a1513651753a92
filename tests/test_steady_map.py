"""``stick_slip_map(method="steady")`` and ``lusm map``'s default against settled transients."""

import json

import numpy as np
import pytest

from contact.maps import stick_slip_map
from contact.steady.settled import transient_reference
from rom import table2


@pytest.fixture(scope="module")
def steady_map():
    # 100 V: dead zone; 150 V / 14 N: two stable branches; 200 and 300 V: stick-slip,
    # 300 V / 10 N: slip-separation
    return stick_slip_map(table2(), [100.0, 150.0, 200.0, 300.0], [10.0, 14.0], progress=False,
                          method="steady", accuracy="exact")


@pytest.mark.parametrize(("voltage_V", "preload_N"), [(200.0, 14.0), (300.0, 10.0),
                                                      (150.0, 14.0), (100.0, 14.0)])
def test_steady_map_points_match_settled_transients(steady_map, voltage_V, preload_N):
    i = int(np.flatnonzero(steady_map.voltages_V == voltage_V)[0])
    j = int(np.flatnonzero(steady_map.preloads_N == preload_N)[0])
    v_t, motion_t = transient_reference(table2(), voltage_V, preload_N, duration_s=0.3)
    assert steady_map.settled[i, j]
    assert steady_map.motion[i, j] == motion_t
    assert steady_map.velocity_m_s[i, j] == pytest.approx(v_t, rel=1e-5, abs=1e-12)


def test_steady_map_reports_both_branches_at_150_V_14_N(steady_map):
    i, j = 1, 1
    stable = steady_map.branches[i, j]
    assert len(stable) == 2
    from_rest = [b for b in stable if b[3]]
    assert len(from_rest) == 1 and from_rest[0][0] == pytest.approx(
        steady_map.velocity_m_s[i, j], rel=1e-12)
    assert {b[1] for b in stable} == {1, 2}  # a one-period and a two-period tip orbit


def test_map_json_keeps_its_keys_and_adds_branches(capsys):
    from lusm.cli import main

    assert main(["map", "--voltages", "150,300", "--preloads", "14", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("voltages_V", "preloads_N", "motion", "steady_velocity_m_s", "stick_fraction",
                "separation_fraction", "mu_d_effective", "settled", "counts", "wall_time_s"):
        assert key in d
    assert d["method"] == "steady"
    assert len(d["branches"][0][0]) == 2 and len(d["branches"][1][0]) == 1
    assert d["branches"][1][0][0]["from_rest"] is True


def test_a_held_points_branch_speaks_the_points_vocabulary(steady_map, capsys):
    """100 V / 14 N holds the slider: the point's motion is pure-stick (as a transient's),
    and its branch had said "dead-zone" in the same JSON (found by exploratory testing); the
    branch now says pure-stick too, and ``held`` says the slider is held."""
    from lusm.cli import main

    i, j = 0, 1
    assert steady_map.motion[i, j] == "pure-stick"
    (row,) = steady_map.branches[i, j]
    assert row[2] == "pure-stick" and row[4] is True and row[0] == 0.0
    moving = steady_map.branches[2, 1]  # 200 V / 14 N: stick-slip, not held
    assert [(b[2], b[4]) for b in moving] == [("stick-slip", False)]
    assert main(["map", "--voltages", "100,200", "--preloads", "14", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    held, moves = d["branches"][0][0], d["branches"][1][0]
    assert d["motion"] == [["pure-stick"], ["stick-slip"]]
    assert held == [{"velocity_m_s": 0.0, "k": 1, "motion": "pure-stick", "from_rest": True,
                     "held": True}]
    assert [(b["motion"], b["held"]) for b in moves] == [("stick-slip", False)]


def test_creep_point_is_decided_on_the_full_model(steady_map):
    # 100 V / 10 N: the slider creeps below its velocity ripple, stopping and starting inside
    # every period, on a slider-tip orbit of ten periods; no transient fallback is needed
    i, j = 0, 0
    assert not steady_map.fallback[i, j]
    v_t, _ = transient_reference(table2(), 100.0, 10.0, duration_s=0.3)
    assert steady_map.velocity_m_s[i, j] == pytest.approx(v_t, rel=1e-6)
    assert [b[1] for b in steady_map.branches[i, j] if b[3]] == [10]


@pytest.mark.parametrize("workers", [1, 2])
def test_an_interrupted_map_does_not_compute_the_points_left(monkeypatch, workers):
    # Ctrl-C reaches the map as an exception in its loop over finished points; the points
    # still queued must be dropped, not computed before the command can stop (a 10 000-point
    # map went on for 40 s after the signal)
    import threading
    import time

    from contact import maps

    calls = []
    lock = threading.Lock()

    def point(*args, **kwargs):
        with lock:
            calls.append(args[1:3])
            if len(calls) == 1:  # the first point (computed before the threads start)
                return ("pure-stick", 0.0, 1.0, 0.0, 0.3, True, (), False, None)
        time.sleep(0.02)  # a point takes time: the map sees the failure while others wait
        raise KeyboardInterrupt

    monkeypatch.setattr(maps, "_steady_point", point)
    with pytest.raises(KeyboardInterrupt):
        stick_slip_map(table2(), np.linspace(50, 450, 10), np.linspace(10, 26, 10),
                       workers=workers, method="steady", progress=False)
    assert len(calls) < 10  # those started before the failure was seen; 100 without the fix


def test_steady_and_transient_maps_classify_the_edges_alike():
    # no drive and no preload: the tip never presses (separated), which the steady map
    # called pure-stick; a held slider under a preload is pure-stick in both
    from contact.maps import stick_slip_map
    from rom.table2 import table2

    v, f = np.array([0.0, 100.0]), np.array([0.0, 14.0])
    steady = stick_slip_map(table2(), v, f, method="steady", progress=False)
    transient = stick_slip_map(table2(), v, f, method="transient", progress=False)
    assert steady.motion[0][0] == "separated"
    assert np.array_equal(steady.motion, transient.motion)


def test_a_transient_map_says_which_points_did_not_settle(capsys):
    """200 V / 0 N is still accelerating after the default 0.05 s (0.067 m/s against the
    steady 0.116 m/s): the map flagged it only in its JSON, simulate warns of the same run."""
    import json

    from lusm.cli import main

    assert main(["map", "--voltages", "0,200", "--preloads", "0,14", "--method", "transient",
                 "--json"]) == 0
    out = capsys.readouterr()
    settled = json.loads(out.out)["settled"]
    assert settled == [[True, True], [False, True]]
    assert "1 point(s) not settled within --duration 0.05 s (200 V/0 N)" in out.err


@pytest.mark.slow
@pytest.mark.benchmark  # what the command says, at a costly run's price
def test_an_undecided_points_transient_is_said_at_its_length(capsys):
    """20 V / 2 N creeps with no short tip orbit: the steady map runs a transient there, of
    --duration when that is longer than 0.3 s, and said "taken from 0.3 s transients"
    whatever ran. The reference: the JSON's velocity equals a 2 s transient's."""
    from contact.simulate import simulate
    from lusm.cli import main

    assert main(["map", "--voltages", "20", "--preloads", "2", "--duration", "2"]) == 0
    assert "taken from 2 s transients" in capsys.readouterr().out
    assert main(["map", "--voltages", "20", "--preloads", "2", "--duration", "2",
                 "--json"]) == 0
    v = json.loads(capsys.readouterr().out)["steady_velocity_m_s"][0][0]
    ref = simulate(table2(), 20.0, 2.0, duration_s=2.0).steady.velocity_m_s
    assert v == pytest.approx(ref, rel=1e-12)


def test_map_json_lists_its_figures_as_the_other_commands_do(tmp_path, capsys):
    """simulate and characteristic write "figures" (a list); map wrote "figure" (a string)
    alone. It writes both now, "figure" kept for compatibility, and the text names the file."""
    from pathlib import Path

    from lusm.cli import main

    out = tmp_path / "maps"
    assert main(["map", "--voltages", "200", "--preloads", "14", "--plot", str(out),
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["figures"] == [d["figure"]] and Path(d["figure"]).is_file()
    assert Path(d["figure"]).parent == out
    assert main(["map", "--voltages", "200", "--preloads", "14", "--plot", str(out),
                 "--force"]) == 0
    assert f"wrote {d['figure']}" in capsys.readouterr().out
