"""Convergence benchmark of the FE plate model (not a test).

For element orders 1 and 2 and a sequence of structured meshes of the paper's plate
(30 x 7.5 x 3 mm, 0.5 mm electrode gap), prints the short-circuit L1 and B2 frequencies, their
relative error against a Richardson-extrapolated reference, and the wall time of one
uncached run (mesh + assembly + short- and open-circuit shift-invert eigensolutions).

Reference: Richardson extrapolation of the two finest order-2 meshes with the theoretical
eigenvalue rate h^4 (``f_ref = f_2 + (f_2 - f_1) / ((h_1/h_2)^4 - 1)``); the order-1 sequence
is also extrapolated on its own (rate h^2) as a cross-check.

Run: ``python benchmarks/fem_convergence.py [--material pzt8|paper] [--repeat N]``
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.mesh import max_element_size_m, structured_mesh  # noqa: E402
from fem.model import build_model  # noqa: E402
from fem.modes import DEFAULT_REFINE, modes_of_model  # noqa: E402

REFINES = {1: (4, 8, 16, 32, 64), 2: (2, 3, 4, 6, 8, 16, 32)}
TARGET_REL = 5e-4
TARGET_TIME_S = 0.5


def run_once(stator: PlateStator, material: str, order: int, refine: int):
    """One uncached solve; returns (L1 Hz, B2 Hz, dofs, wall s, short-only eigensolve s)."""
    t0 = time.perf_counter()
    model = build_model(structured_mesh(stator, refine), stator, material, order)
    res = modes_of_model(model, refine=refine)
    wall = time.perf_counter() - t0
    return res.L1.f_short_Hz, res.B2.f_short_Hz, res.dofs, wall, res.solve_time_s


def richardson(f1: float, f2: float, h1: float, h2: float, rate: float) -> float:
    return f2 + (f2 - f1) / ((h1 / h2) ** rate - 1.0)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--material", default="pzt8", choices=("pzt8", "paper"))
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (best is kept)")
    args = ap.parse_args(argv)
    stator = PlateStator()
    rows = {}
    for order, refines in REFINES.items():
        for r in refines:
            best = None
            for _ in range(args.repeat):
                out = run_once(stator, args.material, order, r)
                if best is None or out[3] < best[3]:
                    best = out
            rows[(order, r)] = best
    r1, r2 = REFINES[2][-2:]
    ref = [
        richardson(rows[(2, r1)][i], rows[(2, r2)][i],
            max_element_size_m(stator, r1), max_element_size_m(stator, r2), 4)
        for i in (0, 1)
    ]
    q1, q2 = REFINES[1][-2:]
    ref1 = [
        richardson(rows[(1, q1)][i], rows[(1, q2)][i],
            max_element_size_m(stator, q1), max_element_size_m(stator, q2), 2)
        for i in (0, 1)
    ]
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
    for (order, r), (fl, fb, dofs, wall, t_eig) in rows.items():
        el, eb = abs(fl / ref[0] - 1), abs(fb / ref[1] - 1)
        mark = " *" if (el <= TARGET_REL and eb <= TARGET_REL and wall <= TARGET_TIME_S) else ""
        print(
            f"{order:>5} {r:>6} {max_element_size_m(stator, r) * 1e3:>7.3f} {dofs:>7} {fl:>11.2f} "
            f"{el:>9.2e} {fb:>11.2f} {eb:>9.2e} {wall:>9.3f} {t_eig:>8.3f}{mark}"
        )
    print()
    print(
        f"* = L1 and B2 within {TARGET_REL:.2%} of the reference in <= {TARGET_TIME_S} s "
        f"(wall = mesh + assembly + short- and open-circuit eigensolutions; eig = short-circuit "
        f"eigensolution only). Default refine = {DEFAULT_REFINE}."
    )


if __name__ == "__main__":
    main()
