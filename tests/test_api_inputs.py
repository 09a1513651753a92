"""The library's entry points refuse what is not a value of their parameter, in one
ValueError/TypeError naming it, and take NumPy scalars as the numbers they are (found by
exploratory testing of the Python API; each case gave a silent wrong answer or an obscure
error before)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact.characteristic import characteristic
from contact.maps import stick_slip_map
from contact.model import OperatingPoint
from contact.simulate import simulate
from contact.steady.engine import steady_state
from fem.mesh_settings import MeshSettings
from rom import table2


@pytest.mark.parametrize("loads", [[float("nan"), 0.1], "0.1", [True]])
def test_a_load_that_is_not_a_finite_number_is_refused(loads):
    # a NaN load fell into the fast level's dead zone and came out as 0 m/s
    with pytest.raises(ValueError, match="loads_N must be finite numbers"):
        characteristic(table2(), 200, 14, loads_N=loads, accuracy="fast")


@pytest.mark.parametrize("points", [0, 10**9, 2.5])
def test_a_characteristic_has_a_bounded_number_of_points(points):
    with pytest.raises(ValueError, match="points must be an integer in \\[2, 10000\\]"):
        characteristic(table2(), 200, 14, points=points, accuracy="fast")


@pytest.mark.parametrize("kw", [{"ultrasonic_friction": "False"}, {"energy": "no"}])
def test_a_string_is_not_a_flag(kw):
    # 'False' is a true string: Eq. 11 was applied (mu_d_eff 0.306, not 0.35)
    with pytest.raises(TypeError, match="must be True or False"):
        simulate(table2(), 200, 14, duration_s=1e-3, **kw)
    with pytest.raises(TypeError, match="ultrasonic_friction must be True or False"):
        steady_state(table2(), 200, 14, ultrasonic_friction="no", accuracy="fast")


@pytest.mark.parametrize("voltage", [True, "200", np.array([200.0])])
def test_a_voltage_is_a_real_number(voltage):
    # True ran at 1 V, '200' at 200 V
    with pytest.raises(ValueError, match="voltage_V must be a finite number >= 0 V"):
        OperatingPoint(voltage, 14.0)
    with pytest.raises(ValueError, match="voltage_V"):
        simulate(table2(), voltage, 14, duration_s=1e-3)


@pytest.mark.slow
def test_numpy_scalars_are_numbers():
    # np.int64(200) and np.float32 were refused as "not a finite number"
    op = OperatingPoint(np.int64(200), np.float32(14.0))
    assert (op.voltage_V, op.preload_N) == (200.0, 14.0)
    assert type(op.voltage_V) is float
    a = simulate(table2(), np.int64(200), 14, duration_s=1e-3, dt_s=np.float32(1e-7))
    b = simulate(table2(), 200.0, 14.0, duration_s=1e-3, dt_s=float(np.float32(1e-7)))
    assert a.steady.velocity_m_s == b.steady.velocity_m_s
    p = table2()
    assert p.with_(M_slider=np.float32(0.25)).M_slider == pytest.approx(0.25)


@pytest.mark.parametrize("f", [0, -4e4, float("nan"), "4e4"])
def test_a_map_checks_its_frequency_first(f):
    # 0 was a ZeroDivisionError, -4e4 blamed duration_s
    with pytest.raises(ValueError, match="frequency_Hz must be a finite number > 0 Hz"):
        stick_slip_map(table2(), [200], [14], frequency_Hz=f)


def test_a_map_checks_its_accuracy_with_any_method():
    with pytest.raises(ValueError, match="accuracy must be one of"):
        stick_slip_map(table2(), [200], [14], method="transient", accuracy="slow")


@pytest.mark.parametrize("dt", [1e-12, 1e-15])
def test_a_run_nothing_could_stop_is_refused(dt):
    # 5e10 steps ran past SIGTERM for minutes (the kernel holds signals); 5e13 was a
    # MemoryError allocating the grid
    with pytest.raises(ValueError, match="time steps, above 1e\\+09"):
        simulate(table2(), 200, 14, dt_s=dt)


@pytest.mark.parametrize("entry", [
    lambda p: simulate(p, 200, 14), lambda p: steady_state(p, 200, 14, accuracy="fast"),
    lambda p: characteristic(p, 200, 14, accuracy="fast"),
    lambda p: stick_slip_map(p, [200], [14])])
@pytest.mark.parametrize("params", [None, "table2"])
def test_params_must_be_a_parameter_set(entry, params):
    # None or a dict reached the set-up as AttributeError: 'K_l'
    with pytest.raises(TypeError, match="params must be a rom.params.MotorParams"):
        entry(table2().to_dict() if params == "table2" else params)


def test_options_must_be_simulation_options():
    with pytest.raises(TypeError, match="options must be a SimulationOptions"):
        simulate(table2(), 200, 14, options={"dt_s": 1e-7})


def test_plate_and_reduction_inputs_name_themselves():
    from fem.geometry import PlateStator
    from rom.from_fem import fem_params

    with pytest.raises(ValueError, match="drive_electrodes must be a non-empty tuple"):
        PlateStator(drive_electrodes=1)
    with pytest.raises(ValueError, match="damping_ratios must be \\(zeta_L1, zeta_B2\\)"):
        fem_params(damping_ratios=(0.01,))


def test_drives_beyond_any_stator_are_refused_not_run():
    """The library had no scale bound: 1e200 V overflowed the event functions and a run
    reported pure stick at 0 m/s; 1e100 V gave 3.6e94 m/s. A drive or preload that deflects
    the stator statically by more than a centimetre is refused, naming the input."""
    from contact.model import MAX_STATIC_DEFLECTION_M
    from contact.simulate import simulate
    from contact.steady.engine import steady_state
    from rom import table2

    p = table2()
    for kwargs in ({"voltage_V": 1e200, "preload_N": 14}, {"voltage_V": 1e100, "preload_N": 14},
                   {"voltage_V": 200, "preload_N": 1e12}):
        name = next(k for k, v in kwargs.items() if v > 1e3)
        with pytest.raises(ValueError, match=rf"{name} = .* deflects the stator statically"):
            simulate(p, kwargs["voltage_V"], kwargs["preload_N"], duration_s=1e-3)
        with pytest.raises(ValueError, match=rf"{name} = "):
            steady_state(p, kwargs["voltage_V"], kwargs["preload_N"], accuracy="fast")
    # the bound sits far above the CLI's 2000 V: 0.01 m at 1.7e7 V on Table 2's set
    v_max = MAX_STATIC_DEFLECTION_M / max(abs(p.A_l) / p.K_l, abs(p.A_b) / p.K_b)
    assert v_max > 5e3 * 2000
    assert simulate(p, 2000, 14, duration_s=1e-3).steady.velocity_m_s > 0


@pytest.mark.parametrize("kw", [{"steady_periods": float("nan")}, {"steady_periods": 2.5},
                                {"max_trace_points": "100"}, {"max_events_per_step": True},
                                {"full_periods": float("inf")}])
def test_simulation_options_integers_are_integers(kw):
    """NaN was numpy's "cannot convert float NaN to integer", inf an OverflowError, '100' a
    TypeError deep in a scheme, and 2.5 or True were stored as typed (found by API testing)."""
    from contact.options import SimulationOptions

    with pytest.raises(ValueError, match=f"{next(iter(kw))} must be an integer >= 1"):
        SimulationOptions(**kw)


def test_simulation_options_numbers_are_numbers():
    import numpy as np

    from contact.options import SimulationOptions

    with pytest.raises(TypeError, match="stick_band_m_s must be a number"):
        SimulationOptions(stick_band_m_s="0")
    o = SimulationOptions(rtol=np.float32(1e-8), steady_periods=np.int64(5))  # numpy scalars
    assert type(o.rtol) is float and type(o.steady_periods) is int


def test_fem_damping_ratios_are_under_damped_as_the_beam_sets():
    """fem_params took zeta_L1 = 5 (it checked > 0 only; its own message said (0, 1))."""
    from rom.from_fem import fem_params

    with pytest.raises(ValueError, match=r"zeta_L1 must lie in \(0, 1\)"):
        fem_params(damping_ratios=(5.0, 0.05))


@pytest.mark.parametrize("workers", [0, -1, 2.0, True])
def test_map_workers_are_a_positive_integer(workers):
    """workers=0 used every CPU silently; -1 gave the thread pool's message."""
    from contact.maps import stick_slip_map
    from rom import table2

    with pytest.raises(ValueError, match="workers must be an integer >= 1"):
        stick_slip_map(table2(), [200.0], [14.0], workers=workers)


