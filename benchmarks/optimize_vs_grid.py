"""lusm optimize against a dense explore grid, and optuna's TPE against scipy's
differential evolution (docs/optimize.md, "Measured").

The problem (issue 41): the tuned 35 mm stator of examples/optimize/stator.toml, its plate
length, width and tip length varied; the objective is the mechanical power at 300 V / 14 N
(``peak_power``, the largest v F along the characteristic), the constraint |split| <= 0.5 %
of f_L1. The grid is computed once by ``lusm explore`` (``studies.explore.explore``; kept in
``--folder`` and reused while its study is the same); each search then gets a tenth of the
grid's evaluations (``--budget``) on the same cluster:

* ``lusm optimize`` (``studies.optimize.optimize``: TPE, batches of the workers), per seed;
* the same with ``split = "tuned"``: the length and tip length searched, each design's width
  tuned to L1 = B2 (``fem.tuning.tune_plate``) within the grid's width range, per seed;
* ``scipy.optimize.differential_evolution`` with a dask map as ``workers`` (deferred
  updating, no polish), the constraint as a penalty (an infeasible design scores its
  excess, above every feasible one's minus power), per seed.

Each is scored by its best feasible power over the grid's best, and by the evaluations it
took to come within 1 % of the grid's best (None if it never did). Every evaluation is the
same computation (``studies.task.compute_geometry`` of the one-plate study).

Run: ``python benchmarks/optimize_vs_grid.py [--levels 9,9,3] [--seeds 0,1,2] [--budget N]
[--methods tpe,tuned,de] [--json]``
(the grid of 9 x 9 x 3 plates takes about half an hour on 2 loaded cores).
"""

from __future__ import annotations

import argparse
import json
import shutil
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
STATOR = ROOT / "examples" / "optimize" / "stator.toml"
BOUNDS_MM = {"length": (34.0, 38.0), "width": (9.0, 10.2), "tip_length": (0.6, 1.4)}
"""The box of the three variables (mm): the grid's ends and the searches' bounds."""
SPLIT_MAX = 0.005
"""|split| / f_L1 at most (0.5 %)."""


def base_doc() -> dict:
    """The study both the grid and the searches evaluate (300 V, 14 N, the stator file)."""
    return {"outputs": ["split", "f_L1_short", "no_load_velocity", "stall_force",
                        "peak_power"],
            "study": {"name": "optimize vs grid", "stator": "stator.toml"},
            "axes": {"voltage": "300 V", "preload": "14 N"}}


def grid_doc(levels: tuple[int, int, int]) -> dict:
    doc = base_doc()
    for (name, (lo, hi)), n in zip(BOUNDS_MM.items(), levels, strict=True):
        doc["axes"][name] = {"start": f"{lo} mm", "stop": f"{hi} mm", "num": n}
    return doc


def problem_doc(budget: int, seed: int, tuned: bool = False) -> dict:
    """The search's study: the three variables with the split bound, or (``tuned``) the
    length and tip length with each design's width tuned to L1 = B2 within the grid's width
    range (``split = "tuned"``)."""
    doc = base_doc()
    bounds = {k: {"min": f"{lo} mm", "max": f"{hi} mm"} for k, (lo, hi) in BOUNDS_MM.items()}
    constraints = {"split": f"{SPLIT_MAX * 100:g} %"}
    if tuned:
        constraints = {"split": "tuned", "tune": {"variable": "width", **bounds.pop("width")}}
    doc["optimize"] = {
        "evaluations": budget, "seed": seed, "variables": bounds,
        "objectives": [{"output": "peak_power", "goal": "maximize"}],
        "constraints": constraints}
    return doc


def run_grid(folder: Path, levels, client) -> dict:
    """The grid's best feasible power (W) and its plate, computed by explore once."""
    from studies.dataset import open_result
    from studies.explore import explore
    from studies.study import study_from_dict

    study = study_from_dict(grid_doc(levels), str(folder / "grid.toml"))
    out = folder / "grid.nc"
    t0 = time.perf_counter()
    if not (out.exists() and open_result(out).attrs["study_fingerprint"] == study.fingerprint):
        explore(study, out, client=client, force=True, resume=(out.with_suffix(".nc.parts")
                                                                .exists()))
    ds = open_result(out).squeeze(drop=True)
    power = ds["peak_power"].values
    ok = np.abs(ds["split"].values / ds["f_L1_short"].values) <= SPLIT_MAX
    ok &= np.isfinite(power)
    best = np.unravel_index(np.nanargmax(np.where(ok, power, np.nan)), power.shape)
    plate = {a: float(ds[a].values[i]) * 1e3 for a, i in zip(("length", "width",
                                                               "tip_length"), best,
                                                              strict=True)}
    return {"evaluations": int(power.size), "feasible": int(ok.sum()),
            "best_W": float(power[best]), "best_mm": plate,
            "wall_s": time.perf_counter() - t0}


def score(history: list[float], grid_best: float) -> dict:
    """A search's best feasible power and the evaluations it took to come within 1 % of
    the grid's best (``history``: each evaluation's power, NaN where infeasible)."""
    h = np.asarray(history, dtype=float)
    best = np.fmax.accumulate(np.where(np.isfinite(h), h, -np.inf))
    hit = np.flatnonzero(best >= 0.99 * grid_best)
    return {"evaluations": int(h.size), "best_W": float(best[-1]) if h.size else None,
            "best_over_grid": float(best[-1] / grid_best) if h.size else None,
            "evaluations_to_1pct": int(hit[0] + 1) if hit.size else None}


