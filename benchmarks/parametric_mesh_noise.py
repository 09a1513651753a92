"""How sure is a parametric stator's L1-B2 split: gmsh mesh noise and mesh convergence (not a
test).

    python benchmarks/parametric_mesh_noise.py [--json]

A stator file with ``[tip]``, ``[chamfers]`` or ``[[holes]]`` is meshed by gmsh, anew for every
plate: a plate longer by a rounding error can get another mesh, and its frequencies move by
the mesh's discretisation error, not smoothly. On the designer's tuned 60 kHz stator
(``examples/tuned_60k/stator.toml``) this solves the 2D modes at element sizes of
``min(length, width) / n`` for n = 8 (the default), 16 and 32, each on six plates whose
lengths differ by 1e-9 relative (a physical change of about 1e-4 Hz, far below what is
measured), and prints per size: the spread (max - min) of L1, B2 and the split over the six
plates, their means, and the mean split's change against the finest size.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from fem.mesh_settings import MeshSettings
from fem.modes import plate_modes
from fem.stator_file import load_stator

STATOR = Path(__file__).resolve().parents[1] / "examples" / "tuned_60k" / "stator.toml"
DIVISIONS = (8, 16, 32)
"""Element sizes min(length, width) / n: the default (fem.meshing.parametric.DEFAULT_SIZE_DIVISIONS)
and two refinements."""
PLATES = 6
"""Plates per size, lengths (1 + i 1e-9) times the file's."""


def measure() -> dict[str, float]:
    """Per division n: ``L1_spread_n_Hz``, ``B2_spread_n_Hz``, ``split_spread_n_Hz``,
    ``L1_n_Hz``, ``B2_n_Hz``, ``split_n_Hz`` (means over the plates)."""
    design = load_stator(STATOR)
    base = design.stator
    out = {}
    for n in DIVISIONS:
        rows = []
        for i in range(PLATES):
            length = base.length_m * (1.0 + i * 1e-9)
            plate = replace(base, length_m=length, mesh_size_m=min(length, base.width_m) / n)
            modes = plate_modes(plate, design.material,
                                MeshSettings(2, 4))  # refine unused: gmsh's mesh
            rows.append((modes.L1.f_short_Hz, modes.B2.f_short_Hz))
        f = np.array(rows)
        split = f[:, 1] - f[:, 0]
        out |= {f"L1_spread_{n}_Hz": float(np.ptp(f[:, 0])),
                f"B2_spread_{n}_Hz": float(np.ptp(f[:, 1])),
                f"split_spread_{n}_Hz": float(np.ptp(split)),
                f"L1_{n}_Hz": float(f[:, 0].mean()), f"B2_{n}_Hz": float(f[:, 1].mean()),
                f"split_{n}_Hz": float(split.mean())}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = ap.parse_args()
    r = measure()
    if args.json:
        print(json.dumps(r, indent=1))
        return
    finest = DIVISIONS[-1]
    print(f"{STATOR.name} ({STATOR.parent.name}), {PLATES} plates per size, lengths 1e-9 "
          "apart")
    print("  size       L1 spread  B2 spread  split spread   mean L1 (Hz)  mean B2 (Hz)  "
          f"mean split  split - split({finest})")
    for n in DIVISIONS:
        print(f"  min/{n:<3d}  {r[f'L1_spread_{n}_Hz']:9.3f}  {r[f'B2_spread_{n}_Hz']:9.3f}  "
              f"{r[f'split_spread_{n}_Hz']:12.3f}   {r[f'L1_{n}_Hz']:12.2f}  "
              f"{r[f'B2_{n}_Hz']:12.2f}  {r[f'split_{n}_Hz']:10.2f}  "
              f"{r[f'split_{n}_Hz'] - r[f'split_{finest}_Hz']:8.2f}")


if __name__ == "__main__":
    main()
