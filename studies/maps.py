"""Figures of a study's dataset (``lusm explore --plot``): maps over two varying axes,
curves over one, a panel or a line per material."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

MAP_VARIABLES = ("no_load_velocity", "stall_force", "split", "peak_efficiency", "f_drive")
"""Variables drawn by :func:`design_maps` (each where the dataset has it)."""

SIGNED_VARIABLES = ("split",)
"""Variables whose sign means something (``split > 0``: B2 above L1): drawn on a diverging
colour scale centred on zero, with the zero contour (a map) or the zero line (a curve)."""

_DRAWN_UNITS = {"no_load_velocity": (1e3, "mm/s"), "split": (1e-3, "kHz"),
                "f_drive": (1e-3, "kHz"), "peak_efficiency": (100.0, "%")}
"""Factor and unit each variable is drawn in (the others in their dataset unit)."""

_NOTES = {"stall_force": "at the exact level the stall force includes the creep band "
                         "(the slider creeps, below two ripple scales, from the averaged "
                         "stall up to it: lusm characteristic prints both)"}
"""What a variable's figure says under its title."""


PLOT_DIMS = ("length", "width", "thickness", "gap", "tip_length", "tip_width", "chamfer",
             "frequency", "voltage", "preload")
"""Numeric dimensions a study's figures are drawn over, in the order they are chosen (the
``material`` axis, a name, is drawn as :func:`drawn_materials` says)."""


def plot_dims(ds, name: str) -> tuple[str, ...]:
    """The numeric dimensions :func:`design_maps` draws variable ``name`` over: length x width
    where both vary (the design-space map), else the first two of :data:`PLOT_DIMS` along which
    it has at least two values (a map), else the first one (a curve); empty when none."""
    varied = [d for d in PLOT_DIMS if d in ds[name].dims and ds.sizes[d] >= 2]
    if "length" in varied and "width" in varied:
        return ("length", "width")
    return tuple(varied[:2])


def drawn_materials(ds, name: str) -> bool:
    """Whether :func:`design_maps` draws variable ``name`` for each value of the ``material``
    axis: when it has two or more. A map is then one panel per material, a curve one line per
    material, and a variable that varies along no numeric axis its values against the
    materials (so that a study over materials alone has figures too)."""
    return "material" in ds[name].dims and ds.sizes["material"] >= 2


def drawable_maps(ds) -> list[str]:
    """The :data:`MAP_VARIABLES` :func:`design_maps` can draw: present, along at least one
    numeric axis of two values or more (:func:`plot_dims`) or two materials or more
    (:func:`drawn_materials`), not all NaN."""
    return [name for name in MAP_VARIABLES
            if name in ds and (plot_dims(ds, name) or drawn_materials(ds, name))
            and np.isfinite(ds[name].values.astype(float)).any()]


def _axis_scale(ds, dim: str) -> tuple[float, str]:
    """Factor and unit a coordinate is drawn in: mm for lengths, kHz for frequencies."""
    unit = ds[dim].attrs.get("units", "")
    return {"m": (1e3, "mm"), "Hz": (1e-3, "kHz")}.get(unit, (1.0, unit))


def design_maps(ds, folder: str | Path) -> list[Path]:
    """PNG figures of :data:`MAP_VARIABLES`, each over its dimensions of :func:`plot_dims`:
    maps over two (length x width for a design-space study), curves over one; with two
    materials or more (:func:`drawn_materials`), one map panel or one curve per material, or
    the values against the materials where no numeric axis varies; the other dimensions at
    their first value.

    Returns the written files (``{name}_{dim}[_{dim}][_material].png``); a variable that is
    absent, all NaN, or without a numeric axis of at least two values or two materials, gives
    none.
    """
    return [_figure(ds, name, Path(folder)) for name in drawable_maps(ds)]


def _figure(ds, name: str, folder: Path) -> Path:
    """Draw variable ``name`` of ``ds`` as :func:`design_maps` says, write it into ``folder``
    and return its path."""
    from matplotlib.figure import Figure

    dims = plot_dims(ds, name)
    per_material = drawn_materials(ds, name)
    drawn = dims + (("material",) if per_material else ())
    da = ds[name]
    fixed = {d: 0 for d in da.dims if d not in drawn}
    # ascending coordinates: a list axis may come in any order; the materials in the
    # study's order
    da = da.isel(fixed).transpose(*drawn)
    if dims:
        da = da.sortby(list(dims))
    materials = [str(m) for m in ds["material"].values] if per_material else [None]
    panels = len(materials) if len(dims) == 2 else 1
    fig = Figure(figsize=(6.5 + 3.5 * (panels - 1), 5.0), layout="constrained")
    axes = fig.subplots(1, panels, sharex=True, sharey=True, squeeze=False)[0]
    if panels > 1:  # room between the panels' end tick labels
        fig.get_layout_engine().set(wspace=0.08)
    scale, unit = _DRAWN_UNITS.get(name, (1.0, da.attrs.get("units", "")))
    label = f"{da.attrs.get('long_name', name)} ({unit})"  # the title's
    axis_label = f"{name} ({unit})"  # the colour bar's or the y axis's
    # the values (drawn unit) of each material (of the only one)
    of = [(da if m is None else da.isel(material=k)).values.astype(float) * scale
          for k, m in enumerate(materials)]
    if len(dims) == 2:
        _draw_maps(ds, da, dims, fig, axes, of, materials, axis_label,
                   name in SIGNED_VARIABLES)
    elif dims:
        _draw_curves(ds, da, dims[0], axes[0], of, materials, axis_label, per_material)
    else:
        _draw_per_material(ds, axes[0], of, materials, axis_label)
    if name in SIGNED_VARIABLES and len(dims) < 2:
        axes[0].axhline(0.0, color="k", lw=0.8)
    title = _title(ds, name, ", ".join(_coord_text(ds, d) for d in fixed), label)
    if panels > 1:
        fig.suptitle(title, fontsize=8)
    else:
        axes[0].set_title(title, fontsize=8)
    path = folder / f"{name}_{'_'.join(drawn)}.png"
    fig.savefig(path, dpi=120)
    return path


