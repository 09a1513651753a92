"""Figures of the free tip's harmonic response (``lusm harmonic``): amplitudes and phases
against frequency, with the direct FE check, and the tip's ellipse at the drive point."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from validation.plotting import pyplot, save


def harmonic_figure(rom, fe, path: str | Path, marks: dict[str, float],
                    title: str) -> Path:
    """PNG of the tip's tangential and normal amplitudes (µm, log scale) and phases
    (degrees) against frequency (kHz).

    Parameters
    ----------
    rom : rom.harmonic.TipResponse
        The reduced model's curves.
    fe : fem.harmonic.FeTipResponse or None
        The direct FE solves, drawn as markers on the curves.
    path : str or Path
        The PNG.
    marks : dict
        Frequencies (Hz) marked by dashed vertical lines, by label (L1, B2, the drive).
    title : str
        The figure's title.
    """
    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 6.5))
    f_k = rom.frequency_Hz * 1e-3
    series = (("tangential (B2, $u_x$)", "C0", "tangential_m"),
              ("normal (L1, $u_y$)", "C1", "normal_m"))
    for label, color, key in series:
        a = getattr(rom, key)
        ax1.semilogy(f_k, np.abs(a) * 1e6, color=color, label=f"{label}, reduced model")
        ax2.plot(f_k, np.angle(a, deg=True), color=color)
        if fe is not None:
            b = getattr(fe, key)
            ax1.semilogy(fe.frequency_Hz * 1e-3, np.abs(b) * 1e6, "o", mfc="none",
                         color=color, label=f"{label}, direct FE solve")
            ax2.plot(fe.frequency_Hz * 1e-3, np.angle(b, deg=True), "o", mfc="none",
                     color=color)
    for i, (name, f) in enumerate(sorted(marks.items(), key=lambda m: m[1])):
        for ax in (ax1, ax2):
            ax.axvline(f * 1e-3, color="grey", lw=0.8, ls="--")
        # one row per mark, so that marks a few hertz apart (a tuned pair) stay readable
        ax1.annotate(name, (f * 1e-3, 1.0), xycoords=("data", "axes fraction"),
                     xytext=(2, -10 - 10 * i), textcoords="offset points", fontsize=8,
                     color="grey")
    ax1.set_ylabel("tip amplitude (µm)")
    ax1.set_title(title, fontsize=10)
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(loc="lower center", fontsize=7)
    ax2.set_ylabel("phase against the drive (deg)")
    ax2.set_yticks(np.arange(-180, 181, 90))
    ax2.set_xlabel("frequency (kHz)")
    ax2.grid(True, alpha=0.3)
    ax1.set_xlim(f_k[0], f_k[-1])
    return save(fig, path)


def ellipse_figure(ellipse, path: str | Path, title: str) -> Path:
    """PNG of the tip's path over one drive period: tangential against normal displacement
    (µm, equal aspect), the start of the period marked and the direction of travel shown."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    t, n = ellipse.tangential_m * 1e6, ellipse.normal_m * 1e6
    ax.plot(t, n, color="C2")
    ax.plot(t[0], n[0], "o", color="C2", label="t = 0 (drive voltage rising through 0)")
    k = max(1, len(t) // 12)
    ax.annotate("", xy=(t[k], n[k]), xytext=(t[0], n[0]),
                arrowprops=dict(arrowstyle="->", color="C2"))
    reach = 1.1 * max(float(np.max(np.abs(t))), float(np.max(np.abs(n))), 1e-30)
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.axvline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("tangential displacement $u_x$ (µm)")
    ax.set_ylabel("normal displacement $u_y$ (µm)")
    ax.set_title(title, fontsize=9)
    ax.legend(loc="lower right", fontsize=7)
    ax.grid(True, alpha=0.3)
    return save(fig, path)
