"""Figures of the FE stage's frequency studies: admittance and dimension sweeps (PNG).

Every function takes a result of :mod:`fem` and a path, draws one labelled figure and
returns the path. Mode pictures are :mod:`fem.render` (pyvista, off screen).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fem.admittance import AdmittanceResult
from fem.sweep import SweepResult
from validation.plotting import pyplot, save


def admittance_figure(result: AdmittanceResult, path: str | Path) -> Path:
    """PNG of ``|Y|`` (log scale) and its phase against frequency, pairs marked."""
    plt = pyplot()
    f_k = result.f_Hz * 1e-3
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    ax1.semilogy(f_k, np.abs(result.Y_S), color="C0")
    for p in result.pairs:
        label = f" {p.mode}" if p.mode else ""
        ax1.axvline(p.f_resonance_Hz * 1e-3, color="C3", lw=0.8, ls="--")
        ax1.axvline(p.f_antiresonance_Hz * 1e-3, color="C2", lw=0.8, ls=":")
        ax1.annotate(f"{label} k={p.k_eff:.3f}", (p.f_resonance_Hz * 1e-3, np.abs(
            result.Y_S).max()), fontsize=8, va="top")
    ax1.set_ylabel("|Y| (S)")
    ax1.set_title(f"admittance of electrodes {result.port.electrodes} (others grounded)")
    ax1.grid(True, which="both", alpha=0.3)
    ax2.plot(f_k, np.degrees(np.angle(result.Y_S)), color="C1")
    ax2.set_ylabel("phase of Y (deg)")
    ax2.set_xlabel("frequency (kHz)")
    ax2.grid(True, alpha=0.3)
    return save(fig, path)


def sweep_figure(result: SweepResult, path: str | Path) -> Path:
    """PNG of L1 and B2 (short circuit) against the swept dimension, other modes in grey."""
    plt = pyplot()
    x_mm = result.values_m * 1e3
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for xv, spec in zip(x_mm, result.spectrum_Hz, strict=True):
        spec = spec[spec > 1.0]
        ax.plot(np.full(spec.size, xv), spec * 1e-3, ".", color="0.75", ms=3)
    ax.plot(x_mm, result.f_L1_short_Hz * 1e-3, "o-", color="C0", ms=3, label="L1 (short)")
    ax.plot(x_mm, result.f_B2_short_Hz * 1e-3, "s-", color="C3", ms=3, label="B2 (short)")
    other = "length" if result.parameter == "width" else "width"
    fixed = getattr(result.base, f"{other}_m") * 1e3
    ax.set_xlabel(f"plate {result.parameter} (mm)")
    ax.set_ylabel("natural frequency (kHz)")
    ax.set_title(f"L1/B2 vs {result.parameter}: {other} {fixed:g} mm, thickness "
                 f"{result.base.thickness_m * 1e3:g} mm, {result.material} (grey: other modes)")
    lo = np.nanmin(np.concatenate((result.f_L1_short_Hz, result.f_B2_short_Hz))) * 1e-3
    hi = np.nanmax(np.concatenate((result.f_L1_short_Hz, result.f_B2_short_Hz))) * 1e-3
    pad = 0.15 * (hi - lo) + 1.0
    ax.set_ylim(lo - pad, hi + pad)
    for xc in result.crossings_m() * 1e3:
        ax.axvline(xc, color="0.4", ls=":", lw=1)
        ax.annotate(f"crossing {xc:.3f} mm", (xc, lo - 0.9 * pad), fontsize=8,
                    rotation=90, va="bottom", ha="right")
    ax.legend()
    ax.grid(True, alpha=0.3)
    return save(fig, path)
