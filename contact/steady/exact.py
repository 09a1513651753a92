"""The exact level of the steady engine: every averaged branch shot on the full model (finite
slider mass) and the branch a start from rest reaches decided on it."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from contact import state as S
from contact.errors import ChatteringError
from contact.results import PHASE_THRESHOLD, classify_motion
from contact.steady.branches import SteadyBranch, averaged_branch
from contact.steady.from_rest import probe_from_rest
from contact.steady.full_orbit import full_system, mean_forces, run_periods, shoot
from contact.steady.periodic_orbit import Orbit
from contact.steady.slow import V_ZERO_M_S, SlowProblem
from contact.transient.event_kernel import N_WORK

REST_MEAN_PERIODS = 400
"""Periods of the full model, after the transient from rest, whose mean velocity stands for a
start from rest that settles on no orbit of period <= :data:`REST_MAX_K`."""

REST_MEAN_BLOCKS = 10
"""Windows of :data:`REST_MEAN_PERIODS` periods whose mean velocities give an irregular creep's
velocity and its standard error (:attr:`contact.steady.branches.SteadyBranch.velocity_error_m_s`): a
motion that repeats with no period up to :data:`REST_MAX_K` and whose windows do not agree (one
window's mean is 10 % off a long transient's on a chaotic creep whose windows scatter by 20 %)."""

REST_SETTLED_RTOL = 1e-6
"""Two consecutive :data:`REST_MEAN_PERIODS` windows after the transient from rest whose mean
velocities agree to this (relative) make its mean the answer where shooting confirmed no
orbit."""

HOLD_CHECK_PERIODS = 100
"""Periods of each of the three blocks whose mean velocities decide whether a slider in the
averaged dead zone stays held from rest (:func:`_held_from`)."""

HOLD_CHECK_FACTOR = 1e-5
"""A slider whose mean speed from rest stays below this fraction of the ripple scale is held
(:func:`_held_from`)."""

HOLD_DECAY_EXPONENT = 1.5
"""A slow drift after the transient from rest whose speed falls at least as ``t**-1.5`` dies
out (:func:`_held_from`): its remaining travel is finite; a creep's speed levels off."""

HELD_M_S = 1e-12
"""Full-model orbits whose mean slider speed is at most this (m/s, roundoff of a slider at
rest) hold the slider: they are reported as the dead zone, with velocity 0."""

REST_TRANSIENT_PERIODS = 2000
"""Drive periods of the transient from rest that decides the branch reached (accuracy
"exact") where the run out of the ripple zone cannot (:mod:`contact.steady.from_rest`; the
transient goes on from that run); shooting then removes what is left of the transient."""

REST_MAX_K = 16
"""Longest period (in drive periods) the exact level looks for at the end of the transient
from rest before shooting it. The creep points below the slider's velocity ripple settle on
slider-tip orbits of ten periods on Table 2's set (100 V / 10 N, 200 V / 20 N; the slider
stops and starts inside every period), which the averaging cannot see."""


def _run_branch(sp: SlowProblem, v: float, k: int, n_periods: int, work: np.ndarray,
                phase_time: np.ndarray, stable: bool, from_rest: bool,
                held: bool, forces: tuple[float, float]) -> SteadyBranch:
    """A branch measured on ``n_periods`` periods of the full model: mean velocity ``v``
    (m/s), work integrals ``work`` (J), phase times (s) and mean forces ``(F_T, F_N)`` (N);
    ``held``: the dead zone, at velocity 0 with no output power (its guide power is the
    slider's rocking with the stuck tip: 3.4e-5 W at 139 V / 14 N, part of the energy
    balance)."""
    duration = n_periods * sp.op.period_s
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0, 0, 0])
    motion = classify_motion(frac[0], frac[1] + frac[2], frac[3], PHASE_THRESHOLD)
    w_in, w_damp, _, w_ts, w_tx, w_g, w_damp_b = (float(w) for w in work)
    load = sp.op.load_N
    v = float(v)
    if held:  # no net travel, but the slider rocks with the stuck tip against the guide
        v, motion = 0.0, "dead-zone"
    output = load * v + 0.0  # + 0.0: 0 W at no load, not -0 W backward
    guide = -(w_g / duration) - load * v if sp.params.mu_sd > 0 else 0.0
    return SteadyBranch(
        velocity_m_s=v, k=k, stable=stable, motion=motion, mean_FT_N=float(forces[0]),
        mean_FN_N=float(forces[1]), input_power_W=w_in / duration, output_power_W=output,
        damping_power_W=w_damp / duration, interface_power_W=-(w_ts + w_tx) / duration,
        guide_power_W=guide, from_rest=from_rest, damping_power_B2_W=w_damp_b / duration,
        phase_fraction=tuple(float(f) for f in frac))


