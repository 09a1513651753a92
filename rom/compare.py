"""Side-by-side comparison of parameter sets against a reference (no printing)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from bounds import ParameterError
from rom.params import MotorParams
from rom.sources import SOURCES, get_params

QUANTITIES = (
    ("f_L1_Hz", "Hz"),
    ("f_B2_Hz", "Hz"),
    ("M_l", "kg"),
    ("K_l", "N/m"),
    ("C_l", "N s/m"),
    ("A_l", "N/V"),
    ("M_b", "kg"),
    ("K_b", "N/m"),
    ("C_b", "N s/m"),
    ("A_b", "N/V"),
    ("eta_N", "-"),
    ("eta_T", "-"),
    ("zeta_L1", "-"),
    ("zeta_B2", "-"),
)
"""Compared quantities (a ``MotorParams.to_dict()`` key) and their SI unit."""


@dataclass(frozen=True)
class Comparison:
    """Parameter sets side by side.

    Attributes
    ----------
    reference : str
        Name of the reference source.
    sources : tuple of str
        Compared sources, in column order (including the reference).
    quantities : tuple of (str, str)
        ``(name, unit)`` rows.
    values : dict
        ``values[source][quantity]``; only sources that could be built.
    relative_difference : dict
        ``value / reference - 1`` per source and quantity (``nan`` if the
        reference is zero or unavailable).
    unavailable : dict
        ``unavailable[source]`` is the reason a source could not be built.
    descriptions : dict
        ``MotorParams.source`` text of each built source.
    """

    reference: str
    sources: tuple[str, ...]
    quantities: tuple[tuple[str, str], ...]
    values: dict[str, dict[str, float]]
    relative_difference: dict[str, dict[str, float]]
    unavailable: dict[str, str]
    descriptions: dict[str, str]

    def to_dict(self) -> dict[str, object]:
        """A JSON-ready dict (``nan`` becomes ``None``)."""

        def clean(d: dict[str, float]) -> dict[str, float | None]:
            return {k: (None if math.isnan(v) else v) for k, v in d.items()}

        return {
            "reference": self.reference,
            "sources": list(self.sources),
            "quantities": [{"name": n, "unit": u} for n, u in self.quantities],
            "values": {s: clean(v) for s, v in self.values.items()},
            "relative_difference": {s: clean(v) for s, v in self.relative_difference.items()},
            "unavailable": dict(self.unavailable),
            "descriptions": dict(self.descriptions),
        }


def compare_sources(
    sources: Sequence[str] = SOURCES, reference: str = "table2",
    given: Mapping[str, MotorParams] | None = None,
) -> Comparison:
    """Build each source's parameter set and tabulate it against ``reference``.

    Parameters
    ----------
    sources : sequence of str
        Source names (see :data:`rom.sources.SOURCES`); the reference is added if missing.
    reference : str
        Source the relative differences refer to.
    given : mapping of str to MotorParams, optional
        Parameter sets to use instead of building a source (e.g. ``{"fem": fem_params(my
        stator)}`` to compare a designer's stator with Table 2).

    Returns
    -------
    Comparison
        Values, relative differences and the reasons for unavailable sources. A source whose
        module cannot be imported is reported as unavailable instead of raising.

    Raises
    ------
    ValueError
        For an unknown source name.
    """
    names = tuple(dict.fromkeys([reference, *sources]))
    for name in names:
        if name not in SOURCES:
            raise ParameterError("source", name, choices=SOURCES,
                                 message=f"source must be one of {', '.join(SOURCES)}, got "
                                 f"{name!r}")
    values: dict[str, dict[str, float]] = {}
    unavailable: dict[str, str] = {}
    descriptions: dict[str, str] = {}
    for name in names:
        try:
            params = given[name] if given and name in given else get_params(name)
        except ImportError as exc:  # e.g. the FE stack of 'fem' not installed
            unavailable[name] = str(exc)
            continue
        d = params.to_dict()
        values[name] = {q: float(d[q]) for q, _ in QUANTITIES}
        descriptions[name] = params.source
    ref = values.get(reference)
    rel: dict[str, dict[str, float]] = {}
    for name, vals in values.items():
        rel[name] = {}
        for q, _ in QUANTITIES:
            r = math.nan if ref is None else ref[q]
            # value / reference - 1: negative where the magnitude is smaller, for negative
            # quantities too (A_b: beam -0.0646 against Table 2's -0.1246 read "+48.2 %")
            rel[name][q] = vals[q] / r - 1.0 if r and not math.isnan(r) else math.nan
    return Comparison(
        reference=reference,
        sources=names,
        quantities=QUANTITIES,
        values=values,
        relative_difference=rel,
        unavailable=unavailable,
        descriptions=descriptions,
    )
