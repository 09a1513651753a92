"""The contact stage's one entry point: :func:`simulate`, one frozen result whatever the scheme.

In the manner of ``scipy.integrate.solve_ivp``, ``method=`` picks a scheme from
:data:`METHODS`; every scheme starts from the same static equilibrium, runs on the same time
window (:mod:`contact.transient.window`), uses the same dynamic friction coefficient (Eq. 11,
from the A_N pre-pass) and returns the same :class:`SimulationResult` with its solver counters:

* ``"event"`` (default): exact per-mode propagators with located switches, numba
  (:mod:`contact.transient.event_kernel`);
* ``"reference"``: the equations written out term by term, ``solve_ivp`` with terminal events
  (:mod:`contact.transient.reference`), the slow yardstick;
* ``"literal"``: the paper's fixed-step RK4 with the stick band
  (:mod:`contact.transient.literal`), for contrast only;
* ``"steady"``: the steady state from rest found directly (averaging, finite-mass shooting,
  :mod:`contact.steady.engine`); no trace.

>>> from rom import table2
>>> from contact.simulate import simulate
>>> r = simulate(table2(), voltage_V=200, preload_N=14)      # doctest: +SKIP
>>> r.steady.velocity_m_s, r.steady.motion, r.events          # doctest: +SKIP
>>> simulate(table2(), 200, 14, method="reference").nfev      # doctest: +SKIP
"""

from __future__ import annotations

import importlib
import math
import numbers
import time
import warnings
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from contact.deferred_signals import call_held
from contact.errors import ChatteringError
from contact.friction import dynamic_friction
from contact.model import (
    COUPLING_CHOICES,
    HybridSystem,
    OperatingPoint,
    build_system,
    check_rest,
    gamma_T,
    linear_normal_amplitude,
    resolve_coupling,
)
from contact.results import EnergyBalance, SchemeOutput, SteadyState, Trace, steady_metrics
from contact.state import ERR_CHATTER, OK
from contact.transient import event_kernel
from contact.transient.window import (
    MAX_STORED_STEPS,
    MIN_PERIODS,
    RunWindow,
    period_step_s,
    run_window,
    work_factor,
)
from rom.params import MotorParams, require_params

PRE_PASS_PERIODS = 60
"""Least drive periods simulated to find the steady normal amplitude A_N of Eq. 11 (more on
a lightly damped stator: :func:`pre_pass_periods`)."""
PRE_PASS_SETTLE = 1e-9
"""Share of the start's transient left where the pre-pass's window (its last third) begins:
the pre-pass is long enough for the L1 vibration to decay to it (:func:`pre_pass_periods`)."""
MAX_PRE_PASS_PERIODS = 20_000
"""Longest pre-pass (drive periods): reached below zeta_L1 of about 2.5e-4 at a drive at
L1's resonance, where its window starts with up to 1e-6 of the start transient left; more
(below about 1.6e-4) gets :class:`UnsettledAmplitudeWarning` (:data:`UNSETTLED_SHARE`)."""
UNSETTLED_SHARE = 1e-6
"""Share of the start transient left at the pre-pass window's start above which A_N is
said to be unsettled."""
MAX_PRE_PASS_STEPS = 20_000_000
"""Most steps of a pre-pass at the caller's step (the CLI's bound on a run,
``validation.limits.MAX_STEPS``); beyond, it takes :data:`PRE_PASS_STEPS_PER_PERIOD`."""
PRE_PASS_STEPS_PER_PERIOD = 250
"""Steps per drive period of a pre-pass too long at the caller's step (the default step's
share at 40 kHz; its A_N error is about 1e-9)."""


class UnsettledAmplitudeWarning(UserWarning):
    """Eq. 11's normal amplitude A_N came from a pre-pass too short for the L1 vibration to
    settle (an almost undamped stator): mu_d,eff carries the start's transient."""

MAX_COUNT_OPTION = 2**31 - 1
"""Largest value of the options counted in periods, points or events (the kernels' int)."""

