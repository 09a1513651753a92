"""The slow equation's scan budget: ripple-scale floor and short k = 0 orbits against the former
scan (not a test).

    python benchmarks/steady_scan_budget.py

Former scan: 16 velocities per side from 1e-5 of the top speed, orbits without a short period
searched for 400 periods and averaged over 200. Now: three velocities per decade from the
slider's velocity-ripple scale (``contact.steady.slow.ripple_scale``), 200 + 100 periods
(``contact.steady.periodic_orbit.SEARCH_PERIODS``, ``AVERAGE_PERIODS``). Prints, on the 9 x 9 map
(50-450 V x 10-26 N, fast level, load 0):

* orbit searches, how many found no orbit of period <= 4 (k = 0) and their share of the
  periods simulated, for both;
* the time of both in the same run;
* points whose velocity from rest or stable branches differ by more than 1e-9 (relative)
  between the two;
* on the k = 0 samples of eight low-speed points, the largest relative change of G when the
  same velocities are solved with the former budget (and whether any changed sign).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from contact.model import OperatingPoint
from contact.steady.branches import branches_at_load
from contact.steady.engine import steady_state
from contact.steady.slow import SlowProblem, scan_grid, slow_problem
from rom import table2

LOW_SPEED_POINTS = ((50, 14), (50, 22), (50, 26), (100, 10), (100, 18), (150, 14), (200, 20),
                    (250, 26))


def _former(sp: SlowProblem) -> SlowProblem:
    """The former scan of the same slow problem: floor 1e-5 of the top speed (16 velocities
    over five decades, the same density) and 400 + 200 periods per orbit, empty cache."""
    return dataclasses.replace(sp, v_floor_m_s=1e-5 * sp.v_max_m_s, search_periods=400,
                               average_periods=200, cache={}, periods=0, newton_iterations=0)


def _solve(params, volts, loads, former: bool):
    """Stable branches per point, orbit statistics and wall time of one scan variant."""
    rows, stats = {}, {"orbits": 0, "k0": 0, "periods": 0, "k0_periods": 0}
    t0 = time.perf_counter()
    for v in volts:
        for f in loads:
            sp = slow_problem(params, OperatingPoint(float(v), float(f), 40e3, 0.0))
            if former:
                sp = _former(sp)
            branches, v_rest = branches_at_load(sp, 0.0)
            rows[(v, f)] = (v_rest, [b.velocity_m_s for b in branches if b.stable])
            for o in sp.cache.values():
                stats["orbits"] += 1
                stats["periods"] += o.periods
                if o.k == 0:
                    stats["k0"] += 1
                    stats["k0_periods"] += o.periods
    stats["time_s"] = time.perf_counter() - t0
    return rows, stats


def _g_change(params) -> tuple[int, float, int]:
    """k = 0 samples, largest relative change of G and sign changes, former budget against
    now on the present scan's velocities."""
    n, worst, flips = 0, 0.0, 0
    for v0, f in LOW_SPEED_POINTS:
        now = slow_problem(params, OperatingPoint(float(v0), float(f), 40e3, 0.0))
        old = dataclasses.replace(_former(now), v_floor_m_s=now.v_floor_m_s)
        vs = scan_grid(now.v_floor_m_s, now.v_max_m_s)
        for v in vs:
            a, b = old.thrust(v), now.thrust(v)
            if now.cache[v].k == 0 or old.cache[v].k == 0:
                n += 1
                worst = max(worst, abs(b - a) / max(abs(a), 1e-12))
                flips += (a > 0) != (b > 0)
    return n, worst, flips


def measure() -> dict:
    """Everything :func:`main` prints, as numbers (``tools.doc_numbers`` quotes them)."""
    params = table2()
    volts, loads = np.linspace(50, 450, 9), np.linspace(10, 26, 9)
    steady_state(params, 200, 14, accuracy="fast")  # numba cache loaded before timing
    old_rows, old = _solve(params, volts, loads, former=True)
    new_rows, new = _solve(params, volts, loads, former=False)
    differ = []
    for key, (v_old, b_old) in old_rows.items():
        v_new, b_new = new_rows[key]
        same = len(b_old) == len(b_new) and all(
            abs(a - b) <= 1e-9 * max(abs(a), 1e-12)
            for a, b in zip([v_old, *b_old], [v_new, *b_new], strict=True))
        if not same:
            differ.append(f"{key[0]:g} V / {key[1]:g} N: {b_old} -> {b_new}")
    n, worst, flips = _g_change(params)
    return {"former": old, "now": new, "time_ratio": old["time_s"] / new["time_s"],
            "differ": differ, "k0_samples": n, "g_change_max": worst, "sign_changes": flips}


def main() -> None:
    m = measure()
    for name in ("former", "now"):
        s = m[name]
        print(f"{name:>6}: {s['orbits']} orbits, {s['k0']} with k = 0 taking "
              f"{s['k0_periods'] / s['periods']:.0%} of {s['periods']} periods; "
              f"{s['time_s']:.3g} s")
    print(f"time former / now: {m['time_ratio']:.2f}")
    print(f"points whose velocity from rest or stable branches differ: {len(m['differ'])}")
    for line in m["differ"]:
        print("  ", line)
    print(f"k = 0 samples at {len(LOW_SPEED_POINTS)} low-speed points: {m['k0_samples']}; "
          f"largest relative change of G {m['g_change_max']:.3g}; sign changes "
          f"{m['sign_changes']}")


if __name__ == "__main__":
    main()
