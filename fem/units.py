"""A decimal quantity in a unit, converted to SI exactly and rounded once.

``6.5 * 1e-3`` is 0.006500000000000001 in binary arithmetic: the two operands are each only
the double nearest their decimal, and the product is rounded again. A study's width of
"6.5 mm" became that coordinate (``ds.sel(width=0.0065)`` raised KeyError), and "0.0065 m" a
study of another fingerprint. :func:`to_si` multiplies the decimal as typed by the unit's
factor as written (``repr``: ``1e-3`` is exactly 1/1000) in exact rational arithmetic and
rounds once, to the double nearest the SI value: 0.0065. A float stands for the shortest
decimal that gives it (its ``repr``), which is what a TOML file or a command line typed. Only
the standard library is imported.
"""

from __future__ import annotations

import math
from decimal import Decimal, InvalidOperation
from fractions import Fraction

MAX_EXACT_EXPONENT = 400
"""Decimal exponents beyond which a number is converted in binary arithmetic (it is then 0
or overflows anyway): ``1e-99999999`` would need a denominator of 10**99999999."""


def exact_si(number: str | float, factor: float) -> Fraction:
    """The SI value of ``number`` in a unit of SI factor ``factor``, as an exact fraction.

    Parameters
    ----------
    number : str or float
        A decimal number as typed (``"6.5"``, ``"1.5e3"``), or a float or int, which stands
        for its shortest decimal (``repr``).
    factor : float
        The unit's factor to SI (``1e-3`` for mm), taken as written (its ``repr``).

    Returns
    -------
    fractions.Fraction
        ``number * factor`` exactly; for a decimal exponent beyond
        :data:`MAX_EXACT_EXPONENT`, the binary product (0, a subnormal, or refused).

    Raises
    ------
    ValueError
        If ``number`` is not a finite decimal, or its SI value is not a finite float.
    """
    text = number.strip() if isinstance(number, str) else repr(number)
    try:
        d = Decimal(text)
    except InvalidOperation:
        raise ValueError(f"{number!r} is not a decimal number") from None
    if not d.is_finite():
        raise ValueError(f"{number!r} is not a finite number")
    if abs(d.adjusted()) <= MAX_EXACT_EXPONENT:
        return Fraction(d) * Fraction(repr(factor))
    value = float(d) * factor
    if not math.isfinite(value):
        raise ValueError(f"{number!r} x {factor!r} is not a finite float")
    return Fraction(value)


def nearest_float(value: Fraction) -> float:
    """The double nearest an exact ``value`` (rounded once, to nearest even).

    Raises
    ------
    ValueError
        If ``value`` lies beyond the largest double.
    """
    try:
        return float(value)  # int / int true division: correctly rounded
    except OverflowError:
        raise ValueError(f"{value} is beyond the largest float") from None


def to_si(number: str | float, factor: float) -> float:
    """The double nearest the SI value of ``number`` in a unit of SI factor ``factor``:
    ``to_si("6.5", 1e-3)`` and ``to_si(6.5, 1e-3)`` are 0.0065, where ``6.5 * 1e-3`` is
    0.006500000000000001 (:func:`exact_si`, then :func:`nearest_float`).

    Raises
    ------
    ValueError
        If ``number`` is not a finite decimal, or its SI value is not a finite float.
    """
    return nearest_float(exact_si(number, factor))
