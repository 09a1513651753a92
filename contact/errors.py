"""The contact stage's own refusals: the switch model chattering, a slider that runs away.

A kernel run refuses to go on when more mode switches than allowed fall within one time step
(a Zeno-like accumulation the fixed-step event search cannot resolve). That refusal is a
property of the operating point and the step, not a bug, so the command line reports it as
bad input (one line, exit 2). Making it a class of its own lets the CLI map exactly this
failure, while any other ``RuntimeError`` (a SciPy solver giving up, a bug) keeps its own
report. It subclasses ``RuntimeError``, which callers may catch for any solver failure.
"""

from __future__ import annotations


class ChatteringError(RuntimeError):
    """The switch-model kernel met more switches within one step than it allows.

    Parameters
    ----------
    situation : str
        Where and when it happened.
    step_remedy : bool
        Whether a smaller time step of the run may resolve it (a transient at the caller's
        ``dt_s``; the steady engine chooses its own step).
    """

    def __init__(self, situation: str, step_remedy: bool = False) -> None:
        super().__init__(situation + ("; reduce dt_s or raise max_events_per_step"
                                      if step_remedy else ""))
        self.situation = situation
        self.step_remedy = step_remedy


class OverflowingParametersError(ValueError):
    """A parameter set whose mode matrices are not finite (they overflow), before NumPy's
    eigensolver fails on them naming nothing.

    Parameters
    ----------
    name : str
        The set's most extreme value's field (farthest from 1 in magnitude, either way).
    value : float
        Its value, in the field's SI unit.
    """

    def __init__(self, name: str, value: float) -> None:
        super().__init__(f"the parameter set's mode matrices overflow (not finite); its most "
                         f"extreme value is {name} = {value:g}, out of any stator's scale")
        self.name = name
        self.value = value


class RunawayError(ValueError):
    """No steady state from rest: the load (or a load pushing the slider forward) exceeds what
    the motor holds, so the slider keeps accelerating. A ``ValueError`` (the operating point
    has no answer); its message names ``load_N`` and the range of loads the motor holds.

    Attributes
    ----------
    reason : str
        The message without the operating point: which way the slider runs away and the
        loads (N) the motor holds.
    """

    def __init__(self, message: str, reason: str = "") -> None:
        super().__init__(message)
        self.reason = reason or message
