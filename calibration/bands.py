"""Uncertainty bands of the steady engine's predictions on a calibrated set (``--uncertainty``).

Each function draws parameter sets from a calibration's covariance
(:func:`calibration.uncertainty.propagate`) and runs one steady prediction on each: the speed
of ``lusm simulate --steady``, the stall force and speed-thrust curve of ``lusm
characteristic``, the speeds of a steady ``lusm map``. A draw where the slider runs away
under its load has no speed (NaN, counted as ``missing``). The engine's remarks on the draws
are not the user's: they are silenced, the nominal run says its own.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence

import numpy as np

from calibration.uncertainty import DEFAULT_SAMPLES, Band, Calibration, propagate
from rom.params import MotorParams


def steady_speed_m_s(params: MotorParams, voltage_V: float, preload_N: float,
                     frequency_Hz: float, *, load_N: float = 0.0, coupling: str = "auto",
                     ultrasonic_friction: bool = True, rest: str = "probe") -> float:
    """Speed from rest (m/s) of the exact steady engine, as ``lusm simulate --steady`` gives
    it; NaN where the slider runs away under ``load_N``."""
    from contact.errors import RunawayError
    from contact.steady import steady_state

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            r = steady_state(params, voltage_V, preload_N, frequency_Hz=frequency_Hz,
                             load_N=load_N, coupling=coupling,
                             ultrasonic_friction=ultrasonic_friction, accuracy="exact",
                             energy=False, rest=rest)
        except RunawayError:
            return math.nan
    return float(r.velocity_m_s)


def speed_band(cal: Calibration, params: MotorParams, voltages_V: Sequence[float],
               preload_N: float, frequency_Hz: float, *, samples: int = DEFAULT_SAMPLES,
               seed: int = 0, progress: Callable[[int, int], None] | None = None,
               **engine) -> Band:
    """The band of the steady speed (m/s) at each of ``voltages_V`` (``engine``: the
    keywords of :func:`steady_speed_m_s`)."""
    return propagate(cal, params, lambda p: [
        steady_speed_m_s(p, v, preload_N, frequency_Hz, **engine) for v in voltages_V],
        samples, seed, progress)


def characteristic_band(cal: Calibration, params: MotorParams, voltage_V: float,
                        preload_N: float, loads_N: Sequence[float], frequency_Hz: float, *,
                        samples: int = DEFAULT_SAMPLES, seed: int = 0,
                        progress: Callable[[int, int], None] | None = None,
                        **engine) -> tuple[Band, Band]:
    """The bands of the stall force (N) and of the speed (m/s) at each of ``loads_N`` (the
    nominal curve's loads, so that every draw is read at the same loads); ``engine``: the
    keywords of :func:`contact.characteristic.characteristic` (``coupling``,
    ``ultrasonic_friction``, ``accuracy``, ``rest``)."""
    from contact.characteristic import characteristic

    loads = [float(f) for f in loads_N]

    def run(p: MotorParams) -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = characteristic(p, voltage_V, preload_N, loads, frequency_Hz=frequency_Hz,
                               **engine)
        return np.concatenate([[c.stall_force_N], np.asarray(c.velocity_m_s, dtype=float)])

    both = propagate(cal, params, run, samples, seed, progress)
    return both.part(0), both.part(slice(1, None))


def map_band(cal: Calibration, params: MotorParams, voltages_V: np.ndarray,
             preloads_N: np.ndarray, frequency_Hz: float, options, *,
             samples: int = DEFAULT_SAMPLES, seed: int = 0, workers: int | None = None,
             progress: Callable[[int, int], None] | None = None, accuracy: str = "exact",
             rest: str = "probe") -> Band:
    """The band of a steady map's speeds (m/s), one value per (voltage, preload) point
    (:func:`contact.maps.stick_slip_map` with ``method="steady"`` and ``options``, a
    :class:`contact.options.SimulationOptions`)."""
    from contact.maps import stick_slip_map

    def run(p: MotorParams) -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = stick_slip_map(p, voltages_V, preloads_N, frequency_Hz, options,
                               workers=workers, method="steady", accuracy=accuracy,
                               rest=rest)
        return np.asarray(m.velocity_m_s, dtype=float)

    return propagate(cal, params, run, samples, seed, progress)
