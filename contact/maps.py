"""Stick-slip maps over voltage x preload (the paper's Figs. 18-19), run in parallel.

Two methods (``method=``): ``"transient"`` runs each point from rest for the options' duration
(:func:`contact.simulate.simulate`, the paper's way); ``"steady"`` finds each point's steady
states directly (:func:`contact.steady.engine.steady_state`) and reports the one a start from rest
reaches, every stable branch, and the points it could not decide.

Each point is an independent call; the numba kernel releases
the GIL, so a thread pool keeps every core busy without pickling parameter sets. BLAS is held
to one thread meanwhile: the tiny 9 x 9 matrix exponentials do not need it, and OpenBLAS
worker threads left spinning after each call would otherwise take the cores from the pool.
"""

from __future__ import annotations

import dataclasses
import numbers
import os
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError
from contact.model import OperatingPoint, check_rest
from contact.operating_limits import operating_limits, simulation_limits
from contact.options import SimulationOptions, options_or_default
from contact.results import MOTION_CLASSES, FrozenArrays
from contact.simulate import simulate
from rom.params import MotorParams, require_params

NON_MONOTONE_FACTOR = 2.0
"""Ratio of neighbouring speeds (-) beyond which a map calls a pair that runs against the
trend (faster at lower voltage or higher preload) non-monotone
(:meth:`StickSlipMap.non_monotone_pairs`)."""


@dataclass(frozen=True, eq=False)
class StickSlipMap(FrozenArrays):
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
        Whether each run (transient or fallback) reached a steady velocity; True for every
        point the steady engine decided.
    wall_time_s : float
        Wall time of the whole map (s).
    method : str
        ``"transient"`` or ``"steady"``.
    branches : ndarray of object
        ``"steady"``: per point, a tuple of every stable steady state as
        ``(velocity_m_s, k, motion, from_rest, held)`` (:func:`branch_row`); ``"transient"``:
        empty tuples.
    fallback : ndarray of bool
        ``"steady"``: the points the engine could not decide (the branch reached from rest has
        no periodic tip orbit of period <= 4 outside the dead zone: creep), whose values come
        from a transient of :data:`FALLBACK_DURATION_S` instead.
    limits : ndarray of object or None
        Per point, its :class:`contact.operating_limits.OperatingLimits` (None without shape
        data).
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
    method: str = "transient"
    branches: np.ndarray | None = None
    fallback: np.ndarray | None = None
    limits: np.ndarray | None = None

    def counts(self) -> dict[str, int]:
        """Number of grid points of each motion class."""
        return {m: int(np.sum(self.motion == m)) for m in MOTION_CLASSES}

    def several_branches(self) -> list[tuple[int, int]]:
        """Grid indices ``(i_voltage, j_preload)`` of the points with more than one stable
        steady state (a steady map's; none for a transient map)."""
        if self.branches is None:
            return []
        return [(i, j) for i in range(self.voltages_V.size) for j in range(self.preloads_N.size)
                if len(self.branches[i, j]) > 1]

    def non_monotone_pairs(self, factor: float = NON_MONOTONE_FACTOR
                           ) -> list[tuple[tuple[int, int], tuple[int, int]]]:
        """Neighbouring grid points whose speeds run against the motor's trend by more than
        ``factor``: the higher voltage (same preload) slower, or the higher preload (same
        voltage) faster, ``|v|`` differing by more than ``factor`` times. Each pair is
        ``((i, j), (i2, j2))``, the lower voltage or preload first; points without a finite
        speed are skipped. Such pairs lie at creep level or across branches: their speeds are
        not a trend to read off the map."""
        speed = np.abs(np.asarray(self.velocity_m_s, dtype=float))
        pairs = []
        for (di, dj), against in (((1, 0), np.less), ((0, 1), np.greater)):
            for i in range(speed.shape[0] - di):
                for j in range(speed.shape[1] - dj):
                    a, b = speed[i, j], speed[i + di, j + dj]
                    if not (np.isfinite(a) and np.isfinite(b)):
                        continue
                    lo, hi = min(a, b), max(a, b)
                    if against(b, a) and hi > factor * lo:
                        pairs.append(((i, j), (i + di, j + dj)))
        return pairs


MAP_METHODS = ("transient", "steady")
"""How a map point is computed: a run from rest, or the steady engine."""


MAX_MAP_POINTS = 1_000_000
"""Most points of one map a library call computes (hours of steady solves; the CLI allows
``lusm.limits.MAX_STEADY_POINTS``)."""

FALLBACK_DURATION_S = 0.3
"""Transient run (s) standing in for a point the steady engine cannot decide (creep: the
branch from rest has no periodic tip orbit of period <= 4)."""


def fallback_duration_s(duration_s: float, frequency_Hz: float) -> float:
    """Length (s) of the transient that stands in for an undecided point of a steady map:
    the map's ``duration_s``, at least :data:`FALLBACK_DURATION_S` and 10 drive periods."""
    return max(duration_s, FALLBACK_DURATION_S, 10.0 / frequency_Hz)


