"""Numerical and modelling options of a run, shared by every scheme of
:func:`contact.simulate.simulate`."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError
from contact.model import COUPLING_CHOICES, check_rest

MAX_COUNT_OPTION = 2**31 - 1
"""Largest value of the options counted in periods, points or events (the kernels' int)."""

DEFAULT_DT_S = 1e-7
"""Nominal fixed step (s) of the transients: 250 steps per period at 40 kHz, where Fig. 9's
traces and the paper reproduction run; off 40 kHz rounded to divide the drive period."""



def default_time_step_s(frequency_Hz: float) -> float:
    """The transients' default time step (s) at ``frequency_Hz`` (Hz): the largest step up
    to :data:`DEFAULT_DT_S` that makes the drive period a whole number of steps, at least 20
    (:func:`contact.transient.window.period_step_s`; 1e-7 s itself at 40 kHz)."""
    from contact.transient.window import period_step_s

    return period_step_s(1.0 / float(frequency_Hz), DEFAULT_DT_S)

@dataclass(frozen=True)
class SimulationOptions:
    """Numerical and modelling options of a run.

    Attributes
    ----------
    duration_s : float
        Simulated time (s); at least :data:`contact.transient.window.MIN_PERIODS` drive periods.
    dt_s : float or None
        Fixed time step (s), in (0, 1/(20 f)]. None (the default): :data:`DEFAULT_DT_S` rounded to
        make the drive period a whole number of steps
        (:func:`contact.transient.window.period_step_s`; 1e-7 s itself at 40 kHz), the CLI's
        default. A fixed 1e-7 s cut the averaging windows mid-period off 40 kHz and biased their
        means; :func:`contact.simulate.simulate` stores the step it ran in the result's ``options``.
    ultrasonic_friction : bool
        Apply Eq. 11 (amplitude-dependent mu_d); otherwise slip uses ``mu_d``.
    coupling : {"auto", "paper", "consistent"}
        Generalized force of F_T on B2 (see :mod:`contact.model`); ``"auto"`` (the default, as the
        CLI's): :func:`contact.model.default_coupling`, the paper's for Table 2's own set and the
        consistent one for every other. :func:`contact.simulate.simulate` stores the one it ran in
        the result's ``options``.
    stick_band_m_s : float
        The paper's epsilon (m/s); see :func:`contact.model.build_system`. The literal scheme
        decides stick with it at every step.
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
    rtol : float
        Relative tolerance of the ``reference`` scheme (absolute tolerances are scaled per
        state component).
    rest : {"probe", "transient"}
        How the ``steady`` scheme decides the branch a start from rest reaches
        (:func:`contact.steady.engine.steady_state` ``rest=``); unused by the transient schemes.
    """

    duration_s: float = 0.05
    dt_s: float | None = None
    ultrasonic_friction: bool = True
    coupling: str = "auto"
    stick_band_m_s: float = 1e-10
    steady_periods: int = 20
    full_periods: int = 5
    max_trace_points: int = 20000
    energy: bool = False
    max_events_per_step: int = 64
    rtol: float = 1e-10
    rest: str = "probe"

    def __post_init__(self) -> None:
        for name in ("duration_s", "dt_s"):
            v = getattr(self, name)
            if v is None and name == "dt_s":
                continue  # resolved per drive frequency by simulate()
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v) \
                    or v <= 0:
                raise ParameterError(name, v, 0.0, None, "s", low_open=True,
                                     message=f"{name} must be a finite number > 0 (s), got {v!r}")
            object.__setattr__(self, name, float(v))
        for name in ("ultrasonic_friction", "energy"):  # 'False' is a true string
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False, got {getattr(self, name)!r}")
        check_rest(self.rest)
        if self.coupling not in COUPLING_CHOICES:
            raise ValueError(f"coupling must be one of {COUPLING_CHOICES}, got "
                             f"{self.coupling!r}")
        for name in ("steady_periods", "full_periods", "max_trace_points", "max_events_per_step"):
            v = getattr(self, name)
            # an integer, stored as one: not NaN (a numpy conversion error), '100' (a
            # TypeError deep in a scheme), 2.5 or True (kept as typed in r.options)
            if isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < 1:
                raise ValueError(f"{name} must be an integer >= 1, got {v!r}")
            if v > MAX_COUNT_OPTION:  # 1e30 reached the kernel as an OverflowError
                raise ValueError(f"{name} must be an integer in [1, {MAX_COUNT_OPTION}], got "
                                 f"{v!r}")
            object.__setattr__(self, name, int(v))
        for name in ("rtol", "stick_band_m_s"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real):
                raise TypeError(f"{name} must be a number, got {v!r}")
            object.__setattr__(self, name, float(v))
        if not 1e-14 <= self.rtol <= 1e-3:
            raise ValueError(f"rtol must lie in [1e-14, 1e-3], got {self.rtol!r}")
        if not (math.isfinite(self.stick_band_m_s) and self.stick_band_m_s >= 0):
            raise ValueError(f"stick_band_m_s must be finite and >= 0 (m/s), got "
                             f"{self.stick_band_m_s!r}")


def options_or_default(options: SimulationOptions | None,
                       overrides: bool = True) -> SimulationOptions:
    """``options``, or the defaults for None; anything else is a TypeError naming it (a dict would
    fail as "has no attribute 'dt_s'" deep in a scheme). ``overrides``: whether the caller also
    takes keyword overrides (``simulate`` does, ``stick_slip_map`` not), which the message then
    suggests."""
    if options is None:
        return SimulationOptions()
    if not isinstance(options, SimulationOptions):
        how = " (or keyword overrides such as dt_s=...)" if overrides else ""
        raise TypeError(f"options must be a SimulationOptions{how}, got "
                        f"{type(options).__name__}")
    return options