def _full_branch(sp: SlowProblem, fo, stable: bool, from_rest: bool) -> SteadyBranch:
    """The branch of a shot full-model orbit, with its least period and its own mean forces;
    one that holds the slider (``|v| <= HELD_M_S``: by the guide, or by the tip's stiction)
    is the dead zone."""
    return _run_branch(sp, fo.velocity_m_s, fo.k, fo.k, fo.work, fo.phase_time, stable,
                       from_rest, held=abs(fo.velocity_m_s) <= HELD_M_S,
                       forces=(fo.mean_FT_N, fo.mean_FN_N))


def _mean_branch(sp: SlowProblem, v: float, work: np.ndarray, phase_time: np.ndarray,
                 n_periods: int, error_m_s: float,
                 forces: tuple[float, float]) -> SteadyBranch:
    """The long mean of the full model's transient from rest, where it repeats with no
    period up to :data:`REST_MAX_K` (k = 0; powers NaN without the work integrals, which
    cover ``n_periods``, as the mean forces ``(F_T, F_N)`` (N) do; ``error_m_s`` the mean
    velocity's standard error)."""
    b = _run_branch(sp, v, 0, n_periods, work, phase_time, True, True, held=False,
                    forces=forces)
    return dataclasses.replace(b, velocity_error_m_s=float(error_m_s))


def _powered(sp: SlowProblem, b: SteadyBranch, energy: bool = True) -> SteadyBranch:
    """The averaged branch ``b`` with its input, damping and interface powers (the exact
    level scans without them and needs them only for the branches it keeps averaged)."""
    if not energy or not math.isnan(b.input_power_W):
        return b
    v = V_ZERO_M_S if b.motion == "dead-zone" else b.velocity_m_s
    w = averaged_branch(sp, v, sp.op.load_N, b.stable)
    return dataclasses.replace(b, input_power_W=w.input_power_W,
                               damping_power_W=w.damping_power_W,
                               damping_power_B2_W=w.damping_power_B2_W,
                               interface_power_W=w.interface_power_W)


def _held_from(sp: SlowProblem, fsys, z: np.ndarray, mode: int,
               elapsed_periods: int | None = None) -> tuple[bool, np.ndarray, int]:
    """Whether the full model's slider, started from ``(z, mode)``, stays in place, and the
    state ``(z, mode)`` it ends the check in (a held slider's, rocking with its stuck tip).

    Three blocks of :data:`HOLD_CHECK_PERIODS` periods give three mean velocities; their
    Aitken extrapolation (the last one where they are not converging geometrically) must be
    at most :data:`HOLD_CHECK_FACTOR` times the ripple scale (about 1e-9 m/s, the settled
    references' own tolerance for a held point). A held slider rocks with its stuck tip
    while the start-up drift decays geometrically (on Table 2's map to 1e-10 m/s or, at
    50 V / 26 N, by a factor of about 6 per block); a creep under a load keeps its speed
    (1e-4 m/s and more).

    Under a small load the drift can die out algebraically instead, about as 1/t^2 (Table 2
    at 10 V / 6.5 N under -0.2 N: 4.4e-9, 4.0e-9, 3.7e-9 m/s over the blocks after the
    2 000-period transient, a fourth per doubling of a long transient's length), which
    Aitken's extrapolation does not see. Given ``elapsed_periods`` (the periods since rest
    at ``z``, late enough for the decay's own law), the slider is also held where the block
    means fall, one sign, at least as :data:`HOLD_DECAY_EXPONENT` powers of the time: faster
    than 1/t, so that the distance still to go is finite (at most ``v t / (exponent - 1)``)
    and the position converges.
    """
    v = []
    for _ in range(3):
        z, mode, dist, _, _ = run_periods(fsys, z, mode, HOLD_CHECK_PERIODS)
        v.append(dist / (HOLD_CHECK_PERIODS * sp.op.period_s))
    d1, d2 = v[1] - v[0], v[2] - v[1]
    limit = v[2]
    if d2 != d1 and abs(d2) < abs(d1):  # converging: Aitken's delta-squared
        limit = v[2] - d2 * d2 / (d2 - d1)
    if abs(limit) <= HOLD_CHECK_FACTOR * sp.v_floor_m_s:
        return True, z, mode
    if elapsed_periods is None or not (abs(v[0]) > abs(v[1]) > abs(v[2]) > 0.0) \
            or v[0] * v[2] < 0.0:
        return False, z, mode
    t0, t2 = (elapsed_periods + (i + 0.5) * HOLD_CHECK_PERIODS for i in (0, 2))
    return math.log(v[0] / v[2]) >= HOLD_DECAY_EXPONENT * math.log(t2 / t0), z, mode


