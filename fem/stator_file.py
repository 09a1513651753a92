"""Stator descriptions in TOML files: dimensions, electrodes, material, points, optional mesh.

Lengths are millimetres in the file and metres inside. Schema (every table optional except
``[plate]``; unknown keys are errors; see ``docs/designer.md``)::

    name = "paper plate"                # free text

    [plate]
    length_mm = 30.0                    # along y; with a mesh: optional, must match it
    width_mm = 7.5                      # across x; with a mesh: optional, must match it
    thickness_mm = 3.0                  # required

    [electrodes]
    gap_mm = 0.5                        # quadrant layout of the generated mesh only
    drive = [1, 4]                      # electrodes at +V (others grounded), numbers 1..4

    [material]
    name = "pzt8"                       # a name of fem.material.MATERIAL_NAMES, or inline:
    # base = "pzt8"                     # start from a named material and override
    # cE_Pa = [[...6 rows of 6...]]     # stiffness at constant E (Pa), Voigt 11,22,33,23,13,12
    # e_C_m2 = [[...3 rows of 6...]]    # piezoelectric stress constants (C/m^2)
    # epsS_F_m = [[...3 rows of 3...]]  # permittivity at constant strain (F/m)
    # rho_kg_m3 = 7600.0
    # source = "datasheet X"            # where inline constants come from (inline only)

    [points]
    tip_mm = [0.0, 30.0]                # default: the mesh's "tip" vertex, else (0, l)
    preload_mm = [0.0, 0.0]             # default: the mesh's "preload" vertex, else (0, 0)
    mounts_mm = [[0.0, 15.0]]           # mounting points, on the planform: lusm modes prints
                                        #   the L1 and B2 amplitude there (0 at a node)

    [mesh]
    file = "plate.msh"                  # relative to the TOML file; replaces the rectangle
    unit = "m"                          # unit of the mesh coordinates: "m" or "mm"

    # --- features of a parametric stator (any of these tables: the planform is then
    # --- meshed by gmsh, fem.meshing.parametric; not with [mesh] file)
    [tip]                               # unelectroded protrusion centred on the end y = l
    length_mm = 1.0                     #   beyond the plate's length, (0, [plate] length_mm]
    width_mm = 2.0                      #   across, (0, width - 2 chamfers]
    # material = "alumina"              #   its own material: "alumina" or "steel"
                                        #   (fem.material.TIP_MATERIALS); default: the
                                        #   plate's ceramic, unelectroded
    [chamfers]
    size_mm = 1.5                       # 45-degree leg at all four corners,
                                        #   (0, (min(length, width) - gap) / 2)
    [[holes]]                           # through holes, one table each, inside the body
    center_mm = [2.0, 5.0]              #   [x, y] (mm)
    diameter_mm = 1.5                   #   > 0, clear of the outline and of other holes
    # [mesh] size_mm = 0.5              # element size, [min(l, W)/100, min(l, W)],
                                        #   default min(l, W) / 8

    # --- the motor around the stator (used when a parameter set is built: lusm simulate,
    # --- map, characteristic, params, report; lusm admittance takes [damping]; the FE
    # --- modes ignore them). Ranges: MOTOR_KEYS, DAMPING_RATIO_RANGE, Q_M_RANGE.
    [damping]                           # modal damping of L1 and B2; ONE of:
    zeta_L1 = 0.01                      #   both ratios (-), each in [1e-05, 1) ...
    zeta_B2 = 0.01
    # Q_m = 500                         #   ... or the material's mechanical quality factor,
                                        #   zeta_L1 = zeta_B2 = 1 / (2 Q_m), Q_m in (0.5, 5e4]
    # source = "table2"                 #   ... or Table 2's ratios
    # source = "paper_amplitudes"       #   ... or fitted, as the paper fitted Table 2's, so
    # frequency_Hz = 40e3               #   that the free tip amplitudes at this drive
                                        #   frequency (default 40 kHz) equal Table 2's at
                                        #   the paper's 40 kHz (rom.damping)
    # Q_mount = 300                     #   ... or only the other losses, combined with the
    # Q_contact = 500                   #   material's data-sheet Q_m: 1/Q = 1/Q_m +
                                        #   1/Q_mount + 1/Q_contact, zeta = 1/(2 Q); each in
                                        #   (0.5, 5e4]; Q_mount default DEFAULT_Q_MOUNT,
                                        #   Q_contact none. No [damping] table: the same
                                        #   with the defaults (a material without Q_m, as
                                        #   "paper": Table 2's ratios)

    [contact]
    k_contact_N_m = 1.7378e7            # normal contact stiffness k, Eq. 7, [1e3, 1e10] N/m

    [slider]
    M_slider_kg = 0.2                   # slider mass M, Eq. 6, [1e-4, 100] kg
    mu_sd = 0.04                        # friction coefficient of the linear guide, [0, 2]

    [friction]                          # tip/slider interface, Eq. 11
    mu_s = 0.5                          # static friction coefficient, (0, 2]
    mu_d = 0.35                         # dynamic, without vibration, (0, 2], <= mu_s
    a_mu = 0.15                         # residual at large amplitude, [0, 2], <= mu_d
    b_mu_per_m = 1e6                    # attenuation factor, [0, 1e9] 1/m

    [force_factor]                      # scales on the reduced force factors A_l, A_b
    scale_L1 = 1.0                      #   (a prototype's electrodes, bond and poling give
    scale_B2 = 1.0                      #   less than the model's), each in
                                        #   FORCE_FACTOR_SCALE_RANGE (lusm calibrate fits them)
    [calibration]                       # written by lusm calibrate: the fit's values,
                                        #   standard errors and covariance; read (and
                                        #   checked) by calibration.uncertainty, not here

With a feature table the stator is a :class:`fem.meshing.parametric.ParametricStator`: the plate
keeps its own length and width (the tip is added beyond ``y = l``; the tip point is the
centre of the tip's end), the electrodes are the plate's quadrants (``[electrodes] gap_mm``
applies) and gmsh meshes the planform when the file is read (cached per geometry).
Without ``[mesh]`` or feature tables the stator is the rectangular
:class:`fem.geometry.PlateStator` (meshed by :func:`fem.meshing.mesh.structured_mesh`), so a TOML
plate and the same plate built in Python give identical models. With a mesh the stator is a
:class:`MeshedStator`: a ``PlateStator`` whose length and width are the mesh's bounding box
and which carries the mesh, the tip and the preload point; :func:`fem.model.plate_model`
then assembles on that mesh.

The four motor tables are carried as plain data (``fem`` knows nothing of the reduced-order
model): :attr:`StatorDesign.motor` maps ``rom.params.MotorParams`` field names (``k_contact``,
``M_slider``, ``mu_sd``, ``mu_s``, ``mu_d``, ``a_mu``, ``b_mu``) to SI values, and
:attr:`StatorDesign.damping_ratios` holds ``(zeta_L1, zeta_B2)`` (None: the parameter source's
default, Table 2's ratios; without damping ratios in the file, the material's ``Q_m``
combined with the mount's, :func:`_material_damping`).
:func:`rom.from_fem.fem_params_from_file` applies them; every
constant not given stays Table 2's (Li, Yao & Wu 2016, Tables 1-2 and Section 4.1). A
``Q_m`` is turned into one viscous ratio for both modes, ``zeta = 1 / (2 Q_m)``: this assumes
the stator's modal loss is the material's mechanical loss alone (no mounting or radiation
loss) and the same for the extensional L1 and the bending B2 mode. Table 1's preload spring
(4000 N/m) has no key: the model applies the preload through a fixed stator base, as the
paper's Eq. 7 does (``--preload``; docs/contact.md 2.5).
"""

from __future__ import annotations

