"""Steady branches of the averaged slow equation: the roots of ``G(v) = load`` and the dead
zone, each with its orbit's phases, forces and powers."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact.results import PHASE_THRESHOLD, classify_motion
from contact.steady.periodic_orbit import orbit_phases, orbit_work
from contact.steady.slow import V_ZERO_M_S, SlowProblem, scan_grid
from contact.transient.event_kernel import N_WORK


@dataclass(frozen=True)
class SteadyBranch:
    """One steady state of the motor.

    Attributes
    ----------
    velocity_m_s : float
        Mean slider velocity (m/s); 0 for the dead zone.
    k : int
        Period multiplicity of the orbit the branch's numbers come from (it repeats every k drive
        periods, its least period); 0 when no orbit was found (period <= 4 for the averaged fast
        problem, <= :data:`contact.steady.exact.REST_MAX_K` for the full model's orbit reached from
        rest) and the averages are long-time means. A held slider's (the dead zone's) at
        ``accuracy="exact"``: the least period of the full model's held orbit, shot from the held
        state a start from rest ends in (0 where that shot fails and a mean stands); the averaged
        orbit's at 0+ only for a dead zone beside a motion reached from rest with no held orbit
        shot, and at the fast level.
    stable : bool
        Whether the slow equation is stable there (``dG/dv < 0``; the dead zone is stable).
    motion : str
        Motion class of the tip orbit (:data:`contact.results.MOTION_CLASSES`) or
        ``"dead-zone"`` (slider held).
    mean_FT_N, mean_FN_N : float
        Period averages of the tangential force on the slider and of the normal force (N),
        integrated exactly over the orbit the branch's numbers come from: the averaged
        (fast) problem's at this velocity, or at ``accuracy="exact"`` the full model's
        (:func:`contact.steady.full_orbit.mean_forces`; a long mean with ``k = 0`` over the window
        of its work integrals). On a full-model orbit whose slider never stops the mean
        tangential force is the guide's kinetic friction plus the load; without separation
        the mean normal force is the preload.
    input_power_W : float
        Mean electrical input power (W): ``<V(t) (A_l du_l + A_b dw_b)>``, the motional
        current times the voltage (the force factors are the current factors by reciprocity).
        At ``accuracy="exact"`` the dead zone a start from rest stays in has the powers of
        the full model's held slider, which rocks with its stuck tip against the guide; a
        dead zone coexisting with a motion reached from rest keeps the averaged orbit's at 0+
        (an infinitely heavy slider, no rocking) unless a held orbit of the full model was
        shot there.
    output_power_W : float
        Mechanical output power ``load_N * velocity_m_s`` (W).
    damping_power_W : float
        Mean power dissipated by the modal damping C_l, C_b (W).
    damping_power_B2_W : float
        B2's share of ``damping_power_W``, ``<C_b dw_b^2>`` (W); L1's is the rest. Each
        mode's mean square modal velocity is its share over its damping
        (:mod:`contact.operating_limits`). NaN where the powers are not computed.
    interface_power_W : float
        Mean power lost at the contact interface (W): what leaves the stator through the tip
        minus what reaches the slider; friction ``<F_T v_rel>`` with ``coupling="consistent"``,
        plus the non-conservative work of the printed coupling with ``coupling="paper"``.
    guide_power_W : float
        Mean power dissipated by the guide friction, ``mu_sd (F_N + M g) |v|`` (W).
    from_rest : bool
        Whether a start from rest reaches this branch (averaged slow dynamics with
        ``accuracy="fast"``, a transient polished by shooting with ``"exact"``).
    phase_fraction : tuple of float
        Fractions of the orbit in stick, slip with v_rel > 0, slip with v_rel < 0, separation.
    velocity_error_m_s : float
        Standard error of ``velocity_m_s`` (m/s) where it is a long-time mean of an irregular motion
        (``k = 0``, from the scatter of :data:`contact.steady.exact.REST_MEAN_BLOCKS` window means);
        0 for an orbit (k >= 1, to the engine's tolerance) and for a mean whose windows agree to
        :data:`contact.steady.exact.REST_SETTLED_RTOL`; NaN where not estimated (the fast level's
        averages).
    """

    velocity_m_s: float
    k: int
    stable: bool
    motion: str
    mean_FT_N: float
    mean_FN_N: float
    input_power_W: float
    output_power_W: float
    damping_power_W: float
    interface_power_W: float
    guide_power_W: float
    from_rest: bool
    phase_fraction: tuple[float, float, float, float] = (math.nan,) * 4
    velocity_error_m_s: float = 0.0
    damping_power_B2_W: float = math.nan

    @property
    def held(self) -> bool:
        """Whether the slider is held: the dead zone, velocity 0."""
        return self.motion == "dead-zone"

    @property
    def tip_motion(self) -> str:
        """Motion class of the orbit's phase fractions alone
        (:data:`contact.results.MOTION_CLASSES`), the vocabulary of transients, of
        ``lusm map``'s points and of ``lusm simulate``: equal to :attr:`motion` except for
        the dead zone, whose held slider's tip sticks to it (``"pure-stick"``; ``"separated"``
        with no preload and no drive), so that a map's branches say what its point says."""
        f = self.phase_fraction
        return classify_motion(f[0], f[1] + f[2], f[3], PHASE_THRESHOLD)

    @property
    def irregular(self) -> bool:
        """A moving motion that repeats with no short period (``k = 0``, not the dead zone):
        its velocity is a long-time mean (:attr:`velocity_error_m_s`), not an orbit's."""
        return self.k == 0 and self.motion != "dead-zone"

    @property
    def efficiency(self) -> float:
        """Output over input power (-), :func:`motor_efficiency` (NaN where the motor does
        not work as a motor, e.g. under a load pushing the slider)."""
        return float(motor_efficiency(self.input_power_W, self.output_power_W))


