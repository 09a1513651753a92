"""Start-up cost of the command line against the work it does (not a test).

Times fresh processes (median of repeats, numba cache warm) of: an empty interpreter,
``import numba``, numba's array-math registry (which imports SciPy's BLAS wrappers),
``import contact.simulate``, one 1 ms contact run, ``lusm simulate --voltage 200 --preload 14
--json`` (a 50 ms run) and ``lusm --help``, and prints each beside the 50 ms run's own
integration time measured in the same session. Run: ``python benchmarks/startup.py``.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

PY = sys.executable
CASES = (
    ("python -c pass", [PY, "-c", "pass"]),
    ("import numba", [PY, "-c", "import numba"]),
    ("import numba.np.arraymath (loads SciPy)", [PY, "-c", "import numba.np.arraymath"]),
    ("import contact.simulate", [PY, "-c", "import contact.simulate"]),
    ("simulate 1 ms (cache load)", [PY, "-c", "import contact.simulate as c; from rom import "
                                    "table2; c.simulate(table2(), 200, 14, duration_s=0.001)"]),
    ("lusm simulate ... --json (50 ms)", [PY, "-m", "validation.cli", "simulate", "--voltage",
                                          "200", "--preload", "14", "--json"]),
    ("lusm --help", [PY, "-m", "validation.cli", "--help"]),
)


def wall(cmd: list[str], repeats: int) -> float:
    """Median wall time (s) of ``repeats`` fresh processes."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    from contact.simulate import simulate
    from rom import table2

    simulate(table2(), 200.0, 14.0, duration_s=0.001)  # cache load in this process
    integration = statistics.median(simulate(table2(), 200.0, 14.0).wall_time_s
                                    for _ in range(5))
    subprocess.run(CASES[4][1], capture_output=True, check=True)  # warm the cache on disk
    print(f"machine: {os.cpu_count()} CPUs, {platform.machine()}, Python "
          f"{platform.python_version()}")
    print(f"integration of one 50 ms run (in process, after JIT): {integration * 1e3:.1f} ms")
    print(f"{'fresh process':<42}{'wall s':>8}{'x integration':>15}")
    for name, cmd in CASES:
        t = wall(cmd, args.repeats)
        print(f"{name:<42}{t:>8.3f}{t / integration:>15.1f}")


if __name__ == "__main__":
    main()