@pytest.mark.parametrize("cls", ["fem.geometry:PlateStator", "rom.beam_stator:BeamStator"])
def test_millimetres_typed_as_metres_are_refused(cls):
    """PlateStator(length_m=30) was a 30 m plate: sweep_dimension ran 29 s of FE into NaN."""
    import importlib

    module, name = cls.split(":")
    stator = getattr(importlib.import_module(module), name)
    with pytest.raises(ValueError, match=r"length_m must lie in \(0, 10\] m.*30 mm is 0.03"):
        stator(length_m=30)
    assert stator(length_m=0.03).length_m == 0.03


def test_smaller_api_inputs_are_checked():
    """Found by API testing: MotorParams kept source=5; steady_state took energy="no" as
    True; characteristic flattened a nested list of loads; stick_slip_map drew a progress
    bar on stderr by default (the other entry points do not)."""
    import inspect

    from contact.characteristic import characteristic
    from contact.maps import stick_slip_map
    from contact.steady.engine import steady_state
    from rom import table2
    from rom.params import MotorParams

    with pytest.raises(TypeError, match="MotorParams.source must be text"):
        MotorParams(**{**table2().__dict__, "source": 5})
    with pytest.raises(TypeError, match="energy must be True or False"):
        steady_state(table2(), 200, 14, energy="no", accuracy="fast")
    with pytest.raises(ValueError, match="loads_N must be a sequence of loads"):
        characteristic(table2(), 200, 14, loads_N=[[0.0, 0.1]], accuracy="fast")
    assert inspect.signature(stick_slip_map).parameters["progress"].default is False


