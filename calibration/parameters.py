"""The parameters a calibration can fit and how each one changes a parameter set.

Every other constant of the set stays what the stator's reduction (or Table 2, or the beam)
gives. ``Q_L1`` and ``Q_B2`` are the modal dampings as quality factors
(``C = sqrt(K M) / Q``); ``A_l_scale`` and ``A_b_scale`` multiply the force factors of the
start set (a real stator's electrodes, bond and poling give less than the FE model's);
``C0_F`` is the clamped capacitance of the driven electrodes, used by the admittance alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rom.params import MotorParams

PARAMETERS: dict[str, tuple[str, str]] = {
    "C_l": ("N s/m", "modal damping of L1"),
    "C_b": ("N s/m", "modal damping of B2"),
    "Q_L1": ("-", "quality factor of L1, C_l = sqrt(K_l M_l) / Q_L1"),
    "Q_B2": ("-", "quality factor of B2, C_b = sqrt(K_b M_b) / Q_B2"),
    "A_l_scale": ("-", "scale on the L1 force factor A_l"),
    "A_b_scale": ("-", "scale on the B2 force factor A_b"),
    "mu_s": ("-", "static friction coefficient of the tip/slider interface"),
    "mu_d": ("-", "dynamic friction coefficient without vibration"),
    "a_mu": ("-", "residual friction coefficient at large amplitude, Eq. 11"),
    "b_mu": ("1/m", "attenuation factor of Eq. 11"),
    "mu_sd": ("-", "friction coefficient of the linear guide"),
    "k_contact": ("N/m", "normal contact stiffness, Eq. 7"),
    "C0_F": ("F", "clamped capacitance of the driven electrodes (admittance only)"),
}
"""Name -> (SI unit, meaning) of every parameter a measurement file may fit."""

EXCLUSIVE = (("C_l", "Q_L1"), ("C_b", "Q_B2"))
"""Pairs of which a file fits at most one: both set the same damping."""

ORDER = (("a_mu", "mu_d"), ("mu_d", "mu_s"))
"""(lower, upper): the friction law needs ``a_mu <= mu_d <= mu_s`` everywhere in the box."""


@dataclass(frozen=True)
class FitParameter:
    """One parameter to fit.

    Attributes
    ----------
    name : str
        A key of :data:`PARAMETERS`.
    start : float
        Start value (SI unit of :data:`PARAMETERS`).
    lower, upper : float
        Bounds, ``lower < upper``; the start lies between them.
    """

    name: str
    start: float
    lower: float
    upper: float

    @property
    def unit(self) -> str:
        """SI unit of the parameter."""
        return PARAMETERS[self.name][0]


def base_value(base: MotorParams, name: str, c0_F: float | None = None) -> float | None:
    """The value ``name`` has in ``base`` (a scale: 1; ``C0_F``: ``c0_F``)."""
    if name in ("A_l_scale", "A_b_scale"):
        return 1.0
    if name == "Q_L1":
        return math.sqrt(base.K_l * base.M_l) / base.C_l
    if name == "Q_B2":
        return math.sqrt(base.K_b * base.M_b) / base.C_b
    if name == "C0_F":
        return c0_F
    return float(getattr(base, name))


def apply(base: MotorParams, values: dict[str, float]) -> MotorParams:
    """``base`` with the parameters ``values`` (name -> SI value) put in, validated once
    (``C0_F`` is not a field of the set and is ignored here).

    Raises
    ------
    ValueError
        If the combination is not a valid set (``MotorParams``' own message).
    """
    changes: dict[str, float] = {}
    for name, v in values.items():
        if name == "Q_L1":
            changes["C_l"] = math.sqrt(base.K_l * base.M_l) / v
        elif name == "Q_B2":
            changes["C_b"] = math.sqrt(base.K_b * base.M_b) / v
        elif name == "A_l_scale":
            changes["A_l"] = base.A_l * v
        elif name == "A_b_scale":
            changes["A_b"] = base.A_b * v
        elif name != "C0_F":
            changes[name] = v
    return base.with_(**changes) if changes else base
