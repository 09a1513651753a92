"""``lusm report --geometry``: the report on a designer's stator (the tip example), complete."""

import json

import numpy as np
import pytest

from tests.conftest import ROOT

TIP = ROOT / "examples" / "tip_protrusion" / "stator.toml"


def _not_json(name: str):
    raise AssertionError(f"report.json holds {name}, which is not JSON")


def _report(out, *options: str) -> None:
    """lusm report --quick through the command's entry point in this process, from the
    repository root (the commands compared with it then share its cached FE solves)."""
    from lusm.cli import main

    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(ROOT)
        assert main(["report", "--quick", "--no-progress", *options, "--out", str(out)]) == 0


@pytest.fixture(scope="module")
def design_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("design_report")
    _report(out, "--geometry", str(TIP))
    # strict JSON: a bare NaN (Python's default) is refused by every other reader
    return out, json.loads((out / "report.json").read_text(), parse_constant=_not_json)


PLATE = ("--length-mm", "60", "--material", "paper")
"""Plate options of the second report: no stator file stands behind them."""


DRIVE = ("--voltages", "200,350", "--preload", "10")
"""The second report's operating points (``lusm report --voltages --preload``)."""


@pytest.fixture(scope="module")
def plate_report(tmp_path_factory):
    """A quick report on plate options, at the operating points of :data:`DRIVE`."""
    out = tmp_path_factory.mktemp("plate_report") / "r"
    _report(out, *PLATE, *DRIVE)
    return out, json.loads((out / "report.json").read_text(), parse_constant=_not_json)


def _cited(md: str, command: str) -> list[str]:
    """The calls ``lusm COMMAND --...`` the report cites in backticks (a bare `lusm modes`
    names the command, in a remark on the examples)."""
    import re

    return re.findall(rf"`(lusm {command} --[^`]*)`", md)


@pytest.mark.slow
@pytest.mark.benchmark
def test_every_section_and_figure_is_there(design_report):
    from matplotlib.image import imread

    out, doc = design_report
    md = (out / "index.md").read_text()
    for heading in ("## 1. Modes", "## 2. Reduced parameters", "## 3. Admittance",
                    "## 4. Speed against voltage", "## 5. Motor characteristics"):
        assert heading in md
    assert "plate 31 x 7.5 x 3 mm" in md  # the design's own plate, not the paper's
    pngs = sorted((out / "figures").glob("*.png"))
    names = {p.name for p in pngs}
    assert {"design_L1.png", "design_B2.png", "design_3d_L1.png", "design_3d_B2.png",
            "design_admittance.png", "design_characteristic.png",
            "design_steady_map.png"} <= names
    for png in pngs:
        assert float(np.std(imread(png)[..., :3])) > 0.01, png.name
        assert f"figures/{png.name}" in md


