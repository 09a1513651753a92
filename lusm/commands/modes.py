"""``lusm modes``: L1/B2 short- and open-circuit frequencies and k_eff of the FE plate.

Parse, call :func:`fem.modes.plate_modes` (or :func:`fem.solid3d.model.solid_modes`), print. No
physics here; ``fem`` is imported when the command runs so that building the ``lusm`` parser
never imports scikit-fem.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lusm import limits
from lusm.errors import short_reason
from lusm.fe_errors import fe_failure, is_fe_failure
from lusm.options import add_output_options, add_plate_options, integer, print_json, real

if TYPE_CHECKING:
    from fem.mesh_settings import MeshSettings

HELP = "FE natural frequencies (short/open circuit) and k_eff of L1 and B2"
DESCRIPTION = """\
Plane-stress piezoelectric FE model of the stator plate: L1 and B2 frequencies with all
electrodes grounded (short) and floating (open), and k_eff.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm modes``."""
    add_plate_options(p)
    add_fe_options(p, three_d=True)
    p.add_argument(
        "--model", choices=("2d", "3d"), default="2d",
        help="2d: plane-stress plate (default); 3d: piezoelastic brick reference (fem.solid3d)",
    )
    p.add_argument("--layers", type=integer("--layers", 1, limits.MAX_LAYERS, work=True),
                   default=None, help="3d: element layers through h (default 3)")
    p.add_argument("--edge-grading", type=integer("--edge-grading", 0, limits.MAX_EDGE_GRADING),
                   default=None, metavar="LEVELS",
                   help="3d: grade the mesh LEVELS times towards the electrode edges, where "
                   "the potential is singular (3 converges B2's k_eff to about "
                   "1 %%, docs/fem3d.md section 1); the generated plate is then solved "
                   "on a quarter by its mirror symmetry (same results, faster)")
    p.add_argument("--quick", action="store_true",
                   help="3d: one solve on the uniform mesh (refine 3, layers 3, no grading) "
                   "instead of the default pair of graded meshes: several times faster, "
                   "B2's k_eff some %% low and no error estimate. Without --quick, --refine, "
                   "--layers or --edge-grading the 3D model solves two graded meshes and "
                   "prints the finer one's numbers, each with its estimated discretisation "
                   "error (docs/fem3d.md section 1.1)")
    add_output_options(p, folder=None)
    p.add_argument(
        "--export", metavar="FILE", default=None,
        help="write the mesh with the mode shapes as point data (meshio format by extension, "
        "e.g. modes.vtu for ParaView); an existing file is not overwritten unless --force",
    )
    p.add_argument("--force", action="store_true",
                   help="write --export over an existing file (the old one is kept as .bak-N)")
    p.add_argument("--band", nargs="?", const="auto", default=None, type=band_option,
                   metavar="F1:F2",
                   help="also list every mode of the model in the band F1:F2 (kHz, or with a "
                   "unit: 40:56, 40kHz:56kHz, 4e4Hz:5.6e4Hz), named by its shape, with "
                   "k_eff; without F1:F2 the L1/B2 pair +- 20 %%")
    p.add_argument("--risk-pct", type=real("--risk-pct", "%", 0.0, 100.0, lo_open=True),
                   default=None, metavar="PCT",
                   help="with --band: flag every other mode within PCT %% of L1's or B2's "
                   "frequency as a risk to the drive (default 5)")


BAND_UNITS = {"hz": 1.0, "khz": 1e3, "mhz": 1e6}
"""The units ``--band`` takes, lower case (a number without one is in kHz)."""


def band_option(text: str) -> str | tuple[float, float]:
    """The ``--band`` value: ``'auto'`` or ``(f1_Hz, f2_Hz)`` from ``F1:F2`` (kHz unless a
    unit follows a number), each in :data:`lusm.limits.FREQUENCY_HZ`, ``f1 < f2``."""
    from fem.units import to_si

    if text == "auto":
        return text
    lo, hi = limits.FREQUENCY_HZ
    rule = (f"--band must be F1:F2 with F1 < F2 in [{lo:g}, {hi:g}] Hz, in kHz or with a "
            f"unit (Hz, kHz, MHz), e.g. 40:56 or 40kHz:56kHz, got {text!r}")
    parts = text.split(":")
    values = []
    for part in parts if len(parts) == 2 else ():
        t = part.strip().lower().replace(" ", "")
        unit = next((u for u in sorted(BAND_UNITS, key=len, reverse=True) if t.endswith(u)),
                    None)
        try:
            values.append(to_si(t[: len(t) - len(unit)] if unit else t,
                                BAND_UNITS[unit] if unit else 1e3))
        except ValueError:
            break
    if len(values) != 2 or not lo <= values[0] < values[1] <= hi:
        raise argparse.ArgumentTypeError(rule)
    return values[0], values[1]


def _split(res) -> float:
    """``(f_B2 - f_L1) / f_L1`` in short circuit (-): what ``lusm tune`` drives to zero."""
    return res.B2.f_short_Hz / res.L1.f_short_Hz - 1.0


def add_fe_options(p: argparse.ArgumentParser, three_d: bool = False) -> None:
    """``--order`` and ``--refine`` (bounded, see :mod:`lusm.limits`); ``three_d``: the
    command also has ``--model 3d``, whose default refine the help names too."""
    p.add_argument("--order", type=int, choices=(1, 2), default=2,
                   help="element order (default 2; 1 locks in bending: B2 several %% high)")
    try:  # scaled as the 2D bound is, so that the help says the bound that runs
        top_3d = limits.work_bound(limits.MAX_REFINE_3D)
    except ValueError:  # a bad LUSM_MAX_WORK: refused on its own before any command runs
        top_3d = limits.MAX_REFINE_3D
    note = f" (at most {top_3d} with --model 3d)" if three_d else ""
    p.add_argument("--refine", type=integer("--refine", 1, limits.MAX_REFINE_2D, work=True,
                                            note=note),
                   default=None, help="elements per plate width (default 4"
                   + (", 3 with --model 3d)" if three_d else ")"))


def warn_linear_elements(args: argparse.Namespace) -> None:
    """``--order 1``: linear elements lock in bending, so B2 comes out too stiff by
    several per cent on the default mesh (docs/fem.md §6: 3.3 % on the paper's plate in 2D,
    more in 3D, where L1 and B2 can swap), and a tuned plate with it; the command said
    nothing (``--help`` only said "element order")."""
    if getattr(args, "order", None) == 1:
        from lusm.messages import warn

        warn("--order 1: linear elements lock in bending, so B2 comes out several per cent "
             "too stiff on the default mesh (3.3 % on the paper's plate, docs/fem.md §6) and "
             "tuned dimensions move with it; use --order 2 (the default) for a design")


def start_band_command(args: argparse.Namespace, out_option: str):
    """The start the FE band commands (``admittance``, ``harmonic``) share, before any work:
    the ``--order 1`` warning, the output folder of ``out_option`` checked
    (:func:`lusm.options.output_folder`; returned, None without one) and ``--f-min`` below
    ``--f-max``."""
    from lusm.options import check_band_order, output_folder

    warn_linear_elements(args)
    out = output_folder(args, out_option)
    check_band_order(args.f_min, args.f_max)
    return out


def check_refine_3d(refine: int | None) -> None:
    """The 3D model's tighter bound on ``--refine``."""
    from lusm.errors import LusmError

    top = limits.work_bound(limits.MAX_REFINE_3D)
    if refine is not None and refine > top:
        raise LusmError(f"--refine with --model 3d must be an integer in [1, {top}], got "
                        f"{refine} ({limits.more_work_hint()})", "--refine")


