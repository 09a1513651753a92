"""Speed of the contact stage, measured after JIT, against the event-driven reference.

Prints the wall time of one 50 ms run at dt = 1e-7 s (median of repeats) with its switch
counts, of a 9 x 9 stick-slip map (threads over all cores and serial), and the speed ratio to
the solve_ivp reference measured in the same run, with the agreement of the two. Not a test:
numbers depend on the machine. Run: ``python benchmarks/contact_speed.py [--quick]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact.maps import stick_slip_map  # noqa: E402
from contact.options import SimulationOptions  # noqa: E402
from contact.simulate import simulate
from rom import table2  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="fewer repeats, smaller map")
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    p = table2()
    simulate(p, 200, 14, duration_s=0.001)  # JIT / cache load

    print(f"machine: {os.cpu_count()} CPUs")
    print(f"{'case':<28}{'kernel ms':>10}{'ref s':>9}{'ratio':>9}{'dv/v':>10}{'d stick':>9}"
          f"{'switches':>10}{'ref sw.':>9}")
    repeats = 3 if args.quick else args.repeats
    for v, f in ((200, 10), (200, 14), (400, 14), (100, 14)):
        times = []
        for _ in range(repeats):
            r = simulate(p, v, f)
            times.append(r.wall_time_s)
        t_k = statistics.median(times)
        ref = simulate(p, v, f, method="reference")
        v_ref = ref.steady.velocity_m_s
        dv = abs(r.steady.velocity_m_s - v_ref) / max(abs(v_ref), 1e-6)
        ds = abs(r.steady.stick_fraction - ref.steady.stick_fraction)
        name = f"{v} V / {f} N {r.steady.motion}"
        print(f"{name:<28}{t_k * 1e3:>10.1f}{ref.wall_time_s:>9.2f}"
              f"{ref.wall_time_s / t_k:>9.0f}{dv:>10.1e}{ds:>9.1e}{r.events:>10}"
              f"{ref.events:>9}")
    print("kernel: 50 ms simulated at dt = 1e-7 s (500 000 steps) incl. the A_N pre-pass")

    n = 5 if args.quick else 9
    volts = np.linspace(50, 450, n)
    loads = np.linspace(10, 26, n)
    opts = SimulationOptions()
    m = stick_slip_map(p, volts, loads, options=opts, progress=False)
    t0 = time.perf_counter()
    stick_slip_map(p, volts, loads, options=opts, workers=1, progress=False)
    serial = time.perf_counter() - t0
    print(f"{n}x{n} map: {m.wall_time_s:.2f} s on {os.cpu_count()} threads, "
          f"{serial:.2f} s serial (parallel speed-up {serial / m.wall_time_s:.2f}x)")


if __name__ == "__main__":
    main()
