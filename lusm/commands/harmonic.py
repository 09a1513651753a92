"""``lusm harmonic``: the free tip's amplitudes and phases against frequency, and its ellipse.

A command of its own rather than a mode of ``lusm admittance``: admittance answers an
electrical question (the port's current) from the plate's full modal basis, harmonic a
mechanical one (the tip's motion, what the paper's Figs. 5-6 measured) from the reduced model
the contact commands run, checked against the direct FE solve. Parse, call
:func:`rom.harmonic.tip_response`, :func:`fem.harmonic.fe_tip_response` and
:mod:`validation.harmonic_figures`, print. No physics here.
"""

from __future__ import annotations

import argparse

from lusm import limits
from lusm.options import (
    add_band_options,
    add_damping_option,
    add_output_options,
    add_plate_options,
    print_json,
    real,
)

HELP = "free tip amplitudes (tangential, normal, µm) and phase against frequency; tip ellipse"
DESCRIPTION = """\
Free (no contact, no preload) steady response of the stator's tip to the drive V sin(w t):
tangential (B2) and normal (L1) amplitudes and phases against frequency from the reduced model
of the FE plate, checked against a direct FE harmonic solve with the same modal damping at L1,
B2, the drive frequency and the band's ends; the tip's ellipse at the drive frequency.
The damping is --zeta's, the stator file's, or the material's data-sheet Q_m with the mount's
(--damping table2: Table 2's ratios); the output names it and where it came from.
"""

FE_CHECKS = ("band start", "L1", "B2", "drive", "band end")
"""Where the direct FE solve checks the reduced model (those inside the band)."""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm harmonic``."""
    v_lo, v_hi = limits.VOLTAGE_V
    p.add_argument("--voltage", type=real("--voltage", "V", v_lo, v_hi), default=100.0,
                   help=f"drive amplitude V0 (V), in [{v_lo:g}, {v_hi:g}], default 100")
    add_band_options(p, points=801)
    p.add_argument("--frequency", default="auto", metavar="HZ|auto",
                   help="drive frequency of the tip ellipse (Hz), default auto: the set's "
                   "operating point, as the contact commands take it")
    p.add_argument("--zeta", type=real("--zeta", "", *limits.ZETA, lo_open=True, hi_open=True),
                   default=None, help="one damping ratio for L1 and B2 (default: the stator "
                   "file's [damping], else --damping)")
    g = add_plate_options(p)
    add_damping_option(g, "the plate options (no --geometry, no --zeta)")
    from lusm.commands.modes import add_fe_options

    add_fe_options(p)
    add_output_options(p, folder="--plot", folder_help="write harmonic.png (amplitudes and "
                       "phases) and tip_ellipse.png into DIR")


def run(args: argparse.Namespace) -> None:
    """Run ``lusm harmonic`` with parsed ``args``."""
    from fem.meshing.mesh import DEFAULT_REFINE
    from lusm.commands.modes import start_band_command
    from lusm.options import check_fe_size, parse_frequency, stator_from_args

    plot = start_band_command(args, "--plot")
    if args.frequency.strip().lower() != "auto":
        parse_frequency(args.frequency)  # refused before any work
    choice = stator_from_args(args)
    refine = DEFAULT_REFINE if args.refine is None else args.refine
    check_fe_size(choice.stator, refine)
    params, origin, model, modes = _reduced(args, choice, refine)
    band = _band(args, modes)
    drive_Hz = parse_frequency(args.frequency, params)
    result = _responses(args, params, model, modes, band, drive_Hz)
    if plot is not None:
        result["png"] = _figures(args, choice, result, modes)
    if args.json:
        _print_json(result, params, origin, modes, args.voltage)
        return
    _print(result, params, origin, modes, args, choice)


def _damping(args: argparse.Namespace, choice) -> tuple[tuple[float, float] | None, str]:
    """The damping ratios to reduce with (None: the set's own) and where they come from:
    ``--zeta``, the stator file's ``[damping]`` (or its material's), or for the plate options
    ``--damping`` (:func:`lusm.options.set_damping`), as the contact commands take them."""
    from lusm.options import check_damping_clash, fem_damping_origin, set_damping

    check_damping_clash(args, [o for o, v in (("--zeta", args.zeta),
                                              ("--geometry", args.geometry)) if v is not None])
    if args.zeta is not None:
        return (args.zeta, args.zeta), "--zeta (L1 and B2)"
    if choice.design is not None:
        return None, fem_damping_origin(args.geometry, choice.design)
    return set_damping(args, choice.material, "fem")


def _reduced(args: argparse.Namespace, choice, refine: int):
    """The reduced set of the FE plate (its damping from :func:`_damping`), where its damping
    came from, and the model and modes it was reduced from (the same mesh)."""
    from fem.mesh_settings import MeshSettings
    from fem.model import plate_model
    from fem.modes import plate_modes
    from lusm.errors import LusmError
    from lusm.fe_errors import fe_failures_as_input
    from rom.from_fem import fem_params, fem_params_from_design

    ratios, origin = _damping(args, choice)
    mesh = MeshSettings(args.order, refine)
    kwargs = {"mesh": mesh}
    if ratios is not None:
        kwargs["damping_ratios"] = ratios
    with fe_failures_as_input(choice.stator):
        try:
            params = (fem_params_from_design(choice.design, **kwargs) if choice.design
                      else fem_params(choice.stator, choice.material, **kwargs))
        except ValueError as exc:
            if choice.design is not None:
                raise LusmError(f"--geometry {exc}", "--geometry") from None
            raise
        model = plate_model(choice.stator, choice.material, mesh)
        modes = plate_modes(choice.stator, choice.material, mesh)
    return params, origin, model, modes


def _band(args: argparse.Namespace, modes) -> tuple[float, float]:
    """``--f-min``, ``--f-max``, each missing one from the design's L1 and B2."""
    from fem.admittance import design_band_Hz
    from lusm.errors import LusmError

    lo, hi = design_band_Hz(modes)
    f_min = lo if args.f_min is None else args.f_min
    f_max = hi if args.f_max is None else args.f_max
    if not f_min < f_max:
        given = "--f-min" if args.f_min is not None else "--f-max"
        raise LusmError(f"{given} leaves no band: the design's band is {lo:.0f}-{hi:.0f} Hz; "
                        "give --f-min below --f-max", given)
    return f_min, f_max


