"""The fast problem: the periodic stator-tip orbit at a fixed slider velocity (M -> infinity).

With the slider velocity held at ``v`` the switch model of :mod:`contact.model` is a hybrid
system of the stator alone, forced with the drive period T. Its steady state is a periodic
orbit; within each contact mode the flow is linear, so the one-period map is piecewise affine.
The orbit is found by shooting: a few periods simulated period by period (none when the
search continues from a neighbouring orbit), then Newton on ``P(y) - y = 0`` for
``y = (u_l, du_l, w_b, dw_b)`` with the Jacobian of the piecewise-affine map by finite
differences (exact inside one mode sequence), reused and corrected by Broyden's updates,
falling back to period-by-period iteration when Newton does not contract; period-k orbits are
detected from the iterates. The search loop runs compiled
(:func:`contact.steady.orbit_kernel.search_orbit`).

The one-period map reuses the event-located kernel :func:`contact.transient.event_kernel.
integrate_switch_model` on a modified system: the slider row of every generator is zeroed
(``dx = v`` exactly) and the slider-position row integrates a force (``dx_state/dt = F``), so
the kernel's exact propagators return the exact period integral of F_T (or F_N) in the
position slot; guide friction is left out of the fast problem (it enters the slow equation).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from contact import state as S
from contact.deferred_signals import call_held
from contact.errors import ChatteringError
from contact.expm import expm_stack
from contact.model import HybridSystem, OperatingPoint, build_system
from contact.steady import orbit_kernel
from contact.transient import event_kernel
from rom.params import MotorParams

STEPS_PER_PERIOD = 25
"""Fixed steps per drive period (dt = T / 25 = 1e-6 s at 40 kHz; the transient default is
1e-7 s). The kernel's propagators are exact and its events located inside a step, so the
step only sets the error of the event location: the steady velocity at 25 steps agrees with
the 250-step one to a few 1e-8 (``python -m tools.doc_tables --update
steady_work_precision``, docs/steady.md)."""

ENERGY_STEPS_PER_PERIOD = 250
"""Steps per period of the runs that integrate the work (power) of an orbit: the kernel's work
integrals use Simpson's rule per step, whose relative error ~ (omega dt)^4 / 2880 is about
1e-6 at 25 steps per period and 1e-10 at 250 (the energy balance closes to 1e-8)."""

NEWTON_MAX = 12
"""Newton steps at most per orbit search."""

NEWTON_FAILURES = 3
"""Failed Newton steps in a row after which the search goes period by period."""

SEARCH_PERIODS = 120
"""Drive periods at most that :func:`find_orbit` spends looking for an orbit of period
<= ``max_k`` (warm-up, Newton's runs and the period-by-period watch)."""

AVERAGE_PERIODS = 80
"""Drive periods the averages of an orbit without a short period (``k = 0``) are taken over,
after the search (long stick phases dragged by the slider at low speed)."""

CHUNK_PERIODS = 80
"""Periods run in one kernel call between the watches for period-k repetition once Newton
has given up (slowly converging or long-period orbits at low slider speed)."""

@dataclass(frozen=True, kw_only=True)
class Stepping:
    """How a propagated system of the steady engine steps through a drive period: the part
    :class:`FastSystem` and :class:`contact.steady.full_orbit.FullSystem` share (keyword
    arguments, after each one's own).

    Attributes
    ----------
    dt_s, period_s : float
        Step (s) and drive period (s).
    phi_Bl : float
        Bending slope factor at the tip phi_B(l) (-), as in :class:`rom.params.MotorParams`.
    steps_per_period : int
        Fixed steps per drive period of the kernel.
    fine : dict
        Cache of the propagators at :data:`ENERGY_STEPS_PER_PERIOD` (built on first use).
    """

    dt_s: float
    period_s: float
    phi_Bl: float
    steps_per_period: int = 0
    fine: dict = field(default_factory=dict, compare=False, repr=False)


@dataclass(frozen=True)
class FastSystem(Stepping):
    """The stator-only hybrid system at fixed slider velocity (built by :func:`fast_system`),
    stepped as :class:`Stepping` says.

    Attributes
    ----------
    ft_system, fn_system : HybridSystem
        Same modes; the position slot integrates F_T (N s) or F_N (N s).
    phi_ft, phi_half_ft, phi_fn, phi_half_fn : ndarray
        One-step and half-step propagators ``expm(A dt)`` of each system (they differ only
        in the X row).
    """

    ft_system: HybridSystem
    fn_system: HybridSystem
    phi_ft: np.ndarray
    phi_half_ft: np.ndarray
    phi_fn: np.ndarray
    phi_half_fn: np.ndarray


def _integrating(system: HybridSystem, rows: np.ndarray, fixed_velocity: bool) -> HybridSystem:
    a = system.A.copy()
    if fixed_velocity:
        a[:, S.DX, :] = 0.0  # the slider velocity is a parameter of the fast problem
    a[:, S.X, :] = rows  # the position slot integrates a force over time
    ev_dh = np.matmul(system.ev_h, a)  # as in build_system
    return dataclasses.replace(system, A=a, ev_dh=ev_dh)


def integrating_systems(system: HybridSystem, period_s: float, steps: int, *,
                        fixed_velocity: bool, fine: bool = True):
    """The twins of ``system`` whose position slot integrates F_T and F_N (N s), with their
    propagators at ``steps`` per period from one matrix exponential per mode.

    Nothing in the switch model reads the slider position (its column of every generator is
    zero), so the twins run the same trajectory as ``system`` and the kernel's exact
    propagators return the exact time integral of the force over the run in that slot.
    ``fixed_velocity``: the slider rows are zeroed too (the fast problem, ``dx = v``).

    Returns ``(ft_system, fn_system, (phi_ft, half_ft), (phi_fn, half_fn), fine_ft)``:
    ``fine_ft`` the F_T twin's propagators at :data:`ENERGY_STEPS_PER_PERIOD` (None as in
    :func:`propagator_ladder`).
    """
    ft_sys = _integrating(system, system.ft_m, fixed_velocity)
    fn_sys = _integrating(system, system.fn_m, fixed_velocity)
    # both twins differ only in the x row, which nothing reads: one exponential of the
    # generator bordered by the F_N row gives both propagator sets
    bordered = np.zeros((S.N_MODES, S.N_STATE + 1, S.N_STATE + 1))
    bordered[:, :S.N_STATE, :S.N_STATE] = ft_sys.A
    bordered[:, S.N_STATE, :S.N_STATE] = fn_sys.A[:, S.X, :]
    phi_b, half_b, fine_b = _ladder(bordered, period_s, steps, fine)
    phi_ft, phi_fn = _split(phi_b)
    half_ft, half_fn = _split(half_b)
    fine_ft = None if fine_b is None else (_split(fine_b[0])[0], _split(fine_b[1])[0])
    return ft_sys, fn_sys, (phi_ft, half_ft), (phi_fn, half_fn), fine_ft


def fast_system(params: MotorParams, op: OperatingPoint, mu_d_eff: float,
                coupling: str = "paper", steps_per_period: int | None = None) -> FastSystem:
    """Build the fixed-velocity fast problem of one operating point (load and guide excluded).

    ``steps_per_period`` defaults to :data:`STEPS_PER_PERIOD`, raised where the fastest mode
    needs it (:func:`steps_for`).
    """
    base = fast_base_system(params, op, mu_d_eff, coupling)
    n = steps_for(base, op.period_s, steps_per_period)
    dt = op.period_s / n
    ft_sys, fn_sys, (phi_ft, half_ft), (phi_fn, half_fn), fine_ft = integrating_systems(
        base, op.period_s, n, fixed_velocity=True)
    fs = FastSystem(ft_sys, fn_sys, phi_ft, half_ft, phi_fn, half_fn, dt_s=dt,
                    period_s=op.period_s, phi_Bl=params.phi_Bl, steps_per_period=n)
    if fine_ft is not None:
        fs.fine["ft"] = fine_ft
    return fs


def fast_base_system(params: MotorParams, op: OperatingPoint, mu_d_eff: float,
                     coupling: str = "paper") -> HybridSystem:
    """The contact model the fast problem starts from (:func:`fast_system`), before its
    fixed-velocity integrating systems are made: the system whose modes :func:`steps_for`
    counts the steps per drive period on.

    Parameters
    ----------
    params : MotorParams
    op : OperatingPoint
        The load is dropped (the fast problem has none).
    mu_d_eff : float
        Dynamic friction coefficient in slip (-).
    coupling : {"paper", "consistent"}

    Returns
    -------
    HybridSystem
    """
    # an effectively infinite slider with a frictionless guide: stick forces take their
    # M -> infinity form; the slider row is zeroed in the integrating systems anyway
    p_inf = params.with_(M_slider=1e12, mu_sd=0.0)
    op0 = OperatingPoint(op.voltage_V, op.preload_N, op.frequency_Hz)
    return build_system(p_inf, op0, mu_d_eff, coupling)


def _power(stack: np.ndarray, k: int) -> np.ndarray:
    """``stack[i] ** k`` (matrix power, k >= 1) by repeated squaring."""
    out, base = None, stack
    while k:
        if k & 1:
            out = base if out is None else np.matmul(out, base)
        k >>= 1
        if k:
            base = np.matmul(base, base)
    return out


def _split(bordered: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The F_T and F_N systems' propagators from those of the bordered generator (the x
    column of both generators is zero, so its exponential's x-x entry is 1 in both)."""
    n = S.N_STATE
    ft = np.ascontiguousarray(bordered[:, :n, :n])
    fn = ft.copy()
    fn[:, S.X, :] = bordered[:, n, :n]
    fn[:, S.X, S.X] = 1.0
    return ft, fn


def propagator_ladder(system: HybridSystem, period_s: float, steps: int, *, fine: bool = True):
    """One-step and half-step propagators at ``steps`` per period, and (``fine``) at
    :data:`ENERGY_STEPS_PER_PERIOD`, from one matrix exponential per mode.

    Returns ``(phi, phi_half, fine_pair)``: ``fine_pair = (phi_fine, phi_half_fine)`` or None
    when the energy step is not a finer multiple of ``steps`` (or ``fine`` is False). The
    coarser propagators are integer powers of ``expm(A dt_fine / 2)``: exact in exact
    arithmetic, a few roundoffs apart from the direct exponentials.
    """
    return _ladder(system.A, period_s, steps, fine)


def _ladder(a: np.ndarray, period_s: float, steps: int, fine: bool):
    """:func:`propagator_ladder` of the generator stack ``a``."""
    ratio = ENERGY_STEPS_PER_PERIOD // steps
    if fine and ratio >= 2 and ratio % 2 == 0 and ratio * steps == ENERGY_STEPS_PER_PERIOD:
        half_f = expm_stack(a * (0.5 * period_s / ENERGY_STEPS_PER_PERIOD))
        phi_f = np.matmul(half_f, half_f)
        half = _power(phi_f, ratio // 2)
        return np.matmul(half, half), half, (phi_f, half_f)
    half = expm_stack(a * (0.5 * period_s / steps))
    return np.matmul(half, half), half, None


def steps_for(system: HybridSystem, period_s: float, steps_per_period: int | None = None) -> int:
    """Steps per drive period: ``steps_per_period`` (default :data:`STEPS_PER_PERIOD`), at
    least as many as keep ``rho(A) dt <= 1`` over all modes (the bound the transient scheme
    checks: the kernel's Taylor flow of partial steps is exact to roundoff below it)."""
    n = STEPS_PER_PERIOD if steps_per_period is None else int(steps_per_period)
    return max(n, int(np.ceil(spectral_radius(system.A) * period_s)))


def spectral_radius(a: np.ndarray) -> float:
    """Largest eigenvalue modulus (1/s) over a stack of mode generators.

    The drive rows (``sin, cos, 1``) of every generator read only the drive slots, so each
    generator is block triangular: its eigenvalues are those of the mechanical block
    (``u_l .. dx``) and ``+-i omega, 0`` of the drive block, whose modulus is the rotation
    rate of its ``sin``/``cos`` pair (``tests/test_steady.py`` checks this against the whole
    matrices' eigenvalues).
    """
    mech = np.abs(np.linalg.eigvals(a[:, :S.SIN, :S.SIN]))
    return float(max(np.max(mech), np.max(np.abs(a[:, S.SIN, S.COS]))))


def run_whole_periods(system: HybridSystem, z: np.ndarray, mode: int, periods: int, *,
                      steps: int, period_s: float, phi: np.ndarray, half: np.ndarray,
                      fine: dict, key: str, energy: bool = False, window: bool = False,
                      what: str = "the fixed-velocity fast problem"):
    """Advance ``system`` by whole drive periods from ``z`` (position slot reset to 0).

    ``steps`` per period with the one- and half-step propagators ``phi``, ``half``; with
    ``energy`` the step is refined to :data:`ENERGY_STEPS_PER_PERIOD` (work integrals need
    it), whose propagators are cached in ``fine[key]``. The kernel's window (phase times,
    and the work integrals with ``energy``) is opened only with ``window``: it triples the
    cost of a step.

    Returns ``(z_end, mode_end, x_end, work, phase_time, events)``: ``x_end`` is what the
    position slot accumulated (the slider distance (m), or a force's time integral (N s) in
    an integrating system), ``work`` the kernel's work integrals (J), ``phase_time`` the time
    per phase (s); both zero when not asked for.

    Raises
    ------
    contact.errors.ChatteringError
        If the kernel chatters (``what`` names the problem).
    """
    dt = period_s / steps
    if energy and steps < ENERGY_STEPS_PER_PERIOD:
        steps, dt = ENERGY_STEPS_PER_PERIOD, period_s / ENERGY_STEPS_PER_PERIOD
        if key not in fine:
            fine[key] = system.propagators(dt)
        phi, half = fine[key]
    z = np.array(z, dtype=float)
    z[S.X] = 0.0
    n = steps * periods
    out = call_held(event_kernel.integrate_switch_model,
        z, mode, n, dt, phi, half, system.A, system.ev_h, system.ev_dh, system.ev_type,
        system.fn_m, system.ft_m, system.ff_m, system.funcs, system.scalars,
        0 if window else n, n, 1, energy, 64, np.empty(0, np.int64), np.empty(0))
    status, _, _, _, phase_time, work, stats, z_end, mode_end = out
    if status != S.OK:
        raise ChatteringError(f"contact chattering in {what}")
    z_end = z_end.copy()
    x_end = float(z_end[S.X])
    z_end[S.X] = 0.0
    return z_end, int(mode_end), x_end, work.copy(), phase_time.copy(), int(stats[3])


def period_map(fs: FastSystem, z: np.ndarray, mode: int, periods: int = 1, *,
               integrand: str = "ft", energy: bool = False, window: bool | None = None):
    """Advance the fast problem by whole periods from ``z`` (x slot reset to 0).

    Returns ``(z_end, mode_end, integral, work, phase_time, events)`` where ``integral`` is
    the time integral of F_T or F_N (N s) over the periods, ``work`` the kernel's work
    integrals (J) when ``energy`` and ``phase_time`` the time per phase (s) when ``window``
    (default: ``energy``); both are zero otherwise (:func:`run_whole_periods`).
    """
    sys_, phi, half = ((fs.ft_system, fs.phi_ft, fs.phi_half_ft) if integrand == "ft"
                       else (fs.fn_system, fs.phi_fn, fs.phi_half_fn))
    return run_whole_periods(sys_, z, mode, periods, steps=fs.steps_per_period,
                             period_s=fs.period_s, phi=phi, half=half, fine=fs.fine,
                             key=integrand, energy=energy,
                             window=energy if window is None else window)


@dataclass(frozen=True)
class Orbit:
    """A periodic orbit of the fast problem at slider velocity ``velocity_m_s``.

    Attributes
    ----------
    velocity_m_s : float
        Fixed slider velocity v (m/s).
    k : int
        Period multiplicity (the orbit repeats every k drive periods); 0 if not converged.
    z : ndarray, shape (9,)
        State at the start of the orbit (drive phase 0).
    mode : int
        Mode at the start.
    mean_FT_N, mean_FN_N : float
        Exact time averages of F_T (tangential force on the slider) and F_N over k periods (N).
    residual : float
        Scaled periodicity defect ``|P^k(y) - y|`` (relative to the orbit amplitude).
    periods : int
        Drive periods simulated to find it (Newton's finite-difference runs included).
    newton_iterations : int
    phase_time : ndarray, shape (4,)
        Time in stick, slip+, slip-, separation over the k periods (s); zero for ``k = 0``
        (:func:`orbit_phases` computes them over the averaging periods).
    work : ndarray, shape (6,)
        Work integrals of :mod:`contact.transient.event_kernel` over the k periods (J); zero unless
        asked for (:func:`find_orbit` ``energy=True``, or :func:`orbit_work`).
    jacobian : tuple or None
        ``(J, mode)``: the last finite-difference Jacobian of the one-period map in
        ``(u_l, du_l, w_b, dw_b)`` (-) and the mode it belongs to, for continuation.
    """

    velocity_m_s: float
    k: int
    z: np.ndarray
    mode: int
    mean_FT_N: float
    mean_FN_N: float
    residual: float
    periods: int
    newton_iterations: int
    phase_time: np.ndarray
    work: np.ndarray
    jacobian: tuple | None = None


def _start(fs: FastSystem, v: float) -> tuple[np.ndarray, int]:
    sys_ = fs.ft_system
    z = sys_.z0.copy()
    z[S.DX] = v
    guide = S.FORWARD if v >= 0 else S.BACKWARD
    tip = S.SLIP_NEG if v > 0 else S.SLIP_POS
    contact = S.CONTACT if float(sys_.funcs[S.F_FN] @ z) > 0 else S.SEPARATED
    return z, S.mode_index(contact, tip, guide)


def find_orbit(fs: FastSystem, v: float, z0: np.ndarray | None = None, mode0: int | None = None,
               *, tol: float = 1e-11, max_periods: int = SEARCH_PERIODS, warmup: int = 20,
               max_k: int = 4, average_periods: int = AVERAGE_PERIODS, energy: bool = False,
               jacobian: tuple | None = None) -> Orbit:
    """Periodic orbit of the fast problem at slider velocity ``v`` (m/s) by shooting.

    ``z0, mode0`` (e.g. the orbit at a neighbouring velocity) start the search without the
    ``warmup`` periods, which only a fresh start from rest runs. When no
    orbit of period <= ``max_k`` is found within ``max_periods`` periods the averages are
    taken over the next ``average_periods`` periods and ``k`` is 0. The work integrals
    (:func:`orbit_work`) are computed only with ``energy``. ``jacobian`` (the
    :attr:`Orbit.jacobian` of a neighbouring orbit) starts a chord Newton iteration.
    """
    if z0 is None or mode0 is None:
        z, mode = _start(fs, v)
    else:
        z, mode = np.array(z0, dtype=float), int(mode0)
        guide = S.FORWARD if v >= 0 else S.BACKWARD
        contact = mode // 9
        tip = (mode // 3) % 3
        vrel = fs.phi_Bl * z[S.DW] - v
        if contact == S.CONTACT and tip != S.STICK:
            tip = S.SLIP_POS if vrel > 0 else S.SLIP_NEG
        mode = S.mode_index(contact, tip, guide)
        try:  # a neighbouring orbit needs no warm-up: Newton starts from it
            orbit = _find(fs, v, z, mode, tol, max_periods, 0, max_k, average_periods,
                          jacobian)
            return dataclasses.replace(orbit, work=orbit_work(fs, orbit)) if energy else orbit
        except ChatteringError:  # a start the kernel cannot leave cleanly: start afresh
            z, mode = _start(fs, v)
    orbit = _find(fs, v, z, mode, tol, max_periods, warmup, max_k, average_periods)
    return dataclasses.replace(orbit, work=orbit_work(fs, orbit)) if energy else orbit


def _find(fs: FastSystem, v: float, z: np.ndarray, mode: int, tol: float, max_periods: int,
          warmup: int, max_k: int, average_periods: int, jac0=None) -> Orbit:
    jac_in, jac_mode_in = ((np.zeros((4, 4)), -1) if jac0 is None
                           else (np.array(jac0[0], dtype=float), int(jac0[1])))
    s, f = fs.ft_system, fs.fn_system
    (code, k_found, z, mode, res, periods, newton_it, int_ft, int_fn, phase_time, jac,
     jac_mode) = call_held(orbit_kernel.find_orbit_compiled,
        np.asarray(z, dtype=float), int(mode), float(v), float(fs.phi_Bl), float(fs.period_s),
        int(warmup), fs.steps_per_period, fs.dt_s, fs.phi_ft, fs.phi_half_ft, s.A, s.ev_h,
        s.ev_dh, s.ev_type, s.fn_m, s.ft_m, s.ff_m, s.funcs, s.scalars, fs.phi_fn,
        fs.phi_half_fn, f.A, f.ev_dh, float(tol), int(max_periods), int(max_k), CHUNK_PERIODS,
        jac_in, jac_mode_in, NEWTON_MAX, NEWTON_FAILURES, int(average_periods))
    if code == orbit_kernel.CHATTER:
        raise ChatteringError("contact chattering in the fixed-velocity fast problem")
    k_found, jac_mode = int(k_found), int(jac_mode)
    # no k-periodic orbit found (k = 0): the average over many periods (quasi-periodic or
    # long-period stick-slip at the tip) stands in
    span = (k_found if k_found else average_periods) * fs.period_s
    return Orbit(float(v), k_found, z, int(mode), float(int_ft) / span, float(int_fn) / span,
                 float(res), int(periods), int(newton_it), phase_time,
                 np.zeros(event_kernel.N_WORK), None if jac_mode < 0 else (jac, jac_mode))


def orbit_phases(fs: FastSystem, orbit: Orbit,
                 average_periods: int = AVERAGE_PERIODS) -> np.ndarray:
    """Time in stick, slip+, slip-, separation (s) over the orbit's k periods, or for ``k = 0``
    over the ``average_periods`` periods its averages were taken on."""
    if orbit.k:
        return orbit.phase_time
    return period_map(fs, orbit.z, orbit.mode, average_periods, window=True)[4]


def orbit_work(fs: FastSystem, orbit: Orbit, average_periods: int = AVERAGE_PERIODS) -> np.ndarray:
    """Work integrals (J) of :mod:`contact.transient.event_kernel` over the orbit's k periods, at
    :data:`ENERGY_STEPS_PER_PERIOD` steps per period (for ``k = 0`` over the
    ``average_periods`` periods the averages were taken on, at the orbit's own step)."""
    if orbit.k:
        return period_map(fs, orbit.z, orbit.mode, orbit.k, energy=True)[3]
    span = average_periods
    sys_ = fs.ft_system
    z = np.array(orbit.z, dtype=float)
    z[S.X] = 0.0
    n = fs.steps_per_period * span
    out = call_held(event_kernel.integrate_switch_model,
        z, orbit.mode, n, fs.dt_s, fs.phi_ft, fs.phi_half_ft, sys_.A, sys_.ev_h, sys_.ev_dh,
        sys_.ev_type, sys_.fn_m, sys_.ft_m, sys_.ff_m, sys_.funcs, sys_.scalars, 0, n, 1, True,
        64, np.empty(0, np.int64), np.empty(0))
    return out[5].copy()