METHODS = {
    "event": "contact.simulate:solve_event",
    "reference": "contact.transient.reference:solve_reference",
    "literal": "contact.transient.literal:solve_literal",
    "steady": "contact.steady.engine:solve_steady",
}
"""Schemes of :func:`simulate`: name -> ``module:function(params, op, options, window,
mu_d_eff) -> SchemeOutput``, imported on first use (the reference pulls in SciPy)."""


DEFAULT_DT_S = 1e-7
"""Nominal fixed step (s) of the transients: 250 steps per period at 40 kHz, where Fig. 9's
traces and the paper reproduction run; off 40 kHz rounded to divide the drive period."""


@dataclass(frozen=True)
class SimulationOptions:
    """Numerical and modelling options of a run.

    Attributes
    ----------
    duration_s : float
        Simulated time (s); at least :data:`MIN_PERIODS` drive periods.
    dt_s : float or None
        Fixed time step (s), in (0, 1/(20 f)]. None (the default): :data:`DEFAULT_DT_S`
        rounded to make the drive period a whole number of steps
        (:func:`contact.transient.window.period_step_s`; 1e-7 s itself at 40 kHz), the CLI's
        default.
        A fixed 1e-7 s cut the averaging windows mid-period off 40 kHz and biased their
        means; :func:`simulate` stores the step it ran in the result's ``options``.
    ultrasonic_friction : bool
        Apply Eq. 11 (amplitude-dependent mu_d); otherwise slip uses ``mu_d``.
    coupling : {"auto", "paper", "consistent"}
        Generalized force of F_T on B2 (see :mod:`contact.model`); ``"auto"`` (the
        default, as the CLI's): :func:`contact.model.default_coupling`, the paper's for
        Table 2's own set and the consistent one for every other. :func:`simulate` stores
        the one it ran in the result's ``options``.
    stick_band_m_s : float
        The paper's epsilon (m/s); see :func:`contact.model.build_system`. The literal scheme
        decides stick with it at every step.
    steady_periods : int
        Length of the steady-state window (periods), capped at half the run.
    full_periods : int
        Periods at the end of the run stored at every step (phase plane, Figs. 10-17).
    max_trace_points : int
        Upper bound on the decimated trace length.
    energy : bool
        Accumulate the work integrals of the energy balance over the window.
    max_events_per_step : int
        Switches allowed within one step before the run is declared chattering.
    rtol : float
        Relative tolerance of the ``reference`` scheme (absolute tolerances are scaled per
        state component).
    rest : {"probe", "transient"}
        How the ``steady`` scheme decides the branch a start from rest reaches
        (:func:`contact.steady.engine.steady_state` ``rest=``); unused by the transient schemes.
    """

    duration_s: float = 0.05
    dt_s: float | None = None
    ultrasonic_friction: bool = True
    coupling: str = "auto"
    stick_band_m_s: float = 1e-10
    steady_periods: int = 20
    full_periods: int = 5
    max_trace_points: int = 20000
    energy: bool = False
    max_events_per_step: int = 64
    rtol: float = 1e-10
    rest: str = "probe"

    def __post_init__(self) -> None:
        for name in ("duration_s", "dt_s"):
            v = getattr(self, name)
            if v is None and name == "dt_s":
                continue  # resolved per drive frequency by simulate()
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v) \
                    or v <= 0:
                raise ValueError(f"{name} must be a finite number > 0 (s), got {v!r}")
            object.__setattr__(self, name, float(v))
        for name in ("ultrasonic_friction", "energy"):  # 'False' is a true string
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False, got {getattr(self, name)!r}")
        check_rest(self.rest)
        if self.coupling not in COUPLING_CHOICES:
            raise ValueError(f"coupling must be one of {COUPLING_CHOICES}, got "
                             f"{self.coupling!r}")
        for name in ("steady_periods", "full_periods", "max_trace_points", "max_events_per_step"):
            v = getattr(self, name)
            # an integer, stored as one: NaN had been a numpy conversion error, '100' a
            # TypeError deep in a scheme, and 2.5 or True were kept as typed in r.options
            if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < 1:
                raise ValueError(f"{name} must be an integer >= 1, got {v!r}")
            if v > MAX_COUNT_OPTION:  # 1e30 reached the kernel as an OverflowError
                raise ValueError(f"{name} must be an integer in [1, {MAX_COUNT_OPTION}], got "
                                 f"{v!r}")
            object.__setattr__(self, name, int(v))
        for name in ("rtol", "stick_band_m_s"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real):
                raise TypeError(f"{name} must be a number, got {v!r}")
            object.__setattr__(self, name, float(v))
        if not 1e-14 <= self.rtol <= 1e-3:
            raise ValueError(f"rtol must lie in [1e-14, 1e-3], got {self.rtol!r}")
        if not (math.isfinite(self.stick_band_m_s) and self.stick_band_m_s >= 0):
            raise ValueError(f"stick_band_m_s must be finite and >= 0 (m/s), got "
                             f"{self.stick_band_m_s!r}")


