"""The paper's plate by FE against the paper's own numbers (not a test; a few seconds).

Prints the tables of ``docs/fem.md`` section 7: the 2D model's L1 and B2 (short and open
circuit, k_eff) of the 30 x 7.5 x 3 mm plate with PZT-8 and with the paper's Table 1
constants; their relative differences from the paper's ANSYS frequencies and from Table 2's
implied ``sqrt(K/M)/2 pi``; the rod estimates ``c/(2l)`` that explain the gap; and the FE
reduced parameters beside Table 2's. Nothing is fitted.

Run: ``python benchmarks/fem_vs_paper.py`` (Markdown on stdout; ``python -m
tools.doc_tables --update fe_vs_paper`` stores it for the docs).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.material import get_material, plane_stress  # noqa: E402
from fem.meshing.mesh import DEFAULT_REFINE  # noqa: E402
from fem.modes import plate_modes  # noqa: E402
from rom.from_fem import fem_params  # noqa: E402
from rom.table2 import PAPER_ANSYS_HZ, TABLE1, table2  # noqa: E402

MATERIALS = ("pzt8", "paper")


def _hz(f: float, decimals: int = 1) -> str:
    """A frequency with spaced thousands, as the docs print them."""
    return f"{f:,.{decimals}f}".replace(",", " ")


def _pct(x: float) -> str:
    return f"{x * 100:+.1f} %"


def main() -> None:
    stator = PlateStator()
    modes = {m: plate_modes(stator, m) for m in MATERIALS}
    t2 = table2()
    out = [f"Default mesh: order 2, refine {DEFAULT_REFINE}, {modes['pzt8'].dofs} dofs.", "",
           "| material | L1 f_short / f_open (Hz) | L1 k_eff | B2 f_short / f_open (Hz) | "
           "B2 k_eff |", "|---|---|---|---|---|"]
    for m, r in modes.items():
        out.append(f"| {m} | {_hz(r.L1.f_short_Hz)} / {_hz(r.L1.f_open_Hz)} | "
                   f"{r.L1.k_eff:.3f} | {_hz(r.B2.f_short_Hz)} / {_hz(r.B2.f_open_Hz)} | "
                   f"{r.B2.k_eff:.3f} |")
    out += ["", f"Against the paper's ANSYS frequencies (L1 {_hz(PAPER_ANSYS_HZ['L1'], 0)} Hz, "
            f"B2 {_hz(PAPER_ANSYS_HZ['B2'], 0)} Hz) and Table 2's implied √(K/M)/2π "
            f"(L1 {_hz(t2.f_L1_Hz, 0)} Hz, B2 {_hz(t2.f_B2_Hz, 0)} Hz):", "",
            "| material | L1 vs ANSYS | L1 vs Table 2 | B2 vs ANSYS | B2 vs Table 2 |",
            "|---|---|---|---|---|"]
    for m, r in modes.items():
        fl, fb = r.L1.f_short_Hz, r.B2.f_short_Hz
        out.append(f"| {m} | {_pct(fl / PAPER_ANSYS_HZ['L1'] - 1)} | "
                   f"{_pct(fl / t2.f_L1_Hz - 1)} | {_pct(fb / PAPER_ANSYS_HZ['B2'] - 1)} | "
                   f"{_pct(fb / t2.f_B2_Hz - 1)} |")
    length, rho = TABLE1["length_m"], TABLE1["rho_kg_m3"]
    young = plane_stress(get_material("pzt8")).young_modulus_Pa(1)
    rod = math.sqrt(young / rho) / (2 * length)
    rod_c11 = math.sqrt(TABLE1["cE11_Pa"] / rho) / (2 * length)
    out += ["", f"Rod estimates c/(2l): PZT-8 (Y = 1/s11ᴱ = {young / 1e9:.2f} GPa) "
            f"{rod / 1e3:.1f} kHz, which would need l = {length * rod / 40e3 * 1e3:.1f} mm or "
            f"Y = {young * (40e3 / rod) ** 2 / 1e9:.0f} GPa for 40 kHz; Table 1's "
            f"cᴱ11 = {TABLE1['cE11_Pa']:.3g} Pa as the rod modulus (Appendix A.3) "
            f"{rod_c11 / 1e3:.1f} kHz."]
    params = {m: fem_params(material=m) for m in MATERIALS}
    rows = (("M_l (kg)", "M_l", ".4g"), ("K_l (N/m)", "K_l", ".4g"), ("A_l (N/V)", "A_l", ".4f"),
            ("M_b (kg)", "M_b", ".4g"), ("K_b (N/m)", "K_b", ".4g"), ("A_b (N/V)", "A_b", ".4f"))
    out += ["", f"Reduced parameters (`fem_params`, order 2, refine {DEFAULT_REFINE}) against "
            "Table 2:", "", "| | Table 2 | FE pzt8 | FE paper |", "|---|---|---|---|"]
    for label, name, fmt in rows:
        cells = [format(getattr(p, name), fmt) for p in (t2, params["pzt8"], params["paper"])]
        out.append(f"| {label} | " + " | ".join(c.replace("-", "−") for c in cells) + " |")
    m_rod = rho * TABLE1["width_m"] * TABLE1["thickness_m"] * length / 2
    out += ["", f"ρAl/2 = {m_rod:.4g} kg (Appendix A.1); FE pzt8 M_l / (ρAl/2) − 1 = "
            f"{_pct(params['pzt8'].M_l / m_rod - 1)}; M_b / Table 2's = "
            f"{params['pzt8'].M_b / t2.M_b:.2f}."]
    print("\n".join(out))


if __name__ == "__main__":
    main()
