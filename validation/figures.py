"""Figures of the contact stage, after the paper's Figs. 9-25 (matplotlib, Agg, PNG).

Every function takes results and a path, draws one labelled figure and returns the path.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from contact.maps import StickSlipMap
from contact.phase_plane import phase_plane
from contact.simulate import SimulationResult
from validation.plotting import pyplot, save

PHASE_COLORS = {0: "tab:green", 1: "tab:blue", 2: "tab:orange", 3: "tab:red"}
PHASE_LABELS = {0: "stick", 1: "slip, v_rel > 0", 2: "slip, v_rel < 0", 3: "separation"}
MAP_STYLE = {
    "slip-separation": dict(marker="o", facecolors="none", edgecolors="k"),
    "stick-slip": dict(marker="o", facecolors="k", edgecolors="k"),
    "stick-slip-separation": dict(marker="s", facecolors="tab:purple", edgecolors="k"),
    "pure-stick": dict(marker="*", facecolors="tab:red", edgecolors="tab:red"),
    "pure-slip": dict(marker="^", facecolors="none", edgecolors="tab:blue"),
    "separated": dict(marker="x", facecolors="tab:gray", edgecolors="tab:gray"),
}


def set_label(source: str) -> str:
    """A short label of a parameter set's source text for titles."""
    if source.startswith("Li, Yao & Wu"):
        return "Table 2"
    return source if len(source) <= 40 else source[:37] + "..."


def set_wrapped_title(ax, text: str, fontsize: float = 9.0) -> None:
    """``ax``'s title, wrapped to the figure's width, so that a long one (a stator file's run,
    ``stick-slip-separation: V0 = ... (stator file examples/tuned_40k/stator.toml ...)``)
    stays inside the PNG."""
    import textwrap

    # about 0.6 em per character of the default sans-serif font
    chars = max(20, int(ax.figure.get_figwidth() * 72.0 / (0.6 * fontsize)))
    ax.set_title(textwrap.fill(text, chars), fontsize=fontsize)


def _title(r: SimulationResult) -> str:
    return (f"V0 = {r.op.voltage_V:g} V, F_P = {r.op.preload_N:g} N, "
            f"f = {r.op.frequency_Hz / 1e3:.4g} kHz ({set_label(r.params.source)})")


def slider_velocity(r: SimulationResult, path: Path) -> Path:
    """Slider velocity against time (paper Fig. 9)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(r.trace.t_s * 1e3, r.trace.v_m_s, lw=0.6)
    ax.axhline(r.steady.velocity_m_s, color="k", ls="--", lw=0.8,
               label=f"steady mean {r.steady.velocity_m_s:.4g} m/s")
    ax.set_xlabel("time t (ms)")
    ax.set_ylabel("slider velocity dx/dt (m/s)")
    set_wrapped_title(ax, _title(r))
    ax.legend(fontsize=8)
    return save(fig, path)


def forces_and_relative_velocity(r: SimulationResult, path: Path, periods: float = 2.0) -> Path:
    """F_T, the limits +-mu_s F_N and v_rel over the last periods (paper Figs. 10-11)."""
    plt = pyplot()
    w = r.window
    keep = w.t_s >= w.t_s[-1] - periods / r.op.frequency_Hz
    t_us = w.t_s[keep] * 1e6
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True)
    a1.plot(t_us, w.F_T_N[keep], label="tangential force F_T")
    lim = r.params.mu_s * w.F_N_N[keep]
    a1.plot(t_us, lim, "k--", lw=0.8, label="+/- mu_s F_N")
    a1.plot(t_us, -lim, "k--", lw=0.8)
    a1.set_ylabel("force (N)")
    a1.legend(fontsize=8)
    a2.plot(t_us, w.v_rel_m_s[keep], color="tab:purple")
    for code, color in PHASE_COLORS.items():
        sel = w.phase[keep] == code
        if np.any(sel):
            a2.scatter(t_us[sel], w.v_rel_m_s[keep][sel], s=3, color=color,
                       label=PHASE_LABELS[code])
    a2.set_xlabel("time t (us)")
    a2.set_ylabel("relative velocity v_rel (m/s)")
    a2.legend(fontsize=7, ncol=2)
    set_wrapped_title(a1, _title(r))
    return save(fig, path)


def hysteresis_loop(r: SimulationResult, path: Path) -> Path:
    """Tangential force against tangential tip displacement (paper Fig. 12)."""
    plt = pyplot()
    w = r.window
    x_tip = w.x_tip_m(r.params.phi_Bl)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for code, color in PHASE_COLORS.items():
        sel = w.phase == code
        if np.any(sel):
            ax.scatter(x_tip[sel] * 1e6, w.F_T_N[sel], s=3, color=color, label=PHASE_LABELS[code])
    ax.set_xlabel("tangential tip displacement x_tip (um)")
    ax.set_ylabel("tangential force F_T (N)")
    set_wrapped_title(ax, _title(r))
    ax.legend(fontsize=8)
    return save(fig, path)


def transformed_phase_plane(r: SimulationResult, path: Path) -> Path:
    """Steady trajectory on the transformed phase plane with L1, L2 (paper Figs. 13-17)."""
    plt = pyplot()
    pp = phase_plane(r)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(pp.y_tip_m * 1e6, pp.v_rel_m_s, color="0.6", lw=0.5)
    for code, color in PHASE_COLORS.items():
        sel = pp.phase == code
        if np.any(sel):
            ax.scatter(pp.y_tip_m[sel] * 1e6, pp.v_rel_m_s[sel], s=3, color=color,
                       label=PHASE_LABELS[code])
    ax.axvline(pp.y_min_m * 1e6, color="k", ls="-", lw=0.8, label="L1: y_tip = y_min")
    ax.axvline(pp.y_c_m * 1e6, color="k", ls="--", lw=0.8, label="L2: y_tip = y_c (Eq. 21)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("normal tip displacement y_tip (um)")
    ax.set_ylabel("relative velocity v_rel (m/s)")
    set_wrapped_title(ax, f"{r.steady.motion}: " + _title(r))
    ax.legend(fontsize=7)
    return save(fig, path)


def stick_slip_map(m: StickSlipMap, path: Path, title: str = "") -> Path:
    """Motion class over voltage x preload on the slider's speed contours (paper Figs.
    18-19), the points with several stable states and the non-monotone neighbours marked."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 7))
    map_axes(ax, m)
    set_wrapped_title(ax, title or "stick-slip map")
    return save(fig, path)


