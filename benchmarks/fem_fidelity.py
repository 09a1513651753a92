"""2D plate model against the 3D model across electrode gaps (issue 8; not a test).

For the paper's plate (30 x 7.5 x 3 mm, PZT-8) and each gap prints the short- and
open-circuit L1 and B2 frequencies and both k_eff of

* ``2D old``: the earlier plate model (``gap_model='open'``: ``D3 = 0`` gap strips, diagonal
  capacitance, no thickness inertia);
* ``2D new``: the default plate model (shorted gap strips with the cross-section
  capacitances and gap coupling, thickness inertia);
* ``3D``: :mod:`fem.solid3d.model` on the meshes given by ``--meshes`` (``refine x layers``),
  and, with ``--graded K ...``, on the first of them graded ``K`` times towards the electrode
  edges (``edge_grading``); with three or more gradings also their geometric (Aitken)
  extrapolation, ``3D graded extrapolated``,

and the 2D/3D - 1 of the new model against the last 3D row of the gap (the extrapolation,
the finest grading or the finest uniform mesh). Gaps above thickness/6 are outside the 2D
model's validity (it warns; the row is printed anyway). Each wall time is printed as a
multiple of the new 2D model's at the same gap, measured in the same run.

Run: ``python benchmarks/fem_fidelity.py [--gaps-mm 0.1 0.5 2] [--refine-2d 4]
[--meshes 3x3 4x4] [--graded 1 2 3]`` (the docs' tables: ``python -m tools.doc_tables
--list``).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.mesh_settings import MeshSettings  # noqa: E402
from fem.model import GapValidityWarning, plate_model  # noqa: E402
from fem.modes import modes_of_model  # noqa: E402
from fem.solid3d.model import build_solid_model, modes_of_solid_model  # noqa: E402
from validation.work_precision import aitken  # noqa: E402


def _row(res) -> tuple[float, ...]:
    return (res.L1.f_short_Hz, res.L1.f_open_Hz, res.B2.f_short_Hz, res.B2.f_open_Hz,
            res.L1.k_eff, res.B2.k_eff)


def run_2d(stator: PlateStator, refine: int, gap_model: str, inertia: bool):
    """(six values, wall s) of the 2D model."""
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GapValidityWarning)
        model = plate_model(stator, "pzt8",
                            MeshSettings(2, refine, gap_model=gap_model, thickness_inertia=inertia))
    return _row(modes_of_model(model)), time.perf_counter() - t0


def run_3d(stator: PlateStator, refine: int, layers: int, grading: int = 0):
    """(six values, wall s) of the 3D model."""
    t0 = time.perf_counter()
    res = modes_of_solid_model(build_solid_model(
        stator, "pzt8", MeshSettings(2, refine, layers, edge_grading=grading)))
    return _row(res), time.perf_counter() - t0


def _fmt_hz(v: float) -> str:
    return f"{v:,.1f}".replace(",", " ")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gaps-mm", type=float, nargs="+", default=[0.1, 0.5, 1.0, 2.0])
    ap.add_argument("--refine-2d", type=int, default=4)
    ap.add_argument("--meshes", nargs="+", default=["3x3"], help="3D refine x layers")
    ap.add_argument("--graded", type=int, nargs="*", default=[],
                    help="edge gradings of the first 3D mesh (e.g. 1 2 3)")
    args = ap.parse_args(argv)
    print("| gap (mm) | model | L1 short | L1 open | B2 short | B2 open | k L1 | k B2 | "
          "wall / 2D |")
    print("|" + "---|" * 9)
    for gap_mm in args.gaps_mm:
        st = PlateStator(electrode_gap_m=gap_mm * 1e-3)
        rows = [("2D old", *run_2d(st, args.refine_2d, "open", False)),
                ("2D", *run_2d(st, args.refine_2d, "shorted", True))]
        for mesh in args.meshes:
            r, lay = (int(v) for v in mesh.split("x"))
            rows.append((f"3D {mesh}", *run_3d(st, r, lay)))
        r, lay = (int(v) for v in args.meshes[0].split("x"))
        for k in args.graded:
            rows.append((f"3D {args.meshes[0]} graded {k}", *run_3d(st, r, lay, k)))
        if len(args.graded) >= 3:
            last = [row[1] for row in rows[-3:]]
            rows.append(("3D graded extrapolated",
                         tuple(aitken(*(v[i] for v in last)) for i in range(6)), float("nan")))
        t_2d = rows[1][2]
        for name, vals, wall in rows:
            freqs = " | ".join(_fmt_hz(v) for v in vals[:4])
            ratio = "" if wall != wall else f"{wall / t_2d:.2g}"
            print(f"| {gap_mm:g} | {name} | {freqs} | {vals[4]:.4f} | {vals[5]:.4f} | "
                  f"{ratio} |")
        ref_name, ref = rows[-1][0], rows[-1][1]
        new = rows[1][1]
        rel = [new[i] / ref[i] - 1.0 for i in range(6)]
        print(f"| | 2D / {ref_name} − 1 | "
              + " | ".join(f"{100 * v:+.3f} %".replace("-", "−") for v in rel[:4]) + " | "
              + " | ".join(f"{100 * v:+.1f} %".replace("-", "−") for v in rel[4:]) + " | |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