def run(args: argparse.Namespace) -> None:
    """Run ``lusm modes`` with parsed ``args``."""
    from lusm.options import stator_from_args

    warn_linear_elements(args)
    choice = stator_from_args(args)
    export = _export_target(args.export, args.force) if args.export is not None else None
    mesh = _mesh_settings(args, choice.stator, export is None)
    coarse_gap = _warn_coarse_gap(args, choice, mesh) if args.model == "3d" else None
    res, validity = _solve(args, choice, mesh, coarse_gap)
    estimate = None
    if mesh.coarse is not None:  # the default 3D meshes: the finer one's modes, estimated
        estimate, res = res, res.fine
    if export is not None:
        _export(args, choice, mesh, res, export)
    mounts = _mount_amplitudes(choice, choice.material, args, mesh.fe, res)
    band = _band(args, choice, mesh, res)
    if validity is not None:
        from lusm.messages import warn

        warn(validity)  # "lusm modes: warning: ...", as every command's
    if args.json:
        _print_json(args, choice, mesh, res, mounts, export, band, estimate)
        return
    _print(args, choice, mesh, res, mounts, export, coarse_gap, estimate)
    if band is not None:
        print_band(band)


@dataclass(frozen=True)
class _Mesh:
    """The FE mesh of one ``lusm modes`` run: the settings the FE entry points take
    (``fe``, built once from ``--order``, ``--refine``, ``--layers``, ``--edge-grading``),
    whether they are the 3D model's (``solid``), whether the quarter-plate model gives the
    full model's results, and the coarse mesh of the error estimate (None: one mesh, no
    estimate)."""

    fe: MeshSettings
    solid: bool = False
    quarter: bool = False
    coarse: object = None

    @property
    def refine(self) -> int:
        return self.fe.refine

    @property
    def layers(self) -> int | None:
        return self.fe.layers if self.solid else None

    @property
    def edge_grading(self) -> int:
        return self.fe.edge_grading


