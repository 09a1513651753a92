"""``lusm admittance``: electrical admittance of the driven electrodes (modal superposition).

Parse, call :func:`fem.admittance.plate_admittance` and
:func:`validation.fem_figures.admittance_figure`, print. No physics here.
"""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from lusm import limits
from lusm.options import add_band_options, add_output_options, add_plate_options, print_json, real

if TYPE_CHECKING:
    from fem.mesh_settings import MeshSettings

HELP = "admittance Y(f) of the driven electrodes: resonance/antiresonance, k_eff, PNG"
DESCRIPTION = """\
Admittance of the driven electrodes (others grounded) of the 2D FE plate by modal superposition
with a residual mode; resonance/antiresonance pairs and the k_eff they imply; |Y| and phase
plot.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm admittance``."""
    add_band_options(p, points=2001)
    p.add_argument("--zeta", type=real("--zeta", "", *limits.ZETA, lo_open=True, hi_open=True),
                   default=None, help="one damping ratio for all modes (default: the stator "
                   "file's [damping], else the paper's zeta_L1, zeta_B2; 0.01 for other "
                   "modes)")
    p.add_argument("--electrodes", default=None, metavar="E[,E...]",
                   help="driven electrodes, e.g. 1,4 (default: the stator's drive)")
    add_plate_options(p)
    from lusm.commands.modes import add_fe_options

    add_fe_options(p)
    add_output_options(p, folder="--out", folder_help="write the admittance plot (PNG) into "
                       "DIR (default: no file)")


def _electrodes(text: str | None) -> tuple[int, ...] | None:
    from lusm.errors import LusmError

    if text is None:
        return None
    try:
        values = tuple(int(t) for t in text.split(","))
    except ValueError:
        values = ()
    if not values or any(e not in (1, 2, 3, 4) for e in values) or len(set(values)) != len(
            values):
        raise LusmError(f"--electrodes must be distinct electrode numbers 1..4 separated by "
                        f"commas, e.g. 1,4, got {text!r}", "--electrodes")
    return values


def run(args: argparse.Namespace) -> None:
    """Run ``lusm admittance`` with parsed ``args``."""
    from fem.mesh_settings import MeshSettings
    from fem.meshing.mesh import DEFAULT_REFINE
    from lusm.commands.modes import start_band_command
    from lusm.options import check_fe_size, stator_from_args, write_figures

    out = start_band_command(args, "--out")
    electrodes = _electrodes(args.electrodes)
    choice = stator_from_args(args)
    refine = DEFAULT_REFINE if args.refine is None else args.refine
    # the default band is the design's L1 and B2: a plate whose B2 the solver cannot reach is
    # refused before any work; a band the user gives needs neither
    check_fe_size(choice.stator, refine, needs_b2=args.f_min is None or args.f_max is None)
    damping = _damping(args, choice)
    res = _solve(args, choice, MeshSettings(args.order, refine), electrodes, damping)
    _warn_unresolved(res, args.f_max, refine)
    _warn_missed(res, args.f_min, args.f_max, args.points)
    circuit = _circuit(res)
    png = None
    if out is not None:
        from validation.fem_figures import admittance_figure

        png = write_figures(args, "--out", lambda stage: [
            admittance_figure(res, stage / "admittance.png", circuit)])[0]
    if args.zeta is not None:
        damping = {"zeta_L1": args.zeta, "zeta_B2": args.zeta, "from": "--zeta (all modes)"}
    if args.json:
        d = res.to_dict()
        d["png"] = png
        d["damping"] = damping
        d["equivalent_circuit"] = None if circuit is None else circuit.to_dict()
        # the design's modes in the band without a pair, and why (the warnings' content):
        # "grid" (too coarse), "band" (the pair reaches beyond it), "peakless" (the damping)
        d["missed_modes"] = (
            [{"mode": n, "f_short_Hz": f, "why": "grid"} for n, f in res.unpaired_modes()]
            + [{"mode": n, "f_short_Hz": f, "why": "band", "f_max_abs_Y_Hz": fm,
                "f_min_abs_Y_Hz": fn} for n, f, (fm, fn) in res.band_cut_modes()]
            + [{"mode": n, "f_short_Hz": f, "why": "peakless"}
               for n, f in res.peakless_modes()])
        print_json(d)
        return
    _print(res, args, damping)
    _print_circuit(circuit)
    if png is not None:
        print(f"wrote {png}")


