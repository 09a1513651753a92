"""The refusal of an input outside its allowed range, shared by ``fem``, ``rom`` and ``contact``.

The library checks its inputs in SI units and raises :class:`ParameterError` with the
parameter's name, the value, the allowed range and its unit as fields, so that a caller (the
``lusm`` command line) names its own option in its own units from the fields, not from the
wording of the message. It subclasses ``ValueError``: callers that catch that keep working.
:func:`short_reason` puts any library message on one line for a caller to show or record.
This module imports nothing of the project, so every package can raise it.
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Mapping


class ParameterError(ValueError):
    """An input parameter outside its allowed range.

    Parameters
    ----------
    name : str
        The parameter's name in the library, with its SI unit (``'length_m'``,
        ``'voltage_V'``, ``'refine'``).
    value : object
        The value refused, as given.
    low, high : float, optional
        The allowed range's bounds in ``unit``; None where the range is open-ended.
    unit : str
        The SI unit of ``value``, ``low`` and ``high`` (``'m'``, ``'Hz'``; ``''`` for a count).
    low_open, high_open : bool
        Whether ``low`` (``high``) itself is excluded.
    reason : str
        Why the range is what it is, a clause a caller may add to its own words
        (``'the fastest mode of this parameter set'``); may be empty.
    choices : tuple, optional
        The values allowed, for a parameter that takes one of a few (a name, a layout)
        rather than a number in a range.
    bound_by : str
        The other parameter whose value is the bound (``'mu_s'`` for ``mu_d <= mu_s``),
        so that a caller can name it in its own terms; ``''`` for a fixed range.
    kind : str
        What the value must be where that is not a range (``'a real number'``,
        ``'non-zero'``); ``''`` for a range.
    label : str, optional
        The parameter as the library's message names it (``'MotorParams.mu_d'``); by
        default ``name``.
    message : str, optional
        The library's full message; by default :meth:`said` with ``label``.
    """

    def __init__(self, name: str, value: object, low: float | None = None,
                 high: float | None = None, unit: str = "", *, low_open: bool = False,
                 high_open: bool = False, reason: str = "", choices: tuple = (),
                 bound_by: str = "", kind: str = "", label: str | None = None,
                 message: str | None = None) -> None:
        self.name = name
        self.value = value
        self.low, self.high, self.unit = low, high, unit
        self.low_open, self.high_open = low_open, high_open
        self.reason = reason
        self.choices = tuple(choices)
        self.bound_by, self.kind = bound_by, kind
        super().__init__(self.said(name if label is None else label)
                         if message is None else message)

    def __reduce__(self) -> tuple:
        """Pickle by the fields, not by a call with the message (a dask worker's refusal
        reaches the client whole)."""
        return _restore, (type(self), self.args, self.__dict__)

    def said(self, label: str, bound_label: str | None = None) -> str:
        """The refusal in words with the parameter called ``label`` and the parameter that
        bounds it (:attr:`bound_by`) ``bound_label`` (default its name):
        ``'key mu_d must be <= mu_s = 0.5, got 0.6 (kinetic friction cannot exceed
        static)'``."""
        return (f"{label} must be {self.range_text(bound_label=bound_label)}, got "
                f"{self.value!r}" + (f" ({self.reason})" if self.reason else ""))

    def range_text(self, scale: float = 1.0, unit: str | None = None,
                   bound_label: str | None = None) -> str:
        """The allowed range in words, its bounds times ``scale`` in ``unit`` (default the
        error's own): ``'in [0.005, 0.2] m'``, ``'> 0 Hz'``, ``'a finite number'``; a bound
        set by another parameter reads ``'<= mu_s = 0.5'`` (``bound_label`` for its name)."""
        if self.kind:
            return self.kind
        if self.choices:
            return f"one of {', '.join(map(str, self.choices))}"
        unit = self.unit if unit is None else unit
        tail = f" {unit}" if unit else ""
        lo = None if self.low is None else _number(self.low * scale)
        hi = None if self.high is None else _number(self.high * scale)
        if self.bound_by:  # the bound that is a parameter: the upper one, where both are
            other = f"{self.bound_by if bound_label is None else bound_label} = "
            if hi is not None:
                hi = other + hi
            elif lo is not None:
                lo = other + lo
        if lo is not None and hi is not None:
            return (f"in {'(' if self.low_open else '['}{lo}, {hi}"
                    f"{')' if self.high_open else ']'}{tail}")
        if lo is not None:
            return f"{'>' if self.low_open else '>='} {lo}{tail}"
        if hi is not None:
            return f"{'<' if self.high_open else '<='} {hi}{tail}"
        return "a finite number"

    def value_text(self, scale: float = 1.0) -> str:
        """The value refused, a real number times ``scale`` (``'3'``, ``'nan'``), anything
        else as its ``repr``."""
        v = self.value
        if isinstance(v, numbers.Real) and not isinstance(v, bool):
            return _number(float(v) * scale)
        return repr(v)