def _mesh_settings(args: argparse.Namespace, stator, quarter_allowed: bool) -> _Mesh:
    """The mesh of ``--model``, ``--refine``, ``--layers``, ``--edge-grading``, ``--quick``,
    bounded before any work (the bound blames the option the user typed)."""
    from fem.mesh_settings import MeshSettings
    from fem.meshing.mesh import DEFAULT_REFINE
    from lusm.errors import LusmError
    from lusm.options import check_fe_size

    if args.model != "3d":
        for option, given, why in (
                ("--layers", args.layers is not None, "the 2D model has no mesh through the "
                 "thickness"),
                ("--edge-grading", bool(args.edge_grading), "the 2D model has no mesh across "
                 "the electrode edges' singularity"),
                ("--quick", args.quick, "it chooses between the 3D model's meshes")):
            if given:
                raise LusmError(f"{option} applies to --model 3d only ({why})", option)
        refine = DEFAULT_REFINE if args.refine is None else args.refine
        check_fe_size(stator, refine)
        return _Mesh(MeshSettings(args.order, refine))
    from fem.solid3d.estimate import QUICK_MESH, default_meshes
    from fem.solid3d.symmetric import quarter_model_applies
    from lusm.messages import typed

    if args.quick and args.edge_grading:
        raise LusmError("--quick is the uniform mesh: leave out --edge-grading, or --quick "
                        "to grade the mesh", "--quick")
    check_refine_3d(args.refine)
    coarse = None
    if args.quick or any(v is not None for v in (args.refine, args.layers, args.edge_grading)):
        refine = QUICK_MESH.refine if args.refine is None else args.refine
        layers = QUICK_MESH.layers if args.layers is None else args.layers
        grading = args.edge_grading or 0
    else:  # the default: two graded meshes, the error estimate from their difference
        coarse, fine = default_meshes(stator)
        refine, layers, grading = fine.refine, fine.layers, fine.edge_grading
    # the quarter-plate model gives the full model's results at about a quarter of the
    # size; the export writes the full model's mesh
    quarter = quarter_allowed and quarter_model_applies(stator, grading)
    blamed = next((o for o in ("--edge-grading", "--layers", "--refine") if typed(o)),
                  "--edge-grading" if grading else "--refine")
    try:
        check_fe_size(stator, refine, layers, blamed, edge_grading=grading, quarter=quarter)
    except LusmError as exc:
        if coarse is None:
            raise
        # the default's fine mesh is above the bound: the uniform mesh may fit
        raise LusmError(f"{exc}; or --quick for one uniform mesh (no error estimate)",
                        exc.option) from None
    return _Mesh(MeshSettings(args.order, refine, layers, edge_grading=grading), True, quarter,
                 coarse)


def _warn_coarse_gap(args: argparse.Namespace, choice, mesh: _Mesh) -> str | None:
    """Warn where the 3D mesh's elements beside the electrode gap are much wider than it
    (ungraded generated plates, planform meshes whose layers are thick against a narrow
    gap); returns the remedy, or None."""
    from fem.solid3d.model import gap_element_ratio

    stator = choice.stator
    ratio = gap_element_ratio(stator, mesh.refine, mesh.layers, mesh.edge_grading)
    if ratio <= NARROW_GAP_RATIO:
        return None
    from fem.meshing.meshed_stator import planform_mesh
    from fem.solid3d.model import planform_gap_m, planform_gap_ratios
    from lusm.messages import warn

    pf = planform_mesh(stator)
    gap_mm = (stator.electrode_gap_m if pf is None else planform_gap_m(pf)) * 1e3
    coarse_gap = _coarse_gap_remedy(
        choice, mesh.edge_grading,
        None if pf is None else planform_gap_ratios(pf, stator.thickness_m, mesh.layers,
                                                    mesh.edge_grading))
    warn(f"--model 3d: the mesh's elements beside the {gap_mm:g} mm electrode gap "
         f"are {ratio:.0f} x wider than it: open-circuit B2 and its k_eff come out "
         f"too low (docs/fem3d.md); {coarse_gap}")
    return coarse_gap


