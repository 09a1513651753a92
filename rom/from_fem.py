"""Reduced-order parameters from the FE stator model (modal reduction onto L1 and B2).

The ``fem`` package (scikit-fem) is imported inside :func:`fem_params` only, so importing
:mod:`rom` never pulls in scikit-fem.

Normalization (so that the FE modal coordinates mean what ``u_l`` and ``w_b`` mean in Eq. 2):

* L1: the FE shape is scaled so that its axial displacement ``u_y`` at the preload point
  (centre of the end ``y = 0``) equals Eq. 3's ``phi_L(0) = 1``;
* B2: the FE shape is scaled so that its transverse displacement ``u_x`` at the contact tip
  (centre of the end ``y = l``) equals Eq. 3's ``phi_B(l) = 2 |alpha2|`` (about 1.998).

Then, with ``Phi`` the scaled short-circuit shape of each mode::

    M = Phi^T M_FE Phi                  (kg)
    K = omega_short^2 M                 (N/m)
    A = Phi^T sum_{driven e} G_e        (N/V; driven electrodes at +V, the others grounded)
    C = 2 zeta sqrt(K M)                (N s/m)

and ``phi_L0, phi_Ll`` (``u_y``) and ``phi_B0, phi_Bl`` (``u_x``) are the FE values of the
scaled shapes at the preload point and at the tip.
"""

from __future__ import annotations

import math

import numpy as np

from bounds import ParameterError
from fem.beam_shapes import phi_B, phi_L
from fem.mesh_settings import MeshSettings
from rom.errors import DesignFileError, NodalPointError, UnreachableAmplitudeError
from rom.params import MotorParams
from rom.shape_data import ShapeData
from rom.table2 import table2

NODE_SHARE = 1e-2
"""Least share of a mode's largest displacement (in the normalised direction) at the point
where :func:`fem_params` normalises it: L1's u_y at the preload point, B2's u_x at the tip.
Below it the point sits at (or next to) a node of the mode and the modal mass, which scales
as the inverse square of that share, is meaningless (the plate's ends: about 1)."""


def fem_params(
    stator=None,
    material="pzt8",
    mesh: MeshSettings | None = None,
    base: MotorParams | None = None,
    damping_ratios: tuple[float, float] | None = None,
) -> MotorParams:
    """Modal reduction of the FE plate into a :class:`MotorParams`.

    Parameters
    ----------
    stator : fem.geometry.PlateStator, optional
        Plate geometry and drive electrodes; default: the paper's plate driven through 1 and 4.
    material : str or fem.material.PiezoMaterial
        ``'pzt8'`` (default) or ``'paper'``, or a material.
    mesh : MeshSettings, optional
        The 2D FE mesh (:func:`fem.model.plate_model`); default
        :class:`fem.mesh_settings.MeshSettings` (order 2, refine
        :data:`fem.mesh_settings.DEFAULT_REFINE`).
    base : MotorParams, optional
        Source of the contact, slider and friction constants (``k_contact``, ``M_slider``,
        ``mu_s``, ``mu_d``, ``mu_sd``, ``a_mu``, ``b_mu``) and of the default damping ratios;
        default :func:`rom.table2.table2`.
    damping_ratios : (float, float), optional
        Modal damping ratios ``(zeta_L1, zeta_B2)``; default ``(base.zeta_L1, base.zeta_B2)``.

    Returns
    -------
    MotorParams
    """
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.model import plate_model
    from fem.modes import plate_modes

    stator = PlateStator() if stator is None else stator
    mesh = (MeshSettings() if mesh is None else mesh).plate()
    base = table2() if base is None else base
    zeta_l, zeta_b = _damping_ratios(base, damping_ratios)
    mat = get_material(material)
    modes = plate_modes(stator, mat, mesh)
    model = plate_model(stator, mat, mesh)

    length = stator.length_m
    points = np.array([stator.preload_point_m, stator.tip_point_m]).T  # (2, 2)
    P = model.probe(points)  # rows: ux(preload), ux(tip), uy(preload), uy(tip)
    drive = model.coupling(stator.drive_electrodes)
    m_l, k_l, a_l, v_l, phi_l = _reduce_mode(model, stator, P, drive, modes.L1.shape, 2,
                                               float(phi_L(0.0, length)), modes.L1.f_short_Hz,
                                               "L1")
    m_b, k_b, a_b, v_b, phi_b = _reduce_mode(model, stator, P, drive, modes.B2.shape, 1,
                                               float(phi_B(length, length)),
                                               modes.B2.f_short_Hz, "B2")
    features = stator.features_text() if hasattr(stator, "features_text") else ""
    mesh_text = _mesh_text(stator, mesh.refine)
    return MotorParams.from_modal(
        M_l=m_l, K_l=k_l, A_l=a_l, phi_L0=float(v_l[2]), phi_Ll=float(v_l[3]),
        M_b=m_b, K_b=k_b, A_b=a_b, phi_B0=float(v_b[0]), phi_Bl=float(v_b[1]),
        damping_ratios=(zeta_l, zeta_b), base=base,
        shape=_fe_shape_data(model, mat, phi_l, phi_b, mesh.order),
        source=(
            f"FE modal reduction (scikit-fem, plane stress, order {mesh.order}, {mesh_text}, "
            f"{modes.dofs} dofs) of a {stator.length_m * 1e3:g} x {stator.width_m * 1e3:g} x "
            f"{stator.thickness_m * 1e3:g} mm plate{features}, material {mat.name}, drive "
            f"electrodes "
            f"{stator.drive_electrodes}; damping ratios ({zeta_l:.4g}, {zeta_b:.4g}); contact "
            f"and friction constants from: {base.source}"
        ),
    )


