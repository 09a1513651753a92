"""The ``lusm`` command line: parse, call the library, print. No physics lives here.

Each sub-command sits in its own ``lusm/commands/<name>.py`` module exposing ``HELP`` (its
line in ``lusm --help``), ``DESCRIPTION``, ``add_arguments(parser)`` and ``run(args)``; its
library is imported inside its ``run`` so that building the parser (``lusm --help``) imports
no numpy, scipy, numba or scikit-fem. Shared options live in
:mod:`lusm.options`, limits in :mod:`lusm.limits`.

Exit codes: 0 success; 2 for every user-facing failure (:class:`lusm.errors.LusmError`,
and the library's ``ValueError`` / ``OSError`` / :class:`contact.errors.ChatteringError`, the
kernel's refusal of an operating point, mapped by :func:`lusm.errors.user_error`),
printed as one line ``lusm <cmd>: error: ...``; 130 on Ctrl-C or SIGTERM (staging folders are
removed by their ``finally`` blocks, :mod:`lusm.interrupts`); 1 for an unexpected
exception (a bug): one line naming it and asking for a report, the traceback only with
``LUSM_DEBUG=1``.
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import importlib
import os
import re
import sys
import warnings
from collections.abc import Iterator, Sequence

COMMAND_MODULES = [
    "lusm.commands.simulate",
    "lusm.commands.map",
    "lusm.commands.modes",
    "lusm.commands.params",
    "lusm.commands.compare",
    "lusm.commands.report",
    "lusm.commands.render",
    "lusm.commands.tune",
    "lusm.commands.sweep",
    "lusm.commands.admittance",
    "lusm.commands.harmonic",
    "lusm.commands.explore",
    "lusm.commands.optimize",
    "lusm.commands.characteristic",
    "lusm.commands.materials",
    "lusm.commands.calibrate",
]
"""Sub-command modules, registered in this order (a module that does not exist is skipped)."""

DEBUG_ENV = "LUSM_DEBUG"
"""Set to 1 to see the traceback of an unexpected error."""

# argparse takes "-1e-7" for an option (its own pattern knows only -1 and -1.5), so the user
# gets "expected one argument"; accept every negative number, list or range ("-1e-7", "-1,2",
# "-5:5:1") as a value and let the option's type give the real message. No option of lusm
# starts with "-" and a digit.
_NEGATIVE_NUMBER = re.compile(
    r"^-(\d|\.\d)[\d.eE+\-:,]*$|^-(inf|infinity|nan)$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line (no usage dump) with exit code 2."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def _get_values(self, action, arg_strings):  # noqa: D102 - argparse API
        # argparse drops a "--" value (--voltage=--) and hands the option an empty list
        if action.nargs is None and action.option_strings and arg_strings == ["--"]:
            self.error(f"argument {action.option_strings[0]}: expected a value, got '--'")
        return super()._get_values(action, arg_strings)

    def error(self, message: str) -> None:  # noqa: D102 - argparse API
        # our argument types name their option already: "argument --dt: --dt must ..." -> once
        message = re.sub(r"^argument (\S+): \1 ", r"\1 ", message)
        self.exit(2, f"{self.prog}: error: {' '.join(message.split())}\n")


def _version() -> str:
    """The installed package's version (read from its metadata: no heavy import)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("lusm")
    except PackageNotFoundError:  # a source tree that is not installed
        return "unknown"


