"""The steady engine: periodic orbits at fixed slider velocity
(:mod:`contact.steady.periodic_orbit`), the full model's orbits (:mod:`contact.steady.full_orbit`),
the start from rest (:mod:`contact.steady.from_rest`) and the steady states of an operating point
(:mod:`contact.steady.engine`).

>>> from contact.steady import steady_state
"""

from contact.steady.engine import (
    SteadyBranch,
    SteadyResult,
    settled_duration,
    steady_state,
    transient_reference,
)

__all__ = ["SteadyBranch", "SteadyResult", "settled_duration", "steady_state",
           "transient_reference"]
