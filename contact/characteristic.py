"""The motor's speed-thrust characteristic, output power and efficiency from the steady engine.

For each load the slider velocity is the steady branch a start from rest reaches
(:func:`contact.steady.branches.branches_at_load`); all loads share one cache of fast orbits,
since the fast problem at fixed velocity does not depend on the load.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact.drive import default_drive_Hz
from contact.model import OperatingPoint, check_rest, check_scale, resolve_coupling
from contact.operating_limits import operating_limits
from contact.results import FrozenArrays
from contact.steady.branches import branches_at_load, motor_efficiency
from contact.steady.engine import steady_state, warn_irregular
from contact.steady.exact import HELD_M_S
from contact.steady.runaway import holding_range_N
from contact.steady.slow import ACCURACIES, EXACT_ROOT_RTOL, ripple_scale, slow_problem
from rom.params import MotorParams, require_params

CREEP_SHARE = 1e-3
"""Relative excess of the exact stall force over the averaged one below which no creep band
is reported (:attr:`Characteristic.creep_from_N`)."""

CREEP_RIPPLES = 2.0
"""A slider creeps (-) where its mean velocity from rest is below this many velocity-ripple
scales (:func:`contact.steady.slow.ripple_scale`; the orbit's peak-to-peak ripple is about three
of them at Table 2's 200 V / 14 N): it then stops, or nearly stops, within every drive period.
The creep band's loads are those (:attr:`Characteristic.creep_from_N`); the largest creep on
Table 2's curves is 1.3 scales (200 V / 14 N), the slowest thrust beside a creep band 3.7
(the tuned 60 kHz stator at 140 V / 14 N, ``examples/tuned_60k``)."""


@dataclass(frozen=True, eq=False)
class Characteristic(FrozenArrays):
    """Speed-thrust, power and efficiency curves at one voltage and preload.

    Attributes
    ----------
    op : OperatingPoint
        Voltage (V), preload (N), frequency (Hz); its load is 0.
    no_load_velocity_m_s : float
        Steady velocity from rest without load (m/s).
    stall_force_N : float
        Load at which the velocity from rest falls to zero (N), signed as ``load_N``. At the
        fast level ``F_T(0+) - mu_sd (F_N + M g)`` for a motor that drives the slider
        forward, and ``F_T(0-) + mu_sd (F_N + M g)`` (negative: a load pushing the slider
        forward) for one that drives it backward, as the same motor with ``A_b`` reversed
        does; 0 in the dead zone. At the exact level the full model's first zero crossing
        (``accuracy``), at the resolution of a scan of ``points`` loads up to it: the same
        whatever ``loads_N`` the curve is asked at.
    load_N, velocity_m_s, input_power_W, output_power_W, efficiency : ndarray
        The curves: load (N), velocity from rest (m/s), electrical input power (W), mechanical
        output power ``load * v`` (W) and their ratio (-), NaN where the motor takes
        mechanical power in (output power < 0). The velocity is NaN at a load the
        slider runs away under (outside ``holding_range_N``, or wherever a start from rest
        reaches no steady state).
    holding_range_N : tuple of float
        Loads (N) the driven motor holds at the tip's full slip
        (:func:`contact.steady.runaway.holding_range_N`): beyond the upper one it is pushed backward
        without bound, below the lower one (a load pushing it forward) forward. NaN where
        the tip does not slide throughout at the scan's end (e.g. no drive).
    accuracy : str
        Level of the velocities, powers, stall force and default loads
        (:data:`contact.steady.slow.ACCURACIES`). At ``"exact"`` the stall force is where the full
        model's velocity from rest crosses zero, beyond the averaged one: the finite slider
        creeps on through the band the averaging calls held. The holding range comes from
        the averaged slow equation at either level.
    wall_time_s : float
    orbits : int
        Fast-problem orbits solved, those of each load's exact steady state included.
    averaged_stall_force_N : float
        The averaged (fast level's) stall force (N); equal to ``stall_force_N`` at the fast
        level. At the exact level it usually lies below the exact one, where a creep band
        begins (:attr:`creep_from_N`); it can also lie above it (Table 2's set at 450 V /
        40 N: the full model stalls at 2.73 N, the averaged one at 3.16 N).
    creep_from_N : float
        Where the exact level's creep band begins (N), or NaN where there is none: from it
        up to the stall force the finite slider creeps, slower than :data:`CREEP_RIPPLES`
        velocity-ripple scales (:func:`contact.steady.slow.ripple_scale`), its ripple breaking the
        guide's ideal Coulomb stiction every period; a real guide's pre-sliding stiffness,
        which the model does not have, may hold it there (``docs/steady.md``). Which rule
        gave it is :attr:`creep_rule`. Only where the exact stall force lies beyond the
        averaged one (same sign, by more than :data:`CREEP_SHARE`); NaN at the fast level,
        where the full model stalls first (Table 2's set at 450 V / 40 N) or where nothing
        before the stall creeps.
    creep_rule : str
        ``"averaged stall"``: the band begins at the averaged stall force, beyond which the
        averaged slider is held (checked: the velocity from rest there and at the scan's
        loads up to the stall creeps). ``"whole curve"``: 0, the no-load velocity already
        creeps (the beam set at 200 V / 14 N at its own frequency). ``"creep threshold"``:
        the band holds faster thrust, because the averaging followed another sheet than the
        start from rest (the tuned 60 kHz stator at 140 V / 14 N: averaged stall 0.469 N,
        2.9e-3 m/s at 0.50 N, no creep): the band begins where the
        velocity from rest falls below the creep speed for the last time before the stall,
        bisected on the scan of ``points`` loads. ``""`` where there is no band.
    creep_speed_m_s : float
        The creep speed (m/s), :data:`CREEP_RIPPLES` velocity-ripple scales: slower than it
        the slider creeps. NaN at the fast level, where no band is looked for.
    limits : tuple
        Each load's :class:`contact.operating_limits.OperatingLimits` (None where the slider
        runs away).
    """

    op: OperatingPoint
    no_load_velocity_m_s: float
    stall_force_N: float
    load_N: np.ndarray
    velocity_m_s: np.ndarray
    input_power_W: np.ndarray
    output_power_W: np.ndarray
    efficiency: np.ndarray
    holding_range_N: tuple[float, float]
    accuracy: str
    wall_time_s: float
    orbits: int
    averaged_stall_force_N: float = math.nan
    creep_from_N: float = math.nan
    creep_rule: str = ""
    limits: tuple = ()
    creep_speed_m_s: float = math.nan

    def worst_limits(self):
        """The :class:`contact.operating_limits.OperatingLimits` of the curve's load whose
        largest ratio to a limit is largest; None without limits."""
        known = [lim for lim in self.limits if lim is not None]
        if not known:
            return None
        return max(known, key=lambda lim: max(
            (r for r in (lim.ratio(q) for q in lim.values) if r == r), default=0.0))

    @property
    def direction(self) -> str:
        """Which way the motor drives the slider from rest without load: ``"forward"``
        (+y, positive velocity), ``"backward"`` (its stall force and default loads are then
        negative: against that motion) or ``"held"`` (within
        :data:`contact.steady.exact.HELD_M_S` of 0)."""
        v = self.no_load_velocity_m_s
        return "forward" if v > HELD_M_S else "backward" if v < -HELD_M_S else "held"

    def to_dict(self) -> dict:
        """The fields of ``lusm characteristic --json``, as Python floats: NaN stays NaN
        (a load the slider runs away under, an undefined efficiency or holding bound); the
        CLI writes it as ``null``, ``json.dumps(..., allow_nan=False)`` refuses it."""
        return {
            "no_load_velocity_m_s": float(self.no_load_velocity_m_s),
            "direction": self.direction,
            "stall_force_N": float(self.stall_force_N),
            "averaged_stall_force_N": float(self.averaged_stall_force_N),
            "creep_from_N": float(self.creep_from_N),
            "creep_from_rule": self.creep_rule,
            "creep_speed_m_s": float(self.creep_speed_m_s),
            "holding_range_N": [float(f) for f in self.holding_range_N],
            "accuracy": self.accuracy,
            "curve": [
                {"load_N": float(f), "velocity_m_s": float(v), "input_power_W": float(pi),
                 "output_power_W": float(po), "efficiency": float(e),
                 "limits": None if lim is None else lim.to_dict()}
                for f, v, pi, po, e, lim in zip(self.load_N, self.velocity_m_s,
                                                self.input_power_W, self.output_power_W,
                                                self.efficiency, self._row_limits(),
                                                strict=True)
            ],
            "limits": None if self.worst_limits() is None else self.worst_limits().to_dict(),
        }

    def _row_limits(self) -> tuple:
        return self.limits if len(self.limits) == len(self.load_N) else (None,) * len(
            self.load_N)


MAX_POINTS = 10_000
"""Most loads of one curve (``points``, or ``loads_N``): 1e9 would run for minutes before
anything."""

STALL_RTOL = EXACT_ROOT_RTOL
"""Relative tolerance (-) of the exact level's stall force, the root ``brentq`` finds of the
velocity from rest against the load: the exact level's own root tolerance (1e-6). Near the stall
the slider creeps below its velocity ripple and every load tried is a 2 000-period transient
from rest (a few nm/s within 1e-6 of Table 2's stall at 300 V / 14 N); the default
characteristic there makes 34 steady solves with 1e-6, 53 with 1e-9."""


def characteristic(params: MotorParams, voltage_V: float, preload_N: float,
                   loads_N=None, *, frequency_Hz: float | None = None,
                   coupling: str = "auto", ultrasonic_friction: bool = True,
                   points: int = 21, accuracy: str = "exact",
                   progress: bool = False, rest: str = "probe") -> Characteristic:
    """Speed-thrust characteristic at one operating point.

    Parameters
    ----------
    params : MotorParams
    voltage_V, preload_N : float
        Drive amplitude (V) and preload (N).
    loads_N : array_like, optional
        Loads (N); by default ``points`` loads from 0 to the stall force (negative for a motor
        that drives the slider backward; only 0 where the motor is in its dead zone: stall
        force 0).
    frequency_Hz : float, optional
        Drive frequency (Hz), 40 kHz when None.
    coupling, ultrasonic_friction
        As in :func:`contact.steady.engine.steady_state`.
    accuracy : {"exact", "fast"}
        ``"exact"`` (the default, as ``lusm characteristic``'s; the fast level's stall force
        on the FE set at 400 V / 14 N is 0.476 N against the motor's 1.014 N):
        :func:`contact.steady.engine.steady_state` at the exact level per
        load (finite slider mass, the start from rest on the full model: creeps, holds by
        the tip's stiction and multi-period starts under a load that the averaging cannot
        see; about a 2 000-period transient per loaded point); ``"fast"``: every load from
        one cache of averaged orbits (the M -> infinity averaging).
    progress : bool
        Show a tqdm progress bar over the loads on stderr once the curve takes more than a
        second (the exact level's curves do).
    rest : {"probe", "transient"}
        How the exact level decides the start from rest under each load
        (:func:`contact.steady.engine.steady_state`).

    Returns
    -------
    Characteristic
    """
    t0 = time.perf_counter()
    loads_arr = _checked_options(accuracy, rest, progress, points, loads_N)
    require_params(params)
    coupling = resolve_coupling(params, coupling)  # "auto": as the CLI's
    op = OperatingPoint(voltage_V, preload_N,
                        default_drive_Hz(params, frequency_Hz))
    if loads_arr is not None and loads_arr.size:  # both levels refuse it, before any solve
        _check_load_scale(params, op, loads_arr)
    sp = slow_problem(params, op, coupling=coupling, ultrasonic_friction=ultrasonic_friction)
    from_rest = _FromRest(params, op, sp, coupling, ultrasonic_friction, accuracy, rest)
    v0 = from_rest(0.0)[0]
    stall = averaged = _stall_force(sp)

    def velocity(load: float) -> float:
        return from_rest(float(load))[0]

    exact_moving = accuracy == "exact" and abs(v0) > HELD_M_S
    if accuracy == "exact":
        stall = _full_model_stall_force(velocity, v0, stall, sp.thrust_at_rest())
        if exact_moving and math.isfinite(stall):
            stall = _first_stop(velocity, v0, stall, points)
    loads = _loads(loads_N, stall, points)
    vel, p_in_a, p_out_a = _curve(from_rest, loads, op, progress)
    irregular = _least_certain_irregular(loads, from_rest.irregular)
    if irregular is not None:  # one word for the curve: rows that are means, not orbits
        warn_irregular(*irregular)
    eff = motor_efficiency(p_in_a, p_out_a)  # NaN, not below 0, under a pushing load
    hold = tuple(float(f) for f in holding_range_N(sp))
    creep_from, creep_rule, creep_speed = math.nan, "", math.nan
    if exact_moving and math.isfinite(stall):
        creep_from, creep_rule, creep_speed = _creep(params, op, sp, velocity, v0, averaged,
                                                     stall, points)
        _warn_beyond_stall(velocity, v0, loads, stall)
    lims = tuple(None if not math.isfinite(v) else
                 operating_limits(params, op.voltage_V, op.frequency_Hz,
                                  from_rest.branches.get(float(f)))
                 for f, v in zip(loads, vel, strict=True))
    return Characteristic(op, float(v0), float(stall), loads, vel, p_in_a, p_out_a,
                          eff, hold, accuracy, time.perf_counter() - t0,
                          len(sp.cache) + from_rest.exact_orbits, float(averaged),
                          float(creep_from), creep_rule, lims, float(creep_speed))


def _loads(loads_N, stall_N: float, points: int) -> np.ndarray:
    """The loads (N) of the curve: ``loads_N`` when given, else ``points`` loads from 0 to
    the stall force; the no-load point alone where the motor is held without load (dead
    zone: stall 0) or no stall was found (NaN), not a NaN load."""
    if loads_N is not None:
        return np.asarray(loads_N, dtype=float).ravel()
    if math.isfinite(stall_N) and stall_N != 0.0:
        return np.linspace(0.0, stall_N, points)
    return np.zeros(1)


def _creep(params: MotorParams, op: OperatingPoint, sp, velocity, v0: float,
           averaged_N: float, stall_N: float, points: int) -> tuple[float, str, float]:
    """``(creep_from_N, creep_rule, creep_speed_m_s)`` of a moving exact-level curve: the
    creep speed is :data:`CREEP_RIPPLES` ripples of the orbit's scale
    (:func:`ripple_scale`), the load where the motor starts creeping from
    :func:`_creep_start`."""
    creep_speed = CREEP_RIPPLES * ripple_scale(params, op, sp.mu_d_eff)
    creep_from, creep_rule = _creep_start(velocity, v0, averaged_N, stall_N, points,
                                          creep_speed)
    return creep_from, creep_rule, creep_speed


def _curve(from_rest: _FromRest, loads: np.ndarray, op: OperatingPoint,
           progress: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocity (m/s) from rest, input and output power (W) at each load, with a progress
    bar on stderr once the curve takes more than a second."""
    from tqdm import tqdm

    vel, p_in, p_out = [], [], []
    for load in tqdm(loads, desc=f"characteristic {op.voltage_V:g} V", unit="load",
                     disable=not progress, delay=1.0, leave=False):
        v, p = from_rest(float(load))
        vel.append(v)
        p_in.append(p)
        p_out.append(float(load) * v + 0.0)  # + 0.0: 0 W at no load, not -0 W backward
    return np.array(vel), np.array(p_in), np.array(p_out)


def _checked_options(accuracy: str, rest: str, progress: bool, points: int,
                     loads_N) -> np.ndarray | None:
    """Refuse options out of their range, naming them; ``loads_N`` as an array (None for
    the default loads)."""
    if accuracy not in ACCURACIES:
        raise ValueError(f"accuracy must be one of {ACCURACIES}, got {accuracy!r}")
    check_rest(rest)
    if not isinstance(progress, (bool, np.bool_)):  # "yes" is a true string, "" a false one
        raise TypeError(f"progress must be True or False, got {progress!r}")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or \
            not 2 <= points <= MAX_POINTS:
        raise ValueError(f"points must be an integer in [2, {MAX_POINTS}], got {points!r}")
    if loads_N is None:
        return None
    # a NaN load would fall into the fast level's dead zone and come out as 0 m/s
    loads_arr = np.asarray(loads_N)
    if loads_arr.ndim > 1:  # a nested list is no sequence of loads, not flattened
        raise ValueError(f"loads_N must be a sequence of loads (N), got shape "
                         f"{loads_arr.shape}")
    if loads_arr.dtype.kind not in "iuf" or not np.all(np.isfinite(loads_arr)):
        raise ValueError(f"loads_N must be finite numbers (N), got {loads_N!r}")
    if loads_arr.size > MAX_POINTS:  # bounded as points is
        raise ValueError(f"loads_N has {loads_arr.size} loads, above {MAX_POINTS}")
    return loads_arr


def _check_load_scale(params: MotorParams, op: OperatingPoint, loads_arr: np.ndarray) -> None:
    """Refuse loads out of the model's scale (:func:`contact.model.check_scale`) at either
    level before any solve (the fast level would answer NaN), naming ``loads_N``."""
    largest = float(loads_arr[np.argmax(np.abs(loads_arr))])
    check_scale(params, op)  # the drive and preload first, named as they are
    try:
        check_scale(params, dataclasses.replace(op, load_N=largest))
    except ValueError as exc:  # the parameter is loads_N, not load_N
        text = str(exc)
        if text.startswith("load_N = "):
            text = "loads_N: its load " + text[len("load_N = "):]
        raise ValueError(text) from None


class _FromRest:
    """Velocity (m/s) and input power (W) of the start from rest under a load, once per load
    (the no-load point is usually one of the loads too): the exact level's steady state, or
    the fast level's branches from the shared slow problem ``sp``. Keeps the branches from
    rest with no short period (``irregular``, by load) and the orbits the exact steady
    states solved (``exact_orbits``)."""

    def __init__(self, params: MotorParams, op: OperatingPoint, sp, coupling: str,
                 ultrasonic_friction: bool, accuracy: str, rest: str) -> None:
        self.params, self.op, self.sp = params, op, sp
        self.coupling, self.ultrasonic_friction = coupling, ultrasonic_friction
        self.accuracy, self.rest = accuracy, rest
        self.irregular: dict[float, object] = {}
        self.branches: dict[float, object] = {}  # the branch from rest at each load
        self.exact_orbits = 0
        self._done: dict[float, tuple[float, float]] = {}

    def __call__(self, load: float) -> tuple[float, float]:
        if load not in self._done:
            self._done[load] = self._solve(load)
        return self._done[load]

    def _solve(self, load: float) -> tuple[float, float]:
        if self.accuracy == "exact":
            op = self.op
            r = steady_state(self.params, op.voltage_V, op.preload_N,
                             frequency_Hz=op.frequency_Hz, load_N=load, coupling=self.coupling,
                             ultrasonic_friction=self.ultrasonic_friction, accuracy="exact",
                             rest=self.rest)
            self.exact_orbits += r.orbits
            b = r.from_rest
            if b is not None and b.irregular:
                self.irregular[load] = b
            self.branches[load] = b
            return r.velocity_m_s, (b.input_power_W if b is not None else np.nan)
        branches, v = branches_at_load(self.sp, load)
        b = next((b for b in branches if b.from_rest), None)
        self.branches[load] = b
        return v, (b.input_power_W if b is not None else np.nan)


def _least_certain_irregular(loads: np.ndarray, irregular: dict) -> tuple | None:
    """``(branch, where)`` for :func:`contact.steady.engine.warn_irregular`: the irregular
    branch from rest of least relative certainty among the curve's loads and the loads it
    names; None where every row is an orbit."""
    shown = {float(f): irregular[float(f)] for f in loads if float(f) in irregular}
    if not shown:
        return None
    worst = max(shown.values(), key=lambda b: b.velocity_error_m_s
                / max(abs(b.velocity_m_s), 1e-300))
    if len(shown) == 1:
        return worst, f"under the load {next(iter(shown)):g} N"
    least = next(f for f, b in shown.items() if b is worst)
    return worst, (f"under the loads {', '.join(f'{f:g}' for f in shown)} N (the least "
                   f"certain, {least:g} N, shown)")


def _stall_force(sp) -> float:
    """The load (N, signed as ``load_N``) that stops the motor in the direction it drives the
    slider from rest: the averaged thrust at 0+ where that is positive, at 0- where that is
    negative (a motor driving backward, e.g. one with ``A_b`` reversed), else 0 (the guide
    and the tip hold the slider: the dead zone)."""
    # as contact.steady.branches.branches_at_load takes them, so that the stall load is exactly
    # where that function's dead zone begins on either side
    forward, backward = sp.thrust_at_rest()
    if forward > 0.0:
        return float(forward)
    return float(backward) if backward < 0.0 else 0.0


def _full_model_stall_force(velocity, v0: float, averaged: float,
                            thrust_at_rest: tuple[float, float]) -> float:
    """The smallest load (N, signed as ``load_N``) under which the full model's start from
    rest no longer moves the slider the way it drives it without load; 0 if it is held.

    ``velocity(load)`` is the exact level's velocity from rest (m/s, NaN for a run-away).
    The finite slider follows the tip's force within every period, not only its average:
    in stick (and, where the tip separates, as the guide's hold drops with the normal force)
    it is pulled on, and it creeps through the band the averaged slow equation calls held
    (``averaged`` to ``G(0-)``). The full model's stall force lies inside that band (Table
    2's set at 14 N: 2.16 N against the averaged 1.735 N at 400 V, 0.945 N against 0.408 N
    at 200 V; ``lusm characteristic --accuracy exact``). A held band (velocity within
    :data:`contact.steady.exact.HELD_M_S` of 0) counts as stopped, so its lower end is found; a
    creep crossing 0 is found by ``brentq`` to :data:`STALL_RTOL` relative.
    """
    if not abs(v0) > HELD_M_S:
        return 0.0
    s = math.copysign(1.0, v0)
    moving = _moving(velocity, s)
    lo, hi = 0.0, averaged
    if averaged == 0.0 or moving(averaged) > 0:
        # the averaging stops the slider too early: search up to where its motion reverses
        # (the other side's thrust at rest), then beyond it in steps of the averaged stall
        lo = averaged
        hi = thrust_at_rest[1] if s > 0 else thrust_at_rest[0]
        step = abs(hi - lo) or abs(averaged) or 1.0
        if s * (hi - lo) <= 0.0:
            # the averaged band lies against the motor's own direction (a dead zone the full
            # model runs backward out of: its stall is a load against that motion)
            hi = lo + s * step
        for _ in range(MAX_STALL_STEPS):
            if moving(hi) <= 0:
                break
            # doubling: a stall many bands away (a 1 m plate running backward at 3 N
            # beyond a 0.08 N band) is reached in a few steps
            lo, hi, step = hi, hi + s * step, 2.0 * step
        else:
            return math.nan
    return float(brentq(moving, lo, hi, xtol=1e-12, rtol=STALL_RTOL))


MAX_STALL_STEPS = 40
"""Most steps of the full model's stall search beyond the averaged band (each twice the
last): 2**40 bands, beyond any load the engine takes."""


def _moving(velocity, s: float):
    """``moving(load)``: > 0 while the slider still moves the way (sign ``s``) it is driven
    without load; held, reversed or run away: < 0 (held as a small negative, so that a held
    band's lower end is a root)."""
    def moving(load: float) -> float:
        v = s * velocity(load)
        return v if v > HELD_M_S else (min(v, -HELD_M_S) if math.isfinite(v) else -1.0)

    return moving


def _scan(stall: float, points: int) -> list[float]:
    """The scan grid (N) of the exact level's stall and creep band: ``points`` loads from 0 up
    to the stall force (excluded), as the default curve takes them, so that both answers are
    the same whatever loads a caller asks the curve at (a grid of ``loads_N`` would give
    0.2823 N by default and 0.4605 N with ``--loads 0,0.2,0.4,0.5``)."""
    return [float(f) for f in np.linspace(0.0, stall, points)[:-1]]


MAX_STALL_REFINEMENTS = 4
"""Most refinements of the exact stall force by :func:`_first_stop` (each a new scan grid of
``points`` loads up to the refined stall); one was enough on every curve seen."""


def _first_stop(velocity, v0: float, stall: float, points: int) -> float:
    """The stall force refined to the first load of the scan grid (:func:`_scan`) under which
    the slider no longer moves the way it is driven, if one comes before ``stall`` (N).

    ``brentq`` finds *a* zero crossing of the velocity from rest in its bracket, not the
    first: where the velocity is not monotone in the load (branches from rest that change
    with it) the curve can show the slider stopped or reversed below a stall force found
    by the first crossing alone (the tuned 40 kHz stator at 100 V / 14 N: -1.1e-5 m/s at
    0.299 N below a crossing at 0.4605 N). The first such load and the moving one before it
    bracket the crossing found here; the grid up to the refined stall is then scanned again
    (the default curve's loads), until it shows no earlier stop. Crossings between the
    grid's loads are not seen: the stall force is the first crossing at the resolution of
    ``points`` loads."""
    s = math.copysign(1.0, v0)
    moving = _moving(velocity, s)
    for _ in range(MAX_STALL_REFINEMENTS):
        previous, found = 0.0, None
        for load in _scan(stall, points):
            if moving(load) <= 0.0:
                found = float(brentq(moving, previous, load, xtol=1e-12, rtol=STALL_RTOL))
                break
            previous = load
        if found is None:
            break
        stall = found
    return stall


def _creep_start(velocity, v0: float, averaged: float, stall: float, points: int,
                 creep_m_s: float) -> tuple[float, str]:
    """:attr:`Characteristic.creep_from_N` (N) and :attr:`Characteristic.creep_rule`: where
    the slider starts to creep, slower than ``creep_m_s`` (m/s), on its way to the stall
    force; NaN and "" where it does not."""
    def excess(load: float) -> float:  # > 0 faster than a creep (a run-away too), < 0 creeps
        v = velocity(load)
        return abs(v) - creep_m_s if math.isfinite(v) else creep_m_s

    if excess(0.0) < 0.0:  # the no-load velocity creeps: the whole curve does
        return 0.0, "whole curve"
    band = averaged * stall >= 0.0 and abs(stall) > abs(averaged) * (1.0 + CREEP_SHARE)
    if not band:  # the full model stalls first (or the other way): no creep band
        return math.nan, ""
    s = math.copysign(1.0, v0)
    grid = _scan(stall, points)
    if excess(averaged) < 0.0 and all(excess(f) < 0.0 for f in grid if s * f >= s * averaged):
        return float(averaged), "averaged stall"  # the averaged slider is held from here on
    # the averaging followed another sheet: the band is where the curve's last run of creeping
    # loads before the stall begins, its threshold crossing bisected (not the grid's load,
    # which would move with the loads asked for)
    last = len(grid)
    while last > 0 and excess(grid[last - 1]) < 0.0:
        last -= 1
    if last == len(grid) or last == 0:  # no creep before the stall, or all of it (v0 not)
        return math.nan, ""
    root = brentq(excess, grid[last - 1], grid[last], xtol=1e-12, rtol=STALL_RTOL)
    return float(root), "creep threshold"


class NonMonotoneWarning(UserWarning):
    """The velocity from rest turns the way the motor drives the slider again beyond the
    stall force: the speed-thrust curve is not monotone (other branches from rest)."""


def _warn_beyond_stall(velocity, v0: float, loads, stall: float) -> None:
    """Warn where one of the curve's loads beyond the stall force moves the slider the way it
    is driven (the tuned 40 kHz stator at 100 V / 14 N: forward at 0.35-0.44 N, beyond its
    0.2823 N stall): the curve is not monotone there."""
    s = math.copysign(1.0, v0)
    moving = _moving(velocity, s)
    beyond = [float(f) for f in loads if s * f > s * stall and moving(float(f)) > 0.0]
    if beyond:
        import warnings

        f = min(beyond, key=lambda x: s * x)
        warnings.warn(
            f"the velocity from rest turns the way the motor drives the slider again beyond "
            f"the stall force {stall:.6g} N ({velocity(f):.3g} m/s at {f:g} N): the "
            "speed-thrust curve is not monotone (other branches from rest under those "
            "loads)", NonMonotoneWarning, stacklevel=3)


def averaging_doubt(params: MotorParams, char: Characteristic, *, coupling: str = "auto",
                    ultrasonic_friction: bool = True) -> str | None:
    """Why the averaged (``accuracy="fast"``) no-load answer of ``char`` is not to be
    trusted, or None.

    Two reasons: its no-load velocity lies below the slider's velocity ripple (the ripple
    scale with Eq. 11's friction, :attr:`contact.steady.slow.SlowProblem.v_floor_m_s`: the
    slider is not slow against the drive period; at 20 Hz the fast level gives 1.8e-6 m/s and
    a 1.18 N stall force where the finite-mass motor is held), or the finite-mass motor
    reaches another steady state from rest (the exact level's no-load point, compared beyond
    the averaging's O(1/M) error: at 30 kHz the fast level finds one branch at 0.0124 m/s
    where a start from rest creeps at 1.1e-4 m/s).
    """
    op = char.op
    sp = slow_problem(params, op, coupling=coupling, ultrasonic_friction=ultrasonic_friction)
    ripple = sp.v_floor_m_s
    v = abs(float(char.no_load_velocity_m_s))
    where = f"at {op.voltage_V:g} V and {op.frequency_Hz:g} Hz"
    if v < ripple:
        return (f"{where} the averaged no-load velocity {v:.3g} m/s is below the slider's "
                f"velocity ripple (about {ripple:.2g} m/s per drive period): the averaging "
                "does not hold there; the exact level runs the finite-mass motor")
    r = steady_state(params, op.voltage_V, op.preload_N, frequency_Hz=op.frequency_Hz,
                     coupling=coupling, ultrasonic_friction=ultrasonic_friction,
                     accuracy="exact", energy=False)
    exact = float(r.velocity_m_s)
    if abs(exact - float(char.no_load_velocity_m_s)) > 0.05 * max(abs(exact), ripple):
        return (f"{where} the averaged no-load velocity {char.no_load_velocity_m_s:.3g} m/s "
                f"is not the one the finite-mass motor reaches from rest ({exact:.3g} m/s, "
                "the exact level): several steady states coexist and the averaging cannot "
                "tell which a start from rest reaches")
    return None