def _held_branch(sp: SlowProblem, fsys, z: np.ndarray, mode: int, from_rest: bool,
                 energy: bool = True) -> tuple[SteadyBranch, int, int]:
    """The dead zone measured on the full model at a held state ``(z, mode)``: its one-period
    orbit by shooting (period k = 1), else the mean of :data:`REST_MEAN_PERIODS` periods
    (k = 0). Returns ``(branch, periods, newton)``; without ``energy`` its powers are NaN
    (its period, phases and mean forces are the same).

    Its powers include the slider's rocking with the stuck tip against the guide, which the
    averaged orbit at 0+ (an infinitely heavy slider) does not have: at 200 V / 14 N driven
    at 1 kHz the guide takes 5.0e-4 W of the 1.07e-3 W put in, which the averaged dead zone
    misses."""
    try:
        h = shoot(fsys, z, mode, 1, energy=energy)
    except ChatteringError:
        h = None
    if h is not None and h.k and abs(h.velocity_m_s) <= HELD_M_S:
        return _full_branch(sp, h, True, from_rest), h.periods, h.newton_iterations
    _, _, _, work, phase = run_periods(fsys, z, mode, REST_MEAN_PERIODS, energy=energy,
                                       window=True)
    if not energy:
        work = np.full(N_WORK, math.nan)
    forces = mean_forces(fsys, z, mode, REST_MEAN_PERIODS)
    periods = 3 * REST_MEAN_PERIODS + (h.periods if h is not None else 0)
    branch = _run_branch(sp, 0.0, 0, REST_MEAN_PERIODS, work, phase, True, from_rest,
                         held=True, forces=forces)
    return branch, periods, h.newton_iterations if h is not None else 0


def _shoot_averaged(fsys, o: Orbit, energy: bool):
    """The full model shot from the averaged orbit ``o`` (its state with the slider moving
    at ``o``'s velocity, over ``o``'s period), or None where the kernel chatters."""
    v = o.velocity_m_s
    z = o.z.copy()
    z[S.DX] = v
    guide = S.FORWARD if v > 0 else S.BACKWARD
    try:
        return shoot(fsys, z, o.mode - o.mode % 3 + guide, max(o.k, 1), energy=energy)
    except ChatteringError:
        return None


def _shoot_probe(fsys, probe, energy: bool):
    """The full model's orbit at the root the run from rest found on its sheet
    (:func:`contact.steady.from_rest.probe_from_rest`), or None where there is none or the shot
    does not confirm it: no convergence, an unstable orbit, or a mean velocity more than
    5 % from the averaged root (another orbit). Returns ``(orbit, periods, newton)``."""
    o = probe.orbit
    fo = None if o is None else _shoot_averaged(fsys, o, energy)
    if fo is None:
        return None, 0, 0
    v = o.velocity_m_s
    # no multiplier when the shot converged before forming a Jacobian: the sheet's root is
    # stable (the slow flow stops there), and so is the orbit
    stable = not (fo.multiplier >= 1.0)
    ok = fo.k and stable and abs(fo.velocity_m_s - v) <= 0.05 * abs(v)
    return (fo if ok else None), fo.periods, fo.newton_iterations


