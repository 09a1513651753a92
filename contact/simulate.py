"""Typed wrapper around the switch-model kernel: one call, one frozen result.

>>> from rom import table2
>>> from contact.simulate import simulate
>>> r = simulate(table2(), voltage_V=200, preload_N=14)      # doctest: +SKIP
>>> r.steady.velocity_m_s, r.steady.motion                    # doctest: +SKIP
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from contact import kernels
from contact.friction import dynamic_friction
from contact.model import COUPLINGS, HybridSystem, OperatingPoint, build_system, gamma_T
from contact.results import EnergyBalance, SteadyState, Trace, classify_motion
from contact.state import ERR_CHATTER, OK
from rom.params import MotorParams

MIN_PERIODS = 10
"""Shortest run accepted, in drive periods."""

PRE_PASS_PERIODS = 60
"""Drive periods simulated to find the steady normal amplitude A_N of Eq. 11."""

PHASE_THRESHOLD = 1e-4
"""A phase counts in the motion class when it fills more than this fraction of the window."""


@dataclass(frozen=True)
class SimulationOptions:
    """Numerical and modelling options of a run.

    Attributes
    ----------
    duration_s : float
        Simulated time (s); at least :data:`MIN_PERIODS` drive periods.
    dt_s : float
        Fixed time step (s), in (0, 1/(20 f)].
    ultrasonic_friction : bool
        Apply Eq. 11 (amplitude-dependent mu_d); otherwise slip uses ``mu_d``.
    coupling : {"paper", "consistent"}
        Generalized force of F_T on B2 (see :mod:`contact.model`).
    stick_band_m_s : float
        The paper's epsilon (m/s); see :func:`contact.model.build_system`.
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
    """

    duration_s: float = 0.05
    dt_s: float = 1e-7
    ultrasonic_friction: bool = True
    coupling: str = "paper"
    stick_band_m_s: float = 1e-10
    steady_periods: int = 20
    full_periods: int = 5
    max_trace_points: int = 20000
    energy: bool = False
    max_events_per_step: int = 64

    def __post_init__(self) -> None:
        for name in ("duration_s", "dt_s"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        if self.coupling not in COUPLINGS:
            raise ValueError(f"coupling must be one of {COUPLINGS}, got {self.coupling!r}")
        for name in ("steady_periods", "full_periods", "max_trace_points", "max_events_per_step"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)!r}")


@dataclass(frozen=True)
class SimulationResult:
    """Everything one run produced.

    Attributes
    ----------
    params : MotorParams
    op : OperatingPoint
    options : SimulationOptions
    mu_d_eff : float
        Dynamic friction coefficient used in slip (-).
    normal_amplitude_m : float
        A_N of Eq. 11 (m), from the pre-pass.
    trace : Trace
        Decimated trace of the whole run.
    window : Trace
        Every step of the last ``full_periods`` periods.
    steady : SteadyState
    energy : EnergyBalance or None
    steps : int
        Fixed steps taken (the pre-pass excluded).
    events : int
        Mode switches located.
    wall_time_s : float
        Wall time of the integration alone (s), pre-pass included.
    """

    params: MotorParams
    op: OperatingPoint
    options: SimulationOptions
    mu_d_eff: float
    normal_amplitude_m: float
    trace: Trace
    window: Trace
    steady: SteadyState
    energy: EnergyBalance | None
    steps: int
    events: int
    wall_time_s: float


def check_time_step(op: OperatingPoint, options: SimulationOptions) -> int:
    """Validate ``dt`` and the duration for a drive frequency; return the number of steps."""
    dt_max = op.period_s / 20.0
    if options.dt_s > dt_max * (1 + 1e-12):
        raise ValueError(
            f"dt_s must be in (0, 1/(20 f)] = (0, {dt_max:.4g}] s at f = {op.frequency_Hz:g} Hz, "
            f"got {options.dt_s!r}"
        )
    min_duration = MIN_PERIODS * op.period_s
    if options.duration_s < min_duration * (1 - 1e-12):
        raise ValueError(
            f"duration_s must be >= {MIN_PERIODS} drive periods = {min_duration:.4g} s, "
            f"got {options.duration_s!r}"
        )
    return int(round(options.duration_s / options.dt_s))


def _check_spectrum(system: HybridSystem, dt_s: float) -> None:
    rho = max(float(np.max(np.abs(np.linalg.eigvals(a)))) for a in system.A)
    if rho * dt_s > 1.0:  # the Taylor flow of partial steps is exact to roundoff below 1
        raise ValueError(
            f"dt_s = {dt_s:g} s is too large for the fastest mode of this parameter set "
            f"({rho / (2 * math.pi):.4g} Hz): use dt_s <= {1.0 / rho:.3g} s"
        )


def _run(system: HybridSystem, n_steps: int, dt: float, win_start: int, decim: int,
         n_full: int, energy: bool, max_events: int):
    phi, phi_half = system.propagators(dt)
    return kernels.integrate_switch_model(
        system.z0, system.mode0, n_steps, dt, phi, phi_half, system.A, system.ev_h,
        system.ev_dh, system.ev_type, system.fn_m, system.ft_m, system.ff_m, system.funcs,
        system.scalars, win_start, decim, n_full, energy, max_events,
    )


def _raise_status(status: int, fail_step: int, dt: float, op: OperatingPoint) -> None:
    if status == ERR_CHATTER:
        raise RuntimeError(
            f"contact chattering: more switches than allowed within one step at "
            f"t = {fail_step * dt:.6g} s (V0 = {op.voltage_V:g} V, F_P = {op.preload_N:g} N); "
            f"reduce dt_s or raise max_events_per_step"
        )
    if status != OK:  # pragma: no cover - no other codes exist
        raise RuntimeError(f"switch-model kernel failed with status {status}")


def normal_amplitude(
    params: MotorParams, op: OperatingPoint, dt_s: float = 1e-7, periods: int = PRE_PASS_PERIODS
) -> float:
    """Steady normal vibration amplitude A_N at the tip (m): half peak-to-peak of y_tip.

    Runs Eqs. 4 + 7 (with separation) for ``periods`` drive periods; the last third is the
    window. The tangential state does not enter, so friction settings do not matter.
    """
    system = build_system(params, op, params.mu_d)
    n_steps = int(round(periods * op.period_s / dt_s))
    win_start = n_steps - max(1, n_steps // 3)
    out = _run(system, n_steps, dt_s, win_start, n_steps, 1, False, 64)
    _raise_status(out[0], out[1], dt_s, op)
    stats = out[6]
    return 0.5 * (stats[2] - stats[1])


def simulate(
    params: MotorParams,
    voltage_V: float,
    preload_N: float,
    frequency_Hz: float = 40e3,
    options: SimulationOptions | None = None,
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
    frequency_Hz : float
        Drive frequency (Hz), > 0.
    options : SimulationOptions, optional
        Numerical options; keyword overrides (``dt_s=...``) are applied on top.

    Returns
    -------
    SimulationResult

    Raises
    ------
    ValueError
        On invalid input, naming the parameter and its allowed range.
    RuntimeError
        When the contact chatters beyond ``max_events_per_step`` within a step.
    """
    op = OperatingPoint(float(voltage_V), float(preload_N), float(frequency_Hz))
    opts = options or SimulationOptions()
    if option_overrides:
        opts = SimulationOptions(**{**opts.__dict__, **option_overrides})
    n_steps = check_time_step(op, opts)
    dt = opts.dt_s
    steps_per_period = op.period_s / dt
    n_periods = n_steps / steps_per_period
    win_periods = min(opts.steady_periods, max(1, int(n_periods // 2)))
    win_steps = int(round(win_periods * steps_per_period))
    win_start = n_steps - win_steps
    n_full = min(n_steps, int(round(min(opts.full_periods, win_periods) * steps_per_period)))
    decim = max(1, int(math.ceil(n_steps / opts.max_trace_points)))

    t0 = time.perf_counter()
    if opts.ultrasonic_friction:
        a_n = normal_amplitude(params, op, dt)
        mu_d_eff = dynamic_friction(params, a_n)
    else:
        a_n = float("nan")
        mu_d_eff = params.mu_d
    system = build_system(params, op, mu_d_eff, opts.coupling, opts.stick_band_m_s)
    _check_spectrum(system, dt)
    out = _run(system, n_steps, dt, win_start, decim, n_full, opts.energy,
               opts.max_events_per_step)
    wall = time.perf_counter() - t0
    status, fail_step, trace_a, full_a, phase_time, work, stats, _, _ = out
    _raise_status(status, fail_step, dt, op)
    if not opts.ultrasonic_friction:
        a_n = 0.5 * (stats[2] - stats[1])

    trace = Trace.from_array(trace_a)
    window = Trace.from_array(full_a)
    steady = _steady_state(trace, phase_time, stats, win_steps * dt, op)
    energy = _energy_balance(params, opts, work, stats) if opts.energy else None
    return SimulationResult(
        params=params, op=op, options=opts, mu_d_eff=mu_d_eff, normal_amplitude_m=a_n,
        trace=trace, window=window, steady=steady, energy=energy, steps=n_steps,
        events=int(stats[3]), wall_time_s=wall,
    )


def _steady_state(trace: Trace, phase_time: np.ndarray, stats: np.ndarray, window_s: float,
                  op: OperatingPoint) -> SteadyState:
    t_end = trace.t_s[-1]
    x_end = trace.x_m[-1]
    v = (x_end - stats[0]) / window_s
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0.0, 0.0, 0.0])
    stick, slip_pos, slip_neg, sep = (float(f) for f in frac)
    driving, braking = (slip_pos, slip_neg) if v >= 0 else (slip_neg, slip_pos)
    # an earlier window, at least a fifth of the run before the last one, tells whether the
    # slider is still accelerating
    t_prev_end = t_end - max(window_s, 0.2 * t_end)
    if t_prev_end - window_s >= trace.t_s[0]:
        x_a, x_b = np.interp([t_prev_end - window_s, t_prev_end], trace.t_s, trace.x_m)
        v_prev = float((x_b - x_a) / window_s)
    else:
        v_prev = float("nan")
    settled = bool(abs(v - v_prev) <= 0.01 * abs(v) + 1e-6) if math.isfinite(v_prev) else False
    return SteadyState(
        velocity_m_s=float(v),
        stick_fraction=stick,
        slip_fraction=slip_pos + slip_neg,
        separation_fraction=sep,
        driving_slip_fraction=driving,
        braking_slip_fraction=braking,
        motion=classify_motion(stick, slip_pos + slip_neg, sep, PHASE_THRESHOLD),
        y_tip_min_m=float(stats[1]),
        y_tip_max_m=float(stats[2]),
        window_s=float(window_s),
        previous_velocity_m_s=float(v_prev),
        settled=settled,
    )


def _energy_balance(params: MotorParams, opts: SimulationOptions, work: np.ndarray,
                    stats: np.ndarray) -> EnergyBalance:
    w_in, w_damp, w_ns, w_ts, w_tx, w_g = (float(w) for w in work)
    delta = float(stats[5] - stats[4])
    # tangential work split: the reaction -phi_B(l) F_T at the tip is the consistent part
    g_t = gamma_T(params, opts.coupling)
    consistent_ts = w_ts * (-params.phi_Bl / g_t)
    non_conservative = w_ts - consistent_ts
    dissipation = -(consistent_ts + w_tx)
    residual = delta - (w_in - w_damp + w_ts + w_tx + w_g)
    return EnergyBalance(
        input_J=w_in,
        damping_J=w_damp,
        normal_on_stator_J=w_ns,
        tangential_on_stator_J=w_ts,
        tangential_on_slider_J=w_tx,
        guide_J=w_g,
        interface_dissipation_J=dissipation,
        non_conservative_J=non_conservative,
        delta_energy_J=delta,
        residual_J=residual,
    )
