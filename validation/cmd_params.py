"""``lusm params``: print one reduced-order parameter set (all ``MotorParams.to_dict()`` fields)."""

from __future__ import annotations

import argparse
import json

from rom.sources import SOURCES, get_params


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``params`` sub-command to the ``lusm`` parser."""
    parser = subparsers.add_parser(
        "params",
        help="print one parameter set (table2, beam or fem)",
        description="Print every field of one reduced-order parameter set, SI units.",
    )
    parser.add_argument(
        "--source", choices=SOURCES, default="table2", help="parameter source (default table2)"
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument(
        "--geometry", metavar="STATOR.toml", default=None,
        help="stator file for --source fem (rom.from_fem.fem_params_from_file)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Build the parameter set of ``args.source`` and print it."""
    if getattr(args, "geometry", None):
        if args.source != "fem":
            raise ValueError(f"--geometry needs --source fem, got --source {args.source}")
        from rom.from_fem import fem_params_from_file

        d = fem_params_from_file(args.geometry).to_dict()
    else:
        d = get_params(args.source).to_dict()
    if args.json:
        print(json.dumps(d, indent=2))
        return
    width = max(len(k) for k in d)
    for key, value in d.items():
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        print(f"{key:<{width}}  {text}")