def motor_efficiency(input_power_W, output_power_W):
    """Output over input power (-), element-wise, where the motor works as a motor
    (electrical power in, mechanical power out); NaN elsewhere: a load pushing the slider
    along, or driving it backward, puts mechanical power in too, and a ratio of the two is no
    efficiency. The rule of :class:`SteadyBranch` and of the speed-thrust characteristic."""
    p_in = np.asarray(input_power_W, dtype=float)
    p_out = np.asarray(output_power_W, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((p_in > 0) & (p_out >= 0), p_out / p_in, np.nan)


def averaged_branch(sp: SlowProblem, v: float, load: float, stable: bool,
            energy: bool = True) -> SteadyBranch:
    """The averaged branch at the root ``v``; without ``energy`` its powers (which take a
    run at :data:`contact.steady.periodic_orbit.ENERGY_STEPS_PER_PERIOD`) are NaN."""
    o = sp.orbit(v)
    span = max(o.k, 1) if o.k else None
    phase_time = orbit_phases(sp.fs, o, sp.average_periods)
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0, 0, 0])
    motion = classify_motion(frac[0], frac[1] + frac[2], frac[3], PHASE_THRESHOLD)
    duration = total if span is None else span * sp.op.period_s
    work = orbit_work(sp.fs, o, sp.average_periods) if energy else np.full(N_WORK, math.nan)
    w_in, w_damp, _, w_ts, w_tx, _, w_damp_b = (float(w) for w in work)
    return SteadyBranch(
        velocity_m_s=float(v), k=o.k, stable=stable, motion=motion, mean_FT_N=o.mean_FT_N,
        mean_FN_N=o.mean_FN_N, input_power_W=w_in / duration,
        output_power_W=load * float(v) + 0.0, damping_power_W=w_damp / duration,
        interface_power_W=-(w_ts + w_tx) / duration,
        guide_power_W=sp.guide_N(o) * abs(float(v)), from_rest=False,
        damping_power_B2_W=w_damp_b / duration,
        phase_fraction=tuple(float(f) for f in frac),
        velocity_error_m_s=0.0 if o.k else math.nan)


def _dead_zone(sp: SlowProblem, load_N: float, energy: bool, from_rest: bool) -> SteadyBranch:
    """The dead zone (slider held, velocity 0) with the averaged orbit at 0+ for its tip."""
    base = averaged_branch(sp, V_ZERO_M_S, load_N, True, energy)
    return dataclasses.replace(base, velocity_m_s=0.0, motion="dead-zone", output_power_W=0.0,
                               guide_power_W=0.0, from_rest=from_rest)


def branches_at_load(sp: SlowProblem, load_N: float, *,
                     energy: bool = True) -> tuple[tuple[SteadyBranch, ...], float]:
    """All steady states of the slow problem under ``load_N`` and the velocity from rest.

    Without ``energy`` the branches' powers are NaN (:func:`_branch`)."""
    found: list[tuple[float, bool]] = []  # (velocity, stable)
    g_pos, g_neg = (g - load_N for g in sp.thrust_at_rest())
    # backward motion needs G(0-) < 0: only then is the negative side searched
    for sign in (1.0, -1.0) if g_neg < 0 else (1.0,):
        vs = sign * scan_grid(sp.v_floor_m_s, sp.v_max_m_s)
        gs = [sp.thrust(v) - load_N for v in vs]
        for i in range(len(vs) - 1):
            if gs[i] * gs[i + 1] < 0:
                root = brentq(lambda v: sp.thrust(v) - load_N, vs[i], vs[i + 1],
                              xtol=1e-12, rtol=sp.root_rtol)
                # stable where M dv/dt = G(v) pushes back towards the root
                falling = (gs[i] > 0) if sign > 0 else (gs[i] < 0)
                found.append((float(root), bool(falling)))
    dead = g_pos <= 0.0 <= g_neg
    if g_pos > 0:
        cands = sorted(v for v, st in found if v > 0 and st)
        v_rest = cands[0] if cands else math.nan
    elif g_neg < 0:
        cands = sorted((v for v, st in found if v < 0 and st), reverse=True)
        v_rest = cands[0] if cands else math.nan
    else:
        v_rest = 0.0
    out = [dataclasses.replace(averaged_branch(sp, v, load_N, st, energy), from_rest=v == v_rest)
           for v, st in found]
    if dead:
        out.append(_dead_zone(sp, load_N, energy, from_rest=v_rest == 0.0))
    out.sort(key=lambda b: b.velocity_m_s)
    return tuple(out), float(v_rest)
