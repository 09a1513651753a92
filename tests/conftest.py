"""Shared fixtures: the published parameter set and a few cached contact runs."""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # running from a checkout without installing
    sys.path.insert(0, str(ROOT))

os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(autouse=True)
def _fresh_warnings():
    """Each test starts with no warning said: the CLI says each warning once per command, and
    a test that calls a warning function directly is its own command."""
    from validation.options import forget_warnings

    forget_warnings()


@pytest.fixture(scope="session")
def paper_params():
    from rom import table2

    return table2()


@functools.cache
def cached_run(voltage_V: float, preload_N: float, **kw):
    """One contact run per distinct argument set for the whole session."""
    from contact.simulate import simulate
    from rom import table2

    return simulate(table2(), voltage_V, preload_N, **kw)