def _solve(args: argparse.Namespace, choice, mesh: _Mesh, coarse_gap: str | None):
    """L1 and B2 of the chosen model (with the default 3D meshes an
    :class:`fem.solid3d.estimate.EstimatedSolidModes`, whose ``fine`` are the modes), and
    the 2D model's gap-validity message (or None); a solver failure said as bad input."""
    from fem.modes import ModePairingError, ModeSolverError, plate_modes

    stator, material = choice.stator, choice.material
    validity = None
    try:
        if mesh.coarse is not None:
            from fem.solid3d.estimate import MeshLevel, estimated_solid_modes

            fine = MeshLevel(mesh.refine, mesh.layers, mesh.edge_grading)
            res = estimated_solid_modes(stator, material, args.order, (mesh.coarse, fine),
                                        quarter=mesh.quarter)
        elif mesh.quarter:
            from fem.solid3d.symmetric import symmetric_solid_modes

            res = symmetric_solid_modes(stator, material, mesh.fe)
        elif args.model == "3d":
            from fem.solid3d.model import solid_modes

            res = solid_modes(stator, material, mesh.fe)
        else:
            import warnings

            from fem.model import GapValidityWarning, stator_gap_validity

            validity = stator_gap_validity(stator)
            with warnings.catch_warnings():  # reported once, after, on one line
                warnings.simplefilter("ignore", GapValidityWarning)
                res = plate_modes(stator, material, mesh.fe)
    except Exception as exc:
        if coarse_gap is not None and isinstance(exc, ModePairingError):
            # an open mode mixed with an out-of-plane one across an unresolved gap
            raise ValueError(f"{short_reason(exc)}; the 3D mesh does not resolve the "
                             f"electrode gap: {coarse_gap}") from exc
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, stator) from exc
        raise
    return res, validity


def _band(args: argparse.Namespace, choice, mesh: _Mesh, res):
    """``--band``: every mode of the model in the band (:func:`fem.band.band_modes`), the
    risks warned of before the results; None without ``--band``."""
    from lusm.errors import LusmError

    if args.band is None:
        if args.risk_pct is not None:
            raise LusmError("--risk-pct applies with --band only (the window around L1 and "
                            "B2 in which other modes of the band are flagged)", "--risk-pct")
        return None
    from fem.band import RISK_PCT, BandTooWideError, band_modes, default_band_Hz
    from lusm.fe_errors import fe_failures_as_input
    from lusm.messages import warn

    ops = {"L1": res.L1.f_short_Hz, "B2": res.B2.f_short_Hz}
    lo, hi = default_band_Hz(ops) if args.band == "auto" else args.band
    risk = RISK_PCT if args.risk_pct is None else args.risk_pct
    with fe_failures_as_input(choice.stator):
        try:
            band = band_modes(_band_model(args, choice, mesh), lo, hi, ops, risk)
        except BandTooWideError as exc:
            held = "more modes" if exc.n_modes is None else f"{exc.n_modes} modes"
            raise LusmError(f"--band {lo:g}:{hi:g} Hz: the band holds {held}, above the "
                            f"limit of {exc.limit} one band solve computes; narrow it "
                            f"({limits.more_work_hint()})", "--band") from None
    for m in band.risks:
        op = min(ops, key=lambda n: abs(m.f_short_Hz / ops[n] - 1.0))
        warn(f"--band: {m.name} ({m.family}) at {m.f_short_Hz:.0f} Hz lies "
             f"{m.f_short_Hz / ops[op] - 1.0:+.1%} from {op} ({ops[op]:.0f} Hz), within the "
             f"--risk-pct {risk:g} % window: the drive may excite it")
    return band


def _band_model(args: argparse.Namespace, choice, mesh: _Mesh):
    """The assembled model whose band ``--band`` lists: the 2D plate, or the full 3D solid
    (the quarter-plate model holds L1's and B2's symmetry classes only)."""
    stator, material = choice.stator, choice.material
    if args.model != "3d":
        from fem.model import plate_model

        return plate_model(stator, material, mesh.fe)
    from fem.solid3d.model import solid_model

    if mesh.quarter:
        from lusm.options import check_fe_size

        check_fe_size(stator, mesh.refine, mesh.layers, "--band",
                      edge_grading=mesh.edge_grading)
    return solid_model(stator, material, mesh.fe)