def options_or_default(options: SimulationOptions | None,
                       overrides: bool = True) -> SimulationOptions:
    """``options``, or the defaults for None; anything else is a TypeError naming it (a dict
    was "has no attribute 'dt_s'" deep in a scheme). ``overrides``: whether the caller also
    takes keyword overrides (``simulate`` does, ``stick_slip_map`` not), which the message
    then suggests."""
    if options is None:
        return SimulationOptions()
    if not isinstance(options, SimulationOptions):
        how = " (or keyword overrides such as dt_s=...)" if overrides else ""
        raise TypeError(f"options must be a SimulationOptions{how}, got "
                        f"{type(options).__name__}")
    return options


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Everything one run produced, whatever the scheme.

    Attributes
    ----------
    params : MotorParams
    op : OperatingPoint
    options : SimulationOptions
    method : str
        The scheme (a key of :data:`METHODS`).
    mu_d_eff : float
        Dynamic friction coefficient used in slip (-).
    normal_amplitude_m : float
        A_N of Eq. 11 (m), from the pre-pass (NaN for a scheme without it when Eq. 11 is off).
    trace : Trace or None
        Decimated trace of the whole run (``event`` only).
    window : Trace or None
        Every step of the last ``full_periods`` periods (``event`` only).
    steady : SteadyState
    energy : EnergyBalance or None
        With ``options.energy`` (``event`` only).
    steps : int
        Steps taken: fixed steps (``event``, ``literal``; the pre-pass excluded) or accepted
        adaptive steps (``reference``).
    events : int or None
        Mode switches: located (``event``, ``reference``) or between steps (``literal``);
        None for ``steady``, which counts none.
    nfev : int
        Flow evaluations: propagator products plus exact-flow evaluations spent locating
        events (``event``), right-hand-side evaluations (``reference``, ``literal``).
    wall_time_s : float
        Wall time of the integration (s), pre-pass included.
    branches : tuple of contact.steady.engine.SteadyBranch or None
        ``steady``: every steady state the engine found at the point (by increasing
        velocity, unstable ones included; ``steady`` describes the one a start from rest
        reaches); None for the transients, which follow one.
    """

    params: MotorParams
    op: OperatingPoint
    options: SimulationOptions
    method: str
    mu_d_eff: float
    normal_amplitude_m: float
    trace: Trace | None
    window: Trace | None
    steady: SteadyState
    energy: EnergyBalance | None
    steps: int
    events: int | None
    nfev: int
    wall_time_s: float
    branches: tuple | None = None


def check_spectrum(system: HybridSystem, dt_s: float) -> None:
    """Refuse a step ``dt_s`` (s) above the inverse spectral radius of the system's modes.

    Raises
    ------
    ValueError
        Naming ``dt_s`` and the largest step the fastest mode allows.
    """
    rho = max(float(np.max(np.abs(np.linalg.eigvals(a)))) for a in system.A)
    if rho * dt_s > 1.0:  # the Taylor flow of partial steps is exact to roundoff below 1
        raise ValueError(
            f"dt_s = {dt_s:g} s is too large for the fastest mode of this parameter set "
            f"({rho / (2 * math.pi):.4g} Hz): use dt_s <= {1.0 / rho:.3g} s"
        )


def _run(system: HybridSystem, n_steps: int, dt: float, win_start: int, decim: int,
         n_full: int, energy: bool, max_events: int, marks: np.ndarray, mark_x: np.ndarray):
    phi, phi_half = system.propagators(dt)
    return call_held(  # a Ctrl-C during the kernel is raised after it returns
        event_kernel.integrate_switch_model,
        system.z0, system.mode0, n_steps, dt, phi, phi_half, system.A, system.ev_h,
        system.ev_dh, system.ev_type, system.fn_m, system.ft_m, system.ff_m, system.funcs,
        system.scalars, win_start, decim, n_full, energy, max_events, marks, mark_x,
    )


def raise_status(status: int, fail_step: int, dt: float, op: OperatingPoint) -> None:
    if status == ERR_CHATTER:
        raise ChatteringError(
            f"contact chattering: more switches than allowed within one step at "
            f"t = {fail_step * dt:.6g} s (V0 = {op.voltage_V:g} V, F_P = {op.preload_N:g} N)",
            step_remedy=True,
        )
    if status != OK:  # pragma: no cover - no other codes exist
        raise RuntimeError(f"switch-model kernel failed with status {status}")


def _l1_decay_rate(params: MotorParams) -> float:
    """Decay rate (1/s) of the L1 coordinate's free transient, ``C_l / (2 M_l)``."""
    return params.C_l / (2.0 * params.M_l)


