"""``lusm modes``: L1/B2 short- and open-circuit frequencies and k_eff of the FE plate.

Parse, call :func:`fem.modes.plate_modes`, print. No physics here; ``fem`` is imported when
the command runs so that building the ``lusm`` parser never imports scikit-fem.
"""

from __future__ import annotations

import argparse
import json


def register(subparsers) -> None:
    """Add the ``modes`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "modes",
        help="FE natural frequencies (short/open circuit) and k_eff of L1 and B2",
        description="Plane-stress piezoelectric FE model of the stator plate: L1 and B2 "
        "frequencies with all electrodes grounded (short) and floating (open), and k_eff.",
    )
    # plate options default to None so that mixing them with --geometry can be refused
    p.add_argument("--length-mm", type=float, default=None, help="plate length l (mm), 30")
    p.add_argument("--width-mm", type=float, default=None, help="plate width b_s (mm), 7.5")
    p.add_argument("--thickness-mm", type=float, default=None,
                   help="plate thickness h_s (mm), 3")
    p.add_argument("--gap-mm", type=float, default=None, help="electrode gap (mm), 0.5")
    p.add_argument("--material", choices=("pzt8", "paper"), default=None, help="pzt8")
    p.add_argument("--order", type=int, choices=(1, 2), default=2, help="element order")
    p.add_argument("--refine", type=int, default=None, help="elements per plate width")
    p.add_argument(
        "--model", choices=("2d", "3d"), default="2d",
        help="2d: plane-stress plate (default); 3d: piezoelastic brick reference (fem.solid3d)",
    )
    p.add_argument("--layers", type=int, default=None, help="3d: element layers through h")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument(
        "--geometry", metavar="STATOR.toml", default=None,
        help="stator file (fem.stator_file); its dimensions, electrodes, material and mesh "
        "replace --length-mm/--width-mm/--thickness-mm/--gap-mm/--material",
    )
    p.add_argument(
        "--export", metavar="FILE", default=None,
        help="write the mesh with the mode shapes as point data (meshio format by extension, "
        "e.g. modes.vtu for ParaView)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Run ``lusm modes`` with parsed ``args``."""
    from fem.geometry import PlateStator
    from fem.material import get_material, plane_stress
    from fem.modes import DEFAULT_REFINE, ModeSolverError, plate_modes

    plate_options = {"--length-mm": args.length_mm, "--width-mm": args.width_mm,
                     "--thickness-mm": args.thickness_mm, "--gap-mm": args.gap_mm,
                     "--material": args.material}
    if getattr(args, "geometry", None):
        from fem.stator_file import load_stator

        given = [name for name, value in plate_options.items() if value is not None]
        if given:
            raise ValueError(f"{', '.join(given)} cannot be combined with --geometry: the "
                             "stator file sets the plate, electrodes and material")
        design = load_stator(args.geometry)
        stator, material = design.stator, design.material
        args.length_mm, args.width_mm = stator.length_m * 1e3, stator.width_m * 1e3
        args.thickness_mm = stator.thickness_m * 1e3
    else:
        defaults = {"--length-mm": 30.0, "--width-mm": 7.5, "--thickness-mm": 3.0,
                    "--gap-mm": 0.5, "--material": "pzt8"}
        opts = {k: defaults[k] if v is None else v for k, v in plate_options.items()}
        args.length_mm, args.width_mm = opts["--length-mm"], opts["--width-mm"]
        args.thickness_mm = opts["--thickness-mm"]
        stator = PlateStator(
            length_m=args.length_mm * 1e-3,
            width_m=args.width_mm * 1e-3,
            thickness_m=args.thickness_mm * 1e-3,
            electrode_gap_m=opts["--gap-mm"] * 1e-3,
        )
        material = get_material(opts["--material"])
    refine = DEFAULT_REFINE if args.refine is None else args.refine
    try:
        if getattr(args, "model", "2d") == "3d":
            from fem.solid3d import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_modes

            if getattr(args, "export", None):
                raise ValueError("--export is only available with --model 2d")
            refine = DEFAULT_REFINE_3D if args.refine is None else args.refine
            layers = DEFAULT_LAYERS if args.layers is None else args.layers
            res = solid_modes(stator, material, args.order, refine, layers)
        else:
            res = plate_modes(stator, material, args.order, refine)
    except ModeSolverError as exc:
        raise ValueError(str(exc)) from exc
    if getattr(args, "export", None):
        from fem.export import export_modes
        from fem.model import plate_model

        export_modes(args.export, plate_model(stator, material, args.order, refine), res)
    if args.json:
        mat = material.to_dict()
        mat["plane_stress"] = plane_stress(material).to_dict()
        out = {
            "L1": res.L1.to_dict(),
            "B2": res.B2.to_dict(),
            "dofs": res.dofs,
            "wall_time_s": res.wall_time_s,
            "order": args.order,
            "refine": refine,
            "material": mat,
            "geometry": getattr(args, "geometry", None),
            "model": getattr(args, "model", "2d"),
        }
        if getattr(args, "model", "2d") == "3d":
            out["layers"], out["element"] = res.layers, res.element
        print(json.dumps(out))
        return
    meshed = getattr(args, "geometry", None) and design.mesh_path is not None
    print(
        f"plate {args.length_mm:g} x {args.width_mm:g} x {args.thickness_mm:g} mm, "
        f"material {material.name}, order {args.order}, "
        + ("mesh from the stator file" if meshed else f"refine {refine}")
        + (f", 3D layers {res.layers} ({res.element})" if hasattr(res, "layers") else "")
    )
    if getattr(args, "geometry", None):
        print(f"stator file {args.geometry}: {design.name} (bounding box above)")
    print(f"{'mode':<5}{'f_short (Hz)':>14}{'f_open (Hz)':>14}{'k_eff':>9}")
    for m in (res.L1, res.B2):
        print(f"{m.name:<5}{m.f_short_Hz:>14.1f}{m.f_open_Hz:>14.1f}{m.k_eff:>9.4f}")
    print(f"dofs {res.dofs}, wall time {res.wall_time_s:.3f} s")