def print_band(band) -> None:
    """The table of every mode in the band (``lusm modes --band``, ``lusm report``)."""
    ops = ", ".join(f"{n} {f:.1f} Hz" for n, f in band.operating_Hz)
    counted = ("" if band.counted is None else
               f"; inertia count of K - (2 pi f)^2 M at the band's ends: {band.counted}")
    print(f"every mode of the {band.model.upper()} model in {band.f_min_Hz:.0f}-"
          f"{band.f_max_Hz:.0f} Hz: {len(band.modes)}{counted} ({band.wall_time_s:.1f} s)")
    print(f"{'mode':<7}{'family':<22}{'f_short (Hz)':>13}{'f_open (Hz)':>13}{'k_eff':>8}"
          f"{'from pair':>11}  drive")
    for m in band.modes:
        f_open = f"{m.f_open_Hz:>13.1f}" if math.isfinite(m.f_open_Hz) else f"{'-':>13}"
        k_eff = f"{m.k_eff:>8.4f}" if math.isfinite(m.k_eff) else f"{'-':>8}"
        flag = "operating" if m.operating else "RISK" if m.risk else ""
        print(f"{m.name:<7}{m.family:<22}{m.f_short_Hz:>13.1f}{f_open}{k_eff}"
              f"{m.offset:>+11.1%}  {flag}".rstrip())
    print(f"names from the shape: Ln longitudinal, Bn in-plane bending, OBn out-of-plane "
          f"bending, Tn torsion (n from the nodes along the length); from pair: to the "
          f"nearer of {ops}; RISK: within {band.risk_pct:g} % of it")


def _export(args: argparse.Namespace, choice, mesh: _Mesh, res, export) -> None:
    """Write the mode shapes on the full model's mesh to ``export``."""
    stator, material = choice.stator, choice.material
    if args.model == "3d":
        from fem.export import export_solid_modes
        from fem.solid3d.model import build_solid_model

        model = build_solid_model(stator, material, mesh.fe)
        _write_export(export, model, res, args.force, export_solid_modes)
    else:
        from fem.export import export_modes
        from fem.model import plate_model

        _write_export(export, plate_model(stator, material, mesh.fe), res, args.force,
                      export_modes)


def _print_json(args: argparse.Namespace, choice, mesh: _Mesh, res, mounts, export,
                band=None, estimate=None) -> None:
    """The modes, the mesh, the material and the plate as JSON (and ``band_modes``; with
    the default 3D meshes ``error_estimate``)."""
    from fem.material import plane_stress
    from fem.model import stator_gap_m

    stator, material, refine, quarter = choice.stator, choice.material, mesh.refine, mesh.quarter
    L_mm, W_mm, H_mm = (v * 1e3 for v in (stator.length_m, stator.width_m, stator.thickness_m))

    mat = material.to_dict()
    mat["plane_stress"] = plane_stress(material).to_dict()
    out = {
        "L1": res.L1.to_dict(),
        "B2": res.B2.to_dict(),
        "dofs": res.dofs,
        "wall_time_s": res.wall_time_s,
        "order": args.order,
        # a stator file's own mesh (or gmsh's) is not refined: the 2D model solves it,
        # the 3D model extrudes it
        "refine": None if choice.meshed or choice.parametric else refine,
        "material": mat,
        "geometry": args.geometry,
        "model": args.model,
        "length_mm": L_mm, "width_mm": W_mm, "thickness_mm": H_mm,
        "gap_mm": float(f"{stator_gap_m(stator) * 1e3:.12g}"),  # mesh roundoff off
    }
    # where the reduction (lusm params --source fem) normalises L1 and B2; a stator file
    # may move them, so the points used are said
    # + 0.0: a point on a mirrored mesh's centre line read -0 mm
    out["tip_mm"] = [float(f"{c * 1e3:.12g}") + 0.0 for c in stator.tip_point_m]
    out["preload_mm"] = [float(f"{c * 1e3:.12g}") + 0.0 for c in stator.preload_point_m]
    out["split_rel"] = _split(res)
    out["mac"] = {m.name: m.mac for m in (res.L1, res.B2)}
    out["symmetry"] = {m.name: m.symmetry for m in (res.L1, res.B2)}
    if choice.parametric:
        out.update(stator.features_mm())
    if mounts:
        out["mounts"] = mounts
    if args.model == "3d":
        out["layers"], out["element"] = res.layers, res.element
        out["edge_grading"] = mesh.edge_grading
        out["quarter_model"] = quarter
    if estimate is not None:
        from fem.solid3d.estimate import SAFETY

        c = estimate.meshes[0]
        out["error_estimate"] = {
            **estimate.errors(),
            "coarse_mesh": {"refine": None if choice.meshed or choice.parametric
                            else c.refine, "layers": c.layers, "edge_grading": c.edge_grading},
            "method": "SAFETY x the change from the coarse mesh (docs/fem3d.md section 1.1)",
            "safety": SAFETY,
            "wall_time_s": estimate.wall_time_s,
        }
    if export is not None:
        out["export"] = str(export)
    if band is not None:
        out["band_modes"] = band.to_dict()
    print_json(out)


