"""The time grid of a run and where its steady-state windows lie, shared by every scheme."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from bounds import ParameterError
from contact.model import OperatingPoint

MIN_PERIODS = 10
"""Shortest run accepted, in drive periods."""

MIN_STEPS_PER_PERIOD = 20
"""Fewest fixed steps per drive period accepted (:func:`check_time_step`)."""


def period_step_s(period_s: float, nominal_dt_s: float) -> float:
    """The largest step up to ``nominal_dt_s`` (s) that makes the drive period ``period_s``
    (s) a whole number of steps, at least :data:`MIN_STEPS_PER_PERIOD` of them.

    ``nominal_dt_s`` itself where it divides the period (40 kHz at 1e-7 s: 250 steps, bit for
    bit). A step that does not divide the period cuts the averaging windows mid-period, and
    the slider's ripple then biases their means (3e-6 at 35 254 Hz; a held slider read
    +-1e-9 m/s and never "settled"). Rounding up, never down, keeps the step at or below the
    nominal one; the floor of 20 steps keeps a default step inside :func:`check_time_step`'s
    range at drive frequencies above 1/(20 ``nominal_dt_s``) (500 kHz at 1e-7 s), so that
    the default is not refused as if the user had typed it.
    """
    n = max(MIN_STEPS_PER_PERIOD, math.ceil(period_s / nominal_dt_s * (1.0 - 1e-12)))
    if abs(n * nominal_dt_s - period_s) <= 1e-12 * period_s:
        return float(nominal_dt_s)
    return period_s / n


@dataclass(frozen=True)
class RunWindow:
    """Steps of a run and its two measuring windows.

    Attributes
    ----------
    dt_s : float
        Time step (s) of the fixed-step schemes (and the grid every scheme measures on).
    n_steps : int
        Steps of length ``dt_s``; the run ends at ``n_steps * dt_s`` (s).
    window_periods : int
        Length of the steady-state window in drive periods.
    win_start : int
        First step of the steady-state window (the last ``window_periods`` periods).
    """

    dt_s: float
    n_steps: int
    window_periods: int
    win_start: int

    @property
    def end_s(self) -> float:
        """End of the run (s)."""
        return self.n_steps * self.dt_s

    @property
    def window_start_s(self) -> float:
        """Start of the steady-state window (s)."""
        return self.win_start * self.dt_s

    @property
    def window_s(self) -> float:
        """Length of the steady-state window (s)."""
        return (self.n_steps - self.win_start) * self.dt_s

    @property
    def previous_end_s(self) -> float:
        """End of the earlier window, at least a fifth of the run before the end (s)."""
        return self.end_s - max(self.window_s, 0.2 * self.end_s)

    @property
    def previous_start_s(self) -> float:
        """Start of the earlier window (s); negative when the run is too short for one."""
        return self.previous_end_s - self.window_s


def check_time_step(op: OperatingPoint, duration_s: float, dt_s: float) -> int:
    """Validate ``dt_s`` and ``duration_s`` for a drive frequency; return the number of steps."""
    dt_max = op.period_s / MIN_STEPS_PER_PERIOD
    if dt_s > dt_max * (1 + 1e-12):
        raise ParameterError(
            "dt_s", dt_s, 0.0, dt_max, "s", low_open=True,
            reason=f"{MIN_STEPS_PER_PERIOD} steps per period at {op.frequency_Hz:g} Hz",
            message=f"dt_s must be in (0, 1/(20 f)] = (0, {dt_max:.4g}] s at f = "
            f"{op.frequency_Hz:g} Hz, got {dt_s!r}")
    min_duration = MIN_PERIODS * op.period_s
    if duration_s < min_duration * (1 - 1e-12):
        raise ParameterError(
            "duration_s", duration_s, min_duration, None, "s",
            reason=f"{MIN_PERIODS} drive periods",
            message=f"duration_s must be >= {MIN_PERIODS} drive periods = {min_duration:.4g} "
            f"s, got {duration_s!r}")
    steps = duration_s / dt_s
    if not steps <= MAX_RUN_STEPS:
        raise ParameterError(
            "dt_s", dt_s, duration_s / MAX_RUN_STEPS, None, "s",
            reason=f"at most {MAX_RUN_STEPS:.0e} time steps in {duration_s:g} s",
            message=f"duration_s / dt_s = {duration_s!r} s / {dt_s!r} s is {steps:.3g} time "
            "steps, "
            f"above {MAX_RUN_STEPS:.0e}: about five minutes of compiled kernel per 1e9 steps, "
            "during which Ctrl-C waits for the kernel; shorten duration_s or raise dt_s")
    return int(round(steps))


WORK_ENV = "LUSM_MAX_WORK"
"""Environment variable multiplying the work bounds of ``lusm`` (docs/limits.md)."""


def work_factor() -> float:
    """``LUSM_MAX_WORK`` (>= 1; 1 when unset or invalid: the CLI reports invalid values), the
    multiplier of the contact stage's library bounds."""
    try:
        value = float(os.environ.get(WORK_ENV, "") or 1.0)
    except ValueError:
        return 1.0
    return value if math.isfinite(value) and value >= 1.0 else 1.0


MAX_STORED_STEPS = 10_000_000
"""Most steps a run keeps, at full resolution (``full_periods``) or in its decimated trace
(``max_trace_points``), times ``LUSM_MAX_WORK``: about 0.8 GB of columns, held three times
while the results are built (``full_periods=10**9`` over 5 s would run out of memory after
its kernel ran; ``lusm simulate`` keeps at most 2e6)."""

MAX_RUN_STEPS = 1_000_000_000
"""Most time steps of one run. A kernel holds Ctrl-C until it returns
(:mod:`contact.deferred_signals`): ``dt_s=1e-12`` asked for 5e10 steps that nothing could
stop, and ``dt_s=1e-15`` failed allocating its grid."""


def run_window(op: OperatingPoint, duration_s: float, dt_s: float,
               steady_periods: int) -> RunWindow:
    """The grid and windows of a run: the last ``steady_periods`` periods (at most half)."""
    n_steps = check_time_step(op, duration_s, dt_s)
    steps_per_period = op.period_s / dt_s
    win_periods = min(int(steady_periods), max(1, int((n_steps / steps_per_period) // 2)))
    win_steps = int(round(win_periods * steps_per_period))
    return RunWindow(dt_s=float(dt_s), n_steps=n_steps, window_periods=win_periods,
                     win_start=n_steps - win_steps)
