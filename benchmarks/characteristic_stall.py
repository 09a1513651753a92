"""The exact characteristic's stall-force tolerance: 1e-6 (``STALL_RTOL``) against 1e-9 (not a
test).

    python benchmarks/characteristic_stall.py

``lusm characteristic`` at the exact level finds the stall force as the root of the velocity
from rest against the load (``contact.characteristic``). Near the stall the slider creeps below
its velocity ripple, and every load tried is a 2 000-period transient from rest. This runs the
default 21-load characteristic of Table 2's set at 14 N and 150-400 V twice in the same
process, with the former tolerance 1e-9 (the reference) and the present one, and prints per
voltage: the steady solves each made, the wall-time ratio (reference / present, one call each
after a warm-up) and the stall forces with their relative difference. The curve's other loads
are solved alike by both (the tolerance enters only the stall-force search, and through it the
loads' grid, linspace(0, stall)).
"""

from __future__ import annotations

import time

import contact.characteristic as ch
from rom import table2

VOLTAGES_V = (150.0, 200.0, 250.0, 300.0, 400.0)
PRELOAD_N = 14.0
REFERENCE_RTOL = 1e-9


def _run(params, volts: float, rtol: float):
    """The characteristic at ``volts`` with the stall tolerance ``rtol``: (result, steady
    solves, wall time in s)."""
    calls = [0]
    inner = ch.steady_state

    def counted(*args, **kwargs):
        calls[0] += 1
        return inner(*args, **kwargs)

    saved = ch.STALL_RTOL
    ch.STALL_RTOL, ch.steady_state = rtol, counted
    try:
        t0 = time.perf_counter()
        c = ch.characteristic(params, volts, PRELOAD_N)
        return c, calls[0], time.perf_counter() - t0
    finally:
        ch.STALL_RTOL, ch.steady_state = saved, inner


def main() -> None:
    params = table2()
    ch.characteristic(params, 200.0, PRELOAD_N)  # numba compilation and caches, not timed
    print(f"Table 2, {PRELOAD_N:g} N, default curve; reference rtol {REFERENCE_RTOL:g}, "
          f"present {ch.STALL_RTOL:g}")
    print("  V   solves ref/now  time ratio   stall ref (N)     stall now (N)     rel diff")
    for v in VOLTAGES_V:
        ref, n_ref, t_ref = _run(params, v, REFERENCE_RTOL)
        now, n_now, t_now = _run(params, v, ch.STALL_RTOL)
        rel = abs(now.stall_force_N - ref.stall_force_N) / abs(ref.stall_force_N)
        print(f"{v:4.0f}   {n_ref:4d} / {n_now:3d}  {t_ref / t_now:9.2f}   "
              f"{ref.stall_force_N:.12f}   {now.stall_force_N:.12f}   {rel:8.1e}")


if __name__ == "__main__":
    main()
