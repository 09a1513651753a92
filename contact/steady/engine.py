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

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from contact.deferred_signals import deferred_signals
from contact.drive import default_drive_Hz, free_tip_amplitudes
from contact.errors import ChatteringError, RunawayError
from contact.friction import dynamic_friction
from contact.model import OperatingPoint, check_rest, resolve_coupling
from contact.options import DEFAULT_DT_S, SimulationOptions
from contact.results import PHASE_THRESHOLD, classify_motion
from contact.steady.from_rest import probe_from_rest
from contact.steady.periodic_orbit import (
    AVERAGE_PERIODS,
    SEARCH_PERIODS,
    FastSystem,
    Orbit,
    fast_base_system,
    fast_system,
    find_orbit,
    orbit_phases,
    orbit_work,
    spectral_radius,
    steps_for,
)
from contact.transient.event import solve_event
from contact.transient.event_kernel import N_WORK
from contact.transient.pre_pass import normal_amplitude
from contact.transient.window import period_step_s, run_window
from rom.params import GRAVITY_M_S2, MotorParams, require_params

ACCURACIES = ("fast", "exact")

REST_MEAN_PERIODS = 400
"""Periods of the full model, after the transient from rest, whose mean velocity stands for a
start from rest that settles on no orbit of period <= :data:`REST_MAX_K`."""

REST_MEAN_BLOCKS = 10
"""Windows of :data:`REST_MEAN_PERIODS` periods whose mean velocities give an irregular
creep's velocity and its standard error (:attr:`SteadyBranch.velocity_error_m_s`): a motion
that repeats with no period up to :data:`REST_MAX_K` and whose windows do not agree. One
window's mean had stood for it, 10 % off a long transient's on a chaotic creep whose
windows scatter by 20 %."""

REST_SETTLED_RTOL = 1e-6
"""Two consecutive :data:`REST_MEAN_PERIODS` windows after the transient from rest whose mean
velocities agree to this (relative) make its mean the answer where shooting confirmed no
orbit."""

HOLD_CHECK_PERIODS = 100
"""Periods of each of the three blocks whose mean velocities decide whether a slider in the
averaged dead zone stays held from rest (:func:`_held_from`)."""

HOLD_CHECK_FACTOR = 1e-5
"""A slider whose mean speed from rest stays below this fraction of the ripple scale is held
(:func:`_held_from`)."""

HOLD_DECAY_EXPONENT = 1.5
"""A slow drift after the transient from rest whose speed falls at least as ``t**-1.5`` dies
out (:func:`_held_from`): its remaining travel is finite; a creep's speed levels off."""

HELD_M_S = 1e-12
"""Full-model orbits whose mean slider speed is at most this (m/s, roundoff of a slider at
rest) hold the slider: they are reported as the dead zone, with velocity 0."""
"""Accuracy levels. ``"fast"``: averaging (M -> infinity), error O(1/M). ``"exact"``: every
averaged branch polished by shooting the full model (finite M) and the start from rest decided
on the full model: its run out of the slider's ripple zone and the averaged sheet it is on
(:mod:`contact.steady.from_rest`), or else a transient of :data:`REST_TRANSIENT_PERIODS` periods
polished by shooting, which also finds branches the averaging cannot see (multi-period
slider-tip orbits at low speed)."""

REST_TRANSIENT_PERIODS = 2000
"""Drive periods of the transient from rest that decides the branch reached (accuracy
"exact") where the run out of the ripple zone cannot (:mod:`contact.steady.from_rest`; the
transient goes on from that run); shooting then removes what is left of the transient."""

REST_MAX_K = 16
"""Longest period (in drive periods) the exact level looks for at the end of the transient
from rest before shooting it. The creep points below the slider's velocity ripple settle on
slider-tip orbits of ten periods on Table 2's set (100 V / 10 N, 200 V / 20 N; the slider
stops and starts inside every period), which the averaging cannot see."""

V_ZERO_M_S = 1e-9
"""Slider speed (m/s) standing in for 0+ / 0- in the fast problem (stick at exactly v = 0 is
degenerate there)."""

SCAN_PER_DECADE = 3
"""Velocities sampled per decade of slider speed to bracket the roots of the slow equation
(the former 16 points over five decades, 10**(1/3) apart)."""

SCAN_FLOOR_FACTOR = 1.0
"""The scan's lowest sampled speed, in units of the slider's velocity-ripple scale
``mu_d_eff F_P / (M omega)`` (:func:`ripple_scale`). Below it the slider's velocity swings by
more than its mean inside one drive period, so the averaging (M -> infinity) no longer
describes the motor, and the tip's fast orbit at fixed v is a slow stick-drag sawtooth with
no short period, whose samples are the scan's most expensive ones and give only finite-time
averages. A root below it is still bracketed (from 0+ to the floor); at the exact level the
full model's orbit from rest decides such a point (the creep points, ``docs/steady.md``)."""

MAX_STEPS_PER_PERIOD = 20_000
"""Steps per drive period above which the steady engine refuses: it resolves the fastest
mode of the contact model in every period, and thousands of periods at a drive far below it
would take minutes (Table 2's set at 14 N: below about 15 Hz; 50 Hz takes 2 s)."""
ORBIT_TOL = 1e-11
"""Scaled periodicity defect at which a fast orbit is accepted (``accuracy="fast"``: the
averaged roots are the answer, to about 1e-10)."""

ROOT_RTOL = 1e-10
"""Relative tolerance of Brent's method on a root of the slow equation (``"fast"``)."""

EXACT_ORBIT_TOL = 1e-8
"""Orbit defect of the slow equation's scan at ``accuracy="exact"``. There the averaged roots
only start the full model's Newton iteration (which converges to 1e-10 by itself) and differ
from its answer by the O(1/M) averaging error (1e-4 to 1e-3 on Table 2's set): G needs the
accuracy of its sign, not of the root."""

EXACT_ROOT_RTOL = 1e-6
"""Relative tolerance of Brent's method at ``accuracy="exact"`` (see :data:`EXACT_ORBIT_TOL`)."""


