"""Periodic orbits of the full switch model (finite slider mass) by shooting.

The averaged steady state of :mod:`contact.steady.engine` is exact only as the slider mass tends to
infinity. Here the slider velocity joins the shooting variables: Newton on
``P^k(y) - y = 0`` for ``y = (u_l, du_l, w_b, dw_b, dx)`` over k drive periods of the full
model (finite M, guide friction, load), with the finite-difference Jacobian of the
piecewise-affine map, started on an averaged orbit or on the end of a transient. The mean
slider velocity of the orbit is its distance over kT. Components fixed by the mode (``dx = 0``
while the guide holds, ``dx = phi_B(l) dw_b`` in stick) are dropped from the unknowns.

The one-period map reuses :func:`contact.transient.event_kernel.integrate_switch_model`; the
Newton loop runs compiled (:func:`contact.steady.orbit_kernel.shoot_full`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact import state as S
from contact.deferred_signals import call_held
from contact.errors import ChatteringError
from contact.model import HybridSystem, OperatingPoint, build_system
from contact.steady import orbit_kernel
from contact.steady.periodic_orbit import (
    Stepping,
    integrating_systems,
    propagator_ladder,
    run_whole_periods,
    steps_for,
)
from contact.transient import event_kernel
from rom.params import MotorParams


@dataclass(frozen=True)
class FullSystem(Stepping):
    """The full model of one operating point with its one-step propagators, stepped as
    :class:`contact.steady.periodic_orbit.Stepping` says (``fine`` also caches the
    force-integrating twins of :func:`mean_forces`)."""

    system: HybridSystem
    phi: np.ndarray
    phi_half: np.ndarray


def full_system(params: MotorParams, op: OperatingPoint, mu_d_eff: float,
                coupling: str = "paper", steps_per_period: int | None = None) -> FullSystem:
    """Build the full model (load included) for shooting (steps per period as
    :func:`contact.steady.periodic_orbit.steps_for`)."""
    sys_ = build_system(params, op, mu_d_eff, coupling)
    n = steps_for(sys_, op.period_s, steps_per_period)
    dt = op.period_s / n
    phi, half, fine = propagator_ladder(sys_, op.period_s, n)
    fs = FullSystem(sys_, phi, half, dt_s=dt, period_s=op.period_s, phi_Bl=params.phi_Bl,
                    steps_per_period=n)
    if fine is not None:
        fs.fine["phi"] = fine
    return fs


def run_periods(fs: FullSystem, z: np.ndarray, mode: int, periods: int, energy: bool = False,
                window: bool | None = None):
    """Advance ``periods`` drive periods; returns ``(z_end, mode_end, distance_m, work,
    phase_time)`` with the position slot reset to 0 at the start (work is accumulated, and
    non-zero, only when ``energy``, at a step of at most ``T / ENERGY_STEPS_PER_PERIOD``;
    phase time only with ``window``, default ``energy``;
    :func:`contact.steady.periodic_orbit.run_whole_periods`)."""
    return run_whole_periods(fs.system, z, mode, periods, steps=fs.steps_per_period,
                             period_s=fs.period_s, phi=fs.phi, half=fs.phi_half, fine=fs.fine,
                             key="phi", energy=energy,
                             window=energy if window is None else window,
                             what="the full-model shooting")[:5]


def _consistent(fs: FullSystem, z: np.ndarray, mode: int) -> np.ndarray:
    z = np.array(z, dtype=float)
    orbit_kernel.full_consistent(z, int(mode), float(fs.phi_Bl))
    return z


@dataclass(frozen=True)
class FullOrbit:
    """A k-periodic orbit of the full model.

    Attributes
    ----------
    velocity_m_s : float
        Mean slider velocity over the orbit (m/s).
    k : int
        Drive periods per orbit, the least period (:func:`least_period`); 0 if shooting did
        not converge.
    z : ndarray
        Start state; ``mode`` its mode.
    residual : float
        Scaled periodicity defect.
    periods, newton_iterations : int
        Work spent.
    work : ndarray
        Work integrals over the orbit (J), see :mod:`contact.transient.event_kernel`.
    phase_time : ndarray
        Time in stick, slip+, slip-, separation over the orbit (s).
    multiplier : float
        Largest modulus of the eigenvalues of the last Newton Jacobian, taken to the k-period
        map (Floquet multiplier): < 1 means the orbit is stable.
    mean_FT_N, mean_FN_N : float
        Means over the orbit of the tangential force on the slider and of the normal force
        (N), integrated exactly (:func:`mean_forces`); NaN if shooting did not converge.
    """

    velocity_m_s: float
    k: int
    z: np.ndarray
    mode: int
    residual: float
    periods: int
    newton_iterations: int
    work: np.ndarray
    phase_time: np.ndarray
    multiplier: float
    mean_FT_N: float = np.nan
    mean_FN_N: float = np.nan


_Y = [S.U, S.DU, S.W, S.DW, S.DX]
"""State slots of the shooting unknowns ``y = (u_l, du_l, w_b, dw_b, dx)``."""


def _scale(fs: FullSystem, z: np.ndarray) -> np.ndarray:
    """The shooting's scale of each unknown at the state ``z`` (its defect is measured in it)."""
    amp = np.array([abs(z[S.U]), 0.0, abs(z[S.W]), 0.0, 0.0]) + 1e-12
    omega = 2 * np.pi / fs.period_s
    amp[1], amp[3] = omega * amp[0], omega * amp[2]
    amp[4] = max(abs(z[S.DX]), fs.phi_Bl * amp[3] * 1e-3, 1e-9)
    return amp