@pytest.mark.parametrize("k_contact", [1e12, 1e13])
def test_the_literal_scheme_refuses_a_step_its_fastest_mode_does_not_allow(k_contact):
    """RK4 beyond its stability returned v = nan labelled "pure-slip" at the default step;
    the event scheme refused the same step. Both refuse it now, naming dt_s."""
    from dataclasses import replace

    stiff = replace(table2(), k_contact=k_contact)
    for method in ("event", "literal"):
        with pytest.raises(ValueError, match=r"dt_s = 1e-07 s is too large .* use dt_s <="):
            simulate(stiff, 200.0, 14.0, method=method)


@pytest.mark.parametrize("method", ["literal", "reference", "steady"])
@pytest.mark.slow
def test_energy_is_refused_where_it_is_not_computed(method):
    # energy=True came back as energy=None without a word
    with pytest.raises(ValueError, match="energy=True is computed by method='event' only"):
        simulate(table2(), 200.0, 14.0, method=method, energy=True, duration_s=0.005)
    # the keyword wins over the options, as for every other option (at a held slider, which
    # the steady engine answers at once)
    from contact.options import SimulationOptions

    r = simulate(table2(), 100.0, 14.0, None, SimulationOptions(energy=True), method=method,
                 energy=False, duration_s=0.005)
    assert r.energy is None


def test_the_default_drive_warns_where_it_misses_the_sets_modes():
    """The beam set's modes lie at 68 and 96 kHz: at the default 40 kHz its free tip ellipse
    is a fifth of the one at its operating point, and `simulate(beam, 200, 14)` returned a
    near-held slider without a word (the CLI warned, the library did not). The warning's
    share is the ellipse ratio; Table 2, a frequency given, or a set driven at its own
    frequency do not warn."""
    import warnings

    from contact.drive import WEAK_DRIVE_SHARE, WeakDriveWarning, auto_frequency
    from contact.drive import free_tip_amplitudes as amp
    from rom.sources import get_params

    beam = get_params("beam")
    a, b = amp(beam, 40e3)
    a0, b0 = amp(beam, auto_frequency(beam))
    assert a * b < WEAK_DRIVE_SHARE * a0 * b0
    with pytest.warns(WeakDriveWarning, match=f"{a * b / (a0 * b0):.2g} of the one"):
        simulate(beam, 200.0, 14.0, duration_s=0.005)
    with pytest.warns(WeakDriveWarning):
        steady_state(beam, 200.0, 14.0, accuracy="fast")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate(beam, 200.0, 14.0, 40e3, duration_s=0.005)
        simulate(table2(), 200.0, 14.0, duration_s=0.005)


