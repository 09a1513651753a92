"""``lusm params``: print one reduced-order parameter set (all ``MotorParams.to_dict()`` fields)."""

from __future__ import annotations

import argparse

from lusm.options import SOURCES, add_output_options, add_plate_options, print_json

HELP = "print one parameter set (table2, beam or fem)"
DESCRIPTION = "Print every field of one reduced-order parameter set, SI units."


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm params``."""
    p.add_argument(
        "--source", choices=SOURCES, default=None,
        help="parameter source (default table2; fem with --geometry or a plate option)",
    )
    add_plate_options(p, note="; any of them selects --source fem")
    add_output_options(p, folder=None)


def run(args: argparse.Namespace) -> None:
    """Build the parameter set of ``args.source`` and print it."""
    from lusm.options import motor_params_of

    params, damping_from = motor_params_of(args, args.source)
    from rom.params import PARAM_UNITS

    d = params.to_dict()
    if args.json:  # the keys are the set's fields (--params reads them back): units beside
        print_json({**d, "units": {k: PARAM_UNITS[k] for k in d if k in PARAM_UNITS}},
                   indent=2)
        return

    width = max(len(k) for k in d)
    for key, value in d.items():
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        unit = PARAM_UNITS.get(key, "")
        print(f"{key:<{width}}  {text:>12}  {unit}" if unit else f"{key:<{width}}  {text}")
    from validation.summaries import damping_line

    print(damping_line(params, damping_from))