def shoot(fs: FullSystem, z0: np.ndarray, mode0: int, k: int, *, tol: float = 1e-10,
          max_newton: int = 25, energy: bool = True) -> FullOrbit:
    """Newton on the k-period map of the full model from ``(z0, mode0)``.

    The orbit's work integrals take a run at
    :data:`contact.steady.periodic_orbit.ENERGY_STEPS_PER_PERIOD` steps per period; without
    ``energy`` they are NaN (the phase times are kept). A converged orbit reports its least
    period (:func:`least_period`), over which its velocity, work, phase times and mean forces
    are taken: a shot over ``k`` periods converges to any orbit whose period divides ``k``."""
    z, mode = _consistent(fs, np.asarray(z0, dtype=float), int(mode0)), int(mode0)
    amp = _scale(fs, z)
    s = fs.system
    code, z, mode, res, periods, it, jac, free = call_held(orbit_kernel.shoot_full,
        z, mode, int(k), amp, float(fs.phi_Bl), fs.steps_per_period, fs.dt_s, fs.phi,
        fs.phi_half, s.A, s.ev_h, s.ev_dh, s.ev_type, s.fn_m, s.ft_m, s.ff_m, s.funcs,
        s.scalars, float(tol), int(max_newton))
    if code == orbit_kernel.CHATTER:
        raise ChatteringError("contact chattering in the full-model shooting")
    mode, periods, it = int(mode), int(periods), int(it)
    sub = jac[np.ix_(free, free)]
    mult = (float(np.max(np.abs(np.linalg.eigvals(sub))))
            if free.any() and np.all(np.isfinite(sub)) else np.nan)
    converged = res <= tol
    z = _consistent(fs, z, mode)
    forces = (np.nan, np.nan)
    if converged:
        d, more = least_period(fs, z, mode, k)
        # the k-period map is the d-period map to the power k / d: so are its eigenvalues
        mult = mult ** (d / k) if d < k else mult
        k = d
        forces = mean_forces(fs, z, mode, k)
        periods += more + 2 * k
    _, _, dist, work, phase_time = run_periods(fs, z, mode, k, energy=energy, window=True)
    if not energy:
        work = np.full(event_kernel.N_WORK, np.nan)
    periods += k
    return FullOrbit(dist / (k * fs.period_s), k if converged else 0, z, mode, res, periods,
                     it, work, phase_time, mult, *forces)


LEAST_PERIOD_TOL = 1e-8
"""Scaled defect (as the shooting's) within which a shot k-period orbit repeats after a
divisor d of k, and so has the least period d (:func:`least_period`): a hundred times the
shooting's own tolerance; an orbit whose least period is k misses it by its own size."""


def least_period(fs: FullSystem, z: np.ndarray, mode: int, k: int) -> tuple[int, int]:
    """The least period (drive periods) of the k-periodic orbit through ``(z, mode)``: the
    smallest divisor d of ``k`` after which its state repeats (:data:`LEAST_PERIOD_TOL`).
    Returns ``(d, periods run)``.

    A k-period shot converges to any orbit whose period divides k: from the averaged orbit
    of period 3 at 200 V / 14 N driven at 1 kHz it converges to the held slider's orbit of
    one period, which must not be reported with k = 3 at one load and k = 1 at the next."""
    amp = _scale(fs, z)
    y0 = z[_Y]
    spent = 0
    for d in range(1, k):
        if k % d:
            continue
        z1, m1, _, _, _ = run_periods(fs, z, mode, d)
        spent += d
        z1 = _consistent(fs, z1, m1)
        if m1 == mode and np.max(np.abs(z1[_Y] - y0) / amp) <= LEAST_PERIOD_TOL:
            return d, spent
    return k, spent


def mean_forces(fs: FullSystem, z: np.ndarray, mode: int, periods: int) -> tuple[float, float]:
    """Period means ``(F_T, F_N)`` (N) of the tangential force on the slider and the normal
    force over ``periods`` drive periods of the full model from ``(z, mode)``.

    The model's integrating twins (:func:`contact.steady.periodic_orbit.integrating_systems`, as the
    fast problem integrates its forces) run the same trajectory with the position slot
    integrating each force: exact propagators and located events, at the shooting's step. They
    are built on first use and cached with the system."""
    if "forces" not in fs.fine:
        ft_sys, fn_sys, ft_phi, fn_phi, _ = integrating_systems(
            fs.system, fs.period_s, fs.steps_per_period, fixed_velocity=False)
        fs.fine["forces"] = ((ft_sys, ft_phi), (fn_sys, fn_phi))
    means = []
    for sys_, (phi, half) in fs.fine["forces"]:
        # no work integrals: no finer propagators, so no cache key is read
        x = run_whole_periods(sys_, z, mode, periods, steps=fs.steps_per_period,
                              period_s=fs.period_s, phi=phi, half=half, fine={}, key="",
                              what="the full model's force integrals")[2]
        means.append(x / (periods * fs.period_s))
    return float(means[0]), float(means[1])