@dataclass(frozen=True)
class SteadyBranch:
    """One steady state of the motor.

    Attributes
    ----------
    velocity_m_s : float
        Mean slider velocity (m/s); 0 for the dead zone.
    k : int
        Period multiplicity of the orbit the branch's numbers come from (it repeats every k
        drive periods, its least period); 0 when no orbit was found (period <= 4 for the
        averaged fast problem, <= :data:`REST_MAX_K` for the full model's orbit reached from
        rest) and the averages are long-time means. A held slider's (the dead zone's) at
        ``accuracy="exact"``: the least period of the full model's held orbit, shot from the
        held state a start from rest ends in (0 where that shot fails and a mean stands);
        the averaged orbit's at 0+ only for a dead zone beside a motion reached from rest
        with no held orbit shot, and at the fast level.
    stable : bool
        Whether the slow equation is stable there (``dG/dv < 0``; the dead zone is stable).
    motion : str
        Motion class of the tip orbit (:data:`contact.results.MOTION_CLASSES`) or
        ``"dead-zone"`` (slider held).
    mean_FT_N, mean_FN_N : float
        Period averages of the tangential force on the slider and of the normal force (N),
        integrated exactly over the orbit the branch's numbers come from: the averaged
        (fast) problem's at this velocity, or at ``accuracy="exact"`` the full model's
        (:func:`contact.steady.full_orbit.mean_forces`; a long mean with ``k = 0`` over the window
        of its work integrals). On a full-model orbit whose slider never stops the mean
        tangential force is the guide's kinetic friction plus the load; without separation
        the mean normal force is the preload.
    input_power_W : float
        Mean electrical input power (W): ``<V(t) (A_l du_l + A_b dw_b)>``, the motional
        current times the voltage (the force factors are the current factors by reciprocity).
        At ``accuracy="exact"`` the dead zone a start from rest stays in has the powers of
        the full model's held slider, which rocks with its stuck tip against the guide; a
        dead zone coexisting with a motion reached from rest keeps the averaged orbit's at 0+
        (an infinitely heavy slider, no rocking) unless a held orbit of the full model was
        shot there.
    output_power_W : float
        Mechanical output power ``load_N * velocity_m_s`` (W).
    damping_power_W : float
        Mean power dissipated by the modal damping C_l, C_b (W).
    interface_power_W : float
        Mean power lost at the contact interface (W): what leaves the stator through the tip
        minus what reaches the slider; friction ``<F_T v_rel>`` with ``coupling="consistent"``,
        plus the non-conservative work of the printed coupling with ``coupling="paper"``.
    guide_power_W : float
        Mean power dissipated by the guide friction, ``mu_sd (F_N + M g) |v|`` (W).
    from_rest : bool
        Whether a start from rest reaches this branch (averaged slow dynamics with
        ``accuracy="fast"``, a transient polished by shooting with ``"exact"``).
    phase_fraction : tuple of float
        Fractions of the orbit in stick, slip with v_rel > 0, slip with v_rel < 0, separation.
    velocity_error_m_s : float
        Standard error of ``velocity_m_s`` (m/s) where it is a long-time mean of an irregular
        motion (``k = 0``, from the scatter of :data:`REST_MEAN_BLOCKS` window means); 0 for
        an orbit (k >= 1, to the engine's tolerance) and for a mean whose windows agree to
        :data:`REST_SETTLED_RTOL`; NaN where not estimated (the fast level's averages).
    """

    velocity_m_s: float
    k: int
    stable: bool
    motion: str
    mean_FT_N: float
    mean_FN_N: float
    input_power_W: float
    output_power_W: float
    damping_power_W: float
    interface_power_W: float
    guide_power_W: float
    from_rest: bool
    phase_fraction: tuple[float, float, float, float] = (math.nan,) * 4
    velocity_error_m_s: float = 0.0

    @property
    def held(self) -> bool:
        """Whether the slider is held: the dead zone, velocity 0."""
        return self.motion == "dead-zone"

    @property
    def tip_motion(self) -> str:
        """Motion class of the orbit's phase fractions alone
        (:data:`contact.results.MOTION_CLASSES`), the vocabulary of transients, of
        ``lusm map``'s points and of ``lusm simulate``: equal to :attr:`motion` except for
        the dead zone, whose held slider's tip sticks to it (``"pure-stick"``; ``"separated"``
        with no preload and no drive). A map's branches had said ``"dead-zone"`` where its
        point said ``"pure-stick"`` for the same state."""
        f = self.phase_fraction
        return classify_motion(f[0], f[1] + f[2], f[3], PHASE_THRESHOLD)

    @property
    def irregular(self) -> bool:
        """A moving motion that repeats with no short period (``k = 0``, not the dead zone):
        its velocity is a long-time mean (:attr:`velocity_error_m_s`), not an orbit's."""
        return self.k == 0 and self.motion != "dead-zone"

    @property
    def efficiency(self) -> float:
        """Output over input power (-), :func:`motor_efficiency` (NaN where the motor does
        not work as a motor; it came out at -0.54 under a load pushing the slider)."""
        return float(motor_efficiency(self.input_power_W, self.output_power_W))


def motor_efficiency(input_power_W, output_power_W):
    """Output over input power (-), element-wise, where the motor works as a motor
    (electrical power in, mechanical power out); NaN elsewhere: a load pushing the slider
    along, or driving it backward, puts mechanical power in too, and a ratio of the two is no
    efficiency. The rule of :class:`SteadyBranch` and of the speed-thrust characteristic."""
    p_in = np.asarray(input_power_W, dtype=float)
    p_out = np.asarray(output_power_W, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((p_in > 0) & (p_out >= 0), p_out / p_in, np.nan)


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
        the thrust the motor can hold against it, :func:`holding_range_N`).
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
        Drive periods of the full model run from rest to decide the branch a start from rest
        reaches (included in ``periods``): the run out of the slider's ripple zone
        (:mod:`contact.steady.from_rest`), or the transient from rest of
        :data:`REST_TRANSIENT_PERIODS` where that run leaves the decision to it, or the hold
        check of a slider the averages hold. 0 at the fast level, which decides on the
        averages.
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


@dataclass
class SlowProblem:
    """The slow equation of one operating point with a cache of fast orbits (mutable helper).

    ``thrust(v)`` is ``F_T(v) - sign(v) mu_sd (F_N + M g)`` (N), the thrust the motor
    delivers against a load at slider velocity v. The scan runs from ``v_floor_m_s`` to
    ``v_max_m_s`` (m/s, :func:`scan_grid`); ``search_periods`` and ``average_periods`` are
    the budget of each orbit (:func:`contact.steady.periodic_orbit.find_orbit`).
    """

    params: MotorParams
    op: OperatingPoint
    mu_d_eff: float
    fs: FastSystem
    v_max_m_s: float
    v_floor_m_s: float
    cache: dict = field(default_factory=dict)
    periods: int = 0
    newton_iterations: int = 0
    search_periods: int = SEARCH_PERIODS
    average_periods: int = AVERAGE_PERIODS
    orbit_tol: float = ORBIT_TOL
    root_rtol: float = ROOT_RTOL

    def orbit(self, v: float) -> Orbit:
        if v in self.cache:
            return self.cache[v]
        # continuation: start from the cached orbit nearest in velocity on the same side
        near = [w for w in self.cache if w * v > 0]
        budget = {"max_periods": self.search_periods, "average_periods": self.average_periods,
                  "tol": self.orbit_tol}
        if near:
            near.sort(key=lambda w: abs(w - v))
            w = near[0]
            z = self.cache[w].z
            if len(near) > 1:
                # secant predictor along the branch from the two nearest one-period orbits
                # with the same mode at the section (extrapolating or interpolating in v)
                a, b = self.cache[w], self.cache[near[1]]
                if a.k == b.k == 1 and a.mode == b.mode:
                    z = a.z + (a.z - b.z) * ((v - w) / (w - near[1]))
            o = find_orbit(self.fs, v, z, self.cache[w].mode,
                           jacobian=self.cache[w].jacobian, **budget)
        else:
            o = find_orbit(self.fs, v, **budget)
        self.periods += o.periods
        self.newton_iterations += o.newton_iterations
        self.cache[v] = o
        return o

    def guide_N(self, o: Orbit) -> float:
        """Kinetic guide friction magnitude mu_sd (F_N + M g) (N)."""
        p = self.params
        return p.mu_sd * (o.mean_FN_N + p.M_slider * GRAVITY_M_S2)

    def thrust(self, v: float) -> float:
        o = self.orbit(v)
        return o.mean_FT_N - math.copysign(1.0, v) * self.guide_N(o)

    def thrust_at_rest(self) -> tuple[float, float]:
        """``(G(0+), G(0-))`` (N): the thrust as the slider leaves rest forward and backward.

        Both come from the orbit at 0+: the fast problem has no guide (it enters G only), and
        the tip's orbits at +-V_ZERO_M_S differ by a drift of 2e-9 m/s (on the 81 map points
        and the 14 N line the branches are the same to 1e-9 as with an orbit at -V_ZERO_M_S).
        The slider is held without load where ``G(0+) <= 0 <= G(0-)``.
        """
        o = self.orbit(V_ZERO_M_S)
        return o.mean_FT_N - self.guide_N(o), o.mean_FT_N + self.guide_N(o)


