"""The slow reference of the steady engine: the event scheme run from rest under the load, and
the shortest run whose velocity is settled."""

from __future__ import annotations

import numpy as np

from contact.drive import default_drive_Hz
from contact.friction import dynamic_friction
from contact.model import OperatingPoint, resolve_coupling
from contact.options import DEFAULT_DT_S, SimulationOptions
from contact.results import PHASE_THRESHOLD, classify_motion
from contact.steady.exact import HELD_M_S
from contact.transient.event import solve_event
from contact.transient.pre_pass import normal_amplitude
from contact.transient.window import period_step_s, run_window
from rom.params import MotorParams


def transient_reference(params: MotorParams, voltage_V: float, preload_N: float, *,
                        load_N: float = 0.0, frequency_Hz: float | None = None,
                        duration_s: float = 0.2, steady_periods: int = 400,
                        coupling: str = "auto",
                        ultrasonic_friction: bool = True,
                        dt_s: float | None = None) -> tuple[float, str]:
    """Mean slider velocity (m/s) and motion class over the last ``steady_periods`` of a
    transient from rest.

    The slow reference of :func:`contact.steady.engine.steady_state`: the event scheme of
    :func:`contact.simulate.simulate` run with the load in the operating point, at the
    step ``dt_s`` (s). By default, :func:`contact.transient.window.period_step_s` of the step of
    :class:`contact.options.SimulationOptions` (1e-7 s): the largest step up to it that
    makes the drive period a whole number of steps (250 at 40 kHz, where it is that step),
    the rule of the CLI's default ``--dt``. A window of whole periods then starts at the
    orbit's own phase. With 283.66 steps per period (35 254 Hz) it cut up to half a step off
    the window, and the slider's ripple biased the mean by 3e-6 (1.6e-5 at a creep under a
    load, found at 44 066 Hz).
    """
    coupling = resolve_coupling(params, coupling)
    op = OperatingPoint(voltage_V, preload_N, default_drive_Hz(params, frequency_Hz), load_N)
    if dt_s is None:
        dt_s = period_step_s(op.period_s, DEFAULT_DT_S)
    step = {"dt_s": float(dt_s)}
    opts = SimulationOptions(duration_s=duration_s, steady_periods=steady_periods,
                             coupling=coupling, ultrasonic_friction=ultrasonic_friction, **step)
    mu = (dynamic_friction(params, normal_amplitude(params, op, opts.dt_s))
          if ultrasonic_friction else params.mu_d)  # as simulate() at this step
    window = run_window(op, opts.duration_s, opts.dt_s, opts.steady_periods)
    out = solve_event(params, op, opts, window, mu)
    frac = out.phase_time / max(float(np.sum(out.phase_time)), 1e-300)
    motion = classify_motion(frac[0], frac[1] + frac[2], frac[3], PHASE_THRESHOLD)
    return float(out.velocity_m_s), motion


def settled_duration(params: MotorParams, voltage_V: float, preload_N: float, *,
                     start_s: float = 0.3, max_s: float = 2.4, rel_tol: float = 1e-6,
                     abs_tol_m_s: float = HELD_M_S, **kwargs) -> tuple[float, bool]:
    """Shortest transient length on a doubling ladder whose velocity is settled.

    Runs :func:`transient_reference` for ``start_s``, ``2 start_s``, ... and returns the first
    length D whose velocity agrees with the run of length 2D to ``rel_tol`` (or ``abs_tol_m_s`` m/s,
    for held points: :data:`contact.steady.exact.HELD_M_S`), with ``True``; ``(start_s, False)``
    when no length up to ``max_s`` / 2 settles (a point still drifting; none on the 9 x 9 map). A
    floor of 1e-9 m/s would let a creep near 1e-5 m/s pass at 1e-4 relative; on the 9 x 9 map no
    length changes with the lower floor. ``kwargs`` go to :func:`transient_reference`. The settled
    reference of the steady engine's benchmarks (``benchmarks/steady_speed.py``).
    """
    d = float(start_s)
    v = transient_reference(params, voltage_V, preload_N, duration_s=d, **kwargs)[0]
    while 2.0 * d <= max_s * (1.0 + 1e-12):
        v2 = transient_reference(params, voltage_V, preload_N, duration_s=2.0 * d, **kwargs)[0]
        if abs(v2 - v) <= max(rel_tol * abs(v2), abs_tol_m_s):
            return d, True
        d, v = 2.0 * d, v2
    return float(start_s), False
