"""The start from rest decided by the run out of the ripple zone against the transient from rest
(not a test: about ten minutes).

    python benchmarks/steady_from_rest.py [--json]

The exact level decides the branch a start from rest reaches by running the full model out of the
slider's ripple zone and following the averaged sheet it is on (:mod:`contact.steady.from_rest`),
and leaves the decision to the transient from rest where that run cannot decide. Here every
point is solved twice, with the probe and with ``rest="transient"`` (the transient from rest
decides, as before the probe), on

* the 9 x 9 maps (50-450 V x 10-26 N, 40 kHz, no load) of Table 2's, the beam and the FE sets;
* Table 2's 14 N line, 10-450 V;
* 60 random points of each of the three sets (4-30 N, 10-450 V, loads of -3 to 3 N at 60 %
  of them; seeds 1, 2, 3);
* the designer's tuned 60 kHz stator of ``examples/tuned_60k`` (40-300 V x 8, 14, 20 N, at its
  own drive frequency; needs gmsh);
* the hard points of the tests (period-2 orbits, creeps, folds, held sliders under loads).

Printed per set and in total: points, how many the probe decided, how many answers differ
(the velocity from rest by more than 1e-8 relative, or the list of branches: velocity to
1e-8, motion, reached from rest), the probe's tracking-check figures (the largest accepted
relative difference, the smallest rejected one) and the drive periods simulated with and
without the probe.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from contact.errors import RunawayError
from contact.model import OperatingPoint, resolve_coupling
from contact.steady import from_rest
from contact.steady.engine import steady_state
from contact.steady.full_orbit import full_system
from contact.steady.slow import slow_problem
from rom.sources import get_params

ROOT = Path(__file__).resolve().parents[1]
TUNED = ROOT / "examples" / "tuned_60k" / "stator.toml"
HARD = (("table2", 61.6, 6.78, 2.2), ("table2", 126.9, 14.72, -1.57),
        ("beam", 118.2, 8.35, -3.02), ("fem", 293.6, 24.12, -1.15),
        ("table2", 75.3, 14.73, 4.74), ("table2", 400, 14, 3.5), ("table2", 400, 24, 3.1),
        ("table2", 10, 6.5, -0.2), ("fem", 7.6, 8.0, 1.04), ("beam", 300, 14, 0.0))
HARD_ANY = ((316.34, 11.61, 2.841), (304.42, 17.60, -1.811), (410.16, 14.22, -0.912),
            (159.48, 9.85, 2.622), (186.50, 11.03, 0.957), (270.51, 23.91, -1.823))


def point_sets() -> dict[str, list[tuple[str, float, float, float]]]:
    """``{set: [(source, voltage_V, preload_N, load_N), ...]}``."""
    grid = [(float(v), float(f)) for v in np.linspace(50, 450, 9)
            for f in np.linspace(10, 26, 9)]
    sets = {f"{s} map": [(s, v, f, 0.0) for v, f in grid] for s in ("table2", "beam", "fem")}
    sets["table2 14 N line"] = [("table2", float(v), 14.0, 0.0)
                                for v in np.linspace(10, 450, 45)]
    for seed, s in enumerate(("table2", "fem", "beam"), start=1):
        rng = np.random.default_rng(seed)
        pts = []
        for _ in range(60):
            v, f = rng.uniform(10, 450), rng.uniform(4, 30)
            pts.append((s, v, f, rng.uniform(-3, 3) if rng.random() < 0.6 else 0.0))
        sets[f"{s} random"] = pts
    sets["tuned 60 kHz"] = [("tuned", float(v), f, 0.0) for v in np.linspace(40, 300, 27)
                            for f in (8.0, 14.0, 20.0)]
    hard = list(HARD) + [(s, v, f, ld) for v, f, ld in HARD_ANY
                         for s in ("table2", "fem", "beam")]
    hard += [("table2", float(v), 14.0, ld) for v in np.linspace(100, 450, 8)
             for ld in (-2.0, -1.0, 0.5, 1.0, 2.0)]
    sets["hard points"] = hard
    return sets


def _sources() -> dict[str, tuple[object, float]]:
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file

    out = {s: (get_params(s), 40e3) for s in ("table2", "beam", "fem")}
    tuned = fem_params_from_file(TUNED)
    out["tuned"] = (tuned, auto_frequency(tuned))
    return out


def _solve(params, f_Hz: float, v: float, f: float, load: float, rest: str = "probe"):
    try:
        return steady_state(params, v, f, frequency_Hz=f_Hz, load_N=load, energy=False,
                            rest=rest)
    except RunawayError:
        return None


def _same(a, b) -> bool:
    if a is None or b is None:
        return a is b
    va, vb = a.velocity_m_s, b.velocity_m_s
    if not (math.isnan(va) and math.isnan(vb)) and not abs(va - vb) <= 1e-8 * abs(va) + 1e-14:
        return False
    if len(a.branches) != len(b.branches):
        return False
    return all(abs(x.velocity_m_s - y.velocity_m_s) <= 1e-8 * abs(x.velocity_m_s) + 1e-14
               and x.motion == y.motion and x.from_rest == y.from_rest
               for x, y in zip(a.branches, b.branches, strict=True))


def measure(progress: bool = True) -> dict:
    """Both decisions on every point set (see the module's docstring)."""
    sources = _sources()
    out = {}
    for name, pts in point_sets().items():
        row = {"points": 0, "probe_decided": 0, "differ": [], "track_max_accepted": 0.0,
               "track_min_rejected": math.inf, "periods_probe": 0, "periods_transient": 0}
        for s, v, f, load in pts:
            params, f_Hz = sources[s]
            coupling = resolve_coupling(params, "auto")
            op = OperatingPoint(v, f, f_Hz, load)
            sp = slow_problem(params, op, coupling=coupling, accuracy="exact")
            probe = from_rest.probe_from_rest(sp, full_system(params, op, sp.mu_d_eff,
                                                              coupling))
            with_probe = _solve(params, f_Hz, v, f, load)
            without = _solve(params, f_Hz, v, f, load, rest="transient")
            row["points"] += 1
            if probe.orbit is not None and with_probe is not None \
                    and with_probe.rest_periods == probe.full_periods:
                row["probe_decided"] += 1
                row["track_max_accepted"] = max(row["track_max_accepted"], probe.track_error)
            elif "does not follow" in probe.reason:
                row["track_min_rejected"] = min(row["track_min_rejected"], probe.track_error)
            if not _same(with_probe, without):
                row["differ"].append([s, v, f, load])
            row["periods_probe"] += with_probe.periods if with_probe else 0
            row["periods_transient"] += without.periods if without else 0
        out[name] = row
        if progress:
            print(name, json.dumps(row), file=sys.stderr, flush=True)
    total = {k: sum(r[k] for r in out.values())
             for k in ("points", "probe_decided", "periods_probe", "periods_transient")}
    total["differ"] = sum(len(r["differ"]) for r in out.values())
    total["track_max_accepted"] = max(r["track_max_accepted"] for r in out.values())
    total["track_min_rejected"] = min(r["track_min_rejected"] for r in out.values())
    return {"sets": out, "total": total}


def main() -> None:
    m = measure()
    if "--json" in sys.argv:
        print(json.dumps(m, indent=1))
        return
    print(f"{'set':20s} {'points':>6s} {'probe':>6s} {'differ':>6s} {'accepted':>9s} "
          f"{'rejected':>9s} {'periods with/without':>22s}")
    for name, r in list(m["sets"].items()) + [("total", m["total"])]:
        differ = r["differ"] if isinstance(r["differ"], int) else len(r["differ"])
        print(f"{name:20s} {r['points']:6d} {r['probe_decided']:6d} {differ:6d} "
              f"{r['track_max_accepted']:9.3f} {r['track_min_rejected']:9.3f} "
              f"{r['periods_probe']:10d} / {r['periods_transient']:<10d}")


if __name__ == "__main__":
    main()
