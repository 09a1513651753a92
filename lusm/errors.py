"""The one error type of the ``lusm`` command line, and how library errors become it.

Library code (``fem``, ``rom``, ``contact``) refuses an input out of range with a
:class:`bounds.ParameterError`: the parameter's SI name, the value and the allowed range as
fields. The CLI layer checks what the user typed first, in the user's units, and raises
:class:`LusmError` naming the option (``--length-mm``); a ``ParameterError`` that still comes
up from the library is said by :func:`user_error` with the option and units of
:data:`PARAMETER_OPTIONS` (a stator file's key, ``'[plate] length_mm'``, keeps the library's
words, which name the file and the key), any other ``ValueError`` or ``OSError`` as its one
line.
:func:`lusm.cli.main` prints ``lusm <cmd>: error: <line>`` and exits with code 2 for every
:class:`LusmError`.
"""

from __future__ import annotations

import math
import numbers
from pathlib import Path

from bounds import ParameterError, said_in, short_reason  # noqa: F401 (callers import short_reason here)


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


PARAMETER_OPTIONS: dict[str, tuple[str, str, float]] = {
    "voltage_V": ("--voltage", "V", 1.0),
    "preload_N": ("--preload", "N", 1.0),
    "load_N": ("--load-N", "N", 1.0),
    "frequency_Hz": ("--frequency", "Hz", 1.0),
    "dt_s": ("--dt", "s", 1.0),
    "duration_s": ("--duration", "s", 1.0),
    "workers": ("--workers", "", 1.0),
    "length_m": ("--length-mm", "mm", 1e3),
    "width_m": ("--width-mm", "mm", 1e3),
    "thickness_m": ("--thickness-mm", "mm", 1e3),
    "electrode_gap_m": ("--gap-mm", "mm", 1e3),
    "target_frequency_Hz": ("--target-frequency", "Hz", 1.0),
    "n_points": ("--points", "", 1.0),
    "f_min_Hz": ("--f-min", "Hz", 1.0),
    "zeta": ("--zeta", "", 1.0),
    "refine": ("--refine", "", 1.0),
    "layers": ("--layers", "", 1.0),
}
"""A library parameter (:attr:`bounds.ParameterError.name`) -> the ``lusm`` option that sets
it, the option's unit and the option's value per SI value (1e3: metres to millimetres)."""

ASSIGNED_NAMES = ("voltage_V", "preload_N", "load_N", "frequency_Hz", "dt_s", "duration_s",
                  "target_frequency_Hz", "n_points", "f_min_Hz", "refine", "layers")
"""Parameters whose option takes the same unit, so that a message's ``frequency_Hz = 1 Hz``
reads ``--frequency 1 Hz`` (:data:`OPTION_FORMS`)."""

OPTION_FORMS: dict[str, str] = {
    **{name: f"{PARAMETER_OPTIONS[name][0]} {{value}}" for name in ASSIGNED_NAMES},
    "ultrasonic_friction": "pass --no-ultrasonic-friction",  # the unsettled-A_N remedy
}
"""A library message's setting (:class:`bounds.Words`) as the option that makes it."""


def _first_line(exc: BaseException) -> str:
    text = in_option_terms(exc).strip()
    line = text.splitlines()[0] if text else type(exc).__name__
    return line


def user_error(exc: BaseException) -> LusmError:
    """A :class:`LusmError` for an exception that reached the CLI from the library.

    ``OSError`` names the path and the operating system's reason; a
    :class:`bounds.ParameterError` names the option that sets the parameter and its range in
    the option's units (:func:`parameter_error`), so the user sees what to change; the
    structured refusals :class:`fem.errors.ShortedDriveError` and
    :class:`contact.errors.OverflowingParametersError` are recognised by class and said with
    the option the user typed; another ``ValueError`` is its first line, its ``name = value``
    assignments in the options' terms.
    """
    if isinstance(exc, LusmError):
        return exc
    from contact.errors import ChatteringError, OverflowingParametersError
    from fem.errors import ShortedDriveError

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
    if isinstance(exc, ParameterError):
        return parameter_error(exc)
    line = _first_line(exc)
    if isinstance(exc, ShortedDriveError):
        from lusm.messages import typed

        option = next((o for o in ("--gap-mm", "--geometry") if typed(o)), None)
        where, fix = {
            "--gap-mm": ("--gap-mm 0", "give --gap-mm of at least 0.001 mm"),
            "--geometry": ("--geometry (its [electrodes] gap_mm = 0, or a mesh whose electrode "
                           "tags touch)", "give [electrodes] gap_mm of at least 0.001 mm, or "
                           "a mesh with gap strips"),
        }.get(option, ("the stator", "give the electrodes a gap of at least 0.001 mm"))
        return LusmError(f"{where}: {line}; {fix}", option)
    if isinstance(exc, OverflowingParametersError):
        from lusm.messages import typed

        if typed("--params"):  # the file's values: named, not a bare NumPy message
            return LusmError(f"--params: {line}", "--params")
    return LusmError(line)


def parameter_error(exc: ParameterError) -> LusmError:
    """A library's :class:`bounds.ParameterError` said with the option that sets the
    parameter, in the option's units: ``--length-mm must be in (0, 10000] mm, got -1000``.

    Without a range (a work bound, a value of the wrong kind) the library's words follow the
    option; a parameter no option sets (a stator file's key among them) keeps the library's
    words alone."""
    from fem.errors import StatorFileError

    known = None if isinstance(exc, StatorFileError) else PARAMETER_OPTIONS.get(exc.name)
    line = _first_line(exc)
    if known is None:
        return LusmError(line)
    option, unit, scale = known
    finite = (isinstance(exc.value, numbers.Real) and not isinstance(exc.value, bool)
              and math.isfinite(exc.value))
    if exc.low is None and exc.high is None and finite:
        return LusmError(line if option in line else f"{option}: {line}", option)
    must = exc.range_text(scale, unit)
    if not finite and (exc.low is not None or exc.high is not None):
        must = f"a finite number {must}"
    return LusmError(f"{option} must be {must}, got {exc.value_text(scale)}"
                     + (f" ({exc.reason})" if exc.reason else ""), option)


def in_option_terms(message: object) -> str:
    """An exception's or a warning's message with the library's settings
    (:class:`bounds.Words`) said as the options that make them: ``load_N = 50 N`` reads
    ``--load-N 50 N``, ``set ultrasonic_friction = False`` reads ``pass
    --no-ultrasonic-friction``; another message as it is."""
    return said_in(message, OPTION_FORMS)


def feature_reason(exc: BaseException) -> str:
    """A parametric stator's refusal in the stator file's terms (mm, hole numbers,
    :attr:`fem.errors.FeatureError.file_text`) where the library gave them; else the text
    as it is."""
    from fem.errors import FeatureError

    if isinstance(exc, FeatureError) and exc.file_text:
        return exc.file_text
    return str(exc)


def design_error_text(path: str | Path, exc: BaseException) -> str:
    """A stator file's refusal on one line that names the file: the operating system's
    reason for a file it cannot open, not ``[Errno 13] Permission denied: '...'``."""
    if isinstance(exc, OSError) and exc.strerror:  # the file it is about: its mesh, maybe
        text = f"{exc.filename or path}: {exc.strerror}"
    else:
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return text if str(path) in text else f"{path}: {text}"