import math
import os
import tomllib
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from bounds import ParameterError
from fem.errors import StatorFileError
from fem.geometry import ELECTRODES, MIN_GAP_M, PlateStator
from fem.material import (  # DEFAULT_Q_MOUNT: the [damping] Q_mount default, named here too
    DEFAULT_Q_MOUNT,  # noqa: F401
    MATERIAL_NAMES,
    PiezoMaterial,
    get_material,
    material_damping,
)
from fem.mesh_settings import MeshSettings
from fem.meshing.meshed_stator import MeshedStator, bbox_mm
from fem.units import to_si

MM = 1e-3
"""One millimetre in metres."""


def _m(mm: float) -> float:
    """A plate dimension the file gives in mm, in m: the double nearest the decimal written
    (:func:`fem.units.to_si`; ``6.5 * MM`` is 0.006500000000000001), the value a study's
    ``"6.5 mm"`` and the commands' ``--width-mm 6.5`` get, so that the same plate is the same
    double, and a gmsh mesh the same mesh, whichever way it is given."""
    return to_si(mm, MM)

MATERIAL_RANGES = {"cE_Pa": (0.1, 1000.0, 1e9, "GPa"), "e_C_m2": (0.0, 100.0, 1.0, "C/m^2"),
                   "epsS_F_m": (1.0, 1e5, 8.8541878128e-12, "eps0")}
"""Accepted size of inline ``[material]`` constants (lower, upper, unit scale, unit): the largest
diagonal stiffness in GPa, the largest piezoelectric constant in C/m^2, the largest diagonal
permittivity in units of eps0. e = 1e6 C/m^2 (1e5 times PZT-8's) gives a clamped capacitance of
0.78 F."""
PZT8_SIZE = {"cE_Pa": "147 GPa", "e_C_m2": "13.9 C/m^2", "epsS_F_m": "904 eps0"}
"""PZT-8's values of the quantities :data:`MATERIAL_RANGES` bounds, for messages."""
DENSITY_RANGE_KG_M3 = (100.0, 50_000.0)
"""``[material] rho_kg_m3`` accepted: from foams to beyond osmium (22 590). Outside it the
frequencies leave every range the solvers are set for (1e-30 gives 5e21 Hz; 1e30 leaves ARPACK
printing to the terminal)."""
PLATE_RANGE_MM = (0.1, 1000.0)
"""Allowed plate length, width and thickness (mm), the same as the ``lusm`` plate options
(``lusm.limits.PLATE_MM``): a plate of 0.1 mm to 1 m."""

MAX_STATOR_FILE_BYTES = 1_000_000
"""Largest stator file (bytes) read: a TOML description is a few kB."""

DAMPING_RATIO_RANGE = (1e-5, 1.0)
"""Allowed ``[damping] zeta_L1, zeta_B2`` (-): ``[1e-5, 1)``, underdamped modes."""

Q_M_RANGE = (0.5, 5e4)
"""Allowed ``[damping] Q_m`` (-): ``(0.5, 5e4]``, i.e. ``zeta = 1/(2 Q_m)`` in
:data:`DAMPING_RATIO_RANGE`."""

FORCE_FACTOR_SCALE_RANGE = (0.01, 100.0)
"""Allowed ``[force_factor] scale_L1, scale_B2`` (-): ``(0.01, 100]``."""

IDENTIFY_FREQUENCY_RANGE_HZ = (1e3, 1e7)
"""Allowed ``[damping] frequency_Hz`` of ``source = "paper_amplitudes"`` (Hz)."""

FEATURE_TABLES = ("tip", "chamfers", "holes")
"""Tables that describe features of a parametric stator (meshed by gmsh,
:mod:`fem.meshing.parametric`)."""

MOTOR_KEYS: dict[str, dict[str, tuple[str, float, float, bool, str]]] = {
    "contact": {"k_contact_N_m": ("k_contact", 1e3, 1e10, True, "N/m")},
    "slider": {"M_slider_kg": ("M_slider", 1e-4, 100.0, True, "kg"),
               "mu_sd": ("mu_sd", 0.0, 2.0, True, "")},
    "friction": {"mu_s": ("mu_s", 0.0, 2.0, False, ""),
                 "mu_d": ("mu_d", 0.0, 2.0, False, ""),
                 "a_mu": ("a_mu", 0.0, 2.0, True, ""),
                 "b_mu_per_m": ("b_mu", 0.0, 1e9, True, "1/m")},
}
"""Keys of the ``[contact]``, ``[slider]`` and ``[friction]`` tables: ``key -> (MotorParams
field, lower bound, upper bound, lower bound allowed, unit)``. The upper bound is allowed; a
lower bound of 0 that is not allowed means "> 0"."""

_KEYS: dict[str, tuple[str, ...]] = {
    "": ("name", "plate", "electrodes", "material", "points", "mesh", "tip", "chamfers",
         "holes", "damping", "contact", "slider", "friction", "force_factor", "calibration"),
    "plate": ("length_mm", "width_mm", "thickness_mm"),
    "electrodes": ("gap_mm", "drive"),
    "material": ("name", "base", "cE_Pa", "e_C_m2", "epsS_F_m", "rho_kg_m3", "source"),
    "points": ("tip_mm", "preload_mm", "mounts_mm"),
    "mesh": ("file", "unit", "size_mm"),
    "tip": ("length_mm", "width_mm", "material"),
    "chamfers": ("size_mm",),
    "holes": ("center_mm", "diameter_mm"),
    "damping": ("zeta_L1", "zeta_B2", "Q_m", "source", "frequency_Hz", "Q_mount", "Q_contact"),
    **{table: tuple(keys) for table, keys in MOTOR_KEYS.items()},
    "force_factor": ("scale_L1", "scale_B2"),
}


OUTLINE_TOLERANCE = 1e-6
"""A tip or preload point farther than this share of the planform's size from its outline
gets :class:`InteriorPointWarning`."""


class InteriorPointWarning(UserWarning):
    """A stator file's tip or preload point lies inside the planform, not on its outline."""


@dataclass(frozen=True, eq=False)
class StatorDesign:
    """A stator loaded from a file: the FE geometry plus its material.

    Attributes
    ----------
    name : str
        The file's ``name`` (default: the file stem).
    stator : PlateStator
        A plain :class:`PlateStator` (no mesh file) or a :class:`MeshedStator`; pass it to
        :func:`fem.modes.plate_modes`, :func:`fem.model.plate_model`,
        :func:`rom.from_fem.fem_params`.
    material : PiezoMaterial
    path : Path or None
        The TOML file.
    mesh_path : Path or None
        The mesh file, resolved.
    notes : tuple of str
        Remarks on how the file was read (e.g. triangles split into quads).
    damping_ratios : (float, float) or None
        ``(zeta_L1, zeta_B2)`` (-) from ``[damping]``; None: no ratios in the file (the
        parameter source's default, Table 2's).
    damping_origin : str
        What set the damping, for printing: ``'[damping] zeta_L1, zeta_B2'``,
        ``'[damping] Q_m = 500 (zeta = 1/(2 Q_m))'``, ``'[damping] source = "table2"'``,
        the identification's or ``''`` (no ``[damping]`` table).
    damping_identify_Hz : float or None
        ``source = "paper_amplitudes"``: the drive frequency (Hz) at which the damping is
        fitted to Table 2's free tip amplitudes when the parameter set is built
        (``rom.damping.identify_damping``); None otherwise.
    mounts_m : tuple of (float, float)
        ``[points] mounts_mm``: mounting points ``(x, y)`` (m) on the planform, where
        ``lusm modes`` reports the modes' amplitude (a free stator is best held at nodes).
    motor : dict
        ``MotorParams`` field name -> SI value from ``[contact]``, ``[slider]`` and
        ``[friction]`` (empty: Table 2's constants).
    force_factor_scales : (float, float) or None
        ``[force_factor] (scale_L1, scale_B2)``: factors on the reduced ``A_l``, ``A_b``
        (None: no table, the reduction's own).
    """

    name: str
    stator: PlateStator
    material: PiezoMaterial
    path: Path | None = None
    mesh_path: Path | None = None
    notes: tuple[str, ...] = field(default=())
    damping_ratios: tuple[float, float] | None = None
    damping_origin: str = ""
    motor: dict[str, float] = field(default_factory=dict)
    damping_identify_Hz: float | None = None
    mounts_m: tuple[tuple[float, float], ...] = ()
    force_factor_scales: tuple[float, float] | None = None

    def motor_keys(self) -> dict[str, str]:
        """``MotorParams`` field -> the ``[table] key`` of the file that set it."""
        where = {spec[0]: f"[{table}] {key}" for table, keys in MOTOR_KEYS.items()
                 for key, spec in keys.items()}
        return {name: where[name] for name in self.motor}

    def model(self, mesh: MeshSettings | None = None):
        """The assembled :class:`fem.model.PiezoPlateModel` on ``mesh`` (cached)."""
        from fem.model import plate_model

        return plate_model(self.stator, self.material, mesh)

    def modes(self, mesh: MeshSettings | None = None):
        """L1 and B2 (:class:`fem.modes.PlateModes`, cached) on ``mesh``; its ``refine``
        ignored with a mesh."""
        from fem.modes import plate_modes

        return plate_modes(self.stator, self.material, mesh)


