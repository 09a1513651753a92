"""The loads the motor holds at one operating point, and the slider that runs away beyond them."""

from __future__ import annotations

import math

import numpy as np

from bounds import Words
from contact.errors import RunawayError
from contact.model import OperatingPoint
from contact.steady.periodic_orbit import orbit_phases
from contact.steady.slow import SlowProblem, slow_problem
from rom.params import GRAVITY_M_S2, MotorParams


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
                      previous_velocity_m_s: float = math.nan) -> Words | None:
    """Why a run under ``op.load_N`` has no steady state: the load lies beyond
    :func:`holding_range_N` (None when it does not, or when there is no load): a transient
    at 1000 N ends at -250 m/s, pure slip, which is no velocity of the motor.

    Where the tip sticks at the scan's ends (no drive, or a weak one) static friction holds
    a load that never breaks the tip free, but a run applies its load at once, and the
    step's overshoot can break it free below that: a transient whose slider speeds up the
    load's way (``velocity_m_s`` its last window's mean, ``previous_velocity_m_s`` an
    earlier one's) under a load beyond the tip's and the guide's sliding friction runs away
    too (0 V / 14 N on Table 2's set from about 5.75 N, where static friction holds 7.638 N;
    its last window can still hold stick phases, so the motion class does not decide)."""
    if not op.load_N:
        return None
    sp = slow_problem(params, op, coupling=coupling, ultrasonic_friction=ultrasonic_friction,
                      mu_d_eff=mu_d_eff)
    low, high = holding_range_N(sp)
    what = "at the tip's full slip"
    if not (math.isfinite(low) and math.isfinite(high)):
        # no full slip at either end (an undriven or weakly driven tip sticks): the most the
        # tip's stiction and the guide can hold, static friction on both (0 V / 20 N under
        # 50 N runs away)
        slide, hold = stiction_hold_N(params, op.preload_N, mu_d_eff)
        low, high, what = -hold, hold, "the tip's and the guide's static friction"
        speeding_away = (velocity_m_s * op.load_N < 0.0
                         and abs(velocity_m_s) > abs(previous_velocity_m_s))
        if speeding_away and slide < abs(op.load_N) <= hold:
            way = "backward" if op.load_N > 0 else "forward"
            return Words(f"{{load_N}} is beyond the loads the motor holds once its tip "
                         f"slips at {op.voltage_V:g} V / {op.preload_N:g} N ({-slide:.4g} to "
                         f"{slide:.4g} N, the tip's and the guide's sliding friction; their "
                         f"static friction holds up to {hold:.4g} N of a load applied gently, "
                         f"but this run applies it at once and the tip broke free): the slider "
                         f"runs away {way} and has no steady state", load_N=f"{op.load_N:g} N")
    if low <= op.load_N <= high:
        return None
    way = "backward" if op.load_N > high else "forward"
    return Words(f"{{load_N}} is beyond the loads the motor holds at "
                 f"{op.voltage_V:g} V / {op.preload_N:g} N ({low:.4g} to {high:.4g} N, {what}): "
                 f"the slider runs away {way} and has no steady state", load_N=f"{op.load_N:g} N")


def runaway_error(sp: SlowProblem, load_N: float) -> RunawayError:
    """The error saying that the slider runs away from rest under ``load_N`` and why."""
    low, high = holding_range_N(sp)
    op = sp.op
    way = "backward" if load_N > 0 else "forward"
    held = (f" (the motor holds loads from {low:.4g} to {high:.4g} N at the tip's full slip)"
            if math.isfinite(low) and math.isfinite(high) else "")
    reason = f"the slider runs away {way}{held}"
    return RunawayError(Words(f"{{load_N}}: no steady state from rest at {op.voltage_V:g} V / "
                              f"{op.preload_N:g} N, {reason}", load_N=f"{load_N:g} N"), reason)