def pre_pass_periods(params: MotorParams, op: OperatingPoint) -> int:
    """Drive periods of the A_N pre-pass: at least :data:`PRE_PASS_PERIODS`, and 1.5 times
    the periods in which the L1 vibration's start transient decays to
    :data:`PRE_PASS_SETTLE`, so that the window (the last third) starts settled; at most
    :data:`MAX_PRE_PASS_PERIODS`.

    The transient decays as ``exp(-C_l t / (2 M_l))`` in contact and in separation alike
    (the contact adds stiffness, not damping). Table 2 (zeta_L1 = 0.12) needs 42 periods
    (1.5 x the 27.8 in which it decays), so 60 stay; at zeta_L1 = 0.01 it decays in about
    330, and a fixed 60-period pre-pass put A_N 7 % above the settled amplitude (84 % at
    zeta_L1 = 0.001).
    """
    rate = _l1_decay_rate(params)
    if not rate > 0.0:
        return MAX_PRE_PASS_PERIODS
    settle = math.log(1.0 / PRE_PASS_SETTLE) / (rate * op.period_s)
    return int(min(MAX_PRE_PASS_PERIODS, max(PRE_PASS_PERIODS, math.ceil(1.5 * settle))))


def normal_amplitude(
    params: MotorParams, op: OperatingPoint, dt_s: float = 1e-7, periods: int | None = None,
    *, closed_form: bool = True,
) -> float:
    """Steady normal vibration amplitude A_N at the tip (m): half peak-to-peak of y_tip.

    Where the tip never separates, the orbit is harmonic and A_N is taken in closed form
    (:func:`contact.model.linear_normal_amplitude`; it equals the simulated pre-pass to
    1e-9, the pre-pass's own step error). Otherwise, or with ``closed_form=False`` (the
    reference), runs Eqs. 4 + 7 (with separation) from rest for ``periods`` drive periods
    (default :func:`pre_pass_periods`, long enough to settle); the last third is the
    window. The tangential state does not enter, so friction settings and the coupling do
    not matter. The step is ``dt_s`` unless the pre-pass would then take more than
    :data:`MAX_PRE_PASS_STEPS`; it then takes :data:`PRE_PASS_STEPS_PER_PERIOD` per period
    (the kernel's propagators are exact: only event location depends on the step). Results
    are cached per set and operating point: a characteristic asks for the same A_N at every
    load.

    Warns
    -----
    UnsettledAmplitudeWarning
        The stator is damped too lightly for the default pre-pass to settle.
    """
    if closed_form:
        a_n = linear_normal_amplitude(params, op)
        if a_n is not None:
            return a_n
    if periods is None:
        periods = pre_pass_periods(params, op)
        rate = _l1_decay_rate(params)
        left = math.exp(-rate * op.period_s * periods * 2.0 / 3.0) if rate > 0.0 else 1.0
        if left > UNSETTLED_SHARE:  # capped far short of settling
            warnings.warn(UnsettledAmplitudeWarning(
                f"Eq. 11's normal amplitude A_N comes from a {periods}-period pre-pass whose "
                f"window starts with {left:.2g} of the L1 start transient left (zeta_L1 = "
                f"{params.zeta_L1:.3g}, too light to settle within {MAX_PRE_PASS_PERIODS} "
                f"periods): A_N and mu_d,eff may be off by about that share; damp L1 more, "
                f"or set ultrasonic_friction = False for a constant mu_d"), stacklevel=3)
    if periods * op.period_s / dt_s > MAX_PRE_PASS_STEPS:
        # a light stator at a low drive frequency: 1e8 steps at 1e-7 s and 1 kHz, five times
        # what the run itself may take
        dt_s = max(dt_s, op.period_s / PRE_PASS_STEPS_PER_PERIOD)
    return _pre_pass(params, op.voltage_V, op.preload_N, op.frequency_Hz, float(dt_s),
                     int(periods))


