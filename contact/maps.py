"""Stick-slip maps over voltage x preload (the paper's Figs. 18-19), run in parallel.

Each point is an independent :func:`contact.simulate.simulate` call; the numba kernel releases
the GIL, so a thread pool keeps every core busy without pickling parameter sets. BLAS is held
to one thread meanwhile: the tiny 9 x 9 matrix exponentials do not need it, and OpenBLAS
worker threads left spinning after each call would otherwise take the cores from the pool.
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass

import numpy as np

from contact.results import MOTION_CLASSES
from contact.simulate import SimulationOptions, simulate
from rom.params import MotorParams


@dataclass(frozen=True)
class StickSlipMap:
    """Motion class and steady metrics on a voltage x preload grid.

    Arrays have shape ``(len(voltages_V), len(preloads_N))``.

    Attributes
    ----------
    voltages_V, preloads_N : ndarray
        Grid axes (V, N).
    motion : ndarray of str
        Motion class per point (one of :data:`contact.results.MOTION_CLASSES`).
    velocity_m_s, stick_fraction, separation_fraction, mu_d_eff : ndarray
        Steady velocity (m/s), phase fractions (-) and the slip friction coefficient (-).
    settled : ndarray of bool
        Whether each run reached a steady velocity.
    wall_time_s : float
        Wall time of the whole map (s).
    """

    voltages_V: np.ndarray
    preloads_N: np.ndarray
    motion: np.ndarray
    velocity_m_s: np.ndarray
    stick_fraction: np.ndarray
    separation_fraction: np.ndarray
    mu_d_eff: np.ndarray
    settled: np.ndarray
    wall_time_s: float

    def counts(self) -> dict[str, int]:
        """Number of grid points of each motion class."""
        return {m: int(np.sum(self.motion == m)) for m in MOTION_CLASSES}


def stick_slip_map(
    params: MotorParams,
    voltages_V: np.ndarray,
    preloads_N: np.ndarray,
    frequency_Hz: float = 40e3,
    options: SimulationOptions | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> StickSlipMap:
    """Simulate every (voltage, preload) pair and classify its steady motion.

    Parameters
    ----------
    params : MotorParams
    voltages_V, preloads_N : array_like
        Grid axes (V, N).
    frequency_Hz : float
        Drive frequency (Hz).
    options : SimulationOptions, optional
        Options of every run.
    workers : int, optional
        Threads; defaults to the number of CPUs.
    progress : bool
        Show a tqdm progress bar on stderr.
    """
    from threadpoolctl import threadpool_limits
    from tqdm import tqdm

    v = np.asarray(voltages_V, dtype=float)
    f = np.asarray(preloads_N, dtype=float)
    if v.ndim != 1 or f.ndim != 1 or v.size == 0 or f.size == 0:
        raise ValueError("voltages_V and preloads_N must be non-empty 1-D sequences")
    opts = options or SimulationOptions()
    shape = (v.size, f.size)
    motion = np.empty(shape, dtype=object)
    vel, stick, sep, mud = (np.empty(shape) for _ in range(4))
    settled = np.zeros(shape, dtype=bool)
    n_workers = workers or os.cpu_count() or 1
    t0 = time.perf_counter()
    # compile (or load from cache) once before the threads start
    simulate(params, float(v[0]), float(f[0]), frequency_Hz,
             SimulationOptions(**{**opts.__dict__, "duration_s": 10 / frequency_Hz}))
    with threadpool_limits(limits=1, user_api="blas"), ThreadPoolExecutor(
        max_workers=n_workers
    ) as pool:
        futures = {
            pool.submit(simulate, params, float(v[i]), float(f[j]), frequency_Hz, opts): (i, j)
            for i in range(v.size)
            for j in range(f.size)
        }
        bar = tqdm(total=len(futures), desc="stick-slip map", unit="run", disable=not progress)
        for fut in as_completed(futures):
            i, j = futures[fut]
            r = fut.result()
            motion[i, j] = r.steady.motion
            vel[i, j] = r.steady.velocity_m_s
            stick[i, j] = r.steady.stick_fraction
            sep[i, j] = r.steady.separation_fraction
            mud[i, j] = r.mu_d_eff
            settled[i, j] = r.steady.settled
            bar.update()
        bar.close()
    return StickSlipMap(v, f, motion.astype(str), vel, stick, sep, mud, settled,
                        time.perf_counter() - t0)
