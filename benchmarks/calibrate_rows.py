"""Where a calibration's steady rows run: in the calling process, on threads, on processes
(not a test: about a minute on an idle 2-core machine; ``--whole`` adds two calibrations of
the example, about two minutes).

    python benchmarks/calibrate_rows.py [--repeats 10] [--whole] [--json]

Times one model evaluation of ``examples/calibration/measurements.toml``'s 30 steady speeds
(Table 2, the paper's coupling, the engine's exact level) three ways in the same run:

* in this process, one row after another (the reference);
* on a thread pool of two (the steady kernels release the GIL, the Python around them
  does not);
* on :func:`calibration.model.row_pool`'s two processes, as ``lusm calibrate`` runs them.

Printed: the median and least wall time of each over ``--repeats`` evaluations, its ratio
to the reference, and whether the speeds are the same to the last bit. With ``--whole``,
the example's calibration with ``workers=1`` and with the default, their wall times and
whether the fitted values are the same.
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from calibration import calibrate, load_measurements
from calibration.model import row_pool, speeds_m_s
from rom.table2 import table2

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "calibration" / "measurements.toml"


def _timed(fn, repeats: int) -> tuple[np.ndarray, list[float]]:
    """``fn()``'s value and its wall times over ``repeats`` calls after one warm-up."""
    value = fn()
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return value, times


def rows(repeats: int) -> dict:
    """One evaluation of the example's speed rows, three ways."""
    meas = load_measurements(EXAMPLE)
    speeds = next(s for s in meas.sets if s.kind == "speed")
    p, x = table2(), speeds.inputs
    ref, t_ref = _timed(lambda: speeds_m_s(p, x, "paper", "exact"), repeats)
    with ThreadPoolExecutor(2) as threads:
        got_t, t_thr = _timed(lambda: speeds_m_s(p, x, "paper", "exact", threads), repeats)
    with row_pool(meas.sets, 2) as pool:
        got_p, t_proc = _timed(lambda: speeds_m_s(p, x, "paper", "exact", pool), repeats)
    out = {"rows": int(speeds.points), "repeats": repeats}
    for name, times, got in (("process", t_ref, ref), ("threads", t_thr, got_t),
                             ("pool", t_proc, got_p)):
        out[name] = {"median_s": float(np.median(times)), "least_s": float(min(times)),
                     "ratio": float(np.median(times) / np.median(t_ref)),
                     "same": bool(np.array_equal(got, ref))}
    return out


def whole() -> dict:
    """The example's calibration in this process and on the row pool."""
    out = {}
    for name, workers in (("process", 1), ("pool", None)):
        r = calibrate(load_measurements(EXAMPLE), table2(), coupling="paper", workers=workers)
        out[name] = {"wall_s": r.wall_time_s, "values": [float(v) for v in r.values],
                     "chi2": r.chi2, "evaluations": r.evaluations}
    out["same_fit"] = out["process"]["values"] == out["pool"]["values"]
    return out


def main() -> None:
    """Time the rows (and the whole calibration) and print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=10, help="evaluations timed (default 10)")
    ap.add_argument("--whole", action="store_true", help="time two whole calibrations too")
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args()
    if not 1 <= args.repeats <= 1000:
        ap.error(f"--repeats must be in [1, 1000], got {args.repeats}")
    result = {"rows": rows(args.repeats)}
    if args.whole:
        result["whole"] = whole()
    if args.json:
        print(json.dumps(result, indent=1))
        return
    r = result["rows"]
    for name in ("process", "threads", "pool"):
        x = r[name]
        print(f"{r['rows']} rows, {name:7s}: median {x['median_s']:.3f} s, least "
              f"{x['least_s']:.3f} s, {x['ratio']:.2f} of in-process, same speeds: {x['same']}")
    if args.whole:
        w = result["whole"]
        for name in ("process", "pool"):
            print(f"calibration, {name:7s}: {w[name]['wall_s']:.1f} s, "
                  f"{w[name]['evaluations']} evaluations, chi-square {w[name]['chi2']:.4f}")
        print(f"same fitted values: {w['same_fit']}")


if __name__ == "__main__":
    main()