def _print(args: argparse.Namespace, choice, mesh: _Mesh, res, mounts, export,
           coarse_gap: str | None, estimate=None) -> None:
    """The modes as a table (with the default 3D meshes each number with its estimated
    error), with the plate, the mesh and the mounts."""
    from validation.summaries import plate_text

    stator, material, refine, quarter = choice.stator, choice.material, mesh.refine, mesh.quarter

    if choice.meshed:
        mesh_text = "mesh from the stator file"
    elif choice.parametric:
        mesh_text = f"gmsh mesh, element size {stator.element_size_m * 1e3:g} mm"
    else:
        mesh_text = f"refine {refine}"
    print(
        f"{plate_text(stator)}, material {material.name}, order {args.order}, {mesh_text}"
        + (f", 3D layers {res.layers} ({res.element})" if hasattr(res, "layers") else "")
        + (f", edge grading {mesh.edge_grading}" if mesh.edge_grading else "")
        + (" (quarter-plate model, mirror symmetry)" if quarter else "")
    )
    if choice.design is not None:
        what = "bounding box above" if choice.meshed else "dimensions above"
        tip, pre = ((f"{x * 1e3 + 0.0:g}, {y * 1e3 + 0.0:g}") for x, y in (
            stator.tip_point_m, stator.preload_point_m))
        print(f"stator file {args.geometry}: {choice.design.name} ({what}); tip ({tip}) mm, "
              f"preload ({pre}) mm")
    if estimate is None:
        print(f"{'mode':<5}{'f_short (Hz)':>14}{'f_open (Hz)':>14}{'k_eff':>9}{'MAC':>7}"
              f"{'symmetry':>10}")
        for m in (res.L1, res.B2):
            print(f"{m.name:<5}{m.f_short_Hz:>14.1f}{m.f_open_Hz:>14.1f}{m.k_eff:>9.4f}"
                  f"{m.mac:>7.3f}{m.symmetry:>10.3f}")
    else:
        _print_estimated(res, estimate, choice.meshed or choice.parametric)
    # in Hz too: a tuned stator's split read "+0.000%" (where the report said +1.3e-04 %)
    print(f"L1-B2 split (f_B2 - f_L1) / f_L1, short circuit: {_split(res):+.3%} "
          f"({res.B2.f_short_Hz - res.L1.f_short_Hz:+.1f} Hz) "
          "(MAC: correlation with the Eq. 3 shape; symmetry: energy share in the mode's "
          "mirror class; both 1 for a clean identification)")
    if estimate is None:
        print(f"dofs {res.dofs}, wall time {res.wall_time_s:.3f} s")
    else:
        print(f"dofs {res.dofs} (fine mesh), wall time {estimate.wall_time_s:.3f} s (both "
              f"meshes)")
    if args.model == "3d" and not mesh.edge_grading and coarse_gap is None:
        # the default 3D mesh is the cheap frequency check: its k_eff rests on a split
        # that the singular potential at the electrode edges controls (docs/fem3d.md §1)
        print("k_eff on an ungraded 3D mesh is low (B2's by about 5 % on the paper's plate, "
              "docs/fem3d.md section 1); the default graded meshes (no --quick, --refine, "
              "--layers) or --edge-grading 1 or more when the coupling matters"
              + _graded_work_clause(stator, refine, res.layers, export is None))
    for i, m in enumerate(mounts, start=1):
        x, y = m["point_mm"]
        print(f"mount {i} at ({x:g}, {y:g}) mm: amplitude / largest L1 {m['L1']:.3g}, "
              f"B2 {m['B2']:.3g} (0 at a node)")
    if export is not None:
        print(f"wrote {export}")



