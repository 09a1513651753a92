"""The event-located switch-model kernel (numba): plain arrays and floats in and out.

The integrator advances the piecewise-linear hybrid system of :mod:`contact.model` on a fixed
time grid with the exact propagator ``expm(A_m dt)`` of the current mode. When a switching
functional ``h . z`` becomes positive inside a step (or grazes zero between two samples, seen
from the cubic Hermite interpolant of ``h`` and ``dh/dt``), the crossing is located (cubic
estimate, then Newton on the exact Taylor-series flow), the state is advanced to it, the mode
is switched by the rules of the switch model, and the rest of the step is integrated in the
new mode. So the mode is state carried between steps, the stick band of the paper is never
needed, and the only time-step dependence left is roundoff and the resolution of events that
are closer together than a step.

The thin typed wrapper is :func:`contact.simulate.simulate` with ``method="event"``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from contact import state as state_module
from contact.numba_cache import depend_on
from contact.state import (
    BACKWARD,
    CONTACT,
    COS,
    DU,
    DW,
    DX,
    ERR_CHATTER,
    EV_CONTACT,
    EV_GUIDE_RELEASE,
    EV_NONE,
    EV_SEPARATE,
    EV_STICK_BREAK,
    EV_VREL_ZERO,
    EV_XDOT_ZERO,
    F_FN,
    F_HOLD,
    F_NG_CONTACT,
    F_NG_SEP,
    F_VREL,
    FORWARD,
    HELD,
    MAX_EVENTS,
    N_STATE,
    OK,
    ONE,
    PHASE_SEPARATION,
    SC_ABV,
    SC_ALV,
    SC_C_B,
    SC_C_L,
    SC_EPS,
    SC_GAMMA_N,
    SC_GAMMA_T,
    SC_K,
    SC_K_B,
    SC_K_L,
    SC_LOAD,
    SC_M,
    SC_M_B,
    SC_M_L,
    SC_MU_D,
    SC_MU_S,
    SC_MU_SD,
    SC_PHI_BL,
    SC_PHI_LL,
    SEPARATED,
    SIN,
    SLIP_NEG,
    SLIP_POS,
    STICK,
    U,
    W,
    X,
)

STICK_FORWARD = CONTACT * 9 + STICK * 3 + FORWARD
STICK_BACKWARD = CONTACT * 9 + STICK * 3 + BACKWARD

N_TAYLOR = 18
"""Taylor terms of expm(A tau) z in partial steps: error < 1e-17 for |lambda tau| <= 1."""

N_TRACE_COLS = 10
"""Trace columns: t, x, dx, u_l, w_b, F_N, F_T, v_rel, y_tip, phase."""

N_WORK = 7
"""Work integrals: input, damping, normal on stator, tangential on stator, on slider, guide,
and B2's share of the damping (``C_b dw_b^2``; L1's is the damping's rest), from which
:mod:`contact.operating_limits` takes each mode's vibration amplitude."""


@njit(cache=True, inline="always")
def _dot(a, z):
    s = 0.0
    for i in range(N_STATE):
        s += a[i] * z[i]
    return s


@njit(cache=True, inline="always")
def _matvec(m, z, out):
    # rows SIN, COS, ONE of every generator and propagator only rotate the drive phase and
    # keep the constant: skipping their structural zeros saves a third of the work
    for i in range(SIN):
        s = 0.0
        for j in range(N_STATE):
            s += m[i, j] * z[j]
        out[i] = s
    out[SIN] = m[SIN, SIN] * z[SIN] + m[SIN, COS] * z[COS]
    out[COS] = m[COS, SIN] * z[SIN] + m[COS, COS] * z[COS]
    out[ONE] = m[ONE, ONE] * z[ONE]


@njit(cache=True)
def _flow(a, z, tau, out, term, tmp):
    """``out = expm(a tau) z`` by its Taylor series (tau is a fraction of one step).

    Terms are added until each one is below 1e-17 of the sum in every component (or
    :data:`N_TAYLOR` terms): about 9 terms at 40 kHz and dt = 1e-7 s.
    """
    for i in range(N_STATE):
        term[i] = z[i]
        out[i] = z[i]
    for k in range(1, N_TAYLOR + 1):
        _matvec(a, term, tmp)
        f = tau / k
        converged = True
        for i in range(N_STATE):
            term[i] = tmp[i] * f
            out[i] += term[i]
            if abs(term[i]) > 1e-17 * abs(out[i]):
                converged = False
        if converged:
            break


