"""Read-only arrays for the frozen result dataclasses of ``fem`` (``contact.results.
FrozenArrays`` is the same idea one stage later; ``fem`` does not import ``contact``)."""

from __future__ import annotations

import numpy as np


def own_read_only(value):
    """A read-only copy of an array (each array of a tuple likewise); other values as given.

    A result that kept the caller's array would change when the caller edits it
    (``sweep_dimension``'s ``values_m``), and one with writable arrays could be edited into
    answers its own methods then report (a sweep's crossings).
    """
    if isinstance(value, np.ndarray):
        own = np.array(value)
        own.setflags(write=False)
        return own
    if isinstance(value, tuple) and any(isinstance(v, np.ndarray) for v in value):
        return tuple(own_read_only(v) for v in value)
    return value


def freeze_arrays(result) -> None:
    """Replace every array field of the frozen dataclass ``result`` by its own read-only copy
    (call from ``__post_init__``)."""
    for name, value in list(vars(result).items()):
        frozen = own_read_only(value)
        if frozen is not value:
            object.__setattr__(result, name, frozen)