def _circuit(res):
    """The Butterworth-Van Dyke circuit fitted to the admittance
    (:func:`fem.equivalent_circuit.equivalent_circuit`), None where no mode the port drives
    lies in the band."""
    from fem.equivalent_circuit import equivalent_circuit

    try:
        return equivalent_circuit(res)
    except ValueError:
        return None


def _print_circuit(circuit) -> None:
    """The fitted circuit per mode, as IEEE Std 176 / IEC 60483 report a resonator."""
    if circuit is None:
        print("equivalent circuit: no mode the port drives lies in the band")
        return
    print(f"Butterworth-Van Dyke circuit fitted over the band: C0 {circuit.C0_F:.4e} F in "
          f"parallel with one R1-L1-C1 branch per driven mode (fit: rms "
          f"{circuit.rms_rel:.1e}, max {circuit.max_rel:.1e} of |Y|)")
    print(f"{'mode':<6}{'R1 (ohm)':>11}{'L1 (H)':>11}{'C1 (F)':>12}{'f_s (Hz)':>11}"
          f"{'f_p (Hz)':>11}{'Q_m':>8}{'k_eff':>8}{'C0/C1':>10}{'f_s/f_FE-1':>12}")
    for b in circuit.branches:
        print(f"{b.mode or '-':<6}{b.R_ohm:>11.4g}{b.L_H:>11.4g}{b.C_F:>12.4e}"
              f"{b.f_s_Hz:>11.1f}{b.f_p_Hz(circuit.C0_F):>11.1f}{b.Q_m:>8.4g}"
              f"{b.k_eff(circuit.C0_F):>8.4f}{circuit.C0_F / b.C_F:>10.4g}"
              f"{b.f_s_Hz / b.f_mode_Hz - 1.0:>+12.1e}")
    print("f_s = 1/(2 pi sqrt(L1 C1)), f_p = f_s sqrt(1 + C1/C0), Q_m = sqrt(L1/C1)/R1, "
          "k_eff^2 = 1 - (f_s/f_p)^2 (IEEE Std 176, IEC 60483); f_FE: the mode's FE "
          "frequency")


def _damping(args: argparse.Namespace, choice) -> dict:
    """The modal damping ratios of L1 and B2 and where they come from: the stator file's
    ``[damping]`` (identified from its reduced set where it asks), else the material's
    ``Q_m`` with the mount's (:func:`validation.summaries.plate_damping`; Table 2's for a
    material without ``Q_m``)."""
    from lusm.errors import LusmError
    from rom.from_fem import design_damping
    from rom.table2 import table2
    from validation.summaries import plate_damping

    zetas = choice.design and design_damping(choice.design)
    origin = (f"stator file {args.geometry} {choice.design.damping_origin}"
              if choice.design is not None and choice.design.damping_origin else "")
    if not zetas and not origin:  # no [damping] (a paper_amplitudes fit is made below)
        zetas, origin = plate_damping(choice.material, "fem")
        zetas = zetas or (table2().zeta_L1, table2().zeta_B2)
    if choice.design is not None and choice.design.damping_identify_Hz is not None:
        from rom.from_fem import fem_params_from_file

        try:  # the fit needs the reduced set: the file's masses, stiffnesses, force factors
            fitted = fem_params_from_file(args.geometry)
        except ValueError as exc:
            raise LusmError(f"--geometry {exc}", "--geometry") from None
        zetas = (fitted.zeta_L1, fitted.zeta_B2)
    return {"zeta_L1": zetas[0], "zeta_B2": zetas[1], "from": origin}


