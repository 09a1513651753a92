"""Write the synthetic measurement set of this folder: Table 2's motor plus noise.

The data are not measured: they are what the model gives with the paper's Table 2 (Li, Yao &
Wu 2016) and the paper's coupling, plus Gaussian noise of a fixed seed, so that a calibration
of them can be checked against the truth (TRUTH below). Run from anywhere:

    python examples/calibration/make_data.py

free.csv: free tip amplitudes (no preload) at the paper's 40 kHz drive, 25-250 V, 3 %
noise (the paper's Figs. 5-6); speed.csv: steady speeds at 14 N preload, 60-400 V, 3 %
noise plus 0.2 mm/s (the paper's Fig. 24), and at 300 V against loads of 0.25-1.25 N and
at preloads of 8-32 N.

fig24.csv (fig24.toml): a prototype whose speed-voltage curve has its dead zone near the
paper's measured ~100 V (Fig. 24, 14 N, 40 kHz) instead of the model's 139 V: Table 2 with
the friction pair of TRUTH_FIG24 (mu_s sets the dead zone's edge; a_mu, b_mu do not move
it), 24 voltages 50-400 V, 3 % noise plus 0.2 mm/s, its own seed.
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np

from contact.steady import steady_state
from rom.damping import free_tip_amplitudes
from rom.params import MotorParams
from rom.table2 import table2

HERE = Path(__file__).resolve().parent
SEED = 2024
REL = 0.03
"""Relative standard deviation of every value."""
SPEED_FLOOR_M_S = 2e-4
"""Absolute standard deviation of a speed (m/s), added in quadrature."""
TRUTH = {"C_l": 173.0, "C_b": 178.0, "a_mu": 0.15, "b_mu": 1e6}
"""Table 2's values of the parameters measurements.toml fits."""
SEED_FIG24 = 24
TRUTH_FIG24 = {"mu_s": 0.31, "mu_d": 0.25}
"""The friction pair of fig24.csv's prototype (every other value Table 2's): its dead zone's
edge at 14 N, 40 kHz is 102.5 V (the bisection of ``validation.hard_cases.dead_zone_edge``)."""
FIG24_VOLTAGES_V = (*range(50, 200, 10), *range(200, 401, 25))
"""Denser through the dead zone and its edge than above it."""


def free_rows(rng: np.random.Generator) -> list[str]:
    """Free tip amplitudes (um) at 40 kHz, 10 voltages: 20 values."""
    n, t = free_tip_amplitudes(table2(), 40e3, 1.0)
    rows = ["voltage_V,tangential_um,normal_um"]
    for v in np.linspace(25.0, 250.0, 10):
        tan, nor = (a * v * 1e6 * (1.0 + REL * rng.standard_normal()) for a in (t, n))
        rows.append(f"{v:g},{tan:.5g},{nor:.5g}")
    return rows


def speed_rows(rng: np.random.Generator, params: MotorParams | None = None,
               points: list[tuple[float, float, float]] | None = None) -> list[str]:
    """Steady speeds (mm/s) of ``params`` (default Table 2's) at ``points`` (voltage V,
    preload N, load N; default 20 voltages at 14 N without load, 5 loads and 5 other
    preloads at 300 V)."""
    params = params or table2()
    if points is None:
        points = [(v, 14.0, 0.0) for v in np.linspace(60.0, 400.0, 20)]
        points += [(300.0, 14.0, f) for f in (0.25, 0.5, 0.75, 1.0, 1.25)]
        points += [(300.0, p, 0.0) for p in (8.0, 11.0, 20.0, 26.0, 32.0)]
    rows = ["voltage_V,preload_N,load_N,velocity_mm_s,sigma_velocity_mm_s"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for v, preload, load in points:
            speed = steady_state(params, v, preload, frequency_Hz=40e3, load_N=load,
                                 coupling="paper", energy=False).velocity_m_s
            speed = speed if np.isfinite(speed) else 0.0
            sigma = float(np.hypot(SPEED_FLOOR_M_S, REL * speed))
            measured = speed + sigma * rng.standard_normal()
            rows.append(f"{v:.4g},{preload:g},{load:g},{measured * 1e3:.5g},"
                        f"{sigma * 1e3:.3g}")
    return rows


def fig24_params() -> MotorParams:
    """Table 2 with the friction pair of ``TRUTH_FIG24``: fig24.csv's prototype."""
    return dataclasses.replace(table2(), **TRUTH_FIG24)


def main() -> None:
    """Write free.csv, speed.csv and fig24.csv beside this script."""
    rng = np.random.default_rng(SEED)
    (HERE / "free.csv").write_text("\n".join(free_rows(rng)) + "\n")
    (HERE / "speed.csv").write_text("\n".join(speed_rows(rng)) + "\n")
    fig24 = speed_rows(np.random.default_rng(SEED_FIG24), fig24_params(),
                       [(float(v), 14.0, 0.0) for v in FIG24_VOLTAGES_V])
    (HERE / "fig24.csv").write_text("\n".join(fig24) + "\n")


if __name__ == "__main__":
    main()