def _damping_ratios(base: MotorParams,
                    damping_ratios: tuple[float, float] | None) -> tuple[float, float]:
    """``(zeta_L1, zeta_B2)``: the ones given, each in (0, 1) (under-damped, as
    :func:`rom.beam.beam_params` takes them), else ``base``'s."""
    if damping_ratios is None:
        return base.zeta_L1, base.zeta_B2
    if np.ndim(damping_ratios) != 1 or len(damping_ratios) != 2:
        raise ParameterError("damping_ratios", damping_ratios,
                             message=f"damping_ratios must be (zeta_L1, zeta_B2), two numbers "
                             f"in (0, 1), got {damping_ratios!r}")
    zeta_l, zeta_b = (float(z) for z in damping_ratios)
    for name, z in (("zeta_L1", zeta_l), ("zeta_B2", zeta_b)):
        if not (math.isfinite(z) and 0.0 < z < 1.0):
            raise ParameterError(name, z, 0.0, 1.0, low_open=True, high_open=True,
                                 message=f"damping_ratios {name} must lie in (0, 1), got {z!r}")
    return zeta_l, zeta_b


def _fe_shape_data(model, material, phi_l: np.ndarray, phi_b: np.ndarray,
                   order: int) -> ShapeData:
    """The reduced shapes' peaks (:func:`fem.mode_peaks.shape_peaks`, per unit modal
    amplitude) and their stress combined over a period
    (:func:`fem.mode_peaks.combined_stress_factors`), with the plate's thickness, volume
    and the material's limits."""
    from fem.mode_peaks import combined_stress_factors, plate_volume_m3, shape_peaks

    peaks_l, peaks_b = shape_peaks(model, phi_l), shape_peaks(model, phi_b)
    return ShapeData(
        velocity_L1=peaks_l[0], velocity_B2=peaks_b[0], stress_L1_Pa_m=peaks_l[1],
        stress_B2_Pa_m=peaks_b[1], thickness_m=model.stator.thickness_m,
        volume_m3=plate_volume_m3(model), material=material.name, limits=material.limits,
        source=f"FE mode shapes (plane stress, order {order}): the largest nodal "
               "displacement and the largest principal stress at the quadrature points",
        combined_stress=combined_stress_factors(model, phi_l, phi_b),
    )