def _default_band(args: argparse.Namespace, choice, mesh: MeshSettings) -> None:
    """Fill a missing ``--f-min`` / ``--f-max`` from the design's L1 and B2, bounding the
    modes below ``--f-max`` before the design's modes are solved."""
    from fem.admittance import check_mode_count, design_band_Hz
    from fem.model import plate_model
    from fem.modes import plate_modes
    from lusm.errors import LusmError

    if args.f_max is not None and args.f_min is None:
        check_mode_count(plate_model(choice.stator, choice.material, mesh),
                         args.f_max, max_modes=limits.work_bound(limits.MAX_ADMITTANCE_MODES))
    lo, hi = design_band_Hz(plate_modes(choice.stator, choice.material, mesh))
    given = "--f-min" if args.f_max is None else "--f-max"
    args.f_min = lo if args.f_min is None else args.f_min
    args.f_max = hi if args.f_max is None else args.f_max
    if not args.f_min < args.f_max:
        raise LusmError(
            f"{given} {args.f_min if given == '--f-min' else args.f_max:g} Hz leaves "
            f"no band: the design's band is {lo:.0f}-{hi:.0f} Hz; give --f-min below "
            "--f-max", given)


def _solve(args: argparse.Namespace, choice, mesh: MeshSettings, electrodes, damping: dict):
    """:func:`fem.admittance.plate_admittance` over the band, its failures as bad input."""
    from fem.admittance import TooManyModesError, plate_admittance
    from fem.modes import ModeSolverError
    from lusm.errors import LusmError
    from lusm.fe_errors import fe_failure, is_fe_failure

    try:
        if args.f_min is None or args.f_max is None:  # centre the band on the design
            _default_band(args, choice, mesh)
        return plate_admittance(choice.stator, choice.material, args.f_min, args.f_max,
                                args.points, electrodes=electrodes, zeta=args.zeta,
                                zeta_L1=damping["zeta_L1"], zeta_B2=damping["zeta_B2"],
                                mesh=mesh,
                                max_modes=limits.work_bound(limits.MAX_ADMITTANCE_MODES))
    except TooManyModesError as exc:
        raise LusmError(
            f"--f-max {args.f_max:g} Hz: this mesh has {exc.n_modes} modes below 6 x --f-max "
            f"({exc.f_cut_Hz:.4g} Hz), above the limit of {exc.max_modes} kept modes; lower "
            f"--f-max ({limits.more_work_hint()})", "--f-max") from None
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, choice.stator) from exc
        raise


def _print(res, args: argparse.Namespace, damping: dict) -> None:
    """The port's capacitances, the damping and the table of resonance pairs."""
    p = res.port
    rest = (f" + residual mode at {p.f_res_Hz:.0f} Hz" if math.isfinite(p.f_res_Hz)
            else "" if p.C_res_F == 0.0 else " + a static remainder")
    print(f"electrodes {', '.join(map(str, p.electrodes))} driven, others grounded; band "
          f"{args.f_min:g}-"
          f"{args.f_max:g} Hz; {p.frequencies_Hz.size} modes{rest}")
    print(f"C0 (clamped) {p.C0_F:.4e} F, C_free (static) {p.C_free_F:.4e} F")
    print(f"damping zeta_L1 = {damping['zeta_L1']:.4g}, zeta_B2 = {damping['zeta_B2']:.4g} "
          f"(from {damping['from']})")
    if not res.pairs:
        print("no resonance/antiresonance pair resolved in the band: "
              + ("the grid is too coarse for the design's modes (the warning above)"
                 if res.unpaired_modes() else
                 "the damping leaves the design's modes without a peak (the warning above)"
                 if res.peakless_modes() else "widen it (--f-min, --f-max)"))
    w = max([5] + [len(q.mode) + 1 for q in res.pairs])
    # series / parallel resonance (max Re Y, max Re 1/Y), not the |Y| extrema: those move
    # with the damping (IEEE Std 176); no header over an empty table
    if res.pairs:
        print(f"{'mode':<{w}}{'f_s (Hz)':>12}{'f_p (Hz)':>12}{'k_eff':>9}")
    for q in res.pairs:
        print(f"{q.mode or '-':<{w}}{q.f_resonance_Hz:>12.1f}{q.f_antiresonance_Hz:>12.1f}"
              f"{q.k_eff:>9.4f}")
    if any("merged" in q.mode for q in res.pairs):
        print("merged: L1 and B2 make one peak at this damping; its k_eff is not either mode's")
    if any("overlaps" in q.mode for q in res.pairs):
        print("overlaps: L1 and B2 make two peaks closer than their bandwidths at this damping; "
              "each k_eff is biased by the other mode")


