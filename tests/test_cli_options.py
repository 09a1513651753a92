"""The ``lusm`` option layer: every stator command takes the same stator options, the parser is
light, and fuzzed option values end in exit 0 or 2 with the option named - never a traceback."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lusm import limits
from lusm.cli import build_parser, main
from tests.conftest import ROOT

STATOR_COMMANDS = ("simulate", "map", "modes", "params", "render", "tune", "sweep",
                   "admittance", "harmonic", "report", "compare", "characteristic")
"""Commands that use a stator (``explore`` takes its stators from the study file)."""

STATOR_OPTIONS = ("--geometry", "--length-mm", "--width-mm", "--thickness-mm", "--gap-mm",
                  "--material")


def _subparsers():
    action = next(a for a in build_parser()._actions if a.dest == "command")
    return action.choices


def test_every_stator_command_takes_the_stator_options(capsys):
    subs = _subparsers()
    assert set(STATOR_COMMANDS) <= set(subs)
    for name in STATOR_COMMANDS:
        options = {o for a in subs[name]._actions for o in a.option_strings}
        missing = [o for o in STATOR_OPTIONS if o not in options]
        assert not missing, f"lusm {name} lacks {missing}"
        assert main([name, "--help"]) == 0
        text = capsys.readouterr().out
        assert all(o in text for o in STATOR_OPTIONS), name
    assert main(["--help"]) == 0
    top = capsys.readouterr().out
    assert all(name in top for name in STATOR_COMMANDS)


def test_output_and_json_options_are_shared():
    subs = _subparsers()
    for name in ("simulate", "map", "modes", "params", "compare", "tune", "sweep",
                 "admittance", "harmonic"):
        assert "--json" in {o for a in subs[name]._actions for o in a.option_strings}, name
    for name, folder in (("simulate", "--plot"), ("map", "--plot"), ("render", "--out"),
                         ("sweep", "--out"), ("admittance", "--out"), ("report", "--out"),
                         ("harmonic", "--plot")):
        options = {o for a in subs[name]._actions for o in a.option_strings}
        assert {folder, "--force"} <= options, name


def test_building_the_parser_imports_no_heavy_module():
    code = ("import sys, lusm.cli as c; c.build_parser();"
            "heavy=[m for m in ('numpy','scipy','numba','skfem','pyvista','matplotlib',"
            "'meshio','rom','fem','contact') if m in sys.modules]; print(heavy);"
            "sys.exit(1 if heavy else 0)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_parser_constants_match_the_library():
    from fem.material import MATERIAL_NAMES
    from fem.stator_file import PLATE_RANGE_MM
    from lusm.options import MATERIALS
    from lusm.options import SOURCES as CLI_SOURCES
    from rom.sources import SOURCES

    assert CLI_SOURCES == SOURCES and MATERIALS == MATERIAL_NAMES
    assert PLATE_RANGE_MM == limits.PLATE_MM


# --- property test ---------------------------------------------------------------------------

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1e-13, 1e-9, 1e-6, 1.0, 1e6, 1e9, 1e30, 1e300,
                     -1.0, -1e-7]),
    st.floats(min_value=1e-3, max_value=1e4),
).map(repr)
MALFORMED = st.sampled_from(["", "abc", "1e", "--", "1,2", "0x10", "1:2:3", "nan", "-inf",
                             " 3", "3 mm", "１"])
VALUES = st.one_of(NUMBERS, MALFORMED, st.integers(-10**12, 10**12).map(str))

# command, option to fuzz, the other options (valid, small)
TARGETS = [
    ("simulate", o, ["--voltage", "200", "--preload", "14", "--duration", "0.0005"])
    for o in ("--voltage", "--preload", "--frequency", "--duration", "--dt")
] + [
    ("map", o, ["--voltages", "100,300", "--preloads", "12", "--duration", "0.0005"])
    for o in ("--frequency", "--duration", "--dt", "--workers", "--voltages", "--preloads")
] + [
    ("modes", o, ["--refine", "2"])
    for o in ("--length-mm", "--width-mm", "--thickness-mm", "--gap-mm", "--refine")
] + [
    ("modes", o, ["--refine", "2", "--band", "40:60", "--risk-pct", "5"])
    for o in ("--band", "--risk-pct")
] + [
    ("admittance", o, ["--refine", "2", "--points", "50"])
    for o in ("--f-min", "--f-max", "--points", "--zeta")
] + [
    ("characteristic", o, ["--voltage", "200", "--preload", "14", "--loads", "0:1:0.5",
                           "--accuracy", "fast"])
    for o in ("--voltage", "--preload", "--frequency", "--loads")
]


@pytest.fixture
def small_work(monkeypatch):
    """Work bounds small enough that any accepted fuzzed run takes well under a second."""
    monkeypatch.setattr(limits, "MAX_STEPS", 200_000)
    monkeypatch.setattr(limits, "MAX_WINDOW_STEPS", 100_000)
    monkeypatch.setattr(limits, "MAX_MAP_STEPS", 400_000)
    monkeypatch.setattr(limits, "MAX_FE_CELLS_2D", 400)
    monkeypatch.setattr(limits, "MAX_FREQUENCY_POINTS", 5000)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(target=st.sampled_from(TARGETS), value=VALUES)
@pytest.mark.slow
def test_fuzzed_options_exit_0_or_2_naming_the_option(target, value, small_work, capsys):
    command, option, rest = target
    rest = [a for i, a in enumerate(rest) if a != option and (i == 0 or rest[i - 1] != option)]
    rc = main([command, *rest, f"{option}={value}"])
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert rc in (0, 2), err
    if rc == 2:
        errors = [ln for ln in err.splitlines() if ": error: " in ln]
        assert len(errors) == 1, err
        assert option in errors[0], errors[0]


def test_options_that_do_nothing_here_are_said_so(capsys):
    # accepted and silently ignored before
    from lusm.cli import main

    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady", "--dt",
                 "1e-12", "--json"]) == 0
    assert "--dt has no effect: --steady takes its own step" in capsys.readouterr().err
    assert main(["map", "--method", "transient", "--accuracy", "fast", "--voltages", "100",
                 "--preloads", "14", "--duration", "0.001", "--json"]) == 0
    assert "--accuracy has no effect" in capsys.readouterr().err
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady", "--json"]) == 0
    assert "no effect" not in capsys.readouterr().err  # defaults are not the user's
    assert main(["compare", "--sources", "table2", "--length-mm", "20"]) == 2
    assert "add fem or beam to --sources" in capsys.readouterr().err


def test_grid_values_carry_no_float_leftovers():
    # "-0.3:0.3:0.1" printed a load of 5.551e-17 and "0:0.9:0.3" gave 0.8999999999999999
    from lusm.ranges import parse_range

    assert list(parse_range("-0.3:0.3:0.1", "--loads", allow_list=False))[3] == 0.0
    assert list(parse_range("0:0.9:0.3", "--voltages")) == [0.0, 0.3, 0.6, 0.9]
    v = parse_range("-4.9:0:0.7", "--loads", allow_list=False)
    assert v[-1] == 0.0 and str(v[-1]) == "0.0"


def test_a_range_with_a_tiny_step_stays_finite():
    """0:1e-300:1e-303 rounded to 315 decimals: NumPy's overflow turned the values into NaN
    (with its warnings printed) and the error blamed a NaN the user never typed."""
    import warnings

    from lusm.ranges import parse_range

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v = parse_range("0:1e-300:1e-303", "--voltages")
    assert np.all(np.isfinite(v)) and v.size == 1001 and v[-1] == pytest.approx(1e-300)
    assert np.all(np.diff(v) > 0)


def test_the_default_step_divides_the_drive_period(capsys):
    """At --frequency auto (39 810.5 Hz on Table 2) the default 1e-7 s step cut the
    averaging windows mid-period: a held slider (130 V / 14 N, inside the dead zone) read
    1.4e-9 m/s, "not settled", at every --duration. The default step now divides the period
    (1e-7 s itself at 40 kHz, bit for bit), and the held slider reads zero to roundoff."""
    import json
    import math

    from contact.options import DEFAULT_DT_S as LIBRARY_DT_S
    from contact.options import SimulationOptions
    from contact.simulate import simulate
    from lusm.options import DEFAULT_DT_S, time_step_s
    from rom import table2

    assert time_step_s(None, 40e3) == DEFAULT_DT_S and time_step_s(2e-7, 39e3) == 2e-7
    # the library runs the same rule by default (it kept 1e-7 s at every frequency, and a
    # held slider's window means off 40 kHz read -3.7e-11 m/s; found by API testing)
    assert LIBRARY_DT_S == DEFAULT_DT_S and SimulationOptions().dt_s is None
    r = simulate(table2(), 100, 14, 35254.0, duration_s=0.01)
    assert r.options.dt_s == time_step_s(None, 35254.0) and abs(r.steady.velocity_m_s) < 1e-15
    for f in (39810.5, 35254.0, 47700.6, 1234.5):
        dt = time_step_s(None, f)
        n = (1.0 / f) / dt
        assert dt <= DEFAULT_DT_S and abs(n - round(n)) < 1e-9 and math.ceil(
            (1.0 / f) / DEFAULT_DT_S - 1e-9) == round(n)
    # Above 500 kHz the 1e-7 s default left fewer than the 20 steps per period that --dt
    # allows, and the user who typed no --dt was told "--dt must be in (0, 5e-08] s ...,
    # got 1e-07". The default now takes 20 steps there, and the run goes through.
    assert time_step_s(None, 1e6) == 5e-8 and time_step_s(None, 1e7) == 5e-9
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--frequency", "1e6",
                 "--duration", "1e-4", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["steps"] == 2000
    assert main(["simulate", "--voltage", "130", "--preload", "14", "--frequency", "auto",
                 "--duration", "0.1", "--json"]) == 0
    out = capsys.readouterr()
    doc = json.loads(out.out)
    assert doc["settled"] is True and abs(doc["steady_velocity_m_s"]) < 1e-12, out.err
    assert "not settled" not in out.err


def test_the_default_frequency_is_the_sets_own_operating_point(capsys):
    """The FE set's modes lie near 55 kHz: at the paper's 40 kHz its free tip ellipse is
    0.14 of the one at its own operating point (contact.drive.auto_frequency), and a stator
    file at 47.7 kHz gave 0.3 % of its no-load speed there. Without --frequency a set other
    than Table 2's is driven at its own point; Table 2's at the paper's 40 kHz; a typed
    frequency is kept."""
    import json

    from contact.drive import WEAK_DRIVE_SHARE, auto_frequency, free_tip_amplitudes
    from fem.material import pzt8
    from rom.sources import get_params
    from validation.summaries import plate_damping

    p = get_params("fem", damping_ratios=plate_damping(pzt8(), "fem")[0])  # --source fem's
    a0, b0 = free_tip_amplitudes(p, auto_frequency(p))
    a, b = free_tip_amplitudes(p, 40e3)
    assert a * b < WEAK_DRIVE_SHARE * a0 * b0
    argv = ["simulate", "--voltage", "200", "--preload", "14", "--steady", "--json"]
    for extra, want in ((["--source", "fem"], auto_frequency(p)), ([], 40e3),
                        (["--source", "fem", "--frequency", "40000"], 40e3)):
        assert main(argv + extra) == 0
        assert json.loads(capsys.readouterr().out)["frequency_Hz"] == pytest.approx(want,
                                                                                  rel=1e-12)


def test_a_drive_that_excites_no_b2_is_said(tmp_path, capsys):
    """Four electrodes in phase drive L1 only (B2 is antisymmetric across the width): A_b
    came out 1.6e-15 N/V and simulate, characteristic and --frequency auto went on without a
    word. The diagonal pair of the paper stays silent."""
    import json

    path = tmp_path / "all4.toml"
    path.write_text("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
                    "[electrodes]\ngap_mm = 0.5\ndrive = [1, 2, 3, 4]\n")
    assert main(["params", "--source", "fem", "--geometry", str(path), "--json"]) == 0
    out = capsys.readouterr()
    p = json.loads(out.out)
    assert abs(p["A_b"]) < 1e-9 * abs(p["A_l"])
    assert "electrodes 1, 2, 3, 4 excites no B2" in out.err
    assert main(["params", "--source", "fem", "--json"]) == 0
    assert "excites no" not in capsys.readouterr().err


def test_a_set_that_drives_no_ellipse_has_no_operating_frequency(tmp_path, capsys):
    """A_b = 0 (the beam set with one full electrode, or a --params file): the free tip
    ellipse is zero at every frequency, and auto_frequency returned the first point of its
    grid (54 442 Hz for the beam set) as the operating frequency."""
    import json

    from contact.drive import auto_frequency
    from rom.sources import get_params

    with pytest.raises(ValueError, match="drives no tip ellipse"):
        auto_frequency(get_params("beam", electrode_layout="full"))
    assert main(["params", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    d = {k: v for k, v in d.items()
         if k not in ("eta_N", "eta_T", "f_L1_Hz", "f_B2_Hz", "zeta_L1", "zeta_B2")}
    d["A_b"] = 0.0
    (tmp_path / "p.json").write_text(json.dumps(d))
    args = ["--params", str(tmp_path / "p.json"), "--voltage", "200", "--preload", "14"]
    assert main(["simulate", *args, "--frequency", "auto", "--duration", "0.002"]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("lusm simulate: error: --frequency auto: the set drives no tip")
    # at a given frequency it is a motor that does not move: answered, not refused; without
    # --frequency the default, which has no operating point to find, falls back to 40 kHz
    assert main(["characteristic", *args, "--loads", "0:0.1:0.1", "--json"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["no_load_velocity_m_s"] == 0.0
    assert json.loads(out.out)["frequency_Hz"] == 40e3
    assert "drives no tip ellipse" in out.err


def test_library_warnings_name_the_options_of_their_settings():
    """The one-line warning printer says a library message's setting (``bounds.Words``)
    ``load_N = 50 N`` as ``--load-N 50 N``; a plain message, with a word like "refine" in a
    sentence, stays as it is."""
    import warnings

    from bounds import Words
    from lusm.errors import in_option_terms

    words = Words("{load_N} is beyond", load_N="50 N")
    assert str(words) == "load_N = 50 N is beyond"
    assert in_option_terms(ValueError(words)) == "--load-N 50 N is beyond"
    assert in_option_terms(UserWarning(words + "; at {f}")) == "--load-N 50 N is beyond; at {f}"
    text = "refine the stator file's mesh; voltage_V = 3 of the drive"
    assert in_option_terms(ValueError(text)) == text
    # the switch of the unsettled-A_N warning's remedy
    remedy = Words("or {ultrasonic_friction} for a constant mu_d",
                   {"ultrasonic_friction": "set {name} = {value}"}, ultrasonic_friction="False")
    assert str(remedy) == "or set ultrasonic_friction = False for a constant mu_d"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.warn(remedy, UserWarning, stacklevel=1)
    assert (in_option_terms(caught[0].message)
            == "or pass --no-ultrasonic-friction for a constant mu_d")


def test_a_diagonal_pair_that_excites_nothing_is_not_told_to_drive_a_diagonal_pair(capsys):
    """A material without piezoelectric constants, driven through [1, 4]: the warning had
    advised "drive a diagonal pair ([electrodes] drive = [1, 4] ...)", the drive it had."""
    from lusm.options import warn_unexcited_mode
    from rom import table2

    p = table2()
    warn_unexcited_mode(p.with_(A_b=p.A_l * 1e-12), (1, 4))
    err = capsys.readouterr().err
    assert "excites no B2" in err and "piezoelectric constants" in err
    assert "drive a diagonal pair" not in err
    warn_unexcited_mode(p.with_(A_b=p.A_l * 1e-12), (1, 2, 3, 4))
    assert "drive a diagonal pair" in capsys.readouterr().err


def test_a_plate_far_thicker_than_measured_is_not_quoted_the_measured_error(capsys):
    """--thickness-mm 1000 (133 x the width) was told the 2D model is "0.6 % off at 1.3"
    (found by exploratory testing), as if that bounded its error there."""
    from lusm.options import warn_thin_plate

    warn_thin_plate("--thickness-mm 1000", 1000.0, 7.5, "the plate's width")
    assert "error is not measured" in capsys.readouterr().err
    warn_thin_plate("--thickness-mm 9", 9.0, 7.5, "the plate's width")  # 1.2 x: measured
    err = capsys.readouterr().err
    assert "assumes a thin plate" in err and "not measured" not in err


def test_a_command_without_refine_is_not_told_to_lower_it(tmp_path, capsys):
    """lusm report (and simulate --source fem) has no --refine, and was told to give a lower
    one for a plate too elongated for the mesh bound (API and CLI testing). Such a plate
    (10 000 times longer than wide) has no B2 within the solver's reach at any mesh: modes,
    which has --refine, is not told to lower it either."""
    plate = ["--length-mm", "1000", "--width-mm", "0.1", "--thickness-mm", "0.1",
             "--gap-mm", "0.05"]
    assert main(["report", *plate, "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert "--length-mm" in err and "times longer than wide" in err and "--refine" not in err
    assert main(["modes", *plate]) == 2
    err = capsys.readouterr().err
    assert "times longer than wide" in err and "--refine" not in err
    assert not (tmp_path / "r").exists()


def test_a_warning_is_said_once_per_command(capsys):
    """lusm report of a stator with a hole said the hole's and the thin plate's warnings
    twice, once per stage that builds the FE model (API and CLI testing)."""
    from lusm.messages import set_command, warn

    set_command("report")
    warn("a hole")
    warn("a hole")
    warn("a thin plate")
    assert capsys.readouterr().err.splitlines() == [
        "lusm report: warning: a hole", "lusm report: warning: a thin plate"]
    set_command("report")  # the next command says it again
    warn("a hole")
    assert capsys.readouterr().err == "lusm report: warning: a hole\n"


@pytest.mark.slow
def test_a_thick_plate_without_an_l1_b2_pair_names_the_thickness(capsys):
    """Found by the fuzzed options: a 30 x 7.5 x 39 mm plate has no pair the 2D model can
    identify, and its refusal told the user to check the length and width only."""
    assert main(["modes", "--refine", "2", "--thickness-mm", "39"]) == 2
    errors = [ln for ln in capsys.readouterr().err.splitlines() if ": error: " in ln]
    assert len(errors) == 1 and "--thickness-mm" in errors[0]
    assert "39 mm thick plate is 5.2 x its smaller in-plane dimension (7.5 mm)" in errors[0]


def test_the_thin_plate_warning_says_when_the_thickness_is_the_default(capsys):
    """A 30 x 2 mm plate is thick for plane stress at the default 3 mm: the warning says the
    thickness is the default, not a --thickness-mm 3 the user never typed (review)."""
    assert main(["modes", "--length-mm", "30", "--width-mm", "2", "--refine", "1"]) in (0, None)
    assert "warning: the default --thickness-mm 3 is 1.5 x" in capsys.readouterr().err
    assert main(["modes", "--length-mm", "30", "--width-mm", "2", "--thickness-mm", "3",
                 "--refine", "1"]) in (0, None)
    err = capsys.readouterr().err
    assert "warning: --thickness-mm 3 is 1.5 x" in err and "default" not in err


def test_a_dt_that_is_no_step_is_refused_before_a_stators_fe_reduction(monkeypatch, capsys):
    """Its figure at the drive frequency waits for ``--frequency auto``, the FE reduction of
    a stator file; a non-number or a step <= 0 is no step at any frequency, and had waited
    for it too (the range form of the refusal is the same)."""
    import rom.from_fem

    def no_fe(*args, **kwargs):
        raise AssertionError("the FE reduction ran before --dt was refused")

    monkeypatch.setattr(rom.from_fem, "fem_params_from_file", no_fe)
    monkeypatch.setattr(rom.from_fem, "fem_params_from_design", no_fe)
    assert main(["simulate", "--geometry", "examples/tuned_40k/stator.toml", "--frequency",
                 "auto", "--voltage", "200", "--preload", "14", "--dt", "abc"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lusm simulate: error: --dt ") and len(err.splitlines()) == 1, err


# the bound said where it is round: it had been rounded down from the float's binary value,
# just below it, and read 9.999e-07 at 50 kHz (review)
_ROUND_DT_BOUNDS = {25e3: "2e-06", 50e3: "1e-06", 1e6: "5e-08"}


@pytest.mark.parametrize("frequency_Hz", [1.0, 3.0, 25e3, 30e3, 33333.0, 39810.47, 50e3,
                                          50001.0, 1e6, 7e6])
def test_the_dt_bound_said_is_a_step_that_is_taken(frequency_Hz):
    # the bound is never said above the steps taken: 1/(20 f) at 30 kHz read 1.667e-06 s,
    # a step above it, refused
    import re

    from lusm.errors import LusmError
    from lusm.options import time_step_of

    with pytest.raises(LusmError) as exc:
        time_step_of("1", frequency_Hz)
    shown = re.search(r"= \(0, (\S+)\] s", str(exc.value)).group(1)
    if frequency_Hz in _ROUND_DT_BOUNDS:
        assert shown == _ROUND_DT_BOUNDS[frequency_Hz]
    assert time_step_of(shown, frequency_Hz) == float(shown)
    assert float(shown) >= 0.999 / (20 * frequency_Hz)  # four digits: close to the bound
    # at most one unit of the bound's fourth digit below it (50001 Hz had said 9.99e-07)
    bound = 1 / (20 * frequency_Hz)
    unit = 10.0 ** (math.floor(math.log10(bound)) - 3)
    assert bound - float(shown) <= unit * 1.000001
    above = f"{float(shown) * 1.001:.6g}"
    with pytest.raises(LusmError):
        time_step_of(above, frequency_Hz)


def test_a_steady_run_takes_any_positive_dt_and_says_it_has_no_effect(capsys):
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady", "--dt", "1e-4",
                 "--json"]) == 0
    assert "--dt has no effect: --steady takes its own step" in capsys.readouterr().err


def test_a_warning_said_before_a_json_record_opens_is_listed_in_it(capsys):
    """lusm says each warning once per command; one said before a --json summary's record
    opened (reading a study, then the run) was left out of the summary's 'warnings' (it is
    not said again, and the record only listed what was said within; review)."""
    from lusm.messages import forget_warnings, warn, warnings_said

    forget_warnings()
    warn("the plate is thick")
    with warnings_said() as said:
        warn("the plate is thick")  # not said again on stderr...
        warn("another")
    assert said == ["the plate is thick", "another"]  # ...but listed
    assert capsys.readouterr().err.count("the plate is thick") == 1
    forget_warnings()
