"""What turns the modal amplitudes of L1 and B2 into the stator's peak velocity and stress.

The reduced model (Eqs. 4-5) knows each mode by one coordinate: ``u_l`` (m) scaled so that
``phi_L(0) = 1`` and ``w_b`` (m) so that ``phi_B(l) = 2 |alpha2|`` (Eq. 3). A designer's
limits are about the stator itself: the vibration velocity at a mode's antinode, the peak
stress in the ceramic, the drive field, the heat per volume. :class:`ShapeData` holds the
per-unit-amplitude figures of the two normalised shapes that take one to the other, with the
ceramic's thickness, volume and material limits. It travels in the parameter set
(:attr:`rom.params.MotorParams.shape`): an FE set takes it from the FE mode shapes
(:func:`rom.from_fem.fem_params`), Table 2's and the beam sets from Appendix A's beam
shapes (:func:`beam_shape_data`); :mod:`contact.operating_limits` uses it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from fem.beam_shapes import phi_B, phi_L
from fem.material import MaterialLimits
from fem.mode_peaks import COMBINED_POINTS

SHAPE_UNITS = {
    "velocity_L1": "-", "velocity_B2": "-", "stress_L1_Pa_m": "Pa/m",
    "stress_B2_Pa_m": "Pa/m", "thickness_m": "m", "volume_m3": "m^3",
}
"""SI unit of every number of :class:`ShapeData` (``material`` and ``source`` are text)."""


@dataclass(frozen=True)
class ShapeData:
    """Per-unit-amplitude figures of the normalised L1 and B2 shapes, and the ceramic.

    Attributes
    ----------
    velocity_L1, velocity_B2 : float
        Largest displacement magnitude of the normalised shape over the stator (-): the
        vibration velocity at the mode's antinode per unit modal velocity.
    stress_L1_Pa_m, stress_B2_Pa_m : float
        Largest principal stress magnitude in the ceramic per unit modal amplitude
        (Pa/m), at the mode's worst point.
    thickness_m : float
        Electrode spacing (m): the drive field is the voltage over it.
    volume_m3 : float
        Ceramic volume (m^3), for the dissipated power per volume.
    material : str
        The material's name.
    limits : fem.material.MaterialLimits or None
        The material's operating limits; None when unknown (inline constants without base).
    source : str
        Where the figures come from (FE mode shapes or beam theory).
    combined_stress : tuple of float or None
        The peak stress of L1 and B2 together over a drive period, at the worst phase between
        them, per unit of their peaks' sum (-), at B2's shares ``t = 0, 1/(n-1), ..., 1`` of
        that sum (``t = s_B W / (s_L U + s_B W)``): 1 at both ends, at most 1 between, where
        the two peaks lie apart. None where the shapes are not known point by point (a
        parameter file written without it): the stress is then the peaks' sum.
    """

    velocity_L1: float
    velocity_B2: float
    stress_L1_Pa_m: float
    stress_B2_Pa_m: float
    thickness_m: float
    volume_m3: float
    material: str
    limits: MaterialLimits | None
    source: str
    combined_stress: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for key in SHAPE_UNITS:
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
                raise TypeError(f"ShapeData.{key} must be a real number, got {value!r}")
            value = float(value)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"ShapeData.{key} must be a finite number > 0, got {value!r}")
            object.__setattr__(self, key, value)
        if self.combined_stress is not None:
            k = tuple(float(v) for v in self.combined_stress)
            if len(k) < 2 or not all(math.isfinite(v) and 0.0 < v <= 1.0 + 1e-12 for v in k):
                raise ValueError("ShapeData.combined_stress must be at least two numbers in "
                                 f"(0, 1], got {self.combined_stress!r}")
            object.__setattr__(self, "combined_stress", k)

    def stress_Pa(self, u_m: float, w_m: float) -> float:
        """The peak stress (Pa) of L1 and B2 at modal amplitudes ``u_m``, ``w_m`` (m)
        together over a period: the peaks' sum :meth:`stress_bound_Pa` times
        :attr:`combined_stress` interpolated at B2's share (linearly: the factor being
        convex in the share, the interpolation bounds it from above); the sum itself
        without :attr:`combined_stress`."""
        bound = self.stress_bound_Pa(u_m, w_m)
        if self.combined_stress is None or bound <= 0.0:
            return bound
        k = self.combined_stress
        share = abs(w_m) * self.stress_B2_Pa_m / bound
        return bound * float(np.interp(share, np.linspace(0.0, 1.0, len(k)), k))

    def stress_bound_Pa(self, u_m: float, w_m: float) -> float:
        """``s_L |U| + s_B |W|`` (Pa): the modes' peak stresses added, as if both peaked at
        one point in phase (an upper bound of :meth:`stress_Pa`)."""
        return abs(u_m) * self.stress_L1_Pa_m + abs(w_m) * self.stress_B2_Pa_m

    def to_dict(self) -> dict:
        """JSON-ready: the numbers (SI, :data:`SHAPE_UNITS`), ``material``, ``limits`` (each
        limit in SI, or None) and ``source``."""
        d = asdict(self)
        if self.combined_stress is not None:
            d["combined_stress"] = list(self.combined_stress)
        if self.limits is not None:
            d["limits"] = {k: v for k, v in asdict(self.limits).items() if k != "source"}
        return d

    @classmethod
    def from_dict(cls, d: dict) -> ShapeData:
        """The shape data of a :meth:`to_dict` dictionary.

        Raises
        ------
        ValueError
            Unknown or missing keys, or bad values (the message names them); ``combined_stress``
        may be missing (None).
        """
        if not isinstance(d, dict):
            raise ValueError(f"shape must be an object, got {type(d).__name__}")
        keys = set(SHAPE_UNITS) | {"material", "limits", "source"}
        unknown = sorted(set(d) - keys - {"combined_stress"})
        missing = sorted(keys - set(d))
        if unknown or missing:
            raise ValueError(f"shape: unknown key(s) {unknown}, missing key(s) {missing}")
        lim = d["limits"]
        try:
            limits = None if lim is None else MaterialLimits(**lim)
            return cls(**{**d, "limits": limits})
        except TypeError as exc:
            raise ValueError(f"shape: {exc}") from None


def beam_shape_data(length_m: float, width_m: float, thickness_m: float, cE11_Pa: float,
                    material: str, limits: MaterialLimits | None, source: str) -> ShapeData:
    """Appendix A's Euler-Bernoulli shapes (Eq. 3) of a beam ``l x b x h``.

    L1 is the rod mode ``phi_L = cos(pi y / l)``: its antinode velocity per unit modal
    velocity is ``max |phi_L| = 1`` (the ends) and its axial stress ``cE11 phi_L'`` peaks at
    the node ``y = l/2``, ``cE11 pi / l`` per unit amplitude. B2 bends in plane about the
    thickness axis: its antinode is the free end, ``|phi_B(0)| = 2 |alpha2|``, and its
    bending stress ``cE11 (b/2) |phi_B''|`` peaks at the largest curvature, on the plate's
    edge. ``cE11`` is the stiffness the beam's ``K_l`` and ``K_b`` use (Appendix A). The
    combined stress over a period is :func:`beam_combined_stress_Pa`'s, in phase."""
    y = np.linspace(0.0, length_m, 20001)
    shares = np.linspace(0.0, 1.0, COMBINED_POINTS)
    return ShapeData(
        velocity_L1=float(np.max(np.abs(phi_L(y, length_m)))),
        velocity_B2=float(np.max(np.abs(phi_B(y, length_m)))),
        stress_L1_Pa_m=cE11_Pa * math.pi / length_m,
        stress_B2_Pa_m=cE11_Pa * 0.5 * width_m * float(np.max(np.abs(phi_B(y, length_m, 2)))),
        thickness_m=thickness_m, volume_m3=length_m * width_m * thickness_m,
        material=material, limits=limits, source=source,
        combined_stress=tuple(beam_combined_stress_Pa(length_m, 1.0 - t, t) for t in shares),
    )