def _transient_from_rest(sp: SlowProblem, fsys, z, mode, done: int, energy: bool):
    """The transient from rest (``done`` of its :data:`REST_TRANSIENT_PERIODS` periods already
    run, ending at ``(z, mode)``) and the orbit it approaches by shooting.

    Returns ``(z_end, mode_end, v_rest, orbit, periods, newton)``: the state at the end of
    the transient, the velocity (m/s) of the shot orbit where shooting confirms the
    transient's recent mean to 5 %, else that mean, with the orbit or None, and the work."""
    periods = newton = 0
    z_end, m_end, _, _, _ = run_periods(fsys, z, mode, REST_TRANSIENT_PERIODS - done)
    periods += REST_TRANSIENT_PERIODS - done
    # the period the transient repeats with: the smallest k <= REST_MAX_K whose defect
    # |y_(j+k) - y_j| is within tenfold of the smallest (multiples of the period repeat too)
    ys, zj, mj = [z_end[[0, 1, 2, 3, 5]]], z_end, m_end
    for _ in range(REST_MAX_K):
        zj, mj, _, _, _ = run_periods(fsys, zj, mj, 1)
        ys.append(zj[[0, 1, 2, 3, 5]])
    periods += REST_MAX_K
    ys_arr = np.array(ys) / np.array([1.0, sp.op.omega, 1.0, sp.op.omega, sp.op.omega])
    scale = np.max(np.abs(ys_arr), axis=0) + 1e-30
    diffs = np.array([np.abs(ys_arr[k] - ys_arr[0]) for k in range(1, REST_MAX_K + 1)])
    defects = np.max(diffs / scale, axis=1)
    # a state repeating to 1e-9 of the orbit's size repeats (a held slider's state does with
    # every k: its coordinates at rest carry only roundoff, which the tenfold rule would match)
    repeats = np.max(diffs, axis=1) <= 1e-9 * scale.max()
    k_best = 1 + int(np.argmax((defects <= 10.0 * defects.min()) | repeats))
    _, _, dist, _, _ = run_periods(fsys, z_end, m_end, 4 * k_best)
    periods += 4 * k_best
    v_transient = dist / (4 * k_best * sp.op.period_s)
    v_rest, fo = v_transient, None
    try:
        cand = shoot(fsys, z_end, m_end, k_best, energy=energy)
        periods += cand.periods
        newton += cand.newton_iterations
        # accept the polished orbit only if the transient was heading for it
        if cand.k and abs(cand.velocity_m_s - v_transient) <= 0.05 * abs(v_transient) + 1e-9:
            v_rest, fo = cand.velocity_m_s, cand
    except ChatteringError:
        pass
    return z_end, m_end, v_rest, fo, periods, newton


@dataclass
class _Cost:
    """Drive periods simulated and Newton iterations spent by the exact level (a tally)."""

    periods: int = 0
    newton: int = 0

    def add(self, periods: int, newton: int = 0) -> None:
        self.periods += periods
        self.newton += newton


@dataclass
class _RestRun:
    """Where the full model started from rest ends, as the exact level decides it.

    ``v`` is the velocity (m/s): a shot orbit's, a long mean's, 0 for a held slider, NaN for
    one that runs away; ``orbit`` the shot full-model orbit or None; ``(z, mode)`` the state
    at the end of the run from rest; ``periods`` that run's length (``rest_periods``);
    ``from_mean``: the answer is a long mean (a ``k = 0`` branch).
    """

    v: float
    orbit: object
    z: np.ndarray
    mode: int
    periods: int
    held: bool = False
    from_mean: bool = False