def _reduce_mode(model, stator, P: np.ndarray, drive: np.ndarray, shape: np.ndarray, row: int,
                 target: float, f_hz: float, name: str):
    """One mode reduced to ``(mass, stiffness, force, values, phi)``: its modal mass (kg),
    stiffness (N/m), force factor (N/V), probe values and the scaled shape ``phi``,
    ``shape`` scaled so that probe ``row`` of ``P``
    reads ``target`` (the beam shape's value), the probes being ``u_x`` at the preload point and the
    tip, then ``u_y`` at both; ``drive`` is the driven electrodes' coupling vector.

    Row 2 is L1's ``u_y`` at the preload point, row 1 B2's ``u_x`` at the tip; each must be
    at least :data:`NODE_SHARE` of the mode's largest vertex displacement in that direction
    (an FE node of the mode is not exactly 0: 1.3e-8 of it at the plate's centre would give
    M_l = 1.5e13 kg)."""
    vals = P @ shape
    comp = 1 if row == 2 else 0
    peak = float(np.max(np.abs(shape[model.basis.nodal_dofs[comp]])))
    share = abs(float(vals[row])) / peak if peak > 0.0 else 0.0
    if not share >= NODE_SHARE:
        point, where, xy = (("preload", stator.preload_point_m, "y") if row == 2
                            else ("tip", stator.tip_point_m, "x"))
        key = f"[points] {point}_mm"
        raise NodalPointError(
            f"the {name} mode's {xy} displacement at the {point} point "
            f"({where[0] * 1e3:g}, {where[1] * 1e3:g}) mm is {share:.2g} of its largest "
            f"(a node of the mode; at least {NODE_SHARE:g} needed), where the reduction "
            f"normalises it; the {point} point ({key} in a stator file) "
            f"must lie where {name} moves in {xy}, e.g. on the plate's end",
            name, point, share, key)
    phi = shape * (target / vals[row])
    vals = P @ phi
    mass = float(phi @ (model.M @ phi))
    stiff = (2.0 * math.pi * f_hz) ** 2 * mass
    force = float(phi @ drive)
    return mass, stiff, force, vals, phi


def _mesh_text(stator, refine: int) -> str:
    """How the reduced set's plate was meshed, for its source line."""
    if hasattr(stator, "element_size_m"):  # fem.meshing.parametric.ParametricStator
        return f"gmsh mesh of element size {stator.element_size_m * 1e3:g} mm"
    if getattr(stator, "mesh", None) is not None:  # fem.meshing.meshed_stator: the file's mesh
        return "the stator file's mesh"
    return f"refine {refine}"


def design_base(design, base: MotorParams | None = None) -> MotorParams:
    """``base`` (default Table 2) with a stator file's ``[contact]``, ``[slider]`` and
    ``[friction]`` constants (:attr:`fem.stator_file.StatorDesign.motor`) put in.

    Raises
    ------
    ValueError
        If the combination is not a valid parameter set (e.g. ``[friction] mu_d`` above
        Table 2's ``mu_s``); the message names the file's ``[table] key``.
    """
    from dataclasses import replace

    base = table2() if base is None else base
    if not design.motor:
        return base
    keys = design.motor_keys()
    given = ", ".join(f"{keys[k]} = {v:g}" for k, v in design.motor.items())
    try:
        return replace(base, **design.motor, source=f"{base.source}, with {given} from "
                       f"{design.path or design.name}")
    except ParameterError as exc:  # the file's keys; what it did not set is the base set's
        label = keys.get(exc.name, f"the base set's {exc.name}")
        reason = exc.said(label, keys.get(exc.bound_by, exc.bound_by))
        raise DesignFileError(design.path or design.name, "", reason) from None


def design_damping(design, base: MotorParams | None = None) -> tuple[float, float] | None:
    """The ``(zeta_L1, zeta_B2)`` a stator file asks for: its ``[damping]`` ratios,
    Table 2's for ``source = "table2"``, or None (no ``[damping]``: the caller's default;
    ``source = "paper_amplitudes"``: fitted by :func:`fem_params_from_file`)."""
    if design.damping_ratios is not None:
        return design.damping_ratios
    if design.damping_identify_Hz is not None:  # fitted once the set is built
        return None
    if design.damping_origin:  # source = "table2", explicitly
        t2 = table2()
        return (t2.zeta_L1, t2.zeta_B2)
    return None


