"""What the model predicts for each measured value of a data set.

* free tip amplitudes: the linear free response of L1 and B2 (:func:`rom.damping.free_tip_phasors`),
  as the paper's Eqs. (4)-(5) fitted to its Figs. 5-6;
* admittance of the free stator at the driven electrodes: the two-mode
  Butterworth-Van Dyke form ``Y = i omega (C0 + A_l^2 / D_l + A_b^2 / D_b)`` with
  ``D = K - M omega^2 + i C omega`` (the modal force ``A V`` and, by reciprocity, the
  charge ``A u`` of each mode); modes other than L1 and B2 enter only through ``C0``;
* steady speed: the steady engine's speed from rest (:func:`contact.steady.steady_state`,
  milliseconds a point); a slider that runs away under its load counts as speed 0;
* input power: the power the drive puts into L1 and B2 on the branch reached from rest
  (``input_power_W`` of the steady engine, ``<A V (q_l' + q_b')>``-like: the dielectric
  loss of the ceramic is not in the model), 0 where the slider runs away.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from calibration.measurements import DataSet
from rom.damping import free_tip_phasors
from rom.params import MotorParams


def admittance_S(params: MotorParams, frequency_Hz: np.ndarray, c0_F: float) -> np.ndarray:
    """Two-mode admittance (S) of the free stator at the driven electrodes (module docstring)."""
    p = params
    w = 2.0 * np.pi * np.asarray(frequency_Hz, dtype=float)
    d_l = p.K_l - p.M_l * w**2 + 1j * p.C_l * w
    d_b = p.K_b - p.M_b * w**2 + 1j * p.C_b * w
    return 1j * w * (c0_F + p.A_l**2 / d_l + p.A_b**2 / d_b)


def speeds_m_s(params: MotorParams, inputs: dict[str, np.ndarray], coupling: str,
               accuracy: str, workers: int | None = None, power: bool = False) -> np.ndarray:
    """Steady speed from rest (m/s) at each row of a speed set's ``inputs`` (``power``: the
    input power (W) of that steady state instead), the rows on ``workers`` threads (default
    every CPU; the steady engine's kernels release the GIL, as ``lusm map`` runs its
    points)."""
    import os
    from concurrent.futures import ThreadPoolExecutor

    from threadpoolctl import threadpool_limits

    from contact.steady import steady_state

    def one(row: tuple[float, float, float, float]) -> float:
        v, fp, load, f = row
        r = steady_state(params, v, fp, frequency_Hz=f, load_N=load, coupling=coupling,
                         accuracy=accuracy, energy=power)
        value = (r.from_rest.input_power_W if r.from_rest is not None else math.nan) \
            if power else r.velocity_m_s
        return value if np.isfinite(value) else 0.0

    rows = [tuple(float(x) for x in r) for r in zip(
        inputs["voltage"], inputs["preload"], inputs["load"], inputs["frequency"],
        strict=True)]
    n = min(workers or os.cpu_count() or 1, len(rows))
    # a fit visits many sets; their remarks are not the user's (the filter is process-wide,
    # set and restored here, in the calling thread)
    with warnings.catch_warnings(), threadpool_limits(limits=1, user_api="blas"):
        warnings.simplefilter("ignore")
        if n <= 1:
            return np.array([one(r) for r in rows], dtype=float)
        with ThreadPoolExecutor(max_workers=n) as pool:
            return np.array(list(pool.map(one, rows)), dtype=float)


def predict(data: DataSet, params: MotorParams, c0_F: float | None, coupling: str,
            accuracy: str) -> dict[str, np.ndarray]:
    """Measured quantity -> the model's value (SI) at every row of ``data``."""
    x = data.inputs
    if data.kind == "free":
        n, t = free_tip_phasors(params, x["frequency"], 1.0)
        return {"normal": np.abs(n) * x["voltage"], "tangential": np.abs(t) * x["voltage"]}
    if data.kind == "admittance":
        y = admittance_S(params, x["frequency"], float(c0_F or 0.0))
        return {"conductance": y.real, "susceptance": y.imag, "abs_Y": np.abs(y),
                "phase": np.angle(y)}
    if data.kind == "power":
        return {"input_power": speeds_m_s(params, x, coupling, accuracy, power=True)}
    return {"velocity": speeds_m_s(params, x, coupling, accuracy)}