def exact_branches(sp: SlowProblem, branches, coupling: str, energy: bool = True,
                   rest: str = "probe"):
    """Polish the averaged branches on the full model and decide the start from rest.

    Returns ``(branches, v_rest, periods, newton, rest_periods)``: the full model's steady
    branches by increasing velocity, the velocity (m/s) a start from rest reaches (NaN: the
    slider runs away), the drive periods simulated and Newton iterations spent, and the
    periods of the run from rest.
    """
    fsys = full_system(sp.params, sp.op, sp.mu_d_eff, coupling)
    cost = _Cost()
    # the dead zone is the only steady state of the slow equation: a start from rest stays
    # held if the full model says so. The averages can hide a creep: under a load the
    # guide's hold can give way for part of every period, and the slider then walks
    # backward below its velocity ripple, where the averaging does not hold.
    released = False  # the full model's slider left the averaged dead zone from rest
    if len(branches) == 1 and branches[0].motion == "dead-zone":
        cost.periods += 3 * HOLD_CHECK_PERIODS
        held_now, z_h, m_h = _held_from(sp, fsys, fsys.system.z0, fsys.system.mode0)
        if held_now:
            # the full model's held slider, whatever energy= says: its period, phases and
            # mean forces are those of every held slider the exact level reports
            measured, more, more_newton = _held_branch(sp, fsys, z_h, m_h, True, energy)
            return (measured,), 0.0, cost.periods + more, more_newton, cost.periods
        released = True
    out, shot_held = _shot_branches(sp, fsys, branches, released, energy, cost)
    run = _run_from_rest(sp, fsys, rest, energy, cost)
    run.held = abs(run.v) <= HELD_M_S
    match = [i for i, b in enumerate(out)
             if abs(b.velocity_m_s - run.v) <= 1e-6 * abs(run.v) + 1e-12
             or (run.held and b.motion == "dead-zone")]
    if run.orbit is None and not run.held:
        match = _mean_from_rest(sp, fsys, branches, out, run, match, energy, cost)
    if match:
        out[match[0]] = dataclasses.replace(out[match[0]], from_rest=True)
    elif run.orbit is not None:
        # a transient from rest settled on it: stable unless its multiplier says otherwise
        # (none when the shot from the transient's end converged at once)
        fo = run.orbit
        stable = bool(fo.multiplier < 1.0) if math.isfinite(fo.multiplier) else True
        out.append(_full_branch(sp, fo, stable, True))
    if (not run.held and math.isfinite(run.v) and abs(run.v) < sp.v_floor_m_s
            and not any(b.motion == "dead-zone" for b in out)):
        _add_held_beside_creep(sp, fsys, run, out, shot_held, energy, cost)
    if run.orbit is not None or run.from_mean:
        # averaged roots below the ripple scale that no full-model orbit confirms are not
        # steady states of the finite-mass motor (the averaging does not hold there); the
        # full model's orbit from rest stands for them
        out = [b for b in out if b.from_rest or b.k > 0 or b.motion == "dead-zone"
               or abs(b.velocity_m_s) >= sp.v_floor_m_s]
    out = _one_dead_zone(sp, fsys, run, out, shot_held, energy, cost)
    out.sort(key=lambda b: b.velocity_m_s)
    return tuple(out), (0.0 if run.held else run.v), cost.periods, cost.newton, run.periods


def _shot_branches(sp: SlowProblem, fsys, branches, released: bool, energy: bool,
                   cost: _Cost) -> tuple[list[SteadyBranch], list[SteadyBranch]]:
    """Every averaged branch shot on the full model (kept averaged, with its powers, where
    the shot fails), and the dead zones among the shots (held full-model orbits). The
    averaged dead zone is dropped where the full model's slider left it from rest
    (``released``): there it is no steady state of the full model."""
    out: list[SteadyBranch] = []
    shot_held: list[SteadyBranch] = []
    for b in branches:
        if b.motion == "dead-zone":
            if not released:
                out.append(dataclasses.replace(_powered(sp, b, energy), from_rest=False))
            continue
        fo = _shoot_averaged(fsys, sp.orbit(b.velocity_m_s), energy)
        if fo is not None:
            cost.add(fo.periods, fo.newton_iterations)
        if fo is not None and fo.k:
            # no multiplier when the shot converged before forming a Jacobian: the averaged
            # stability stands
            stable = bool(fo.multiplier < 1.0) if math.isfinite(fo.multiplier) else b.stable
            full = _full_branch(sp, fo, stable, False)
            out.append(full)
            if full.motion == "dead-zone":  # the shot converged to a held slider
                shot_held.append(full)
        else:
            out.append(dataclasses.replace(_powered(sp, b, energy), from_rest=False))
    return out, shot_held


