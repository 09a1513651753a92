"""The example calibration's run time, with the friction screen ranked fast and exactly
(not a test: about two minutes on an idle 2-core machine).

    python benchmarks/calibrate_example.py [--seeds 0,1,2] [--json]

Fits ``examples/calibration/measurements.toml`` (4 parameters, 30 speeds, 20 free
amplitudes; Table 2, the paper's coupling) twice per seed:

* as ``lusm calibrate`` does: the screen's Sobol points ranked by the steady engine's
  ``fast`` level, its :data:`calibration.fit.SCREEN_RERANK` best ranked again exactly;
* the reference: every screen point ranked exactly.

Printed per seed and run: wall time of the whole fit and of the screen, model evaluations,
chi-square, the fitted values, and the fast screen's wall time as a share of the
reference's.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import calibration.fit as fit
from calibration import calibrate, load_measurements
from rom.table2 import table2

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "calibration" / "measurements.toml"


def run(seed: int, rerank: int) -> dict:
    """One calibration of the example with ``rerank`` screen points ranked exactly."""
    saved = fit.SCREEN_RERANK
    fit.SCREEN_RERANK = rerank
    stages: list[tuple[float, str]] = []
    try:
        t0 = time.perf_counter()
        result = calibrate(load_measurements(EXAMPLE), table2(), coupling="paper", seed=seed,
                           progress=lambda text: stages.append((time.perf_counter(), text)))
    finally:
        fit.SCREEN_RERANK = saved
    screen_end = next(t for t, text in stages if text.startswith("local fit"))
    return {"seed": seed, "reranked": rerank, "wall_s": round(result.wall_time_s, 2),
            "screen_s": round(screen_end - t0, 2), "evaluations": result.evaluations,
            "chi2": round(result.chi2, 4),
            "values": dict(zip(result.names, (float(v) for v in result.values), strict=True))}


def main() -> None:
    """Run both screens per seed and print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0", help="comma-separated seeds (default 0)")
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args()
    try:
        seeds = [int(s) for s in args.seeds.split(",")]
    except ValueError:
        ap.error(f"--seeds must be comma-separated whole numbers, got {args.seeds!r}")
    rows = []
    for seed in seeds:
        fast, exact = run(seed, fit.SCREEN_RERANK), run(seed, 2 ** fit.SCREEN_FRICTION_LOG2)
        same = all(np.isclose(fast["values"][k], exact["values"][k], rtol=1e-6)
                   for k in fast["values"])
        rows.append({"fast": fast, "exact": exact, "same_fit": bool(same),
                     "screen_ratio": round(fast["screen_s"] / exact["screen_s"], 3)})
    if args.json:
        print(json.dumps(rows, indent=1))
        return
    for r in rows:
        for name in ("fast", "exact"):
            x = r[name]
            print(f"seed {x['seed']} {name:5s}: {x['wall_s']:6.1f} s (screen {x['screen_s']:5.1f}"
                  f" s), {x['evaluations']} evaluations, chi-square {x['chi2']:.2f}")
        print(f"  screen time fast/exact {r['screen_ratio']:.2f}; same fitted values: "
              f"{r['same_fit']}")


if __name__ == "__main__":
    main()