def slow_problem(params: MotorParams, op: OperatingPoint, *, coupling: str = "paper",
                 ultrasonic_friction: bool = True, mu_d_eff: float | None = None,
                 accuracy: str = "fast") -> SlowProblem:
    """Set up the slow equation of one operating point (the load is applied by the caller).

    ``mu_d_eff`` (-), when given, replaces Eq. 11's A_N and mu_d. ``accuracy`` sets the
    tolerances of the orbits and roots (:data:`ORBIT_TOL`, :data:`EXACT_ORBIT_TOL`).
    """
    require_params(params)
    if accuracy not in ACCURACIES:
        raise ValueError(f"accuracy must be one of {ACCURACIES}, got {accuracy!r}")
    if not isinstance(ultrasonic_friction, (bool, np.bool_)):  # 'no' is a true string
        raise TypeError(f"ultrasonic_friction must be True or False, got "
                        f"{ultrasonic_friction!r}")
    coupling = resolve_coupling(params, coupling)
    if mu_d_eff is not None:
        mu = float(mu_d_eff)
    elif ultrasonic_friction:
        mu = dynamic_friction(params, normal_amplitude(params, op))  # the transients' A_N
    else:
        mu = params.mu_d
    fs = fast_system(params, op, mu, coupling)
    if fs.steps_per_period > MAX_STEPS_PER_PERIOD:
        # the lowest frequency taken, counted with this point's friction as fs was
        low = lowest_frequency_Hz(params, coupling, mu_d_eff=mu)
        raise ValueError(
            f"frequency_Hz = {op.frequency_Hz:g} Hz is too far below the stator's fastest mode "
            f"for the steady engine: {fs.steps_per_period} steps per drive period, above "
            f"{MAX_STEPS_PER_PERIOD} (it resolves that mode in every period); it takes "
            f"frequency_Hz >= {low:g} Hz here")
    _, b_amp = free_tip_amplitudes(params, op.frequency_Hz, op.voltage_V)
    v_max = max(1.5 * float(b_amp) * op.omega, 1e-6)
    floor = min(max(SCAN_FLOOR_FACTOR * ripple_scale(params, op, mu), 1e-5 * v_max),
                0.1 * v_max)
    tols = ((ORBIT_TOL, ROOT_RTOL) if accuracy == "fast"
            else (EXACT_ORBIT_TOL, EXACT_ROOT_RTOL))
    return SlowProblem(params, op, mu, fs, v_max, floor, orbit_tol=tols[0], root_rtol=tols[1])


def steps_per_period(params: MotorParams, frequency_Hz: float, coupling: str = "paper",
                     mu_d_eff: float | None = None) -> int:
    """Steps per drive period the steady engine takes at ``frequency_Hz`` (Hz): its cost per
    period, and so per point, grows with it (25 at 40 kHz on Table 2's set, 14 923 at 20 Hz,
    where a point takes 1.5 s). A work estimate for callers that bound a study beforehand.

    ``mu_d_eff`` (-) is the friction in slip, ``params.mu_d`` by default; the count is the
    one :func:`fast_system` makes (:func:`contact.steady.periodic_orbit.steps_for`), without its
    propagators.
    """
    op = OperatingPoint(0.0, 0.0, float(frequency_Hz))
    mu = params.mu_d if mu_d_eff is None else float(mu_d_eff)
    return int(steps_for(fast_base_system(params, op, mu, coupling), op.period_s))


LOWEST_FREQUENCY_DIGITS = 4
"""Significant digits of :func:`lowest_frequency_Hz`."""


def lowest_frequency_Hz(params: MotorParams, coupling: str = "paper",
                        mu_d_eff: float | None = None) -> float:
    """The lowest drive frequency (Hz) the steady engine takes: the lowest at which
    :func:`steps_per_period` stays within :data:`MAX_STEPS_PER_PERIOD` (about 14.93 Hz on
    Table 2's set), rounded up to :data:`LOWEST_FREQUENCY_DIGITS` significant digits, so that
    the figure said is one that is taken and the one a unit of its last digit below is not.

    Parameters
    ----------
    params : MotorParams
    coupling : {"paper", "consistent"}
    mu_d_eff : float, optional
        The friction in slip (-), as for :func:`steps_per_period`.

    Returns
    -------
    float
    """
    from decimal import ROUND_CEILING, Decimal

    def taken(f: Decimal) -> bool:
        return steps_per_period(params, float(f), coupling, mu_d_eff) <= MAX_STEPS_PER_PERIOD

    def unit(f: Decimal) -> Decimal:  # one in the last digit kept
        return Decimal(1).scaleb(f.adjusted() - LOWEST_FREQUENCY_DIGITS + 1)

    # the count is ceil(rho T) (steps_for), rho the fastest rate of the modes (1/s), which the
    # drive frequency does not change far below them: the bound is near rho / MAX
    mu = params.mu_d if mu_d_eff is None else float(mu_d_eff)
    base = fast_base_system(params, OperatingPoint(0.0, 0.0, 1.0), mu, coupling)
    guess = Decimal(spectral_radius(base.A) / MAX_STEPS_PER_PERIOD)
    f = guess.quantize(unit(guess), rounding=ROUND_CEILING)
    # the count decides, on the figures said: roundoff in rho and in T may put the bound a
    # unit off the guess
    while not taken(f):
        f += unit(f)
    while True:
        below = f - unit(f)
        if below.adjusted() < f.adjusted():  # 10.00 -> 9.999, not 9.99
            below = f - unit(f) / 10
        if below <= 0 or not taken(below):
            return float(f)
        f = below


def ripple_scale(params: MotorParams, op: OperatingPoint, mu_d_eff: float) -> float:
    """Velocity-ripple scale of the slider (m/s): ``mu_d_eff F_P / (M omega)``.

    The velocity amplitude a tangential force swinging by the tip's sliding friction at the
    preload gives the slider at the drive frequency. At 200 V / 14 N on Table 2's set it is
    8.5e-5 m/s, a third of the peak-to-peak ripple of the full model's orbit there (2.6e-4
    m/s, sampled at every step of the shot orbit): below it the slider's velocity swings by
    several times its mean.
    """
    return mu_d_eff * op.preload_N / (params.M_slider * op.omega)


def holding_range_N(sp: SlowProblem) -> tuple[float, float]:
    """Loads (N) between which the slider cannot run away: the thrust at ``+v_max`` and at
    ``-v_max`` (``v_max`` = 1.5 x the free tip's tangential speed, the scan's end).

    Where the orbit at that end slides one way throughout contact (no stick, no slip the
    other way), the thrust no longer depends on v beyond it: a load above the upper bound
    (below the lower one) leaves ``G < 0`` (``> 0``) for every faster backward (forward)
    velocity, and a slider past the last root on that side accelerates without bound. At
    400 V / 14 N on Table 2's set: about -4.5 N to 4.5 N, the tip's sliding friction plus the
    guide's. A bound whose orbit still sticks (no drive, or too little to make the tip outrun
    the slider) is NaN: there the tip's stiction, which the averaging does not see, decides.
    """
    bounds = []
    for v in (sp.v_max_m_s, -sp.v_max_m_s):
        o = sp.orbit(v)
        phase = orbit_phases(sp.fs, o, sp.average_periods)
        against = phase[1] if v > 0 else phase[2]  # slip the slider's way, or stick
        full_slip = phase[0] + against <= 1e-12 * float(np.sum(phase))
        bounds.append(sp.thrust(v) if full_slip else math.nan)
    return bounds[0], bounds[1]


