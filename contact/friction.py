"""Amplitude-dependent dynamic friction of Eq. 11.

``mu_d(A_N) = a_mu + (mu_d - a_mu) exp(-b_mu A_N)`` with A_N the normal vibration amplitude
at the contact tip. The paper computes A_N "by using Eq. (4)" for each voltage and preload
(its Fig. 7). Since the L1 equation with the normal force of Eq. 7 involves only ``u_l`` (the
normal dynamics does not depend on the tangential state), A_N is a property of the operating
point: we take it as half the peak-to-peak tip normal displacement ``y_tip = phi_L(l) u_l`` in
the steady state of Eqs. 4 + 7, including separation. See ``docs/contact.md``.
"""

from __future__ import annotations

import math

from rom.params import MotorParams


def dynamic_friction(params: MotorParams, amplitude_m: float) -> float:
    """Eq. 11: dynamic friction coefficient at normal vibration amplitude ``amplitude_m`` (m)."""
    if not (math.isfinite(amplitude_m) and amplitude_m >= 0.0):
        raise ValueError(f"amplitude_m must be finite and >= 0, got {amplitude_m!r}")
    p = params
    return p.a_mu + (p.mu_d - p.a_mu) * math.exp(-p.b_mu * amplitude_m)
