"""Steady engine against settled transients: speed and error (issue 9).

    python benchmarks/steady_speed.py            # one point, 200 V / 14 N
    python benchmarks/steady_speed.py --map      # the 9 x 9 map, 50-450 V x 10-26 N

The reference is the event scheme run from rest and averaged over its last 400 periods, for
the shortest length on the ladder ``--duration`` (default 0.3 s, 12 000 periods), 2x, 4x, ... up to
2.4 s whose velocity the next rung confirms to 1e-6 (``contact.steady.settled_duration``): the
settled transient. Only the run of that length is timed (finding the length is not
counted); a point that does not settle (creep below the slider's velocity ripple) keeps the
first length and is marked ``settled: false``. Times are wall
times measured in the same run, medians of ``--repeats`` calls (5 for the single point, 1 on
the map); the first call of each solver is made before timing (numba compilation excluded). Beside
the reference, the same settled length is timed at 20 steps per period (``coarse``): with the
kernel's exact propagators only event location depends on the step, so this is the cheapest
transient of nearly the same accuracy, and the steady engine's speed is also given against it.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from contact.steady.engine import steady_state
from contact.steady.settled import settled_duration, transient_reference
from rom import table2

COARSE_STEPS = 20
"""Steps per period of the coarse transient timed beside the reference (250 per period)."""
COARSE_DT_S = 1.0 / (40e3 * COARSE_STEPS)
"""Its time step (s) at the benchmarks' 40 kHz."""


def _timed(fn, repeats):
    """``(result, median wall time)`` over ``repeats`` calls."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return out, float(np.median(times))


def point(params, v0, fp, duration, repeats=1):
    """One row: the settled transient (timed at its settled length) and both steady levels
    (medians of ``repeats`` timed calls), velocities, errors and times."""
    length, settled = settled_duration(params, v0, fp, start_s=duration)
    (v_ref, motion), t_ref = _timed(
        lambda: transient_reference(params, v0, fp, duration_s=length), repeats)
    row = {"voltage_V": v0, "preload_N": fp, "motion": motion, "transient_m_s": v_ref,
           "transient_s": t_ref, "transient_duration_s": length, "settled": settled}
    # the same settled transient at COARSE_STEPS steps per period: the event kernel's
    # propagators are exact, so a coarse step costs only event-location accuracy
    (v_c, _), row["coarse_s"] = _timed(
        lambda: transient_reference(params, v0, fp, duration_s=length,
                                    dt_s=COARSE_DT_S), repeats)
    row["coarse_m_s"] = v_c
    row["coarse_rel_error"] = abs(v_c - v_ref) / max(abs(v_ref), 1e-12)
    for acc in ("fast", "exact"):
        r, row[f"{acc}_s"] = _timed(lambda acc=acc: steady_state(params, v0, fp, accuracy=acc),
                                    repeats)
        row[f"{acc}_m_s"] = r.velocity_m_s
        row[f"{acc}_branches"] = len(r.branches)
        scale = max(abs(v_ref), 1e-12)
        row[f"{acc}_rel_error"] = abs(r.velocity_m_s - v_ref) / scale
        row[f"{acc}_abs_error_m_s"] = abs(r.velocity_m_s - v_ref)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--map", action="store_true", help="run the 9 x 9 map")
    ap.add_argument("--duration", type=float, default=0.3,
                    help="first transient length of the settling ladder (s)")
    ap.add_argument("--repeats", type=int, default=None,
                    help="timed repeats per point, medians reported (default 5, map 1)")
    args = ap.parse_args()
    params = table2()
    steady_state(params, 200, 14, accuracy="exact")  # warm the numba cache
    transient_reference(params, 200, 14, duration_s=0.01, steady_periods=20)
    points = ([(v, f) for v in np.linspace(50, 450, 9) for f in np.linspace(10, 26, 9)]
              if args.map else [(200.0, 14.0)])
    repeats = args.repeats or (1 if args.map else 5)
    rows = [point(params, float(v), float(f), args.duration, repeats) for v, f in points]
    for r in rows:
        print(json.dumps(r))
    t_ref = sum(r["transient_s"] for r in rows)
    for acc in ("fast", "exact"):
        t = sum(r[f"{acc}_s"] for r in rows)
        err = np.array([r[f"{acc}_rel_error"] for r in rows])
        moving = np.array([abs(r["transient_m_s"]) > 1e-6 for r in rows])
        print(f"{acc:>5}: {t:.3g} s against {t_ref:.3g} s transient -> speedup "
              f"{t_ref / t:.3g}x; relative error on moving points: median "
              f"{np.median(err[moving]) if moving.any() else float('nan'):.2e}, max "
              f"{np.max(err[moving]) if moving.any() else float('nan'):.2e}; "
              f"held points {int((~moving).sum())}")
    moving = np.array([abs(r["transient_m_s"]) > 1e-6 for r in rows])
    t_c = sum(r["coarse_s"] for r in rows)
    t_x = sum(r["exact_s"] for r in rows)
    err_c = np.array([r["coarse_rel_error"] for r in rows])[moving]
    print(f"coarse transient ({COARSE_STEPS} steps per period, same length): {t_c:.3g} s, "
          f"{t_ref / t_c:.3g}x faster than the reference; relative error on moving points "
          f"max {err_c.max() if err_c.size else float('nan'):.2e}; the exact level is "
          f"{t_c / t_x:.3g}x faster than it")
    if args.map:
        _map_line(params, rows, t_ref)
    else:
        _fixed_costs(params, rows[0], repeats)


def _fixed_costs(params, row, repeats: int) -> None:
    """What one steady point costs before any orbit is searched: the Eq. 11 normal amplitude A_N
    that fixes mu_d,eff as the transient scheme does (closed form where the tip does not
    separate, else a 60-period pre-pass; :func:`contact.transient.pre_pass.normal_amplitude`)
    and the fast and full systems with their matrix exponentials; the speed-up cannot exceed the
    transient's time over their sum."""
    from contact.model import OperatingPoint
    from contact.transient.pre_pass import normal_amplitude

    op = OperatingPoint(row["voltage_V"], row["preload_N"], 40e3)
    _, t_pre = _timed(lambda: normal_amplitude(params, op), max(repeats, 5))
    t_sys = setup_seconds(params, row["voltage_V"], row["preload_N"], max(repeats, 5))
    t_ref = row["transient_s"]
    print(f"fixed costs: Eq. 11 A_N = transient / {t_ref / t_pre:.3g}, systems and "
          f"propagators = transient / {t_ref / t_sys:.3g} -> speed-up bound "
          f"{t_ref / (t_pre + t_sys):.3g}x")
    from contact.steady.engine import steady_state

    periods = steady_state(params, row["voltage_V"], row["preload_N"], accuracy="exact").periods
    per_period = kernel_seconds_per_period(params, row["voltage_V"], row["preload_N"])
    print(f"period floor: the exact level simulates {periods} drive periods, "
          f"{per_period * 1e6:.3g} us each in the kernel -> speed-up bound "
          f"{t_ref / (periods * per_period):.3g}x with everything else free")
    print(f"systems and periods together: speed-up bound "
          f"{t_ref / (t_sys + periods * per_period):.3g}x")


