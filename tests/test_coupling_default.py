"""``--coupling auto``: the paper's coupling for Table 2's set, the work-consistent one for every
other set (docs/contact.md 2.3.1), named in every output."""

from __future__ import annotations

import json

import pytest

from contact.model import default_coupling
from contact.simulate import simulate
from lusm.cli import main
from rom.sources import get_params
from rom.table2 import table2


def test_rule():
    assert default_coupling(table2())[0] == "paper"
    assert default_coupling(get_params("beam"))[0] == "consistent"
    # an edited Table 2 is not the paper's set any more
    assert default_coupling(table2().with_(C_l=100.0))[0] == "consistent"


@pytest.mark.parametrize(("extra", "coupling", "why"), [
    ([], "paper", "auto"),
    (["--source", "beam"], "consistent", "auto"),
    (["--source", "beam", "--coupling", "paper"], "paper", "--coupling"),
])
def test_cli_runs_and_names_the_coupling(capsys, extra, coupling, why):
    # at 40 kHz by name: without --frequency the beam set is driven at its own point
    args = ["simulate", "--voltage", "300", "--preload", "14", "--duration", "0.005",
            "--frequency", "40e3", "--damping", "table2", *extra]
    assert main([*args, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["coupling"] == coupling and d["coupling_from"].startswith(why)
    p = table2() if "beam" not in extra else get_params("beam")
    r = simulate(p, 300.0, 14.0, 40e3, duration_s=0.005, coupling=coupling)  # the CLI's
    assert d["steady_velocity_m_s"] == r.steady.velocity_m_s
    assert main(args) == 0
    assert f"coupling {coupling} (" in capsys.readouterr().out


def test_an_edited_copy_of_table2_is_told_why_its_speed_jumps(tmp_path, capsys):
    # a 1e-6 edit of a saved Table 2 set switched auto to the consistent coupling and the
    # speed several-fold, silently; the rule stands, the user is told
    assert main(["params", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for k in ("eta_N", "eta_T", "f_L1_Hz", "f_B2_Hz", "zeta_L1", "zeta_B2"):
        d.pop(k)
    path = tmp_path / "t2.json"
    path.write_text(json.dumps(d))
    args = ["simulate", "--params", str(path), "--voltage", "200", "--preload", "14",
            "--duration", "0.005", "--json"]
    assert main(args) == 0
    assert "edited copy" not in capsys.readouterr().err  # the unedited copy is Table 2's
    d["C_l"] *= 1 + 1e-6
    path.write_text(json.dumps(d))
    assert main(args) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["coupling"] == "consistent"
    assert "edited copy of Table 2's" in cap.err and "--coupling paper" in cap.err
    assert main([*args, "--coupling", "paper"]) == 0
    assert "edited copy" not in capsys.readouterr().err


def test_the_library_runs_the_clis_coupling_by_default():
    """The library's entry points defaulted to the paper's coupling for every set while the
    CLI ran non-Table-2 sets with the consistent one: the same input gave a held slider in
    simulate and 4.1e-5 m/s in lusm simulate (found by API testing). Now both say "auto"."""
    from contact.options import SimulationOptions
    from contact.simulate import simulate
    from contact.steady.engine import steady_state
    from rom import table2
    from rom.sources import get_params

    beam = get_params("beam")
    r = simulate(beam, 300, 14, 40e3, duration_s=0.005)  # at the CLI's default drive
    assert r.options.coupling == "consistent" and SimulationOptions().coupling == "auto"
    explicit = simulate(beam, 300, 14, 40e3, duration_s=0.005, coupling="consistent")
    assert r.steady.velocity_m_s == explicit.steady.velocity_m_s
    assert simulate(table2(), 200, 14, duration_s=0.005).options.coupling == "paper"
    kw = {"frequency_Hz": 40e3, "accuracy": "exact", "energy": False}
    auto = steady_state(beam, 300, 14, **kw)
    cons = steady_state(beam, 300, 14, **kw, coupling="consistent")
    paper = steady_state(beam, 300, 14, **kw, coupling="paper")
    assert auto.velocity_m_s == cons.velocity_m_s != paper.velocity_m_s
