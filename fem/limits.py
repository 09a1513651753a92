"""The multiplier of the FE stage's library bounds (mesh sizes, frequency points, sweeps)."""

from __future__ import annotations

import math
import os

WORK_ENV = "LUSM_MAX_WORK"
"""Environment variable multiplying the work bounds of ``lusm`` (docs/limits.md)."""


def work_factor() -> float:
    """``LUSM_MAX_WORK`` (>= 1; 1 when unset or invalid - the CLI reports invalid values)."""
    try:
        value = float(os.environ.get(WORK_ENV, "") or 1.0)
    except ValueError:
        return 1.0
    return value if math.isfinite(value) and value >= 1.0 else 1.0