def build_parser() -> argparse.ArgumentParser:
    """The full ``lusm`` parser with every available sub-command."""
    parser = _Parser(
        prog="lusm",
        description="Linear piezoelectric ultrasonic motor: FE stator, reduced-order "
        "parameters and the stick-slip-separation contact model. Limits of every input: "
        "docs/limits.md (LUSM_MAX_WORK=N allows N times more work).",
    )
    parser.add_argument("--version", action="version", version=f"lusm {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:  # a command of another branch, not merged here
                continue
            raise
        p = sub.add_parser(name.rpartition(".")[2], help=module.HELP,
                           description=module.DESCRIPTION)
        module.add_arguments(p)
        p.set_defaults(func=module.run)
    return parser


def _one_line(text: str) -> str:
    return " ".join(text.split())


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``lusm`` console script; returns the process exit code."""
    with _standard_streams() as closed:
        code = _main_or_interrupted(argv, closed)
    if argv is None:  # the console script: only the interpreter's shutdown is left
        _after_the_command(code)
        gc.freeze()  # the exit's last collection skips numba's and SciPy's ~2e5 objects
    return code


class StandardOutputError(OSError):
    """Standard output refused a write (full, an I/O error; not a closed pipe, which stops
    the command quietly)."""


class _Output:
    """Standard output whose failed writes are :class:`StandardOutputError`: said as
    standard output's, not as "cannot use: No space left on device" of no file. After one,
    its descriptor goes to /dev/null, so that the exit's flush does not fail again."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def _call(self, fn, *args):
        try:
            return fn(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            with contextlib.suppress(OSError, ValueError, AttributeError):
                devnull = os.open(os.devnull, os.O_WRONLY)
                os.dup2(devnull, self._stream.fileno())
                os.close(devnull)
            raise StandardOutputError(exc.errno, exc.strerror or str(exc)) from None

    def write(self, text: str) -> int:
        return self._call(self._stream.write, text)

    def flush(self) -> None:
        self._call(self._stream.flush)

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


class _Unfailing:
    """A text stream (standard error) whose writes never raise: a full or closed one
    (``2>/dev/full``) loses the line, and the exit code still says how the command ended
    (a warning's failed write had ended it with an OSError, whose line failed again)."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        with contextlib.suppress(OSError, ValueError):
            return self._stream.write(text)
        return len(text)

    def flush(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            self._stream.flush()

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


@contextlib.contextmanager
def _standard_streams() -> Iterator[list[str]]:
    """Meanwhile, standard error never raises (:class:`_Unfailing`), and a standard stream
    the shell closed (``>&-``, ``2>&-``; Python then has None for it) is /dev/null at its
    descriptor, so that no file the command opens takes its number. Yields the names of the
    closed output streams: a closed standard error had made ``print(file=sys.stderr)``
    write the warnings into standard output, into the middle of ``--json``."""
    closed = []
    for fd, name in ((0, "stdin"), (1, "stdout"), (2, "stderr")):
        try:
            os.fstat(fd)
        except OSError:
            opened = os.open(os.devnull, os.O_RDWR)  # the lowest free number: ``fd``
            if opened != fd:
                os.dup2(opened, fd)
                os.close(opened)
            if fd:
                closed.append(name)
    before = sys.stdout, sys.stderr
    if sys.stderr is None or "stderr" in closed:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - for the whole command
    if sys.stdout is None:
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - for the whole command
        if "stdout" not in closed:
            closed.append("stdout")
    sys.stderr = _Unfailing(sys.stderr)
    sys.stdout = _Output(sys.stdout)
    try:
        yield closed
    finally:
        sys.stdout, sys.stderr = before


def _main_or_interrupted(argv: Sequence[str] | None, closed: list[str]) -> int:
    """:func:`_main`, and a Ctrl-C before the command's own handlers; a closed standard
    output is refused before any work (the command's results would go nowhere)."""
    try:
        if "stdout" in closed:
            words = [a for a in (sys.argv[1:] if argv is None else argv)
                     if not a.startswith("-")]
            name = f"lusm {words[0]}" if words and words[0].isidentifier() else "lusm"
            _say(f"{name}: error: standard output is closed (>&-), so the results would "
                 "go nowhere; redirect it to a file or to /dev/null")
            return 2
        return _main(argv)
    except KeyboardInterrupt:  # before the command's handlers (imports, parsing): nothing written
        words = [a for a in (sys.argv[1:] if argv is None else argv) if not a.startswith("-")]
        name = f"lusm {words[0]}" if words and words[0].isidentifier() else "lusm"
        _say(f"{name}: interrupted")
        return 130


def _after_the_command(code: int) -> None:
    """Once the command has said how it ended, only the interpreter's shutdown is left
    (closing explore's cluster, exit hooks): a Ctrl-C there is ignored, not a traceback from
    ``threading._shutdown``, and SIGTERM ends the process at once with the command's exit
    ``code`` (the shutdown may hang, and Python's default would end it with 143)."""
    import signal

    def end(signum, frame) -> None:  # pragma: no cover - exercised by signals
        for stream in (sys.stdout, sys.stderr):  # os._exit does not flush Python's buffers
            with contextlib.suppress(Exception):  # a closed pipe: the exit matters more
                stream.flush()
        os._exit(code)

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, end)


def _main(argv: Sequence[str] | None) -> int:
    from lusm.messages import set_command, set_typed

    # Figures are files: the CLI picks matplotlib's file backend, library code never does.
    os.environ.setdefault("MPLBACKEND", "Agg")
    from lusm.limits import work_factor

    try:  # before parsing: options' bounds use it, and the fault is not theirs
        work_factor()
    except ValueError as exc:
        print(f"lusm: error: {exc}", file=sys.stderr)
        return 2
    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
    except SystemExit as exc:  # argparse's one-line error (2) or --help (0): a return code
        return exc.code if isinstance(exc.code, int) else 2
    if extra:  # named by the sub-command, not by the top-level parser
        print(f"lusm {args.command}: error: unrecognized arguments: {' '.join(extra)}",
              file=sys.stderr)
        return 2
    set_command(args.command)
    set_typed(sys.argv[1:] if argv is None else argv)
    for attr, option, what in (("geometry", "--geometry", "a stator file"),
                               ("params", "--params", "a parameter file")):
        value = getattr(args, attr, None)
        if value is not None and not str(value).strip():  # "" is not "not given"
            print(f"lusm {args.command}: error: {option} must name {what}, got {value!r}",
                  file=sys.stderr)
            return 2
    return _run(args, argv)


def _say(line: str) -> None:
    """Print the one line a command ends with on stderr, on a line of its own.

    A progress bar the command left open (it was interrupted or failed inside the loop) is
    closed first: its text has no line end, so the line would otherwise be printed after it,
    and on a terminal over it. Only bars of an already imported tqdm are looked at.
    """
    tqdm_module = sys.modules.get("tqdm")
    if tqdm_module is not None:
        for bar in list(getattr(tqdm_module.tqdm, "_instances", ())):
            bar.close()
    print(line, file=sys.stderr)


@contextlib.contextmanager
def _one_line_warnings(prog: str) -> Iterator[None]:
    """Show every Python warning a command raises as one line, ``lusm <cmd>: warning: ...``,
    once per message: not Python's two-line form with a library's file, line and source
    (``fem/model.py:635: GapValidityWarning: ...`` and the statement under it).
    ``LUSM_DEBUG=1`` keeps Python's form."""
    if os.environ.get(DEBUG_ENV):
        yield
        return
    seen: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        from fem.errors import GapValidityWarning
        from lusm.errors import in_option_terms
        from lusm.messages import in_file_terms, record_said

        text = _one_line(in_file_terms(message) if isinstance(message, GapValidityWarning)
                         else in_option_terms(message))
        # a --json summary lists it too (lusm explore's), also when it is said before the
        # summary's record opens
        record_said(text)
        if text not in seen:
            seen.add(text)
            _say(f"{prog}: warning: {text}")

    with warnings.catch_warnings():  # restores showwarning (and the filters) on the way out
        warnings.showwarning = show
        yield


def _run(args: argparse.Namespace, argv: Sequence[str] | None) -> int:
    """Run the parsed command; map every way it can end to an exit code and one line."""
    from contact.errors import ChatteringError
    from lusm import interrupts
    from lusm.errors import LusmError, user_error

    prog = f"lusm {args.command}"
    try:
        with interrupts.handlers(), _one_line_warnings(prog):
            args.func(args)
            sys.stdout.flush()  # a full standard output is said here, not at the exit
    except (KeyboardInterrupt, interrupts.Terminated):
        _say(f"{prog}: interrupted")
        return 130
    except BrokenPipeError:  # the reader left (``lusm params | head``): stop quietly, as
        # the Python docs advise, so that flushing stdout at exit does not fail again
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except StandardOutputError as exc:  # full (>/dev/full) or failing: said on stderr
        _say(f"{prog}: error: cannot write standard output: {exc.strerror or exc}")
        return 2
    except (LusmError, ValueError, OSError, ChatteringError) as exc:
        err = exc if isinstance(exc, LusmError) else user_error(exc)
        _say(f"{prog}: error: {_one_line(str(err))}")
        if os.environ.get(DEBUG_ENV):
            raise
        return 2
    except Exception as exc:  # a bug: say so in one line, never silently
        if os.environ.get(DEBUG_ENV):
            raise
        text = _one_line(str(exc))[:300]
        _say(f"{prog}: internal error: {type(exc).__name__}: {text} - please report it "
             f"(run with {DEBUG_ENV}=1 for the traceback)")
        return 1
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