def run_tpe(folder: Path, budget: int, seed: int, client, grid_best: float,
            tuned: bool = False) -> dict:
    """One ``lusm optimize`` search (``tuned``: ``split = "tuned"``), scored; its best
    design (mm), its wall time and its CPU time (s, :func:`cpu_s`)."""
    from studies.dataset import open_result
    from studies.optimize import optimize, problem_from_dict
    from studies.optimize.result import best_row, row_design

    problem = problem_from_dict(problem_doc(budget, seed, tuned), str(folder / "problem.toml"))
    t0, c0 = time.perf_counter(), cpu_s(client)
    name = f"tpe{'-tuned' if tuned else ''}-{seed}-{budget}.nc"
    result = optimize(problem, folder / name, client=client, force=True)
    ds = open_result(result.path)
    power = np.where(ds["feasible"].values == 1, ds["objective_peak_power"].values, np.nan)
    row = best_row(ds)
    best = None if row is None else {k: v * 1e3 for k, v in
                                     row_design(problem, ds, row).items()}
    return {"seed": seed, **score(list(power), grid_best), "best_mm": best,
            "feasible": int(ds["feasible"].values.sum()), "wall_s": time.perf_counter() - t0,
            "cpu_s": cpu_s(client) - c0}


def _process_cpu_s() -> float:
    import psutil

    t = psutil.Process().cpu_times()
    return t.user + t.system


def cpu_s(client) -> float:
    """The CPU time (s, user + system) of this process and of every worker process so far:
    on a shared machine the measure of a search's work that the others' load leaves alone."""
    return _process_cpu_s() + sum(client.run(_process_cpu_s).values())


def de_value(x, problem) -> tuple[float, float]:
    """One design's power (W) and constraint excess (<= 0 met): the task of a DE member."""
    from studies.optimize.metrics import evaluation_metrics
    from studies.optimize.problem import trial_study
    from studies.task import compute_geometry

    design = {v.name: float(xi) for v, xi in zip(problem.variables, x, strict=True)}
    study = trial_study(problem, design)
    values, cons = evaluation_metrics(problem, compute_geometry(study, 0), design, study)
    return values[0], cons[0]


def run_de(budget: int, seed: int, client, grid_best: float, folder: Path) -> dict:
    """scipy's differential evolution with a dask map as ``workers``: a population of 6
    (popsize 2 x 3 variables), as many generations as the budget allows."""
    from scipy.optimize import differential_evolution

    from studies.optimize import problem_from_dict

    problem = problem_from_dict(problem_doc(budget, seed), str(folder / "problem.toml"))
    history: list[float] = []

    def dask_map(func, xs):
        xs = [np.asarray(x) for x in xs]
        pairs = client.gather(client.map(de_value, xs, problem=problem, pure=False))
        out = []
        for power, excess in pairs:
            feasible = np.isfinite(power) and np.isfinite(excess) and excess <= 0
            history.append(power if feasible else np.nan)
            out.append(-power if feasible else 1.0 + (excess if np.isfinite(excess) else 1.0))
        return out

    bounds = [(v.low, v.high) for v in problem.variables]
    pop = 2 * len(bounds)
    t0 = time.perf_counter()
    differential_evolution(lambda x: 0.0, bounds, popsize=2, maxiter=max(budget // pop - 1, 0),
                           seed=seed, polish=False, updating="deferred", workers=dask_map,
                           init="latinhypercube", tol=0.0)
    return {"seed": seed, **score(history[:budget], grid_best),
            "wall_s": time.perf_counter() - t0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", default="/tmp/lusm-optimize-vs-grid")
    parser.add_argument("--levels", default="9,9,3", help="grid levels of length,width,tip")
    parser.add_argument("--budget", type=int, default=None, help="default: grid / 10")
    parser.add_argument("--seeds", default="0,1,2")
    parser.add_argument("--methods", default="tpe,tuned,de",
                        help="the searches to run: tpe, tuned (TPE with split = \"tuned\"), de")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    from studies.cluster import study_client

    folder = Path(args.folder)
    folder.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(STATOR, folder / "stator.toml")
    levels = tuple(int(n) for n in args.levels.split(","))
    seeds = [int(s) for s in args.seeds.split(",")]
    with study_client(None, None, None, args.workers, gmsh=True) as client:
        grid = run_grid(folder, levels, client)
        budget = args.budget or grid["evaluations"] // 10
        methods = args.methods.split(",")
        tpe = [run_tpe(folder, budget, s, client, grid["best_W"]) for s in seeds
               if "tpe" in methods]
        tuned = [run_tpe(folder, budget, s, client, grid["best_W"], tuned=True) for s in seeds
                 if "tuned" in methods]
        de = [run_de(budget, s, client, grid["best_W"], folder) for s in seeds
              if "de" in methods]
    report = {"grid": grid, "budget": budget, "tpe": tpe, "tpe_tuned": tuned,
              "differential_evolution": de}
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"grid {args.levels}: {grid['evaluations']} plates, {grid['feasible']} feasible, best "
          f"{grid['best_W']:.4g} W at {grid['best_mm']} ({grid['wall_s']:.0f} s)")
    for name, runs in (("TPE (lusm optimize)", tpe), ("TPE, split = tuned", tuned),
                       ("differential evolution", de)):
        for r in runs:
            print(f"{name}, seed {r['seed']}: {r['evaluations']} evaluations, best "
                  f"{r['best_W']:.4g} W = {r['best_over_grid']:.4f} x grid best, within 1 % "
                  f"after {r['evaluations_to_1pct']} evaluations ({r['wall_s']:.0f} s)")


if __name__ == "__main__":
    main()