def fem_params_from_file(path, **kwargs) -> MotorParams:
    """:func:`fem_params` of the stator described by a TOML file (``fem.stator_file``).

    The file's motor tables are applied: ``[damping]`` sets the damping ratios (unless
    ``damping_ratios`` is passed here) or, with ``source = "paper_amplitudes"``, fits the
    dampings to Table 2's free tip amplitudes (:func:`rom.damping.identify_damping`);
    ``[contact]``, ``[slider]`` and ``[friction]`` replace those constants of ``base``
    (default Table 2; see :func:`design_base`).

    Parameters
    ----------
    path : str or Path
        Stator file; its geometry, drive electrodes, material, points, mesh and motor
        tables are used.
    **kwargs
        Further :func:`fem_params` options (``mesh``, ``base``, ``damping_ratios``;
        ``material`` overrides the file's). ``mesh.refine`` is ignored when the file gives
        a mesh.

    Returns
    -------
    MotorParams
        Its ``source`` names the file and where the damping came from.

    Raises
    ------
    ValueError
        For a bad file or motor constants that make no valid set (the message names the
        file's ``[table] key``).
    """
    from fem.stator_file import load_stator

    if "stator" in kwargs:
        raise ValueError("fem_params_from_file takes the stator from the file; drop 'stator'")
    return fem_params_from_design(load_stator(path), **kwargs)


def fem_params_from_design(design, stator=None, **kwargs) -> MotorParams:
    """:func:`fem_params` of a loaded stator file (:class:`fem.stator_file.StatorDesign`),
    with its motor tables applied as :func:`fem_params_from_file` describes.

    Parameters
    ----------
    design : fem.stator_file.StatorDesign
    stator : fem.geometry.PlateStator, optional
        The plate to reduce instead of ``design.stator``: the file's plate with other
        dimensions (a design-space study varies them, ``studies.explore``), its features,
        material and motor tables kept.
    **kwargs
        As :func:`fem_params_from_file`.
    """
    from dataclasses import replace

    path = design.path or design.name
    kwargs.setdefault("material", design.material)
    kwargs["base"] = design_base(design, kwargs.get("base"))
    ratios = design_damping(design)
    if "damping_ratios" in kwargs:
        damping = "damping ratios given by the caller"
    elif ratios is not None:
        kwargs["damping_ratios"] = ratios
        damping = f"damping from {design.damping_origin}"
    else:
        damping = "no [damping]: the base set's damping ratios"
    params = fem_params(stator=design.stator if stator is None else stator, **kwargs)
    if design.damping_identify_Hz is not None and "damping_ratios" not in kwargs:
        from rom.damping import identify_damping

        try:
            fitted = identify_damping(params, design.damping_identify_Hz).params
        except ValueError as exc:
            if isinstance(exc, UnreachableAmplitudeError):  # the remedy in the file's terms
                exc = UnreachableAmplitudeError(
                    exc.mode, exc.target_m_per_V, exc.frequency_Hz, exc.undamped_m_per_V,
                    exc.natural_Hz, "set the file's [damping] frequency_Hz nearer to it")
            raise DesignFileError(path, '[damping] source = "paper_amplitudes"', str(exc)) \
                from None
        # the set's description names the fitted ratios it carries, not the ones the
        # reduction started from (Table 2's)
        before = f"damping ratios ({params.zeta_L1:.4g}, {params.zeta_B2:.4g})"
        after = f"damping ratios ({fitted.zeta_L1:.4g}, {fitted.zeta_B2:.4g}), fitted"
        params = replace(fitted, source=fitted.source.replace(before, after))
        damping = f"damping from {design.damping_origin}"
    if design.force_factor_scales is not None:
        s_l, s_b = design.force_factor_scales
        params = replace(params, A_l=params.A_l * s_l, A_b=params.A_b * s_b,
                         source=f"{params.source}; force factors scaled by [force_factor] "
                         f"({s_l:g}, {s_b:g})")
    mesh = f", mesh {design.mesh_path}" if design.mesh_path is not None else ""
    return replace(params, source=f"stator file {path} ({design.name}{mesh}; {damping}): "
                   f"{params.source}")
