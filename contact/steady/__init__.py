"""The steady engine: periodic orbits at fixed slider velocity
(:mod:`contact.steady.periodic_orbit`), the slow equation they average into
(:mod:`contact.steady.slow`), its branches (:mod:`contact.steady.branches`), the full model's
orbits (:mod:`contact.steady.full_orbit`) and the start from rest on it
(:mod:`contact.steady.from_rest`, :mod:`contact.steady.exact`), the loads the motor holds
(:mod:`contact.steady.runaway`), the transient reference (:mod:`contact.steady.settled`) and
the steady states of an operating point (:mod:`contact.steady.engine`).

>>> from contact.steady import steady_state
"""

from contact.steady.branches import SteadyBranch
from contact.steady.engine import SteadyResult, steady_state
from contact.steady.settled import settled_duration, transient_reference

__all__ = ["SteadyBranch", "SteadyResult", "settled_duration", "steady_state",
           "transient_reference"]
