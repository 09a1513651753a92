"""Eq. 11's normal amplitude A_N: in closed form where the tip never separates, else from a
pre-pass of the event kernel from rest."""

from __future__ import annotations

import math
import warnings
from functools import lru_cache

import numpy as np

from bounds import Words
from contact.model import OperatingPoint, build_system, linear_normal_amplitude
from contact.transient.event import raise_status, run_kernel
from rom.params import MotorParams

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
``lusm.limits.MAX_STEPS``); beyond, it takes :data:`PRE_PASS_STEPS_PER_PERIOD`."""

PRE_PASS_STEPS_PER_PERIOD = 250
"""Steps per drive period of a pre-pass too long at the caller's step (the default step's
share at 40 kHz; its A_N error is about 1e-9)."""


class UnsettledAmplitudeWarning(UserWarning):
    """Eq. 11's normal amplitude A_N came from a pre-pass too short for the L1 vibration to
    settle (an almost undamped stator): mu_d,eff carries the start's transient."""


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
    330, and a fixed 60-period pre-pass would put A_N 7 % above the settled amplitude (84 %
    at zeta_L1 = 0.001).
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
            warnings.warn(UnsettledAmplitudeWarning(Words(
                f"Eq. 11's normal amplitude A_N comes from a {periods}-period pre-pass whose "
                f"window starts with {left:.2g} of the L1 start transient left (zeta_L1 = "
                f"{params.zeta_L1:.3g}, too light to settle within {MAX_PRE_PASS_PERIODS} "
                f"periods): A_N and mu_d,eff may be off by about that share; damp L1 more, "
                f"or {{ultrasonic_friction}} for a constant mu_d",
                {"ultrasonic_friction": "set {name} = {value}"}, ultrasonic_friction="False")),
                stacklevel=3)
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
    out = run_kernel(system, n_steps, dt_s, win_start, n_steps, 1, False, 64,
               np.empty(0, dtype=np.int64), np.empty(0))
    raise_status(out[0], out[1], dt_s, op)
    stats = out[6]
    return 0.5 * (stats[2] - stats[1])