def stiction_hold_N(params: MotorParams, preload_N: float,
                    mu_d_eff: float) -> tuple[float, float]:
    """Loads (N, magnitudes) a stuck tip holds by friction: ``(sliding, static)``, the tip's
    sliding (``mu_d_eff``) or static (``mu_s``) friction at the preload plus the guide's
    ``mu_sd (F_P + M g)``. Where the tip sticks at the scan's ends (no drive, or a weak one;
    :func:`holding_range_N` NaN) static friction holds a load applied gently, and a slider
    that slips under a load beyond the sliding bound runs away."""
    guide = params.mu_sd * (preload_N + params.M_slider * GRAVITY_M_S2)
    return mu_d_eff * preload_N + guide, params.mu_s * preload_N + guide


class RunawayWarning(UserWarning):
    """A transient under a load beyond what the motor holds: the slider accelerates until
    the run ends, and its velocity is where the run stopped (``simulate`` warns)."""


def transient_runaway(params: MotorParams, op: OperatingPoint, coupling: str,
                      ultrasonic_friction: bool, mu_d_eff: float,
                      velocity_m_s: float = math.nan,
                      previous_velocity_m_s: float = math.nan) -> str | None:
    """Why a run under ``op.load_N`` has no steady state: the load lies beyond
    :func:`holding_range_N` (None when it does not, or when there is no load). A transient
    at 1000 N had reported -250 m/s, pure slip, as its velocity.

    Where the tip sticks at the scan's ends (no drive, or a weak one) static friction holds
    a load that never breaks the tip free, but a run applies its load at once, and the
    step's overshoot can break it free below that: a transient whose slider speeds up the
    load's way (``velocity_m_s`` its last window's mean, ``previous_velocity_m_s`` an
    earlier one's) under a load beyond the tip's and the guide's sliding friction runs away
    too (0 V / 14 N on Table 2's set from about 5.75 N, where static friction holds 7.638 N:
    it had said only "not settled"; its last window can still hold stick phases, so the
    motion class does not decide)."""
    if not op.load_N:
        return None
    sp = slow_problem(params, op, coupling=coupling, ultrasonic_friction=ultrasonic_friction,
                      mu_d_eff=mu_d_eff)
    low, high = holding_range_N(sp)
    what = "at the tip's full slip"
    if not (math.isfinite(low) and math.isfinite(high)):
        # no full slip at either end (an undriven or weakly driven tip sticks): the most the
        # tip's stiction and the guide can hold, static friction on both (0 V / 20 N under
        # 50 N ran away without a word)
        slide, hold = stiction_hold_N(params, op.preload_N, mu_d_eff)
        low, high, what = -hold, hold, "the tip's and the guide's static friction"
        speeding_away = (velocity_m_s * op.load_N < 0.0
                         and abs(velocity_m_s) > abs(previous_velocity_m_s))
        if speeding_away and slide < abs(op.load_N) <= hold:
            way = "backward" if op.load_N > 0 else "forward"
            return (f"load_N = {op.load_N:g} N is beyond the loads the motor holds once its tip "
                    f"slips at {op.voltage_V:g} V / {op.preload_N:g} N ({-slide:.4g} to "
                    f"{slide:.4g} N, the tip's and the guide's sliding friction; their static "
                    f"friction holds up to {hold:.4g} N of a load applied gently, but this "
                    f"run applies it at once and the tip broke free): the slider runs away "
                    f"{way} and has no steady state")
    if low <= op.load_N <= high:
        return None
    way = "backward" if op.load_N > high else "forward"
    return (f"load_N = {op.load_N:g} N is beyond the loads the motor holds at "
            f"{op.voltage_V:g} V / {op.preload_N:g} N ({low:.4g} to {high:.4g} N, {what}): "
            f"the slider runs away {way} and has no steady state")


def runaway_error(sp: SlowProblem, load_N: float) -> RunawayError:
    """The error saying that the slider runs away from rest under ``load_N`` and why."""
    low, high = holding_range_N(sp)
    op = sp.op
    way = "backward" if load_N > 0 else "forward"
    held = (f" (the motor holds loads from {low:.4g} to {high:.4g} N at the tip's full slip)"
            if math.isfinite(low) and math.isfinite(high) else "")
    reason = f"the slider runs away {way}{held}"
    return RunawayError(f"load_N = {load_N:g} N: no steady state from rest at "
                        f"{op.voltage_V:g} V / {op.preload_N:g} N, {reason}", reason)


def scan_grid(v_floor: float, v_max: float) -> np.ndarray:
    """Slider velocities (m/s) the slow equation is sampled at on one side: 0+ and
    :data:`SCAN_PER_DECADE` per decade from ``v_floor`` to ``v_max``, both included."""
    n = max(2, 1 + math.ceil(SCAN_PER_DECADE * math.log10(v_max / v_floor) - 1e-9))
    return np.concatenate([[V_ZERO_M_S], np.geomspace(v_floor, v_max, n)])


def _branch(sp: SlowProblem, v: float, load: float, stable: bool,
            energy: bool = True) -> SteadyBranch:
    """The averaged branch at the root ``v``; without ``energy`` its powers (which take a
    run at :data:`contact.steady.periodic_orbit.ENERGY_STEPS_PER_PERIOD`) are NaN."""
    o = sp.orbit(v)
    span = max(o.k, 1) if o.k else None
    phase_time = orbit_phases(sp.fs, o, sp.average_periods)
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0, 0, 0])
    motion = classify_motion(frac[0], frac[1] + frac[2], frac[3], PHASE_THRESHOLD)
    duration = total if span is None else span * sp.op.period_s
    work = orbit_work(sp.fs, o, sp.average_periods) if energy else np.full(N_WORK, math.nan)
    w_in, w_damp, _, w_ts, w_tx, _ = (float(w) for w in work)
    return SteadyBranch(
        velocity_m_s=float(v), k=o.k, stable=stable, motion=motion, mean_FT_N=o.mean_FT_N,
        mean_FN_N=o.mean_FN_N, input_power_W=w_in / duration,
        output_power_W=load * float(v) + 0.0, damping_power_W=w_damp / duration,
        interface_power_W=-(w_ts + w_tx) / duration,
        guide_power_W=sp.guide_N(o) * abs(float(v)), from_rest=False,
        phase_fraction=tuple(float(f) for f in frac),
        velocity_error_m_s=0.0 if o.k else math.nan)


def _dead_zone(sp: SlowProblem, load_N: float, energy: bool, from_rest: bool) -> SteadyBranch:
    """The dead zone (slider held, velocity 0) with the averaged orbit at 0+ for its tip."""
    base = _branch(sp, V_ZERO_M_S, load_N, True, energy)
    return dataclasses.replace(base, velocity_m_s=0.0, motion="dead-zone", output_power_W=0.0,
                               guide_power_W=0.0, from_rest=from_rest)