def _steady_point(params: MotorParams, voltage_V: float, preload_N: float,
                  frequency_Hz: float, opts: SimulationOptions, accuracy: str,
                  rest: str = "probe"):
    """One map point from the steady engine, in the shape of a transient's steady metrics;
    an undecided point falls back to a transient of :data:`FALLBACK_DURATION_S`."""
    from contact.steady.engine import steady_state

    r = steady_state(params, voltage_V, preload_N, frequency_Hz=frequency_Hz,
                     coupling=opts.coupling, ultrasonic_friction=opts.ultrasonic_friction,
                     accuracy=accuracy, energy=True, rest=rest)  # powers: the limits
    b = r.from_rest
    stable = tuple(branch_row(x) for x in r.branches if x.stable)
    decided = bool(np.isfinite(r.velocity_m_s) and (b.k > 0 or b.motion == "dead-zone"))
    if not decided:
        # within the drive period's limits whatever the map's options (the steady map does
        # not check them against the frequency)
        period = 1.0 / frequency_Hz
        long = dataclasses.replace(
            opts, duration_s=fallback_duration_s(opts.duration_s, frequency_Hz),
            dt_s=None if opts.dt_s is None else min(opts.dt_s, period / 20))
        t = simulate(params, voltage_V, preload_N, frequency_Hz, long)
        st = t.steady
        return (st.motion, st.velocity_m_s, st.stick_fraction, st.separation_fraction,
                t.mu_d_eff, st.settled, stable, True, simulation_limits(t))
    # a dead zone's orbit is the held slider's: the tip stuck to it, or with no preload and
    # no drive never pressing on it (separated, as the transient says)
    frac = b.phase_fraction
    return (b.tip_motion, float(r.velocity_m_s), float(frac[0]), float(frac[3]), r.mu_d_eff,
            True, stable, False, operating_limits(params, voltage_V, frequency_Hz, b))


def branch_row(b) -> tuple[float, int, str, bool, bool]:
    """One steady state as a map point lists it: ``(velocity_m_s, k, motion, from_rest,
    held)``.

    Parameters
    ----------
    b : contact.steady.branches.SteadyBranch

    Returns
    -------
    tuple
        ``motion`` is :attr:`~contact.steady.branches.SteadyBranch.tip_motion`, the point's own
        vocabulary (a held slider's branch is ``"pure-stick"`` as its point is, not
        ``"dead-zone"``), and ``held`` whether the slider is held (the dead zone).
    """
    return (float(b.velocity_m_s), int(b.k), b.tip_motion, bool(b.from_rest), bool(b.held))


def stick_slip_map(
    params: MotorParams,
    voltages_V: np.ndarray,
    preloads_N: np.ndarray,
    frequency_Hz: float | None = None,
    options: SimulationOptions | None = None,
    workers: int | None = None,
    progress: bool = False,
    *,
    method: str = "transient",
    accuracy: str = "exact",
    rest: str = "probe",
) -> StickSlipMap:
    """Classify the steady motion of every (voltage, preload) pair.

    Parameters
    ----------
    params : MotorParams
    voltages_V, preloads_N : array_like
        Grid axes (V, N).
    frequency_Hz : float, optional
        Drive frequency (Hz); default the paper's 40 kHz, with
        :class:`contact.drive.WeakDriveWarning` when that misses the set's modes.
    options : SimulationOptions, optional
        Options of every run.
    workers : int, optional
        Threads; defaults to the number of CPUs.
    progress : bool
        Show a tqdm progress bar on stderr (off by default, as the other entry points: a
        library call draws none uninvited; ``lusm map`` turns it on).
    method : {"transient", "steady"}
        A run from rest of ``options.duration_s`` per point, or the steady engine
        (:func:`contact.steady.engine.steady_state`; ``options`` give coupling and friction only).
    accuracy : {"fast", "exact"}
        Level of the steady engine (``method="steady"``), see
        :data:`contact.steady.slow.ACCURACIES`.
    rest : {"probe", "transient"}
        How the exact level decides the start from rest
        (:func:`contact.steady.engine.steady_state`).
    """
    from contact.drive import default_drive_Hz

    v, f = _map_axes(voltages_V, preloads_N)
    require_params(params)
    _check_map_options(progress, method, accuracy, rest)
    # once for the map, not per point; the frequency checked before it is used
    frequency_Hz = OperatingPoint(0.0, 0.0, default_drive_Hz(params, frequency_Hz)).frequency_Hz
    opts = options_or_default(options, overrides=False)
    if workers is not None and (isinstance(workers, bool)
                                or not isinstance(workers, numbers.Integral) or workers < 1):
        # 0 is no number of threads, and -1 is named here, not by the thread pool
        raise ParameterError("workers", workers, 1, None,
                             message=f"workers must be an integer >= 1 or None (every CPU), "
                             f"got {workers!r}")
    n_workers = workers or os.cpu_count() or 1
    t0 = time.perf_counter()
    if method == "steady":
        def task(vi: float, fj: float):
            return _steady_point(params, vi, fj, frequency_Hz, opts, accuracy, rest)
    else:
        def task(vi: float, fj: float):
            r = simulate(params, vi, fj, frequency_Hz, opts)
            s = r.steady
            return (s.motion, s.velocity_m_s, s.stick_fraction, s.separation_fraction,
                    r.mu_d_eff, s.settled, (), False, simulation_limits(r))
    # compile (or load from cache) once before the threads start. Steady: the first point
    # itself, kept (at the engine's own step; a warm-up transient at T/250 fails the step
    # check far below 40 kHz). Transient: a 10-period run at the map's step
    first = None
    if method == "steady":
        first = task(float(v[0]), float(f[0]))
    else:
        simulate(params, float(v[0]), float(f[0]), frequency_Hz,
                 SimulationOptions(**{**opts.__dict__, "duration_s": 10 / frequency_Hz}))
    cols = _map_points(task, v, f, first, n_workers,
                       f"stick-slip map ({method})" if progress else None)
    motion, vel, stick, sep, mud, settled, branches, fallback, lims = cols
    return StickSlipMap(v, f, motion.astype(str), vel, stick, sep, mud, settled,
                        time.perf_counter() - t0, method, branches, fallback, lims)


