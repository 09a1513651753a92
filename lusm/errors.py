"""The one error type of the ``lusm`` command line, and how library errors become it.

Library code (``fem``, ``rom``, ``contact``) cannot import :mod:`validation`; it raises
``ValueError`` (or ``OSError`` for files) with a message naming its parameter in SI units
(``PlateStator.length_m``, ``voltage_V``). The CLI layer checks what the user typed first, in
the user's units, and raises :class:`LusmError` naming the option (``--length-mm``); whatever
still comes up from the library is mapped by :func:`user_error` to one line that names the
option when one is known. :func:`lusm.cli.main` prints ``lusm <cmd>: error: <line>`` and
exits with code 2 for every :class:`LusmError`.
"""

from __future__ import annotations

import re
from pathlib import Path


class LusmError(ValueError):
    """Bad input or an impossible request, reported as one line with exit code 2.

    Parameters
    ----------
    message : str
        One line naming the option the user typed and its allowed range.
    option : str, optional
        The option (``'--voltage'``), when one is to blame.
    """

    def __init__(self, message: str, option: str | None = None) -> None:
        super().__init__(message)
        self.option = option


LIBRARY_NAMES: dict[str, str] = {
    "voltage_V": "--voltage",
    "preload_N": "--preload",
    "load_N": "--load-N",
    "frequency_Hz": "--frequency",
    "dt_s": "--dt",
    "duration_s": "--duration",
    "max_workers": "--workers",
    "PlateStator.length_m": "--length-mm",
    "PlateStator.width_m": "--width-mm",
    "PlateStator.thickness_m": "--thickness-mm",
    "PlateStator.electrode_gap_m": "--gap-mm",
    "target_frequency_Hz": "--target-frequency",
    "n_points": "--points",
    "f_min_Hz": "--f-min",
    "refine": "--refine",
    "layers": "--layers",
}
"""Library parameter names and the ``lusm`` option that sets them (first match wins)."""

SAME_UNITS = frozenset({"voltage_V", "preload_N", "load_N", "frequency_Hz", "dt_s",
                        "duration_s", "max_workers", "target_frequency_Hz", "n_points",
                        "f_min_Hz", "refine", "layers"})
"""Library names whose option takes the same unit: a message's ``frequency_Hz = 1 Hz`` reads
``--frequency 1 Hz`` (lengths stay as they are: the library's are in m, the options in mm)."""


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    line = text.splitlines()[0] if text else type(exc).__name__
    return line


def user_error(exc: BaseException) -> LusmError:
    """A :class:`LusmError` for an exception that reached the CLI from the library.

    ``OSError`` names the path and the operating system's reason; a ``ValueError`` that names a
    library parameter gets the option that sets it prepended (``--voltage: voltage_V must
    ...``) so the user sees what to change.
    """
    if isinstance(exc, LusmError):
        return exc
    from contact.errors import ChatteringError

    if isinstance(exc, ChatteringError):  # the remedy in the CLI's words
        if exc.step_remedy:
            return LusmError(f"{exc.situation}; a smaller --dt may resolve it", "--dt")
        return LusmError(exc.situation)
    if isinstance(exc, UnicodeDecodeError):
        return LusmError(f"cannot read a file as UTF-8 text ({exc.reason} at byte "
                         f"{exc.start}); save it as UTF-8")
    if isinstance(exc, OSError):
        where = f" {exc.filename}" if exc.filename else ""
        reason = exc.strerror or _first_line(exc)
        return LusmError(f"cannot use{where}: {reason}")
    line = _first_line(exc)
    if type(exc).__name__ == "ShortedDriveError":  # fem.model's, by name: no FE import here
        from lusm.messages import typed

        option = next((o for o in ("--gap-mm", "--geometry") if typed(o)), None)
        where, fix = {
            "--gap-mm": ("--gap-mm 0", "give --gap-mm of at least 0.001 mm"),
            "--geometry": ("--geometry (its [electrodes] gap_mm = 0, or a mesh whose electrode "
                           "tags touch)", "give [electrodes] gap_mm of at least 0.001 mm, or "
                           "a mesh with gap strips"),
        }.get(option, ("the stator", "give the electrodes a gap of at least 0.001 mm"))
        return LusmError(f"{where}: {line}; {fix}", option)
    if line.startswith("the parameter set's mode matrices overflow"):
        from lusm.messages import typed

        if typed("--params"):  # the file's values: named, not a bare NumPy message
            return LusmError(f"--params: {line}", "--params")
    blamed = None
    for name, option in LIBRARY_NAMES.items():
        if re.search(rf"(?<![\w.-]){re.escape(name)}\b", line):
            blamed = blamed or option
            if name in SAME_UNITS:  # say it as the user typed it: "--frequency 1 Hz"
                line = re.sub(rf"(?<![\w.-]){re.escape(name)}\b(\s*=)?", option, line)
    if blamed is None:
        return LusmError(line)
    return LusmError(line if blamed in line else f"{blamed}: {line}", blamed)


def assignments_as_options(text: str) -> str:
    """A library message's ``name = value`` in the options' terms, for the names whose option
    takes the same unit: ``load_N = 50 N`` reads ``--load-N 50 N`` (the one-line warnings;
    only the assignment form, so that a word like "refine" in a sentence stays a word)."""
    for name in SAME_UNITS:
        text = re.sub(rf"(?<![\w.-]){re.escape(name)}\s*=\s*", f"{LIBRARY_NAMES[name]} ", text)
    # a switch: the unsettled-A_N warning's remedy
    return re.sub(r"set ultrasonic_friction\s*=\s*False", "pass --no-ultrasonic-friction", text)


def feature_reason(exc: BaseException) -> str:
    """A parametric stator's refusal in the stator file's terms (mm, hole numbers) where the
    library gave them after its SI text, as for the holes; else the text as it is."""
    text = str(exc)
    for mark in ("): hole ", "): [chamfers] ", "): [tip] ", "): [mesh] "):
        if mark in text:
            return text.split("): ", 1)[-1]
    return text


def short_reason(exc: Exception | str) -> str:
    """The solver's message on one line, a long list of numbers shortened to its range
    (``[801078.0, ..., 889047.7]`` becomes ``[801078 ... 889048]``)."""
    import re

    def shorten(m: re.Match) -> str:
        try:
            values = [float(v) for v in m.group(0)[1:-1].split(",")]
        except ValueError:
            return "[...]"
        return f"[{min(values) + 0.0:.6g} ... {max(values) + 0.0:.6g}]"  # no "-0"

    return re.sub(r"\[[^\]]{60,}\]", shorten, " ".join(str(exc).split()))


def design_error_text(path: str | Path, exc: BaseException) -> str:
    """A stator file's refusal on one line that names the file: the operating system's
    reason for a file it cannot open, not ``[Errno 13] Permission denied: '...'``."""
    if isinstance(exc, OSError) and exc.strerror:  # the file it is about: its mesh, maybe
        text = f"{exc.filename or path}: {exc.strerror}"
    else:
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return text if str(path) in text else f"{path}: {text}"