def branches_at_load(sp: SlowProblem, load_N: float, *,
                     energy: bool = True) -> tuple[tuple[SteadyBranch, ...], float]:
    """All steady states of the slow problem under ``load_N`` and the velocity from rest.

    Without ``energy`` the branches' powers are NaN (:func:`_branch`)."""
    found: list[tuple[float, bool]] = []  # (velocity, stable)
    g_pos, g_neg = (g - load_N for g in sp.thrust_at_rest())
    # backward motion needs G(0-) < 0: only then is the negative side searched
    for sign in (1.0, -1.0) if g_neg < 0 else (1.0,):
        vs = sign * scan_grid(sp.v_floor_m_s, sp.v_max_m_s)
        gs = [sp.thrust(v) - load_N for v in vs]
        for i in range(len(vs) - 1):
            if gs[i] * gs[i + 1] < 0:
                root = brentq(lambda v: sp.thrust(v) - load_N, vs[i], vs[i + 1],
                              xtol=1e-12, rtol=sp.root_rtol)
                # stable where M dv/dt = G(v) pushes back towards the root
                falling = (gs[i] > 0) if sign > 0 else (gs[i] < 0)
                found.append((float(root), bool(falling)))
    dead = g_pos <= 0.0 <= g_neg
    if g_pos > 0:
        cands = sorted(v for v, st in found if v > 0 and st)
        v_rest = cands[0] if cands else math.nan
    elif g_neg < 0:
        cands = sorted((v for v, st in found if v < 0 and st), reverse=True)
        v_rest = cands[0] if cands else math.nan
    else:
        v_rest = 0.0
    out = [dataclasses.replace(_branch(sp, v, load_N, st, energy), from_rest=v == v_rest)
           for v, st in found]
    if dead:
        out.append(_dead_zone(sp, load_N, energy, from_rest=v_rest == 0.0))
    out.sort(key=lambda b: b.velocity_m_s)
    return tuple(out), float(v_rest)


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
        for a steady state the motor does not reach from rest. The default was ``"fast"``:
        ``characteristic`` of the FE set at 400 V / 14 N gave a 0.476 N stall force where
        the CLI gave the motor's 1.014 N.
    energy : bool
        Compute each branch's powers (input, damping, interface, guide), one run per branch
        at :data:`contact.steady.periodic_orbit.ENERGY_STEPS_PER_PERIOD` steps per period; without
        it they are NaN (velocities, periods, stability, phase fractions and mean forces are
        the same).
    rest : {"probe", "transient"}
        How the exact level decides the branch a start from rest reaches: ``"probe"`` (the
        default) by the full model's run out of the slider's ripple zone and the averaged
        sheet it is on, with the transient where that run cannot decide
        (:mod:`contact.steady.from_rest`; several times faster, a heuristic with known failures,
        docs/steady.md); ``"transient"`` by a transient from rest of
        :data:`REST_TRANSIENT_PERIODS` periods at every point (the reference the probe is
        measured against). Ignored at the fast level.

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
        branches, v_rest, more_periods, more_newton, rest_periods = _exact(
            sp, branches, coupling, energy, rest)
        periods += more_periods
        newton += more_newton
    return SteadyResult(op=op, branches=branches, velocity_m_s=v_rest, mu_d_eff=sp.mu_d_eff,
                        accuracy=accuracy, orbits=len(sp.cache), periods=periods,
                        newton_iterations=newton, wall_time_s=time.perf_counter() - t0,
                        rest_periods=rest_periods)


def _run_branch(sp: SlowProblem, v: float, k: int, n_periods: int, work: np.ndarray,
                phase_time: np.ndarray, stable: bool, from_rest: bool,
                held: bool, forces: tuple[float, float]) -> SteadyBranch:
    """A branch measured on ``n_periods`` periods of the full model: mean velocity ``v``
    (m/s), work integrals ``work`` (J), phase times (s) and mean forces ``(F_T, F_N)`` (N);
    ``held``: the dead zone, at velocity 0 with no output power (its guide power is the
    slider's rocking with the stuck tip: 3.4e-5 W at 139 V / 14 N, which had been left out
    of the energy balance)."""
    duration = n_periods * sp.op.period_s
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0, 0, 0])
    motion = classify_motion(frac[0], frac[1] + frac[2], frac[3], PHASE_THRESHOLD)
    w_in, w_damp, _, w_ts, w_tx, w_g = (float(w) for w in work)
    load = sp.op.load_N
    v = float(v)
    if held:  # no net travel, but the slider rocks with the stuck tip against the guide
        v, motion = 0.0, "dead-zone"
    output = load * v + 0.0  # + 0.0: 0 W at no load, not -0 W backward
    guide = -(w_g / duration) - load * v if sp.params.mu_sd > 0 else 0.0
    return SteadyBranch(
        velocity_m_s=v, k=k, stable=stable, motion=motion, mean_FT_N=float(forces[0]),
        mean_FN_N=float(forces[1]), input_power_W=w_in / duration, output_power_W=output,
        damping_power_W=w_damp / duration, interface_power_W=-(w_ts + w_tx) / duration,
        guide_power_W=guide, from_rest=from_rest,
        phase_fraction=tuple(float(f) for f in frac))


def _full_branch(sp: SlowProblem, fo, stable: bool, from_rest: bool) -> SteadyBranch:
    """The branch of a shot full-model orbit, with its least period and its own mean forces;
    one that holds the slider (``|v| <= HELD_M_S``: by the guide, or by the tip's stiction)
    is the dead zone."""
    return _run_branch(sp, fo.velocity_m_s, fo.k, fo.k, fo.work, fo.phase_time, stable,
                       from_rest, held=abs(fo.velocity_m_s) <= HELD_M_S,
                       forces=(fo.mean_FT_N, fo.mean_FN_N))


def _mean_branch(sp: SlowProblem, v: float, work: np.ndarray, phase_time: np.ndarray,
                 n_periods: int, error_m_s: float,
                 forces: tuple[float, float]) -> SteadyBranch:
    """The long mean of the full model's transient from rest, where it repeats with no
    period up to :data:`REST_MAX_K` (k = 0; powers NaN without the work integrals, which
    cover ``n_periods``, as the mean forces ``(F_T, F_N)`` (N) do; ``error_m_s`` the mean
    velocity's standard error)."""
    b = _run_branch(sp, v, 0, n_periods, work, phase_time, True, True, held=False,
                    forces=forces)
    return dataclasses.replace(b, velocity_error_m_s=float(error_m_s))


def _powered(sp: SlowProblem, b: SteadyBranch, energy: bool = True) -> SteadyBranch:
    """The averaged branch ``b`` with its input, damping and interface powers (the exact
    level scans without them and needs them only for the branches it keeps averaged)."""
    if not energy or not math.isnan(b.input_power_W):
        return b
    v = V_ZERO_M_S if b.motion == "dead-zone" else b.velocity_m_s
    w = _branch(sp, v, sp.op.load_N, b.stable)
    return dataclasses.replace(b, input_power_W=w.input_power_W,
                               damping_power_W=w.damping_power_W,
                               interface_power_W=w.interface_power_W)


