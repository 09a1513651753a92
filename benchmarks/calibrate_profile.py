"""The example calibration's profiles against a reference traced with full re-fits (not a
test: about four minutes on an idle 2-core machine).

    python benchmarks/calibrate_profile.py [--json]

Fits ``examples/calibration/measurements.toml`` (Table 2, the paper's coupling; ``C_l``,
``C_b``, ``a_mu``, ``b_mu``) once, then traces the profile of each identifiable parameter two
ways in the same run, at the same points (:data:`calibration.fit.PROFILE_STEPS` standard
errors, out to the first past chi-square + 3.84):

* as ``lusm calibrate`` does (:func:`calibration.fit._profile_side`: continuation, each
  re-fit at most :data:`calibration.fit.REFIT_NFEV` evaluations on the Jacobian of the step
  before);
* the reference: :func:`scipy.optimize.least_squares` of the other parameters at each point
  (its own finite-difference Jacobian at every iteration, ending at the fit's tolerance),
  from the point before.

Printed per parameter and side: the rise of chi-square at each point both ways, the
interval's end both ways, and the model evaluations each took.
"""

from __future__ import annotations

import argparse
import json
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

import calibration.fit as fit
from calibration import load_measurements
from calibration.model import row_pool
from rom.table2 import table2

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "calibration" / "measurements.toml"


def _reference_side(problem, i: int, best, chi2: float, targets: list[float]) -> list[float]:
    """Rise of chi-square at each scaled ``targets`` value of parameter ``i``, the others
    fitted by ``least_squares`` from the point before."""
    others = [k for k in range(best.x.size) if k != i]
    v, rises = best.x[others].copy(), []
    for t in targets:
        def fun(w, t=t):
            u = best.x.copy()
            u[i], u[others] = t, w
            return problem.residuals(u)

        r = least_squares(fun, v, bounds=(0.0, 1.0), method="trf", diff_step=fit.DIFF_STEP,
                          x_scale=1.0, max_nfev=fit.MAX_NFEV, ftol=fit.TOLERANCE,
                          xtol=fit.TOLERANCE)
        v = r.x
        rises.append(2.0 * r.cost - chi2)
    return rises


def _end(points: list[tuple[float, float]]) -> float | None:
    """Where the rise crosses 3.84 between the points (linearly), scaled."""
    for (u0, d0), (u1, d1) in zip(points, points[1:], strict=False):
        if d0 < fit.DELTA_CHI2_95 <= d1:
            return u0 + (fit.DELTA_CHI2_95 - d0) * (u1 - u0) / (d1 - d0)
    return None


def main() -> None:
    """Fit the example, trace both profiles each way and print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    meas = load_measurements(EXAMPLE)
    rows = []
    with row_pool(meas.sets) as pool:
        problem = fit._Problem(meas, table2(), "paper", "exact", None, pool)
        best = min(fit._fits(problem, 3, 0, True, lambda _t: None), key=lambda f: f[1].cost)[1]
        chi2 = 2.0 * float(best.cost)
        slope = problem.slope(best.x)
        cov, _ = fit._covariance(best.jac, slope)
        for i, p in enumerate(meas.parameters):
            if p.name in ("a_mu", "b_mu"):
                continue  # not identifiable on the example: no profile
            se_u = float(np.sqrt(cov[i, i]) / slope[i])
            for sign in (-1, +1):
                before = problem.evaluations
                pts, end, _open = fit._profile_side(problem, i, best, min(se_u, 0.25),
                                                    sign)
                used = problem.evaluations - before
                targets = [u for u, _ in pts[1:]]
                before = problem.evaluations
                ref = _reference_side(problem, i, best, chi2, targets)
                ref_used = problem.evaluations - before
                ref_pts = [pts[0], *zip(targets, ref, strict=True)]
                ref_end = _end(ref_pts)
                rows.append({
                    "name": p.name, "side": sign, "steps_se": [
                        round(float((u - best.x[i]) / se_u), 3) for u in targets],
                    "rise": [round(d, 3) for _, d in pts[1:]],
                    "reference_rise": [round(float(d), 3) for d in ref],
                    "end": float(problem.value(i, end)),
                    "reference_end": None if ref_end is None else float(
                        problem.value(i, ref_end)),
                    "evaluations": used, "reference_evaluations": ref_used})
    if args.json:
        print(json.dumps({"chi2": chi2, "sides": rows}, indent=1))
        return
    for r in rows:
        print(f"{r['name']} {'+' if r['side'] > 0 else '-'} side, at {r['steps_se']} standard "
              f"errors:\n  rise {r['rise']} ({r['evaluations']} evaluations)\n  reference "
              f"{r['reference_rise']} ({r['reference_evaluations']} evaluations)\n  end "
              f"{r['end']:.4f}, reference {r['reference_end']}")


if __name__ == "__main__":
    main()
