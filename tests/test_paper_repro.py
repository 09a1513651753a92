"""The paper reproduction judges settled values: its numbers equal long runs from rest."""

from __future__ import annotations

import pytest

from contact.options import SimulationOptions
from contact.simulate import simulate
from rom import table2
from validation.paper_repro import ReproSettings, reproduce


@pytest.fixture(scope="module")
def repro(tmp_path_factory):
    settings = ReproSettings(map_voltages_V=(400.0,), map_preloads_N=(14.0,),
                             curve_voltages_V=(125.0, 400.0), curve_preloads_N=(14.0,),
                             low_voltages_V=(50.0,))
    return reproduce(table2(), 40e3, tmp_path_factory.mktemp("repro"), "t_", settings)


@pytest.mark.slow
def test_judged_velocities_are_settled_runs_from_rest(repro):
    """Fig. 24's 400 V velocity: the 50 ms figure run is still accelerating (0.19 m/s), the
    judged value must be where a run from rest ends after 0.3 s (12 000 periods)."""
    sweep = repro.numbers["voltage_sweep"]
    assert repro.numbers["method"] == "steady"
    opts = SimulationOptions(duration_s=0.3, steady_periods=400)
    for v, got, motion in zip(sweep["voltage_V"], sweep["velocity_m_s"], sweep["motion"],
                              strict=True):
        ref = simulate(table2(), v, 14.0, 40e3, opts)
        assert motion == ref.steady.motion
        assert got == pytest.approx(ref.steady.velocity_m_s, rel=1e-5, abs=1e-9)
    short = simulate(table2(), 400.0, 14.0, 40e3, SimulationOptions(duration_s=0.05))
    assert abs(short.steady.velocity_m_s / sweep["velocity_m_s"][-1] - 1) > 0.05


def test_transient_method_is_refused_unless_named():
    with pytest.raises(ValueError, match="method"):
        ReproSettings(method="settled")
    assert ReproSettings.quick().method == "transient"


@pytest.mark.slow
def test_the_dead_zone_verdict_follows_the_edge_not_the_grid(repro):
    """On a grid stuck at 125 V and moving at 400 V (and on the report's 25 V grid, stuck
    at 125 V and moving from 150 V) the edge looked like the paper's 120 V and the report
    said 'yes', while the README and docs/contact.md quote the bisected edge, 139.1 V,
    +16 %. The verdict now rests on the edge, which runs from rest on both sides confirm."""
    from validation.paper_repro import DEAD_ZONE_REL

    row = next(r for r in repro.rows if r.paper_says.startswith("dead zone"))
    edge = float(row.we_get.split("edge ")[1].split(" V")[0])
    opts = SimulationOptions(duration_s=0.05, coupling="paper")
    assert simulate(table2(), edge - 1.0, 14.0, 40e3, opts).steady.motion == "pure-stick"
    assert simulate(table2(), edge + 1.0, 14.0, 40e3, opts).steady.motion != "pure-stick"
    assert row.agrees == (abs(edge / 120.0 - 1.0) <= DEAD_ZONE_REL)
    assert not row.agrees  # 139 V: 16 % above the paper's 120 V


@pytest.mark.slow
def test_a_held_slider_reads_held_not_a_roundoff_speed(tmp_path):
    """A set that holds the slider in pure stick at 200 V / 14 N (here Table 2 driven three
    times more weakly): Fig. 9's row had read a window mean of roundoff as a speed
    ("1.661e-19 m/s (settled)" on a report's beam set). It says held, as the run is."""
    t = table2()
    p = t.with_(A_l=0.3 * t.A_l, A_b=0.3 * t.A_b)
    settings = ReproSettings(map_voltages_V=(400.0,), map_preloads_N=(14.0,),
                             curve_voltages_V=(400.0,), curve_preloads_N=(14.0,),
                             low_voltages_V=(50.0,))
    out = reproduce(p, 40e3, tmp_path, "w_", settings)
    row = next(r for r in out.rows if r.figure == "Fig. 9")
    ref = simulate(p, 200.0, 14.0, 40e3, SimulationOptions(duration_s=0.3))
    assert ref.steady.motion == "pure-stick" and abs(ref.steady.velocity_m_s) < 1e-15
    assert row.we_get.startswith("0 m/s, held in pure stick") and not row.agrees