def _where(table: str, key: str) -> str:
    return f"[{table}] {key}" if table else key


def _check_keys(data: dict[str, Any], table: str, src: str) -> None:
    allowed = _KEYS[table]
    for key in data:
        if key not in allowed:
            where = f"[{table}]" if table else "top level"
            raise StatorFileError(
                src, _where(table, key), data[key],
                text=f"unknown key {key!r} at {where}; allowed: {', '.join(allowed)}")


def _table(data: dict[str, Any], name: str, src: str, required: bool = False) -> dict:
    value = data.get(name)
    if value is None:
        if required:
            raise StatorFileError(src, f"[{name}]", text=f"missing table [{name}]")
        return {}
    if not isinstance(value, dict):
        raise StatorFileError(src, name, value, f"a table [{name}]")
    _check_keys(value, name, src)
    return value


def _length_mm(
    table: dict, tname: str, key: str, src: str, required: bool, upper_mm: float | None = None,
    allow_zero: bool = False,
) -> float | None:
    """A length in mm: in ``PLATE_RANGE_MM``, or with ``allow_zero`` in ``[0, upper_mm)``."""
    if key not in table:
        if required:
            lo, hi = PLATE_RANGE_MM
            raise StatorFileError(src, _where(tname, key), None, low=lo, high=hi, unit="mm",
                                  text=f"missing {_where(tname, key)} (mm, a number in "
                                       f"[{lo:g}, {hi:g}])")
        return None
    v = table[key]
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    if not allow_zero:
        lo, hi = PLATE_RANGE_MM
        if not ok or not lo <= v <= hi:
            raise _key_error(src, tname, key, v, lo, hi, "mm", False, False,
                             f"{_where(tname, key)} must lie in [{lo:g}, {hi:g}] mm, got {v!r}")
        return float(v)
    lower = "[0"
    upper = f"{upper_mm:g})" if upper_mm is not None else "inf)"
    if not ok or v < 0 or (upper_mm is not None and v >= upper_mm):
        raise _key_error(src, tname, key, v, 0.0, upper_mm, "mm", False, upper_mm is not None,
                         f"{_where(tname, key)} must lie in {lower}, {upper} mm, got {v!r}")
    if 0 < v < MIN_GAP_M / MM:  # said here in the file's unit, not by PlateStator in m
        raise StatorFileError(src, _where(tname, key), v,
                              f"0 (touching quadrants) or at least {MIN_GAP_M / MM:g} mm")
    return float(v)


def _point_mm(table: dict, key: str, src: str,
              table_name: str = "[points]") -> tuple[float, float] | None:
    if key not in table:
        return None
    v = table[key]
    if (
        not isinstance(v, list) or len(v) != 2
        or not all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in v)
        or not all(math.isfinite(c) for c in v)
    ):
        raise StatorFileError(src, f"{table_name} {key}", v, "[x, y] in mm")
    return (float(v[0]) * MM, float(v[1]) * MM)


def _drive(table: dict, src: str) -> tuple[int, ...]:
    if "drive" not in table:
        return PlateStator().drive_electrodes
    v = table["drive"]
    if not isinstance(v, list) or not v or not all(
        isinstance(e, int) and not isinstance(e, bool) for e in v
    ):
        raise StatorFileError(src, "[electrodes] drive", v,
                              "a non-empty list of electrode numbers 1..4")
    for e in v:
        if e not in ELECTRODES:
            raise StatorFileError(
                src, "[electrodes] drive", v, choices=ELECTRODES,
                text=f"[electrodes] drive names electrode {e}, which is not on the plate; "
                     f"allowed electrode numbers 1..4")
    if len(set(v)) != len(v):
        raise StatorFileError(src, "[electrodes] drive", v,
                              text=f"[electrodes] drive repeats an electrode: {v!r}")
    return tuple(v)


INLINE_KEYS = ("cE_Pa", "e_C_m2", "epsS_F_m", "rho_kg_m3")
"""The ``[material]`` keys of inline constants."""


def _material(table: dict, src: str) -> PiezoMaterial:
    """The ``[material]`` table's material: PZT-8 without one, a named one, or inline
    constants (from ``base`` where given)."""
    if not table:
        return get_material("pzt8")
    if not any(k in table for k in INLINE_KEYS):
        return _named_material(table, src)
    base = _material_base(table, src)
    values = _material_arrays(table, base, src)
    rho = table.get("rho_kg_m3", base.rho_kg_m3 if base is not None else None)
    lo, hi = DENSITY_RANGE_KG_M3
    if (not isinstance(rho, (int, float)) or isinstance(rho, bool) or not math.isfinite(rho)
            or not lo <= rho <= hi):
        raise StatorFileError(src, "[material] rho_kg_m3", rho, low=lo, high=hi, unit="kg/m^3",
                              text=f"[material] rho_kg_m3 must lie in [{lo:g}, {hi:g}] kg/m^3 "
                                   f"(solids; PZT-8 is 7600), got {rho!r}")
    name = str(table.get("name", "inline" if base is None else f"{base.name}-modified"))
    source = str(table.get("source", f"inline constants in {src}"))
    try:
        return PiezoMaterial(  # a base's Q_m and limits carry over to its modification
            name=name, cE_Pa=values["cE_Pa"], e_C_m2=values["e_C_m2"],
            epsS_F_m=values["epsS_F_m"], rho_kg_m3=float(rho), source=source,
            mechanical_Q=None if base is None else base.mechanical_Q,
            limits=None if base is None else base.limits,
        )
    except ParameterError as exc:  # the file's key, not the class's attribute name
        got = "" if exc.value is None else f", got {exc.value!r}"
        raise StatorFileError(src, f"[material] {exc.name}", exc.value, exc.range_text(),
                              text=f"[material] {exc.name} must be {exc.range_text()}"
                                   f"{got}") from None


def _library_material(key: str, name: object, src: str, text: str) -> PiezoMaterial:
    """The library's material ``name``, or a refusal of ``[material] key`` with ``text``."""
    try:
        if not isinstance(name, str):
            raise ValueError
        return get_material(name)
    except ValueError:
        raise StatorFileError(src, f"[material] {key}", name, choices=MATERIAL_NAMES,
                              text=text) from None