@njit(cache=True)
def _cubic(a, b, c, d, s):
    return a + s * (b + s * (c + s * d))


@njit(cache=True)
def _hermite_extremum(y0, y1, d0, d1, h):
    """Value at the interior critical point of the cubic Hermite interpolant on [0, h]."""
    a = y0
    b = h * d0
    c = 3.0 * (y1 - y0) - 2.0 * h * d0 - h * d1
    d = 2.0 * (y0 - y1) + h * d0 + h * d1
    # p'(s) = b + 2 c s + 3 d s^2 = 0, the root between the slopes of opposite sign
    if d == 0.0:
        s = -b / (2.0 * c) if c != 0.0 else 0.0
    else:
        disc = max(c * c - 3.0 * d * b, 0.0)
        r = np.sqrt(disc)
        s1 = (-c - r) / (3.0 * d)
        s2 = (-c + r) / (3.0 * d)
        s = s1 if 0.0 <= s1 <= 1.0 else s2
    s = min(max(s, 0.0), 1.0)
    return _cubic(a, b, c, d, s)


@njit(cache=True)
def _first_crossing(h0, h1, d0, d1, H):
    """First s in [0, 1] where the Hermite cubic of h becomes > 0, or -1.0 if none."""
    if h0 > 0.0:
        return 0.0
    a = h0
    b = H * d0
    c = 3.0 * (h1 - h0) - 2.0 * H * d0 - H * d1
    d = 2.0 * (h0 - h1) + H * d0 + H * d1
    # split [0, 1] at the critical points so that the cubic is monotone on each piece (no
    # array: this runs for every grazing alarm of every switching functional)
    k1 = 2.0
    k2 = 2.0
    qa, qb, qc = 3.0 * d, 2.0 * c, b
    if qa != 0.0:
        disc = qb * qb - 4.0 * qa * qc
        if disc > 0.0:
            r = np.sqrt(disc)
            s1 = (-qb - r) / (2.0 * qa)
            s2 = (-qb + r) / (2.0 * qa)
            if s1 > s2:
                s1, s2 = s2, s1
            if 0.0 < s1 < 1.0:
                k1 = s1
            if 0.0 < s2 < 1.0:
                if k1 > 1.0:
                    k1 = s2
                else:
                    k2 = s2
    elif qb != 0.0:
        s1 = -qc / qb
        if 0.0 < s1 < 1.0:
            k1 = s1
    lo = 0.0
    for i in range(3):
        hi = k1 if i == 0 else (k2 if i == 1 else 1.0)
        if hi > 1.0:
            continue
        if _cubic(a, b, c, d, hi) > 0.0:
            # bisection to 1e-9 of the step: the exact-flow Newton of _locate refines it
            # (the cubic itself is only accurate to ~(omega dt)^4)
            for _ in range(30):
                mid = 0.5 * (lo + hi)
                if _cubic(a, b, c, d, mid) > 0.0:
                    hi = mid
                else:
                    lo = mid
            return hi
        lo = hi
    return -1.0


