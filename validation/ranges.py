"""Parsing of the ``start:stop:step`` grids the ``lusm`` commands take (one rule for all)."""

from __future__ import annotations

import math

import numpy as np

MAX_POINTS = 2000
"""Largest grid a command accepts."""


def parse_range(text: str, name: str, *, allow_list: bool = True,
                positive: bool = False) -> np.ndarray:
    """``start:stop:step`` (stop included when on the grid) or, if ``allow_list``, a comma list.

    Parameters
    ----------
    text : str
        The option's value.
    name : str
        The option's name, used in the error message.
    allow_list : bool
        Also accept ``a,b,c``.
    positive : bool
        Require ``start > 0`` (dimensions).

    Raises
    ------
    ValueError
        Naming the option and the allowed form.
    """
    form = "start:stop:step" + (" or a comma list of numbers" if allow_list else "")
    try:
        if ":" in text or not allow_list:
            parts = [float(v) for v in text.split(":")]
            if len(parts) != 3:
                raise ValueError
            start, stop, step = parts
            if not all(math.isfinite(v) for v in parts) or step <= 0 or stop < start:
                raise ValueError
            n = int(math.floor((stop - start) / step + 1e-9)) + 1
            values = start + step * np.arange(n)
        else:
            values = np.array([float(v) for v in text.split(",")])
            if not np.all(np.isfinite(values)):
                raise ValueError
    except ValueError:
        raise ValueError(
            f"{name} must be {form} (finite, step > 0, stop >= start), got {text!r}"
        ) from None
    if positive and values.min() <= 0:
        raise ValueError(f"{name} must start above 0, got {text!r}")
    if values.size > MAX_POINTS:
        raise ValueError(f"{name} has {values.size} points (limit {MAX_POINTS}), got {text!r}")
    return values