def _axis_label(ds, dim: str) -> tuple[float, str]:
    """Factor and label of a coordinate as drawn: ``plate length (mm)``."""
    factor, unit = _axis_scale(ds, dim)
    return factor, f"{ds[dim].attrs.get('long_name', dim)} ({unit})"


def _draw_maps(ds, da, dims, fig, axes, of, materials, label: str, signed: bool) -> None:
    """One map over ``dims`` (y, x) per material panel, on one colour scale: a diverging one
    centred on zero with the zero contour for a ``signed`` variable (:data:`SIGNED_VARIABLES`),
    viridis over the values' range otherwise."""
    fy, ylabel = _axis_label(ds, dims[0])
    fx, xlabel = _axis_label(ds, dims[1])
    finite = np.asarray(of)[np.isfinite(of)]
    lo, hi = (finite.min(), finite.max()) if finite.size else (None, None)
    cmap = "viridis"
    if signed and finite.size:
        top = float(np.abs(finite).max()) or 1.0
        lo, hi, cmap = -top, top, "RdBu_r"
    x, y = da[dims[1]].values * fx, da[dims[0]].values * fy
    for k, ax in enumerate(axes):
        mesh = ax.pcolormesh(x, y, of[k], shading="nearest", cmap=cmap, vmin=lo, vmax=hi)
        if signed:
            _zero_contour(ax, x, y, of[k])
        ax.set_xlabel(xlabel)
        if materials[k] is not None:
            ax.set_title(f"material {materials[k]}", fontsize=8)
    axes[0].set_ylabel(ylabel)
    fig.colorbar(mesh, ax=list(axes), label=label)


def _zero_contour(ax, x: np.ndarray, y: np.ndarray, values: np.ndarray) -> None:
    """The zero contour of ``values`` on the grid ``x`` x ``y`` (drawn units), labelled, where
    the values change sign on a grid of two points or more each way."""
    v = np.asarray(values, dtype=float)
    finite = v[np.isfinite(v)]
    if min(v.shape) < 2 or not (finite.size and finite.min() < 0.0 < finite.max()):
        return
    cs = ax.contour(x, y, np.ma.masked_invalid(v), levels=[0.0], colors="k", linewidths=1.5)
    ax.clabel(cs, fmt={0.0: "0 (L1 = B2)"}, fontsize=7)


def _draw_curves(ds, da, dim: str, ax, of, materials, label: str, per_material: bool) -> None:
    """The answer against the one axis ``dim`` that varies, a line per material."""
    f, xlabel = _axis_label(ds, dim)
    for k, m in enumerate(materials):
        ax.plot(da[dim].values * f, of[k], "o-", label=m)
    if per_material:
        ax.legend(title="stator material", fontsize=8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(label)
    ax.grid(True, alpha=0.3)


def _draw_per_material(ds, ax, of, materials, label: str) -> None:
    """Only the material varies: the values against the materials' names."""
    ax.plot(range(len(materials)), of, "o")
    ax.set_xticks(range(len(materials)), labels=materials)
    ax.set_xlim(-0.5, len(materials) - 0.5)
    ax.set_xlabel(ds["material"].attrs.get("long_name", "material"))
    ax.set_ylabel(label)
    ax.grid(True, alpha=0.3)


def _title(ds, name: str, where: str, label: str) -> str:
    """A figure's title: the variable with its meaning and drawn unit (``label``), where the
    other axes stand, what the variable includes (:data:`_NOTES`), and for a speed or a force
    the damping it depends on."""
    import textwrap

    lines = [textwrap.fill(f"{name}: {label}", 95)]
    lines += [textwrap.fill(f"at {where}", 95)] if where else []
    lines += [textwrap.fill(_NOTES[name], 95)] if name in _NOTES else []
    if name not in ("split", "f_drive") and "damping" in ds.attrs:
        lines.append(textwrap.fill(textwrap.shorten(f"damping {ds.attrs['damping']}", 190), 95))
    return "\n".join(lines)


def _coord_text(ds, dim: str) -> str:
    v = ds[dim].values[0]
    if dim == "material":
        return f"material {v}"
    if dim == "gap" and math.isnan(v):  # a stator file's own mesh: its tagged electrodes
        return "gap of the stator's mesh"
    unit = ds[dim].attrs.get("units", "")
    if unit == "m":
        return f"{dim} {v * 1e3:g} mm"
    return f"{dim} {v:g} {unit}"
