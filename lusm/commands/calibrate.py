"""``lusm calibrate``: fit a parameter set to a prototype's measurements (docs/calibration.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

from lusm import limits
from lusm.errors import LusmError
from lusm.options import SOURCES, add_output_options, integer

HELP = "fit dampings, force factors and friction to a prototype's measurements"
DESCRIPTION = (
    "Fit the parameters a measurement file names (start values and bounds) to its free tip "
    "amplitudes, admittance and steady speeds by weighted least squares from several starts; "
    "report each parameter's standard error, 95 % profile-likelihood interval and "
    "correlations, name the ones the data cannot fix, and write the calibrated set: a stator "
    "file (--geometry) or a parameter file for --params (--source). docs/calibration.md.")

COUPLINGS = ("auto", "paper", "consistent")
MAX_STARTS = 20


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm calibrate``."""
    p.add_argument("measurements", metavar="MEASUREMENTS.toml",
                   help="measurement file: the CSV files and the parameters to fit")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--geometry", metavar="STATOR.toml", default=None,
                   help="stator file whose FE reduction is the start set; --out is then a "
                   "stator file (.toml) with the calibrated motor tables")
    g.add_argument("--source", choices=SOURCES, default=None,
                   help="start set by name; --out is then a parameter file (.json) for "
                   "--params")
    p.add_argument("--out", required=True, metavar="FILE",
                   help="the calibrated file (.toml with --geometry, .json with --source); "
                   "an existing one only with --force (kept as FILE.bak-N)")
    p.add_argument("--coupling", choices=COUPLINGS, default="auto",
                   help="tangential coupling of the steady engine; auto (default): "
                   "consistent, the one later commands run a calibrated (not Table 2's own) "
                   "set with")
    p.add_argument("--accuracy", choices=("exact", "fast"), default="exact",
                   help="level of the steady engine (default exact, as simulate --steady)")
    p.add_argument("--starts", type=integer("--starts", 1, MAX_STARTS), default=3,
                   help=f"starts of the fit: the file's and random ones in the box; with "
                   f"speed data and a fitted friction parameter, local fits from the N-1 "
                   f"best points of a Sobol screen of the friction law instead; [1, "
                   f"{MAX_STARTS}] (default 3)")
    p.add_argument("--seed", type=integer("--seed", 0, 2**31 - 1), default=0,
                   help="seed of the random starts and the screen (default 0)")
    p.add_argument("--profile", default="all", metavar="NAMES",
                   help="parameters whose profile likelihood is traced: all (default), none, "
                   "or names separated by commas")
    add_output_options(p, folder="--plot",
                       folder_help="write the figures (data and fit, profiles, correlations)")


def _out_path(args: argparse.Namespace) -> Path:
    """``--out``, checked before any work: the suffix of its kind, not a folder, not an
    existing file without --force, in a folder that can be written."""
    import os

    from lusm.options import check_path_usable

    text = args.out
    if not str(text).strip():
        raise LusmError("--out must name a file, got ''", "--out")
    out = Path(text)
    want = ".toml" if args.geometry else ".json"
    if out.suffix.lower() != want:
        what = ("a stator file (.toml)" if args.geometry else
                "a parameter file (.json, read by --params)")
        raise LusmError(f"--out {text}: {'--geometry' if args.geometry else '--source'} "
                        f"writes {what}; name a {want} file", "--out")
    check_path_usable(out, "--out")
    if out.is_dir():
        raise LusmError(f"--out {text} is a folder; name a {want} file", "--out")
    if (out.exists() or out.is_symlink()) and not args.force:
        raise LusmError(f"--out {text} already exists; choose a new name or pass --force "
                        "(the old file is kept as .bak-N)", "--out")
    parent = next((q for q in out.absolute().parents if q.exists()), None)
    if parent is None or not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise LusmError(f"--out {text}: cannot write into {parent}", "--out")
    return out


def _profile_names(args: argparse.Namespace, meas) -> tuple[str, ...]:
    """The parameters ``--profile`` names."""
    names = tuple(p.name for p in meas.parameters)
    if args.profile == "all":
        return names
    if args.profile == "none":
        return ()
    chosen = tuple(n.strip() for n in args.profile.split(",") if n.strip())
    bad = [n for n in chosen if n not in names]
    if bad or not chosen:
        raise LusmError(f"--profile must be all, none or fitted parameters separated by commas "
                        f"({', '.join(names)}), got {args.profile!r}", "--profile")
    return chosen


def _measurements(args: argparse.Namespace):
    """The measurement file, its failures as one line naming it; the steady rows (speeds,
    powers) bounded."""
    from calibration.measurements import STEADY_KINDS, MeasurementError, load_measurements

    try:
        meas = load_measurements(args.measurements)
    except MeasurementError as exc:
        raise LusmError(str(exc), args.measurements) from None
    rows = sum(len(s.inputs["voltage"]) for s in meas.sets if s.kind in STEADY_KINDS)
    top = limits.work_bound(limits.MAX_CALIBRATION_SPEEDS)
    if rows > top:
        raise LusmError(f"{args.measurements}: {rows} speed and power rows, above the limit "
                        f"{top} (each is a steady solve per model evaluation; "
                        f"{limits.more_work_hint()})",
                        args.measurements)
    _check_ranges(meas, args.measurements)
    return meas


