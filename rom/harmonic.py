"""The free tip's harmonic response of the reduced model: amplitudes, phases and ellipse.

What the paper's Figs. 5 and 6 measured with a laser vibrometer, the tip of the free stator
(no contact, no preload) driven by ``V sin(omega t)``: its tangential (B2, ``u_x``) and
normal (L1, ``u_y``) displacement amplitudes and phases against frequency, from the two
modes of Eqs. (4)-(5) (:func:`rom.damping.free_tip_phasors`). Over one period the tip traces
the ellipse ``(Im(t e^{j w t}), Im(n e^{j w t}))``: the motion the contact turns into thrust.
:func:`fem.harmonic.fe_tip_response` is the direct FE reference it is checked against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fem.harmonic import tip_arrays
from rom.damping import free_tip_phasors
from rom.params import MotorParams


@dataclass(frozen=True, eq=False)
class TipResponse:
    """Complex free tip amplitudes against frequency.

    Attributes
    ----------
    frequency_Hz : numpy.ndarray
        Frequencies (Hz).
    tangential_m, normal_m : numpy.ndarray
        Complex amplitudes (m) of the tip's tangential (B2) and normal (L1) displacement for
        the drive ``voltage_V sin(w t)``: the displacement is ``Im(a e^{j w t})``.
    voltage_V : float
        Drive amplitude (V).
    """

    frequency_Hz: np.ndarray
    tangential_m: np.ndarray
    normal_m: np.ndarray
    voltage_V: float

    def to_dict(self) -> dict[str, object]:
        """JSON-ready arrays: amplitudes (µm) and phases against the drive (degrees)."""
        return {"voltage_V": self.voltage_V,
                **tip_arrays(self.frequency_Hz, self.tangential_m, self.normal_m)}


def tip_response(params: MotorParams, frequency_Hz, voltage_V: float) -> TipResponse:
    """The free tip's response of ``params`` at each of ``frequency_Hz`` for the drive
    ``voltage_V sin(w t)`` (:func:`rom.damping.free_tip_phasors`)."""
    f = np.atleast_1d(np.asarray(frequency_Hz, dtype=float)).copy()
    normal, tangential = free_tip_phasors(params, f, voltage_V)
    f.setflags(write=False)
    return TipResponse(frequency_Hz=f, tangential_m=np.asarray(tangential),
                       normal_m=np.asarray(normal), voltage_V=float(voltage_V))


@dataclass(frozen=True)
class TipEllipse:
    """The tip's path over one drive period at one frequency.

    Attributes
    ----------
    frequency_Hz : float
        The drive frequency (Hz).
    tangential_m, normal_m : numpy.ndarray
        The tip's displacement (m) at ``n`` equally spaced instants of one period.
    width_m, height_m : float
        Tangential and normal amplitudes (m): the ellipse's half extents.
    phase_deg : float
        Phase of the tangential motion behind the normal one (degrees, in (-180, 180]):
        +-90 an upright ellipse, 0 or 180 a line.
    """

    frequency_Hz: float
    tangential_m: np.ndarray
    normal_m: np.ndarray
    width_m: float
    height_m: float
    phase_deg: float

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (µm, degrees)."""
        return {"frequency_Hz": self.frequency_Hz, "tangential_um": self.width_m * 1e6,
                "normal_um": self.height_m * 1e6, "phase_deg": self.phase_deg}


def tip_ellipse(params: MotorParams, frequency_Hz: float, voltage_V: float,
                n: int = 181) -> TipEllipse:
    """The free tip's ellipse at the drive ``voltage_V sin(2 pi frequency_Hz t)``."""
    normal, tangential = (complex(np.asarray(a).ravel()[0])
                          for a in free_tip_phasors(params, frequency_Hz, voltage_V))
    wt = np.linspace(0.0, 2.0 * np.pi, n)
    rot = np.exp(1j * wt)
    return TipEllipse(frequency_Hz=float(frequency_Hz),
                      tangential_m=np.imag(tangential * rot), normal_m=np.imag(normal * rot),
                      width_m=abs(tangential), height_m=abs(normal),
                      phase_deg=float(np.angle(normal * np.conj(tangential), deg=True)))