def beam_combined_stress_Pa(length_m: float, stress_L1_Pa: float, stress_B2_Pa: float,
                            phase_rad: float = 0.0, points: int = 20001) -> float:
    """The peak axial stress of L1 and B2 together over a drive period, on Appendix A's beam.

    Both modes stress the beam along its length: L1 as ``s_L sin(pi y / l)`` (``phi_L'``,
    uniform over the width), B2 as ``s_B x phi_B''(y) / ((b/2) max|phi_B''|)`` (bending,
    linear across the width ``x``), each the amplitude of a sinusoid in time, B2's lagging
    L1's by ``phase_rad``. At each point the sum of two sinusoids has the amplitude
    ``|a exp(i phase) + c|``; across the width ``c`` takes both signs, so the largest over
    the width is ``sqrt(a^2 + c^2 + 2 |a c cos(phase)|)`` at the edges. Its maximum over the
    length is the combined peak: at most ``s_L + s_B`` (the modes' peaks added, the bound
    :func:`contact.operating_limits.limits_from_amplitudes` reports beside it), less where
    the peaks lie apart (L1's at the middle, where the antisymmetric B2 does not bend).
    ``phase_rad = 0`` (the default, the modes in phase) is the largest over every phase.

    Parameters
    ----------
    length_m : float
        Beam length (m).
    stress_L1_Pa, stress_B2_Pa : float
        Each mode's peak stress amplitude (Pa): shape data's per-unit stress times the
        modal amplitude.
    phase_rad : float
        Phase of B2's motion against L1's (rad).
    points : int
        Points along the length.

    Returns
    -------
    float
        The combined peak stress amplitude (Pa), the peak tensile stress over the period.
    """
    y = np.linspace(0.0, length_m, points)
    a = stress_L1_Pa * np.abs(np.sin(np.pi * y / length_m))
    curvature = np.abs(phi_B(y, length_m, 2))
    c = stress_B2_Pa * curvature / np.max(curvature)
    return float(np.max(np.sqrt(a * a + c * c + 2.0 * np.abs(a * c * math.cos(phase_rad)))))
