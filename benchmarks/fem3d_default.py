"""Accuracy and cost of ``lusm modes --model 3d``'s default against converged 3D meshes.

For each stator: a reference (the quarter-plate model on refine 8, layers 8, grading 4 for a
plain plate, which agrees with a converged model of another FE code to 1e-5 and 0.08 %
(issue 38); for the stator with a tip its gmsh planform at 0.6 mm, 1.6 times finer than its
own, in layers graded twice: finer meshes did not fit the machine's time), the default pair
of graded meshes (:func:`fem.solid3d.estimate.estimated_solid_modes`: the fine mesh's
numbers and the estimated error) and the ``--quick`` uniform mesh. Each
solve runs in its own process, so its CPU time (user + system, all threads) and peak memory
are its own; every solve prints one JSON line, and ``--reuse FILE`` takes the solves of an
earlier run's lines instead of repeating them (the references take minutes).

Usage::

    python benchmarks/fem3d_default.py [--plates paper p36 p26 tip] [--reuse runs.jsonl]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

from fem.mesh_settings import MeshSettings

PLATES = {"paper": (30.0, 7.5, 3.0, 0.5), "p36": (36.0, 9.0, 2.5, 0.5),
          "p26": (26.0, 6.5, 3.5, 1.0)}
"""Plain plates: length, width, thickness, gap (mm): the paper's and issue 38's two."""

TIP = "examples/tip_parametric/stator.toml"
"""The example stator with a tip (the paper's plate and a 2 x 1 mm tip, gmsh-meshed)."""

REFERENCE = {"plain": ("-", 8, 8, 4), "tip": ("0.6", 0, 3, 2)}
"""``(planform element size mm or '-', refine, layers, grading)`` of the references."""

KEYS = ("L1s", "L1o", "B2s", "B2o")


def _stator(plate: str, size: str):
    import dataclasses

    if plate == "tip":
        from fem.stator_file import load_stator

        st = load_stator(TIP).stator
        return st if size == "-" else dataclasses.replace(st, mesh_size_m=float(size) * 1e-3)
    from fem.geometry import PlateStator

    L, W, H, G = PLATES[plate]
    return PlateStator(length_m=L * 1e-3, width_m=W * 1e-3, thickness_m=H * 1e-3,
                       electrode_gap_m=G * 1e-3)


def _record(plate: str, setting: str, res, estimate=None) -> dict:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    rec = {"plate": plate, "setting": setting, "dofs": res.dofs,
           "cpu_s": usage.ru_utime + usage.ru_stime, "peak_MB": usage.ru_maxrss / 1024}
    for key, (m, q) in zip(KEYS + ("kL1", "kB2"), (
            ("L1", "f_short_Hz"), ("L1", "f_open_Hz"), ("B2", "f_short_Hz"),
            ("B2", "f_open_Hz"), ("L1", "k_eff"), ("B2", "k_eff")), strict=True):
        rec[key] = getattr(getattr(res, m), q)
        if estimate is not None:
            rec["err_" + key] = estimate.error(m, q)
    return rec


def solve_one(plate: str, setting: str) -> dict:
    """One solve in this process: ``setting`` is ``reference``, ``default`` or ``quick``."""
    from fem.solid3d.estimate import QUICK_MESH, estimated_solid_modes
    from fem.solid3d.model import solid_modes
    from fem.solid3d.symmetric import symmetric_solid_modes

    kind = "tip" if plate == "tip" else "plain"
    if setting == "reference":
        size, r, layers, g = REFERENCE[kind]
        st = _stator(plate, size)
        solve = solid_modes if kind == "tip" else symmetric_solid_modes
        return _record(plate, setting, solve(st, "pzt8", 2, r or 3, layers, edge_grading=g))
    st = _stator(plate, "-")
    if setting == "default":
        est = estimated_solid_modes(st)
        return _record(plate, setting, est.fine, est)
    q = QUICK_MESH
    return _record(plate, setting, solid_modes(st, "pzt8", MeshSettings(2, q.refine, q.layers)))


def _run(plate: str, setting: str) -> dict:
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, __file__, "--one", plate, setting], text=True,
                         capture_output=True, check=True)
    rec = json.loads(out.stdout.strip().splitlines()[-1])
    rec["wall_s"] = time.perf_counter() - t0
    print(json.dumps(rec), file=sys.stderr, flush=True)
    return rec


def _row(rec: dict, ref: dict) -> str:
    freq = max(abs(rec[k] / ref[k] - 1.0) for k in KEYS)
    k_l1, k_b2 = (rec[k] / ref[k] - 1.0 for k in ("kL1", "kB2"))
    est = ""
    if "err_L1s" in rec:
        est = (f"{max(rec['err_' + k] / rec[k] for k in KEYS):.1e} | "
               f"{max(rec['err_' + k] / rec[k] for k in ('kL1', 'kB2')):.2%}")
    else:
        est = " | "
    return (f"| {rec['plate']} | {rec['setting']} | {rec['dofs']} | {freq:.1e} | {k_l1:+.2%} | "
            f"{k_b2:+.2%} | {est} | {rec['cpu_s']:.1f} | {rec['peak_MB']:.0f} |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--plates", nargs="+", default=["paper", "p36", "p26", "tip"])
    p.add_argument("--reuse", default=None, help="JSON lines of an earlier run")
    p.add_argument("--one", nargs=2, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.one:
        print(json.dumps(solve_one(*args.one)))
        return
    done = {}
    if args.reuse:
        with open(args.reuse) as f:
            for line in f:
                rec = json.loads(line)
                done[rec["plate"], rec["setting"]] = rec
    print("| stator | setting | dofs | max freq err | k L1 err | k B2 err | est. freq err "
          "| est. k err | CPU (s) | peak (MB) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for plate in args.plates:
        recs = {s: done.get((plate, s)) or _run(plate, s)
                for s in ("reference", "default", "quick")}
        for s in ("default", "quick"):
            print(_row(recs[s], recs["reference"]))


if __name__ == "__main__":
    main()