def test_results_own_read_only_arrays_and_compare_by_identity():
    """A characteristic kept the caller's ``loads`` array (editing it relabelled the curve
    beside velocities computed at the old loads), its arrays were writable, and ``==`` raised
    (the truth value of an array); a map likewise kept the caller's voltages."""
    p = table2()
    loads = np.array([0.0, 0.2])
    c = characteristic(p, 300, 14, loads, accuracy="fast")
    loads[1] = 99.0
    assert c.load_N[1] == 0.2 and not c.load_N.flags.writeable
    with pytest.raises(ValueError):
        c.velocity_m_s[0] = 0.0
    again = characteristic(p, 300, 14, [0.0, 0.2], accuracy="fast")
    assert c == c and c != again and len({c, again}) == 2
    volts = np.array([200.0])
    m = stick_slip_map(p, volts, [14.0], method="steady", accuracy="fast", workers=1)
    volts[0] = 1.0
    assert m.voltages_V[0] == 200.0 and not m.velocity_m_s.flags.writeable
    assert m == m and hash(m) == hash(m)


@pytest.mark.parametrize("axis", [[True], ["200"]])
def test_a_maps_axes_are_real_numbers(axis):
    # as simulate's voltage: [True] ran at 1 V and ["200"] at 200 V
    with pytest.raises(ValueError, match="voltages_V must be real numbers"):
        stick_slip_map(table2(), axis, [14.0])
    with pytest.raises(ValueError, match="preloads_N must be real numbers"):
        stick_slip_map(table2(), [200.0], axis)


def test_a_maps_options_message_offers_no_keyword_overrides():
    # stick_slip_map takes none; the message simulate gives suggested them
    with pytest.raises(TypeError) as info:
        stick_slip_map(table2(), [200.0], [14.0], options={"dt_s": 1e-7})
    assert "keyword" not in str(info.value) and "SimulationOptions" in str(info.value)


def test_the_phase_plane_names_the_method_that_stores_its_window():
    # any other scheme's result failed with an AttributeError on None
    from contact.phase_plane import phase_plane

    r = simulate(table2(), 200, 14, duration_s=2e-3, method="literal")
    with pytest.raises(ValueError, match="only method='event' stores; this run used "
                                         "method='literal'"):
        phase_plane(r)


@pytest.mark.parametrize(("call", "words"), [
    # plate_modes(refine=10000) had been killed for memory, solid_modes(refine=200) ended in
    # a MemoryError; both are refused from a lower bound of the count, before any line
    (lambda: __import__("fem.modes", fromlist=["x"]).plate_modes(
        mesh=MeshSettings(refine=10_000)),
     "refine = 10000 makes at least 4e+08 elements"),
    (lambda: __import__("fem.solid3d.model", fromlist=["x"]).solid_modes(
        mesh=MeshSettings(layers=10**5)),
     "layers = 100000 and edge_grading = 0 make at least"),
    (lambda: __import__("fem.solid3d.model", fromlist=["x"]).solid_modes(
        mesh=MeshSettings(edge_grading=100)),
     "edge_grading = 100 make 3.18e+05 bricks"),
    (lambda: stick_slip_map(table2(), np.linspace(1, 400, 2000), np.linspace(1, 20, 2000),
                            method="steady", accuracy="fast"),
     "give 4000000 points, above 1000000"),
    (lambda: characteristic(table2(), 400, 14, loads_N=np.linspace(0, 2, 100_000)),
     "loads_N has 100000 loads, above 10000"),
])
def test_library_work_is_bounded_before_it_starts(call, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace("+", r"\+")):
        call()


def test_fe_entry_points_say_what_a_stator_is_and_take_numpy_sizes():
    """A loaded stator file passed whole failed as "'StatorDesign' object has no attribute
    'width_m'"; thickness_inertia="False" ran with the inertia; PlateStator refused
    np.float32(0.03) as not > 0 and took True as a 1 m thickness (API testing)."""
    from fem.geometry import PlateStator
    from fem.modes import plate_modes
    from fem.stator_file import load_stator

    design = load_stator("examples/tuned_60k/stator.toml")
    with pytest.raises(TypeError, match="got StatorDesign; .* design.stator and "
                                        "design.material"):
        plate_modes(design)
    with pytest.raises(TypeError, match="thickness_inertia must be True or False"):
        plate_modes(mesh=MeshSettings(thickness_inertia="False"))
    a = PlateStator(length_m=np.float32(0.03), electrode_gap_m=np.int64(0))
    assert type(a.length_m) is float and a.length_m == float(np.float32(0.03))
    with pytest.raises(ValueError, match="thickness_m must be a number"):
        PlateStator(thickness_m=True)


