"""Compiled shooting loop of the fixed-velocity fast problem (:mod:`contact.steady.periodic_orbit`).

One call runs the whole search for a periodic orbit of the one-period map at slider velocity
``v``: chord Newton on ``P(y) - y = 0`` for ``y = (u_l, du_l, w_b, dw_b)`` with a
finite-difference Jacobian corrected by Broyden's secant updates, the period-by-period
fallback that watches for period-k repetition, and the multi-period jumps once Newton has
given up. It began as the Python loop of :func:`contact.steady.periodic_orbit.find_orbit` moved into
numba, so that the dozens of one-period kernel calls of a search cost no Python dispatch;
each period is one call of :func:`contact.transient.event_kernel.integrate_switch_model` with its
window closed. Like that kernel,
every function here releases the GIL (``nogil``): ``lusm map`` runs points on a thread pool.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from contact import state
from contact.numba_cache import depend_on
from contact.state import CONTACT, COS, DU, DW, DX, HELD, ONE, SIN, STICK, U, W, X
from contact.transient import event_kernel
from contact.transient.event_kernel import integrate_switch_model

N_Y = 4
"""Shooting variables (u_l, du_l, w_b, dw_b)."""

FOUND, SEARCH_OVER, CHATTER = 1, 0, -1
"""Return codes: an orbit of period <= max_k, none within max_periods, kernel chattering."""


@njit(cache=True, nogil=True)
def _y_index(i):
    if i == 0:
        return U
    if i == 1:
        return DU
    if i == 2:
        return W
    return DW


@njit(cache=True, nogil=True)
def _consistent(z, mode, v, phi_bl):
    z[DX] = v
    z[SIN] = 0.0
    z[COS] = 1.0
    z[ONE] = 1.0
    if mode // 9 == CONTACT and (mode // 3) % 3 == STICK:
        z[DW] = v / phi_bl


@njit(cache=True, nogil=True)
def _defect(za, zb, amp):
    d = 0.0
    for i in range(N_Y):
        j = _y_index(i)
        e = abs(za[j] - zb[j]) / amp[i]
        if e > d:
            d = e
    return d


@njit(cache=True, nogil=True)
def _broyden(jac, za, zb, pa, pb, amp):
    """Broyden's rank-one secant update of the one-period map's Jacobian ``jac`` (in place)
    from the step ``za -> zb`` and its images ``pa -> pb``, in variables scaled by ``amp``
    (so that displacements and velocities weigh alike): ``J += (dP - J s) s^T / |s|^2``."""
    s = np.zeros(N_Y)
    ss = 0.0
    for i in range(N_Y):
        s[i] = zb[_y_index(i)] - za[_y_index(i)]
        ss += (s[i] / amp[i]) ** 2
    if ss == 0.0:
        return
    for r in range(N_Y):
        js = 0.0
        for c in range(N_Y):
            js += jac[r, c] * s[c]
        err = (pb[_y_index(r)] - pa[_y_index(r)]) - js
        for c in range(N_Y):
            jac[r, c] += err * s[c] / (amp[c] * amp[c] * ss)


@njit(cache=True, nogil=True)
def _run(z, mode, steps, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, sc):
    """``steps`` steps from a copy of ``z`` with its x slot reset (the integral starts at 0),
    no phase times and no trace: the output tuple of :func:`integrate_switch_model`."""
    zs = z.copy()
    zs[X] = 0.0
    # np.int64 and np.bool_, not constants, which numba types as literals and would compile
    # the kernel once more for: the kernel keeps the one signature the Python calls use
    return integrate_switch_model(zs, mode, steps, dt, phi, half, a, ev_h, ev_dh, ev_type,
                                  fn_m, ft_m, ff_m, funcs, sc, steps, steps, np.int64(1),
                                  np.bool_(False), np.int64(64), np.empty(0, np.int64),
                                  np.empty(0))


@njit(cache=True, nogil=True)
def _period(z, mode, periods, v, phi_bl, n, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m,
            ft_m, ff_m, funcs, sc):
    """``periods`` drive periods from ``z`` (x slot reset); returns status, the consistent
    end state, its mode and the integral in the x slot. Callers pass ``periods`` as int64
    (``np.int64(1)``, not a literal ``1``), so that it is compiled once."""
    out = _run(z, mode, n * periods, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m,
               funcs, sc)
    z_end = out[7].copy()
    integral = z_end[X]
    z_end[X] = 0.0
    m_end = out[8]
    _consistent(z_end, m_end, v, phi_bl)
    return out[0], z_end, m_end, integral


@njit(cache=True, nogil=True)
def search_orbit(z0, mode0, v, amp, phi_bl, n, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m,
                 ft_m, ff_m, funcs, sc, tol, max_periods, periods0, max_k, chunk, jac0,
                 jac_mode0, max_newton, max_failures):
    """Search a periodic orbit from the consistent state ``z0`` in mode ``mode0``.

    Returns ``(code, k, z, mode, residual, periods, newton_iterations, integral, jac,
    jac_mode)``: ``integral`` is the x-slot integral over the last period from ``z`` when
    ``k == 1`` (NaN otherwise); ``jac`` (4 x 4) and ``jac_mode`` the last Jacobian (mode -1
    when none).
    """
    z = z0.copy()
    mode = mode0
    periods = periods0
    newton_it = 0
    failures = 0
    res = np.inf
    jac = jac0.copy()
    jac_mode = jac_mode0
    hist = np.zeros((max_k + 1, z.size))
    hist_modes = np.zeros(max_k + 1, dtype=np.int64)
    n_hist = 1
    hist[0, :] = z
    hist_modes[0] = mode
    have_pending = False
    z1 = z.copy()
    m1 = mode
    i1 = 0.0
    integral = np.nan
    free = np.zeros(N_Y, dtype=np.bool_)
    slow = 0
    while periods < max_periods:
        if not have_pending:
            st, z1, m1, i1 = _period(z, mode, np.int64(1), v, phi_bl, n, dt, phi, half, a,
                                     ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, sc)
            if st != 0:
                return CHATTER, 0, z, mode, res, periods, newton_it, integral, jac, jac_mode
            periods += 1
        have_pending = False
        res = _defect(z1, z, amp)
        if res <= tol and m1 == mode:
            return FOUND, 1, z, mode, res, periods, newton_it, i1, jac, jac_mode
        stick = mode // 9 == CONTACT and (mode // 3) % 3 == STICK
        n_free = 0
        for i in range(N_Y):
            free[i] = not (i == 3 and stick)
            if free[i]:
                n_free += 1
        newton_on = newton_it < max_newton and failures < max_failures
        fd_ok = True
        fresh = False
        if newton_on and m1 == mode:
            fresh = jac_mode != mode
            if fresh:
                jac[:, :] = 0.0
                for i in range(N_Y):
                    if not free[i]:
                        continue
                    zp = z.copy()
                    h = 1e-7 * amp[i]
                    zp[_y_index(i)] += h
                    # the perturbed start keeps its perturbation: no consistency reset
                    out = _run(zp, mode, n, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m,
                               ft_m, ff_m, funcs, sc)
                    periods += 1
                    if out[0] != 0:
                        # a perturbed start off the orbit can chatter where the orbit does
                        # not: no Jacobian this time, the period-by-period iteration goes on
                        fd_ok = False
                        break
                    zq = out[7]
                    for r in range(N_Y):
                        jac[r, i] = (zq[_y_index(r)] - z1[_y_index(r)]) / h
                jac_mode = mode if fd_ok else -1
        if newton_on and m1 == mode and not fd_ok:
            failures += 1
        elif newton_on and m1 == mode:
            mat = np.zeros((n_free, n_free))
            rhs = np.zeros(n_free)
            ri = 0
            for r in range(N_Y):
                if not free[r]:
                    continue
                ci = 0
                for c in range(N_Y):
                    if not free[c]:
                        continue
                    mat[ri, ci] = jac[r, c] - (1.0 if r == c else 0.0)
                    ci += 1
                rhs[ri] = -(z1[_y_index(r)] - z[_y_index(r)])
                ri += 1
            ok = True
            step = rhs
            if abs(np.linalg.det(mat)) == 0.0:
                ok = False
            else:
                step = np.linalg.solve(mat, rhs)
                for i in range(n_free):
                    if not np.isfinite(step[i]):
                        ok = False
            newton_it += 1
            if ok:
                zn = z.copy()
                ri = 0
                for i in range(N_Y):
                    if free[i]:
                        zn[_y_index(i)] += step[ri]
                        ri += 1
                _consistent(zn, mode, v, phi_bl)
                st, z2, m2, i2 = _period(zn, mode, np.int64(1), v, phi_bl, n, dt, phi, half,
                                         a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, sc)
                periods += 1
                # a Newton trial that chatters is a failed step, not a failed search
                res2 = _defect(z2, zn, amp) if st == 0 else np.inf
                if m2 == mode and res2 < res:
                    _broyden(jac, z, zn, z1, z2, amp)
                    z = zn
                    z1, m1, i1 = z2, m2, i2
                    have_pending = True
                    failures = 0
                    if res2 > 0.1 * res:
                        # slow contraction: the secant update gets one more step, then a
                        # fresh Jacobian
                        slow += 1
                        if slow >= 2:
                            jac_mode = -1
                            slow = 0
                    else:
                        slow = 0
                    continue
            jac_mode = -1
            if not fresh:  # the reused Jacobian failed: retry from z with a fresh one
                have_pending = True
                continue
            failures += 1  # three failed Newton steps in a row: period by period only
        # period-by-period fallback, watching for period-k repetition
        z = z1
        mode = m1
        if n_hist == max_k + 1:
            for j in range(max_k):
                hist[j, :] = hist[j + 1, :]
                hist_modes[j] = hist_modes[j + 1]
            n_hist = max_k
        hist[n_hist, :] = z
        hist_modes[n_hist] = mode
        n_hist += 1
        last = n_hist - 1
        for k in range(2, max_k + 1):
            if n_hist > k and hist_modes[last] == hist_modes[last - k] and \
                    _defect(hist[last], hist[last - k], amp) <= tol:
                return FOUND, k, z, mode, res, periods, newton_it, integral, jac, jac_mode
        if n_hist > max_k and not newton_on and periods + chunk < max_periods:
            st, z, mode, _ = _period(z, mode, chunk, v, phi_bl, n, dt, phi, half, a, ev_h,
                                     ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, sc)
            if st != 0:
                return CHATTER, 0, z, mode, res, periods, newton_it, integral, jac, jac_mode
            periods += chunk
            hist[0, :] = z
            hist_modes[0] = mode
            n_hist = 1
    return SEARCH_OVER, 0, z, mode, res, periods, newton_it, integral, jac, jac_mode


@njit(cache=True, nogil=True)
def full_consistent(z, mode, phi_bl):
    """Make ``z`` consistent with ``mode`` in place: drive phase at t = 0, stick and guide
    constraints on ``dw_b`` and the slider velocity ``dx`` (full model)."""
    z[SIN] = 0.0
    z[COS] = 1.0
    z[ONE] = 1.0
    stick = mode // 9 == CONTACT and (mode // 3) % 3 == STICK
    held = mode % 3 == HELD
    if stick and held:
        z[DW] = 0.0
        z[DX] = 0.0
    elif stick:
        z[DX] = phi_bl * z[DW]
    elif held:
        z[DX] = 0.0


@njit(cache=True, nogil=True)
def _full_y(i):
    if i < N_Y:
        return _y_index(i)
    return DX


@njit(cache=True, nogil=True)
def shoot_full(z0, mode0, k, amp, phi_bl, n, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m,
               ft_m, ff_m, funcs, sc, tol, max_newton):
    """Newton on the k-period map of the full model, ``y = (u_l, du_l, w_b, dw_b, dx)``:
    the loop of :func:`contact.steady.full_orbit.shoot` compiled.

    Returns ``(code, z, mode, residual, periods, iterations, jac, free)``: ``code`` is
    :data:`FOUND` when converged, :data:`SEARCH_OVER` when not, :data:`CHATTER` on kernel
    chattering; ``jac`` (5 x 5) the last finite-difference Jacobian and ``free`` its free
    components (NaN Jacobian when none was formed).
    """
    z = z0.copy()
    mode = mode0
    full_consistent(z, mode, phi_bl)
    periods = 0
    res = np.inf
    it = 0
    steps = n * k
    jac = np.full((N_Y + 1, N_Y + 1), np.nan)
    free = np.zeros(N_Y + 1, dtype=np.bool_)
    last_free = np.zeros(N_Y + 1, dtype=np.bool_)
    for it in range(1, max_newton + 1):
        out = _run(z, mode, steps, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m,
                   funcs, sc)
        if out[0] != 0:
            return CHATTER, z, mode, res, periods, it, jac, last_free
        z1 = out[7].copy()
        z1[X] = 0.0
        m1 = out[8]
        full_consistent(z1, m1, phi_bl)
        periods += k
        res = 0.0
        for i in range(N_Y + 1):
            e = abs(z1[_full_y(i)] - z[_full_y(i)]) / amp[i]
            if e > res:
                res = e
        if m1 == mode and res <= tol:
            return FOUND, z, mode, res, periods, it, jac, last_free
        stick = mode // 9 == CONTACT and (mode // 3) % 3 == STICK
        held = mode % 3 == HELD
        n_free = 0
        for i in range(N_Y + 1):
            if stick and held:
                free[i] = i < 3
            elif stick or held:
                free[i] = i < 4
            else:
                free[i] = True
            if free[i]:
                n_free += 1
        jac[:, :] = 0.0
        for i in range(N_Y + 1):
            if not free[i]:
                continue
            zp = z.copy()
            h = 1e-7 * amp[i]
            zp[_full_y(i)] += h
            full_consistent(zp, mode, phi_bl)
            outp = _run(zp, mode, steps, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m,
                        ff_m, funcs, sc)
            if outp[0] != 0:
                return CHATTER, z, mode, res, periods, it, jac, last_free
            zq = outp[7].copy()
            full_consistent(zq, m1, phi_bl)
            periods += k
            for r in range(N_Y + 1):
                jac[r, i] = (zq[_full_y(r)] - z1[_full_y(r)]) / h
        last_free[:] = free
        mat = np.zeros((n_free, n_free))
        rhs = np.zeros(n_free)
        ri = 0
        finite = True
        for r in range(N_Y + 1):
            if not free[r]:
                continue
            ci = 0
            for c in range(N_Y + 1):
                if not free[c]:
                    continue
                mat[ri, ci] = jac[r, c] - (1.0 if r == c else 0.0)
                if not np.isfinite(mat[ri, ci]):
                    finite = False
                ci += 1
            rhs[ri] = -(z1[_full_y(r)] - z[_full_y(r)])
            ri += 1
        if not finite or np.linalg.det(mat) == 0.0:
            break
        step = np.linalg.solve(mat, rhs)
        if m1 != mode:  # the mode at the section changed: continue from the image
            z = z1
            mode = m1
            continue
        ri = 0
        for i in range(N_Y + 1):
            if free[i]:
                z[_full_y(i)] += step[ri]
                ri += 1
        full_consistent(z, mode, phi_bl)
    return SEARCH_OVER, z, mode, res, periods, it, jac, last_free


@njit(cache=True, nogil=True)
def find_orbit_compiled(z0, mode0, v, phi_bl, period_s, warmup, n, dt, phi, half, a, ev_h,
                        ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, sc, phi_fn, half_fn, a_fn,
                        ev_dh_fn, tol, max_periods, max_k, chunk, jac0, jac_mode0,
                        max_newton, max_failures, average_periods):
    """Warm-up, :func:`search_orbit` and the period averages of one fast-problem orbit.

    The arrays ``phi_fn, half_fn, a_fn, ev_dh_fn`` are those of the system whose x slot
    integrates F_N (the other fields are shared). Returns ``(code, k, z, mode, residual,
    periods, newton_iterations, int_ft, int_fn, phase_time, jac, jac_mode)``: the integrals
    (N s) over k periods (over ``average_periods`` when k = 0; phase times then zero).
    """
    z = z0.copy()
    mode = mode0
    _consistent(z, mode, v, phi_bl)
    periods = 0
    nan4 = np.zeros(4)
    if warmup > 0:  # one kernel call: the drive phase is reset at its end only
        st, z, mode, _ = _period(z, mode, warmup, v, phi_bl, n, dt, phi, half, a, ev_h, ev_dh,
                                 ev_type, fn_m, ft_m, ff_m, funcs, sc)
        if st != 0:
            return (CHATTER, 0, z, mode, np.inf, periods, 0, np.nan, np.nan, nan4, jac0,
                    jac_mode0)
        periods += warmup
    amp = np.zeros(N_Y)
    amp[0] = max(abs(z[U]), 1e-12)
    amp[2] = max(abs(z[W]), 1e-12)
    omega = 2.0 * np.pi / period_s
    amp[1] = omega * amp[0]
    amp[3] = omega * amp[2]
    code, k, z, mode, res, periods, newton_it, int_ft, jac, jac_mode = search_orbit(
        z, mode, v, amp, phi_bl, n, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m,
        funcs, sc, tol, max_periods, periods, max_k, chunk, jac0, jac_mode0, max_newton,
        max_failures)
    if code == CHATTER:
        return (CHATTER, 0, z, mode, res, periods, newton_it, np.nan, np.nan, nan4, jac,
                jac_mode)
    kk = k if k > 0 else average_periods
    _consistent(z, mode, v, phi_bl)
    steps = n * kk
    phase_time = np.zeros(4)
    if k != 1:
        # the search's last period gives the F_T integral of a one-period orbit only
        out = _run(z, mode, steps, dt, phi, half, a, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m,
                   funcs, sc)
        if out[0] != 0:
            return (CHATTER, 0, z, mode, res, periods, newton_it, np.nan, np.nan, nan4, jac,
                    jac_mode)
        int_ft = out[7][X]
        periods += kk
    zs = z.copy()
    zs[X] = 0.0
    # the F_N run also gives the phase times (the two systems differ only in the x row,
    # which no switching functional reads); those of the k = 0 average are left to the
    # caller (the window triples the cost of a step)
    out2 = integrate_switch_model(zs, mode, steps, dt, phi_fn, half_fn, a_fn, ev_h, ev_dh_fn,
                                  ev_type, fn_m, ft_m, ff_m, funcs, sc, 0 if k > 0 else steps,
                                  steps, np.int64(1), np.bool_(False), np.int64(64),
                                  np.empty(0, np.int64), np.empty(0))
    if out2[0] != 0:
        return (CHATTER, 0, z, mode, res, periods, newton_it, np.nan, np.nan, nan4, jac,
                jac_mode)
    if k > 0:
        phase_time = out2[4].copy()
    periods += kk
    return (code, k, z, mode, res, periods, newton_it, int_ft, out2[7][X], phase_time, jac,
            jac_mode)


depend_on(globals(), event_kernel, state)
