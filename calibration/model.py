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
import multiprocessing
import os
import signal
import threading
import time
import warnings
from collections.abc import Iterator
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager

import numpy as np

from calibration.measurements import STEADY_KINDS, DataSet
from rom.damping import free_tip_phasors
from rom.params import MotorParams


def admittance_S(params: MotorParams, frequency_Hz: np.ndarray, c0_F: float) -> np.ndarray:
    """Two-mode admittance (S) of the free stator at the driven electrodes (module docstring)."""
    p = params
    w = 2.0 * np.pi * np.asarray(frequency_Hz, dtype=float)
    d_l = p.K_l - p.M_l * w**2 + 1j * p.C_l * w
    d_b = p.K_b - p.M_b * w**2 + 1j * p.C_b * w
    return 1j * w * (c0_F + p.A_l**2 / d_l + p.A_b**2 / d_b)


POOL_MIN_ROWS = 16
"""Steady rows of a data set from which :func:`row_pool` runs them on worker processes: the
two workers take about 2 s to start (importing the engine, loading its compiled kernels),
about ten evaluations of a 30-row set; a smaller set runs in the calling process."""


def _quiet_worker() -> None:
    """A row worker: no remarks (a fit visits many sets; they are not the user's), one BLAS
    thread, Ctrl-C left to the parent (which ends the pool), and an end of its own when the
    parent is gone without ending it (killed: the pool's queue does not tell an idle
    worker)."""
    from threadpoolctl import threadpool_limits

    warnings.simplefilter("ignore")
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threadpool_limits(limits=1, user_api="blas")
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(0)

    threading.Thread(target=watch, daemon=True).start()


@contextmanager
def row_pool(sets, workers: int | None = None) -> Iterator[Executor | None]:
    """A pool of ``workers`` processes (default every CPU) for the steady rows of ``sets``,
    or None (the rows run in the calling process) with one worker or when no steady set has
    :data:`POOL_MIN_ROWS` rows. Processes, not threads: the steady kernels release the GIL
    but the Python around them (about 40 % of a solve) does not. On the example's 30 speeds
    two threads take 0.84 of one process's time and two processes 0.64, and its
    calibration takes 44.6 s against 72.7 s in one process, to the same fitted values
    (``python benchmarks/calibrate_rows.py --whole``). Started by ``spawn``: a script that
    calibrates needs ``if __name__ == "__main__":``, as :mod:`multiprocessing` says."""
    n = workers or os.cpu_count() or 1
    rows = max((s.points for s in sets if s.kind in STEADY_KINDS), default=0)
    if n <= 1 or rows < POOL_MIN_ROWS:
        yield None
        return
    pool = ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_quiet_worker)
    try:
        yield pool
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _row_value(task: tuple) -> float:
    """Steady speed from rest (m/s) of one row, or its input power (W); 0 where the slider
    runs away."""
    from contact.steady import steady_state

    params, (v, fp, load, f), coupling, accuracy, power = task
    r = steady_state(params, v, fp, frequency_Hz=f, load_N=load, coupling=coupling,
                     accuracy=accuracy, energy=power)
    value = (r.from_rest.input_power_W if r.from_rest is not None else math.nan) \
        if power else r.velocity_m_s
    return value if np.isfinite(value) else 0.0


def speeds_m_s(params: MotorParams, inputs: dict[str, np.ndarray], coupling: str,
               accuracy: str, pool: Executor | None = None, power: bool = False) -> np.ndarray:
    """Steady speed from rest (m/s) at each row of a speed set's ``inputs`` (``power``: the
    input power (W) of that steady state instead), the rows on ``pool``
    (:func:`row_pool`) or in this process."""
    tasks = [(params, tuple(float(x) for x in r), coupling, accuracy, power) for r in zip(
        inputs["voltage"], inputs["preload"], inputs["load"], inputs["frequency"],
        strict=True)]
    if pool is not None:
        chunk = max(1, len(tasks) // (4 * (os.cpu_count() or 1)))
        return np.array(list(pool.map(_row_value, tasks, chunksize=chunk)), dtype=float)
    # a fit visits many sets; their remarks are not the user's (the filter is process-wide,
    # set and restored here, in the calling thread)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return np.array([_row_value(t) for t in tasks], dtype=float)


def predict(data: DataSet, params: MotorParams, c0_F: float | None, coupling: str,
            accuracy: str, pool: Executor | None = None) -> dict[str, np.ndarray]:
    """Measured quantity -> the model's value (SI) at every row of ``data``, the steady
    rows on ``pool`` (:func:`row_pool`) if given."""
    x = data.inputs
    if data.kind == "free":
        n, t = free_tip_phasors(params, x["frequency"], 1.0)
        return {"normal": np.abs(n) * x["voltage"], "tangential": np.abs(t) * x["voltage"]}
    if data.kind == "admittance":
        y = admittance_S(params, x["frequency"], float(c0_F or 0.0))
        return {"conductance": y.real, "susceptance": y.imag, "abs_Y": np.abs(y),
                "phase": np.angle(y)}
    if data.kind == "power":
        return {"input_power": speeds_m_s(params, x, coupling, accuracy, pool, power=True)}
    return {"velocity": speeds_m_s(params, x, coupling, accuracy, pool)}