@pytest.mark.parametrize(("call", "error", "words"), [
    (lambda: simulate(table2(), 200, 14, method=["event"]), ValueError,
     r"method must be one of event, .*got \['event'\]"),
    (lambda: simulate(table2(), 400, 14, max_events_per_step=10**30), ValueError,
     r"max_events_per_step must be an integer in \[1, 2147483647\]"),
    (lambda: __import__("rom.params", fromlist=["x"]).MotorParams.from_dict(
        {**table2().to_dict(), 5: 1}), ValueError, r"keys are names, got \[5\]"),
    (lambda: __import__("rom.params", fromlist=["x"]).MotorParams.from_dict(
        {**table2().to_dict(), "units": None}), ValueError, "units must be an object"),
    (lambda: __import__("fem.stator_file", fromlist=["x"]).load_stator(None), TypeError,
     "path must name a stator TOML file, got None"),
])
def test_obscure_errors_of_the_api_name_their_parameter(call, error, words):
    """Each had failed as an unhashable list, an OverflowError, a str.join TypeError, an
    'unknown key units' or os.fspath's message (API testing)."""
    with pytest.raises(error, match=words):
        call()


def test_an_overflowing_set_names_its_extreme_value_however_small():
    """M_l = 1e-300 was reported as "its largest value is K_l" (API testing)."""
    import warnings

    with warnings.catch_warnings(), pytest.raises(ValueError, match="M_l = 1e-300"):
        warnings.simplefilter("ignore", RuntimeWarning)
        simulate(table2().with_(M_l=1e-300), 400, 14)


def test_a_map_names_its_own_axis_when_a_value_is_not_finite():
    """stick_slip_map(p, [nan], [14]) named simulate's voltage_V (API testing)."""
    with pytest.raises(ValueError, match=r"voltages_V must be finite, got \[nan\]"):
        stick_slip_map(table2(), [float("nan")], [14.0])


@pytest.mark.parametrize("accuracy", ["fast", "exact"])
def test_a_load_beyond_the_linear_scale_is_refused_at_both_levels(accuracy):
    """1e7 N came out as NaN (runs away) at the fast level and was refused at the exact one,
    after its other loads were solved (API testing). The refusal names loads_N and keeps the
    load's sign (-1e9 N had read "load_N = 1e+09")."""
    with pytest.raises(ValueError, match=r"^loads_N: its load 1e\+07 N deflects the stator"):
        characteristic(table2(), 200, 14, loads_N=[0.0, 1e7], accuracy=accuracy)
    with pytest.raises(ValueError, match=r"^loads_N: its load -1e\+07 N deflects"):
        characteristic(table2(), 200, 14, loads_N=[0.0, -1e7], accuracy=accuracy)
    with pytest.raises(ValueError, match=r"^load_N = -1e\+09 N deflects"):
        simulate(table2(), 200, 14, load_N=-1e9)
    # a preload beyond the scale stays the preload's refusal (it had read "preloads_N: its
    # load 1e+09 N"; review)
    with pytest.raises(ValueError, match=r"^preload_N = 1e\+09 N deflects"):
        characteristic(table2(), 200, 1e9, loads_N=[0.0, 1.0], accuracy=accuracy)


def test_progress_is_a_bool():
    with pytest.raises(TypeError, match="progress must be True or False, got 'yes'"):
        characteristic(table2(), 200, 14, points=2, accuracy="fast", progress="yes")
    with pytest.raises(TypeError, match="progress must be True or False"):
        stick_slip_map(table2(), [200.0], [14.0], progress="no")


def test_an_edited_table2_set_says_its_coupling_switched():
    """``coupling="auto"`` gives Table 2's own set the paper's coupling and every other set
    the consistent one. A copy of Table 2 with the slider mass changed by 1e-9 ran 5.7 times
    faster (0.0076 -> 0.043 m/s at 200 V / 14 N) without a word from the library (physics
    audit). It now warns; Table 2 itself, an explicit coupling and the FE set do not."""
    import dataclasses
    import warnings

    from contact.model import CouplingSwitchWarning
    from rom.sources import get_params

    p = table2()
    edited = dataclasses.replace(p, M_slider=p.M_slider * (1 + 1e-6))  # above rounding
    with pytest.warns(CouplingSwitchWarning, match="edited copy of Table 2's"):
        moved = simulate(edited, 200.0, 14.0, duration_s=0.01).steady.velocity_m_s
    with pytest.warns(CouplingSwitchWarning):
        steady_state(edited, 200.0, 14.0, accuracy="fast")
    with warnings.catch_warnings():
        warnings.simplefilter("error", CouplingSwitchWarning)
        paper = simulate(edited, 200.0, 14.0, duration_s=0.01,
                         coupling="paper").steady.velocity_m_s
        own = simulate(p, 200.0, 14.0, duration_s=0.01).steady.velocity_m_s
        simulate(get_params("fem"), 200.0, 14.0, 54e3, duration_s=0.002)
    # the edit alone moves nothing visible; the switch moves the speed several-fold
    assert paper == pytest.approx(own, rel=1e-6)
    assert moved > 2.0 * own