def _restore(cls: type[ParameterError], args: tuple, fields: dict) -> ParameterError:
    """A pickled :class:`ParameterError` (or subclass) from its message and fields."""
    exc = cls.__new__(cls)
    exc.args = args
    exc.__dict__.update(fields)
    return exc


class ParameterTypeError(ParameterError, TypeError):
    """A parameter of the wrong kind (text for a number), with :attr:`ParameterError.kind`
    saying what it must be; a ``TypeError`` too, for callers that catch that."""


class Words(str):
    """A library message whose parameter settings (``load_N = 50 N``) are kept apart from its
    text, so that a caller says each in its own terms (the CLI: ``--load-N 50 N``).

    It is the message itself, a ``str``, wherever one is expected (an exception's or a
    warning's argument); :meth:`said` words it again.

    Parameters
    ----------
    template : str
        The message with a ``{name}`` slot for each setting (other braces doubled).
    forms : Mapping[str, str], optional
        How the library says a setting, ``'{name} = {value}'`` by default (``'set {name} =
        {value}'`` for a remedy).
    **values : str
        Each setting's value as the message gives it, with its unit (``load_N='50 N'``).
    """

    template: str
    values: dict[str, str]
    forms: dict[str, str]

    def __new__(cls, template: str, forms: Mapping[str, str] | None = None,
                **values: str) -> Words:
        forms = dict(forms or {})
        words = super().__new__(cls, _fill(template, forms, values))
        words.template, words.values, words.forms = template, values, forms
        return words

    def __getnewargs_ex__(self) -> tuple[tuple, dict]:  # pickled (a dask worker's warning)
        return (self.template, self.forms), self.values

    def said(self, forms: Mapping[str, str]) -> str:
        """The message with each setting in ``forms[name]`` (a format of ``{name}`` and
        ``{value}``: ``'--load-N {value}'``), the others in the library's own form."""
        return _fill(self.template, {**self.forms, **forms}, self.values)

    def __add__(self, text: str) -> Words:
        """The message followed by ``text`` (plain text: its braces are kept)."""
        tail = text.template if isinstance(text, Words) else text.replace("{", "{{").replace(
            "}", "}}")
        more = text.values if isinstance(text, Words) else {}
        return Words(self.template + tail, self.forms, **self.values, **more)


def said_in(message: object, forms: Mapping[str, str]) -> str:
    """An exception's or a warning's message with its settings (:class:`Words`) in a front
    end's ``forms`` (:meth:`Words.said`); another message as it is."""
    words = message.args[0] if isinstance(message, BaseException) and message.args else message
    return words.said(forms) if isinstance(words, Words) else str(message)


def _fill(template: str, forms: Mapping[str, str], values: Mapping[str, str]) -> str:
    return template.format(**{name: forms.get(name, "{name} = {value}").format(
        name=name, value=value) for name, value in values.items()})


def _number(x: float) -> str:
    """A bound or value as a short number: ``30``, ``2.5e-06``, ``inf``, ``nan`` (no ``-0``)."""
    return f"{x + 0.0:g}"


def short_reason(exc: Exception | str) -> str:
    """The solver's message on one line, a long list of numbers shortened to its range
    (``[801078.0, ..., 889047.7]`` becomes ``[801078 ... 889048]``)."""

    def shorten(m: re.Match) -> str:
        try:
            values = [float(v) for v in m.group(0)[1:-1].split(",")]
        except ValueError:
            return "[...]"
        return f"[{min(values) + 0.0:.6g} ... {max(values) + 0.0:.6g}]"  # no "-0"

    return re.sub(r"\[[^\]]{60,}\]", shorten, " ".join(str(exc).split()))
