"""The 2D model's gap cross-sections against the 3D model's clamped electrostatics.

    python benchmarks/fem_capacitance_check.py

With the fully clamped permittivities of the 3D model (eps11^S, eps33^S) the cross-sections
of ``fem.capacitance.gap_cross_section`` give the clamped capacitance matrix of the paper's
plate; the 3D model's (``fem.solid3d.model.build_solid_model``: K_phiphi condensed onto the four
electrodes, the bottom face grounded) is printed beside it on the default brick mesh graded
0, 1 and 2 times towards the electrode edges (docs/fem.md, "Check against 3D").
"""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as sla

from fem.capacitance import gap_cross_section
from fem.geometry import PlateStator
from fem.material import get_material
from fem.mesh_settings import MeshSettings
from fem.solid3d.model import build_solid_model


def cross_section_pF(stator: PlateStator) -> tuple[float, float, float]:
    """``(C_13, C_12, C_ee)`` (pF) of the cross-section model with clamped permittivities."""
    m = get_material("pzt8")
    e11, e33 = m.epsS_F_m[0, 0], m.epsS_F_m[2, 2]
    w, length, g, h = stator.width_m, stator.length_m, stator.electrode_gap_m, stator.thickness_m
    wa, la = w / 2 - g / 2, length / 2 - g / 2  # a quadrant's edges along the two strips
    along_x0 = gap_cross_section(g, h, wa, wa, e11, e33)  # strip along x = 0, 14.75 mm long
    along_mid = gap_cross_section(g, h, la, la, e11, e33)  # strip along y = l/2, 3.5 mm long
    cee = e33 * wa * la / h + along_x0.excess_F_m[0] * la + along_mid.excess_F_m[0] * wa
    return (along_x0.mutual_F_m * la * 1e12, along_mid.mutual_F_m * wa * 1e12, cee * 1e12)


def solid_pF(stator: PlateStator, edge_grading: int) -> tuple[float, float, float]:
    """``(C_13, C_12, C_ee)`` (pF) of the 3D model's K_phiphi condensed onto the electrodes."""
    mod = build_solid_model(stator, "pzt8", MeshSettings(2, 3, 3, edge_grading=edge_grading))
    k = mod.Kphiphi.tocsr()
    n = k.shape[0]
    fixed = np.zeros(n, dtype=bool)
    for d in mod.electrode_dofs:
        fixed[d] = True
    fixed[mod.ground_dofs] = True
    free = np.flatnonzero(~fixed)
    lu = sla.splu(k[free][:, free].tocsc())
    c = np.zeros((4, 4))
    for j, dj in enumerate(mod.electrode_dofs):
        phi = np.zeros(n)
        phi[dj] = 1.0
        phi[free] = lu.solve(-(k[free][:, fixed] @ phi[fixed]))
        q = k @ phi
        for i, di in enumerate(mod.electrode_dofs):
            c[i, j] = q[di].sum()
    c *= np.sign(c[0, 0])  # the charge convention of K_phiphi
    return (c[0, 2] * 1e12, c[0, 1] * 1e12, c[0, 0] * 1e12)


def main() -> None:
    st = PlateStator()
    heads = "".join(f"{c:>9}" for c in ("C_13", "C_12", "C_ee"))
    print(f"{'clamped capacitances (pF)':<28}{heads}")
    row = "{:<28}" + "{:9.1f}" * 3
    print(row.format("cross-sections (2D model)", *cross_section_pF(st)))
    for grading in (0, 1, 2):
        print(row.format(f"3D, edge grading {grading}", *solid_pF(st, grading)))

if __name__ == "__main__":
    main()