def map_axes(ax, m: StickSlipMap) -> dict:
    """Draw the map ``m`` on ``ax``: filled speed contours ``|v|`` (mm/s, log scale; blank
    where the slider is held), the motion classes, red rings beyond a limit, black diamonds
    round points with several stable steady states and red dashes joining non-monotone
    neighbours (:meth:`contact.maps.StickSlipMap.non_monotone_pairs`).

    Returns
    -------
    dict
        ``"contours"`` (the filled contour set or None: a map with fewer than two voltages
        or preloads, or fewer than two positive speeds, has none), ``"several"`` (the
        diamonds' ``(preload_N, voltage_V)`` points) and ``"non_monotone"`` (the dashed
        segments' endpoints).
    """
    from matplotlib.colors import LogNorm

    ff, vv = np.meshgrid(m.preloads_N, m.voltages_V)
    speed = np.abs(np.asarray(m.velocity_m_s, dtype=float)) * 1e3
    positive = np.isfinite(speed) & (speed > 0)
    drawn: dict = {"contours": None, "several": [], "non_monotone": []}
    if min(speed.shape) > 1 and np.count_nonzero(positive) > 1:
        lo, hi = float(speed[positive].min()), float(speed[positive].max())
        if hi > lo:
            levels = np.logspace(np.floor(np.log10(lo)), np.ceil(np.log10(hi)),
                                 4 * int(np.ceil(np.log10(hi)) - np.floor(np.log10(lo))) + 1)
            cs = ax.contourf(ff, vv, np.ma.masked_where(~positive, speed), levels=levels,
                             norm=LogNorm(levels[0], levels[-1]), cmap="viridis", alpha=0.55)
            ax.figure.colorbar(cs, ax=ax, label="slider speed |v| (mm/s, log scale)",
                               pad=0.02)
            drawn["contours"] = cs
    for cls, style in MAP_STYLE.items():
        sel = m.motion == cls
        if np.any(sel):
            ax.scatter(ff[sel], vv[sel], s=40, label=cls, zorder=3, **style)
    if m.limits is not None:  # a ring around every point beyond a limit of the ceramic
        over = np.array([[lim is not None and bool(lim.exceeded()) for lim in row]
                         for row in m.limits], dtype=bool)
        if np.any(over):
            ax.scatter(ff[over], vv[over], s=110, facecolors="none", edgecolors="red",
                       linewidths=1.2, label="beyond a limit", zorder=4)
    several = [(float(m.preloads_N[j]), float(m.voltages_V[i])) for i, j in m.several_branches()]
    if several:
        x, y = zip(*several, strict=True)
        ax.scatter(x, y, s=180, marker="D", facecolors="none", edgecolors="k",
                   linewidths=1.2, label="several stable states", zorder=4)
        drawn["several"] = several
    for k, (a, b) in enumerate(m.non_monotone_pairs()):
        seg = ((float(m.preloads_N[a[1]]), float(m.preloads_N[b[1]])),
               (float(m.voltages_V[a[0]]), float(m.voltages_V[b[0]])))
        ax.plot(*seg, "--", color="tab:red", lw=1.5, zorder=2,
                label="non-monotone neighbours (speeds x2 against the trend)" if k == 0
                else None)
        drawn["non_monotone"].append(seg)
    for axis, values in ((ax.set_xlim, m.preloads_N), (ax.set_ylim, m.voltages_V)):
        lo, hi = float(np.min(values)), float(np.max(values))
        pad = 0.05 * (hi - lo) if hi > lo else 0.5 * max(abs(lo), 1.0)
        axis(lo - pad, hi + pad)  # room for the markers of the grid's edge points
    ax.set_xlabel("preload F_P (N)")
    ax.set_ylabel("voltage amplitude V0 (V)")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=3)
    return drawn


def curve(x: Sequence[float], ys: dict[str, Sequence[float]], xlabel: str, ylabel: str,
          path: Path, title: str = "") -> Path:
    """Line plot of several named series against one axis (Figs. 20-21, 24)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, y in ys.items():
        ax.plot(x, y, "o-", ms=3, label=name)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    return save(fig, path)


def simulation_figures(r: SimulationResult, out_dir: Path, prefix: str = "") -> list[Path]:
    """The figures ``lusm simulate --plot`` writes, in ``out_dir``."""
    out = Path(out_dir)
    return [
        slider_velocity(r, out / f"{prefix}fig09_slider_velocity.png"),
        forces_and_relative_velocity(r, out / f"{prefix}fig11_forces_vrel.png"),
        hysteresis_loop(r, out / f"{prefix}fig12_hysteresis.png"),
        transformed_phase_plane(r, out / f"{prefix}fig14_phase_plane.png"),
    ]
