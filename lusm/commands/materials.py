"""``lusm materials``: the named piezoceramics (:mod:`fem.material`) with their key constants,
``Q_m``, operating limits and where each number comes from."""

from __future__ import annotations

import argparse

from lusm.options import add_output_options, print_json

HELP = "list the named materials (constants, Q_m, limits, sources)"
DESCRIPTION = """\
List the named piezoceramics a stator file's [material] name or --material takes: density,
s11E, d31, eps33T, k31, the k31 bar's frequency constant, the data-sheet Q_m and the operating
limits (vibration velocity, tensile stress, AC field, heating); then the materials a stator
file's [tip] material takes (isotropic, not piezoelectric). --json adds the full e-form
constants and each material's source.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm materials``."""
    add_output_options(p, folder=None)


def material_rows() -> list[dict]:
    """One JSON-ready row per named material, SI units in the keys."""
    from fem.material import MATERIAL_NAMES, get_material, transverse_coupling

    rows = []
    for name in MATERIAL_NAMES:
        mat = get_material(name)
        rows.append({**mat.to_dict(), **transverse_coupling(mat)})
    return rows


def run(args: argparse.Namespace) -> None:
    """Print the table (or one JSON object ``{"materials": [...]}``)."""
    from fem.material import TIP_MATERIALS

    rows = material_rows()
    tips = [t.to_dict() for t in TIP_MATERIALS.values()]
    if args.json:
        print_json({"materials": rows, "tip_materials": tips}, indent=2)
        return
    head = ("name", "rho kg/m3", "s11E pm2/N", "d31 pC/N", "eps33T/eps0", "k31", "N31 Hz m",
            "Q_m", "v m/s", "T MPa", "E V/mm", "P W/cm3")
    lines = [head]
    for r in rows:
        lim = r["limits"] or {}
        lines.append((
            r["name"], f"{r['rho_kg_m3']:.0f}", f"{r['s11E_m2_N'] * 1e12:.2f}",
            f"{r['d31_C_N'] * 1e12:.0f}", f"{r['eps33T_F_m'] / 8.8541878128e-12:.0f}",
            f"{r['k31']:.3f}", f"{r['N31_Hz_m']:.0f}",
            "-" if r["mechanical_Q"] is None else f"{r['mechanical_Q']:.0f}",
            *(f"{lim[k] * f:g}" if k in lim else "-" for k, f in (
                ("vibration_velocity_m_s", 1.0), ("dynamic_tensile_stress_Pa", 1e-6),
                ("drive_field_V_m", 1e-3), ("power_density_W_m3", 1e-6))),
        ))
    widths = [max(len(line[i]) for line in lines) for i in range(len(head))]
    for line in lines:
        print("  ".join(c.rjust(w) if i else c.ljust(w)
                        for i, (c, w) in enumerate(zip(line, widths, strict=True))).rstrip())
    print("v: peak vibration velocity, T: dynamic tensile strength, E: AC drive field, P: heat "
          "per volume; sources: lusm materials --json, fem/material.py, docs/designer.md")
    print("tip materials ([tip] material): " + "; ".join(
        f"{t['name']} E {t['young_Pa'] / 1e9:g} GPa, nu {t['poisson']:g}, rho "
        f"{t['rho_kg_m3']:g} kg/m3" for t in tips))
