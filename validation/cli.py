"""The ``lusm`` command line: parse, call the library, print. No physics lives here.

Each sub-command sits in its own ``validation/cmd_<name>.py`` module exposing
``register(subparsers)``; this module only builds the parser and turns library errors
(``ValueError`` with a message naming the parameter) into one-line errors with exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

COMMAND_MODULES = (
    "validation.cmd_simulate",
    "validation.cmd_map",
    "validation.cmd_modes",
    "validation.cmd_params",
    "validation.cmd_compare",
    "validation.cmd_report",
    "validation.cmd_render",
    "validation.cmd_tune",
    "validation.cmd_sweep",
    "validation.cmd_admittance",
    "validation.cmd_characteristic",
)
"""Sub-command modules, registered in this order when they exist."""


class UsageError(ValueError):
    """Bad command-line input; reported as one line and exit code 2."""


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line (no usage dump) with exit code 2."""

    def error(self, message: str) -> None:  # noqa: D102 - argparse API
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The full ``lusm`` parser with every available sub-command."""
    parser = _Parser(
        prog="lusm",
        description="Linear piezoelectric ultrasonic motor: FE stator, reduced-order "
        "parameters and the stick-slip-separation contact model.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:  # sub-command not written yet
                continue
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``lusm`` console script; returns the process exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        args.func(args)
    except (ValueError, FileNotFoundError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"lusm {args.command}: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