def _held_from(sp: SlowProblem, fsys, z: np.ndarray, mode: int,
               elapsed_periods: int | None = None) -> tuple[bool, np.ndarray, int]:
    """Whether the full model's slider, started from ``(z, mode)``, stays in place, and the
    state ``(z, mode)`` it ends the check in (a held slider's, rocking with its stuck tip).

    Three blocks of :data:`HOLD_CHECK_PERIODS` periods give three mean velocities; their
    Aitken extrapolation (the last one where they are not converging geometrically) must be
    at most :data:`HOLD_CHECK_FACTOR` times the ripple scale (about 1e-9 m/s, the settled
    references' own tolerance for a held point). A held slider rocks with its stuck tip
    while the start-up drift decays geometrically (on Table 2's map to 1e-10 m/s or, at
    50 V / 26 N, by a factor of about 6 per block); a creep under a load keeps its speed
    (1e-4 m/s and more).

    Under a small load the drift can die out algebraically instead, about as 1/t^2 (Table 2
    at 10 V / 6.5 N under -0.2 N: 4.4e-9, 4.0e-9, 3.7e-9 m/s over the blocks after the
    2 000-period transient, a fourth per doubling of a long transient's length), which
    Aitken's extrapolation does not see. Given ``elapsed_periods`` (the periods since rest
    at ``z``, late enough for the decay's own law), the slider is also held where the block
    means fall, one sign, at least as :data:`HOLD_DECAY_EXPONENT` powers of the time: faster
    than 1/t, so that the distance still to go is finite (at most ``v t / (exponent - 1)``)
    and the position converges.
    """
    from contact.steady.full_orbit import run_periods

    v = []
    for _ in range(3):
        z, mode, dist, _, _ = run_periods(fsys, z, mode, HOLD_CHECK_PERIODS)
        v.append(dist / (HOLD_CHECK_PERIODS * sp.op.period_s))
    d1, d2 = v[1] - v[0], v[2] - v[1]
    limit = v[2]
    if d2 != d1 and abs(d2) < abs(d1):  # converging: Aitken's delta-squared
        limit = v[2] - d2 * d2 / (d2 - d1)
    if abs(limit) <= HOLD_CHECK_FACTOR * sp.v_floor_m_s:
        return True, z, mode
    if elapsed_periods is None or not (abs(v[0]) > abs(v[1]) > abs(v[2]) > 0.0) \
            or v[0] * v[2] < 0.0:
        return False, z, mode
    t0, t2 = (elapsed_periods + (i + 0.5) * HOLD_CHECK_PERIODS for i in (0, 2))
    return math.log(v[0] / v[2]) >= HOLD_DECAY_EXPONENT * math.log(t2 / t0), z, mode


def _held_branch(sp: SlowProblem, fsys, z: np.ndarray, mode: int, from_rest: bool,
                 energy: bool = True) -> tuple[SteadyBranch, int, int]:
    """The dead zone measured on the full model at a held state ``(z, mode)``: its one-period
    orbit by shooting (period k = 1), else the mean of :data:`REST_MEAN_PERIODS` periods
    (k = 0). Returns ``(branch, periods, newton)``; without ``energy`` its powers are NaN
    (its period, phases and mean forces are the same).

    Its powers include the slider's rocking with the stuck tip against the guide, which the
    averaged orbit at 0+ (an infinitely heavy slider) does not have: at 200 V / 14 N driven
    at 1 kHz the guide takes 5.0e-4 W of the 1.07e-3 W put in, and the averaged dead zone had
    said 2.4e-5 W at some loads of one characteristic and 1.07e-3 W at the others."""
    from contact.steady.full_orbit import mean_forces, run_periods, shoot

    try:
        h = shoot(fsys, z, mode, 1, energy=energy)
    except ChatteringError:
        h = None
    if h is not None and h.k and abs(h.velocity_m_s) <= HELD_M_S:
        return _full_branch(sp, h, True, from_rest), h.periods, h.newton_iterations
    _, _, _, work, phase = run_periods(fsys, z, mode, REST_MEAN_PERIODS, energy=energy,
                                       window=True)
    if not energy:
        work = np.full(N_WORK, math.nan)
    forces = mean_forces(fsys, z, mode, REST_MEAN_PERIODS)
    periods = 3 * REST_MEAN_PERIODS + (h.periods if h is not None else 0)
    branch = _run_branch(sp, 0.0, 0, REST_MEAN_PERIODS, work, phase, True, from_rest,
                         held=True, forces=forces)
    return branch, periods, h.newton_iterations if h is not None else 0


def _shoot_averaged(fsys, o: Orbit, energy: bool):
    """The full model shot from the averaged orbit ``o`` (its state with the slider moving
    at ``o``'s velocity, over ``o``'s period), or None where the kernel chatters."""
    from contact import state as S
    from contact.steady.full_orbit import shoot

    v = o.velocity_m_s
    z = o.z.copy()
    z[S.DX] = v
    guide = S.FORWARD if v > 0 else S.BACKWARD
    try:
        return shoot(fsys, z, o.mode - o.mode % 3 + guide, max(o.k, 1), energy=energy)
    except ChatteringError:
        return None


def _shoot_probe(fsys, probe, energy: bool):
    """The full model's orbit at the root the run from rest found on its sheet
    (:func:`contact.steady.from_rest.probe_from_rest`), or None where there is none or the shot
    does not confirm it: no convergence, an unstable orbit, or a mean velocity more than
    5 % from the averaged root (another orbit). Returns ``(orbit, periods, newton)``."""
    o = probe.orbit
    fo = None if o is None else _shoot_averaged(fsys, o, energy)
    if fo is None:
        return None, 0, 0
    v = o.velocity_m_s
    # no multiplier when the shot converged before forming a Jacobian: the sheet's root is
    # stable (the slow flow stops there), and so is the orbit
    stable = not (fo.multiplier >= 1.0)
    ok = fo.k and stable and abs(fo.velocity_m_s - v) <= 0.05 * abs(v)
    return (fo if ok else None), fo.periods, fo.newton_iterations


def _transient_from_rest(sp: SlowProblem, fsys, z, mode, done: int, energy: bool):
    """The transient from rest (``done`` of its :data:`REST_TRANSIENT_PERIODS` periods already
    run, ending at ``(z, mode)``) and the orbit it approaches by shooting.

    Returns ``(z_end, mode_end, v_rest, orbit, periods, newton)``: the state at the end of
    the transient, the velocity (m/s) of the shot orbit where shooting confirms the
    transient's recent mean to 5 %, else that mean, with the orbit or None, and the work."""
    from contact.steady.full_orbit import run_periods, shoot

    periods = newton = 0
    z_end, m_end, _, _, _ = run_periods(fsys, z, mode, REST_TRANSIENT_PERIODS - done)
    periods += REST_TRANSIENT_PERIODS - done
    # the period the transient repeats with: the smallest k <= REST_MAX_K whose defect
    # |y_(j+k) - y_j| is within tenfold of the smallest (multiples of the period repeat too)
    ys, zj, mj = [z_end[[0, 1, 2, 3, 5]]], z_end, m_end
    for _ in range(REST_MAX_K):
        zj, mj, _, _, _ = run_periods(fsys, zj, mj, 1)
        ys.append(zj[[0, 1, 2, 3, 5]])
    periods += REST_MAX_K
    ys_arr = np.array(ys) / np.array([1.0, sp.op.omega, 1.0, sp.op.omega, sp.op.omega])
    scale = np.max(np.abs(ys_arr), axis=0) + 1e-30
    diffs = np.array([np.abs(ys_arr[k] - ys_arr[0]) for k in range(1, REST_MAX_K + 1)])
    defects = np.max(diffs / scale, axis=1)
    # a state repeating to 1e-9 of the orbit's size repeats (a held slider's state does with
    # every k: its coordinates at rest carry only roundoff, which the tenfold rule would match)
    repeats = np.max(diffs, axis=1) <= 1e-9 * scale.max()
    k_best = 1 + int(np.argmax((defects <= 10.0 * defects.min()) | repeats))
    _, _, dist, _, _ = run_periods(fsys, z_end, m_end, 4 * k_best)
    periods += 4 * k_best
    v_transient = dist / (4 * k_best * sp.op.period_s)
    v_rest, fo = v_transient, None
    try:
        cand = shoot(fsys, z_end, m_end, k_best, energy=energy)
        periods += cand.periods
        newton += cand.newton_iterations
        # accept the polished orbit only if the transient was heading for it
        if cand.k and abs(cand.velocity_m_s - v_transient) <= 0.05 * abs(v_transient) + 1e-9:
            v_rest, fo = cand.velocity_m_s, cand
    except ChatteringError:
        pass
    return z_end, m_end, v_rest, fo, periods, newton