def _named_material(table: dict, src: str) -> PiezoMaterial:
    """A ``[material]`` table without inline constants: ``name`` (default PZT-8) alone."""
    if "base" in table:
        raise StatorFileError(src, "[material] base", table["base"],
                              text="[material] base needs at least one inline constant")
    name = table.get("name", "pzt8")
    if "source" in table:  # refused, not dropped: a named material has its own
        raise StatorFileError(
            src, "[material] source", table["source"],
            text=f"[material] source describes inline constants (cE_Pa, e_C_m2, "
                 f"epsS_F_m, rho_kg_m3) and cannot be combined with name = {name!r} "
                 f"alone, whose source is fixed; remove source, or give constants inline "
                 f"(with base = {name!r} to start from it)")
    return _library_material(
        "name", name, src,
        f"[material] name {name!r} is unknown; allowed: {', '.join(MATERIAL_NAMES)}, or "
        f"inline constants cE_Pa, e_C_m2, epsS_F_m, rho_kg_m3 (optionally with base = "
        f"\"pzt8\")")


def _material_base(table: dict, src: str) -> PiezoMaterial | None:
    """The named material inline constants start from (``base``), None without one (then
    every constant is needed)."""
    base_name = table.get("base")
    if base_name is not None:
        return _library_material("base", base_name, src,
                                 f"[material] base {base_name!r} is unknown; allowed: "
                                 f"{', '.join(MATERIAL_NAMES)}")
    missing = [k for k in INLINE_KEYS if k not in table]
    if missing:
        raise StatorFileError(
            src, f"[material] {missing[0]}",
            text=f"[material] inline constants need {', '.join(missing)} (or base = "
                 f"\"pzt8\" to start from a named material)")
    return None


def _material_arrays(table: dict, base: PiezoMaterial | None,
                     src: str) -> dict[str, np.ndarray]:
    """The stiffness, piezoelectric and permittivity arrays (SI): the table's, checked for
    shape and size, or the base's."""
    values: dict[str, Any] = {}
    for key, shape in (("cE_Pa", (6, 6)), ("e_C_m2", (3, 6)), ("epsS_F_m", (3, 3))):
        if key not in table:
            values[key] = getattr(base, key)
            continue
        try:
            arr = np.array(table[key], dtype=float)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.shape != shape:
            raise StatorFileError(src, f"[material] {key}", table[key],
                                  f"a {shape[0]}x{shape[1]} array of numbers",
                                  text=f"[material] {key} must be a {shape[0]}x{shape[1]} "
                                       "array of numbers")
        lo, hi, scale, unit = MATERIAL_RANGES[key]
        size = np.max(np.abs(np.diag(arr))) if key != "e_C_m2" else np.max(np.abs(arr))
        if not (np.all(np.isfinite(arr)) and lo <= size / scale <= hi):
            raise StatorFileError(
                src, f"[material] {key}", size / scale, low=lo, high=hi, unit=unit,
                text=f"[material] {key}'s largest "
                     f"{'entry' if key == 'e_C_m2' else 'diagonal entry'} must lie in "
                     f"[{lo:g}, {hi:g}] {unit} (solid piezoelectrics; PZT-8: "
                     f"{PZT8_SIZE[key]}), got {size / scale:.4g} {unit}")
        values[key] = arr
    return values


def _number(table: dict, tname: str, key: str, src: str, lo: float, hi: float,
            lo_closed: bool, hi_closed: bool, unit: str = "") -> float:
    """A real number of ``table[key]`` in the interval; the message names ``[tname] key``."""
    v = table[key]
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    if ok:
        ok = (v >= lo if lo_closed else v > lo) and (v <= hi if hi_closed else v < hi)
    if not ok:
        interval = f"{'[' if lo_closed else '('}{lo:g}, {hi:g}{']' if hi_closed else ')'}"
        got = f"{v:g}" if isinstance(v, (int, float)) and not isinstance(v, bool) else repr(v)
        raise _key_error(src, tname, key, v, lo, hi, unit, not lo_closed, not hi_closed,
                         f"{_where(tname, key)} must be a number in {interval}"
                         f"{' ' + unit if unit else ''}, got {got}")
    return float(v)


def _key_error(src: str, tname: str, key: str, value: object, low: float | None,
               high: float | None, unit: str, low_open: bool, high_open: bool,
               text: str) -> StatorFileError:
    """The refusal of a stator file's ``[tname] key``: a :class:`fem.errors.StatorFileError`
    named by the file's key (``'[plate] length_mm'``, what the user typed), its range in the
    key's unit (``unit``'s first word; the rest, a bound's origin, is the ``reason``)."""
    first, _, rest = unit.partition(" ")
    return StatorFileError(src, f"[{tname}] {key}", value, low=low, high=high, unit=first,
                           low_open=low_open, high_open=high_open, reason=rest.strip("() "),
                           text=text)


def _plate_mm(plate: dict, elec: dict, src: str) -> tuple[float, float, float]:
    """Length, width and electrode gap (mm) of a generated plate (the gap defaults to the
    paper's); each failure names its ``[table] key``."""
    length = _length_mm(plate, "plate", "length_mm", src, required=True)
    width = _length_mm(plate, "plate", "width_mm", src, required=True)
    assert length is not None and width is not None
    gap = _length_mm(elec, "electrodes", "gap_mm", src, required=False,
                     upper_mm=min(length, width), allow_zero=True)
    if gap is None:
        gap = PlateStator().electrode_gap_m / MM
        if gap >= min(length, width):  # said in the file's terms, not by PlateStator in m
            raise StatorFileError(
                src, _where("electrodes", "gap_mm"), None, low=0.0, high=min(length, width),
                high_open=True, unit="mm",
                text=f"the default {_where('electrodes', 'gap_mm')} {gap:g} mm leaves no "
                     f"electrode on a plate {min(length, width):g} mm wide; set "
                     f"{_where('electrodes', 'gap_mm')} in [0, {min(length, width):g}) mm")
    return length, width, gap


def _material_damping(table: dict, src: str, material: PiezoMaterial
                      ) -> tuple[tuple[float, float] | None, str, None]:
    """The default damping of a stator without ``[damping]`` ratios: the material's data-sheet
    ``Q_m`` combined with the mount's and the contact's losses (``[damping] Q_mount``,
    ``Q_contact``; :func:`fem.material.material_damping`), the same ratio in both
    modes. A material without ``Q_m`` (the paper's, inline constants without a base) keeps
    the parameter source's default (Table 2's ratios) unless the table asks for a mount."""
    given = [k for k in ("Q_mount", "Q_contact") if k in table]
    if material.mechanical_Q is None:
        if given:
            raise StatorFileError(
                src, f"[damping] {given[0]}", table[given[0]],
                text=f"[damping] {given[0]} combines with the material's mechanical Q_m, and "
                     f"material {material.name!r} has none; give [damping] Q_m (the "
                     "stator's total) instead")
        return None, "", None
    q_mount = (_number(table, "damping", "Q_mount", src, *Q_M_RANGE, False, True)
               if "Q_mount" in table else None)
    q_contact = (_number(table, "damping", "Q_contact", src, *Q_M_RANGE, False, True)
                 if "Q_contact" in table else None)
    z, origin = material_damping(material, q_mount, q_contact)
    tail = "" if table else "; the file has no [damping]"
    return (z, z), origin + tail, None