def setup_seconds(params, voltage_V: float, preload_N: float, repeats: int = 5) -> float:
    """Wall time (s, median of ``repeats``) of the fast and the full system of one operating
    point with their matrix exponentials: what every steady point pays before its first
    orbit (``steady_state(..., accuracy="exact")`` builds both)."""
    from contact.model import OperatingPoint
    from contact.steady.full_orbit import full_system
    from contact.steady.periodic_orbit import fast_system

    op = OperatingPoint(voltage_V, preload_N, 40e3)
    _, t = _timed(lambda: (fast_system(params, op, params.mu_d),
                           full_system(params, op, params.mu_d)), repeats)
    return t


def kernel_seconds_per_period(params, voltage_V: float, preload_N: float,
                              periods: int = 200) -> float:
    """Wall time (s) of one drive period of the fast problem's kernel at 25 steps per period,
    on the orbit at the operating point's steady velocity (median of 5 runs of ``periods``
    periods, window closed): the unit of work of every orbit search."""
    from contact.model import OperatingPoint
    from contact.steady.engine import steady_state
    from contact.steady.periodic_orbit import period_map
    from contact.steady.slow import slow_problem

    v = steady_state(params, voltage_V, preload_N, accuracy="fast").velocity_m_s
    sp = slow_problem(params, OperatingPoint(voltage_V, preload_N, 40e3, 0.0))
    o = sp.orbit(v)
    period_map(sp.fs, o.z, o.mode, periods, window=False)
    _, t = _timed(lambda: period_map(sp.fs, o.z, o.mode, periods, window=False), 5)
    return t / periods


def _map_line(params, rows, t_ref: float) -> None:
    """``stick_slip_map(method="steady")`` (what ``lusm map`` runs: exact level, transient
    fallback on undecided points), one worker, against the same settled transients."""
    from contact.maps import stick_slip_map

    volts = np.linspace(50, 450, 9)
    loads = np.linspace(10, 26, 9)
    m = stick_slip_map(params, volts, loads, workers=1, progress=False, method="steady")
    ref = {(r["voltage_V"], r["preload_N"]): r["transient_m_s"] for r in rows}
    err = []
    for i, v in enumerate(volts):
        for j, f in enumerate(loads):
            v_ref = ref[(float(v), float(f))]
            err.append(abs(m.velocity_m_s[i, j] - v_ref) / max(abs(v_ref), 1e-12)
                       if abs(v_ref) > 1e-6 else abs(m.velocity_m_s[i, j] - v_ref))
    err = np.array(err)
    print(f"  map: {m.wall_time_s:.3g} s against {t_ref:.3g} s transient -> speedup "
          f"{t_ref / m.wall_time_s:.3g}x; worst relative error (moving) / absolute (held) "
          f"{err.max():.2e}; undecided points {int(m.fallback.sum())} (transient fallback); "
          f"points with several stable branches {sum(len(b) > 1 for b in m.branches.flat)}")


if __name__ == "__main__":
    main()