def _exact(sp: SlowProblem, branches, coupling: str, energy: bool = True,
           rest: str = "probe"):
    """Polish the averaged branches on the full model and decide the start from rest."""
    from contact.steady.full_orbit import full_system, mean_forces, run_periods, shoot

    fsys = full_system(sp.params, sp.op, sp.mu_d_eff, coupling)
    periods = newton = 0
    # the dead zone is the only steady state of the slow equation: a start from rest stays
    # held if the full model says so. The averages can hide a creep: under a load the
    # guide's hold can give way for part of every period, and the slider then walks
    # backward below its velocity ripple, where the averaging does not hold.
    released = False  # the full model's slider left the averaged dead zone from rest
    if len(branches) == 1 and branches[0].motion == "dead-zone":
        periods += 3 * HOLD_CHECK_PERIODS
        held_now, z_h, m_h = _held_from(sp, fsys, fsys.system.z0, fsys.system.mode0)
        if held_now:
            # the full model's held slider, whatever energy= says: its period, phases and
            # mean forces are those of every held slider the exact level reports
            measured, more, more_newton = _held_branch(sp, fsys, z_h, m_h, True, energy)
            return (measured,), 0.0, periods + more, more_newton, periods
        released = True
    out: list[SteadyBranch] = []
    shot_held: list[SteadyBranch] = []  # dead zones that are full-model orbits
    for b in branches:
        if b.motion == "dead-zone":
            if not released:  # else not a steady state of the full model
                out.append(dataclasses.replace(_powered(sp, b, energy), from_rest=False))
            continue
        fo = _shoot_averaged(fsys, sp.orbit(b.velocity_m_s), energy)
        if fo is not None:
            periods += fo.periods
            newton += fo.newton_iterations
        if fo is not None and fo.k:
            # no multiplier when the shot converged before forming a Jacobian: the averaged
            # stability stands
            stable = bool(fo.multiplier < 1.0) if math.isfinite(fo.multiplier) else b.stable
            full = _full_branch(sp, fo, stable, False)
            out.append(full)
            if full.motion == "dead-zone":  # the shot converged to a held slider
                shot_held.append(full)
        else:
            out.append(dataclasses.replace(_powered(sp, b, energy), from_rest=False))
    # the start from rest: the full model out of the ripple zone and the averaged sheet it
    # is on (contact.steady.from_rest), else a transient from rest and shooting for the orbit it
    # approaches. Not the scan's own first root: the full model from rest can take another
    # sheet of the slow equation (a tuned 60 kHz stator at 140 V / 14 N: stick-slip at
    # 6.23e-3 m/s from rest, where the scan's only branch, pure slip at 1.36e-2 m/s, had been
    # reported as reached from rest without a transient)
    if rest == "probe":
        probe = probe_from_rest(sp, fsys)
        periods += probe.periods
        newton += probe.newton_iterations
        fo, more, more_newton = _shoot_probe(fsys, probe, energy)
        periods += more
        newton += more_newton
        z0, m0, done = probe.z, probe.mode, probe.full_periods
    else:  # rest == "transient": the transient from rest decides at every point
        fo, z0, m0, done = None, fsys.system.z0, fsys.system.mode0, 0
    if fo is not None:
        v_rest, z_end, m_end = fo.velocity_m_s, z0, m0
        rest_periods = done
    else:
        z_end, m_end, v_rest, fo, more, more_newton = _transient_from_rest(
            sp, fsys, z0, m0, done, energy)
        periods += more
        newton += more_newton
        rest_periods = REST_TRANSIENT_PERIODS
    held = abs(v_rest) <= HELD_M_S
    match = [i for i, b in enumerate(out)
             if abs(b.velocity_m_s - v_rest) <= 1e-6 * abs(v_rest) + 1e-12
             or (held and b.motion == "dead-zone")]
    from_mean = False
    if fo is None and not held:
        # the transient settled on no orbit of k <= REST_MAX_K periods that shooting could
        # confirm: a quasi-periodic or irregular motion, or a fast slider that 2 000 periods
        # have not settled. Two more windows tell which: where their mean velocities agree
        # (REST_SETTLED_RTOL), or below the ripple scale (where the averaging does not hold),
        # the transient's mean is the answer, as a k = 0 branch; otherwise the averaged
        # choice stands. With no averaged choice (no root a start from rest stops at) the
        # slider runs away.
        avg = [i for i, b in enumerate(branches) if b.from_rest]
        if not avg:
            v_rest = math.nan
        else:
            window_s = REST_MEAN_PERIODS * sp.op.period_s
            # the velocities always at the engine's own step, the work integrals on a run of
            # their own: with energy=True the mean of a chaotic creep had come from a run at
            # the energy step, another trajectory, and moved by 4 % with the flag
            z_a, m_a, dist_a, _, _ = run_periods(fsys, z_end, m_end, REST_MEAN_PERIODS)
            z_b, m_b, dist, _, phase = run_periods(fsys, z_a, m_a, REST_MEAN_PERIODS,
                                                   window=True)
            periods += 2 * REST_MEAN_PERIODS
            means = [dist_a / window_s, dist / window_s]
            v_a, v_mean = means
            settled = abs(v_mean - v_a) <= REST_SETTLED_RTOL * abs(v_mean)
            # below the ripple scale the averaging does not hold: the full model's mean
            # stands even unsettled (an irregular creep)
            creep = abs(branches[avg[0]].velocity_m_s) < sp.v_floor_m_s
            error = 0.0
            if not settled and creep:
                # an irregular creep: the mean of more windows, with its standard error
                for _ in range(REST_MEAN_BLOCKS - 2):
                    z_b, m_b, dist, _, ph = run_periods(fsys, z_b, m_b, REST_MEAN_PERIODS,
                                                        window=True)
                    means.append(dist / window_s)
                    phase = phase + ph
                periods += (REST_MEAN_BLOCKS - 2) * REST_MEAN_PERIODS
                v_mean = float(np.mean(means))
                error = float(np.std(means, ddof=1) / math.sqrt(len(means)))
            if energy:
                work = run_periods(fsys, z_a, m_a, REST_MEAN_PERIODS, energy=True)[3]
                periods += REST_MEAN_PERIODS
            else:
                work = np.full(N_WORK, math.nan)
            if settled or creep:
                v_rest = v_mean
                if abs(v_rest) <= 1e-3 * sp.v_floor_m_s:
                    # a slow drift, not yet a creep: held if it dies out (the dead zone)
                    periods += 3 * HOLD_CHECK_PERIODS
                    held_now, z_h, m_h = _held_from(sp, fsys, z_end, m_end,
                                                    REST_TRANSIENT_PERIODS)
                    if held_now:
                        v_rest, held, z_end, m_end = 0.0, True, z_h, m_h
                if not held:
                    match, from_mean = [], True
                    # the mean forces over the window of the work integrals
                    forces = mean_forces(fsys, z_a, m_a, REST_MEAN_PERIODS)
                    periods += 2 * REST_MEAN_PERIODS
                    out.append(_mean_branch(sp, v_rest, work, phase, REST_MEAN_PERIODS,
                                            error, forces))
            else:
                match = avg
                v_rest = out[avg[0]].velocity_m_s
    if match:
        out[match[0]] = dataclasses.replace(out[match[0]], from_rest=True)
    elif fo is not None:
        # a transient from rest settled on it: stable unless its multiplier says otherwise
        # (none when the shot from the transient's end converged at once)
        stable = bool(fo.multiplier < 1.0) if math.isfinite(fo.multiplier) else True
        out.append(_full_branch(sp, fo, stable, True))
    if (not held and math.isfinite(v_rest) and abs(v_rest) < sp.v_floor_m_s
            and not any(b.motion == "dead-zone" for b in out)):
        # a creep below the slider's velocity ripple: a held orbit (the slider rocking with
        # no net travel) can coexist with it where the averaged G(0+) > 0 and the start from
        # rest creeps, so neither search sees it (252 V / 25.64 N / 40 414 Hz: a 15-period
        # creep from rest beside a held orbit with Floquet multiplier 0.75). One period shot
        # from the transient's end finds it; the hold check confirms it.
        try:
            h = shoot(fsys, z_end, m_end, 1, energy=energy)
        except ChatteringError:
            h = None
        if h is not None:
            periods += h.periods
            newton += h.newton_iterations
            if h.k == 1 and abs(h.velocity_m_s) <= HELD_M_S and h.multiplier < 1.0:
                periods += 3 * HOLD_CHECK_PERIODS
                if _held_from(sp, fsys, h.z, h.mode)[0]:
                    shot_held.append(_full_branch(sp, h, True, False))
                    out.append(shot_held[-1])
    if fo is not None or from_mean:
        # averaged roots below the ripple scale that no full-model orbit confirms are not
        # steady states of the finite-mass motor (the averaging does not hold there); the
        # full model's orbit from rest stands for them
        out = [b for b in out if b.from_rest or b.k > 0 or b.motion == "dead-zone"
               or abs(b.velocity_m_s) >= sp.v_floor_m_s]
    # one dead zone. The one a start from rest stays in is the full model's held slider
    # (its least period, phases, mean forces and powers, energy= or not): the averaged orbit
    # at 0+ has no slider rocking against the guide (_held_branch), and the averaged dead
    # zone and the held orbits shot from other branches are its twins. Its period had
    # depended on the path that found it: k = 3, 0, 0, 1 under loads 0, 1, 2, 3 N at
    # 200 V / 14 N driven at 1 kHz, one held orbit of one period.
    if held:
        if fo is not None:  # a held orbit, shot
            measured = _full_branch(sp, fo, True, True)
        else:
            measured, more, more_newton = _held_branch(sp, fsys, z_end, m_end, True, energy)
            periods += more
            newton += more_newton
        out = [b for b in out if b.motion != "dead-zone"] + [measured]
    else:
        # beside a motion from rest: a held orbit of the full model where one was shot,
        # else the averaged dead zone (the fast orbit at 0+, an infinitely heavy slider)
        dead = [b for b in out if b.motion == "dead-zone"]
        if len(dead) > 1:
            keep = next((b for b in dead if any(b is s for s in shot_held)), dead[0])
            out = [b for b in out if b.motion != "dead-zone"] + [keep]
    out.sort(key=lambda b: b.velocity_m_s)
    return tuple(out), (0.0 if held else v_rest), periods, newton, rest_periods