def _damping(table: dict, src: str, material: PiezoMaterial
             ) -> tuple[tuple[float, float] | None, str, float | None]:
    """``(zeta_L1, zeta_B2)`` or None, the origin text, and the identification frequency
    (Hz, or None) of a ``[damping]`` table (absent, or with ``Q_mount``/``Q_contact`` only:
    :func:`_material_damping`)."""
    if not table or set(table) <= {"Q_mount", "Q_contact"}:
        return _material_damping(table, src, material)
    loss_keys = [k for k in ("Q_mount", "Q_contact") if k in table]
    choices = ('give zeta_L1 and zeta_B2, or Q_m, or source = "table2" or '
               '"paper_amplitudes", or only Q_mount and Q_contact (combined with the '
               "material's Q_m)")
    if loss_keys:
        others = ", ".join(k for k in table if k not in ("Q_mount", "Q_contact"))
        raise StatorFileError(src, f"[damping] {loss_keys[0]}", table[loss_keys[0]],
                              text=f"[damping] {loss_keys[0]} combines with the material's "
                                   f"Q_m and cannot be combined with {others}; {choices}")
    if "source" in table:
        if table["source"] not in ("table2", "paper_amplitudes"):
            raise StatorFileError(
                src, "[damping] source", table["source"], choices=("table2", "paper_amplitudes"),
                text=f"[damping] source must be \"table2\" (Table 2's ratios) or "
                     f"\"paper_amplitudes\" (fitted to Table 2's free tip amplitudes), got "
                     f"{table['source']!r}; or {choices}")
        allowed = ("source", "frequency_Hz") if table["source"] == "paper_amplitudes" else (
            "source",)
        others = [k for k in table if k not in allowed]
        if others:
            raise StatorFileError(src, f"[damping] {others[0]}", table[others[0]],
                                  text=f"[damping] source = \"{table['source']}\" cannot be "
                                       f"combined with {', '.join(others)}; {choices}")
        if table["source"] == "table2":
            return None, '[damping] source = "table2"', None
        f = (_number(table, "damping", "frequency_Hz", src, *IDENTIFY_FREQUENCY_RANGE_HZ,
                     True, True, "Hz") if "frequency_Hz" in table else 40e3)
        return None, (f'[damping] source = "paper_amplitudes" (at {f:g} Hz, fitted to '
                      f'Table 2\'s free tip amplitudes at 40 kHz)'), f
    if "frequency_Hz" in table:
        raise StatorFileError(src, "[damping] frequency_Hz", table["frequency_Hz"],
                              text=f'[damping] frequency_Hz belongs to source = '
                                   f'"paper_amplitudes"; {choices}')
    if "Q_m" in table:
        if len(table) > 1:
            others = ", ".join(k for k in table if k != "Q_m")
            raise StatorFileError(src, "[damping] Q_m", table["Q_m"],
                                  text=f"[damping] Q_m sets both modes (zeta = 1/(2 Q_m)) and "
                                       f"cannot be combined with {others}; {choices}")
        q = _number(table, "damping", "Q_m", src, *Q_M_RANGE, False, True)
        z = 1.0 / (2.0 * q)
        return (z, z), f"[damping] Q_m = {q:g} (zeta = 1/(2 Q_m))", None
    missing = [k for k in ("zeta_L1", "zeta_B2") if k not in table]
    if missing:
        raise StatorFileError(src, f"[damping] {missing[0]}",
                              text=f"[damping] {missing[0]} is missing; {choices}")
    lo, hi = DAMPING_RATIO_RANGE
    zl = _number(table, "damping", "zeta_L1", src, lo, hi, True, False)
    zb = _number(table, "damping", "zeta_B2", src, lo, hi, True, False)
    return (zl, zb), "[damping] zeta_L1, zeta_B2", None


def _motor(data: dict[str, Any], src: str) -> dict[str, float]:
    """``MotorParams`` overrides of the ``[contact]``, ``[slider]``, ``[friction]`` tables."""
    out: dict[str, float] = {}
    for tname, keys in MOTOR_KEYS.items():
        table = _table(data, tname, src)
        for key, (name, lo, hi, lo_closed, unit) in keys.items():
            if key in table:
                out[name] = _number(table, tname, key, src, lo, hi, lo_closed, True, unit)
    fric = data.get("friction") or {}
    for low, high, reason in (("mu_d", "mu_s", "kinetic friction cannot exceed static"),
                              ("a_mu", "mu_d", "Eq. 11 decays from mu_d to a_mu")):
        if low in out and high in out and out[low] > out[high]:
            raise StatorFileError(
                src, f"[friction] {low}", fric[low], high=out[high],
                bound_by=f"[friction] {high}", reason=reason,
                text=f"[friction] {low} = {fric[low]!r} must be <= [friction] {high} = "
                     f"{fric[high]!r} ({reason})")
    return out


def _force_factor(data: dict[str, Any], src: str) -> tuple[float, float] | None:
    """``[force_factor] (scale_L1, scale_B2)`` (each 1 when not given), None without it."""
    table = _table(data, "force_factor", src)
    if "force_factor" not in data:
        return None
    lo, hi = FORCE_FACTOR_SCALE_RANGE
    return tuple(_number(table, "force_factor", k, src, lo, hi, False, True)  # type: ignore
                 if k in table else 1.0 for k in ("scale_L1", "scale_B2"))


def _holes(data: dict[str, Any], src: str) -> list[tuple[int, tuple[float, float], float]]:
    """``[[holes]]`` entries: ``(number, centre (mm), diameter (mm))``."""
    value = data.get("holes")
    if value is None:
        return []
    if not isinstance(value, list) or not value or not all(isinstance(v, dict) for v in value):
        raise StatorFileError(src, "holes", value, "an array of tables [[holes]] with "
                              "center_mm and diameter_mm")
    out = []
    for i, hole in enumerate(value, start=1):
        where = f"[[holes]] #{i}"
        for key in hole:
            if key not in _KEYS["holes"]:
                raise StatorFileError(src, f"{where} {key}", hole[key],
                                      text=f"unknown key {key!r} in {where}; allowed: "
                                           f"{', '.join(_KEYS['holes'])}")
        for key in _KEYS["holes"]:
            if key not in hole:
                raise StatorFileError(src, f"{where} {key}",
                                      text=f"{where} needs {key} (center_mm = [x, y] in mm, "
                                           "diameter_mm > 0)")
        c = _point_mm(hole, "center_mm", src, table_name=where)
        d = hole["diameter_mm"]
        if not (isinstance(d, (int, float)) and not isinstance(d, bool) and math.isfinite(d)
                and d > 0):
            raise StatorFileError(src, f"{where} diameter_mm", d, "a number > 0 mm")
        assert c is not None
        out.append((i, (c[0] / MM, c[1] / MM), float(d)))
    return out


def _tip_material(tip_t: dict, src: str) -> str:
    """``[tip] material``: a name of :data:`fem.material.TIP_MATERIALS`, or ``""`` (the plate's
    ceramic) when absent."""
    from fem.material import TIP_MATERIALS

    if "material" not in tip_t:
        return ""
    name = tip_t["material"]
    if not isinstance(name, str) or name.strip().lower() not in TIP_MATERIALS:
        raise StatorFileError(src, "[tip] material", name, choices=TIP_MATERIALS,
                              text=f"[tip] material {name!r} is unknown; allowed: "
                                   f"{', '.join(TIP_MATERIALS)} (leave it out for a tip of the "
                                   "plate's ceramic)")
    return name.strip().lower()


def _parametric_holes(data, src, length: float, width: float,
                      chamfer: float) -> list[tuple[float, float, float]]:
    """The ``[[holes]]`` of a parametric design as ``(x, y, diameter)`` (m), each inside the
    plate body (``length``, ``width``, ``chamfer`` in mm) and clear of the others."""
    from fem.meshing.parametric import hole_clearance_m

    holes = []
    for i, (x, y), d in _holes(data, src):
        hole = (x * MM, y * MM, d * MM)
        clear = hole_clearance_m(hole, width * MM, length * MM, chamfer * MM)
        if clear <= 0.0:
            raise StatorFileError(
                src, f"[[holes]] #{i}", [x, y],
                text=f"[[holes]] #{i} (diameter {d:g} mm at [{x:g}, {y:g}] mm) reaches the "
                     f"plate's outline; a hole must lie inside the plate body (x in "
                     f"[{-width / 2:g}, {width / 2:g}] mm, y in [0, {length:g}] mm"
                     f"{', inside the chamfers' if chamfer else ''})")
        for j, (ox, oy, od) in enumerate(holes, start=1):
            if math.hypot(hole[0] - ox, hole[1] - oy) <= 0.5 * (hole[2] + od):
                raise StatorFileError(src, f"[[holes]] #{i}", [x, y],
                                      text=f"[[holes]] #{i} overlaps [[holes]] #{j}")
        holes.append(hole)
    return holes


