"""The event-located scheme: exact per-mode propagators with located switches
(:mod:`contact.transient.event_kernel`), and the kernel call the A_N pre-pass shares."""

from __future__ import annotations

import math

import numpy as np

from bounds import ParameterError
from contact.deferred_signals import call_held
from contact.errors import ChatteringError
from contact.model import HybridSystem, OperatingPoint, build_system, gamma_T
from contact.options import SimulationOptions
from contact.results import EnergyBalance, SchemeOutput, Trace
from contact.state import ERR_CHATTER, OK
from contact.transient import event_kernel
from contact.transient.window import MAX_STORED_STEPS, RunWindow, work_factor
from rom.params import MotorParams


def check_spectrum(system: HybridSystem, dt_s: float) -> None:
    """Refuse a step ``dt_s`` (s) above the inverse spectral radius of the system's modes.

    Raises
    ------
    ValueError
        Naming ``dt_s`` and the largest step the fastest mode allows.
    """
    rho = max(float(np.max(np.abs(np.linalg.eigvals(a)))) for a in system.A)
    if rho * dt_s > 1.0:  # the Taylor flow of partial steps is exact to roundoff below 1
        raise ParameterError(
            "dt_s", dt_s, 0.0, 1.0 / rho, "s", low_open=True,
            reason=f"the fastest mode of this parameter set, {rho / (2 * math.pi):.4g} Hz",
            message=f"dt_s = {dt_s:g} s is too large for the fastest mode of this parameter "
            f"set ({rho / (2 * math.pi):.4g} Hz): use dt_s <= {1.0 / rho:.3g} s")


def run_kernel(system: HybridSystem, n_steps: int, dt: float, win_start: int, decim: int,
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


def full_and_decimation(op: OperatingPoint, opts: SimulationOptions,
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
    n_full, decim = full_and_decimation(op, opts, window)
    system = build_system(params, op, mu_d_eff, opts.coupling, opts.stick_band_m_s)
    check_spectrum(system, dt)
    # an earlier window, at least a fifth of the run before the last one, tells whether the
    # slider is still accelerating: its ends are marked in the kernel (interpolating the
    # decimated trace puts them 0.5-2 % off at creep speeds, enough to call a creep whose
    # windows differ by 10-18 % settled)
    has_prev = window.previous_start_s >= 0.0
    marks = (np.array([int(round(window.previous_start_s / dt)),
                       int(round(window.previous_end_s / dt))], dtype=np.int64)
             if has_prev else np.empty(0, dtype=np.int64))
    mark_x = np.full(marks.size, np.nan)
    out = run_kernel(system, n_steps, dt, win_start, decim, n_full, opts.energy,
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
    w_in, w_damp, w_ns, w_ts, w_tx, w_gl = (float(w) for w in work[:6])
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
