"""Figures of the motor's steady characteristics: speed-thrust/efficiency, branch diagram.

Library code: matplotlib is imported on use and no backend is chosen here (the CLI sets Agg).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contact.characteristic import Characteristic
from rom.params import MotorParams


def characteristic_figure(char: Characteristic, path: Path) -> Path:
    """Speed, output power and efficiency against load (PNG at ``path``)."""
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(char.load_N, char.velocity_m_s * 1e3, "o-")
    ax1.set_xlabel("load force (N)")
    ax1.set_ylabel("slider velocity (mm/s)")
    ax1.set_title(f"speed-thrust, {char.op.voltage_V:g} V, {char.op.preload_N:g} N")
    ax1.grid(True)
    ax2.plot(char.load_N, char.output_power_W * 1e3, "o-", label="output power (mW)")
    ax2.set_xlabel("load force (N)")
    ax2.set_ylabel("output power (mW)")
    ax3 = ax2.twinx()
    ax3.plot(char.load_N, char.efficiency * 100, "s--", color="C1", label="efficiency (%)")
    ax3.set_ylabel("efficiency (%)")
    ax2.grid(True)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def branch_diagram(params: MotorParams, voltages_V, preload_N: float, path: Path, *,
                   accuracy: str = "exact") -> Path:
    """Every steady branch's velocity against voltage at one preload (PNG at ``path``).

    Stable branches are filled, unstable ones open; the branch a start from rest reaches is
    ringed; the period multiplicity k labels multi-period orbits.
    """
    import matplotlib.pyplot as plt

    from contact.steady import steady_state

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for v0 in np.asarray(voltages_V, dtype=float):
        r = steady_state(params, v0, preload_N, accuracy=accuracy)
        for b in r.branches:
            if b.motion == "dead-zone":
                ax.plot(v0, 0.0, "ks", ms=6)
                if b.from_rest:
                    ax.plot(v0, 0.0, "o", mfc="none", mec="k", ms=11)
                continue
            colour = f"C{min(max(b.k, 1), 4) - 1}"
            ax.plot(v0, b.velocity_m_s * 1e3, "o", color=colour,
                    mfc=colour if b.stable else "none", ms=6)
            if b.from_rest:
                ax.plot(v0, b.velocity_m_s * 1e3, "o", mfc="none", mec="k", ms=11)
    for k in (1, 2, 3, 4):
        ax.plot([], [], "o", color=f"C{k - 1}", label=f"period-{k} orbit")
    ax.plot([], [], "ks", label="dead zone (slider held)")
    ax.plot([], [], "o", mfc="none", mec="k", ms=11, label="reached from rest")
    ax.set_xlabel("drive voltage V0 (V)")
    ax.set_ylabel("steady slider velocity (mm/s)")
    ax.set_yscale("symlog", linthresh=1e-2)
    ax.set_title(f"steady branches at F_P = {preload_N:g} N (open: unstable)")
    ax.grid(True)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