def _print_estimated(res, estimate, planform: bool) -> None:
    """The modes of the default 3D meshes, each number with its estimated error (the mesh
    named without its refine on a stator file's ``planform``)."""
    from fem.solid3d.estimate import SAFETY

    print(f"{'mode':<5}{'f_short (Hz)':>20}{'f_open (Hz)':>20}{'k_eff':>18}{'MAC':>7}"
          f"{'symmetry':>10}")
    for m in (res.L1, res.B2):
        e = estimate.errors()[m.name]
        print(f"{m.name:<5}{m.f_short_Hz:>11.1f} +- {e['f_short_Hz']:<5.1f}"
              f"{m.f_open_Hz:>11.1f} +- {e['f_open_Hz']:<5.1f}"
              f"{m.k_eff:>9.4f} +- {e['k_eff']:<6.4f}{m.mac:>7.3f}{m.symmetry:>10.3f}")
    print(f"+-: estimated discretisation error of each number, {SAFETY:g} x its change from "
          f"the coarse mesh ({estimate.meshes[0].text(planform)}); docs/fem3d.md section 1.1. "
          f"--quick: one uniform mesh, faster, no estimate")


def _mount_amplitudes(choice, material, args, fe: MeshSettings, res) -> list[dict]:
    """``[points] mounts_mm`` of the stator file: L1 and B2 amplitude there (2D model)."""
    design = choice.design
    if design is None or not design.mounts_m or args.model == "3d":
        return []
    import numpy as np

    from fem.model import plate_model
    from fem.modes import amplitude_ratio

    model = plate_model(choice.stator, material, fe)
    pts = np.array(design.mounts_m).T
    ratios = {name: amplitude_ratio(model, getattr(res, name).shape, pts)
              for name in ("L1", "B2")}
    return [{"point_mm": [x * 1e3, y * 1e3], "L1": float(ratios["L1"][i]),
             "B2": float(ratios["B2"][i])} for i, (x, y) in enumerate(design.mounts_m)]


def _export_target(text: str, force: bool):
    """The ``--export`` file, checked before any work (a file, in an existing folder)."""
    from lusm.errors import LusmError
    from lusm.options import file_target

    # refused before the FE solve (30 s of a 3D model), not after
    path = file_target(text, "--export", force, "modes.vtu")
    side = path.with_suffix(".h5")  # meshio's XDMF writer puts the arrays beside it
    if path.suffix.lower() == ".xdmf" and (side.exists() or side.is_symlink()) and not force:
        # refused before the FE solve, not after
        raise LusmError(f"--export {path}: its side file {side} already exists; choose a new "
                        "name or pass --force", "--export")
    suffix = path.suffix.lower()
    if suffix not in EXPORT_SUFFIXES:
        import meshio

        what = ("cannot carry the mode shapes (quadrilateral or brick cells with vectors at "
                "the points)" if suffix in meshio.extension_to_filetypes
                else "is not a mesh format")
        said = f"{suffix} {what}" if suffix else "has no format suffix"
        raise LusmError(f"--export {path}: {said}; use one of {', '.join(EXPORT_SUFFIXES)}",
                        "--export")
    return path


def _relink_kept_xdmf(xdmf, renamed: dict[str, str]) -> None:
    """Point a kept-aside .xdmf at its own kept-aside HDF5 file: ``renamed`` maps the side
    files' names to their backups'. Without it ``modes.xdmf.bak-1`` would read the new run's
    ``modes.h5`` (the old export unreadable although both files are kept)."""
    if xdmf is None:
        return
    text = xdmf.read_text(encoding="utf-8")
    for old, new in renamed.items():
        if old.lower().endswith(".h5"):
            text = text.replace(f"{old}:", f"{new}:")
    xdmf.write_text(text, encoding="utf-8")


EXPORT_SUFFIXES = (".vtu", ".vtk", ".xdmf", ".msh")
"""Formats ``--export`` writes: those that carry the quads (bricks) and the shapes as point
vectors, round-tripped by the tests. meshio also writes .stl (an empty file: triangles only)
and .ply (the vectors dropped), which said "wrote" and exited 0."""

NARROW_GAP_RATIO = 10.0
"""``lusm modes --model 3d`` warns when the elements beside the electrode gap (in-plane
neighbours and the top layer) are more than this many times wider than the gap
(:func:`fem.solid3d.model.gap_element_ratio`; 4.9 on the paper's plate, whose default mesh is
documented in docs/fem3d.md)."""


def _graded_work_clause(stator, refine, layers, quarter_allowed: bool) -> str:
    """Where ``--edge-grading 1`` needs more bricks than the bound, what it takes, so that the
    hint runs as given (the tip examples need 2 140 bricks against 2 000). Counted on the
    model the graded run would use (the quarter plate where it applies, as :func:`run`
    decides)."""
    from fem.cell_count import fe_cell_count
    from fem.solid3d.symmetric import quarter_model_applies
    from lusm import limits

    quarter = quarter_allowed and quarter_model_applies(stator, 1)
    try:
        bricks = fe_cell_count(stator, refine, layers, edge_grading=1, quarter=quarter)
    except ValueError:
        return ""
    top = limits.work_bound(limits.MAX_FE_CELLS_3D)
    if bricks <= top:
        return ""
    return (f" (here with {limits.WORK_ENV}={math.ceil(bricks / limits.MAX_FE_CELLS_3D)}: "
            f"the graded mesh needs {bricks} bricks, above the limit {top})")