def _run_from_rest(sp: SlowProblem, fsys, rest: str, energy: bool, cost: _Cost) -> _RestRun:
    """The full model started from rest: out of the ripple zone and along the averaged sheet
    it is on (:mod:`contact.steady.from_rest`, ``rest="probe"``), else a transient from rest
    and shooting for the orbit it approaches.

    Not the scan's own first root: the full model from rest can take another sheet of the
    slow equation (a tuned 60 kHz stator at 140 V / 14 N reaches stick-slip at 6.23e-3 m/s
    from rest, where the scan's only branch is pure slip at 1.36e-2 m/s).
    """
    if rest == "probe":
        probe = probe_from_rest(sp, fsys)
        cost.add(probe.periods, probe.newton_iterations)
        fo, more, more_newton = _shoot_probe(fsys, probe, energy)
        cost.add(more, more_newton)
        z0, m0, done = probe.z, probe.mode, probe.full_periods
    else:  # rest == "transient": the transient from rest decides at every point
        fo, z0, m0, done = None, fsys.system.z0, fsys.system.mode0, 0
    if fo is not None:
        return _RestRun(fo.velocity_m_s, fo, z0, m0, done)
    z_end, m_end, v_rest, fo, more, more_newton = _transient_from_rest(
        sp, fsys, z0, m0, done, energy)
    cost.add(more, more_newton)
    return _RestRun(v_rest, fo, z_end, m_end, REST_TRANSIENT_PERIODS)


def _mean_from_rest(sp: SlowProblem, fsys, branches, out: list[SteadyBranch], run: _RestRun,
                    match: list[int], energy: bool, cost: _Cost) -> list[int]:
    """Decide a start from rest whose transient settled on no orbit of ``k <=``
    :data:`REST_MAX_K` periods that shooting could confirm: a quasi-periodic or irregular
    motion, or a fast slider that 2 000 periods have not settled.

    Two more windows tell which: where their mean velocities agree
    (:data:`REST_SETTLED_RTOL`), or below the ripple scale (where the averaging does not
    hold), the transient's mean is the answer, a ``k = 0`` branch appended to ``out`` (or the
    dead zone, where that mean is a drift that dies out); otherwise the averaged choice
    stands. With no averaged choice (no root a start from rest stops at) the slider runs
    away. Updates ``run`` and returns the indices of ``out`` reached from rest.
    """
    avg = [i for i, b in enumerate(branches) if b.from_rest]
    if not avg:
        run.v = math.nan
        return match
    # below the ripple scale the averaging does not hold: the full model's mean stands even
    # unsettled (an irregular creep)
    creep = abs(branches[avg[0]].velocity_m_s) < sp.v_floor_m_s
    v_mean, error, settled, phase, work, z_a, m_a = _window_means(
        sp, fsys, run.z, run.mode, creep, energy, cost)
    if not (settled or creep):
        run.v = out[avg[0]].velocity_m_s
        return avg
    run.v = v_mean
    if abs(run.v) <= 1e-3 * sp.v_floor_m_s:
        # a slow drift, not yet a creep: held if it dies out (the dead zone)
        cost.periods += 3 * HOLD_CHECK_PERIODS
        held_now, z_h, m_h = _held_from(sp, fsys, run.z, run.mode, REST_TRANSIENT_PERIODS)
        if held_now:
            run.v, run.held, run.z, run.mode = 0.0, True, z_h, m_h
    if run.held:
        return match
    run.from_mean = True
    # the mean forces over the window of the work integrals
    forces = mean_forces(fsys, z_a, m_a, REST_MEAN_PERIODS)
    cost.periods += 2 * REST_MEAN_PERIODS
    out.append(_mean_branch(sp, run.v, work, phase, REST_MEAN_PERIODS, error, forces))
    return []


