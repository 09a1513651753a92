"""The free tip's path: its ellipse's area and the operating frequency's proxy.

One voltage drives L1 and B2, so the free tip traces an ellipse whose area depends on the
phase difference of the two resonances' responses, not on the two amplitudes alone: a
physics audit found ``tip_ellipse_area`` returning the amplitudes' product. The product
stays the proxy ``auto_frequency`` maximizes (docs/contact.md section 6: the true area's
point drove the tuned plate 13 times slower); the area is now the area.
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contact.drive import auto_frequency, tip_ellipse_area
from rom import table2
from rom.damping import free_tip_amplitudes


def _free_tip_path(p, frequency_Hz: float, periods: int = 60, samples: int = 4000):
    """The free tip's (tangential, normal) path over the last drive period of a run from
    rest of Eqs. 4-5 without contact, integrated by ``solve_ivp`` (no phasors)."""
    w = 2 * math.pi * frequency_Hz

    def rhs(t, y):
        drive = math.sin(w * t)
        return [y[1], (p.A_l * drive - p.K_l * y[0] - p.C_l * y[1]) / p.M_l,
                y[3], (p.A_b * drive - p.K_b * y[2] - p.C_b * y[3]) / p.M_b]

    period = 1.0 / frequency_Hz
    t = np.linspace((periods - 1) * period, periods * period, samples + 1)
    sol = solve_ivp(rhs, (0.0, periods * period), [0.0] * 4, method="DOP853", t_eval=t,
                    rtol=1e-11, atol=1e-22)
    return p.phi_Bl * sol.y[2], p.phi_Ll * sol.y[0]


def _shoelace_area(x: np.ndarray, y: np.ndarray) -> float:
    return 0.5 * abs(float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1])))


@pytest.mark.parametrize("frequency_Hz", [39e3, 40e3, 41.5e3])
def test_the_ellipse_area_is_that_of_the_integrated_free_tip_path(frequency_Hz):
    """Independent reference: the area enclosed by the tip's path, integrated in time. The
    amplitudes' product is several times larger (Table 2's responses are nearly in phase)."""
    p = table2()
    x, y = _free_tip_path(p, frequency_Hz)
    enclosed = _shoelace_area(x, y)
    assert tip_ellipse_area(p, frequency_Hz) * math.pi == pytest.approx(enclosed, rel=1e-5)
    a, b = free_tip_amplitudes(p, frequency_Hz)
    assert math.pi * a * b > 2.0 * enclosed


def test_modes_in_phase_trace_a_line():
    """B2 given L1's resonance and damping ratio: the two responses are in phase at every
    frequency and the tip moves on a line (no area), while ``auto_frequency`` still finds the
    amplitudes' product's peak."""
    p = table2()
    scale = p.M_b / p.M_l
    q = dataclasses.replace(p, K_b=p.K_l * scale, C_b=p.C_l * scale)
    for f in (0.9 * q.f_L1_Hz, q.f_L1_Hz, 1.1 * q.f_L1_Hz):
        x, y = _free_tip_path(q, f)
        assert _shoelace_area(x, y) <= 1e-6 * math.pi * math.prod(free_tip_amplitudes(q, f))
        assert tip_ellipse_area(q, f) <= 1e-12 * math.prod(free_tip_amplitudes(q, f))
    f = auto_frequency(q)
    best = math.prod(free_tip_amplitudes(q, f))
    assert all(math.prod(free_tip_amplitudes(q, g)) < best for g in (0.99 * f, 1.01 * f))
