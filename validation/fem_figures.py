"""Figures of the FE stage's frequency studies: admittance and dimension sweeps (PNG).

Every function takes a result of :mod:`fem` and a path, draws one labelled figure and
returns the path. Mode pictures are :mod:`fem.render` (pyvista, off screen).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fem.admittance import AdmittanceResult
from fem.equivalent_circuit import EquivalentCircuit
from fem.sweep import SweepResult
from validation.plotting import pyplot, save


def admittance_figure(result: AdmittanceResult, path: str | Path,
                      circuit: EquivalentCircuit | None = None) -> Path:
    """PNG of ``|Z|`` (ohm, log scale) and its phase against frequency, pairs marked, and the
    fitted equivalent ``circuit`` over the computed curve where one is given."""
    fig, _ = draw_admittance(result, circuit)
    # laid out already: the k_eff labels are placed on the final axes (a later tight layout
    # would move the resonances under labels measured on the old ones)
    return save(fig, path, tight=False)


LABEL_PAD_PT = 3.0
"""Gap between a k_eff label and its resonance line, and between label rows (points)."""


def draw_admittance(result: AdmittanceResult, circuit: EquivalentCircuit | None = None):
    """The figure of :func:`admittance_figure` and its k_eff labels (matplotlib ``Text``).

    The top panel is the impedance ``|Z| = 1 / |Y|`` in ohm, as an impedance analyser shows
    it (the series resonance a minimum, the parallel one a maximum), with the fitted
    Butterworth-Van Dyke ``circuit`` dashed over it; the bottom panel its phase.
    Each pair's label sits beside its resonance line at the top of the |Z| panel, in rows
    (:func:`validation.plotting.stack_rows`): a label goes to the first row where it clears
    every label already there, so close resonances (L1 and B2 2 kHz apart at ``zeta = 0.005``)
    no longer print over each other; the panel's top is raised above the curve by the rows'
    height, so no label sits on a peak either.
    """
    plt = pyplot()
    f_k = result.f_Hz * 1e-3
    z = 1.0 / np.asarray(result.Y_S)
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    ax1.semilogy(f_k, np.abs(z), color="C0", label="computed (FE, modal superposition)")
    ax2.plot(f_k, np.degrees(np.angle(z)), color="C1")
    top = float(np.abs(z).max())
    if circuit is not None:
        z_fit = 1.0 / circuit.admittance_S(result.f_Hz)
        ax1.semilogy(f_k, np.abs(z_fit), color="k", lw=0.9, ls="--",
                     label=f"fitted BVD circuit ({len(circuit.branches)} branch"
                     f"{'es' if len(circuit.branches) != 1 else ''})")
        ax2.plot(f_k, np.degrees(np.angle(z_fit)), color="k", lw=0.9, ls="--")
        ax1.legend(loc="lower left", fontsize=8)
        top = max(top, float(np.abs(z_fit).max()))
    for p in result.pairs:
        ax1.axvline(p.f_resonance_Hz * 1e-3, color="C3", lw=0.8, ls="--")
        ax1.axvline(p.f_antiresonance_Hz * 1e-3, color="C2", lw=0.8, ls=":")
    ax1.set_ylabel("|Z| (ohm)")
    ax1.set_title(f"impedance of electrodes {result.port.electrodes} (others grounded)")
    ax1.grid(True, which="both", alpha=0.3)
    ax2.set_ylabel("phase of Z (deg)")
    ax2.set_xlabel("frequency (kHz)")
    ax2.grid(True, alpha=0.3)
    ax1.set_xlim(f_k[0], f_k[-1])
    fig.tight_layout()
    texts = [f"{p.mode + ' ' if p.mode else ''}k={p.k_eff:.3f}" for p in result.pairs]
    labels = _label_lines(ax1, [p.f_resonance_Hz * 1e-3 for p in result.pairs], texts, top)
    return fig, labels


def _label_lines(ax, x_data, texts, y_top: float) -> list:
    """Labels ``texts`` beside the vertical lines at ``x_data`` along the top of ``ax`` (log
    y), stacked so that none overlaps another (:func:`validation.plotting.stack_rows`), and
    the y range raised so that ``y_top``, the curve's highest point, stays below them."""
    from validation.plotting import stack_rows

    if not texts:
        return []
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    px_per_pt = fig.dpi / 72.0
    box = ax.get_window_extent(renderer)
    pad = LABEL_PAD_PT * px_per_pt
    made, spans = [], []
    for x, text in zip(x_data, texts, strict=True):
        t = ax.annotate(text, (x, 1.0), xycoords=("data", "axes fraction"), fontsize=8,
                        va="top", ha="left", xytext=(LABEL_PAD_PT, -LABEL_PAD_PT),
                        textcoords="offset points",
                        # the antiresonance line a label may cross does not strike it out
                        bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none",
                              "alpha": 0.8})
        width = t.get_window_extent(renderer).width
        x_px = ax.transData.transform((x, 1.0))[0]
        if x_px + pad + width > box.x1:  # no room right of the line: left of it
            t.set_ha("right")
            t.set_position((-LABEL_PAD_PT, -LABEL_PAD_PT))
            spans.append((x_px - pad - width, x_px - pad))
        else:
            spans.append((x_px + pad, x_px + pad + width))
        made.append(t)
    height_pt = max(t.get_window_extent(renderer).height for t in made) / px_per_pt
    rows = stack_rows(spans, pad)
    for t, row in zip(made, rows, strict=True):
        dx, _ = t.get_position()
        t.set_position((dx, -LABEL_PAD_PT - row * (height_pt + LABEL_PAD_PT)))
    # the rows' band at the top (a fraction of the panel's height) is kept clear of the curve:
    # the top of the log axis is raised until y_top sits just below the band
    band = ((max(rows) + 1) * (height_pt + LABEL_PAD_PT) + LABEL_PAD_PT) * px_per_pt
    share = min(band / box.height, 0.8)
    lo, hi = ax.get_ylim()
    if y_top > 0 and lo > 0:
        top = np.exp(np.log(lo) + (np.log(y_top) - np.log(lo)) / (1.0 - share))
        ax.set_ylim(lo, max(hi, float(top)))
    return made


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