def _responses(args: argparse.Namespace, params, model, modes, band, drive_Hz: float) -> dict:
    """The reduced model's curves, the FE check and the ellipse."""
    import numpy as np

    from fem.harmonic import fe_tip_response
    from rom.harmonic import tip_ellipse, tip_response

    f = np.linspace(band[0], band[1], args.points)
    rom = tip_response(params, f, args.voltage)
    where = dict(zip(FE_CHECKS, (band[0], modes.L1.f_short_Hz, modes.B2.f_short_Hz, drive_Hz,
                                 band[1]), strict=True))
    where = {k: v for k, v in where.items() if band[0] <= v <= band[1]}
    fe = fe_tip_response(model, modes, list(where.values()), args.voltage, params.zeta_L1,
                         params.zeta_B2)
    at = tip_response(params, fe.frequency_Hz, args.voltage)
    check = []
    for i, name in enumerate(where):
        row = {"at": name, "frequency_Hz": float(fe.frequency_Hz[i])}
        for key, comp in (("tangential", "tangential_m"), ("normal", "normal_m")):
            a, b = getattr(at, comp)[i], getattr(fe, comp)[i]
            row[f"{key}_rom_um"], row[f"{key}_fe_um"] = abs(a) * 1e6, abs(b) * 1e6
            row[f"{key}_rel_error"] = abs(a - b) / abs(b) if abs(b) > 0 else float("nan")
        check.append(row)
    ellipse = tip_ellipse(params, drive_Hz, args.voltage)
    return {"rom": rom, "fe": fe, "check": check, "ellipse": ellipse, "png": None}


