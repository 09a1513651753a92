"""What a command says besides its results: its warnings, once each, on stderr, and the
options as the user typed them (so a refusal names the option given, and a default is told
from a value given on purpose)."""

from __future__ import annotations

import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

_COMMAND = ["lusm"]


_TYPED: set[str] = set()
_ARGV: list[str] = []


def set_typed(argv: Sequence[str]) -> None:
    """Record the options the user typed (``--dt``, ``--dt=1e-7``), so that a command can tell
    an option given on purpose from its default (set by :func:`lusm.cli.main`)."""
    _TYPED.clear()
    _TYPED.update(a.split("=", 1)[0] for a in argv if a.startswith("--"))
    _ARGV[:] = list(argv)


def command_line() -> str:
    """The running command as the user typed it, shell-quoted (``lusm tune --fix ...``)."""
    import shlex

    return shlex.join(["lusm", *_ARGV])


def typed(option: str) -> bool:
    """Whether the user typed ``option`` on the command line."""
    return option in _TYPED


def warn_unused(options: Sequence[str], why: str) -> None:
    """Warn that the typed ones among ``options`` have no effect, and why."""
    given = [o for o in options if typed(o)]
    if given:
        warn(f"{' and '.join(given)} {'has' if len(given) == 1 else 'have'} no effect: {why}")


_SAID: set[str] = set()
"""The warning lines said by the running command (each is said once)."""


def set_command(name: str) -> None:
    """The command named in warnings (set by :func:`lusm.cli.main` for each command,
    which starts a fresh record of the warnings said)."""
    _COMMAND[0] = f"lusm {name}"
    forget_warnings()


def forget_warnings() -> None:
    """Start a fresh record of the warnings said (:func:`warn` says each once)."""
    _SAID.clear()


def warn(message: str | Warning) -> None:
    """One warning line on stderr: ``lusm <cmd>: warning: ...``, once per command (lusm
    report builds the FE model in several stages, each of which warns); a library warning
    in the stator file's terms where it has them (:func:`in_file_terms`)."""
    text = in_file_terms(message)
    line = f"{_COMMAND[0]}: warning: {text}"
    record_said(text)  # also when said before the record opened: the --json lists it too
    if line in _SAID:
        return
    _SAID.add(line)
    print(line, file=sys.stderr)


_RECORDS: list[list[str]] = []
"""The open records of :func:`warnings_said`."""


def record_said(text: str) -> None:
    """Add a warning just said on stderr (its text after ``warning:``) to every open record of
    :func:`warnings_said`: :func:`warn` calls it, and so does the CLI's one-line printer of
    Python warnings (:mod:`lusm.cli`)."""
    for said in _RECORDS:
        if text not in said:
            said.append(text)


@contextmanager
def warnings_said() -> Iterator[list[str]]:
    """Record the warnings said within, for a command's ``--json``.

    Yields
    ------
    list of str
        Filled as the warnings are said, in order, once each: the text of each warning line
        (after ``warning:``) said by :func:`warn` or by the CLI's one-line printer of Python
        warnings (``LUSM_DEBUG=1`` keeps Python's own form, which is not recorded).
    """
    said: list[str] = []
    _RECORDS.append(said)
    try:
        yield said
    finally:
        _RECORDS.remove(said)


def in_file_terms(message: object) -> str:
    """A library warning in a stator file's terms when the user gave ``--geometry``: the 2D
    model's :class:`fem.errors.GapValidityWarning` compares the file's ``[electrodes] gap_mm``
    (or its mesh's gap strips) with its ``[plate] thickness_mm``; any other message as it
    is."""
    from fem.errors import GapValidityWarning

    if not (isinstance(message, GapValidityWarning) and typed("--geometry")):
        return str(message)
    return (f"the stator file's electrode gap ({message.gap_m * 1e3:g} mm: [electrodes] "
            f"gap_mm, or its mesh's gap strips) exceeds its [plate] thickness_mm / 6 = "
            f"{message.limit_m * 1e3:.3g} mm{message.detail}")