def _check_ranges(meas, src: str) -> None:
    """The voltages, preloads and frequencies of the CSVs within the commands' ranges."""
    import numpy as np

    for s in meas.sets:
        for q, (lo, hi), unit in (("voltage", limits.VOLTAGE_V, "V"),
                                  ("preload", limits.PRELOAD_N, "N"),
                                  ("frequency", limits.FREQUENCY_HZ, "Hz")):
            if q in s.inputs and not np.all((s.inputs[q] >= lo) & (s.inputs[q] <= hi)):
                col = s.columns.get(q, "frequency_Hz")
                raise LusmError(f"{src}: {s.path.name} {col}: every {q} must lie in "
                                f"[{lo:g}, {hi:g}] {unit}", src)


def _start_set(args: argparse.Namespace):
    """The start set (the stator file's reduction or the named source) and the stator file's
    force-factor scales."""
    from lusm.options import load_design, motor_params_of

    design = load_design(args.geometry) if args.geometry else None
    params, _ = motor_params_of(args, "fem" if args.geometry else args.source)
    scales = (design.force_factor_scales or (1.0, 1.0)) if design is not None else (1.0, 1.0)
    return params, design, scales


def run(args: argparse.Namespace) -> None:
    """Fit, write the calibrated file and the figures, print the parameters."""
    out = _out_path(args)
    from lusm.options import output_folder

    output_folder(args, "--plot")
    meas = _measurements(args)
    profile = _profile_names(args, meas)
    base, design, scales = _start_set(args)
    from calibration.fit import base_values, calibrate
    from calibration.measurements import MeasurementError

    coupling = "consistent" if args.coupling == "auto" else args.coupling
    try:
        result = calibrate(meas, base, coupling=coupling, accuracy=args.accuracy,
                           starts=args.starts, seed=args.seed, profile=profile)
    except MeasurementError as exc:  # bounds that leave the set invalid
        raise LusmError(str(exc), args.measurements) from None
    text = _file_text(args, result, meas, design, scales, out)
    _write(out, text, args.force)
    figures = _figures(args, result, meas)
    from calibration.output import summary

    if args.json:
        from lusm.options import print_json

        print_json({**summary(result, base_values(meas, base), str(out), meas),
                    "figures": figures}, indent=2)
        return
    _print(result, out, figures)


def _file_text(args, result, meas, design, scales, out: Path) -> str:
    """The calibrated file's text, checked to read back as the fitted set."""
    import json
    import tomllib

    from calibration.output import params_text, relative_mesh, same_set, stator_text
    from rom.params import MotorParams

    if design is None:
        text = params_text(result, meas.path, meas.name)
        if not same_set(MotorParams.from_dict(json.loads(text)), result.params):
            raise RuntimeError("the calibrated parameter file does not read back as the set")
        return text
    original = Path(args.geometry).read_text(encoding="utf-8")
    text = stator_text(original, result, meas.path, meas.name, scales,
                       relative_mesh(design.mesh_path, out))
    from fem.stator_file import parse_stator

    back = parse_stator(tomllib.loads(text), base_dir=out.absolute().parent, src=str(out))
    p = result.params
    want = (p.zeta_L1, p.zeta_B2)
    if back.damping_ratios is None or not all(
            abs(a - b) <= 1e-12 * b for a, b in zip(back.damping_ratios, want, strict=True)):
        raise RuntimeError("the calibrated stator file does not read back its damping")
    return text


def _write(out: Path, text: str, force: bool) -> None:
    """Write ``text`` beside ``out`` and move it in complete; an existing file (``--force``)
    is kept as ``.bak-N``."""
    import os

    from lusm.interrupts import checkpoint
    from lusm.output_set import OutputError, keep_aside, staging

    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        with staging(out.parent, out.name, "--out", out) as stage:
            staged = stage / out.name
            staged.write_text(text, encoding="utf-8")
            checkpoint()
            if force and (out.exists() or out.is_symlink()):
                keep_aside(out, "--force")
            os.replace(staged, out)
    except (OutputError, OSError) as exc:
        raise LusmError(f"--out {out}: cannot write ({getattr(exc, 'strerror', None) or exc})",
                        "--out") from None


def _figures(args: argparse.Namespace, result, meas) -> list[str]:
    """The --plot figures (none without it)."""
    if args.plot is None:
        return []
    from calibration.plots import draw
    from lusm.options import write_figures

    return write_figures(args, "--plot", lambda stage: draw(result, meas, stage))


def _print(result, out: Path, figures: list[str]) -> None:
    """The parameters, the fit's figures and the files written."""
    from calibration.output import fitted_text

    for i in range(len(result.parameters)):
        print(fitted_text(result, i))
    names = result.names
    pairs = [(names[i], names[j], result.correlation[i, j]) for i in range(len(names))
             for j in range(i + 1, len(names)) if abs(result.correlation[i, j]) > 0.5]
    for a, b, c in pairs:
        print(f"correlation {a} / {b}: {c:+.3f}")
    print(f"chi-square {result.chi2:.4g} for {result.dof} degrees of freedom "
          f"({result.points} measured values); {result.evaluations} model evaluations, "
          f"{result.wall_time_s:.1f} s (profiles {result.profile_time_s:.1f} s)")
    for note in result.notes:
        print(f"note: {note}")
    print(f"wrote {out}")
    for f in figures:
        print(f"wrote {f}")