def _figures(args: argparse.Namespace, choice, result: dict, modes) -> list[str]:
    """harmonic.png and tip_ellipse.png, built aside and moved into ``--plot`` complete."""
    from lusm.options import write_figures
    from validation.harmonic_figures import ellipse_figure, harmonic_figure
    from validation.summaries import plate_text

    plate = plate_text(choice.stator)
    e = result["ellipse"]
    marks = {"L1": modes.L1.f_short_Hz, "B2": modes.B2.f_short_Hz, "drive": e.frequency_Hz}

    def draw(stage):
        return [harmonic_figure(result["rom"], result["fe"], stage / "harmonic.png", marks,
                                f"free tip at {args.voltage:g} V: {plate}"),
                ellipse_figure(e, stage / "tip_ellipse.png",
                               f"free tip over one period at {e.frequency_Hz:.0f} Hz, "
                               f"{args.voltage:g} V\n{plate}")]

    return write_figures(args, "--plot", draw)


def _print_json(result: dict, params, origin: str, modes, voltage_V: float) -> None:
    """The reduced model's arrays at the top level, the FE check, the ellipse."""
    out = result["rom"].to_dict()
    out.update({"voltage_V": voltage_V,
                "modes_Hz": {"L1": modes.L1.f_short_Hz, "B2": modes.B2.f_short_Hz},
                "damping": {"zeta_L1": params.zeta_L1, "zeta_B2": params.zeta_B2,
                            "from": origin},
                "fe_check": {**result["fe"].to_dict(), "points": result["check"]},
                "ellipse": result["ellipse"].to_dict(), "png": result["png"]})
    print_json(out)


def _print(result: dict, params, origin: str, modes, args: argparse.Namespace,
           choice) -> None:
    """The peaks, the ellipse and the FE check as text."""
    import numpy as np

    from validation.summaries import plate_text

    rom, fe, e = result["rom"], result["fe"], result["ellipse"]
    print(f"free tip (no contact, no preload) at {args.voltage:g} V: {plate_text(choice.stator)}"
          f", material {choice.material.name}; L1 {modes.L1.f_short_Hz:.1f} Hz, B2 "
          f"{modes.B2.f_short_Hz:.1f} Hz")
    print(f"damping zeta_L1 = {params.zeta_L1:.4g}, zeta_B2 = {params.zeta_B2:.4g} (from "
          f"{origin})")
    for name, comp in (("tangential", "tangential_m"), ("normal", "normal_m")):
        a = np.abs(getattr(rom, comp))
        k = int(np.argmax(a))
        print(f"{name:<11} peak {a[k] * 1e6:.4g} µm at {rom.frequency_Hz[k]:.1f} Hz "
              f"({a[k] * 1e6 / max(args.voltage, 1e-300):.4g} µm/V)")
    print(f"tip ellipse at {e.frequency_Hz:.1f} Hz: tangential {e.width_m * 1e6:.4g} µm, normal "
          f"{e.height_m * 1e6:.4g} µm, phase of the normal motion ahead of the tangential "
          f"{e.phase_deg:+.1f} deg")
    print(f"check against the direct FE harmonic solve ({fe.dofs} dofs, same modal damping; "
          "other modes undamped):")
    print(f"{'at':<11}{'f (Hz)':>10}{'tang. ROM':>11}{'FE (µm)':>10}{'error':>9}"
          f"{'norm. ROM':>11}{'FE (µm)':>10}{'error':>9}")
    for r in result["check"]:
        print(f"{r['at']:<11}{r['frequency_Hz']:>10.1f}{r['tangential_rom_um']:>11.4g}"
              f"{r['tangential_fe_um']:>10.4g}{r['tangential_rel_error']:>9.2%}"
              f"{r['normal_rom_um']:>11.4g}{r['normal_fe_um']:>10.4g}"
              f"{r['normal_rel_error']:>9.2%}")
    print("error: |ROM - FE| / |FE| of the complex amplitude; the reduced model keeps L1 and "
          "B2 only, the FE solve every mode (their quasi-static share is the difference away "
          "from resonance)")
    for path in result["png"] or ():
        print(f"wrote {path}")