def _parametric(data, plate, elec, mesh_t, tip_pt, preload_pt, thickness, drive, src, name,
                material, motor) -> StatorDesign:
    """A :class:`fem.meshing.parametric.ParametricStator` design from the feature tables."""
    from fem.meshing.parametric import (
        DEFAULT_SIZE_DIVISIONS,
        SIZE_DIVISIONS_RANGE,
        ParametricStator,
        parametric_mesh,
    )

    tables = ", ".join(f"[{t}]" if t != "holes" else "[[holes]]" for t in FEATURE_TABLES)
    for key in ("file", "unit"):
        if key in mesh_t:
            raise StatorFileError(src, f"[mesh] {key}", mesh_t[key],
                                  text=f"[mesh] {key} cannot be combined with the feature "
                                       f"tables ({tables}): those are meshed by gmsh; describe "
                                       "the whole planform in the mesh file instead")
    length, width, gap = _plate_mm(plate, elec, src)
    tip_t = _table(data, "tip", src)
    cham_t = _table(data, "chamfers", src)
    chamfer = 0.0
    if "chamfers" in data:
        if "size_mm" not in cham_t:
            raise StatorFileError(src, "[chamfers] size_mm",
                                  text="[chamfers] needs size_mm (the 45-degree leg, mm)")
        c_max = 0.5 * (min(length, width) - gap)
        chamfer = _number(cham_t, "chamfers", "size_mm", src, 0.0, c_max, False, False, "mm "
                          "((min(length, width) - gap) / 2)")
    tip_l = tip_w = 0.0
    tip_mat = _tip_material(tip_t, src) if "tip" in data else ""
    if "tip" in data:
        for key in ("length_mm", "width_mm"):
            if key not in tip_t:
                raise StatorFileError(src, f"[tip] {key}",
                                      text=f"[tip] needs {key} (the protrusion beyond the "
                                           "plate's end: length_mm along the plate, width_mm "
                                           "across, centred)")
        tip_l = _number(tip_t, "tip", "length_mm", src, 0.0, length, False, True,
                        "mm ([plate] length_mm)")
        tip_w = _number(tip_t, "tip", "width_mm", src, 0.0, width - 2 * chamfer, False, True,
                        "mm ([plate] width_mm" + (" minus the chamfers)" if chamfer else ")"))
    holes = _parametric_holes(data, src, length, width, chamfer)
    size = None
    if "size_mm" in mesh_t:
        lo, hi = (min(length, width) / n for n in SIZE_DIVISIONS_RANGE[::-1])
        size = _number(mesh_t, "mesh", "size_mm", src, lo, hi, True, True,
                       "mm (min(length, width) / 100 .. / 1)")
    try:
        stator = ParametricStator(
            length_m=_m(length), width_m=_m(width), thickness_m=_m(thickness),
            electrode_gap_m=_m(gap), drive_electrodes=drive, tip_length_m=_m(tip_l),
            tip_width_m=_m(tip_w), chamfer_m=_m(chamfer), holes_m=tuple(holes),
            mesh_size_m=None if size is None else size * MM, tip_material=tip_mat,
        )
    except ValueError as exc:
        raise StatorFileError(src, "", text=str(exc)) from None
    for key, pt, default in (("tip_mm", tip_pt, stator.tip_point_m),
                             ("preload_mm", preload_pt, stator.preload_point_m)):
        if pt is not None and not np.allclose(pt, default, rtol=0.0,
                                               atol=1e-9 * length * MM):
            raise StatorFileError(
                src, f"[points] {key}", [pt[0] / MM, pt[1] / MM],
                text=f"[points] {key} = [{pt[0] / MM:g}, {pt[1] / MM:g}] mm: the parametric "
                     f"stator puts it at [{default[0] / MM:g}, {default[1] / MM:g}] mm; give a "
                     "mesh file ([mesh] file) for other points")
    try:
        mesh = parametric_mesh(stator)
    except (ImportError, ValueError) as exc:
        raise StatorFileError(src, "", text=str(exc)) from None
    size_text = (f"{stator.element_size_m / MM:g} mm" + ("" if size is not None else
                 f" (min(length, width) / {DEFAULT_SIZE_DIVISIONS})"))
    notes = (f"meshed by gmsh: {mesh.n_elements} quads, element size {size_text}",)
    return StatorDesign(name=name, stator=stator, material=material, notes=notes, **motor)


def _mounts(data: dict[str, Any], design: StatorDesign, src: str):
    """``[points] mounts_mm`` in metres, each checked to lie on the planform."""
    from fem.meshing.meshed_stator import planform_mesh

    value = (data.get("points") or {}).get("mounts_mm")
    if value is None:
        return ()
    # a flat [0, 15] (one point without its list) is told how to write one point
    if not isinstance(value, list) or not value or not all(isinstance(pt, list) for pt in value):
        raise StatorFileError(src, "[points] mounts_mm", value, "a list of [x, y] pairs in mm, "
                              "e.g. [[0, 15]] for one point")
    st = design.stator
    mesh = planform_mesh(st)
    out = []
    for i, pt in enumerate(value, start=1):
        xy = _point_mm({"mounts_mm": pt}, "mounts_mm", src, table_name="[points]")
        assert xy is not None
        x, y = xy
        slack = 1e-9 * max(st.length_m, st.width_m)
        if mesh is not None:
            on = bool(mesh.contains(np.array(xy)[:, None])[0])
        else:
            on = abs(x) <= st.width_m / 2 + slack and -slack <= y <= st.length_m + slack
        if not on:
            raise StatorFileError(src, "[points] mounts_mm", value,
                                  text=f"[points] mounts_mm point {i} = [{x / MM:g}, "
                                       f"{y / MM:g}] mm lies off the stator's planform")
        out.append((x, y))
    return tuple(out)


def parse_stator(data: dict[str, Any], base_dir: Path | None = None,
                 src: str = "stator") -> StatorDesign:
    """Build a :class:`StatorDesign` from a parsed TOML document (see module docstring).

    Parameters
    ----------
    data : dict
        The TOML document as a dictionary.
    base_dir : Path, optional
        Directory that ``[mesh] file`` is relative to (default: the working directory).
    src : str
        Name used in error messages.

    Raises
    ------
    ValueError
        A message naming the offending key and its allowed range.
    FileNotFoundError
        If the mesh file does not exist.
    """
    design = _parse_design(data, base_dir, src)
    mounts = _mounts(data, design, src)
    return replace(design, mounts_m=mounts) if mounts else design


