"""Parameter-set sources by name: the one dispatch from a name to a :class:`MotorParams`.

``table2`` is the paper's published set, ``beam`` the Appendix A beam theory
(:func:`rom.beam.beam_params`), ``fem`` the finite-element reduction
(:func:`rom.from_fem.fem_params`, imported lazily so that the FE stack is only loaded when
asked for).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from bounds import ParameterError
from rom.params import MotorParams

SOURCES = ("table2", "beam", "fem")
"""Allowed source names, in display order."""


def _table2(**kwargs: Any) -> MotorParams:
    """The published set; it takes no options."""
    if kwargs:
        raise ValueError(f"source 'table2' takes no options, got {sorted(kwargs)}")
    from rom.table2 import table2

    return table2()


def _beam(**kwargs: Any) -> MotorParams:
    """Appendix A beam theory; geometry and material keywords build the :class:`BeamStator`."""
    import inspect
    from dataclasses import fields

    from rom.beam import beam_params
    from rom.beam_stator import BeamStator

    names = {f.name for f in fields(BeamStator)}
    options = set(inspect.signature(beam_params).parameters) - {"beam"}
    unknown = sorted(set(kwargs) - names - options)
    if unknown:  # bad input, as get_params says (not a TypeError from the call)
        raise ValueError(f"source 'beam' takes no option {', '.join(unknown)}; its options are "
                         f"{', '.join(sorted(names | options))}")
    beam = BeamStator(**{k: kwargs.pop(k) for k in list(kwargs) if k in names})
    return beam_params(beam, **kwargs)


def _fem(**kwargs: Any) -> MotorParams:
    """FE reduction, imported here so that only this source loads the FE stack."""
    import inspect

    from rom.from_fem import fem_params

    # an unknown option is bad input, as the docstring of get_params says (not a TypeError
    # from the call)
    known = set(inspect.signature(fem_params).parameters)
    unknown = sorted(set(kwargs) - known)
    if unknown:
        raise ValueError(f"source 'fem' takes no option {', '.join(unknown)}; its options are "
                         f"{', '.join(sorted(known))} (a plate's dimensions go in a "
                         "PlateStator passed as stator=)")
    return fem_params(**kwargs)


_DISPATCH: dict[str, Callable[..., MotorParams]] = {
    "table2": _table2,
    "beam": _beam,
    "fem": _fem,
}


def get_params(source: str, **kwargs: Any) -> MotorParams:
    """Build the parameter set of a named source.

    Parameters
    ----------
    source : {"table2", "beam", "fem"}
        Which source to use.
    **kwargs
        Options passed to the source's builder (none for ``table2``; see
        :func:`rom.beam.beam_params` and ``rom.from_fem.fem_params``).

    Returns
    -------
    MotorParams
        The parameter set.

    Raises
    ------
    ValueError
        For an unknown source (the message lists the allowed names) or bad options.
    ImportError
        If the source needs a library that is not installed (the FE stack for ``fem``).
    """
    try:
        builder = _DISPATCH[source]
    except (KeyError, TypeError):
        raise ParameterError("source", source, choices=SOURCES,
                             message=f"source must be one of {', '.join(SOURCES)}, got "
                             f"{source!r}") from None
    return builder(**kwargs)
