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
import time
import warnings
from dataclasses import dataclass, replace

from contact.friction import dynamic_friction
from contact.model import OperatingPoint, resolve_coupling
from contact.options import DEFAULT_DT_S, SimulationOptions, options_or_default
from contact.results import EnergyBalance, SchemeOutput, SteadyState, Trace, steady_metrics
from contact.transient.event import check_stored_steps, full_and_decimation
from contact.transient.pre_pass import normal_amplitude
from contact.transient.window import MIN_PERIODS, RunWindow, period_step_s, run_window
from rom.params import MotorParams, require_params

METHODS = {
    "event": "contact.transient.event:solve_event",
    "reference": "contact.transient.reference:solve_reference",
    "literal": "contact.transient.literal:solve_literal",
    "steady": "contact.steady.engine:solve_steady",
}
"""Schemes of :func:`simulate`: name -> ``module:function(params, op, options, window,
mu_d_eff) -> SchemeOutput``, imported on first use (the reference pulls in SciPy)."""


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Everything one run produced, whatever the scheme.

    Attributes
    ----------
    params : MotorParams
        The motor's parameter set.
    op : OperatingPoint
        Drive and load.
    options : SimulationOptions
        The solver settings of the run.
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
        Metrics over the steady-state window.
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
    branches : tuple of contact.steady.branches.SteadyBranch or None
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
    _check_method(method, load_N)
    from contact.drive import default_drive_Hz

    op = OperatingPoint(voltage_V, preload_N, default_drive_Hz(params, frequency_Hz), load_N)
    opts = _resolved_options(op, method, options, option_overrides)
    if opts.coupling == "auto":  # here: CouplingSwitchWarning names simulate's caller
        opts = replace(opts, coupling=resolve_coupling(params, "auto"))
    window, dt_a_n = _scheme_window(op, opts, method)
    module, _, name = METHODS[method].partition(":")
    scheme = getattr(importlib.import_module(module), name)

    t0 = time.perf_counter()
    # here, not in a helper: UnsettledAmplitudeWarning names simulate's caller
    if opts.ultrasonic_friction:
        a_n = normal_amplitude(params, op, dt_a_n)
        mu_d_eff = dynamic_friction(params, a_n)
    else:
        a_n, mu_d_eff = float("nan"), params.mu_d
    out: SchemeOutput = scheme(params, op, opts, window, mu_d_eff)
    wall = time.perf_counter() - t0
    if not opts.ultrasonic_friction and math.isfinite(out.y_tip_max_m):
        a_n = 0.5 * (out.y_tip_max_m - out.y_tip_min_m)
    steady = steady_metrics(out.velocity_m_s, out.previous_velocity_m_s, out.phase_time,
                            out.y_tip_min_m, out.y_tip_max_m, window.window_s)
    if op.load_N and method != "steady" and not steady.settled:
        _warn_if_runaway(params, op, opts, mu_d_eff, steady)
    return SimulationResult(
        params=params, op=op, options=opts, method=method, mu_d_eff=mu_d_eff,
        normal_amplitude_m=a_n, trace=out.trace, window=out.window, steady=steady,
        energy=out.energy, steps=out.steps, events=out.events, nfev=out.nfev,
        wall_time_s=wall, branches=out.branches,
    )


def _check_method(method: str, load_N: float) -> None:
    """Refuse a scheme that is not one of :data:`METHODS`, or a load it does not model."""
    if not isinstance(method, str) or method not in METHODS:  # ["event"]: "unhashable"
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if load_N and method in ("reference", "literal"):
        raise ValueError(f"load_N is modelled by the event and steady schemes only, got "
                         f"load_N={load_N!r} with method={method!r}")


def _resolved_options(op: OperatingPoint, method: str, options: SimulationOptions | None,
                      overrides: dict) -> SimulationOptions:
    """The run's options: ``options`` (or the defaults) with the keyword overrides and the
    step resolved for the drive frequency, so that the result's options say what ran
    (:func:`simulate` resolves ``"auto"`` coupling for the set)."""
    opts = options_or_default(options)
    if overrides:
        opts = SimulationOptions(**{**opts.__dict__, **overrides})
    if method != "event" and opts.energy:  # the override wins, and its type is checked
        # the other schemes compute no energy balance (steady: SteadyResult's powers)
        raise ValueError(f"energy=True is computed by method='event' only, got "
                         f"method={method!r}")
    if opts.dt_s is None:
        opts = replace(opts, dt_s=period_step_s(op.period_s, DEFAULT_DT_S))
    return opts


def _scheme_window(op: OperatingPoint, opts: SimulationOptions,
                   method: str) -> tuple[RunWindow, float]:
    """The run's window and the step (s) of Eq. 11's pre-pass; the scheme's own work bounds
    are checked here, before the pre-pass starts.

    The steady engine takes its own step and length: ``duration_s`` and ``dt_s`` are not
    used (checked against the frequency, the defaults would refuse a drive below 200 Hz or
    above 500 kHz); its window only carries the phase fractions, and the pre-pass
    (separating points) takes 250 steps per period (1e-7 s at 40 kHz, the transients'
    default).
    """
    if method == "steady":
        window = run_window(op, MIN_PERIODS * op.period_s, op.period_s / 20.0,
                            opts.steady_periods)
        return window, op.period_s / 250.0
    window = run_window(op, opts.duration_s, opts.dt_s, opts.steady_periods)
    if method == "reference":
        from contact.transient.reference import check_reference_work

        check_reference_work(op, window.end_s)
    if method == "event":  # what it keeps
        n_full, decim = full_and_decimation(op, opts, window)
        check_stored_steps(n_full, math.ceil(window.n_steps / decim))
    return window, opts.dt_s


def _warn_if_runaway(params: MotorParams, op: OperatingPoint, opts: SimulationOptions,
                     mu_d_eff: float, steady: SteadyState) -> None:
    """Warn where an unsettled transient's load lies beyond what the motor holds
    (:func:`contact.steady.runaway.transient_runaway`): its velocity is where the run
    stopped. The steady scheme refuses such a load instead. The steady engine is imported
    here, for loaded runs that do not settle: ``import contact.simulate`` loads no SciPy
    solver."""
    from contact.steady.runaway import RunawayWarning, transient_runaway

    reason = transient_runaway(params, op, opts.coupling, opts.ultrasonic_friction,
                               mu_d_eff, steady.velocity_m_s,
                               steady.previous_velocity_m_s)
    if reason is not None:  # stacklevel: the caller of simulate
        warnings.warn(reason + "; the velocity is where the run stopped", RunawayWarning,
                      stacklevel=3)