def transient_reference(params: MotorParams, voltage_V: float, preload_N: float, *,
                        load_N: float = 0.0, frequency_Hz: float | None = None,
                        duration_s: float = 0.2, steady_periods: int = 400,
                        coupling: str = "auto",
                        ultrasonic_friction: bool = True,
                        dt_s: float | None = None) -> tuple[float, str]:
    """Mean slider velocity (m/s) and motion class over the last ``steady_periods`` of a
    transient from rest.

    The slow reference of :func:`steady_state`: the event scheme of
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
    length D whose velocity agrees with the run of length 2D to ``rel_tol`` (or
    ``abs_tol_m_s`` m/s, for held points: :data:`HELD_M_S`), with ``True``; ``(start_s,
    False)`` when no length up to ``max_s`` / 2 settles (a point still drifting; none on the
    9 x 9 map). The floor was 1e-9 m/s, which let a creep near 1e-5 m/s pass at 1e-4
    relative; on the 9 x 9 map no length changed with the lower floor.
    ``kwargs`` go to :func:`transient_reference`. The settled reference of the steady
    engine's benchmarks (``benchmarks/steady_speed.py``).
    """
    d = float(start_s)
    v = transient_reference(params, voltage_V, preload_N, duration_s=d, **kwargs)[0]
    while 2.0 * d <= max_s * (1.0 + 1e-12):
        v2 = transient_reference(params, voltage_V, preload_N, duration_s=2.0 * d, **kwargs)[0]
        if abs(v2 - v) <= max(rel_tol * abs(v2), abs_tol_m_s):
            return d, True
        d, v = 2.0 * d, v2
    return float(start_s), False


IRREGULAR_RTOL = 0.01
"""Standard error (relative) up to which an irregular creep's mean counts as settled, the
transient's own 1 % rule (:func:`contact.results.steady_metrics`)."""


class IrregularMotionWarning(UserWarning):
    """The motion from rest repeats with no period up to :data:`REST_MAX_K`: its velocity is a
    long-time mean with a standard error, not an orbit's."""


def warn_irregular(b: SteadyBranch, where: str) -> None:
    """Say that the branch from rest ``b`` (``k = 0``) is a long-time mean, and how good."""
    import warnings

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
    import warnings

    others = [b for b in branches if b.stable and not b.from_rest]
    if not others or not math.isfinite(v_rest):
        return
    what = "; ".join(f"{b.velocity_m_s:.4g} m/s ({b.motion}"
                     + (f", period {b.k}" if b.k > 1 else "") + ")" for b in others)
    load = f" under {op.load_N:g} N" if op.load_N else ""
    many = "other stable steady states" if len(others) > 1 else "another stable steady state"
    warnings.warn(f"at {op.voltage_V:g} V / {op.preload_N:g} N{load} the motor has {many}"
                  f" besides the {v_rest:.4g} m/s a start from rest reaches: {what}; a slider "
                  # the result lists them now (SimulationResult.branches, lusm simulate
                  # --steady's branches); the warning had been their only mention
                  "brought there stays (every one is listed under branches)",
                  CoexistingBranchesWarning, stacklevel=3)


def solve_steady(params: MotorParams, op: OperatingPoint, opts, window, mu_d_eff: float):
    """Adapter for the scheme table of :func:`contact.simulate.simulate` (``method="steady"``).

    Returns a :class:`contact.results.SchemeOutput` for the branch reached from rest at the
    ``"exact"`` level (``op.load_N`` applied; ``opts.coupling`` honoured), with every branch
    found at the point (``branches``: a single-point answer had hidden the others but for a
    warning). Traces, tip extrema
    and the energy balance are not produced (None / NaN); ``steps`` and ``nfev`` count the
    drive periods simulated times the steps per period; ``events`` is None: the engine
    shoots orbits and counts no mode switches (it had read 0, as if a stick-slip orbit
    never switched).
    """
    from contact.results import SchemeOutput

    sp = slow_problem(params, op, coupling=opts.coupling, mu_d_eff=mu_d_eff, accuracy="exact")
    branches, v_rest = branches_at_load(sp, op.load_N, energy=False)
    branches, v_rest, periods, _, _ = _exact(sp, branches, opts.coupling, energy=False,
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
