"""The slow equation of one operating point: the thrust ``G(v)`` the motor delivers at a fixed
slider velocity, from the fast periodic orbits of :mod:`contact.steady.periodic_orbit`, and the
budget of the steady engine (tolerances, steps per period, the lowest drive frequency)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from bounds import ParameterError
from contact.drive import free_tip_amplitudes
from contact.friction import dynamic_friction
from contact.model import OperatingPoint, resolve_coupling
from contact.steady.periodic_orbit import (
    AVERAGE_PERIODS,
    SEARCH_PERIODS,
    FastSystem,
    Orbit,
    fast_base_system,
    fast_system,
    find_orbit,
    spectral_radius,
    steps_for,
)
from contact.transient.pre_pass import normal_amplitude
from rom.params import GRAVITY_M_S2, MotorParams, require_params

ACCURACIES = ("fast", "exact")
"""Accuracy levels. ``"fast"``: averaging (M -> infinity), error O(1/M). ``"exact"``: every averaged
branch polished by shooting the full model (finite M) and the start from rest decided on the full
model: its run out of the slider's ripple zone and the averaged sheet it is on
(:mod:`contact.steady.from_rest`), or else a transient of
:data:`contact.steady.exact.REST_TRANSIENT_PERIODS` periods polished by shooting, which also finds
branches the averaging cannot see (multi-period slider-tip orbits at low speed)."""

V_ZERO_M_S = 1e-9
"""Slider speed (m/s) standing in for 0+ / 0- in the fast problem (stick at exactly v = 0 is
degenerate there)."""

SCAN_PER_DECADE = 3
"""Velocities sampled per decade of slider speed to bracket the roots of the slow equation
(10**(1/3) apart)."""

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
        raise ParameterError(
            "frequency_Hz", op.frequency_Hz, low, None, "Hz",
            reason="the steady engine resolves the stator's fastest mode in every period",
            message=f"frequency_Hz = {op.frequency_Hz:g} Hz is too far below the stator's "
            "fastest mode "
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

    ``mu_d_eff`` (-) is the friction in slip, ``params.mu_d`` by default; the count is the one
    :func:`contact.steady.periodic_orbit.fast_system` makes
    (:func:`contact.steady.periodic_orbit.steps_for`), without its propagators.
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


def scan_grid(v_floor: float, v_max: float) -> np.ndarray:
    """Slider velocities (m/s) the slow equation is sampled at on one side: 0+ and
    :data:`SCAN_PER_DECADE` per decade from ``v_floor`` to ``v_max``, both included."""
    n = max(2, 1 + math.ceil(SCAN_PER_DECADE * math.log10(v_max / v_floor) - 1e-9))
    return np.concatenate([[V_ZERO_M_S], np.geomspace(v_floor, v_max, n)])