@njit(cache=True)
def _locate(a, z, hv, dv, H, s_est, h_end, zt, term, tmp, counter):
    """Time in [0, H] just past the first zero of ``h(t) = hv . z(t)``, or -1.0 if none.

    ``z(t)`` is the exact flow of ``a`` from ``z``; ``s_est`` is the cubic estimate (a
    fraction of H) and ``h_end = h(H)``. Newton on the exact flow, safeguarded by a bracket
    ``h(lo) <= 0 < h(hi)``; once it has converged the state is taken a little past the zero
    (1e-9 of a step) and accepted there if ``h > 0``, so the next mode starts on the far side
    of the surface with the sign of every force set by the physics, not by roundoff. That is
    two flow evaluations for a typical event. Without a sign change at the step end (a
    grazing alarm) it returns -1.0 unless a positive value is found. ``zt`` holds the state.
    """
    past = 1e-9 * H
    lo = 0.0
    hi = H if h_end > 0.0 else -1.0
    tau = s_est * H
    landing = False
    for _ in range(60):
        _flow(a, z, tau, zt, term, tmp)
        counter[0] += 1
        g = _dot(hv, zt)
        if g > 0.0:
            if landing or tau == 0.0:
                return tau
            hi = tau
        else:
            lo = tau
        landing = False
        if hi >= 0.0 and hi - lo <= past:
            break
        dg = _dot(dv, zt)
        t_new = tau - g / dg if dg > 0.0 else -1.0
        if hi >= 0.0:
            if not (lo < t_new < hi):
                t_new = 0.5 * (lo + hi)
            elif abs(t_new - tau) <= 1e-6 * H:
                # the next Newton correction would be ~1e-12 H: step just past the zero
                t_new += past
                landing = True
                if t_new >= hi:  # hi itself may be past the zero by roundoff only
                    return _land(a, z, hv, min(t_new, H), hi, zt, term, tmp, counter)
        elif not (tau < t_new <= H):
            return -1.0  # h turns down before reaching zero: no crossing
        elif abs(t_new - tau) <= 1e-6 * H:
            t_new = min(t_new + past, H)
            landing = True
        tau = t_new
    if hi < 0.0:
        return -1.0
    # the bracket holds the zero to within `past`: land `past` beyond it, as Newton does
    return _land(a, z, hv, min(hi + past, H), hi, zt, term, tmp, counter)


@njit(cache=True)
def _land(a, z, hv, tau, hi, zt, term, tmp, counter):
    """State ``zt`` at ``tau``, a little past a zero known to lie before ``hi <= tau``, if
    ``h`` is still positive there; else at ``hi`` (h turned down again: a graze).

    ``h(hi) > 0`` may hold by roundoff only (a few 1e-16 of the force); the next mode's own
    functionals compute the same force by other rows and may then disagree on the side,
    e.g. a guide released by the held mode whose slider's acceleration is -1e-15 in the
    moving mode, which stops it at once and holds it again at the same instant: chattering.
    ``past`` (1e-9 of a step) beyond the zero the sign is the physics'.
    """
    if tau > hi:
        _flow(a, z, tau, zt, term, tmp)
        counter[0] += 1
        if _dot(hv, zt) > 0.0:
            return tau
    _flow(a, z, hi, zt, term, tmp)
    return hi


@njit(cache=True)
def _tip_zero(z, guide, funcs, scalars):
    """(tip, guide) once v_rel = 0 with the slider moving (``guide`` 1 or 2) or not (0).

    Returns the stick mode if the force that keeps v_rel = 0 is within mu_s F_N, otherwise
    the slip direction that force points to (the friction then acts the same way).
    """
    mu_s = scalars[SC_MU_S]
    mu_sd = scalars[SC_MU_SD]
    fn = _dot(funcs[F_FN], z)
    if guide == HELD:
        # tip and slider at rest together: can the guide and the interface both hold? The
        # guide holds the slider against the tip's force and the load together.
        fh = _dot(funcs[F_HOLD], z)
        ng = _dot(funcs[F_NG_CONTACT], z)
        net = fh - scalars[SC_LOAD]
        if abs(net) <= mu_sd * ng:
            if abs(fh) <= mu_s * fn:
                return STICK, HELD
            return (SLIP_POS if fh > 0.0 else SLIP_NEG), HELD
        guide = FORWARD if net > 0.0 else BACKWARD
    fs = _dot(funcs[F_HOLD + guide], z)
    if abs(fs) <= mu_s * fn:
        return STICK, guide
    return (SLIP_POS if fs > 0.0 else SLIP_NEG), guide


