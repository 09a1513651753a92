"""Draw fig24.csv against the model before (Table 2) and after its calibration.

    lusm calibrate examples/calibration/fig24.toml --source table2 --coupling paper \\
        --out fig24.json
    python examples/calibration/plot_fig24.py fig24.json fig24_before_after.png

The steady speed of both sets at 14 N, 40 kHz, paper's coupling, 50-400 V every 5 V, over
the synthetic measurement with its standard deviations; each set's dead-zone edge
(:func:`validation.hard_cases.dead_zone_edge`, bisected to 0.05 V) as a dotted line.
``lusm calibrate --plot`` draws the fit alone; this figure adds the start.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from calibration.model import speeds_m_s
from rom.params import MotorParams
from rom.table2 import table2
from validation.hard_cases import dead_zone_edge

HERE = Path(__file__).resolve().parent
PRELOAD_N = 14.0
FREQUENCY_HZ = 40e3


def curve_m_s(params: MotorParams, volts: np.ndarray) -> np.ndarray:
    """Steady speed from rest (m/s) at each voltage (V), 14 N, 40 kHz, paper's coupling."""
    n = len(volts)
    inputs = {"voltage": volts, "preload": np.full(n, PRELOAD_N), "load": np.zeros(n),
              "frequency": np.full(n, FREQUENCY_HZ)}
    return speeds_m_s(params, inputs, "paper", "exact")


def main(argv: list[str] | None = None) -> None:
    """Read the calibrated parameter file, write the figure, print both edges (V)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("calibrated", help="parameter file written by lusm calibrate (.json)")
    ap.add_argument("figure", help="the figure to write (.png)")
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from validation.plotting import save

    fitted = MotorParams.from_dict(json.loads(Path(args.calibrated).read_text()))
    data = np.genfromtxt(HERE / "fig24.csv", delimiter=",", names=True)
    volts = np.arange(50.0, 400.1, 5.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.errorbar(data["voltage_V"], data["velocity_mm_s"], yerr=data["sigma_velocity_mm_s"],
                fmt="o", ms=3, color="k", label="fig24.csv (synthetic, 3 % + 0.2 mm/s)")
    for name, params, color in (("Table 2", table2(), "tab:red"),
                                ("calibrated", fitted, "tab:blue")):
        edge = dead_zone_edge(params, PRELOAD_N, FREQUENCY_HZ, tol_V=0.05)
        ax.plot(volts, 1e3 * curve_m_s(params, volts), "-", color=color,
                label=f"{name}: mu_s {params.mu_s:.3f}, mu_d {params.mu_d:.3f}, "
                f"edge {edge:.1f} V")
        ax.axvline(edge, color=color, ls=":", lw=1.0)
        print(f"{name}: dead-zone edge {edge:.2f} V")
    ax.set_xlabel("voltage amplitude V0 (V)")
    ax.set_ylabel("steady slider speed (mm/s)")
    ax.set_title("Fig. 24 procedure: 14 N, 40 kHz, paper's coupling")
    ax.legend(fontsize=7)
    save(fig, args.figure)


if __name__ == "__main__":
    main()