def _coarse_gap_remedy(choice, edge_grading: int,
                       planform_ratios: tuple[float, float] | None) -> str:
    """What refines the 3D mesh at the electrode gap: more ``--edge-grading`` levels; for a
    planform mesh (``planform_ratios``, :func:`fem.solid3d.model.planform_gap_ratios`) they grade
    only its layers, and its in-plane elements are the file's to refine."""
    more = (f"raise --edge-grading above {edge_grading}" if edge_grading
            else "add --edge-grading 1 or more")
    if planform_ratios is None:
        return more
    in_plane, layer = planform_ratios
    fixes = []
    if layer > NARROW_GAP_RATIO:
        fixes.append(f"{more} (it grades the layers)")
    if in_plane > NARROW_GAP_RATIO:
        fixes.append("refine the stator file's [mesh] size_mm" if choice.parametric
                     else "refine the mesh file at the gap")
    return " and ".join(fixes)


def _written_whole(writer, staged: str, model, res) -> None:
    """``writer(staged, model, res)``, and the file read back: raise ``OSError`` where it
    could not be written whole.

    meshio's XDMF writer leaves its HDF5 file to h5py's finalizers, whose write errors (a
    full disk, a file-size limit) Python only prints, as "Exception ignored in" tracebacks:
    the command said "wrote m.xdmf", exit 0, beside a truncated ``m.h5`` that meshio cannot
    read. Those errors are collected here instead, and every format is read back."""
    import gc
    import io
    import os
    import sys

    import meshio

    lost: list[BaseException] = []
    hook, err = sys.unraisablehook, sys.stderr
    sys.unraisablehook = lambda u: lost.append(u.exc_value)
    sys.stderr = said = io.StringIO()  # Cython prints a finalizer's traceback itself
    try:
        writer(staged, model, res)
        gc.collect()  # the finalizers run here, while the hook listens
    finally:
        sys.unraisablehook, sys.stderr = hook, err
    if lost:
        code = getattr(lost[0], "errno", None)
        reason = os.strerror(code) if code else str(lost[0]).splitlines()[0]
        raise OSError(f"cannot write {staged} whole ({reason})")
    if said.getvalue():  # not a failure: what the writer said stays said
        print(said.getvalue(), end="", file=sys.stderr)
    try:
        meshio.read(staged)
    except Exception as exc:  # any reader failure means the file is not whole
        raise OSError(f"{staged} does not read back ({type(exc).__name__}: "
                      f"{str(exc).splitlines()[0] if str(exc) else ''})") from None


def _write_export(path, model, res, force: bool, writer) -> None:
    """Write the export with ``writer(path, model, res)`` (and any side file, e.g. the HDF5
    of an .xdmf) in a staging folder beside the target under its final name; move the files
    in only when all are written."""
    import os

    from lusm.errors import LusmError
    from lusm.interrupts import checkpoint
    from lusm.output_set import keep_aside, staging

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise LusmError(f"--export {path}: cannot write into {path.parent} "
                        f"({exc.strerror or exc})", "--export") from None
    with staging(path.parent, path.name, "--export", path) as stage:
        staged = os.path.join(stage, path.name)
        try:
            _written_whole(writer, staged, model, res)
        except (ValueError, OSError) as exc:  # name the user's file, not the staging one
            raise LusmError(f"--export: {str(exc).replace(staged, str(path))}",
                            "--export") from None
        names = sorted(os.listdir(stage))
        taken = [n for n in names if (path.parent / n).exists() and n != path.name]
        if taken and not force:
            raise LusmError(f"--export {path}: its side file {path.parent / taken[0]} already "
                            "exists; choose a new name or pass --force", "--export")
        checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
        kept = {}
        for n in names:
            dst = path.parent / n
            if dst.exists() or dst.is_symlink():  # --force: the old file is kept, not lost
                kept[n] = keep_aside(dst, "--force")
            os.replace(os.path.join(stage, n), dst)
        if path.suffix.lower() == ".xdmf":
            _relink_kept_xdmf(kept.get(path.name), {n: b.name for n, b in kept.items()})