UNRESOLVED_SHARE = 0.25
"""Share of a mesh's modes below which its frequencies are taken as converged: the top of a
discrete spectrum (here above a quarter of the unknowns) is the mesh's, not the plate's."""


def _warn_missed(res, f_min_Hz: float, f_max_Hz: float, points: int) -> None:
    """Warn when L1 or B2 lies in the band but no resonance pair found on the grid is theirs
    (``--f-min 1 --f-max 1e7``: a 5 kHz step listed pairs from 177 kHz up, without a word
    about the design's modes at 54-56 kHz)."""
    from lusm.messages import warn

    missed = [f"{name} ({f:.0f} Hz)" for name, f in res.unpaired_modes()]
    if missed:
        step = (f_max_Hz - f_min_Hz) / (points - 1)
        warn(f"--points {points}: {' and '.join(missed)} lie{'s' if len(missed) == 1 else ''} "
             f"in the band but no resonance pair on this grid (step {step:.4g} Hz) belongs "
             f"to {'it' if len(missed) == 1 else 'them'}; raise --points or narrow the band "
             "(--f-min, --f-max)")
    for name, f, (f_m, f_n) in res.band_cut_modes():
        edges = [o for o, cut in (("--f-min", f_m < f_min_Hz), ("--f-max", f_n > f_max_Hz))
                 if cut]
        warn(f"{' and '.join(edges)}: {name} ({f:.0f} Hz) lies in the band but its resonance "
             f"pair reaches beyond it (the peak of |Y| at {f_m:.0f} Hz, the minimum after it "
             f"at {f_n:.0f} Hz); widen the band to include both (no --points finds the pair "
             "inside it)")
    flat = res.peakless_modes()
    if flat:
        port = res.port
        named = {n: (z, k) for n, z, k in zip(port.mode_names, port.zeta, port.coupling(),
                                                strict=True) if n}
        one = len(flat) == 1
        modes = " and ".join(f"{n} ({f:.0f} Hz, zeta {named[n][0]:.3g}, coupling k "
                             f"{named[n][1]:.3g})" for n, f in flat)
        wires = f"electrode{'s' if len(port.electrodes) > 1 else ''} " + ", ".join(
            map(str, port.electrodes))
        warn(f"{modes} {'has' if one else 'have'} no resonance peak through {wires} at this "
             f"damping, on any grid: the coupling is too weak against the damping; a lighter "
             f"--zeta resolves {'it' if one else 'them'}")


def _warn_unresolved(res, f_max_Hz: float, refine: int) -> None:
    """Warn when the band reaches modes the mesh cannot resolve (a 1 MHz band on the default
    mesh listed resonances up to 0.95 MHz from elements 1.9 mm long)."""
    from lusm.messages import warn

    port = res.port
    n = int(port.g_N_V.size)
    k = sum(1 for f in port.frequencies_Hz if f <= f_max_Hz)
    if k > UNRESOLVED_SHARE * n:
        warn(f"--f-max {f_max_Hz:g} Hz reaches mode {k} of the mesh's {n} (--refine {refine}): "
             f"frequencies that high are not converged; raise --refine, or lower --f-max")