def _parse_design(data: dict[str, Any], base_dir: Path | None = None,
                  src: str = "stator") -> StatorDesign:
    """:func:`parse_stator` without the mounting points: the tables every stator has, then
    the planform by its kind (parametric features, a generated plate, a mesh file)."""
    _check_keys(data, "", src)
    plate = _table(data, "plate", src, required=True)
    elec = _table(data, "electrodes", src)
    mat_t = _table(data, "material", src)
    pts_t = _table(data, "points", src)
    mesh_t = _table(data, "mesh", src)
    if "mesh" in data and not mesh_t:  # say so, not "missing [plate] length_mm"
        raise StatorFileError(src, "[mesh]", mesh_t,
                              text="[mesh] is empty; give it file = \"plate.msh\" (a mesh file, "
                                   "with unit = \"m\" or \"mm\"), or size_mm (the element size "
                                   "of a parametric stator: [tip], [chamfers], [[holes]]), or "
                                   "remove the table")
    name = data.get("name", src)
    if not isinstance(name, str):
        raise StatorFileError(src, "name", name, "a string")
    material = _material(mat_t, src)
    damping, damping_origin, identify_Hz = _damping(_table(data, "damping", src), src,
                                                    material)
    motor = {"damping_ratios": damping, "damping_origin": damping_origin,
             "damping_identify_Hz": identify_Hz, "motor": _motor(data, src),
             "force_factor_scales": _force_factor(data, src)}
    drive = _drive(elec, src)
    thickness = _length_mm(plate, "plate", "thickness_mm", src, required=True)
    tip = _point_mm(pts_t, "tip_mm", src)
    preload = _point_mm(pts_t, "preload_mm", src)
    assert thickness is not None

    features = [t for t in FEATURE_TABLES if t in data]
    if features:
        return _parametric(data, plate, elec, mesh_t, tip, preload, thickness, drive, src,
                           name, material, motor)
    if "size_mm" in mesh_t:
        raise StatorFileError(src, "[mesh] size_mm", mesh_t["size_mm"],
                              text="[mesh] size_mm sets the gmsh mesh of a parametric stator "
                                   "([tip], [chamfers] or [[holes]]); a plain plate is meshed "
                                   "by --refine, a mesh file by itself")
    if not mesh_t:
        stator = _generated_plate(plate, elec, thickness, drive, tip, preload, src)
        return StatorDesign(name=name, stator=stator, material=material, **motor)
    mesh_path, unit = _mesh_file(mesh_t, elec, base_dir, src)
    stator, notes = _meshed_stator(mesh_path, unit, plate, thickness, drive, tip, preload, src)
    return StatorDesign(
        name=name, stator=stator, material=material, mesh_path=mesh_path, notes=notes, **motor
    )


def _generated_plate(plate: dict, elec: dict, thickness: float, drive: tuple[int, ...],
                     tip: tuple[float, float] | None, preload: tuple[float, float] | None,
                     src: str) -> PlateStator:
    """The rectangular plate of ``[plate]`` and ``[electrodes]``; points given in
    ``[points]`` must be the ones it puts them at."""
    length, width, gap = _plate_mm(plate, elec, src)
    stator = PlateStator(
        length_m=_m(length), width_m=_m(width), thickness_m=_m(thickness),
        electrode_gap_m=_m(gap),
        drive_electrodes=drive,
    )
    for key, pt, default in (("tip_mm", tip, stator.tip_point_m),
                             ("preload_mm", preload, stator.preload_point_m)):
        if pt is None:
            continue
        if not np.allclose(pt, default, rtol=0.0, atol=1e-9 * length * MM):
            raise StatorFileError(
                src, f"[points] {key}", [pt[0] / MM, pt[1] / MM],
                text=f"[points] {key} = [{pt[0] / MM:g}, {pt[1] / MM:g}] mm: the generated "
                     f"plate puts it at [{default[0] / MM:g}, {default[1] / MM:g}] mm; give a "
                     "mesh file ([mesh] file) for other points")
    return stator


def _mesh_file(mesh_t: dict, elec: dict, base_dir: Path | None, src: str) -> tuple[Path, str]:
    """The mesh file ``[mesh] file`` names (relative to ``base_dir``) and its unit, checked
    to be a regular file before it is read."""
    from fem.meshing.mesh_io import UNITS

    if "file" not in mesh_t or not isinstance(mesh_t["file"], str):
        raise StatorFileError(src, "[mesh] file", mesh_t.get("file"),
                              text="[mesh] file must be the path of a mesh file (a string)")
    unit = mesh_t.get("unit", "m")
    if not isinstance(unit, str) or unit not in UNITS:
        raise StatorFileError(src, "[mesh] unit", unit, choices=UNITS)
    if "gap_mm" in elec:
        raise StatorFileError(src, "[electrodes] gap_mm", elec["gap_mm"],
                              text="[electrodes] gap_mm applies to the generated plate only; "
                                   "with [mesh] file the mesh's electrode groups define the "
                                   "layout")
    mesh_path = Path(mesh_t["file"])
    if not mesh_path.is_absolute():
        mesh_path = (base_dir or Path.cwd()) / mesh_path
    if mesh_path.is_dir():  # say so: "not found" sends the user looking for a path
        raise StatorFileError(src, "[mesh] file", mesh_t["file"],
                              text=f"[mesh] file {mesh_t['file']!r} is a folder ({mesh_path}); "
                                   "name the mesh file, e.g. \"plate.msh\"")
    if not mesh_path.exists():
        raise FileNotFoundError(f"{src}: [mesh] file {mesh_t['file']!r} not found ({mesh_path})")
    if not mesh_path.is_file():  # a FIFO or a device: say what it is, not "not found"
        from fem.small_file import kind_of

        what = kind_of(mesh_path.stat().st_mode) or "not a regular file"
        raise StatorFileError(src, "[mesh] file", mesh_t["file"],
                              text=f"[mesh] file {mesh_t['file']!r} is {what} ({mesh_path}), "
                                   "not a mesh file")
    return mesh_path, unit


def _meshed_stator(mesh_path: Path, unit: str, plate: dict, thickness: float,
                   drive: tuple[int, ...], tip: tuple[float, float] | None,
                   preload: tuple[float, float] | None,
                   src: str) -> tuple[MeshedStator, tuple[str, ...]]:
    """The stator of a mesh file and the notes on its reading: the plate's lengths, if
    given, must be the mesh's extent, the driven electrodes must have cells, and the tip and
    the preload point (``[points]``, the mesh's vertex groups, or the plate's ends) must lie
    on the mesh, apart."""
    from fem.meshing.mesh_io import read_stator_mesh

    try:
        imported = read_stator_mesh(mesh_path, unit=unit)
    except ValueError as exc:
        raise StatorFileError(src, "[mesh] file", str(mesh_path),
                              text=f"[mesh] file: {exc}") from None
    mesh = imported.mesh
    x0, x1, y0, y1 = mesh.bounding_box_m()
    for key, value_m in (("length_mm", y1 - y0), ("width_mm", x1 - x0)):
        given = _length_mm(plate, "plate", key, src, required=False)
        if given is not None and abs(given * MM - value_m) > 1e-6 * value_m:
            raise StatorFileError(
                src, f"[plate] {key}", given,
                text=f"[plate] {key} = {given:g} mm does not match the mesh's bounding box "
                     f"({value_m / MM:g} mm); lengths with a mesh are its overall extent")
    present = {int(k) for k in np.unique(mesh.electrode) if k > 0}
    for e in drive:
        if e not in present:
            raise StatorFileError(
                src, "[electrodes] drive", list(drive), choices=tuple(sorted(present)),
                text=f"[electrodes] drive names electrode {e}, which has no cells in "
                     f"{mesh_path.name} (electrodes present: {sorted(present)})")
    tip = _mesh_point(imported, "tip", "tip_mm", tip, (0.0, y1), src)
    preload = _mesh_point(imported, "preload", "preload_mm", preload, (0.0, 0.0), src)
    if math.hypot(tip[0] - preload[0], tip[1] - preload[1]) <= 1e-9 * max(x1 - x0, y1 - y0):
        # else refused later as "MotorParams.phi_Ll must differ from phi_L0", naming no key
        raise StatorFileError(
            src, "[points] preload_mm", [preload[0] / MM, preload[1] / MM],
            text=f"the tip and the preload point are the same point, [{tip[0] / MM:g}, "
                 f"{tip[1] / MM:g}] mm ([points] tip_mm and preload_mm, or the mesh's vertex "
                 "groups): the tip touches the slider at one end of the stator and the "
                 "preload presses at the other")
    stator = MeshedStator(
        length_m=y1 - y0, width_m=x1 - x0, thickness_m=_m(thickness), electrode_gap_m=0.0,
        drive_electrodes=drive, mesh=mesh, tip_m=tip, preload_m=preload,
        mesh_file=str(mesh_path),
    )
    notes = (f"triangles split into quads ({', '.join(imported.cell_types)})",) if (
        imported.converted
    ) else ()
    return stator, notes


