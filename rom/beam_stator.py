"""The stator as a beam: its geometry and the material constants beam theory uses.

Shared by the Appendix A constants (:mod:`rom.beam`) and the Timoshenko reference frequency
(:mod:`rom.timoshenko`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError
from fem.geometry import MAX_SIZE_M
from rom.table2 import TABLE1

SHEAR_FACTOR = 5.0 / 6.0
"""Timoshenko shear correction factor of a rectangular section (-)."""


def check_positive(name: str, value: float) -> float:
    """Return ``value`` as float if it is finite and > 0, else raise a ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ParameterError(name, value, 0.0, math.inf, low_open=True, high_open=True,
                             message=f"{name} must be a finite number in (0, inf), got "
                             f"{value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ParameterError(name, value, 0.0, math.inf, low_open=True, high_open=True,
                             message=f"{name} must be a finite number in (0, inf), got "
                             f"{value!r}")
    return v


def check_finite(name: str, value: float) -> float:
    """Return ``value`` as float if it is finite, else raise a ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ParameterError(name, value, message=f"{name} must be a finite number in "
                             f"(-inf, inf), got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise ParameterError(name, value, message=f"{name} must be a finite number in "
                             f"(-inf, inf), got {value!r}")
    return v


@dataclass(frozen=True)
class BeamStator:
    """The stator as a beam: geometry and the material constants beam theory uses.

    Attributes
    ----------
    length_m, width_m, thickness_m : float
        Length ``l``, width ``b_s`` (in-plane bending direction) and thickness ``h_s`` (m),
        finite and > 0.
    rho_kg_m3 : float
        Density (kg/m^3), > 0.
    cE11_Pa, cE66_Pa : float
        Short-circuit axial and shear stiffness constants (Pa), > 0.
    e31_C_m2 : float
        Piezoelectric stress constant (C/m^2), finite.

    Defaults are the paper's Table 1.
    """

    length_m: float = TABLE1["length_m"]
    width_m: float = TABLE1["width_m"]
    thickness_m: float = TABLE1["thickness_m"]
    rho_kg_m3: float = TABLE1["rho_kg_m3"]
    cE11_Pa: float = TABLE1["cE11_Pa"]
    cE66_Pa: float = TABLE1["cE66_Pa"]
    e31_C_m2: float = TABLE1["e31_C_m2"]

    def __post_init__(self) -> None:
        for name in ("length_m", "width_m", "thickness_m", "rho_kg_m3", "cE11_Pa", "cE66_Pa"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        for name in ("length_m", "width_m", "thickness_m"):
            if getattr(self, name) > MAX_SIZE_M:  # millimetres typed as metres
                raise ParameterError(
                    name, getattr(self, name), 0.0, MAX_SIZE_M, "m", low_open=True,
                    reason="sizes are in metres: 30 mm is 0.03",
                    message=f"BeamStator.{name} must lie in (0, {MAX_SIZE_M:g}] m, got "
                    f"{getattr(self, name)!r} (sizes are in metres: 30 mm is 0.03)")
        object.__setattr__(self, "e31_C_m2", check_finite("e31_C_m2", self.e31_C_m2))

    @property
    def area_m2(self) -> float:
        """Cross-section ``b_s h_s`` (m^2)."""
        return self.width_m * self.thickness_m

    @property
    def inertia_m4(self) -> float:
        """Second moment of area for in-plane bending, ``h_s b_s^3 / 12`` (m^4)."""
        return self.thickness_m * self.width_m**3 / 12.0
