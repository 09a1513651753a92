"""Steady states of the motor by averaging: fast periodic orbit at fixed v, slow equation in v.

The slider (0.2 kg) is slow against the 40 kHz vibration, so the steady state separates into

* the **fast problem** (:mod:`contact.steady.periodic_orbit`): at a fixed slider velocity v the
  stator-tip contact settles on a periodic orbit; its exact period averages F_T(v), F_N(v);
* the **slow equation**: the mean slider acceleration vanishes,
  ``G(v) = F_T(v) - sign(v) mu_sd (F_N + M g) - F_load = 0``. Every root is a branch; a root
  is stable where ``G`` falls through zero; ``v = 0`` is a steady state (the dead zone, slider
  held by the guide) when ``G(0-) >= 0 >= G(0+)``. At the fast level a start from rest follows
  ``M dv/dt = G(v)`` from 0 to the first stable root on the side ``G(0)`` points to; the
  exact level decides it on the full model (:mod:`contact.steady.from_rest`): ``G`` can be
  many-valued, and which sheet a start from rest takes is decided below the slider's
  velocity ripple, where the averaging does not hold.

``F_T(v) - sign(v) mu_sd (F_N + M g)`` at fixed v is the motor's speed-thrust characteristic
(:mod:`contact.characteristic`). Averaging is exact as ``M -> infinity``; at finite M the
error scales as 1/M (see ``docs/steady.md``).

The load ``load_N`` is a constant force on the slider in -x: it opposes positive velocity.

>>> from rom import table2
>>> from contact.steady.engine import steady_state
>>> r = steady_state(table2(), 200, 14)          # doctest: +SKIP
>>> r.velocity_m_s, r.branches                    # doctest: +SKIP
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from contact.deferred_signals import deferred_signals
from contact.drive import default_drive_Hz
from contact.model import OperatingPoint, check_rest, resolve_coupling
from contact.results import SchemeOutput
from contact.steady.branches import SteadyBranch, branches_at_load
from contact.steady.exact import REST_MAX_K, REST_MEAN_BLOCKS, REST_MEAN_PERIODS, exact_branches
from contact.steady.runaway import runaway_error
from contact.steady.slow import slow_problem
from rom.params import MotorParams, require_params


@dataclass(frozen=True)
class SteadyResult:
    """All steady states at one operating point (:func:`steady_state`).

    Attributes
    ----------
    op : OperatingPoint
        Voltage (V), preload (N), frequency (Hz) and load (N).
    branches : tuple of SteadyBranch
        Every steady state found, by increasing velocity (unstable ones included).
    velocity_m_s : float
        Velocity of the branch a start from rest reaches (m/s); NaN when a start from rest
        reaches none: the slider runs away (the load, or a load pushing it forward, exceeds
        the thrust the motor can hold against it, :func:`contact.steady.runaway.holding_range_N`).
    mu_d_eff : float
        Dynamic friction coefficient used in slip (-).
    accuracy : str
    orbits : int
        Fast-problem orbits solved.
    periods : int
        Drive periods simulated in total (Newton's finite-difference runs included).
    newton_iterations : int
    wall_time_s : float
    rest_periods : int
        Drive periods of the full model run from rest to decide the branch a start from rest reaches
        (included in ``periods``): the run out of the slider's ripple zone
        (:mod:`contact.steady.from_rest`), or the transient from rest of
        :data:`contact.steady.exact.REST_TRANSIENT_PERIODS` where that run leaves the decision to
        it, or the hold check of a slider the averages hold. 0 at the fast level, which decides on
        the averages.
    """

    op: OperatingPoint
    branches: tuple[SteadyBranch, ...]
    velocity_m_s: float
    mu_d_eff: float
    accuracy: str
    orbits: int
    periods: int
    newton_iterations: int
    wall_time_s: float
    rest_periods: int = 0

    @property
    def from_rest(self) -> SteadyBranch | None:
        """The branch a start from rest reaches; None when the slider runs away."""
        return next((b for b in self.branches if b.from_rest), None)


def steady_state(params: MotorParams, voltage_V: float, preload_N: float, *,
                 frequency_Hz: float | None = None, load_N: float = 0.0,
                 coupling: str = "auto", ultrasonic_friction: bool = True,
                 accuracy: str = "exact", energy: bool = True,
                 rest: str = "probe") -> SteadyResult:
    """Every steady state of the motor at one operating point, by averaging and shooting.

    Parameters
    ----------
    params : MotorParams
        Any parameter set.
    voltage_V : float
        Drive amplitude V0 (V), >= 0.
    preload_N : float
        Preload F_P (N), >= 0.
    frequency_Hz : float, optional
        Drive frequency (Hz); 40 kHz (the transient default) when None.
    load_N : float
        External load (N), a constant force opposing positive slider velocity.
    coupling : {"auto", "paper", "consistent"}
        See :func:`contact.model.build_system`; ``"auto"`` (default, as the CLI's):
        :func:`contact.model.default_coupling`.
    ultrasonic_friction : bool
        Apply Eq. 11 (same A_N as the transient schemes).
    accuracy : {"exact", "fast"}
        ``"exact"`` (the default, as the CLI's): every branch shot on the full model
        (finite M) and the branch reached from rest decided on it; ``"fast"``: the
        M -> infinity averaging (error ~ 1/M, see ``docs/steady.md``), which can answer
        for a steady state the motor does not reach from rest (at the fast level
        ``characteristic`` of the FE set at 400 V / 14 N gives a 0.476 N stall force, where
        the motor's is 1.014 N).
    energy : bool
        Compute each branch's powers (input, damping, interface, guide), one run per branch
        at :data:`contact.steady.periodic_orbit.ENERGY_STEPS_PER_PERIOD` steps per period; without
        it they are NaN (velocities, periods, stability, phase fractions and mean forces are
        the same).
    rest : {"probe", "transient"}
        How the exact level decides the branch a start from rest reaches: ``"probe"`` (the default)
        by the full model's run out of the slider's ripple zone and the averaged sheet it is on,
        with the transient where that run cannot decide (:mod:`contact.steady.from_rest`; several
        times faster, a heuristic with known failures, docs/steady.md); ``"transient"`` by a
        transient from rest of :data:`contact.steady.exact.REST_TRANSIENT_PERIODS` periods at every
        point (the reference the probe is measured against). Ignored at the fast level.

    Returns
    -------
    SteadyResult

    Notes
    -----
    A Ctrl-C during the point is delivered when it is done (milliseconds to about a second):
    one signal hold around its ~20 compiled calls instead of one each
    (:mod:`contact.deferred_signals`).
    """
    with deferred_signals():
        return _steady_state(params, voltage_V, preload_N, frequency_Hz=frequency_Hz,
                             load_N=load_N, coupling=coupling,
                             ultrasonic_friction=ultrasonic_friction, accuracy=accuracy,
                             energy=energy, rest=rest)


def _steady_state(params: MotorParams, voltage_V: float, preload_N: float, *,
                  frequency_Hz: float | None = None, load_N: float = 0.0,
                  coupling: str = "auto", ultrasonic_friction: bool = True,
                  accuracy: str = "exact", energy: bool = True,
                  rest: str = "probe") -> SteadyResult:
    """:func:`steady_state` without the signal hold."""
    t0 = time.perf_counter()
    require_params(params)
    if not isinstance(energy, (bool, np.bool_)):  # "no" is a true string
        raise TypeError(f"energy must be True or False, got {energy!r}")
    check_rest(rest)
    coupling = resolve_coupling(params, coupling)
    op = OperatingPoint(voltage_V, preload_N,
                        default_drive_Hz(params, frequency_Hz, 4), load_N)
    sp = slow_problem(params, op, coupling=coupling, ultrasonic_friction=ultrasonic_friction,
                      accuracy=accuracy)
    # the exact level replaces the averaged branches' powers by the full model's
    branches, v_rest = branches_at_load(sp, op.load_N, energy=energy and accuracy == "fast")
    periods, newton, rest_periods = sp.periods, sp.newton_iterations, 0
    if accuracy == "exact":
        branches, v_rest, more_periods, more_newton, rest_periods = exact_branches(
            sp, branches, coupling, energy, rest)
        periods += more_periods
        newton += more_newton
    return SteadyResult(op=op, branches=branches, velocity_m_s=v_rest, mu_d_eff=sp.mu_d_eff,
                        accuracy=accuracy, orbits=len(sp.cache), periods=periods,
                        newton_iterations=newton, wall_time_s=time.perf_counter() - t0,
                        rest_periods=rest_periods)


IRREGULAR_RTOL = 0.01
"""Standard error (relative) up to which an irregular creep's mean counts as settled, the
transient's own 1 % rule (:func:`contact.results.steady_metrics`)."""


class IrregularMotionWarning(UserWarning):
    """The motion from rest repeats with no period up to :data:`contact.steady.exact.REST_MAX_K`:
    its velocity is a long-time mean with a standard error, not an orbit's."""


def warn_irregular(b: SteadyBranch, where: str) -> None:
    """Say that the branch from rest ``b`` (``k = 0``) is a long-time mean, and how good."""
    if math.isfinite(b.velocity_error_m_s) and b.velocity_error_m_s > 0:
        how = (f"a mean over {REST_MEAN_BLOCKS * REST_MEAN_PERIODS} periods, standard error "
               f"{b.velocity_error_m_s:.2g} m/s "
               f"({b.velocity_error_m_s / max(abs(b.velocity_m_s), 1e-300):.1%})")
    else:
        how = f"a mean over {REST_MEAN_PERIODS} periods whose windows agree to 1e-6"
    warnings.warn(f"{where} the motion from rest repeats with no period up to {REST_MAX_K} "
                  f"drive periods: its velocity {b.velocity_m_s:.4g} m/s is {how}; a long "
                  "transient is the reference there", IrregularMotionWarning, stacklevel=3)


class CoexistingBranchesWarning(UserWarning):
    """The operating point has stable steady states besides the one a start from rest
    reaches: a slider started on one of them (or driven there by a change of voltage or load)
    stays there, so the motor's speed depends on its history (hysteresis)."""


def warn_coexisting(branches, v_rest: float, op: OperatingPoint) -> None:
    """Name the stable branches a start from rest does not reach (a one-point answer, such
    as ``lusm simulate --steady``, describes the one it does and lists the others under
    ``branches``, which a reader of its velocity alone may miss)."""
    others = [b for b in branches if b.stable and not b.from_rest]
    if not others or not math.isfinite(v_rest):
        return
    what = "; ".join(f"{b.velocity_m_s:.4g} m/s ({b.motion}"
                     + (f", period {b.k}" if b.k > 1 else "") + ")" for b in others)
    load = f" under {op.load_N:g} N" if op.load_N else ""
    many = "other stable steady states" if len(others) > 1 else "another stable steady state"
    warnings.warn(f"at {op.voltage_V:g} V / {op.preload_N:g} N{load} the motor has {many}"
                  f" besides the {v_rest:.4g} m/s a start from rest reaches: {what}; a slider "
                  # the result lists them too (SimulationResult.branches, lusm simulate
                  # --steady's branches)
                  "brought there stays (every one is listed under branches)",
                  CoexistingBranchesWarning, stacklevel=3)


def solve_steady(params: MotorParams, op: OperatingPoint, opts, window, mu_d_eff: float):
    """Adapter for the scheme table of :func:`contact.simulate.simulate` (``method="steady"``).

    Returns a :class:`contact.results.SchemeOutput` for the branch reached from rest at the
    ``"exact"`` level (``op.load_N`` applied; ``opts.coupling`` honoured), with every branch
    found at the point (``branches``, which a single-point answer would hide). Traces, tip
    extrema and the energy balance are not produced (None / NaN); ``steps`` and ``nfev`` count the
    drive periods simulated times the steps per period; ``events`` is None: the engine
    shoots orbits and counts no mode switches (0 would say that a stick-slip orbit never
    switches).
    """
    sp = slow_problem(params, op, coupling=opts.coupling, mu_d_eff=mu_d_eff, accuracy="exact")
    branches, v_rest = branches_at_load(sp, op.load_N, energy=False)
    branches, v_rest, periods, _, _ = exact_branches(sp, branches, opts.coupling, energy=True,
                                             rest=opts.rest)
    if math.isnan(v_rest):
        raise runaway_error(sp, op.load_N)
    rest = [b for b in branches if b.from_rest]
    frac = rest[0].phase_fraction if rest else (math.nan,) * 4
    steps = (sp.periods + periods) * sp.fs.steps_per_period
    warn_coexisting(branches, float(v_rest), op)
    previous = float(v_rest)
    if rest and rest[0].irregular:
        load = f" under {op.load_N:g} N" if op.load_N else ""
        warn_irregular(rest[0], f"at {op.voltage_V:g} V / {op.preload_N:g} N{load}")
        if not rest[0].velocity_error_m_s <= IRREGULAR_RTOL * abs(rest[0].velocity_m_s):
            previous = math.nan  # not settled: the mean is not known to 1 %
    return SchemeOutput(
        velocity_m_s=float(v_rest), previous_velocity_m_s=previous,
        phase_time=np.asarray(frac, dtype=float) * window.window_s, y_tip_min_m=math.nan,
        y_tip_max_m=math.nan, trace=None, window=None, energy=None, steps=int(steps),
        events=None, nfev=int(steps), branches=tuple(branches))