def _mesh_point(imported, group: str, key: str, given: tuple[float, float] | None,
                default: tuple[float, float], src: str) -> tuple[float, float]:
    """The ``group`` point (m) of a mesh file's stator: ``[points] key`` if ``given``, else
    the mesh's vertex group, else ``default``. Refused off the mesh's cells, naming where it
    came from; a point inside the planform, off its outline, is warned about
    (:class:`InteriorPointWarning`)."""
    mesh, name = imported.mesh, imported.path.name
    x0, x1, y0, y1 = mesh.bounding_box_m()
    pt = given if given is not None else imported.points_m.get(group, default)
    slack = 1e-9 * max(x1 - x0, y1 - y0)
    in_box = x0 - slack <= pt[0] <= x1 + slack and y0 - slack <= pt[1] <= y1 + slack
    if not in_box or not bool(mesh.contains(np.array(pt)[:, None])[0]):
        at = f"[{pt[0] / MM:g}, {pt[1] / MM:g}] mm"
        # say where the point came from: a vertex group off the cells is no [points] key
        if given is not None:
            raise StatorFileError(src, f"[points] {key}", [pt[0] / MM, pt[1] / MM],
                                  text=f"[points] {key} = {at} lies off the mesh "
                                       f"({bbox_mm(mesh)})")
        if group in imported.points_m:
            raise StatorFileError(
                src, f"[points] {key}", None,
                text=f"the {group!r} vertex group of the mesh file {name} is at {at}, off the "
                     f"mesh's cells ({bbox_mm(mesh)}); put its node on the planform or set "
                     f"[points] {key}")
        raise StatorFileError(
            src, f"[points] {key}", None,
            text=f"the default {group} point {at} (no [points] {key}, no {group!r} vertex "
                 f"group in {name}) lies off the mesh's cells ({bbox_mm(mesh)}); set "
                 f"[points] {key} or add a {group!r} vertex group to the mesh")
    inside = mesh.outline_distance_m(pt)
    if inside > OUTLINE_TOLERANCE * max(x1 - x0, y1 - y0):
        # the reduction normalises the mode at the point: a tip 1 mm inside the plate moves
        # M_b from 0.0089 to 0.0155 kg
        origin = (f"[points] {key}" if given is not None else
                  f"the {group!r} vertex group" if group in imported.points_m else
                  f"the default {group} point")
        what = ("the contact tip touches the slider" if group == "tip" else
                "the preload presses")
        # stacklevel: the caller of parse_stator, past _meshed_stator and _parse_design
        warnings.warn(InteriorPointWarning(
            f"{src}: {origin} = [{pt[0] / MM:g}, {pt[1] / MM:g}] mm lies "
            f"{inside / MM:.3g} mm inside the planform, off its outline, where {what}; "
            f"the reduction normalises its mode there: move it onto the outline (the "
            f"plate's end) unless the part is meant to act inside"), stacklevel=5)
    return pt


def load_stator(path: str | Path) -> StatorDesign:
    """Read a stator TOML file (mm in the file, SI in the result).

    Parameters
    ----------
    path : str or Path
        The ``.toml`` file; ``[mesh] file`` is resolved relative to its directory.

    Returns
    -------
    StatorDesign
        ``.stator`` is what the FE stage takes, ``.material`` its material.

    Raises
    ------
    FileNotFoundError
        If the TOML file or its mesh file does not exist.
    fem.errors.StatorFileError
        For bad TOML or bad values: its ``key`` the file's key (``'[plate] length_mm'``),
        its ``value`` the value given, its ``allowed`` what the key takes; the message names
        the key and the allowed range.
    ValueError
        For a path that is no regular file (a folder, a loop of links, a device) or a file
        too large for a stator description.
    """
    from fem.small_file import (
        FileTooLarge,
        NotRegularFile,
        link_loop,
        read_small_text,
    )

    if not isinstance(path, (str, os.PathLike)):  # None: named, not "expected str, bytes..."
        raise TypeError(f"path must name a stator TOML file, got {path!r}")
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"stator file {path} is a folder; name its .toml file")
    if not path.exists():
        loop = link_loop(path)
        if loop:
            raise ValueError(f"stator file {path}: a loop of symbolic links ({loop}); point "
                             "the link at a file")
        raise FileNotFoundError(f"stator file not found: {path}")
    try:
        # bounded: a 512 MB file read whole takes 1.1 GB of memory, a FIFO would block
        data = tomllib.loads(read_small_text(path, MAX_STATOR_FILE_BYTES))
    except NotRegularFile as exc:
        raise ValueError(f"stator file {path} is {exc.what}, not a TOML file") from None
    except FileTooLarge as exc:
        raise ValueError(f"stator file {path} has {exc.size} bytes, above "
                         f"{MAX_STATOR_FILE_BYTES} for a TOML description (its mesh goes in "
                         "the file [mesh] file names)") from None
    except UnicodeDecodeError as exc:
        raise StatorFileError(path, "", text=f"not a UTF-8 text file ({exc.reason} at byte "
                                             f"{exc.start}); a stator file is TOML, saved as "
                                             "UTF-8") from None
    except tomllib.TOMLDecodeError as exc:
        raise StatorFileError(path, "", text=f"not valid TOML: {exc}") from None
    design = parse_stator(data, base_dir=path.parent, src=str(path))
    return replace(design, path=path, name=design.name if "name" in data else path.stem)


def tuned_stator_text(dimensions_mm: dict[str, float], comment: str,
                      source_text: str | None = None,
                      plate_tables: dict[str, dict[str, object]] | None = None) -> str:
    """A stator file (TOML text) with the ``[plate]`` dimensions of ``dimensions_mm`` set.

    The user's file is edited with tomlkit, which keeps its comments, order and layout: only
    the keys named change, each with a trailing comment saying its former value; every other
    table (electrodes, material, features, motor tables) stays as written. Without a file
    the text is built from ``plate_tables`` (``{"electrodes": {...}, "material": {...}}``).

    Parameters
    ----------
    dimensions_mm : dict
        ``{"length_mm": .., "width_mm": .., "thickness_mm": ..}`` (mm), written to 12
        significant digits (below a picometre on a 1 m plate: the frequencies do not move).
    comment : str
        Lines put as comments at the top of the file (how the dimensions were found).
    source_text : str, optional
        The user's stator file.
    plate_tables : dict, optional
        Tables written after ``[plate]`` when there is no ``source_text``.
    """
    import tomlkit

    doc = tomlkit.parse(source_text) if source_text is not None else tomlkit.document()
    if source_text is None:
        doc["name"] = "tuned plate"
    if "plate" not in doc:
        doc["plate"] = tomlkit.table()
    plate = doc["plate"]
    for key, value in dimensions_mm.items():
        new = float(f"{value:.12g}")
        old = plate.get(key)
        item = tomlkit.item(new)
        if old is not None and float(old) != new:
            item.comment(f"tuned (was {float(old):g})")
        plate[key] = item
    for name, table in (plate_tables or {}).items() if source_text is None else ():
        t = tomlkit.table()
        for k, v in table.items():
            t[k] = v
        doc[name] = t
    head = "".join(f"# {line}\n" if line else "#\n" for line in comment.splitlines())
    return head + "\n" + tomlkit.dumps(doc)
