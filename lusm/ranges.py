"""Parsing of the ``start:stop:step`` grids the ``lusm`` commands take (one rule for all)."""

from __future__ import annotations

import math

import numpy as np

from bounds import ParameterError
from lusm.limits import MAX_GRID_POINTS, more_work_hint, work_bound

MAX_POINTS = MAX_GRID_POINTS
"""Largest grid a command accepts (times ``LUSM_MAX_WORK``)."""


def parse_range(text: str, name: str, *, allow_list: bool = True,
                bounds: tuple[float, float] | None = None,
                unit: str = "", note: str = "") -> np.ndarray:
    """``start:stop:step`` (stop included when on the grid) or, if ``allow_list``, a comma list.

    Parameters
    ----------
    text : str
        The option's value.
    name : str
        The option's name, used in the error message.
    allow_list : bool
        Also accept ``a,b,c``.
    bounds : (float, float), optional
        The closed range every value must lie in, in the option's ``unit``: checked here and
        said in every refusal of the text's form too (``--loads nan`` names its range, as
        ``--load-N nan`` does).
    unit : str
        The option's unit as the user types it (``'N'``, ``'V'``).
    note : str
        Where the range comes from, said with it (``'the range of simulate --load-N'``).

    Raises
    ------
    bounds.ParameterError
        More points than :data:`MAX_POINTS` (times ``LUSM_MAX_WORK``): its ``name`` the
        option, its ``value`` the count, its ``high`` the limit.
    ValueError
        Naming the option, the allowed form and, with ``bounds``, the range.
    """
    values_in = ""
    if bounds is not None:
        values_in = f" in [{bounds[0]:g}, {bounds[1]:g}]" + (f" {unit}" if unit else "")
    form = "start:stop:step" + (" or a comma list of numbers" if allow_list else "") + values_in
    top = work_bound(MAX_POINTS)

    def too_many(n: float) -> ParameterError:
        return ParameterError(name, n, high=top, reason=more_work_hint(),
                              message=f"{name} has {n:.6g} points, above the limit {top} "
                                      f"({more_work_hint()}), got {text!r}")

    if text.count(",") >= top:
        raise too_many(text.count(",") + 1)
    try:
        if ":" in text or not allow_list:
            parts = [float(v) for v in text.split(":")]
            if len(parts) != 3:
                raise ValueError
            start, stop, step = parts
            if not all(math.isfinite(v) for v in parts) or step <= 0 or stop < start:
                raise ValueError
            ratio = (stop - start) / step  # may be inf: compared, never allocated
            if not ratio + 1 <= top:
                raise too_many(ratio + 1)
            n = int(math.floor(ratio + 1e-9)) + 1
            values = start + step * np.arange(n)
            # to 12 digits of the step: -0.3 + 3 x 0.1 is 0, not 5.6e-17, and 3 x 0.3 is 0.9
            decimals = 12 - math.floor(math.log10(step))
            if decimals <= 300:  # beyond, 10**decimals overflows and the values read NaN
                values = np.round(values, decimals) + 0.0  # no -0
        else:
            values = np.array([float(v) for v in text.split(",")])
            if not np.all(np.isfinite(values)):
                raise ValueError
    except ParameterError:
        raise  # too many points: said as it is
    except ValueError:
        also = f"; {note}" if note else ""
        raise ValueError(
            f"{name} must be {form} (finite, step > 0, stop >= start{also}), got {text!r}"
        ) from None
    if bounds is not None and (values.min() < bounds[0] or values.max() > bounds[1]):
        raise ValueError(f"{name} must lie{values_in}{f' ({note})' if note else ''}, "
                         f"got {text!r}")
    uniq, counts = np.unique(values, return_counts=True)
    if np.any(counts > 1):  # a typo more likely than a wish to compute a point twice
        raise ValueError(f"{name} lists {uniq[counts > 1][0]:g} more than once, got {text!r}")
    if values.size > top:
        raise too_many(values.size)
    return values