def _map_axes(voltages_V, preloads_N) -> tuple[np.ndarray, np.ndarray]:
    """The map's axes as float arrays: real, finite, non-empty, 1-D, and at most
    :data:`MAX_MAP_POINTS` points together."""
    for name, axis in (("voltages_V", voltages_V), ("preloads_N", preloads_N)):
        # as simulate's voltage_V: neither [True] nor ["200"] is a voltage
        if np.asarray(axis).dtype.kind not in "iuf":
            raise ValueError(f"{name} must be real numbers, got {axis!r}")
    v = np.asarray(voltages_V, dtype=float)
    f = np.asarray(preloads_N, dtype=float)
    if v.ndim != 1 or f.ndim != 1 or v.size == 0 or f.size == 0:
        raise ValueError("voltages_V and preloads_N must be non-empty 1-D sequences")
    for name, axis in (("voltages_V", v), ("preloads_N", f)):  # named as the axis
        if not np.all(np.isfinite(axis)):
            raise ValueError(f"{name} must be finite, got {axis.tolist()!r}")
    if v.size * f.size > MAX_MAP_POINTS:
        raise ValueError(f"voltages_V x preloads_N give {v.size * f.size} points, above "
                         f"{MAX_MAP_POINTS}")
    return v, f


def _check_map_options(progress: bool, method: str, accuracy: str, rest: str) -> None:
    """Refuse a map option out of its choices, naming it."""
    from contact.steady.slow import ACCURACIES

    if not isinstance(progress, (bool, np.bool_)):  # "yes" is a true string, "" a false one
        raise TypeError(f"progress must be True or False, got {progress!r}")
    if method not in MAP_METHODS:
        raise ValueError(f"method must be one of {MAP_METHODS}, got {method!r}")
    if accuracy not in ACCURACIES:
        raise ValueError(f"accuracy must be one of {ACCURACIES}, got {accuracy!r}")
    check_rest(rest)


def _map_points(task, v: np.ndarray, f: np.ndarray, first, n_workers: int,
                bar_title: str | None) -> tuple[np.ndarray, ...]:
    """Every point's ``task(v_i, f_j)`` on ``n_workers`` threads (BLAS on one thread each),
    ``first`` standing for point (0, 0) where given, gathered into the map's columns
    (motion, velocity, stick and separation fractions, mu_d_eff, settled, branches,
    fallback, limits). A progress bar titled ``bar_title`` on stderr (none for None)."""
    from threadpoolctl import threadpool_limits
    from tqdm import tqdm

    shape = (v.size, f.size)
    motion = np.empty(shape, dtype=object)
    vel, stick, sep, mud = (np.empty(shape) for _ in range(4))
    settled = np.zeros(shape, dtype=bool)
    branches = np.empty(shape, dtype=object)
    branches.fill(())
    fallback = np.zeros(shape, dtype=bool)
    lims = np.empty(shape, dtype=object)
    cols = (motion, vel, stick, sep, mud, settled, branches, fallback, lims)

    def store(i: int, j: int, point) -> None:
        for col, value in zip(cols, point, strict=True):
            col[i, j] = value

    with threadpool_limits(limits=1, user_api="blas"), ThreadPoolExecutor(
        max_workers=n_workers
    ) as pool:
        futures = {
            pool.submit(task, float(v[i]), float(f[j])): (i, j)
            for i in range(v.size)
            for j in range(f.size)
            if first is None or (i, j) != (0, 0)
        }
        bar = tqdm(total=v.size * f.size, desc=bar_title, unit="point",
                   disable=bar_title is None)
        if first is not None:
            store(0, 0, first)
            bar.update()
        try:
            for fut in as_completed(futures):
                store(*futures[fut], fut.result())
                bar.update()
        except BaseException:
            # an interrupt or a failed point: drop the points not started, or leaving the
            # block would wait for every one of them (tens of seconds on a large map)
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        finally:
            bar.close()
    return cols