@lru_cache(maxsize=256)
def _pre_pass(params: MotorParams, voltage_V: float, preload_N: float, frequency_Hz: float,
              dt_s: float, periods: int) -> float:
    """The A_N pre-pass of :func:`normal_amplitude` (m), once per set, point, step, length."""
    op = OperatingPoint(voltage_V, preload_N, frequency_Hz)
    # the normal coordinate does not see F_T: any coupling the set accepts builds the same
    # normal motion ("paper" refused a set with phi_B0 = phi_Bl asked to run "consistent")
    coupling = "consistent" if params.phi_Bl else "paper"
    system = build_system(params, op, params.mu_d, coupling)
    n_steps = int(round(periods * op.period_s / dt_s))
    win_start = n_steps - max(1, n_steps // 3)
    out = _run(system, n_steps, dt_s, win_start, n_steps, 1, False, 64,
               np.empty(0, dtype=np.int64), np.empty(0))
    raise_status(out[0], out[1], dt_s, op)
    stats = out[6]
    return 0.5 * (stats[2] - stats[1])


def simulate(
    params: MotorParams,
    voltage_V: float,
    preload_N: float,
    frequency_Hz: float | None = None,
    options: SimulationOptions | None = None,
    *,
    method: str = "event",
    load_N: float = 0.0,
    **option_overrides: object,
) -> SimulationResult:
    """Simulate the stick-slip-separation switch model (Eqs. 4-19) from rest.

    Parameters
    ----------
    params : MotorParams
        Any parameter set (:func:`rom.table2`, beam theory, FE reduction).
    voltage_V : float
        Drive amplitude V0 (V), >= 0.
    preload_N : float
        Preload F_P (N), >= 0.
    frequency_Hz : float, optional
        Drive frequency (Hz), > 0; default the paper's 40 kHz, with
        :class:`contact.drive.WeakDriveWarning` when that misses the set's modes.
    options : SimulationOptions, optional
        Numerical options; keyword overrides (``dt_s=...``) are applied on top.
    method : str
        A key of :data:`METHODS`: ``"event"`` (default), ``"reference"``, ``"literal"`` or
        ``"steady"``.
    load_N : float
        External load on the slider (N), opposing positive velocity (see
        :class:`contact.model.OperatingPoint`); the ``event`` and ``steady`` schemes model it,
        the others refuse a nonzero load.

    Returns
    -------
    SimulationResult

    Raises
    ------
    ValueError
        On invalid input, naming the parameter and its allowed range.
    contact.errors.ChatteringError
        When the contact chatters beyond ``max_events_per_step`` within a step.
    """
    require_params(params)
    if not isinstance(method, str) or method not in METHODS:  # ["event"]: "unhashable"
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if load_N and method in ("reference", "literal"):
        raise ValueError(f"load_N is modelled by the event and steady schemes only, got "
                         f"load_N={load_N!r} with method={method!r}")

    from contact.drive import default_drive_Hz

    op = OperatingPoint(voltage_V, preload_N, default_drive_Hz(params, frequency_Hz), load_N)
    opts = options_or_default(options)
    if option_overrides:
        opts = SimulationOptions(**{**opts.__dict__, **option_overrides})
    if method != "event" and opts.energy:  # the override wins, and its type is checked
        # it came back as energy=None without a word (steady: SteadyResult's powers)
        raise ValueError(f"energy=True is computed by method='event' only, got "
                         f"method={method!r}")
    if opts.dt_s is None:
        opts = replace(opts, dt_s=period_step_s(op.period_s, DEFAULT_DT_S))
    if opts.coupling == "auto":  # the result's options say which coupling ran
        opts = replace(opts, coupling=resolve_coupling(params, "auto"))
    dt_a_n = opts.dt_s
    if method == "steady":
        # the steady engine takes its own step and length: duration_s and dt_s are not
        # used (checked against the frequency, the defaults would refuse a drive below
        # 200 Hz or above 500 kHz); the window only carries the phase fractions, and Eq. 11's
        # pre-pass (separating points) takes 250 steps per period (1e-7 s at 40 kHz, the
        # transients' default)
        window = run_window(op, MIN_PERIODS * op.period_s, op.period_s / 20.0,
                            opts.steady_periods)
        dt_a_n = op.period_s / 250.0
    else:
        window = run_window(op, opts.duration_s, opts.dt_s, opts.steady_periods)
    if method == "reference":  # its work bound, before the A_N pre-pass starts
        from contact.transient.reference import check_reference_work

        check_reference_work(op, window.end_s)
    if method == "event":  # what it keeps, before the A_N pre-pass starts too
        n_full, decim = _full_and_decimation(op, opts, window)
        check_stored_steps(n_full, math.ceil(window.n_steps / decim))
    module, _, name = METHODS[method].partition(":")
    scheme = getattr(importlib.import_module(module), name)

    t0 = time.perf_counter()
    if opts.ultrasonic_friction:
        a_n = normal_amplitude(params, op, dt_a_n)
        mu_d_eff = dynamic_friction(params, a_n)
    else:
        a_n = float("nan")
        mu_d_eff = params.mu_d
    out: SchemeOutput = scheme(params, op, opts, window, mu_d_eff)
    wall = time.perf_counter() - t0
    if not opts.ultrasonic_friction and math.isfinite(out.y_tip_max_m):
        a_n = 0.5 * (out.y_tip_max_m - out.y_tip_min_m)
    steady = steady_metrics(out.velocity_m_s, out.previous_velocity_m_s, out.phase_time,
                            out.y_tip_min_m, out.y_tip_max_m, window.window_s)
    if op.load_N and method != "steady" and not steady.settled:
        from contact.steady.engine import RunawayWarning, transient_runaway

        reason = transient_runaway(params, op, opts.coupling, opts.ultrasonic_friction,
                                   mu_d_eff, steady.velocity_m_s,
                                   steady.previous_velocity_m_s)
        if reason is not None:  # the steady scheme refuses such a load; a transient says so
            warnings.warn(f"{reason}; the velocity is where the run stopped", RunawayWarning,
                          stacklevel=2)
    return SimulationResult(
        params=params, op=op, options=opts, method=method, mu_d_eff=mu_d_eff,
        normal_amplitude_m=a_n, trace=out.trace, window=out.window, steady=steady,
        energy=out.energy, steps=out.steps, events=out.events, nfev=out.nfev,
        wall_time_s=wall, branches=out.branches,
    )


def _full_and_decimation(op: OperatingPoint, opts: SimulationOptions,
                         window: RunWindow) -> tuple[int, int]:
    """``(steps kept at full resolution, decimation of the trace)`` of the event scheme."""
    n_steps = window.n_steps
    n_full = min(n_steps, int(round(min(opts.full_periods, window.window_periods)
                                    * op.period_s / window.dt_s)))
    return n_full, max(1, int(math.ceil(n_steps / opts.max_trace_points)))


def check_stored_steps(full_steps: int, trace_points: int) -> None:
    """Refuse, before the kernel runs, a run that would keep more than
    :data:`contact.transient.window.MAX_STORED_STEPS` steps (times ``LUSM_MAX_WORK``) at full
    resolution or in its decimated trace, naming the option that asks for them."""
    top = MAX_STORED_STEPS * work_factor()
    for name, n in (("full_periods", full_steps), ("max_trace_points", trace_points)):
        if n > top:
            raise ValueError(f"{name}: the run would keep {n:.3g} steps, above the limit "
                             f"{top:.3g} of a library call (about 80 bytes each, held three "
                             f"times); lower {name} (set LUSM_MAX_WORK=N to allow N times "
                             "more)")


def solve_event(params: MotorParams, op: OperatingPoint, opts: SimulationOptions,
                 window: RunWindow, mu_d_eff: float) -> SchemeOutput:
    """The event-located scheme (:mod:`contact.transient.event_kernel`)."""
    dt = window.dt_s
    n_steps, win_start = window.n_steps, window.win_start
    n_full, decim = _full_and_decimation(op, opts, window)
    system = build_system(params, op, mu_d_eff, opts.coupling, opts.stick_band_m_s)
    check_spectrum(system, dt)
    # an earlier window, at least a fifth of the run before the last one, tells whether the
    # slider is still accelerating: its ends are marked in the kernel (interpolating the
    # decimated trace put them 0.5-2 % off at creep speeds, and at 10-18 % the flag said
    # settled)
    has_prev = window.previous_start_s >= 0.0
    marks = (np.array([int(round(window.previous_start_s / dt)),
                       int(round(window.previous_end_s / dt))], dtype=np.int64)
             if has_prev else np.empty(0, dtype=np.int64))
    mark_x = np.full(marks.size, np.nan)
    out = _run(system, n_steps, dt, win_start, decim, n_full, opts.energy,
               opts.max_events_per_step, marks, mark_x)
    status, fail_step, trace_a, full_a, phase_time, work, stats, _, _ = out
    raise_status(status, fail_step, dt, op)
    trace = Trace.from_array(trace_a)
    v = (trace.x_m[-1] - stats[0]) / window.window_s
    v_prev = float((mark_x[1] - mark_x[0]) / window.window_s) if has_prev else float("nan")
    return SchemeOutput(
        velocity_m_s=float(v), previous_velocity_m_s=v_prev, phase_time=phase_time,
        y_tip_min_m=float(stats[1]), y_tip_max_m=float(stats[2]), trace=trace,
        window=Trace.from_array(full_a),
        # + 0.0: no load's work is 0 J, not the -0 J a zero load times a travel gives
        energy=(_energy_balance(params, opts, work, stats,
                                -op.load_N * float(trace.x_m[-1] - stats[0]) + 0.0)
                if opts.energy else None),
        steps=n_steps, events=int(stats[3]), nfev=n_steps + int(stats[6]),
    )


def _energy_balance(params: MotorParams, opts: SimulationOptions, work: np.ndarray,
                    stats: np.ndarray, load_J: float) -> EnergyBalance:
    """The window's work integrals; ``load_J`` is the load's work on the slider over the
    window, ``-load_N`` times its displacement."""
    w_in, w_damp, w_ns, w_ts, w_tx, w_gl = (float(w) for w in work)
    # the kernel integrates the guide and the load together (both are in the model's ff_m
    # rows); the load's work is exact from the displacement, the rest is the guide's
    w_g = w_gl - load_J
    delta = float(stats[5] - stats[4])
    # tangential work split: the reaction -phi_B(l) F_T at the tip is the consistent part
    g_t = gamma_T(params, opts.coupling)
    consistent_ts = w_ts * (-params.phi_Bl / g_t)
    non_conservative = w_ts - consistent_ts
    dissipation = -(consistent_ts + w_tx)
    residual = delta - (w_in - w_damp + w_ts + w_tx + w_g + load_J)
    return EnergyBalance(
        input_J=w_in,
        damping_J=w_damp,
        normal_on_stator_J=w_ns,
        tangential_on_stator_J=w_ts,
        tangential_on_slider_J=w_tx,
        guide_J=w_g,
        load_J=load_J,
        interface_dissipation_J=dissipation,
        non_conservative_J=non_conservative,
        delta_energy_J=delta,
        residual_J=residual,
    )
