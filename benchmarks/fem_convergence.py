"""Convergence benchmark of the FE plate model (not a test).

For element orders 1 and 2 and a sequence of structured meshes of the paper's plate
(30 x 7.5 x 3 mm, 0.5 mm electrode gap), prints the short-circuit L1 and B2 frequencies, their
relative error against a Richardson-extrapolated reference, and the wall time of one
uncached run (mesh + assembly + short- and open-circuit shift-invert eigensolutions).

Reference: Richardson extrapolation of the two finest order-2 meshes with the theoretical
eigenvalue rate h^4 (``f_ref = f_2 + (f_2 - f_1) / ((h_1/h_2)^4 - 1)``); the order-1 sequence
is also extrapolated on its own (rate h^2) as a cross-check. The study itself is
:func:`validation.work_precision.fe_work_precision` (the report's FE section runs it on
smaller meshes); this script runs it on the full sequences and prints the table.

Run: ``python benchmarks/fem_convergence.py [--material pzt8|paper] [--repeat N] [--markdown]``
(``--markdown``: the table of ``docs/fem.md`` section 6, with each wall time as a multiple of
the default mesh's measured in the same run; ``python -m tools.doc_tables --update
fe2d_convergence`` stores it for the docs).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.meshing.mesh import (
    DEFAULT_REFINE,  # noqa: E402
    max_element_size_m,  # noqa: E402
)
from validation.work_precision import fe_work_precision, richardson  # noqa: E402

REFINES = {1: (4, 8, 16, 32, 64), 2: (2, 3, 4, 6, 8, 16, 32)}
TARGET_REL = 5e-4
TARGET_TIME_S = 0.5


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--material", default="pzt8", choices=("pzt8", "paper"))
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (best is kept)")
    ap.add_argument("--markdown", action="store_true",
                    help="print the docs' Markdown table (wall times as ratios)")
    args = ap.parse_args(argv)
    stator = PlateStator()
    points, ref_info = fe_work_precision(REFINES, REFINES[2][-2:], args.material, args.repeat)
    ref = [ref_info["f_L1_Hz"], ref_info["f_B2_Hz"]]
    rows = {(pt.order, pt.refine): pt for pt in points}
    q1, q2 = REFINES[1][-2:]
    h1, h2 = max_element_size_m(stator, q1), max_element_size_m(stator, q2)
    ref1 = [richardson(getattr(rows[(1, q1)], f), getattr(rows[(1, q2)], f), h1, h2, 2)
            for f in ("f_L1_Hz", "f_B2_Hz")]
    if args.markdown:
        print(markdown(points, ref, ref1, args.material))
        return
    print(f"material {args.material}, plate 30 x 7.5 x 3 mm, gap 0.5 mm")
    print(f"Richardson reference (order 2, h^4): L1 {ref[0]:.2f} Hz, B2 {ref[1]:.2f} Hz")
    print(f"order-1 self-extrapolation (h^2):    L1 {ref1[0]:.2f} Hz, B2 {ref1[1]:.2f} Hz")
    print()
    hdr = (
        f"{'order':>5} {'refine':>6} {'h (mm)':>7} {'dofs':>7} {'L1 (Hz)':>11} {'err L1':>9} "
        f"{'B2 (Hz)':>11} {'err B2':>9} {'wall (s)':>9} {'eig (s)':>8}"
    )
    print(hdr)
    print("-" * len(hdr))
    for pt in points:
        ok = (pt.error_L1 <= TARGET_REL and pt.error_B2 <= TARGET_REL
              and pt.wall_time_s <= TARGET_TIME_S)
        print(
            f"{pt.order:>5} {pt.refine:>6} {max_element_size_m(stator, pt.refine) * 1e3:>7.3f} "
            f"{pt.dofs:>7} {pt.f_L1_Hz:>11.2f} {pt.error_L1:>9.2e} {pt.f_B2_Hz:>11.2f} "
            f"{pt.error_B2:>9.2e} {pt.wall_time_s:>9.3f} {pt.eig_time_s:>8.3f}"
            f"{' *' if ok else ''}"
        )
    print()
    print(
        f"* = L1 and B2 within {TARGET_REL:.2%} of the reference in <= {TARGET_TIME_S} s "
        f"(wall = mesh + assembly + short- and open-circuit eigensolutions; eig = short-circuit "
        f"eigensolution only). Default refine = {DEFAULT_REFINE}."
    )


def _hz(f: float) -> str:
    """``56 178.39``: a frequency with spaced thousands, as the docs print them."""
    return f"{f:,.2f}".replace(",", " ")


def markdown(points, ref: list[float], ref1: list[float], material: str) -> str:
    """The docs' table: frequencies, errors, dofs and the wall time as a multiple of the
    default mesh's (order 2, ``DEFAULT_REFINE``), measured in the same run."""
    default = next(pt for pt in points if pt.order == 2 and pt.refine == DEFAULT_REFINE)
    lines = [
        f"Material {material}. Reference (Richardson, order 2, h⁴): L1 = {_hz(ref[0])} Hz, "
        f"B2 = {_hz(ref[1])} Hz; order 1 extrapolated on its own (h²): {_hz(ref1[0])} / "
        f"{_hz(ref1[1])} Hz. Wall = mesh, assembly, short- and open-circuit solutions (best "
        f"of the repeats), as a multiple of the default mesh's.",
        "",
        "| order | refine | dofs | L1 (Hz) | err L1 | B2 (Hz) | err B2 | wall / default |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for pt in points:
        cells = [str(pt.order), str(pt.refine), str(pt.dofs), f"{pt.f_L1_Hz:.2f}",
                 f"{pt.error_L1:.2e}", f"{pt.f_B2_Hz:.2f}", f"{pt.error_B2:.2e}",
                 f"{pt.wall_time_s / default.wall_time_s:.2g}"]
        if pt is default:
            cells[1] += " (default)"
            cells = [f"**{c}**" for c in cells]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