def test_the_default_coupling_follows_the_numbers_not_the_label():
    """Table 2's numbers saved without their source text (from_dict makes it optional), or
    relabelled, ran with the consistent coupling: 0.043 m/s at 200 V / 14 N where Table 2
    gives 0.0076 (API testing). The numbers decide; an edit of a number still switches."""
    from contact.model import default_coupling
    from rom.params import MotorParams

    p = table2()
    d = p.to_dict()
    d.pop("source")
    unlabelled = MotorParams.from_dict(d)
    assert unlabelled.source != p.source
    own = simulate(p, 200.0, 14.0, duration_s=0.01).steady.velocity_m_s
    for q in (unlabelled, p.with_(source="my motor")):
        assert default_coupling(q)[0] == "paper"
        assert simulate(q, 200.0, 14.0, duration_s=0.01).steady.velocity_m_s == own
    # an edit above single precision's rounding switches; Table 2 written through float32,
    # which from_dict takes as unedited, keeps the paper's coupling (it had run 5.7x faster)
    assert default_coupling(p.with_(k_contact=p.k_contact * (1 + 1e-6)))[0] == "consistent"
    f32 = MotorParams.from_dict({k: (float(np.float32(v)) if isinstance(v, float) else v)
                                 for k, v in p.to_dict().items()})
    assert f32 != p and default_coupling(f32)[0] == "paper"


def test_a_run_that_would_keep_too_many_steps_is_refused_before_its_kernel():
    """full_periods=10**9 over a 5 s run kept half the run at full resolution: a MemoryError
    after the kernel had run (1.3 GB at 1 s; API testing), and max_trace_points=10**9 kept
    every step. Both are refused before the kernel, naming the option; a run that keeps
    little stays allowed whatever full_periods says."""
    import time

    p = table2()
    t0 = time.perf_counter()
    for name in ("full_periods", "max_trace_points"):
        with pytest.raises(ValueError, match=rf"^{name}: the run would keep .* steps, above "
                                             r"the limit 1e\+07"):
            simulate(p, 200.0, 14.0, duration_s=5.0, steady_periods=10**9, **{name: 10**9})
    assert time.perf_counter() - t0 < 60  # no kernel ran, not even the A_N pre-pass
    r = simulate(p, 200.0, 14.0, duration_s=0.01, full_periods=10**9)
    assert math.isfinite(r.steady.velocity_m_s)  # its window is at most half of 1e5 steps


def test_beam_damping_ratios_are_refused_with_their_range():
    """beam_params(damping_ratios=(0.0, 0.1)) said "(0, inf)"; the range is (0, 1)."""
    from rom.beam import beam_params

    for bad in (0.0, 1.0, "0.1", True):
        with pytest.raises(ValueError, match=r"^damping_ratios\[0\] \(zeta_L1\) must be a "
                                             r"number in \(0, 1\)"):
            beam_params(damping_ratios=(bad, 0.1))


def test_an_unknown_source_option_is_a_value_error_naming_the_options():
    """get_params("fem", foo=1) raised the builder's TypeError where get_params promises a
    ValueError for bad options (API testing); "fem" takes no plate dimensions directly."""
    from rom.sources import get_params

    with pytest.raises(ValueError, match=r"^source 'fem' takes no option length_m; its "
                                         r"options are .*stator"):
        get_params("fem", length_m=0.03)
    with pytest.raises(ValueError, match=r"^source 'beam' takes no option foo; its options "
                                         r"are .*length_m"):
        get_params("beam", foo=1)
    assert get_params("beam", length_m=0.031).f_L1_Hz < get_params("beam").f_L1_Hz
