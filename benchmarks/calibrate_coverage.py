"""Coverage of the example calibration's intervals over noise seeds (not a test: about 15
minutes on an idle 2-core machine).

    python benchmarks/calibrate_coverage.py [--seeds 20] [--first 1] [--hold a_mu] [--json]

For each seed, ``examples/calibration/make_data.py``'s free amplitudes and speeds of Table 2
(3 % noise, the speeds plus 0.2 mm/s) are drawn with that seed and fitted as
``examples/calibration/measurements.toml`` fits them (``C_l``, ``C_b``, ``a_mu``, ``b_mu``;
the paper's coupling; ``--hold NAME`` leaves a parameter out of the fit, at Table 2's value,
which is the truth). Printed: for each identifiable parameter, how many 95 % profile
intervals cover the truth (and how many of the standard intervals, 1.96 standard errors),
the mean error, the mean standard error and the fitted values' standard deviation; how often each
parameter was named not identifiable; the chi-square's mean against its degrees of freedom;
the mean wall time of a fit.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import tempfile
import warnings
from pathlib import Path

import numpy as np

from calibration import calibrate, load_measurements
from rom.table2 import table2

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "calibration"


def _make_data():
    """The example's data writer, a script beside its data."""
    spec = importlib.util.spec_from_file_location("make_data", EXAMPLE / "make_data.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def fit_seed(seed: int, folder: Path, make_data, hold: tuple[str, ...] = ()) -> dict:
    """Draw the example's data with ``seed`` in ``folder`` and fit them, the parameters
    ``hold`` names left out."""
    rng = np.random.default_rng(seed)
    (folder / "free.csv").write_text("\n".join(make_data.free_rows(rng)) + "\n")
    (folder / "speed.csv").write_text("\n".join(make_data.speed_rows(rng)) + "\n")
    lines = (EXAMPLE / "measurements.toml").read_text().splitlines(keepends=True)
    (folder / "measurements.toml").write_text("".join(
        ln for ln in lines if not any(ln.startswith(f"{name} = {{") for name in hold)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = calibrate(load_measurements(folder / "measurements.toml"), table2(),
                      coupling="paper", seed=seed)
    out = {"seed": seed, "chi2": r.chi2, "dof": r.dof, "wall_s": r.wall_time_s, "params": {}}
    for i, name in enumerate(r.names):
        prof = r.profiles.get(name)
        out["params"][name] = {
            "value": float(r.values[i]), "stderr": float(r.stderr[i]),
            "identifiable": bool(r.identifiable[i]),
            "interval": None if prof is None else [float(prof.lower), float(prof.upper)]}
    return out


def summary(rows: list[dict], truth: dict[str, float]) -> dict:
    """Coverage, bias and identifiability per parameter over the seeds."""
    out = {"seeds": len(rows), "mean_chi2": float(np.mean([r["chi2"] for r in rows])),
           "dof": rows[0]["dof"], "mean_wall_s": float(np.mean([r["wall_s"] for r in rows]))}
    for name, true in truth.items():
        fits = [r["params"][name] for r in rows]
        ok = [f for f in fits if f["identifiable"] and f["interval"] is not None]
        covered = sum(f["interval"][0] <= true <= f["interval"][1] for f in ok)
        wald = sum(abs(f["value"] - true) <= 1.96 * f["stderr"] for f in ok)
        out[name] = {
            "identifiable_in": len(ok), "covered_in": covered, "wald_covered_in": wald,
            "mean_error": float(np.mean([f["value"] - true for f in ok])) if ok else None,
            "mean_stderr": float(np.mean([f["stderr"] for f in ok])) if ok else None,
            "sd_of_values": float(np.std([f["value"] for f in ok], ddof=1))
            if len(ok) > 1 else None}
    return out


def main() -> None:
    """Fit every seed and print the coverage."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20, help="how many seeds (default 20)")
    ap.add_argument("--first", type=int, default=1, help="the first seed (default 1)")
    ap.add_argument("--hold", action="append", default=[], choices=("C_l", "C_b", "a_mu",
                                                                    "b_mu"),
                    help="leave this parameter out of the fit (repeatable)")
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args()
    if not 1 <= args.seeds <= 1000:
        ap.error(f"--seeds must be in [1, 1000], got {args.seeds}")
    if not 0 <= args.first <= 10**6:
        ap.error(f"--first must be in [0, 1000000], got {args.first}")
    make_data = _make_data()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(args.first, args.first + args.seeds):
            rows.append(fit_seed(seed, Path(tmp), make_data, tuple(args.hold)))
            if not args.json:
                p = rows[-1]["params"]
                print(f"seed {seed:2d}: chi2 {rows[-1]['chi2']:6.2f}, C_l {p['C_l']['value']:.2f}"
                      f", C_b {p['C_b']['value']:.2f}, {rows[-1]['wall_s']:.0f} s", flush=True)
    result = summary(rows, {k: v for k, v in make_data.TRUTH.items() if k not in args.hold})
    print(json.dumps(result if not args.json else {"summary": result, "seeds": rows},
                     indent=1))


if __name__ == "__main__":
    main()
