"""Through holes: the 2D plate model against its 3D extrusion (docs/fem3d.md; not a test).

The paper's 30 x 7.5 mm PZT-8 plate (gap 0.5 mm) with one hole at its centre (0, 15) mm, the
node L1 and B2 share, or one off the axis at (1.8, 5) mm, at two thicknesses; each case is a
:class:`fem.meshing.parametric.ParametricStator` meshed by gmsh, 2D on the planform mesh and 3D on
its extrusion (:func:`fem.plane_stress_error.plane_stress_error`, 3 layers). The plain plate
meshed the same way is the baseline: "extra" is a case's 2D/3D - 1 minus the plain plate's
at the same thickness, the error the hole adds. The last column is ``d h / (L W)``, which
:data:`lusm.options.HOLE_AREA_SHARE` bounds for the CLI's warning. Run:
``python benchmarks/fem_holes_2d_3d.py`` (about 3 minutes on two cores).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.meshing.parametric import ParametricStator  # noqa: E402
from fem.plane_stress_error import plane_stress_error  # noqa: E402

LENGTH_MM, WIDTH_MM = 30.0, 7.5
CASES = (  # (thickness mm, where, diameter mm)
    (3.0, "centre", 1.0), (3.0, "centre", 3.0), (3.0, "off-axis", 1.5),
    (1.5, "centre", 0.5), (1.5, "centre", 1.5), (1.5, "off-axis", 1.0),
)
CENTRES_MM = {"centre": (0.0, 15.0), "off-axis": (1.8, 5.0)}


def errors(h_mm: float, holes_mm: tuple = ()) -> dict[str, float]:
    """2D/3D - 1 of the short-circuit L1 and B2 frequencies of one plate."""
    st = ParametricStator(length_m=LENGTH_MM * 1e-3, width_m=WIDTH_MM * 1e-3,
                          thickness_m=h_mm * 1e-3, electrode_gap_m=0.5e-3,
                          holes_m=tuple((x * 1e-3, y * 1e-3, d * 1e-3)
                                        for x, y, d in holes_mm))
    return plane_stress_error(stator=st, material="pzt8", layers=3).relative_error


def main() -> None:
    base = {h: errors(h) for h in sorted({c[0] for c in CASES})}
    print("| h (mm) | hole | d (mm) | 2D/3D - 1, L1 / B2 | extra, L1 / B2 | d h / (L W) |")
    print("|---|---|---|---|---|---|")
    for h, e in base.items():
        print(f"| {h:g} | none | | {e['L1_short'] * 100:+.3f} % / "
              f"{e['B2_short'] * 100:+.3f} % | | |")
    for h, where, d in CASES:
        e = errors(h, ((*CENTRES_MM[where], d),))
        extra = {k: e[k] - base[h][k] for k in ("L1_short", "B2_short")}
        print(f"| {h:g} | {where} | {d:g} | {e['L1_short'] * 100:+.3f} % / "
              f"{e['B2_short'] * 100:+.3f} % | {extra['L1_short'] * 100:+.3f} % / "
              f"{extra['B2_short'] * 100:+.3f} % | {d * h / (LENGTH_MM * WIDTH_MM):.4f} |")


if __name__ == "__main__":
    main()
