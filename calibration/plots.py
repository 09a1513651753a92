"""Figures of a calibration: data against fit with residuals, profiles, correlations."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from calibration.fit import DELTA_CHI2_95, CalibrationResult
from calibration.measurements import DataSet, Measurements


def _axis(data: DataSet) -> str:
    """The input that varies most across a set's rows: its figure's abscissa."""
    order = {"free": ("voltage", "frequency"), "admittance": ("frequency",),
             "speed": ("voltage", "load", "preload", "frequency"),
             "power": ("voltage", "load", "preload", "frequency")}[data.kind]
    for q in order:
        x = data.inputs[q]
        if np.ptp(x) > 0:
            return q
    return order[0]


def _data_figure(data: DataSet, pred: dict[str, np.ndarray], path: Path) -> None:
    """Measured values with error bars, the model at the optimum, and the residuals in
    standard deviations below."""
    import matplotlib.pyplot as plt

    q_x = _axis(data)
    x = data.inputs[q_x]
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.6),
                                      gridspec_kw={"height_ratios": (3, 1)})
    order = np.argsort(x, kind="stable")
    for q, y in data.observed.items():
        ok = np.isfinite(y)
        line = top.plot(x[order], pred[q][order], "-", label=f"{q}, model")[0]
        top.errorbar(x[ok], y[ok], yerr=data.sigma[q][ok], fmt="o", ms=3,
                     color=line.get_color(), label=f"{q}, measured ({data.columns[q]})")
        bottom.plot(x[ok], (pred[q][ok] - y[ok]) / data.sigma[q][ok], "o", ms=3,
                    color=line.get_color())
    top.set_ylabel("value (SI)")
    top.set_title(f"{data.kind}: {data.path.name}")
    top.legend(fontsize=7)
    bottom.axhline(0.0, color="k", lw=0.8)
    bottom.set_ylabel("residual / sigma")
    bottom.set_xlabel(f"{q_x} (SI)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _profile_figure(result: CalibrationResult, path: Path) -> None:
    """Delta chi-square of every profiled parameter against its value."""
    import matplotlib.pyplot as plt

    names = list(result.profiles)
    fig, axes = plt.subplots(1, len(names), figsize=(3.2 * len(names), 3.2), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        prof = result.profiles[name]
        ax.plot(prof.values, prof.delta_chi2, "o-", ms=3)
        ax.axhline(DELTA_CHI2_95, color="r", lw=0.8, ls="--")
        i = result.names.index(name)
        ax.set_title(name if result.identifiable[i] else f"{name} (not identifiable)",
                     fontsize=9)
        ax.set_xlabel(f"{name} ({result.parameters[i].unit})")
    axes[0][0].set_ylabel("delta chi-square")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _correlation_figure(result: CalibrationResult, path: Path) -> None:
    """The correlation matrix (blank where a parameter has no finite variance)."""
    import matplotlib.pyplot as plt

    n = len(result.names)
    fig, ax = plt.subplots(figsize=(1.0 + 0.8 * n, 0.8 + 0.8 * n))
    im = ax.imshow(result.correlation, vmin=-1, vmax=1, cmap="RdBu_r")
    ax.set_xticks(range(n), result.names, rotation=45, fontsize=8)
    ax.set_yticks(range(n), result.names, fontsize=8)
    for i in range(n):
        for j in range(n):
            c = result.correlation[i, j]
            if np.isfinite(c):
                ax.text(j, i, f"{c:.2f}", ha="center", va="center", fontsize=7)
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(result: CalibrationResult, meas: Measurements, folder: Path) -> list[Path]:
    """Write every figure into ``folder``; returns their paths."""
    out = []
    for k, (data, pred) in enumerate(zip(meas.sets, result.predictions, strict=True), start=1):
        path = folder / f"fit_{k}_{data.kind}.png"
        _data_figure(data, pred, path)
        out.append(path)
    if result.profiles:
        out.append(folder / "profiles.png")
        _profile_figure(result, out[-1])
    out.append(folder / "correlation.png")
    _correlation_figure(result, out[-1])
    return out
