"""The figures of an optimisation's dataset: the convergence history and the Pareto front."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from studies.optimize.result import objective_variable

SCALES = {"W": (1e3, "mW"), "m/s": (1e3, "mm/s"), "Hz": (1e-3, "kHz"), "N": (1.0, "N"),
          "1": (100.0, "%")}
"""How an objective's SI unit is drawn: factor and unit."""


def _axis(ds, name: str) -> tuple[np.ndarray, str]:
    """An objective's values, scaled for drawing, and its axis label with the unit."""
    var = ds[name]
    factor, unit = SCALES.get(var.attrs.get("units", ""), (1.0, var.attrs.get("units", "")))
    label = var.attrs["long_name"].split(",")[0].removeprefix("objective: ")
    return var.values * factor, f"{label} ({unit})"


def convergence(ds, folder: Path, labels: list[str], goals: list[bool]) -> Path:
    """The best feasible value of each objective against the evaluations (one panel each):
    ``convergence.png`` in ``folder``."""
    import matplotlib.pyplot as plt

    n = len(labels)
    fig, axes = plt.subplots(n, 1, figsize=(6.4, 2.6 + 1.8 * n), squeeze=False)
    feasible = ds["feasible"].values.astype(bool)
    trial = ds["trial"].values
    for ax, label, maximize in zip(axes[:, 0], labels, goals, strict=True):
        y, ylabel = _axis(ds, objective_variable(label))
        ok = feasible & np.isfinite(y)
        ax.plot(trial[ok], y[ok], "o", ms=3, color="0.6", label="feasible design")
        ax.plot(trial[~ok], np.where(np.isfinite(y), y, np.nan)[~ok], "x", ms=3, color="C3",
                label="infeasible design")
        pick = np.fmax if maximize else np.fmin
        best = pick.accumulate(np.where(ok, y, np.nan))
        ax.step(trial, best, where="post", color="C0", label="best feasible so far")
        _label(ax, "evaluation (trial number)", ylabel)
        ax.xaxis.get_major_locator().set_params(integer=True)
    fig.suptitle(f"{ds.attrs['title']}: convergence", fontsize="medium")
    return _save(fig, folder / "convergence.png")


def _label(ax, xlabel: str, ylabel: str) -> None:
    """Axis labels (with units), a legend and a light grid."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)


def _save(fig, path: Path) -> Path:
    """Write ``fig`` to ``path`` (PNG) and close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def pareto(ds, folder: Path, labels: list[str]) -> Path:
    """The first two objectives of every design, the Pareto front (``best``) joined:
    ``pareto.png`` in ``folder``."""
    import matplotlib.pyplot as plt

    x, xlabel = _axis(ds, objective_variable(labels[0]))
    y, ylabel = _axis(ds, objective_variable(labels[1]))
    feasible = ds["feasible"].values.astype(bool)
    front = ds["best"].values.astype(bool)
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    ax.plot(x[feasible], y[feasible], "o", ms=4, color="0.6", label="feasible design")
    ax.plot(x[~feasible], y[~feasible], "x", ms=4, color="C3", label="infeasible design")
    order = np.argsort(x[front])
    ax.plot(x[front][order], y[front][order], "o-", color="C0", label="Pareto front")
    _label(ax, xlabel, ylabel)
    ax.set_title(f"{ds.attrs['title']}: Pareto front", fontsize="medium")
    return _save(fig, folder / "pareto.png")


def optimize_figures(ds, folder: Path, labels: list[str], goals: list[bool]) -> list[Path]:
    """Every figure of the dataset: the convergence, and the Pareto front of several
    objectives."""
    out = [convergence(ds, folder, labels, goals)]
    if len(labels) > 1:
        out.append(pareto(ds, folder, labels))
    return out
