"""Start-up cost of the command line against the work it does (not a test).

Times fresh processes (median of repeats, numba cache warm) of: an empty interpreter,
``import numba``, numba's array-math registry (which imports SciPy's BLAS wrappers),
``import contact.simulate``, one 1 ms contact run, ``lusm simulate --voltage 200 --preload 14
--json`` (a 50 ms run) and ``lusm --help``, and prints each beside the 50 ms run's own
integration time measured in the same session; and the propagators of one run (NumPy
``contact.expm`` against ``scipy.linalg.expm``); and the stages of one fresh process (each
import, numba's target set-up, the cached kernel load, the run). Run:
``python benchmarks/startup.py``.
"""

from __future__ import annotations

import argparse
import json
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
    ("lusm simulate ... --json (50 ms)", [PY, "-m", "lusm.cli", "simulate", "--voltage",
                                          "200", "--preload", "14", "--json"]),
    ("lusm --help", [PY, "-m", "lusm.cli", "--help"]),
    # the same command with Python's default collector threshold (lusm raises it: cli.main)
    ("lusm simulate, default gc threshold", [
        PY, "-c", "import gc, sys; gc.set_threshold = lambda *a: None; "
        "from lusm.cli import main; sys.argv[1:] = ['simulate', '--voltage', '200', "
        "'--preload', '14', '--json']; sys.exit(main())"]),
    # the same command letting numba's BLAS probe import scipy.linalg whole (lusm.fast_start)
    ("lusm simulate, whole scipy.linalg", [
        PY, "-c", "import sys; from validation import fast_start; "
        "fast_start.load_blas_probe = lambda: False; "
        "from lusm.cli import main; sys.argv[1:] = ['simulate', '--voltage', '200', "
        "'--preload', '14', '--json']; sys.exit(main())"]),
)


STAGES = """
import json, sys, time
t = [time.perf_counter()]
import numpy
t.append(time.perf_counter())
import numba
t.append(time.perf_counter())
import scipy.linalg  # numba's BLAS probe imports it whole (lusm loads one module instead)
t.append(time.perf_counter())
from numba.core.registry import cpu_target
cpu_target.target_context.refresh()  # numba's own registries
t.append(time.perf_counter())
import contact.simulate as cs
from rom import table2
t.append(time.perf_counter())
cs.simulate(table2(), 200.0, 14.0, duration_s=0.001)  # loads the cached kernel
t.append(time.perf_counter())
cs.simulate(table2(), 200.0, 14.0)
t.append(time.perf_counter())
print(json.dumps([b - a for a, b in zip(t, t[1:])]))
"""
STAGE_NAMES = ("import numpy", "import numba", "import scipy.linalg (numba's BLAS probe)",
               "numba target set-up (own registries)", "import contact.simulate, rom",
               "first call, 1 ms (cached kernel load)", "one 50 ms run (pre-pass + run)",
               "interpreter start + exit (final GC)")


def stages(repeats: int) -> list[float]:
    """Median time (s) of each start-up stage, in fresh processes (see ``STAGES``)."""
    runs = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = subprocess.run([PY, "-c", STAGES], capture_output=True, check=True, text=True,
                             cwd=Path(__file__).resolve().parents[1])
        inside = json.loads(out.stdout)
        runs.append([*inside, time.perf_counter() - t0 - sum(inside)])
    return [statistics.median(col) for col in zip(*runs, strict=True)]


def wall(cmd: list[str], repeats: int) -> float:
    """Median wall time (s) of ``repeats`` fresh processes."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def propagator_times(repeats: int = 5) -> tuple[float, float]:
    """Median time (s) of the propagators of one run: NumPy ``expm_stack`` and SciPy's ``expm``.

    Alike on a quiet machine; SciPy's goes through its own threaded OpenBLAS and was measured
    at ~8 ms per 9 x 9 matrix on a busy one (``docs/contact.md`` 5.1), which is why
    :mod:`contact.expm` exists.
    """
    import numpy as np
    from scipy.linalg import expm

    from contact.expm import expm_stack
    from contact.model import OperatingPoint, build_system
    from rom import table2

    a = build_system(table2(), OperatingPoint(200.0, 14.0, 40e3), table2().mu_d).A * 1e-7

    def timed(fn) -> float:
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return statistics.median(times)

    t_np = timed(lambda: (expm_stack(a), expm_stack(0.5 * a)))
    t_sp = timed(lambda: (np.stack([expm(m) for m in a]), np.stack([expm(0.5 * m) for m in a])))
    return t_np, t_sp


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
    t_np, t_sp = propagator_times()
    print(f"propagators expm(A dt) of one run (2 x 18 matrices 9 x 9): contact.expm "
          f"{t_np * 1e3:.2f} ms ({t_np / integration:.3f} x integration), scipy.linalg.expm "
          f"one by one {t_sp * 1e3:.2f} ms ({t_sp / integration:.3f} x)")
    print(f"{'fresh process':<42}{'wall s':>8}{'x integration':>15}")
    for name, cmd in CASES:
        t = wall(cmd, args.repeats)
        print(f"{name:<42}{t:>8.3f}{t / integration:>15.1f}")
    print("(the lusm rows run the console-script path, lusm.cli.main() with argv None)")
    print(f"\n{'stages of one fresh process':<42}{'s':>8}")
    for name, t in zip(STAGE_NAMES, stages(args.repeats), strict=True):
        print(f"{name:<42}{t:>8.3f}")


if __name__ == "__main__":
    main()