@njit(cache=True)
def _stick_exact(z, scalars):
    """Make ``v_rel = phi_B(l) dw_b - dx`` exactly 0 in place (stick with the slider moving),
    setting the lighter body's velocity from the other's.

    An event state lies a little past ``v_rel = 0`` (:func:`_land`), where ``v_rel`` is its
    rate of change times that delay, nearly all of it the tip's acceleration. The tip's
    effective mass ``M_b / phi_B(l)^2`` is about a hundredth of the slider's on the motors
    here, so the tip takes the correction. Setting the heavy slider's velocity to the tip's
    instead kicked the slider the same way at every stick and biased its settled speed
    (docs/contact.md §3). A tip heavier than the slider, as at a node of B2
    (``phi_B(l) -> 0``), is left as it is and the slider takes it, so that nothing is divided
    by a small ``phi_B(l)``. (Undoing the delay along the old mode's flow, or a
    momentum-conserving impulse, agreed with this rule to the event-location error.)
    """
    phi = scalars[SC_PHI_BL]
    if phi * phi * scalars[SC_M] >= scalars[SC_M_B]:
        z[DW] = z[DX] / phi
    else:
        z[DX] = phi * z[DW]


@njit(cache=True)
def _switch(mode, etype, z, funcs, scalars):
    """New mode after event ``etype`` at state ``z``; may project ``z`` onto the new mode."""
    contact = mode // 9
    tip = (mode // 3) % 3
    guide = mode % 3
    was_stuck = contact == CONTACT and tip == STICK
    mu_d = scalars[SC_MU_D]
    mu_sd = scalars[SC_MU_SD]
    load = scalars[SC_LOAD]  # on the slider in -x, beside the tip's force
    if etype == EV_SEPARATE:
        contact = SEPARATED
        tip = SLIP_POS
    elif etype == EV_CONTACT:
        contact = CONTACT
        vr = _dot(funcs[F_VREL], z)
        if vr > scalars[SC_EPS]:
            tip = SLIP_POS
        elif vr < -scalars[SC_EPS]:
            tip = SLIP_NEG
        else:
            # touching down inside the stick band (F_N = 0 here)
            tip, guide = _tip_zero(z, guide, funcs, scalars)
            if tip != STICK and vr != 0.0:
                # no normal force holds v_rel at zero, so the tip slides the way it moves:
                # the stick force's direction against a v_rel of the other sign started the
                # new slip past its own v_rel = 0 surface, which fired at once, again and
                # again (a band of 0.03 m/s at 400 V / 14 N ended in ChatteringError)
                tip = SLIP_POS if vr > 0.0 else SLIP_NEG
    elif etype == EV_VREL_ZERO:
        tip, guide = _tip_zero(z, guide, funcs, scalars)
    elif etype == EV_STICK_BREAK:
        fs = _dot(funcs[F_HOLD + guide], z)
        tip = SLIP_POS if fs > 0.0 else SLIP_NEG
    elif etype == EV_XDOT_ZERO:
        if contact == CONTACT and tip == STICK:
            # int64, not the literal HELD: one compiled _tip_zero for every call
            tip, guide = _tip_zero(z, np.int64(HELD), funcs, scalars)
        else:
            ft = 0.0
            ng = _dot(funcs[F_NG_SEP], z)
            if contact == CONTACT:
                fn = _dot(funcs[F_FN], z)
                ft = mu_d * fn if tip == SLIP_POS else -mu_d * fn
                ng = _dot(funcs[F_NG_CONTACT], z)
            if abs(ft - load) <= mu_sd * ng:
                guide = HELD
            else:
                guide = FORWARD if ft - load > 0.0 else BACKWARD
    elif etype == EV_GUIDE_RELEASE:
        if contact == CONTACT and tip == STICK:
            fh = _dot(funcs[F_HOLD], z)
            guide = FORWARD if fh - load > 0.0 else BACKWARD
            tip, guide = _tip_zero(z, guide, funcs, scalars)
        else:
            fn = _dot(funcs[F_FN], z) if contact == CONTACT else 0.0
            ft = mu_d * fn if tip == SLIP_POS else -mu_d * fn
            guide = FORWARD if ft - load > 0.0 else BACKWARD
    if contact == CONTACT and tip == STICK:
        if guide == HELD:
            z[DW] = 0.0
            z[DX] = 0.0
        else:
            _stick_exact(z, scalars)
    elif contact == CONTACT and was_stuck:
        # The tip leaves stick for slip: it starts slipping from v_rel = 0, the constraint
        # that held until now, in the direction of the stick force (docs/contact.md 2.1).
        # The stick state carries v_rel = phi_B(l) dw_b - dx only to roundoff (an ulp of
        # dx, either sign); the new slip mode's v_rel-zero functional -sigma v_rel must start
        # on its surface, not past it: a positive ulp fired it at once, _tip_zero chose the
        # same slip again from the unchanged state, and so on at the same instant (a stick
        # break just before a separation, where the slip flow's end-of-step v_rel turns
        # back: "contact chattering"). Exactly 0 in the functional's own arithmetic, the
        # slider taking the ulp (a held slider and its tip are at rest together).
        if guide == HELD:
            z[DX] = 0.0
            z[DW] = 0.0
        else:
            z[DX] = scalars[SC_PHI_BL] * z[DW]
    elif guide == HELD:
        z[DX] = 0.0
    return contact * 9 + tip * 3 + guide


@njit(cache=True)
def _phase(mode):
    if mode // 9 == SEPARATED:
        return PHASE_SEPARATION
    return (mode // 3) % 3


@njit(cache=True)
def _record(buf, row, t, z, mode, fn_m, ft_m, funcs, phi_ll):
    buf[row, 0] = t
    buf[row, 1] = z[X]
    buf[row, 2] = z[DX]
    buf[row, 3] = z[U]
    buf[row, 4] = z[W]
    buf[row, 5] = _dot(fn_m[mode], z)
    buf[row, 6] = _dot(ft_m[mode], z)
    buf[row, 7] = _dot(funcs[F_VREL], z)
    buf[row, 8] = phi_ll * z[U]
    buf[row, 9] = _phase(mode)


@njit(cache=True)
def _powers(z, mode, fn_m, ft_m, ff_m, sc, out):
    fn = _dot(fn_m[mode], z)
    ft = _dot(ft_m[mode], z)
    ff = _dot(ff_m[mode], z)
    out[0] = z[SIN] * (sc[SC_ALV] * z[DU] + sc[SC_ABV] * z[DW])
    out[1] = sc[SC_C_L] * z[DU] * z[DU] + sc[SC_C_B] * z[DW] * z[DW]
    out[2] = sc[SC_GAMMA_N] * fn * z[DU]
    out[3] = sc[SC_GAMMA_T] * ft * z[DW]
    out[4] = ft * z[DX]
    out[5] = ff * z[DX]
    out[6] = sc[SC_C_B] * z[DW] * z[DW]


@njit(cache=True)
def stored_energy(z, mode, fn_m, sc):
    """Kinetic + modal strain + contact-spring energy of the state (J)."""
    fn = _dot(fn_m[mode], z)
    e = 0.5 * (sc[SC_M_L] * z[DU] ** 2 + sc[SC_K_L] * z[U] ** 2 + sc[SC_M_B] * z[DW] ** 2)
    e += 0.5 * (sc[SC_K_B] * z[W] ** 2 + sc[SC_M] * z[DX] ** 2)
    if mode // 9 == CONTACT:
        e += 0.5 * fn * fn / sc[SC_K]
    return e


@njit(cache=True)
def _accumulate(za, zm, zb, mode, H, phase_time, work, fn_m, ft_m, ff_m, sc,
                pa, pm, pb, energy):
    phase_time[_phase(mode)] += H
    if energy:
        _powers(za, mode, fn_m, ft_m, ff_m, sc, pa)
        _powers(zm, mode, fn_m, ft_m, ff_m, sc, pm)
        _powers(zb, mode, fn_m, ft_m, ff_m, sc, pb)
        for i in range(N_WORK):
            work[i] += H / 6.0 * (pa[i] + 4.0 * pm[i] + pb[i])


@njit(cache=True, nogil=True)
def integrate_switch_model(
    z0, mode0, n_steps, dt, phi, phi_half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m,
    funcs, scalars, win_start, decim, n_full, energy, max_events_per_step, marks, mark_x,
):
    """Integrate the hybrid switch model on a fixed grid with located events.

    Parameters
    ----------
    z0 : (9,) float64 array
        Initial state.
    mode0 : int
        Initial mode.
    n_steps : int
        Number of steps of length ``dt`` (s).
    phi, phi_half : (18, 9, 9) arrays
        ``expm(A_m dt)`` and ``expm(A_m dt / 2)``.
    a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, scalars : arrays
        The :class:`contact.model.HybridSystem` fields.
    win_start : int
        First step of the steady-state window over which metrics are accumulated.
    decim : int
        Store every ``decim``-th step in the decimated trace.
    n_full : int
        Store each of the last ``n_full`` steps in the full-resolution trace.
    energy : bool
        Accumulate the work integrals over the window.
    max_events_per_step : int
        More switches than this inside one step is reported as chattering.
    marks : (m,) int64 array
        Steps, ascending, at whose end the slider position is wanted (0: the start).
    mark_x : (m,) float64 array
        Filled with the slider position x (m) at each of ``marks`` (left as it is for a step
        beyond the run). The earlier window of :func:`contact.transient.event.solve_event` is read
        there exactly, not interpolated from the decimated trace.

    Returns
    -------
    status, fail_step, trace, full, phase_time, work, stats, z_end, mode_end
        ``stats = [x at window start, y_tip min, y_tip max, events, E at window start,
        E at end, exact-flow evaluations spent locating events]``.
    """
    z = z0.copy()
    mode = mode0
    z1 = np.empty(N_STATE)
    zt = np.empty(N_STATE)
    zm = np.empty(N_STATE)
    term = np.empty(N_STATE)
    tmp = np.empty(N_STATE)
    pa = np.empty(N_WORK)
    pm = np.empty(N_WORK)
    pb = np.empty(N_WORK)
    # every decim-th step, plus the final state when decim does not divide n_steps
    n_dec = n_steps // decim + 1 + (1 if n_steps % decim else 0)
    trace = np.empty((n_dec, N_TRACE_COLS))
    full = np.empty((n_full + 1, N_TRACE_COLS))
    phase_time = np.zeros(4)
    work = np.zeros(N_WORK)
    stats = np.zeros(7)
    stats[1] = np.inf
    stats[2] = -np.inf
    phi_ll = scalars[SC_PHI_LL]
    full_start = n_steps - n_full
    # np.int64(0), not 0: numba types a constant argument as a literal and compiles the
    # callee once more for it; as int64 every call shares the one signature
    row0 = np.int64(0)
    _record(trace, row0, 0.0, z, mode, fn_m, ft_m, funcs, phi_ll)
    if full_start == 0:
        _record(full, row0, 0.0, z, mode, fn_m, ft_m, funcs, phi_ll)
    if win_start == 0:
        stats[0] = z[X]
        stats[4] = stored_energy(z, mode, fn_m, scalars)
    n_marks = marks.size
    j_mark = 0
    while j_mark < n_marks and marks[j_mark] <= 0:
        mark_x[j_mark] = z[X]
        j_mark += 1
    counter = np.zeros(2, dtype=np.int64)  # flows in event location, located events
    s_est = np.zeros(MAX_EVENTS)
    hc = np.zeros(MAX_EVENTS)
    dc = np.zeros(MAX_EVENTS)
    hn = np.zeros(MAX_EVENTS)
    dn = np.zeros(MAX_EVENTS)
    cached = False
    n_events = 0
    status = OK
    fail_step = -1
    for n in range(n_steps):
        in_window = n >= win_start
        u_start = z[U]
        du_start = z[DU]
        done = 0.0
        count = 0
        while True:
            H = dt - done
            if done == 0.0:
                _matvec(phi[mode], z, z1)
            else:
                _flow(a[mode], z, H, z1, term, tmp)
            n_cand = 0
            for j in range(MAX_EVENTS):
                s_est[j] = 2.0  # every slot: a shorter event list must not see stale ones
            for j in range(MAX_EVENTS):
                et = ev_type[mode, j]
                if et == EV_NONE:
                    break
                if cached:
                    h0 = hc[j]
                    d0 = dc[j]
                else:
                    h0 = _dot(ev_h[mode, j], z)
                    d0 = _dot(ev_dh[mode, j], z)
                h1 = 0.0
                d1 = 0.0
                for i in range(N_STATE):
                    h1 += ev_h[mode, j, i] * z1[i]
                    d1 += ev_dh[mode, j, i] * z1[i]
                hn[j] = h1
                dn[j] = d1
                if h1 > 0.0 or (d0 > 0.0 and d1 < 0.0):
                    s = _first_crossing(h0, h1, d0, d1, H)
                    if s >= 0.0:
                        s_est[j] = s
                        n_cand += 1
            # earliest crossing confirmed on the exact flow (a grazing alarm may not be)
            j_min = -1
            tau = -1.0
            while n_cand > 0:
                j_best = -1
                s_best = 2.0
                for j in range(MAX_EVENTS):
                    if s_est[j] < s_best:
                        s_best = s_est[j]
                        j_best = j
                if j_best < 0:
                    break
                tau = _locate(a[mode], z, ev_h[mode, j_best], ev_dh[mode, j_best], H, s_best,
                              hn[j_best], zt, term, tmp, counter)
                if tau >= 0.0:
                    j_min = j_best
                    break
                s_est[j_best] = 2.0
            # advance to the step's end (z1) or, with an event, to just past it (zt, at tau)
            h = H if j_min < 0 else tau
            z_end = z1 if j_min < 0 else zt
            if h > 0.0:
                if energy and in_window:
                    if j_min < 0 and done == 0.0:
                        _matvec(phi_half[mode], z, zm)
                    else:
                        _flow(a[mode], z, 0.5 * h, zm, term, tmp)
                if in_window:
                    _accumulate(z, zm, z_end, mode, h, phase_time, work, fn_m, ft_m, ff_m,
                                scalars, pa, pm, pb, energy)
                for i in range(N_STATE):
                    z[i] = z_end[i]
            if j_min < 0:
                if mode == STICK_FORWARD or mode == STICK_BACKWARD:
                    _stick_exact(z, scalars)  # keep v_rel = 0 free of roundoff
                # the end values of the switching functionals start the next step
                for j in range(MAX_EVENTS):
                    hc[j] = hn[j]
                    dc[j] = dn[j]
                cached = True
                break
            cached = False
            done += tau
            mode = _switch(mode, ev_type[mode, j_min], z, funcs, scalars)
            n_events += 1
            count += 1
            if count > max_events_per_step:
                status = ERR_CHATTER
                fail_step = n
                break
            if done >= dt:
                break
        if status != OK:
            break
        t = (n + 1) * dt
        if (n + 1) % decim == 0:
            _record(trace, (n + 1) // decim, t, z, mode, fn_m, ft_m, funcs, phi_ll)
        if n + 1 >= full_start:
            _record(full, n + 1 - full_start, t, z, mode, fn_m, ft_m, funcs, phi_ll)
        if n + 1 == win_start:
            stats[0] = z[X]
            stats[4] = stored_energy(z, mode, fn_m, scalars)
        while j_mark < n_marks and marks[j_mark] == n + 1:
            mark_x[j_mark] = z[X]
            j_mark += 1
        if in_window:
            y = phi_ll * z[U]
            if du_start * z[DU] < 0.0:
                # u_l turned inside the step: take the extremum of its cubic interpolant
                y = _hermite_extremum(phi_ll * u_start, y, phi_ll * du_start, phi_ll * z[DU],
                                      dt)
            lo_y = min(y, phi_ll * z[U])
            hi_y = max(y, phi_ll * z[U])
            if lo_y < stats[1]:
                stats[1] = lo_y
            if hi_y > stats[2]:
                stats[2] = hi_y
    if status == OK and n_steps % decim:
        _record(trace, n_dec - 1, n_steps * dt, z, mode, fn_m, ft_m, funcs, phi_ll)
    stats[3] = n_events
    stats[6] = counter[0]
    stats[5] = stored_energy(z, mode, fn_m, scalars)
    return status, fail_step, trace, full, phase_time, work, stats, z, mode


# the kernel inlines contact.state's layout constants: an edit there must recompile it
depend_on(globals(), state_module)