@pytest.mark.slow
@pytest.mark.benchmark
def test_design_report_numbers_are_the_commands_numbers(design_report, capsys):
    from lusm.cli import main

    _, doc = design_report
    capsys.readouterr()
    assert main(["modes", "--geometry", str(TIP), "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)
    for m in ("L1", "B2"):
        assert doc["modes"]["2d"][m]["f_short_Hz"] == modes[m]["f_short_Hz"]
    # the admittance band follows the design: it contains all four of its frequencies
    lo, hi = doc["admittance"]["band_Hz"]
    for m in ("L1", "B2"):
        assert lo < modes[m]["f_short_Hz"] < modes[m]["f_open_Hz"] < hi
    assert doc["parameters"]["phi_Bl"] != 0.0
    # the mesh is described as the command meshes it: the file's, no refine (the report had
    # said "order 2, refine 4" where lusm modes --json says refine null)
    md = (design_report[0] / "index.md").read_text()
    assert modes["refine"] is None
    assert "2D plane-stress model (order 2, the stator file's own mesh," in md
    # section 4 names a state as lusm simulate --steady does: a held slider is pure-stick
    section = md.split("## 4. Speed against voltage")[1].split("## 5.")[0]
    assert "dead-zone" not in section


def test_a_difference_below_the_printed_decimals_keeps_its_size_and_sign():
    """A 2D/3D difference of -3e-5 read "-0.00%" in the modes table: a sign without a size."""
    from validation.summaries import signed_percent

    for x, d in ((-3e-5, 2), (4e-7, 3), (-0.0123, 2), (0.01, 3)):
        text = signed_percent(x, d)
        assert float(text.rstrip("%")) == pytest.approx(100 * x, rel=0.05), text
    assert signed_percent(0.0, 2) == "+0.00%"


@pytest.mark.slow
@pytest.mark.benchmark
def test_the_report_repeats_the_2d_validity_warning(design_report):
    """A stator whose gap exceeds thickness/6 got the 2D validity warning on stderr only: the
    report, which outlives the run, showed its 2D rows without a word."""
    from fem.geometry import PlateStator
    from validation.report_design import _validity_note

    _, doc = design_report
    assert doc["modes"]["gap_validity"] is None  # the example's 0.5 mm gap on a 3 mm plate
    validity, note = _validity_note(PlateStator(electrode_gap_m=0.8e-3))
    assert "exceeds thickness/6 = 0.5 mm" in validity and "outside its validity" in note[0]


def test_the_3d_column_names_the_call_that_reproduces_it(monkeypatch):
    """The quick report's 3D column used refine 2 and called `lusm modes --model 3d` "the same
    call" (its default refine 3: a tuned plate's split read +0.312 % against +0.021 %), and a
    chamfered example's 3D mesh lay above `lusm modes`' own work bound, so the quoted call was
    refused. The command now carries the refine and the work bound it needs (the chamfered
    example's 2 988 bricks under a bound of 2 000, as when this was found)."""
    from fem.stator_file import load_stator
    from lusm import limits
    from lusm.errors import LusmError
    from lusm.options import check_fe_size
    from validation.report_design import _command_3d

    tuned = load_stator(ROOT / "examples" / "tuned_40k" / "identified.toml").stator
    on = "--geometry examples/tuned_40k/identified.toml"
    assert _command_3d(tuned, 2, on) == f"lusm modes --model 3d {on} --layers 3 --refine 2"
    assert "--refine" not in _command_3d(tuned, 3, on) and "LUSM" not in _command_3d(tuned, 3, on)
    chamfered = load_stator(ROOT / "examples" / "chamfered" / "stator.toml").stator
    monkeypatch.setattr(limits, "MAX_FE_CELLS_3D", 2000)
    with pytest.raises(LusmError):
        check_fe_size(chamfered, 3, 3)
    assert _command_3d(chamfered, 3, "--geometry c.toml").startswith(
        "LUSM_MAX_WORK=2 lusm modes --model 3d --geometry c.toml")


@pytest.mark.slow
def test_the_mode_pictures_are_drawn_with_the_signals_held(monkeypatch, tmp_path):
    """A SIGTERM landing in VTK's rendering crashed the design report (exit 139, 2 of about
    90 tries) and left its staging folder: the pictures (about a second) are drawn with
    SIGINT and SIGTERM held, delivered once they are done."""
    import signal

    import fem.render
    from contact import deferred_signals
    from fem.geometry import PlateStator
    from fem.material import get_material
    from lusm.options import StatorChoice
    from validation.report_design import _modes_section

    class Drawn(Exception):
        pass

    def draw(*args, **kwargs):
        held = signal.getsignal(signal.SIGTERM) is deferred_signals._record
        raise Drawn(held)

    monkeypatch.setattr(fem.render, "render_modes", draw)
    with pytest.raises(Drawn) as info:
        _modes_section(StatorChoice(PlateStator(), get_material("pzt8")), tmp_path, True,
                       lambda text: None, "")
    assert info.value.args == (True,)
    assert signal.getsignal(signal.SIGTERM) is not deferred_signals._record  # released


@pytest.mark.slow
@pytest.mark.benchmark
def test_the_admittance_command_the_report_names_gives_its_numbers(design_report, capsys):
    """The report named `lusm admittance ... --f-min 50774 --f-max 74098` but used 801 points
    and the unrounded band: the command's f_s and f_p differed in the 8th digit. It names
    the points and the band as it used them, and that command gives the report's pairs."""
    import re

    from lusm.cli import main

    out, doc = design_report
    md = (out / "index.md").read_text()
    m = re.search(rf"lusm admittance --geometry {re.escape(str(TIP))} "
                  r"(--f-min \S+ --f-max \S+ --points \d+)", md)
    assert m is not None
    assert main(["admittance", "--geometry", str(TIP), *m.group(1).split(), "--json",
                 "--out", str(out.parent / "adm")]) == 0
    cmd = json.loads(capsys.readouterr().out)
    report_pairs = doc["admittance"]["pairs"] if "admittance" in doc else None
    assert report_pairs is not None
    keys = ("f_resonance_Hz", "f_antiresonance_Hz", "k_eff")
    got = {p["mode"]: tuple(p[k] for k in keys) for p in cmd["pairs"]}
    want = {p["mode"]: tuple(p[k] for k in keys) for p in report_pairs}
    assert got == want


@pytest.mark.slow
def test_a_report_on_plate_options_cites_commands_that_carry_them(plate_report, capsys):
    """A report on ``--length-mm 60`` cited ``lusm modes --geometry ...``, ``lusm params
    --geometry ...`` and so on: a stator file the user never gave, so no cited command could
    be run. They carry the plate options now, and the cited commands give the report's
    numbers."""
    import shlex

    from lusm.cli import main

    out, doc = plate_report
    md = (out / "index.md").read_text()
    assert "--geometry" not in md
    typed = " ".join(PLATE)
    for command in ("report --quick", "modes", "modes --model 3d", "params", "admittance",
                    "simulate --steady", "characteristic", "map"):
        cites = _cited(md, command)
        assert cites, command
        assert all(typed in c for c in cites), cites
    # the motor section's characteristic, as cited (it had cited `lusm characteristic
    # --frequency F` alone, which runs Table 2's set), gives its curve at 200 V
    (char,) = _cited(md, "characteristic")
    assert main([*shlex.split(char.replace("V0", "200"))[1:], "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    rep = doc["motor_characteristics"]["design"]["characteristics"]["200"]
    assert got["no_load_velocity_m_s"] == rep["no_load_velocity_m_s"]
    assert got["stall_force_N"] == rep["stall_force_N"]
    assert "--preload 10" in char
    # the 2D modes command, as cited, gives the table's frequencies
    (modes,) = [c for c in _cited(md, "modes") if "--model" not in c]
    assert main([*shlex.split(modes)[1:], "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    for m in ("L1", "B2"):
        assert got[m]["f_short_Hz"] == doc["modes"]["2d"][m]["f_short_Hz"]
        assert f"| {m} | {got[m]['f_short_Hz']:.1f} |" in md
    # and the parameter command the whole reduced set
    (params,) = _cited(md, "params")
    assert main([*shlex.split(params)[1:], "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    shown = {k: v for k, v in doc["parameters"].items() if k in got and k != "source"}
    assert len(shown) > 10 and shown == {k: got[k] for k in shown}
    assert f"| K_l | {got['K_l']:.6g} |" in md


@pytest.mark.slow
@pytest.mark.benchmark
def test_a_report_on_a_stator_file_cites_that_file_as_given(design_report):
    """With --geometry FILE every cited stator command names FILE, the path as typed."""
    md = (design_report[0] / "index.md").read_text()
    assert "--geometry ..." not in md
    for command in ("modes", "params", "admittance", "simulate --steady", "characteristic",
                    "map"):
        cites = _cited(md, command)
        assert cites and all(f"--geometry {TIP} " in c + " " for c in cites), cites


def test_the_stator_options_are_written_as_typed():
    """The text the report cites: the typed options only, numbers as they read back, a
    stator file's path quoted for the shell."""
    from lusm.cli import build_parser
    from lusm.options import stator_options_text

    parser = build_parser()
    args = parser.parse_args(["report", "--width-mm", "7.35", "--length-mm", "6e1"])
    assert stator_options_text(args) == "--length-mm 60 --width-mm 7.35"
    args = parser.parse_args(["report", "--thickness-mm", "3.0000000001", "--material", "paper"])
    assert stator_options_text(args) == "--thickness-mm 3.0000000001 --material paper"
    args = parser.parse_args(["report", "--geometry", "my plates/a.toml"])
    assert stator_options_text(args) == "--geometry 'my plates/a.toml'"
    assert stator_options_text(parser.parse_args(["report"])) == ""


@pytest.mark.slow
def test_the_report_computes_at_the_voltages_and_preload_it_is_given(plate_report):
    """``lusm report --voltages 200,350 --preload 10``: the motor table has a row per given
    voltage, the speed table and the curves run at 10 N, the report's own command carries
    the options, and the words speak of this stator, not of the paper's plate."""
    out, doc = plate_report
    md = (out / "index.md").read_text()
    assert doc["drive"]["voltages_V"] == [200.0, 350.0] and doc["drive"]["preload_N"] == 10.0
    assert sorted(doc["motor_characteristics"]["design"]["characteristics"]) == ["200", "350"]
    section = md.split("## 5. Motor characteristics")[1]
    rows = [line for line in section.splitlines() if line.startswith("| design |")]
    assert [line.split("|")[2].strip() for line in rows] == ["200", "350"]
    assert "Speed-thrust and efficiency at 200, 350 V and 10 N" in section
    assert doc["speed_vs_voltage"]["preload_N"] == 10.0
    assert "Steady velocity reached from rest at 10 N" in md
    (own,) = _cited(md, "report --quick")
    assert own.endswith("--voltages 200,350 --preload 10")
    assert "the paper's plate" not in md and "Table 2's set runs" not in md
    assert "What this stator does as a motor" in section


@pytest.mark.parametrize("drive, named", [((1, 2), "B2"), ((1, 4), None)])
def test_a_drive_that_excites_no_B2_is_said_in_the_report(drive, named):
    """Electrodes 1 and 2 in phase give A_b at roundoff: the report's zero speeds come with a
    paragraph at its top (stderr is gone when the report is read); a diagonal pair gets none."""
    from rom.table2 import table2
    from validation.report_design import _unexcited_note
    from validation.summaries import unexcited_modes

    params = table2().with_(A_b=1e-15 if named else table2().A_b)
    note = _unexcited_note(unexcited_modes(params, drive))
    if named is None:
        assert note == []
    else:
        assert len(note) == 2 and f"excites no {named}" in note[0] and "zero" in note[0]
