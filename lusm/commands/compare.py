"""``lusm compare``: the table2, beam and fem parameter sets side by side."""

from __future__ import annotations

import argparse
import math

from lusm.errors import LusmError
from lusm.options import SOURCES, add_plate_options, motor_params_of, plate_given, print_json

HELP = "compare the parameter sources side by side"
DESCRIPTION = """\
Frequencies, modal masses, stiffnesses, force factors, load coefficients and damping of each
source, with relative differences to the reference.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm compare``."""
    p.add_argument(
        "--sources", nargs="+", choices=SOURCES, default=list(SOURCES),
        help="sources to compare (default: all)",
    )
    p.add_argument(
        "--reference", choices=SOURCES, default="table2", help="reference source (default table2)"
    )
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    add_plate_options(p, note="; any of them makes the fem column that stator's and "
                      "the beam column a beam of its length, width and thickness (a stator file "
                      "with a mesh or features: its electroded body)")


def run(args: argparse.Namespace) -> None:
    """Build the comparison and print it."""
    from rom.compare import compare_sources
    from validation.summaries import borrowed_damping, table2_damping

    # the paper's plate is compared with the paper on the paper's damping; a stator of the
    # user's own gets its material's (validation.summaries.plate_damping) below
    origins = {"table2": table2_damping(),
               "beam": f"{borrowed_damping('beam')} for the comparison with the paper",
               "fem": f"{borrowed_damping('fem')} for the comparison with the paper"}
    given = None
    stator_options = (["--geometry"] if args.geometry else []) + plate_given(args)
    if stator_options and not {"fem", "beam"} & set(args.sources):
        raise LusmError(f"{stator_options[0]} sets the stator of the fem and beam columns, "
                        f"and --sources {' '.join(args.sources)} shows neither; add fem or "
                        "beam to --sources", stator_options[0])
    if args.geometry or plate_given(args):
        fem, origins["fem"] = motor_params_of(args, "fem")
        given = {"fem": fem}
        if "beam" in args.sources:
            # the beam column follows the plate too (it stayed the paper's 30 x 7.5 x 3 mm,
            # so --length-mm changed one column of two)
            from lusm.options import beam_damping, beam_of_plate

            given["beam"], origins["beam"] = beam_of_plate(args), beam_damping(args)[1]
    cmp = compare_sources(args.sources, reference=args.reference, given=given)
    if args.json:
        d = cmp.to_dict()
        d["damping_from"] = {s: origins[s] for s in cmp.values}
        print_json(d, indent=2)
        return
    shown = [s for s in cmp.sources if s in cmp.values]
    header = f"{'quantity':<10} {'unit':<6}" + "".join(f" {s:>12}" for s in shown)
    header += "".join(f" {'d(' + s + ')':>10}" for s in shown if s != cmp.reference)
    print(header)
    for name, unit in cmp.quantities:
        row = f"{name:<10} {unit:<6}" + "".join(f" {cmp.values[s][name]:>12.5g}" for s in shown)
        for s in shown:
            if s == cmp.reference:
                continue
            r = cmp.relative_difference[s][name]
            row += f" {'n/a':>10}" if math.isnan(r) else f" {r:>+10.1%}"
        print(row)
    print(f"relative differences d(.) are to {cmp.reference}")
    for s in shown:
        print(f"{s}: {cmp.descriptions[s]}")
    print("damping ratios from: " + "; ".join(f"{s}: {origins[s]}" for s in shown))
    for s, reason in cmp.unavailable.items():
        print(f"{s}: unavailable ({reason})")