def _window_means(sp: SlowProblem, fsys, z: np.ndarray, mode: int, creep: bool,
                  energy: bool, cost: _Cost):
    """The mean velocity of the full model over windows of :data:`REST_MEAN_PERIODS` after
    ``(z, mode)``: two, and :data:`REST_MEAN_BLOCKS` for an unsettled ``creep``.

    Returns ``(v_mean, error, settled, phase, work, z_a, m_a)``: the mean velocity (m/s) and
    its standard error (0 from two windows), whether the two windows agree to
    :data:`REST_SETTLED_RTOL`, the phase times (s) and work integrals (J; NaN without
    ``energy``) of the windows, and the state the first window ends in, where the work
    integrals start.
    """
    window_s = REST_MEAN_PERIODS * sp.op.period_s
    # the velocities always at the engine's own step, the work integrals on a run of their
    # own: a run at the energy step is another trajectory, whose mean of a chaotic creep
    # differs by 4 %, and energy= must not move the answer
    z_a, m_a, dist_a, _, _ = run_periods(fsys, z, mode, REST_MEAN_PERIODS)
    z_b, m_b, dist, _, phase = run_periods(fsys, z_a, m_a, REST_MEAN_PERIODS, window=True)
    cost.periods += 2 * REST_MEAN_PERIODS
    means = [dist_a / window_s, dist / window_s]
    v_a, v_mean = means
    settled = abs(v_mean - v_a) <= REST_SETTLED_RTOL * abs(v_mean)
    error = 0.0
    if not settled and creep:
        # an irregular creep: the mean of more windows, with its standard error
        for _ in range(REST_MEAN_BLOCKS - 2):
            z_b, m_b, dist, _, ph = run_periods(fsys, z_b, m_b, REST_MEAN_PERIODS,
                                                window=True)
            means.append(dist / window_s)
            phase = phase + ph
        cost.periods += (REST_MEAN_BLOCKS - 2) * REST_MEAN_PERIODS
        v_mean = float(np.mean(means))
        error = float(np.std(means, ddof=1) / math.sqrt(len(means)))
    if energy:
        work = run_periods(fsys, z_a, m_a, REST_MEAN_PERIODS, energy=True)[3]
        cost.periods += REST_MEAN_PERIODS
    else:
        work = np.full(N_WORK, math.nan)
    return v_mean, error, settled, phase, work, z_a, m_a


def _add_held_beside_creep(sp: SlowProblem, fsys, run: _RestRun, out: list[SteadyBranch],
                           shot_held: list[SteadyBranch], energy: bool, cost: _Cost) -> None:
    """Look for a held orbit beside a creep from rest below the slider's velocity ripple.

    A held orbit (the slider rocking with no net travel) can coexist with the creep where
    the averaged ``G(0+) > 0`` and the start from rest creeps, so neither search sees it
    (252 V / 25.64 N / 40 414 Hz: a 15-period creep from rest beside a held orbit with
    Floquet multiplier 0.75). One period shot from the run's end finds it; the hold check
    confirms it, and it joins ``out`` and ``shot_held``.
    """
    try:
        h = shoot(fsys, run.z, run.mode, 1, energy=energy)
    except ChatteringError:
        h = None
    if h is None:
        return
    cost.add(h.periods, h.newton_iterations)
    if h.k == 1 and abs(h.velocity_m_s) <= HELD_M_S and h.multiplier < 1.0:
        cost.periods += 3 * HOLD_CHECK_PERIODS
        if _held_from(sp, fsys, h.z, h.mode)[0]:
            shot_held.append(_full_branch(sp, h, True, False))
            out.append(shot_held[-1])


def _one_dead_zone(sp: SlowProblem, fsys, run: _RestRun, out: list[SteadyBranch],
                   shot_held: list[SteadyBranch], energy: bool,
                   cost: _Cost) -> list[SteadyBranch]:
    """``out`` with one dead zone at most.

    The one a start from rest stays in is the full model's held slider (its least period,
    phases, mean forces and powers, energy= or not): the averaged orbit at 0+ has no slider
    rocking against the guide (:func:`_held_branch`), and the averaged dead zone and the held
    orbits shot from other branches are its twins, so its period does not depend on the path
    that found it (one held orbit of one period at 200 V / 14 N driven at 1 kHz, under loads
    of 0 to 3 N). Beside a motion from rest: a held orbit of the full model where one was
    shot, else the averaged dead zone (the fast orbit at 0+, an infinitely heavy slider).
    """
    if run.held:
        if run.orbit is not None:  # a held orbit, shot
            measured = _full_branch(sp, run.orbit, True, True)
        else:
            measured, more, more_newton = _held_branch(sp, fsys, run.z, run.mode, True,
                                                       energy)
            cost.add(more, more_newton)
        return [b for b in out if b.motion != "dead-zone"] + [measured]
    dead = [b for b in out if b.motion == "dead-zone"]
    if len(dead) > 1:
        keep = next((b for b in dead if any(b is s for s in shot_held)), dead[0])
        return [b for b in out if b.motion != "dead-zone"] + [keep]
    return out
